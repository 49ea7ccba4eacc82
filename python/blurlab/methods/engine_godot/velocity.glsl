#version 450
// engine_godot step 1, docs/spec.md §17.10: the velocity V = r·rotation + t·translation +
// o·object, the camera's two parts from the depth and the camera's transforms
// (common/camera_motion.glsl), the object's the rest of the G-buffer's motion; V clamped to
// max(r, t, o) times the original vector's length; an end of the shutter at which the point
// lies closer than the near plane moved back to where it crossed that plane (near_correction;
// without it each end is divided by its own w and a point behind the eye flips); the camera's
// depth change dz (the depth velocity) beside it; V and dz scaled by the frame-rate mode's factor.
// Stored as (V, depth, dz).
// Compute, one invocation per pixel. NumPy twin: twin.py, velocity.
#include "common/velocity_setup.glsl"
#include "common/camera_motion.glsl"

uniform float rotation_multiplier;
uniform float translation_multiplier;
uniform float object_multiplier;
uniform bool clamp_to_original;
uniform bool near_correction;
uniform bool depth_velocity;
uniform float framerate_scale;  // the frame-rate mode's factor, from twin.framerate_scale
uniform float flip_guard;  // twin.FLIP_GUARD
uniform bool has_camera;  // false for a frame made from arrays: all of its motion is the object's

// `end` moved back along the segment from `instant` to where it meets the near plane, where
// it lies closer than that plane.
vec4 near_clipped(vec4 end, vec4 instant) {
    if (end.w >= near) return end;
    float span = instant.w - end.w;
    float s = span != 0.0 ? clamp((instant.w - near) / span, 0.0, 1.0) : 0.0;
    return instant + s * (end - instant);
}

// Without the correction: the clip position divided by its own w, as a velocity buffer made
// without clipping divides it (a point behind the eye flips through the image centre), |w| kept
// at least flip_guard·near.
vec2 divided_pixels(vec4 clip, vec2 size) {
    float guard = flip_guard * near;
    float w = abs(clip.w) < guard ? (clip.w < 0.0 ? -guard : guard) : clip.w;
    return (clip.xy / w * 0.5 + 0.5) * size;
}

// The camera's motion of the point at finite depth z, and its depth change (dz).
vec2 camera_part(ivec2 x, ivec2 size, float z, out float dz) {
    vec4 world = camera_world_point(x, size, z);
    vec4 a = clip_from_world[0] * world, b = clip_from_world[1] * world;
    if (near_correction) {
        vec4 instant = vec4(pixel_ndc(x, size) * z, z, z);
        a = near_clipped(a, instant);
        b = near_clipped(b, instant);
    }
    dz = b.w - a.w;
    if (near_correction) return camera_pixels(b, vec2(size)) - camera_pixels(a, vec2(size));
    return divided_pixels(b, vec2(size)) - divided_pixels(a, vec2(size));
}

void main() {
    ivec2 x = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = imageSize(velocity);
    if (any(greaterThanEqual(x, size))) return;
    float z = depth_at(x);
    vec2 m = motion_at(x);
    vec2 v = object_multiplier * m;
    float dz = 0.0;
    if (has_camera) {
        vec2 rotation = camera_rotation_motion(x, size);
        vec2 whole = rotation;
        if (!isinf(z)) whole = camera_part(x, size, z, dz);
        vec2 object_part = m - camera_motion(x, size, z);
        v = rotation_multiplier * rotation + translation_multiplier * (whole - rotation) +
            object_multiplier * object_part;
        dz *= translation_multiplier;
        if (clamp_to_original) {
            float largest = max(rotation_multiplier, max(translation_multiplier, object_multiplier));
            float limit = largest * length(whole + object_part);
            float n = length(v);
            if (n > limit) v *= n > 0.0 ? limit / n : 0.0;
        }
    }
    dz = depth_velocity ? dz * framerate_scale : 0.0;
    imageStore(velocity, x, vec4(v * framerate_scale, z, dz));
}
