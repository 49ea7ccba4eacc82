// The interface that the neighbour dilations of engine_unreal (docs/spec.md §17.5 step 3) and
// engine_unreal5 (§17.7 step 3) share: step 2's tiles and R in; each tile D's result out to
// `neighbors`, one invocation per tile. Each scans the 7 x 7 tiles around D that lie in the grid
// (common/pixel.glsl's outside) with common/unreal.glsl's reaches_tile.
// NumPy twins: blurlab.twins.unreal.neighborhood_sources and reaches.
#include "common/pixel.glsl"
#include "common/unreal.glsl"

layout(binding = 0) uniform sampler2D tiles;
uniform float radius;  // R, pixels

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0, rgba32f) uniform writeonly image2D neighbors;
