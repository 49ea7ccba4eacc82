// The tile reductions of engine_unity, engine_hdrp and engine_unreal (docs/spec.md §17.3-§17.5):
// over the block of `side` x `side` texels of `codes` at `origin` (the last ones may be
// partial), the code (.xy) whose block_key is largest, the first in row-major order among equal
// keys (`none` where no key exceeds `none_key`), and the smallest length code (.x). The shader
// that includes it defines float block_key(vec2 code) first.

struct BlockExtremes {
    vec2 longest;
    float shortest;
};

BlockExtremes block_extremes(sampler2D codes, ivec2 origin, int side, vec2 none, float none_key) {
    ivec2 end = min(origin + side, textureSize(codes, 0));
    BlockExtremes found = BlockExtremes(none, 3.4e38);
    float best_key = none_key;
    for (int y = origin.y; y < end.y; ++y) {
        for (int x = origin.x; x < end.x; ++x) {
            vec2 c = texelFetch(codes, ivec2(x, y), 0).xy;
            float k = block_key(c);
            if (k > best_key) {
                found.longest = c;
                best_key = k;
            }
            found.shortest = min(found.shortest, c.x);
        }
    }
    return found;
}
