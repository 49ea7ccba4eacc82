#version 450
// engine_unity step 2, docs/spec.md §17.3: one reduction of TileMax, the longest coded velocity
// of each block x block region (the last ones may be partial), the first in row-major order among
// equal keys. Run with block 2 three times, then once with block tile/8. Compute, one thread per
// output texel. NumPy twin: twin.reduce_max (twin.py).
#include "unity.glsl"

float block_key(vec2 code) { return code_key(code); }
#include "common/block_extremes.glsl"

layout(binding = 0) uniform sampler2D codes;
uniform int block;  // block side, texels

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0, rgba32f) uniform writeonly image2D reduced;

void main() {
    ivec2 out_texel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(out_texel, imageSize(reduced)))) return;
    BlockExtremes e = block_extremes(codes, out_texel * block, block, vec2(0.0), -1.0);
    imageStore(reduced, out_texel, vec4(e.longest, 0.0, 0.0));
}
