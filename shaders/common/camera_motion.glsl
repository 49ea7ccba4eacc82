// The motion a pixel would have if only the camera moved (docs/spec.md §4, camera_only; §17.4
// splits it into rotation and translation): reproject the point seen at pixel x, from its depth
// and the camera's transforms, to t0 and t1. camera_rotation_motion is the part due to the
// camera's rotation alone (its position held still): a point's projection then depends on its
// direction only, so it is the motion of points at infinity, whatever the depth.
// Needs common/inputs.glsl. NumPy twins: blurlab.twins.gathers.camera_motion and
// camera_rotation_motion.

uniform mat4 view_from_clip;      // inverse projection (y flipped), instant
uniform mat4 world_from_view;     // camera at the instant
uniform mat4 clip_from_world[2];  // projection x view at t0 and t1
uniform mat4 sky_from_clip;       // as in the G-buffer pass
uniform mat4 sky_projection[2];
uniform float near;

vec2 camera_pixels(vec4 clip, vec2 size) {
    return (clip.xy / max(clip.w, near) * 0.5 + 0.5) * size;
}

vec2 pixel_ndc(ivec2 x, ivec2 size) {
    return (vec2(x) + 0.5) / vec2(size) * 2.0 - 1.0;
}

vec2 camera_rotation_motion(ivec2 x, ivec2 size) {
    vec4 far_point = sky_from_clip * vec4(pixel_ndc(x, size), 1.0, 1.0);
    vec3 direction = far_point.xyz / far_point.w;
    vec4 a = sky_projection[0] * vec4(direction, 0.0);
    vec4 b = sky_projection[1] * vec4(direction, 0.0);
    return (a.w > 0.0 && b.w > 0.0) ? (b.xy / b.w - a.xy / a.w) * 0.5 * vec2(size) : vec2(0.0);
}

// The world point seen at pixel x's center at finite depth z: the view-space ray through the
// center, scaled to the stored linear depth.
vec4 camera_world_point(ivec2 x, ivec2 size, float z) {
    vec4 ray = view_from_clip * vec4(pixel_ndc(x, size), 1.0, 1.0);
    vec3 view = ray.xyz / ray.w;
    view *= z / -view.z;
    return world_from_view * vec4(view, 1.0);
}

// z: the pixel's depth, read through sanitize_depth (+inf: a point at infinity).
vec2 camera_motion(ivec2 x, ivec2 size, float z) {
    if (isinf(z)) return camera_rotation_motion(x, size);
    vec4 world = camera_world_point(x, size, z);
    return camera_pixels(clip_from_world[1] * world, vec2(size))
         - camera_pixels(clip_from_world[0] * world, vec2(size));
}
