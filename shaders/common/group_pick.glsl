// Picking the longest of a tile's candidates with a work group per tile: shared by TileMax
// (passes/tile_max.glsl, docs/spec.md §3.2) and engine_eevee's tile flatten and dilation
// (common/tile_pick.glsl, §17.2). Each invocation keeps, per slot (PICK_SLOTS of them: TileMax
// has one, the eevee passes one per half-shutter), the longest candidate offered to it, the
// first in row order among equal lengths, as long as it is offered its candidates in row order.
// reduce_picks() then merges the group's picks on the key (longest length, then smallest index),
// which is the candidate one invocation scanning them all would keep; every layout gives the
// same bits. Walks: scan_grid (invocation (i, j) of a square group takes every step-th candidate
// of every step-th row) and scan_rows (invocation t of a row of N takes candidates t, t + N, ...
// in row order: neighbouring invocations read neighbouring texels).
//
// Before including it a pass defines (preprocessor only, so that the #extension lines below
// come before any declaration) PICK_SLOTS and, in compute, the work group's layout: PICK_ROWS
// (N invocations in a row, scan_rows) or PICK_GRID_SIDE (a square, scan_grid), N or the side²
// a power of two; PICK_SUBGROUP asks for a subgroup reduction and one barrier instead of the
// log2(invocations) barrier steps of the shared-memory one, where the driver has
// GL_KHR_shader_subgroup_arithmetic and _ballot (without them, the shared-memory one). The pass
// defines consider(tile, p, index), which offer()s the candidate at p of the tile's scan grid,
// and tile_extent(tile), the grid's size; in compute pick_tile() runs the whole choice.
#ifdef PICK_ROWS
#define PICK_GROUP_SIZE PICK_ROWS
#else
#define PICK_GROUP_SIZE (PICK_GRID_SIDE * PICK_GRID_SIDE)
#endif
#if defined(STAGE_COMPUTE) && defined(PICK_SUBGROUP) && \
    defined(GL_KHR_shader_subgroup_arithmetic) && defined(GL_KHR_shader_subgroup_ballot)
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_ballot : require
#define SUBGROUP_REDUCTION 1
#endif

#ifdef STAGE_COMPUTE
#ifdef PICK_ROWS
layout(local_size_x = PICK_ROWS) in;
#else
layout(local_size_x = PICK_GRID_SIDE, local_size_y = PICK_GRID_SIDE) in;
#endif
#endif

// A candidate: its vector, the vector's length and its row-order index in the tile's scan.
struct Candidate {
    vec2 v;
    float len;
    uint index;
};

// The first candidate offered replaces it, even at length 0.
const Candidate NO_CANDIDATE = Candidate(vec2(0.0), -1.0, 0xffffffffu);

Candidate picks[PICK_SLOTS];

void clear_picks() {
    for (int slot = 0; slot < PICK_SLOTS; ++slot) picks[slot] = NO_CANDIDATE;
}

// Offers a candidate to a slot; offered in row order, the first of equal lengths stays.
void offer(int slot, vec2 v, float len, uint index) {
    if (len > picks[slot].len) picks[slot] = Candidate(v, len, index);
}

// a beats b: longer, or as long and earlier in row order.
bool beats(Candidate a, Candidate b) {
    return a.len > b.len || (a.len == b.len && a.index < b.index);
}

// The including pass's: offers the candidate at p (0 <= p < extent) of `tile`'s scan grid,
// whose row-order index is `index`; and the size of a tile's scan grid.
void consider(ivec2 tile, ivec2 p, uint index);
ivec2 tile_extent(ivec2 tile);

// Candidates first + step * (i, j) of an `extent`-sized grid, in row order.
void scan_grid(ivec2 tile, ivec2 extent, ivec2 first, int step) {
    for (int y = first.y; y < extent.y; y += step) {
        for (int x = first.x; x < extent.x; x += step) consider(tile, ivec2(x, y), uint(y * extent.x + x));
    }
}

