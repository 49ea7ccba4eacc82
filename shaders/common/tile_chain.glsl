// A tile filter in one dispatch (docs/spec.md §3.7), compute only: the entry point of a reconstruct
// pass built with TILE_CHAIN (common/tile_filter.glsl declares its images). A work group per
// tile:
//   1. TileMax of its tile, as passes/tile_max.glsl computes it (common/group_pick.glsl), stored;
//   2. one atomic increment of the counter of each tile of its 3 x 3 neighbourhood. The group
//      that brings a tile's counter to the number of grid tiles around it is the last of them to
//      store its TileMax, so that tile's NeighborMax can be read now: the group computes it
//      (common/neighbor_max.glsl), resets the counter to 0 for the next run, and
//   3. reconstructs every pixel of that tile with the pass's PASS_AT.
// No group waits for another, so no order of groups can stall; each tile is reconstructed once,
// by one group. The same functions as the three passes, so the same bits.

layout(binding = 0, rgba32f) uniform writeonly image2D result;
#ifndef TILE_CHAIN_DIAG
#define TILE_CHAIN_DIAG 0
#endif

vec2 tile_motion_at(ivec2 p) {
#ifdef PACKED_INPUTS
    return sanitize_motion(texelFetch(motion_depth, p, 0).xy);
#else
    return sanitize_motion(texelFetch(motion, p, 0).xy);
#endif
}

void consider(ivec2 tile, ivec2 p, uint index) {
    vec2 v = half_velocity(tile_motion_at(tile * k + p), exposure, float(k));
    offer(0, v, length(v), index);
}

ivec2 tile_extent(ivec2 tile) {
    return min(tile * k + k, textureSize(color, 0)) - tile * k;
}

// How many grid tiles the 3 x 3 around `tile` holds: its counter's value once all have stored.
uint neighborhood_size(ivec2 tile, ivec2 grid) {
    ivec2 span = min(tile + 1, grid - 1) - max(tile - 1, ivec2(0)) + 1;
    return uint(span.x * span.y);
}

// NeighborMax from the TileMax image, which other groups of this dispatch wrote.
vec2 neighbor_max_from_image(ivec2 tile, ivec2 grid) {
    vec2 best = vec2(0.0);
    float best_length = -1.0;
    for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
            ivec2 t = tile + ivec2(dx, dy);
            if (any(lessThan(t, ivec2(0))) || any(greaterThanEqual(t, grid))) continue;
            offer_neighbor(imageLoad(tile_max, t).xy, ivec2(dx, dy), diagonal_reach, best, best_length);
        }
    }
    return best;
}

shared uint ready;  // bit 3 (dy + 1) + dx + 1: this group completed that neighbour's count

void main() {
    ivec2 grid = imageSize(tile_max);
    ivec2 tile;
    if (pick_tile(grid, tile)) {
        imageStore(tile_max, tile, vec4(picks[0].v, 0.0, 0.0));
#ifndef TILE_CHAIN_NO_FENCE
        memoryBarrierImage();  // the store is visible before any counter says so
#endif
        ready = 0u;
    }
    barrier();
#if TILE_CHAIN_DIAG == 2
    if (gl_LocalInvocationIndex == 0u) {
        chained_neighbor_max = diagonal_reach ? picks[0].v : picks[0].v * 1.0001;
        imageStore(neighbor_max, tile, vec4(picks[0].v, 0.0, 0.0));
        imageAtomicAdd(tile_counts, tile, 0u);
    }
    barrier();
    {
        ivec2 extent = tile_extent(tile);
        for (int i = int(gl_LocalInvocationIndex); i < extent.x * extent.y; i += PICK_ROWS) {
            ivec2 x = tile * k + ivec2(i % extent.x, i / extent.x);
            imageStore(result, x, PASS_AT(x));
        }
    }
    return;
#endif
    uint slot = gl_LocalInvocationIndex;  // invocations 0..8: a neighbour each, in parallel
    ivec2 neighbour = tile + ivec2(int(slot % 3u) - 1, int(slot / 3u) - 1);
    if (slot < 9u && all(greaterThanEqual(neighbour, ivec2(0))) && all(lessThan(neighbour, grid))) {
        if (imageAtomicAdd(tile_counts, neighbour, 1u) + 1u == neighborhood_size(neighbour, grid)) {
            imageStore(tile_counts, neighbour, uvec4(0u));
            atomicOr(ready, 1u << slot);
        }
    }
    barrier();
    for (uint bits = ready; bits != 0u; bits &= bits - 1u) {
        uint r = uint(findLSB(bits));
        ivec2 n = tile + ivec2(int(r % 3u) - 1, int(r / 3u) - 1);
        if (gl_LocalInvocationIndex == 0u) {
            chained_neighbor_max = neighbor_max_from_image(n, grid);
            imageStore(neighbor_max, n, vec4(chained_neighbor_max, 0.0, 0.0));
        }
        barrier();
        ivec2 extent = tile_extent(n);
        for (int i = int(gl_LocalInvocationIndex); i < extent.x * extent.y; i += PICK_ROWS) {
            ivec2 x = n * k + ivec2(i % extent.x, i / extent.x);
#if TILE_CHAIN_DIAG == 1
            float zd; vec2 md;
            depth_motion_at(x, zd, md);
            imageStore(result, x, chained_neighbor_max.x > 1e30 ? PASS_AT(x) : vec4(color_at(x).rgb, zd + md.x));
#else
            imageStore(result, x, PASS_AT(x));
#endif
        }
        barrier();  // before chained_neighbor_max is overwritten
    }
}
