// The jittered tile lookup of engine_eevee and engine_unity (docs/spec.md §17.2, §17.3): the
// tile containing pixel x's center moved by (rand - 1/2)·s/2 per axis (up to ±1/4 tile),
// clamped to the grid; each method hashes with its own salts. Needs common/random.glsl.
// NumPy twin: blurlab.twins.eevee.lookup_tile.

ivec2 jittered_tile(ivec2 x, float s, uint seed, uvec2 salts, ivec2 grid) {
    vec2 offset = (vec2(rand(uint(x.x), uint(x.y), seed ^ salts.x),
                        rand(uint(x.x), uint(x.y), seed ^ salts.y)) - 0.5) * 0.5 * s;
    return clamp(ivec2(floor((vec2(x) + 0.5 + offset) / s)), ivec2(0), grid - 1);
}

// What pixel x reads of `tiles`, one texel per tile of `tile_size` pixels, through that lookup.
vec4 jittered_tile_texel(sampler2D tiles, ivec2 x, int tile_size, uint seed, uvec2 salts) {
    ivec2 grid = textureSize(tiles, 0);
    return texelFetch(tiles, jittered_tile(x, float(tile_size), seed, salts, grid), 0);
}