// Candidates t, t + n, t + 2n, ... of an `extent`-sized grid in row order.
void scan_rows(ivec2 tile, ivec2 extent, int t, int n) {
    ivec2 step = ivec2(n % extent.x, n / extent.x);  // n candidates on in row order
    ivec2 p = ivec2(t % extent.x, t / extent.x);
    for (int i = t; p.y < extent.y; i += n) {
        consider(tile, p, uint(i));
        p += step;
        if (p.x >= extent.x) p += ivec2(-extent.x, 1);
    }
}

#ifdef STAGE_COMPUTE
#ifdef SUBGROUP_REDUCTION
// One winner per subgroup and slot, then every invocation picks among them.
shared Candidate subgroup_winners[PICK_SLOTS][PICK_GROUP_SIZE];

// The group's picks into every invocation's picks; call it in uniform control flow.
void reduce_picks() {
    for (int slot = 0; slot < PICK_SLOTS; ++slot) {
        Candidate mine = picks[slot];
        float longest = subgroupMax(mine.len);
        uint first = subgroupMin(mine.len == longest ? mine.index : 0xffffffffu);
        bool wins = mine.len == longest && mine.index == first;
        uint lane = subgroupBallotFindLSB(subgroupBallot(wins));
        if (gl_SubgroupInvocationID == lane) subgroup_winners[slot][gl_SubgroupID] = mine;
    }
    barrier();
    for (int slot = 0; slot < PICK_SLOTS; ++slot) {
        Candidate best = subgroup_winners[slot][0];
        for (uint i = 1u; i < gl_NumSubgroups; ++i) {
            if (beats(subgroup_winners[slot][i], best)) best = subgroup_winners[slot][i];
        }
        picks[slot] = best;
    }
}
#else
shared Candidate group_picks[PICK_SLOTS][PICK_GROUP_SIZE];

// The group's picks into every invocation's picks; call it in uniform control flow.
void reduce_picks() {
    uint i = gl_LocalInvocationIndex;
    for (int slot = 0; slot < PICK_SLOTS; ++slot) group_picks[slot][i] = picks[slot];
    barrier();
    for (uint stride = uint(PICK_GROUP_SIZE) / 2u; stride > 0u; stride >>= 1u) {
        if (i < stride) {
            for (int slot = 0; slot < PICK_SLOTS; ++slot) {
                if (beats(group_picks[slot][i + stride], group_picks[slot][i])) {
                    group_picks[slot][i] = group_picks[slot][i + stride];
                }
            }
        }
        barrier();
    }
    for (int slot = 0; slot < PICK_SLOTS; ++slot) picks[slot] = group_picks[slot][0];
}
#endif

// A work group per tile; else one invocation per tile. A #define, 0 or 1, not a uniform: the
// mode not taken is then not compiled in (the H100 measured code compiled in and switched off
// by a uniform at 15 % of the reconstruct pass: docs/benchmarks.md, "Where the filters' time
// goes"), and reduce_picks's barriers stay in uniform control flow either way.
#ifndef GROUP_PER_TILE
#error "define GROUP_PER_TILE (0 or 1): a work group per tile, or one invocation per tile"
#endif
const bool group_per_tile = GROUP_PER_TILE != 0;

// The picks for the tile this invocation (one per tile) or work group (group_per_tile) serves
// of a `grid`-sized output, in `picks`; returns whether this invocation holds them and stores
// them (an invocation beyond the grid, or not the group's first, does not).
bool pick_tile(ivec2 grid, out ivec2 tile) {
    clear_picks();
    if (!group_per_tile) {
        tile = ivec2(gl_GlobalInvocationID.xy);
        if (any(greaterThanEqual(tile, grid))) return false;
        scan_grid(tile, tile_extent(tile), ivec2(0), 1);
        return true;
    }
    tile = ivec2(gl_WorkGroupID.xy);
#ifdef PICK_ROWS
    scan_rows(tile, tile_extent(tile), int(gl_LocalInvocationIndex), PICK_ROWS);
#else
    scan_grid(tile, tile_extent(tile), ivec2(gl_LocalInvocationID.xy), PICK_GRID_SIDE);
#endif
    reduce_picks();
    return gl_LocalInvocationIndex == 0u;
}
#endif
