#version 450
// gather_coverage step 3, docs/spec.md §17.6. Per half-shutter of the two-sided motion, taps
// alternately along the dilated tile's line and along X's own half-motion; a tap whose trail
// passes over X adds spacing / max(|v|, 1) of coverage (the share of the half-shutter it
// spends on X), the families' weights divided by 1 + their overlap. Each side is its coverage
// times the covering color plus the rest times what lies behind X: the mean of the taps behind
// X that do not reach it where X moves, X itself where it is still. Compute, one invocation
// per pixel. Variant (blurlab.methods.coverage.GATHER_VARIANTS): GATHER_SKIP_UNWEIGHTED reads a
// tap's colour only where it weighs on a sum; same bits. With FILM_THROUGH_TAPS (the option
// film_through_taps) every colour is read through the film filter instead of a pass after this
// one: tap k bilinearly at (±d, ±d) px, the signs turning with k; X as the mean of the turns.
// Where the neighbourhood's longest half-motion is under early_exit px, X keeps its colour.
// With PER_TILE_SAMPLES (the option tap_spacing > 0) a side takes
// clamp(ceil(longest / tap_spacing), 2, samples) taps; with UNIFORM_FAST_PATH (the option
// uniform_tolerance > 0) an X whose own trails lie within uniform_tolerance px of the tile's
// lines takes the plain gather of uniform_gather instead of the coverage weights. With
// HALF_RES_GATHER (the option half_res_above > 0) this is the pass at half resolution that
// gathers the top-left pixel of each 2 x 2 quad whose tile line and pixels' half-motions are
// longer than half_res_above px; with HALF_RES_READ the full-resolution pass gives such a
// quad's pixels that result. With BLOCK_CLASSIFY this file is the pass that sorts 16 px blocks
// into still and moving lists, with OVER_LIST the gather over one list (docs/spec.md §17.6.2).
// NumPy twin: twin.py, gather_coverage (and blurlab.twins.film's tap_color, own_color).
#if defined(BLOCK_CLASSIFY)
#define TILE_LISTS_APPEND 1
#elif defined(OVER_LIST)
#define TILE_LISTS_READ 1
#endif
#include "common/tile_lists.glsl"
#include "common/eevee.glsl"
#include "common/mcguire2012.glsl"
#include "common/random.glsl"
#include "common/jittered_tile.glsl"

layout(binding = 0) uniform sampler2D color;
layout(binding = 1) uniform sampler2D depth;
layout(binding = 2) uniform sampler2D motion_sides;
#ifdef GATHER_READS_KEYS
// The scatter dilation's keys, resolved here rather than by a pass of their own
// (blurlab.methods.eevee.DILATION_VARIANTS scatter_in_gather).
#include "common/reach_keys.glsl"
layout(binding = 3) uniform sampler2D tiles;
layout(binding = 4) uniform usampler2D reach_keys;

ivec2 tile_grid() {
    return textureSize(tiles, 0);
}

vec4 dilated_at(ivec2 tile) {
    return resolved_reach(reach_keys, tiles, tile);
}
#else
layout(binding = 3) uniform sampler2D dilated;

ivec2 tile_grid() {
    return textureSize(dilated, 0);
}

vec4 dilated_at(ivec2 tile) {
    return texelFetch(dilated, tile, 0);
}
#endif
uniform int tile_size;     // px, from tile_percent
uniform float reach_limit;  // px, from max_blur
uniform int samples;
uniform float soft_z;
uniform float exposure;
uniform uint seed;
uniform float early_exit;  // px
#ifdef PER_TILE_SAMPLES
uniform float tap_spacing;  // px of the tile's longer line per tap
#endif
#ifdef UNIFORM_FAST_PATH
uniform float uniform_tolerance;  // px
#endif
#ifdef FILM_THROUGH_TAPS
uniform float film_spread;  // d, px²: the film kernel's variance (twins.film.film_spread)

// The colour at y read through the film filter for tap k: per axis weight 1 - d on y and d on
// its neighbour, the side each way turning with k % 4 as twins.film.TAP_TURNS.
vec4 film_tap(ivec2 y, int k, ivec2 size) {
    int turn = k % 4;
    ivec2 way = ivec2(turn == 0 || turn == 2 ? 1 : -1, turn == 0 || turn == 3 ? 1 : -1);
    ivec2 n = clamp(y + way, ivec2(0), size - 1);
    float d = film_spread;
    vec4 row = (1.0 - d) * sanitize_color(texelFetch(color, y, 0))
             + d * sanitize_color(texelFetch(color, ivec2(n.x, y.y), 0));
    vec4 next_row = (1.0 - d) * sanitize_color(texelFetch(color, ivec2(y.x, n.y), 0))
                  + d * sanitize_color(texelFetch(color, n, 0));
    return (1.0 - d) * row + d * next_row;
}

