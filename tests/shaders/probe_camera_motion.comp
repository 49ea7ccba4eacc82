#version 450
// The motion each pixel would have if only the camera moved (common/camera_motion.glsl), into
// an RG32F image: for tests/test_shader_pass.py (reflect() lists arrays of matrices and image
// formats other than RGBA32F).
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
