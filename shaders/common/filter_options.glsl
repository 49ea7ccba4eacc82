// Options of the reconstruction filters reconstruct_mcguire2012 and reconstruct_guertin2014
// (docs/guertin2014.md "Options"). Each is off at its default, which leaves docs/spec.md §3.4
// unchanged. Needs common/random.glsl. NumPy twin: blurlab.twins.mcguire2012 (lookup_tile,
// sample_count, exits_early).

// Jittered tile lookup (Unity / KinoMotion): the tile whose NeighborMax pixel x reads. Off: the
// tile containing x. On: the tile containing x_center + k/4 (cos a, sin a), a = 2 pi
// rand(x, y, seed ^ TILE_JITTER_SALT), clamped to the grid; where that would be a diagonal
// neighbor (as the HPG 2014 paper forbids), the axis of the smaller offset stays x's own.
const uint TILE_JITTER_SALT = 0x68E31DA4u;

ivec2 lookup_tile(ivec2 x, int k, uint seed, bool jitter, ivec2 grid) {
    ivec2 own = x / k;
    if (!jitter) return own;
    float a = 6.283185307179586 * rand(uint(x.x), uint(x.y), seed ^ TILE_JITTER_SALT);
    vec2 offset = 0.25 * float(k) * vec2(cos(a), sin(a));
    ivec2 tile = clamp(ivec2(floor((vec2(x) + 0.5 + offset) / float(k))), ivec2(0), grid - 1);
    if (tile.x != own.x && tile.y != own.y) {
        if (abs(offset.x) >= abs(offset.y)) tile.y = own.y;
        else tile.x = own.x;
    }
    return tile;
}

// Adaptive sample count: about one sample per 2 pixels of the blur's span 2|vN|, at least 2 and
// at most S; off: S.
int sample_count(float vn_length, int samples, bool adaptive) {
    if (!adaptive) return samples;
    return min(samples, max(2, int(floor(vn_length + 0.5))));
}

// Early exit: nothing moves near x (|vN| <= 0.5 + 0.01, docs/spec.md §3.4), or, with a threshold
// early_exit > 0 pixels, the neighborhood's longest motion 2|vN| is under it.
bool exits_early(float vn_length, float early_exit) {
    return vn_length <= 0.5 + 0.01 || 2.0 * vn_length < early_exit;
}
