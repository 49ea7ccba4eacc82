// Taps of the engines' gathers (docs/spec.md §4), shared by the gathers along the motion.
// A tap at continuous position p reads the pixel containing it. Edge rules ("Blurry things"):
//   clamp  - a tap outside the image reads the nearest edge pixel;
//   ignore - a tap outside the image is dropped and the weights of the others renormalized;
//   guard  - the frame was rendered with a margin, so taps stay inside (run as clamp, cropped).
#include "common/inputs.glsl"

layout(binding = 0) uniform sampler2D color;
layout(binding = 1) uniform sampler2D motion;
// The method's `edge` parameter as its index among the choices; EDGE_CLAMP, EDGE_IGNORE and
// EDGE_GUARD are defined from the parameter's declaration (blurlab/methods/gathers.py).
uniform int edge;

// Adds weight * color at p to sum (rgb, a) and the weight used to total.
void add_tap(vec2 p, float weight, inout vec4 sum, inout float total) {
    ivec2 size = textureSize(color, 0);
    ivec2 y = ivec2(floor(p));
    if (any(lessThan(y, ivec2(0))) || any(greaterThanEqual(y, size))) {
        if (edge == EDGE_IGNORE) return;
        y = clamp(y, ivec2(0), size - 1);
    }
    sum += weight * sanitize_color(texelFetch(color, y, 0));
    total += weight;
}
