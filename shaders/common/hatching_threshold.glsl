// The threshold scheme of docs/spec.md §5 (Webb, Praun, Finkelstein, Hoppe 2002), fragment stage only
// (it needs implicit derivatives). NumPy twin: python/blurlab/twins/hatching.py.

// threshold, at one mip level: each texel is ink where its threshold < darkness; the four texels
// around uv are blended with weights smoothstep(fract) in x and y, a smooth step one texel wide
// across stroke edges (antialiasing without letting filtered thresholds move the edges).
float threshold_ink_level(sampler2D thresholds, vec2 uv, int level, float darkness) {
    ivec2 size = textureSize(thresholds, level);
    vec2 p = uv * vec2(size) - 0.5;
    ivec2 corner = ivec2(floor(p));
    vec2 f = smoothstep(0.0, 1.0, p - floor(p));
    float ink[4];
    for (int k = 0; k < 4; ++k) {
        ivec2 texel = corner + ivec2(k & 1, k >> 1);
        texel = ((texel % size) + size) % size;  // the TAM repeats
        ink[k] = texelFetch(thresholds, texel, level).r < darkness ? 1.0 : 0.0;
    }
    return mix(mix(ink[0], ink[1], f.x), mix(ink[2], ink[3], f.x), f.y);
}

// threshold: the level of detail GL would pick for trilinear filtering, and the two levels
// around it blended. Must be called in uniform control flow (implicit derivatives).
float threshold_ink(sampler2D thresholds, vec2 uv, float darkness) {
    float lod = textureQueryLod(thresholds, uv).x;
    int last = textureQueryLevels(thresholds) - 1;
    int level = min(int(floor(lod)), last);
    float ink = threshold_ink_level(thresholds, uv, level, darkness);
    if (level == last) return ink;
    return mix(ink, threshold_ink_level(thresholds, uv, level + 1, darkness), fract(lod));
}
