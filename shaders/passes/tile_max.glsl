#version 450
// TileMax, docs/spec.md §3.2: for each k x k tile (the last row and column may be partial), the
// half-vector of largest length among its pixels; among equal lengths, the first pixel in row
// order (the NumPy twin's argmax). Built as a compute shader (STAGE_COMPUTE) or a fragment shader
// (STAGE_FRAGMENT: one fragment per tile scans it all). The compute shader has two modes: for
// small tiles (group_per_tile = false) one thread per tile, since a group per 4 x 4 tile leaves
// most threads idle and barriers cost llvmpipe dearly; for large tiles one work group per tile,
// each thread scanning part of it, then a reduction. The group's layout is a variant (§3.2,
// blurlab.methods.tile_filter.TILE_MAX_VARIANTS), measured by benchmarks/speed_floor.py:
//   default           8 x 8 threads, thread (i, j) scans pixels (i + 8a, j + 8b), shared-memory
//                     reduction in 6 barrier steps;
//   TILE_MAX_THREADS  N threads in a row, thread t scans the pixels t, t + N, ... of the tile in
//                     row order (neighbouring threads read neighbouring pixels), shared-memory
//                     reduction in log2 N steps; with TILE_MAX_SUBGROUP, where the driver has
//                     GL_KHR_shader_subgroup_arithmetic and _ballot, a subgroup reduction and one
//                     barrier instead (without them, the shared-memory one).
// Every mode reduces (length, row-order index), so all give the same bits.
// NumPy twin: blurlab.twins.mcguire2012.tile_max.
#if defined(TILE_MAX_SUBGROUP) && defined(GL_KHR_shader_subgroup_arithmetic) \
    && defined(GL_KHR_shader_subgroup_ballot)
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_ballot : require
#define SUBGROUP_REDUCTION 1
#endif
#include "common/inputs.glsl"
#include "common/mcguire2012.glsl"

layout(binding = 0) uniform sampler2D motion;
uniform int k;
uniform float exposure;

// A tile's candidate: the half-vector, its length and the pixel's row-order index in the tile.
struct Candidate {
    vec2 v;
    float len;
    uint index;
};

const Candidate NO_CANDIDATE = Candidate(vec2(0.0), -1.0, 0xffffffffu);

// a beats b: longer, or as long and earlier in row order.
bool beats(Candidate a, Candidate b) {
    return a.len > b.len || (a.len == b.len && a.index < b.index);
}

Candidate candidate_at(ivec2 pixel, ivec2 origin) {
    vec2 v = half_velocity(sanitize_motion(texelFetch(motion, pixel, 0).xy), exposure, float(k));
    return Candidate(v, length(v), uint((pixel.y - origin.y) * k + (pixel.x - origin.x)));
}

// The winner over pixels origin + first + step * (i, j) inside tile and image, scanned in row
// order so that the first of equal lengths stays.
Candidate scan(ivec2 tile, ivec2 first, int step) {
    ivec2 origin = tile * k;
    ivec2 end = min(origin + k, textureSize(motion, 0));
    Candidate best = NO_CANDIDATE;
    for (int y = origin.y + first.y; y < end.y; y += step) {
        for (int x = origin.x + first.x; x < end.x; x += step) {
            Candidate c = candidate_at(ivec2(x, y), origin);
            if (c.len > best.len) best = c;
        }
    }
    return best;
}

#ifdef STAGE_COMPUTE
layout(binding = 0, rg32f) uniform writeonly image2D tile_max;
uniform bool group_per_tile;

#ifndef TILE_MAX_THREADS
layout(local_size_x = 8, local_size_y = 8) in;
const uint GROUP_THREADS = 64u;
#else
layout(local_size_x = TILE_MAX_THREADS) in;
const uint GROUP_THREADS = uint(TILE_MAX_THREADS);

// Pixels t, t + N, t + 2N, ... of the tile in row order: neighbouring threads read
// neighbouring pixels of a row.
Candidate scan_rows(ivec2 tile, int t) {
    ivec2 origin = tile * k;
    ivec2 extent = min(origin + k, textureSize(motion, 0)) - origin;
    int n = int(GROUP_THREADS);
    ivec2 step = ivec2(n % extent.x, n / extent.x);  // N pixels on in row order
    ivec2 p = ivec2(t % extent.x, t / extent.x);
    Candidate best = NO_CANDIDATE;
    while (p.y < extent.y) {
        Candidate c = candidate_at(origin + p, origin);
        if (c.len > best.len) best = c;
        p += step;
        if (p.x >= extent.x) p += ivec2(-extent.x, 1);
    }
    return best;
}
#endif

#ifdef SUBGROUP_REDUCTION
// One winner per subgroup, then the group's first thread picks among them.
shared Candidate subgroup_winners[GROUP_THREADS];

Candidate reduce(Candidate mine) {
    float longest = subgroupMax(mine.len);
    uint first = subgroupMin(mine.len == longest ? mine.index : 0xffffffffu);
    bool wins = mine.len == longest && mine.index == first;
    uint lane = subgroupBallotFindLSB(subgroupBallot(wins));
    if (gl_SubgroupInvocationID == lane) subgroup_winners[gl_SubgroupID] = mine;
    barrier();
    Candidate best = subgroup_winners[0];
    for (uint i = 1u; i < gl_NumSubgroups; ++i) {
        if (beats(subgroup_winners[i], best)) best = subgroup_winners[i];
    }
    return best;
}
#else
shared Candidate candidates[GROUP_THREADS];

Candidate reduce(Candidate mine) {
    uint i = gl_LocalInvocationIndex;
    candidates[i] = mine;
    barrier();
    for (uint stride = GROUP_THREADS / 2u; stride > 0u; stride >>= 1u) {
        if (i < stride && beats(candidates[i + stride], candidates[i])) candidates[i] = candidates[i + stride];
        barrier();
    }
    return candidates[0];
}
#endif

void main() {
    if (!group_per_tile) {
        ivec2 tile = ivec2(gl_GlobalInvocationID.xy);
        if (any(greaterThanEqual(tile, imageSize(tile_max)))) return;
        imageStore(tile_max, tile, vec4(scan(tile, ivec2(0), 1).v, 0.0, 0.0));
        return;
    }
    // group_per_tile is a uniform: the barriers below stay in uniform control flow.
    ivec2 tile = ivec2(gl_WorkGroupID.xy);
#ifdef TILE_MAX_THREADS
    Candidate best = reduce(scan_rows(tile, int(gl_LocalInvocationIndex)));
#else
    Candidate best = reduce(scan(tile, ivec2(gl_LocalInvocationID.xy), 8));
#endif
    if (gl_LocalInvocationIndex == 0u) imageStore(tile_max, tile, vec4(best.v, 0.0, 0.0));
}
#endif

#ifdef STAGE_FRAGMENT
layout(location = 0) out vec2 tile_max;

void main() {
    tile_max = scan(ivec2(gl_FragCoord.xy), ivec2(0), 1).v;
}
#endif
