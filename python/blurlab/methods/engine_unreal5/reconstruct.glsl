#version 450
// engine_unreal5 step 5, docs/spec.md §17.7: one compute work group per 16 x 16 tile, the path
// chosen by the tile's class. With OVER_LIST the group runs on a tile of one class's list
// (common/tile_lists.glsl), the class being LIST_CLASS, so each class compiles to its own
// program; without, the groups cover the image and each takes its tile's class from neighbors.
// Both write the same bits (test_engine_unreal5.py).
// Skip: C. Otherwise a line of mirrored pairs along the tile's longest velocity, and for
// gather_2 a second line along its second direction. A line whose longest half-vector is L px
// takes P = clamp(ceil(2L), 1, taps/2) pairs at X ± t·v, t = (i + j)/P; where half_res_gather is
// on and its taps lie HALF_RES_SPACING px apart or more, they read the half-size colour.
// Uniform: every tap weighs 1. Gather: the soft depth split of whether X's blur or the tap's
// reaches it (common/depth_spread.glsl), each blur's radius its length along the line, and the
// pairs' mirror. Each line adds its taps' mean, Σa·C/2P, and its coverage, Σa/2P; the coverage
// the lines leave goes to C, and where they cover more than the whole pixel the sum is
// normalised. uniform_half and gather_half gather at half resolution, one invocation per 2 x 2
// block of the tile (its line through the block's corner, weighed as the block's fastest
// pixel), and the tile's pixels take the bilinear mean of the block sums and coverages inside
// the tile, then composite with their own C; a gather_half block whose pixels differ in depth
// or velocity gathers each of them at full resolution. NumPy twin: twin.py, engine_unreal5.
#ifdef OVER_LIST
#define TILE_LISTS_READ 1
#define TILE_LIST_SAMPLER 4
#include "common/tile_lists.glsl"
#endif
#include "common/inputs.glsl"
#include "common/random.glsl"
#include "common/mirrored_pair.glsl"
#include "common/depth_spread.glsl"
#include "unreal5.glsl"

layout(local_size_x = 16, local_size_y = 16) in;
layout(binding = 0) uniform sampler2D color;
layout(binding = 1) uniform sampler2D velocity;
layout(binding = 2) uniform sampler2D neighbors;
layout(binding = 3) uniform sampler2D half_color;
layout(binding = 0, rgba32f) uniform writeonly image2D result;
uniform int taps;  // the quality level's sample count: the most taps on one line
uniform int half_res_gather;
uniform float depth_extent;
uniform float radius;  // R, pixels
uniform uint seed;

const int HALF_TILE = TILE / 2;
const float MIXED_DEPTH = 0.5;  // depth_extent: a pixel this far from its block's depth ...
const float MIXED_PX = 1.0;     // ... or this far from its velocity makes the block mixed
shared vec4 block_share[HALF_TILE * HALF_TILE];
shared float block_coverage[HALF_TILE * HALF_TILE];
shared bool block_mixed[HALF_TILE * HALF_TILE];

// Blur radius along the unit `axis` of the pixel whose velocity texel is s.
float along(vec4 s, vec2 axis) {
    return abs(dot(decode_polar(s.xy, radius), axis));
}

// One line's taps through `center` for the pixel x whose blur and depth weigh them: adds their
// mean Σa·C/2P to shares and Σa/2P to coverage.
void gather_line(ivec2 x, vec2 center, vec2 codes, bool uniform_tile, float j,
                 inout vec4 shares, inout float coverage) {
    ivec2 size = textureSize(color, 0);
    vec2 v = decode_polar(codes, radius);
    float angle = codes.y * (TWO_PI / ANGLE_CODES);
    vec2 axis = vec2(cos(angle), sin(angle));
    float len = codes.x / LENGTH_CODE_MAX * radius;
    int pairs = line_pairs(len, taps);
    bool from_half = line_from_half(len, pairs, half_res_gather);
    vec4 own = texelFetch(velocity, x, 0);
    float len_x = along(own, axis);
    vec4 sum = vec4(0.0);
    float weight = 0.0;
    for (int i = 0; i < pairs; ++i) {
        float t = (float(i) + j) / float(pairs);
        ivec2 y1 = clamp(ivec2(floor(center + t * v)), ivec2(0), size - 1);
        ivec2 y2 = clamp(ivec2(floor(center - t * v)), ivec2(0), size - 1);
        float a1 = 1.0, a2 = 1.0;
        if (!uniform_tile) {
            vec4 s1 = texelFetch(velocity, y1, 0);
            vec4 s2 = texelFetch(velocity, y2, 0);
            a1 = depth_spread_weight(own.z, len_x, s1.z, along(s1, axis), length(vec2(y1 - x)),
                                     depth_extent);
            a2 = depth_spread_weight(own.z, len_x, s2.z, along(s2, axis), length(vec2(y2 - x)),
                                     depth_extent);
            mirror_pair(a1, a2, s1.z, s2.z, s1.x, s2.x);
        }
        vec4 c1 = from_half ? texelFetch(half_color, y1 / 2, 0)
                            : sanitize_color(texelFetch(color, y1, 0));
        vec4 c2 = from_half ? texelFetch(half_color, y2 / 2, 0)
                            : sanitize_color(texelFetch(color, y2, 0));
        add_pair(a1, a2, c1, c2, sum, weight);
    }
    float n = float(2 * pairs);
    shares += sum / n;
    coverage += weight / n;
}

