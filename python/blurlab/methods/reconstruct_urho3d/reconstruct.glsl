#version 450
// reconstruct_urho3d: the reconstruct pass as the Urho3D thesis printed it (docs/spec.md §3.5,
// a variant of §3), kept as the seed's baseline (a fragment pass; STAGE_FRAGMENT only). Its
// differences from McGuire 2012 (methods/reconstruct_mcguire2012/reconstruct.glsl):
//   - start weight 0.75 instead of 1 / len(V[X]);
//   - sdc(za, zb) = clamp((za - zb) / soft_z, 0, 1);
//   - vN, V[X], V[Y] clamped per component to +-k pixels (no half-pixel minimum);
//   - samples Y at X + vN t + 0.5 px, read bilinearly (here from four texels in the shader:
//     hardware filtering weights have too few bits for the NumPy twin to match);
//   - jitter from a tiled 64 x 64 texture.
// Depth +inf (the background) is read as `far`, so that bilinear weights never meet inf * 0.
// NumPy twin: twin.py beside it (reconstruct_urho3d).
#include "common/inputs.glsl"
#include "common/mcguire2012.glsl"

layout(binding = 0) uniform sampler2D color;
layout(binding = 1) uniform sampler2D depth;
layout(binding = 2) uniform sampler2D motion;
layout(binding = 3) uniform sampler2D neighbor_max;
layout(binding = 4) uniform sampler2D jitter;  // 64 x 64, values in [0, 1)
uniform int k;
uniform int samples;
uniform float soft_z;
uniform float exposure;
uniform float far;

vec2 velocity_urho(vec2 m) {
    return clamp(m * exposure * 0.5, -float(k), float(k));
}

float depth_at(ivec2 p) {
    return min(sanitize_depth(texelFetch(depth, p, 0).x), far);
}

float sdc_urho(float za, float zb) {
    return clamp((za - zb) / soft_z, 0.0, 1.0);
}

struct Tap {
    vec4 color;
    float depth;
    vec2 motion;
};

// Bilinear read at a continuous position (texel centers at i + 0.5), edges clamped.
Tap bilinear(vec2 position) {
    ivec2 size = textureSize(color, 0);
    vec2 u = position - 0.5;
    vec2 f = u - floor(u);
    ivec2 i0 = ivec2(floor(u));
    Tap tap = Tap(vec4(0.0), 0.0, vec2(0.0));
    for (int dy = 0; dy <= 1; ++dy) {
        for (int dx = 0; dx <= 1; ++dx) {
            ivec2 p = clamp(i0 + ivec2(dx, dy), ivec2(0), size - 1);
            float w = (dx == 1 ? f.x : 1.0 - f.x) * (dy == 1 ? f.y : 1.0 - f.y);
            tap.color += w * sanitize_color(texelFetch(color, p, 0));
            tap.depth += w * depth_at(p);
            tap.motion += w * sanitize_motion(texelFetch(motion, p, 0).xy);
        }
    }
    return tap;
}

layout(location = 0) out vec4 result;

void main() {
    ivec2 x = ivec2(gl_FragCoord.xy);
    vec4 cx = sanitize_color(texelFetch(color, x, 0));
    vec2 vn = clamp(texelFetch(neighbor_max, x / k, 0).xy, -float(k), float(k));
    if (length(vn) <= 0.5 + 0.01) {
        result = cx;
        return;
    }
    float zx = depth_at(x);
    vec2 vx = velocity_urho(sanitize_motion(texelFetch(motion, x, 0).xy));
    float weight = 0.75;
    vec4 sum = cx * weight;
    float j = texelFetch(jitter, x % 64, 0).x - 0.5;
    vec2 center = vec2(x) + 0.5;
    int skip = (samples % 2 == 1) ? (samples - 1) / 2 : -1;
    for (int i = 0; i < samples; ++i) {
        if (i == skip) continue;
        float t = -1.0 + 2.0 * (float(i) + j + 1.0) / float(samples + 1);
        Tap y = bilinear(center + vn * t);
        vec2 vy = velocity_urho(y.motion);
        float dist = length(vn * t);
        float f = sdc_urho(zx, y.depth);
        float b = sdc_urho(y.depth, zx);
        float a = f * cone(dist, vy) + b * cone(dist, vx)
                + cylinder(dist, vy) * cylinder(dist, vx) * 2.0;
        weight += a;
        sum += a * y.color;
    }
    result = sum / weight;
}
