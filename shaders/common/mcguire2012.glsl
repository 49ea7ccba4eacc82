// Shared terms of the reconstruction filter of McGuire, Hennessy, Bukowski and Osman,
// "A Reconstruction Filter for Plausible Motion Blur", I3D 2012 — docs/spec.md §3.
// NumPy twin: blurlab.twins.mcguire2012.

// §3.1: the half-vector, its length clamped to [0.5, k] pixels; zero stays zero.
vec2 half_velocity(vec2 motion, float exposure, float k) {
    vec2 q = motion * exposure * 0.5;
    float n = length(q);
    if (n == 0.0) return vec2(0.0);
    if (isinf(n)) {
        // |q|^2 overflowed float32 (|q| > 1.8e19): take the direction from q scaled down.
        vec2 d = q / max(abs(q.x), abs(q.y));
        return d / length(d) * k;
    }
    return q * (clamp(n, 0.5, k) / max(n, 1e-6));
}

// §3: wherever a length divides, it is at least half a pixel.
float len_half(vec2 v) {
    return max(length(v), 0.5);
}

// §3.4 cone(P, Q, v) with dist = |P - Q|.
float cone(float dist, vec2 v) {
    return clamp(1.0 - dist / len_half(v), 0.0, 1.0);
}

// §3.4 cyl(P, Q, v) with dist = |P - Q|.
float cylinder(float dist, vec2 v) {
    float l = len_half(v);
    return 1.0 - smoothstep(0.95 * l, 1.05 * l, dist);
}

// §3.4 sdc(za, zb) = clamp(1 - (zb - za) / soft_z, 0, 1): 1 where zb is as near as za or
// nearer. Equal depths (two background pixels, both +inf) compare as equal, not as inf - inf.
float soft_depth_compare(float za, float zb, float soft_z) {
    float d = za == zb ? 0.0 : zb - za;
    return clamp(1.0 - d / soft_z, 0.0, 1.0);
}
