#version 450
// camera_only's motion, docs/spec.md §4 (Urho3D thesis §2.3.2): the motion each pixel would have if
// only the camera moved, from its depth and the camera's transforms (common/camera_motion.glsl).
// Points at infinity (depth +inf) move with the camera's rotation only.
// Compute only. NumPy twin: blurlab.twins.gathers.camera_motion.
#include "common/inputs.glsl"
#include "common/camera_motion.glsl"

layout(local_size_x = 16, local_size_y = 16) in;
layout(binding = 0) uniform sampler2D depth;
layout(binding = 0, rg32f) uniform writeonly image2D motion;

void main() {
    ivec2 x = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = textureSize(depth, 0);
    if (any(greaterThanEqual(x, size))) return;
    float z = sanitize_depth(texelFetch(depth, x, 0).x);
    imageStore(motion, x, vec4(camera_motion(x, size, z), 0.0, 0.0));
}
