#version 450
// Tile classification (Jimenez 2014, "Next Generation Post Processing in Call of Duty:
// Advanced Warfare"), on top of docs/spec.md §3.2-3.3. One thread per tile T, with vN =
// NeighborMax[T] and B = the union of the component-wise bounds of V over the 3 x 3 tiles
// around T (those inside the grid):
//   still   (0): |vN| <= still_threshold                       — the filter's own early exit;
//   uniform (1): max over the corners c of B of |c - vN| <= uniform_spread — then every V[Y]
//                that a pixel of T can sample lies within uniform_spread of vN;
//   full    (2): otherwise.
// Writes the class map and appends T to its class's list. Each class has two indirect
// dispatch commands, {count, blocks per tile, 1} and {count, 1, 1} (passes that take whole
// tiles, WHOLE_TILES), at words 6c and 6c + 3; the atomic counter is the first one's count.
// Compute only.
// NumPy twin: blurlab.twins.classify.classify_tiles.
#ifdef STAGE_COMPUTE
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0) uniform sampler2D tile_bounds;  // min V.x, min V.y, max V.x, max V.y
layout(binding = 1) uniform sampler2D neighbor_max;
layout(binding = 0, r32f) uniform writeonly image2D tile_class;
layout(std430, binding = 0) buffer TileLists { uint words[]; };
uniform float still_threshold;
uniform float uniform_spread;
uniform uint list_first;   // word where class 0's list starts
uniform uint list_stride;  // words from one class's list to the next

const uint STILL = 0u, UNIFORM = 1u, FULL = 2u;

void main() {
    ivec2 tile = ivec2(gl_GlobalInvocationID.xy);
    ivec2 grid = textureSize(neighbor_max, 0);
    if (any(greaterThanEqual(tile, grid))) return;
    vec2 vn = texelFetch(neighbor_max, tile, 0).xy;
    uint c = FULL;
    if (length(vn) <= still_threshold) {
        c = STILL;
    } else {
        vec2 lo = vec2(3.4e38), hi = vec2(-3.4e38);
        for (int dy = -1; dy <= 1; ++dy) {
            for (int dx = -1; dx <= 1; ++dx) {
                ivec2 t = tile + ivec2(dx, dy);
                if (any(lessThan(t, ivec2(0))) || any(greaterThanEqual(t, grid))) continue;
                vec4 b = texelFetch(tile_bounds, t, 0);
                lo = min(lo, b.xy);
                hi = max(hi, b.zw);
            }
        }
        // The corner of B farthest from vN, one axis at a time.
        float spread = length(max(abs(lo - vn), abs(hi - vn)));
        if (spread <= uniform_spread) c = UNIFORM;
    }
    imageStore(tile_class, tile, vec4(float(c)));
    uint i = atomicAdd(words[6u * c], 1u);
    atomicAdd(words[6u * c + 3u], 1u);
    words[list_first + c * list_stride + i] = uint(tile.x) | (uint(tile.y) << 16);
}
#endif
