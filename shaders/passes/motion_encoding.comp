#version 450
// Motion-vector storage formats, docs/spec.md §2 (the precision study of "Blurry things").
// Built with FORMAT_* (the stored format) and either ENCODE (rg32f motion -> stored) or DECODE
// (stored -> rg32f motion, as a method reading that format would see it).
//   rg16f         M as half floats
//   rgba8_offset  c = clamp(M / maxlen, -1, 1) * 0.5 + 0.5 per channel; M = (c * 2 - 1) * maxlen,
//                 except that levels 127 and 128 decode to 0: 0.5 is not an 8-bit level, and
//                 without this every still pixel moves by half a step (8.6 px at maxlen = the
//                 1080p diagonal)
//   rgba8_polar   RG = dir * 0.5 + 0.5, B = sqrt(min(|M| / maxlen, 1)); M = dir * B^2 * maxlen
#include "common/pixel.glsl"

layout(local_size_x = 16, local_size_y = 16) in;

#if defined(FORMAT_RG16F)
#define STORED_LAYOUT rg16f
#else
#define STORED_LAYOUT rgba8
#endif

#ifdef ENCODE
layout(binding = 0, rg32f) uniform readonly image2D motion;
layout(binding = 1, STORED_LAYOUT) uniform writeonly image2D stored;
#else
layout(binding = 0, STORED_LAYOUT) uniform readonly image2D stored;
layout(binding = 1, rg32f) uniform writeonly image2D motion;
#endif

uniform float maxlen;

vec4 encode(vec2 m) {
#if defined(FORMAT_RG16F)
    return vec4(m, 0.0, 0.0);  // the image format rounds to half
#elif defined(FORMAT_RGBA8_OFFSET)
    return vec4(clamp(m / maxlen, -1.0, 1.0) * 0.5 + 0.5, 0.0, 1.0);
#elif defined(FORMAT_RGBA8_POLAR)
    float len = length(m);
    vec2 dir = len > 0.0 ? m / len : vec2(0.0);
    return vec4(dir * 0.5 + 0.5, sqrt(min(len / maxlen, 1.0)), 1.0);
#endif
}

vec2 decode(vec4 c) {
#if defined(FORMAT_RG16F)
    return c.xy;
#elif defined(FORMAT_RGBA8_OFFSET)
    vec2 level = round(c.xy * 255.0);
    vec2 m = (c.xy * 2.0 - 1.0) * maxlen;
    return mix(m, vec2(0.0), lessThan(abs(level - 127.5), vec2(1.0)));
#elif defined(FORMAT_RGBA8_POLAR)
    return (c.xy * 2.0 - 1.0) * (c.z * c.z) * maxlen;
#endif
}

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (outside(p, imageSize(motion))) return;
#ifdef ENCODE
    imageStore(stored, p, encode(imageLoad(motion, p).xy));
#else
    imageStore(motion, p, vec4(decode(imageLoad(stored, p)), 0.0, 0.0));
#endif
}
