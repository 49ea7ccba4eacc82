#version 450
// camera_only's motion, docs/spec.md §4 (Urho3D thesis §2.3.2): the motion each pixel would have if
// only the camera moved, from its depth and the camera's transforms: reproject the point seen
// at X to t0 and t1. Points at infinity (depth +inf) move with the camera's rotation only.
// Compute only. NumPy twin: blurlab.twins.gathers.camera_motion.
#include "common/inputs.glsl"

layout(local_size_x = 16, local_size_y = 16) in;
layout(binding = 0) uniform sampler2D depth;
layout(binding = 0, rg32f) uniform writeonly image2D motion;
uniform mat4 view_from_clip;      // inverse projection (y flipped), instant
uniform mat4 world_from_view;     // camera at the instant
uniform mat4 clip_from_world[2];  // projection x view at t0 and t1
uniform mat4 sky_from_clip;       // as in the G-buffer pass
uniform mat4 sky_projection[2];
uniform float near;

vec2 to_pixels(vec4 clip, vec2 size) {
    return (clip.xy / max(clip.w, near) * 0.5 + 0.5) * size;
}

void main() {
    ivec2 x = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = textureSize(depth, 0);
    if (any(greaterThanEqual(x, size))) return;
    vec2 ndc = (vec2(x) + 0.5) / vec2(size) * 2.0 - 1.0;
    float z = sanitize_depth(texelFetch(depth, x, 0).x);
    vec2 m;
    if (isinf(z)) {
        vec4 far_point = sky_from_clip * vec4(ndc, 1.0, 1.0);
        vec3 direction = far_point.xyz / far_point.w;
        vec4 a = sky_projection[0] * vec4(direction, 0.0);
        vec4 b = sky_projection[1] * vec4(direction, 0.0);
        m = (a.w > 0.0 && b.w > 0.0) ? (b.xy / b.w - a.xy / a.w) * 0.5 * vec2(size) : vec2(0.0);
    } else {
        // The view-space ray through the pixel center, scaled to the stored linear depth.
        vec4 ray = view_from_clip * vec4(ndc, 1.0, 1.0);
        vec3 view = ray.xyz / ray.w;
        view *= z / -view.z;
        vec4 world = world_from_view * vec4(view, 1.0);
        m = to_pixels(clip_from_world[1] * world, vec2(size))
          - to_pixels(clip_from_world[0] * world, vec2(size));
    }
    imageStore(motion, x, vec4(m, 0.0, 0.0));
}