// X read through the film filter: the mean of the four turns, [d/2, 1 - d, d/2] on each axis.
vec4 film_own(ivec2 x, ivec2 size) {
    float d = film_spread;
    float weights[3] = float[3](0.5 * d, 1.0 - d, 0.5 * d);
    vec4 sum = vec4(0.0);
    for (int dy = -1; dy <= 1; ++dy) {
        int yy = clamp(x.y + dy, 0, size.y - 1);
        vec4 row = vec4(0.0);
        for (int dx = -1; dx <= 1; ++dx) {
            int xx = clamp(x.x + dx, 0, size.x - 1);
            row += weights[dx + 1] * sanitize_color(texelFetch(color, ivec2(xx, yy), 0));
        }
        sum += weights[dy + 1] * row;
    }
    return sum;
}
#endif

const uvec2 JITTER_SALTS = uvec2(0x510E527Fu, 0x9B05688Cu);
const float MOVING = 1.0;        // px: shorter half-motions count as still
const float ACROSS = 2.0;        // px: how far across a trail it still passes over X,
const float ACROSS_SHARE = 0.05; // ... plus this share of its length
const float MOVING_DEPTH = 10.0; // in-front extent where X moves, multiple of X's depth
const float DISPLAY_WHITE = 1.0; // colour above it is the hot share

// The share of a colour above display white (0 in alpha).
vec4 hot(vec4 c) {
    return vec4(max(c.rgb - DISPLAY_WHITE, 0.0), 0.0);
}

// a's signed distance across the unit vector b.
float cross2(vec2 a, vec2 b) {
    return a.x * b.y - a.y * b.x;
}

// How far (0..1) the trail of a pixel at offset d, moving by v (len = |v|) towards X, passes
// over X. The trail is the parabola through the pixel's three positions,
// d = τ·v + τ(1 − τ)·bend. A tap is held by its arithmetic on the H100 (docs/benchmarks.md,
// "What a tap costs"), so |d| is taken only for a still pixel and 1/|v| once. `on_pixel`: the
// same with the pixel's own width across (§17.6's hot share), 1 within half of it, 0 beyond it.
float trail_reaches(vec2 d, vec2 v, float len, vec2 bend, out float on_pixel) {
    if (len <= 0.0) {  // a still pixel reaches within ACROSS px
        float dist = length(d);
        float near = clamp(1.0 - dist, 0.0, 1.0);
        on_pixel = near;
        return near * clamp(ACROSS - dist, 0.0, 1.0);
    }
    float inverse = 1.0 / len;
    vec2 unit = v * inverse;
    float along = dot(d, unit);
    float tau = clamp(along * inverse, 0.0, 1.0);
    float across = abs(cross2(d, unit) - tau * (1.0 - tau) * cross2(bend, unit));
    float ahead = along > -0.5 ? 1.0 : 0.0;
    float widest = ACROSS + ACROSS_SHARE * len;
    float reach_along = clamp(len + 1.0 - along, 0.0, 1.0) * ahead;
    float width = abs(unit.x) + abs(unit.y);  // a pixel's width across its trail
    on_pixel = reach_along * clamp(2.0 - 2.0 * across / width, 0.0, 1.0);
    return reach_along * clamp(widest - across, 0.0, 1.0);
}

// cos between the tile's line and X's own motion, at least 0; 1 where X is still (both
// families then sample the tile's line).
float family_overlap(vec2 line, vec2 own) {
    float lo = length(own);
    if (lo < MOVING) return 1.0;
    return clamp(dot(line, own) / max(length(line) * lo, 1e-12), 0.0, 1.0);
}

// A half-motion scaled and clamped to reach_limit: clamp_length with the square root taken
// only where it clamps.
vec2 clamped_half(vec2 m) {
    vec2 v = scaled_motion(m, exposure);
    float n2 = dot(v, v);
    if (n2 > reach_limit * reach_limit) v *= reach_limit * inversesqrt(n2);
    return v;
}