vec4 composite(vec4 shares, float coverage, vec4 cx) {
    return (shares + max(1.0 - coverage, 0.0) * cx) / max(coverage, 1.0);
}

// The full-resolution classes at pixel x of a tile whose neighbors texel is n.
vec4 full_res(ivec2 x, vec4 n, float kind) {
    vec4 cx = sanitize_color(texelFetch(color, x, 0));
    if (kind == CLASS_SKIP) return cx;
    float j = rand(uint(x.x), uint(x.y), seed);
    vec4 shares = vec4(0.0);
    float coverage = 0.0;
    vec2 center = vec2(x) + 0.5;
    gather_line(x, center, n.xy, kind == CLASS_UNIFORM, j, shares, coverage);
    if (kind == CLASS_GATHER_2)
        gather_line(x, center, unpack_codes(n.z), false, j, shares, coverage);
    return composite(shares, coverage, cx);
}

// The half-resolution classes: every invocation of the group calls it (it holds a barrier).
void half_res(ivec2 tile, vec4 n, float kind, ivec2 x, bool inside) {
    ivec2 size = textureSize(color, 0);
    ivec2 first = tile * HALF_TILE;
    ivec2 last = min(first + HALF_TILE - 1, (size + 1) / 2 - 1);
    ivec2 local = ivec2(gl_LocalInvocationID.xy);
    ivec2 h = first + local;
    if (all(lessThan(local, ivec2(HALF_TILE))) && all(lessThanEqual(h, last))) {
        // The block's fastest pixel (the first of the 2 x 2 in row-major order among equal
        // length codes) stands for it: a moving edge blurs rather than the still pixel beside it.
        ivec2 x0 = min(2 * h, size - 1);
        vec4 own = texelFetch(velocity, x0, 0);
        for (int i = 1; i < 4; ++i) {
            ivec2 p = min(2 * h + ivec2(i & 1, i >> 1), size - 1);
            vec4 s = texelFetch(velocity, p, 0);
            if (s.x > own.x) {
                own = s;
                x0 = p;
            }
        }
        float j = rand(uint(x0.x), uint(x0.y), seed);
        vec4 shares = vec4(0.0);
        float coverage = 0.0;
        gather_line(x0, vec2(2 * h) + 1.0, n.xy, kind == CLASS_UNIFORM_HALF, j, shares,
                    coverage);
        int b = local.y * HALF_TILE + local.x;
        block_share[b] = shares;
        block_coverage[b] = coverage;
        // A gather_half block whose pixels differ from it (MIXED_DEPTH·depth_extent in depth or
        // MIXED_PX in velocity) gathers each of its pixels at full resolution instead.
        bool mixed = false;
        vec2 v0 = decode_polar(own.xy, radius);
        for (int i = 0; i < 4; ++i) {
            vec4 s = texelFetch(velocity, min(2 * h + ivec2(i & 1, i >> 1), size - 1), 0);
            if (abs(s.z - own.z) >= MIXED_DEPTH * depth_extent ||
                length(decode_polar(s.xy, radius) - v0) >= MIXED_PX)
                mixed = true;
        }
        block_mixed[b] = mixed && kind == CLASS_GATHER_HALF;
    }
    barrier();
    if (!inside) return;
    ivec2 block = x / 2 - first;
    if (block_mixed[block.y * HALF_TILE + block.x]) {
        imageStore(result, x, full_res(x, n, CLASS_GATHER));
        return;
    }
    vec2 u = vec2(x) * 0.5 - 0.25;  // x's center in block coordinates
    ivec2 below = ivec2(floor(u));
    vec2 f = u - vec2(below);
    ivec2 a = clamp(below, first, last) - first;
    ivec2 b = clamp(below + 1, first, last) - first;
    int i00 = a.y * HALF_TILE + a.x, i10 = a.y * HALF_TILE + b.x;
    int i01 = b.y * HALF_TILE + a.x, i11 = b.y * HALF_TILE + b.x;
    vec4 shares = (1.0 - f.y) * ((1.0 - f.x) * block_share[i00] + f.x * block_share[i10]) +
                  f.y * ((1.0 - f.x) * block_share[i01] + f.x * block_share[i11]);
    float coverage =
        (1.0 - f.y) * ((1.0 - f.x) * block_coverage[i00] + f.x * block_coverage[i10]) +
        f.y * ((1.0 - f.x) * block_coverage[i01] + f.x * block_coverage[i11]);
    vec4 cx = sanitize_color(texelFetch(color, x, 0));
    imageStore(result, x, composite(shares, coverage, cx));
}

void main() {
    ivec2 grid = textureSize(neighbors, 0);
#ifdef OVER_LIST
    ivec2 tile = listed_tile(grid.x);
    float kind = float(LIST_CLASS);
#else
    ivec2 tile = ivec2(gl_WorkGroupID.xy);
    float kind = texelFetch(neighbors, tile, 0).w;
#endif
    vec4 n = texelFetch(neighbors, tile, 0);
    ivec2 x = tile * TILE + ivec2(gl_LocalInvocationID.xy);
    bool inside = all(lessThan(x, textureSize(color, 0)));
    if (kind >= CLASS_UNIFORM_HALF) half_res(tile, n, kind, x, inside);
    else if (inside) imageStore(result, x, full_res(x, n, kind));
}
