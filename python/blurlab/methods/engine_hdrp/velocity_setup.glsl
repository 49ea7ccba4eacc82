#version 450
// engine_hdrp step 1, docs/spec.md §17.4: the velocity v = intensity·M, its camera part split
// off and clamped as camera_clamp_mode says (common/camera_motion.glsl) and the rest clamped to
// maximum_velocity; stored polar (length, turn) in two unsigned 11-bit floats and the linear
// depth in an unsigned 10-bit float: the B10G11R11 texel, its codes kept exactly in RGBA32F.
// Compute, one invocation per pixel. NumPy twin: twin.velocity_setup (twin.py).
#include "common/velocity_setup.glsl"
#include "common/camera_motion.glsl"
#include "common/small_float.glsl"
#include "common/polar_small_float.glsl"
#include "common/vector_clamps.glsl"

uniform float intensity;
uniform float maximum_velocity;
uniform bool camera_motion_blur;
uniform int camera_clamp_mode;
uniform float rotation_clamp;
uniform float translation_clamp;
uniform float motion_vector_clamp;
uniform bool has_camera;  // false for a frame made from arrays: no camera motion to split off

vec2 hdrp_velocity(ivec2 x, ivec2 size, float z) {
    vec2 m = motion_at(x) * intensity;
    if (!has_camera || (camera_motion_blur && camera_clamp_mode == CAMERA_CLAMP_MODE_NONE))
        return clamp_length(m, maximum_velocity);
    vec2 whole = camera_motion(x, size, z) * intensity;
    vec2 rotation = camera_rotation_motion(x, size) * intensity;
    vec2 fsize = vec2(size);
    if (!camera_motion_blur) return clamp_length(m - whole, maximum_velocity);
    if (camera_clamp_mode == CAMERA_CLAMP_MODE_FULL)
        return clamp_length(m - whole, maximum_velocity) +
               clamp_screen_fraction(whole, motion_vector_clamp, fsize);
    vec2 translation = whole - rotation;
    vec2 clamped = vec2(0.0), separated = vec2(0.0);
    if (camera_clamp_mode == CAMERA_CLAMP_MODE_ROTATION ||
        camera_clamp_mode == CAMERA_CLAMP_MODE_SEPARATE) {
        clamped += clamp_screen_fraction(rotation, rotation_clamp, fsize);
        separated += rotation;
    }
    if (camera_clamp_mode == CAMERA_CLAMP_MODE_TRANSLATION ||
        camera_clamp_mode == CAMERA_CLAMP_MODE_SEPARATE) {
        clamped += clamp_screen_fraction(translation, translation_clamp, fsize);
        separated += translation;
    }
    return clamp_length(m - separated, maximum_velocity) + clamped;
}

void main() {
    ivec2 x = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = imageSize(velocity);
    if (any(greaterThanEqual(x, size))) return;
    float z = depth_at(x);
    vec2 v = hdrp_velocity(x, size, z);
    imageStore(velocity, x, vec4(polar_codes(v), quantize_small_float(z, UF10_MANTISSA), 0.0));
}