// A pixel's half-motions: xy its prev half, zw its next half, scaled and clamped.
vec4 halves_at(ivec2 y) {
    vec4 m = texelFetch(motion_sides, y, 0);
    return vec4(clamped_half(m.xy), clamped_half(m.zw));
}

// The half-motion of a side read as a trail towards X: prev, or minus next.
vec2 trail_of(vec4 halves, int side) {
    return side == 0 ? halves.xy : -halves.zw;
}

// The colour of tap k = side·samples + i at y, through the film filter where it is read so.
vec4 tap_color(ivec2 y, int k, ivec2 size) {
#ifdef FILM_THROUGH_TAPS
    return film_tap(y, k, size);
#else
    return sanitize_color(texelFetch(color, y, 0));
#endif
}

#ifdef UNIFORM_FAST_PATH
// The uniform-motion path (docs/spec.md §17.6.1): per side the mean of X and of the taps along
// the tile's line, but those in front of X whose own trail lies further than
// uniform_tolerance px from the line (what does not move with X stands over it only where it
// is; what lies behind showed where X's object was not).
vec4 uniform_gather(ivec2 x, vec4 cx, float zx, vec2 lines[2], int taps, float j, ivec2 size) {
    vec2 center = vec2(x) + 0.5;
    vec4 result = vec4(0.0);
    for (int side = 0; side < 2; ++side) {
        vec4 total = cx;
        float kept = 1.0;
        float offset = fract(j + 0.25 * float(side));
        for (int i = 0; i < taps; ++i) {
            float t = (float(i) + offset) / float(taps);
            ivec2 y = clamp(ivec2(floor(center + lines[side] * t)), ivec2(0), size - 1);
            bool in_front = sanitize_depth(texelFetch(depth, y, 0).x) < zx;
            if (in_front && length(trail_of(halves_at(y), side) - lines[side]) > uniform_tolerance)
                continue;
            total += tap_color(y, side * samples + i, size);
            kept += 1.0;
        }
        result += 0.5 * total / kept;
    }
    return result;
}
#endif

// The lines of X's jittered tile, each side's clamped to reach_limit; returns the longer's length.
// Dilated tile `tile`'s two lines, each clamped to reach_limit; returns the longer's length.
float lines_of(ivec2 tile, out vec2 lines[2]) {
    vec4 tile_motion = dilated_at(tile);
    lines = vec2[2](clamp_length(tile_motion.xy, reach_limit),
                    -clamp_length(tile_motion.zw, reach_limit));
    return max(length(lines[0]), length(lines[1]));
}

float tile_lines(ivec2 x, out vec2 lines[2]) {
    return lines_of(jittered_tile(x, float(tile_size), seed, JITTER_SALTS, tile_grid()), lines);
}

#if defined(HALF_RES_GATHER) || defined(HALF_RES_READ)
uniform float half_res_above;  // px

// Whether X's 2 x 2 quad takes the half-resolution path: its top-left pixel's tile line is
// longer than half_res_above, and so are both half-motions of each of its pixels (a still
// pixel under a long tile stays sharp).
bool quad_is_long(ivec2 x) {
    ivec2 corner = 2 * (x / 2);
    vec2 lines[2];
    if (tile_lines(corner, lines) <= half_res_above) return false;
    ivec2 last = textureSize(color, 0) - 1;
    for (int i = 0; i < 4; ++i) {
        vec4 halves = halves_at(min(corner + ivec2(i & 1, i >> 1), last));
        if (min(length(halves.xy), length(halves.zw)) <= half_res_above) return false;
    }
    return true;
}
#endif
#ifdef HALF_RES_READ
layout(binding = 5) uniform sampler2D half_gathered;
#endif

// X's own colour, through the film filter where colours are read so.
vec4 own_color(ivec2 x, ivec2 size) {
#ifdef FILM_THROUGH_TAPS
    return film_own(x, size);
#else
    return sanitize_color(texelFetch(color, x, 0));
#endif
}

