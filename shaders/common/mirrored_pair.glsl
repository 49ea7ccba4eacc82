// The mirrored pair of Guertin et al. 2014 (docs/spec.md §7.2), shared by the filters that
// take it: the pair takes the weight of its sample that is nearer and moves farther (sample
// 1's where neither sample is both). z: depths, s: speeds of samples 1 and 2.
void mirror_pair(inout float a1, inout float a2, float z1, float z2, float s1, float s2) {
    bool behind = z1 > z2;
    bool slower = s2 > s1;
    if (behind && slower) a1 = a2;
    else if (!behind && !slower) a2 = a1;
}

// Pair i of `pairs` mirrored about X's center along v: the texels at center ± t·v,
// t = (i + j) / pairs with jitter j, clamped to an image of `size`.
void mirrored_taps(ivec2 x, vec2 v, int i, float j, int pairs, ivec2 size, out ivec2 y1,
                   out ivec2 y2) {
    float t = (float(i) + j) / float(pairs);
    vec2 center = vec2(x) + 0.5;
    y1 = clamp(ivec2(floor(center + t * v)), ivec2(0), size - 1);
    y2 = clamp(ivec2(floor(center - t * v)), ivec2(0), size - 1);
}

// A mirrored pair's taps, weights a1, a2 and colours c1, c2, added to the sums.
void add_pair(float a1, float a2, vec4 c1, vec4 c2, inout vec4 sum, inout float weight) {
    weight += a1 + a2;
    sum += a1 * c1 + a2 * c2;
}
