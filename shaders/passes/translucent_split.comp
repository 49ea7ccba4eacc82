#version 450
// The translucent layer as a frame the methods read (docs/spec.md §20.4, layered): its dominant
// fragment's motion and depth apart, and its two-sided motion at constant velocity around the
// instant (§17.1: share_prev·M before, share_next·M after), as blurlab.Frame derives them.
layout(local_size_x = 16, local_size_y = 16) in;
layout(binding = 0) uniform sampler2D translucent_motion;  // motion xy, depth, count
layout(binding = 0, rg32f) uniform writeonly image2D layer_motion;
layout(binding = 1, r32f) uniform writeonly image2D layer_depth;
layout(binding = 2, rgba32f) uniform writeonly image2D layer_sides;
uniform float share_prev;
uniform float share_next;

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, imageSize(layer_motion)))) return;
    vec4 layer = texelFetch(translucent_motion, p, 0);
    imageStore(layer_motion, p, vec4(layer.xy, 0.0, 0.0));
    imageStore(layer_depth, p, vec4(layer.z));
    imageStore(layer_sides, p, vec4(layer.xy * share_prev, layer.xy * share_next));
}