vec4 gather_at(ivec2 x) {
#ifdef HALF_RES_READ
    if (quad_is_long(x)) return texelFetch(half_gathered, x / 2, 0);
#endif
    ivec2 size = textureSize(color, 0);
    vec4 cx = own_color(x, size);
    vec2 lines[2];
    float longest = tile_lines(x, lines);
    if (longest < early_exit) return cx;
#ifdef PER_TILE_SAMPLES
    int taps = clamp(int(ceil(longest / tap_spacing)), 2, samples);
#else
    int taps = samples;
#endif

    float zx = sanitize_depth(texelFetch(depth, x, 0).x);
    vec4 x_halves = halves_at(x);
    vec2 owns[2] = vec2[2](trail_of(x_halves, 0), trail_of(x_halves, 1));
    vec2 x_bend = 0.5 * (x_halves.zw - x_halves.xy);
    bool x_moves = max(length(owns[0]), length(owns[1])) >= MOVING;
    // Where X moves, taps within MOVING_DEPTH times its depth (in effect any) count as in front
    // (its own object turns and tilts); where X is still, soft_z.
    float front_extent = (x_moves && !isinf(zx)) ? max(soft_z, MOVING_DEPTH * zx) : soft_z;
    float j = rand(uint(x.x), uint(x.y), seed);
#ifdef UNIFORM_FAST_PATH
    if (max(length(owns[0] - lines[0]), length(owns[1] - lines[1])) <= uniform_tolerance)
        return uniform_gather(x, cx, zx, lines, taps, j, size);
#endif
    vec2 center = vec2(x) + 0.5;
    int counts[2] = int[2]((taps + 1) / 2, taps / 2);
    vec4 behind_sum = vec4(0.0);
    float behind_weight = 0.0;
    vec4 cover_sums[2];
    float covers[2], seen_shares[2];
    for (int side = 0; side < 2; ++side) {
        vec2 own = owns[side];
        bool own_moves = length(own) >= MOVING;
        float share = 1.0 / (1.0 + family_overlap(lines[side], own));
        // What a family's taps share: the line they follow, their spacing, 1/count and the
        // offset of their jitter (family 0 the tile's line, family 1 X's own motion).
        vec2 along_0 = lines[side], along_1 = own_moves ? own : lines[side];
        float per_tap_0 = 1.0 / float(counts[0]), per_tap_1 = 1.0 / float(counts[1]);
        float spacing_0 = length(along_0) * per_tap_0 * share;
        float spacing_1 = length(along_1) * per_tap_1 * share;
        float offset_0 = fract(j + 0.25 * float(side));
        float offset_1 = fract(j + 0.5 + 0.25 * float(side));
        vec2 bend_1 = own_moves ? x_bend : vec2(0.0);
        cover_sums[side] = vec4(0.0);
        float cover = 0.0, spaced = 0.0, seen = 0.0;
        for (int i = 0; i < taps; ++i) {
            bool family_1 = (i & 1) == 1;
            vec2 along = family_1 ? along_1 : along_0;
            float spacing = family_1 ? spacing_1 : spacing_0;
            float t = (float(i >> 1) + (family_1 ? offset_1 : offset_0))
                    * (family_1 ? per_tap_1 : per_tap_0);
            // X's own family follows X's arc: the parabola through its three positions.
            vec2 bent = family_1 ? bend_1 * (t * (1.0 + t)) : vec2(0.0);
            ivec2 y = clamp(ivec2(floor(center + along * t + bent)), ivec2(0), size - 1);
            vec4 halves = halves_at(y);
            vec2 vy = trail_of(halves, side);
            float speed = length(vy);
            float moving = clamp(speed - 0.5, 0.0, 1.0);
            float zy = sanitize_depth(texelFetch(depth, y, 0).x);
            float on_pixel;
            float reaches = trail_reaches(vec2(y - x), vy, speed, 0.5 * (halves.zw - halves.xy),
                                          on_pixel);
            // soft_depth_compare(zx, zy, e) = clamp(1 - dz / e) and (zy, zx, e) = clamp(1 + dz / e)
            float dz = zx == zy ? 0.0 : zy - zx;
            float behind_soft = dz / soft_z;
            // the share of the half-shutter the tap's trail spends on X, where it reaches X
            float share_on_x = clamp(1.0 - dz / front_extent, 0.0, 1.0) * moving * spacing
                             / max(speed, 1.0);
            float a = share_on_x * reaches;
            float a_hot = share_on_x * on_pixel;
            // A still tap in front of a moving X hides the part of X's line behind it.
            float nearer = 1.0 - clamp(1.0 + behind_soft, 0.0, 1.0);
            spaced += spacing;
            seen += spacing * (1.0 - (x_moves ? 1.0 : 0.0) * nearer * (1.0 - moving));
            float b = (1.0 - nearer) * (1.0 - clamp(1.0 - behind_soft, 0.0, 1.0)) * (1.0 - reaches);
            cover += a;
            behind_weight += b;
#ifdef GATHER_SKIP_UNWEIGHTED
            // A tap of weight 0 on both sums adds +-0 to them (its colour is finite): same bits
            // without reading it.
            if (a == 0.0 && b == 0.0) continue;
#endif
            vec4 cy = tap_color(y, side * samples + i, size);
            cover_sums[side] += a * cy;
            // Colour past display white covers X only where the tap's own pixel crosses it:
            // the tolerance's stray weight would saturate pixels its streak never crosses.
            cover_sums[side] -= (a - a_hot) * hot(cy);
            behind_sum += b * cy;
        }
        covers[side] = cover;
        seen_shares[side] = seen > 0.0 ? spaced / seen : 1.0;
    }
    vec4 background = (x_moves && behind_weight > 0.0) ? behind_sum / behind_weight : cx;
    vec4 result = vec4(0.0);
    for (int side = 0; side < 2; ++side) {
        float alpha = min(covers[side] * seen_shares[side], 1.0);
        vec4 covering = cover_sums[side] / max(covers[side], 1e-12);
        result += 0.5 * (alpha * covering + (1.0 - alpha) * background);
    }
    return result;
}

