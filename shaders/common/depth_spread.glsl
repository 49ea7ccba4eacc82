// The tap weight of Jimenez 2014 (docs/spec.md §17.5 step 4, §17.8), shared by engine_unreal and
// engine_jimenez2014: the soft depth split of whether X's own blur reaches the tap (the tap lies
// behind X) or the tap's blur reaches X (it lies in front), each a spread over its last pixel.
// NumPy twin: blurlab.twins.unreal.tap_weight.

// 1 where a blur of radius `len` reaches `dist` pixels, falling to 0 over its last pixel.
float spread(float dist, float len) {
    return clamp(1.0 + len - dist, 0.0, 1.0);
}

// A tap at depth z_y with blur radius len_y, `dist` pixels from X (depth z_x, radius len_x);
// the split's extent is `extent` depth units. At most 1.
float depth_spread_weight(float z_x, float len_x, float z_y, float len_y, float dist, float extent) {
    float d = z_y == z_x ? 0.0 : (z_y - z_x) / extent;
    float behind = clamp(0.5 + d, 0.0, 1.0);
    return min(behind * spread(dist, len_x) + (1.0 - behind) * spread(dist, len_y), 1.0);
}

// The pairs' mean over their 2·pairs taps; the weight the taps leave stays with C(X) = cx.
vec4 left_to_center(vec4 sum, float weight, vec4 cx, int pairs) {
    float n = float(2 * pairs);
    return (sum + (n - weight) * cx) / n;
}
