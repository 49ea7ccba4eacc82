// What every tile-based filter's reconstruct pass reads (docs/spec.md §3): the G-buffer, the
// NeighborMax grid, and the uniforms of blurlab/methods/tile_filter.py's TILE_FILTER_PARAMS
// and FILTER_OPTIONS under the same names (values validated in Python, once per call).
#include "common/inputs.glsl"
#include "common/mcguire2012.glsl"
#include "common/random.glsl"
#include "common/filter_options.glsl"

layout(binding = 0) uniform sampler2D color;
layout(binding = 1) uniform sampler2D depth;
layout(binding = 2) uniform sampler2D motion;
layout(binding = 3) uniform sampler2D neighbor_max;
uniform int k;
uniform int samples;
uniform float soft_z;
uniform float exposure;
uniform uint seed;
uniform bool jitter_tiles;  // options, common/filter_options.glsl
uniform bool adaptive_samples;
uniform float early_exit;  // pixels; 0: only the §3.4 test