#if defined(BLOCK_CLASSIFY) || defined(OVER_LIST)
const int LIST_BLOCK = 16;  // px: the blocks the lists hold (docs/spec.md §17.6.2)
#endif

#ifdef BLOCK_CLASSIFY
// The still blocks (docs/spec.md §17.6.2): block b of LIST_BLOCK px is still (class 0) where
// every tile that a pixel of b may look up, its jitter of up to a quarter tile included (one
// tile more on every side, against rounding), has lines shorter than early_exit, so that each of
// its pixels keeps its colour; else moving (1). Writes the class and appends b to its list.
// One invocation per block. NumPy twin: blurlab.twins.coverage.still_blocks.
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0, r32ui) uniform writeonly uimage2D block_class;

void main() {
    ivec2 b = ivec2(gl_GlobalInvocationID.xy);
    ivec2 blocks = imageSize(block_class);
    if (any(greaterThanEqual(b, blocks))) return;
    ivec2 size = textureSize(color, 0);
    float s = float(tile_size);
    vec2 low = vec2(b * LIST_BLOCK) + 0.5 - 0.25 * s;
    vec2 high = vec2(min(b * LIST_BLOCK + LIST_BLOCK, size) - 1) + 0.5 + 0.25 * s;
    ivec2 grid = tile_grid();
    ivec2 first = clamp(ivec2(floor(low / s)) - 1, ivec2(0), grid - 1);
    ivec2 last = clamp(ivec2(floor(high / s)) + 1, ivec2(0), grid - 1);
    bool still = true;
    for (int ty = first.y; ty <= last.y; ++ty) {
        for (int tx = first.x; tx <= last.x; ++tx) {
            vec2 lines[2];
            if (!(lines_of(ivec2(tx, ty), lines) < early_exit)) still = false;
        }
    }
    int cls = still ? 0 : 1;
    imageStore(block_class, b, uvec4(uint(cls)));
    append_tile(cls, b, blocks.x);
}
#elif defined(OVER_LIST)
// One 16 x 16 work group per block of list LIST_CLASS: a still block's pixels keep their colour
// (gather_at's early exit, which each of them takes), a moving block's gather.
layout(local_size_x = 16, local_size_y = 16) in;
layout(binding = 0, rgba32f) uniform writeonly image2D result;

void main() {
    ivec2 size = textureSize(color, 0);
    ivec2 blocks = (size + LIST_BLOCK - 1) / LIST_BLOCK;
    ivec2 x = listed_tile(blocks.x) * LIST_BLOCK + ivec2(gl_LocalInvocationID.xy);
    if (any(greaterThanEqual(x, size))) return;
#if LIST_CLASS == 0
    imageStore(result, x, own_color(x, size));
#else
    imageStore(result, x, gather_at(x));
#endif
}
#else
#ifdef HALF_RES_GATHER
// The half-resolution pass: invocation q gathers the top-left pixel 2q of its quad where the
// quad is long (the full-resolution pass reads it for all four pixels), nothing elsewhere.
vec4 half_gather_at(ivec2 q) {
    ivec2 x = 2 * q;
    return quad_is_long(x) ? gather_at(x) : vec4(0.0);
}
#define PASS_AT half_gather_at
#else
#define PASS_AT gather_at
#endif
#include "common/pass_main.glsl"
#endif
