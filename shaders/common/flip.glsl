// LDR-FLIP's colour spaces (Andersson et al. 2020), docs/spec.md §6.1; NumPy twin:
// blurlab.twins.flip. XYZ is normalized by the reference white (XYZ of linear RGB (1, 1, 1)),
// so the white point never appears below. XYZ_TO_RGB_NORMALIZED is injected by the pass: the
// inverse of RGB_TO_XYZ_NORMALIZED, computed in double on the CPU.

// Linear sRGB to XYZ / white: the sRGB primaries' matrix (exact rationals) with each row
// divided by its sum, written column by column as GLSL wants.
const mat3 RGB_TO_XYZ_NORMALIZED = transpose(mat3(
    vec3(10135552.0, 8788810.0, 4435075.0) / 23359437.0,
    vec3(2613072.0, 8788810.0, 887015.0) / 12288897.0,
    vec3(1425312.0, 8788810.0, 70074185.0) / 80288307.0));

vec3 linear_to_ycxcz(vec3 linear) {
    vec3 t = RGB_TO_XYZ_NORMALIZED * clamp(linear, 0.0, 1.0);
    return vec3(116.0 * t.y - 16.0, 500.0 * (t.x - t.y), 200.0 * (t.y - t.z));
}

vec3 ycxcz_to_linear(vec3 c) {
    float y = (c.x + 16.0) / 116.0;
    return XYZ_TO_RGB_NORMALIZED * vec3(c.y / 500.0 + y, y, y - c.z / 200.0);
}

// CIELAB of linear RGB with the Hunt effect (a*, b* scaled by L* / 100).
vec3 linear_to_hunt_lab(vec3 linear) {
    const float delta = 6.0 / 29.0;
    vec3 t = RGB_TO_XYZ_NORMALIZED * linear;
    vec3 f = mix(t / (3.0 * delta * delta) + 4.0 / 29.0, pow(max(t, 0.0), vec3(1.0 / 3.0)),
                 greaterThan(t, vec3(delta * delta * delta)));
    float l = 116.0 * f.y - 16.0;
    return vec3(l, 0.01 * l * vec2(500.0 * (f.x - f.y), 200.0 * (f.y - f.z)));
}

// The HyAB distance: |ΔL| plus the Euclidean distance in (a, b).
float hyab(vec3 a, vec3 b) {
    vec3 d = a - b;
    return abs(d.x) + length(d.yz);
}
