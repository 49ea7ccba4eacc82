#version 450
// Translucent resolve, docs/spec.md §20: each pixel's list of translucent fragments (written by
// the G-buffer pass with LAYERS, src/passes/gbuffer.h) sorted back to front by a total order on
// the fragments' values, so that the result does not depend on the order they were drawn in, and
// composited over the opaque colour with each fragment's own rule. Also the translucent layer
// apart: premultiplied colour Σ and coverage a, and the depth and motion of its dominant fragment.
// NumPy twin: blurlab.twins.translucency.resolve.
// CAPACITY (a define): the fragments a pixel holds.

layout(local_size_x = 16, local_size_y = 16) in;
layout(binding = 0) uniform sampler2D opaque_color;
layout(binding = 1) uniform usampler2D fragment_counts;
layout(binding = 2) uniform sampler2D fragment_surface;  // premultiplied rgb, coverage
layout(binding = 3) uniform sampler2D fragment_motion;   // depth, motion xy, alpha mode
layout(binding = 0, rgba32f) uniform writeonly image2D composite;
layout(binding = 1, rgba32f) uniform writeonly image2D translucent;
layout(binding = 2, rgba32f) uniform writeonly image2D translucent_motion;  // motion, depth, count
layout(binding = 3, r32ui) uniform uimage2D most_fragments;  // 1 x 1: the largest count

vec4 surfaces[CAPACITY];
vec4 motions[CAPACITY];

// Whether fragment (s, m) lies behind fragment (t, n): greater depth first, ties broken by the
// fragments' other values (coverage, colour, mode, motion) in a fixed order.
bool behind(vec4 s, vec4 m, vec4 t, vec4 n) {
    float a[8] = float[8](m.x, s.a, s.r, s.g, s.b, m.w, m.y, m.z);
    float b[8] = float[8](n.x, t.a, t.r, t.g, t.b, n.w, n.y, n.z);
    for (int k = 0; k < 8; ++k)
        if (a[k] != b[k]) return a[k] > b[k];
    return false;
}

// How much of the image a fragment makes: its coverage for blend, its brightest premultiplied
// channel (at most 1) for additive, whose coverage is 0.
float strength(vec4 s, vec4 m) {
    return m.w == 3.0 ? min(1.0, max(max(s.r, s.g), s.b)) : s.a;
}

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = imageSize(composite);
    if (any(greaterThanEqual(p, size))) return;
    uint count = texelFetch(fragment_counts, p, 0).r;
    if (count > 0u) imageAtomicMax(most_fragments, ivec2(0), count);
    int n = int(min(count, uint(CAPACITY)));
    int rows = textureSize(fragment_surface, 0).y / size.y;  // fragment_layout's blocks
    // Insertion sort as the fragments are read: index 0 is the backmost.
    for (int k = 0; k < n; ++k) {
        ivec2 q = ivec2(p.x + k / rows * size.x, p.y + k % rows * size.y);
        vec4 s = texelFetch(fragment_surface, q, 0), m = texelFetch(fragment_motion, q, 0);
        int j = k;
        while (j > 0 && behind(s, m, surfaces[j - 1], motions[j - 1])) {
            surfaces[j] = surfaces[j - 1];
            motions[j] = motions[j - 1];
            --j;
        }
        surfaces[j] = s;
        motions[j] = m;
    }
    // Back to front: the composite over the opaque colour, and the layer apart (Σ, a).
    vec4 color = texelFetch(opaque_color, p, 0);
    vec3 sum = vec3(0.0);
    float coverage = 0.0;
    for (int k = 0; k < n; ++k) {
        float alpha = surfaces[k].a;
        color.rgb = surfaces[k].rgb + (1.0 - alpha) * color.rgb;
        sum = surfaces[k].rgb + (1.0 - alpha) * sum;
        coverage = alpha + (1.0 - alpha) * coverage;
    }
    // The dominant fragment: the largest strength x the transmittance in front of it (front to
    // back; the front one wins a tie).
    float transmittance = 1.0, best = 0.0;
    vec3 dominant = vec3(0.0, 0.0, uintBitsToFloat(0x7f800000u));  // motion, depth (+inf: none)
    for (int k = n - 1; k >= 0; --k) {
        float weight = strength(surfaces[k], motions[k]) * transmittance;
        if (weight > best) {
            best = weight;
            dominant = vec3(motions[k].yz, motions[k].x);
        }
        transmittance *= 1.0 - surfaces[k].a;
    }
    imageStore(composite, p, color);
    imageStore(translucent, p, vec4(sum, coverage));
    imageStore(translucent_motion, p, vec4(dominant, float(count)));
}
