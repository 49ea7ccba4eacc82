// Tonal-art-map hatching, docs/spec.md §5 (Praun, Hoppe, Webb, Finkelstein 2001, "Real-Time
// Hatching"; Webb, Praun, Finkelstein, Hoppe 2002, "Fine Tone Control in Hardware Hatching").
// NumPy twin: python/blurlab/twins/hatching.py. Tones are numbered 0 (white paper) to 6
// (the darkest TAM tone); darkness = 1 − intensity.

const vec3 HATCHING_LUMINANCE = vec3(0.2126, 0.7152, 0.0722);

// The tone source: the luminance of Lambert (specular = 0) or Blinn–Phong light on a white
// surface, in [0, 1]. `n` faces the viewer, `v` points to the eye, `l` to the light.
float hatching_intensity(vec3 n, vec3 v, vec3 l, vec3 light_color, vec3 ambient, float specular,
                         float shininess) {
    float diffuse = max(dot(n, l), 0.0);
    float highlight = 0.0;
    if (diffuse > 0.0 && specular > 0.0)
        highlight = specular * pow(max(dot(n, normalize(l + v)), 0.0), shininess);
    return clamp(dot(ambient + light_color * (diffuse + highlight), HATCHING_LUMINANCE), 0.0, 1.0);
}

// six_way_blend: tone t = 6·(1 − intensity); the two nearest tones floor(t) and floor(t) + 1
// get 1 − fract(t) and fract(t), all others 0 (the hat function max(0, 1 − |t − k|)). Tone 0
// is paper and needs no texture: `low` holds tones 1–3, `high` tones 4–6.
void six_way_weights(float intensity, out vec3 low, out vec3 high) {
    float t = 6.0 * (1.0 - clamp(intensity, 0.0, 1.0));
    low = max(vec3(0.0), 1.0 - abs(t - vec3(1.0, 2.0, 3.0)));
    high = max(vec3(0.0), 1.0 - abs(t - vec3(4.0, 5.0, 6.0)));
}
