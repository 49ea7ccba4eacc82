#version 450
// engine_unity step 4, docs/spec.md §17.3: the reconstruction. NeighborMax read at a tile
// lookup jittered by up to ±1/4 tile per axis; under 2 px the pixel keeps its color. Otherwise
// n = clamp(floor(|vmax|/2), 1, samples) mirrored sample pairs, alternately along vmax and
// along v_alt (the center's own direction where it moves more than half as far as vmax),
// weighted by a soft depth comparison on the 10-bit linear depth (factor depth_factor) and §3.4's
// cones; each pair takes the weight of its nearer and faster sample. Compute, one invocation per
// pixel. NumPy twin: twin.engine_unity (twin.py).
#include "common/inputs.glsl"
#include "common/mcguire2012.glsl"
#include "common/random.glsl"
#include "common/jittered_tile.glsl"
#include "unity.glsl"
#include "common/mirrored_pair.glsl"

layout(binding = 0) uniform sampler2D color;
layout(binding = 1) uniform sampler2D velocity;
layout(binding = 2) uniform sampler2D neighbor_max;
uniform int samples;
uniform float depth_factor;
uniform float radius;  // R, pixels
uniform int tile;      // T, pixels
uniform uint seed;

const float EARLY_EXIT = 2.0;
const uvec2 JITTER_SALTS = uvec2(0x1B873593u, 0xCC9E2D51u);

vec4 reconstruct_at(ivec2 x) {
    ivec2 size = textureSize(color, 0);
    vec4 cx = sanitize_color(texelFetch(color, x, 0));
    vec4 lookup = jittered_tile_texel(neighbor_max, x, tile, seed, JITTER_SALTS);
    vec2 vmax = decode_velocity(lookup.xy, radius);
    float l_max = length(vmax);
    if (l_max < EARLY_EXIT) return cx;

    vec4 own = texelFetch(velocity, x, 0);
    vec2 vc = decode_velocity(own.xy, radius);
    float zc = own.z / CODE_MAX;
    float l_c = length(vc);
    vec2 v_alt = 2.0 * l_c > l_max ? vc * (l_max / max(l_c, 1e-20)) : vmax;
    int n = int(clamp(floor(l_max / 2.0), 1.0, float(samples)));

    float weight = 1.0 / max(l_c, 0.5);
    vec4 sum = cx * weight;
    float j = rand(uint(x.x), uint(x.y), seed);
    for (int i = 0; i < n; ++i) {
        ivec2 y1, y2;
        mirrored_taps(x, (i % 2 == 0) ? vmax : v_alt, i, j, n, size, y1, y2);
        vec4 s1 = texelFetch(velocity, y1, 0);
        vec4 s2 = texelFetch(velocity, y2, 0);
        vec2 v1 = decode_velocity(s1.xy, radius);
        vec2 v2 = decode_velocity(s2.xy, radius);
        float z1 = s1.z / CODE_MAX, z2 = s2.z / CODE_MAX;
        float f1 = clamp(0.5 + depth_factor * (zc - z1), 0.0, 1.0);
        float f2 = clamp(0.5 + depth_factor * (zc - z2), 0.0, 1.0);
        float a1 = f1 * cone(length(vec2(y1 - x)), v1) + (1.0 - f1) * cone(length(vec2(y1 - x)), vc);
        float a2 = f2 * cone(length(vec2(y2 - x)), v2) + (1.0 - f2) * cone(length(vec2(y2 - x)), vc);
        mirror_pair(a1, a2, z1, z2, length(v1), length(v2));
        vec4 c1 = sanitize_color(texelFetch(color, y1, 0));
        add_pair(a1, a2, c1, sanitize_color(texelFetch(color, y2, 0)), sum, weight);
    }
    return sum / weight;
}

#define PASS_AT reconstruct_at
#include "common/pass_main.glsl"
