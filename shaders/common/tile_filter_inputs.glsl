// What every tile-based filter's reconstruct pass reads (docs/spec.md §3): the G-buffer, and
// blurlab/methods/tile_filter.py's TILE_FILTER_PARAMS under the same names (uniforms, values
// validated in Python, once per call). A pass declares its NeighborMax input itself.
#include "common/inputs.glsl"

// The G-buffer as docs/spec.md §10.1 reads it: three textures sanitized on every read
// (common/gbuffer.glsl), or with PACKED_INPUTS the two half-float textures of
// passes/pack_inputs.comp (§19), sanitized once when packed, depth and motion in one fetch.
#ifdef PACKED_INPUTS
layout(binding = 0) uniform sampler2D color;
layout(binding = 1) uniform sampler2D motion_depth;  // xy: motion, z: depth

vec4 color_at(ivec2 p) {
    return texelFetch(color, p, 0);
}

void depth_motion_at(ivec2 p, out float z, out vec2 m) {
    vec4 texel = texelFetch(motion_depth, p, 0);
    z = texel.z;
    m = texel.xy;
}
#else
#include "common/gbuffer.glsl"

void depth_motion_at(ivec2 p, out float z, out vec2 m) {
    z = depth_at(p);
    m = motion_at(p);
}
#endif
uniform int k;
uniform int samples;
uniform float soft_z;
uniform float exposure;
uniform uint seed;
