#version 450
// The translucent layer over the opaque one (docs/spec.md §20.4), premultiplied:
// out = Σ + (1 − a)·opaque, alpha the opaque's. "unblurred" takes the layer as rendered,
// "layered" as blurred with its own motion. NumPy twin: blurlab.twins.translucency.over.
layout(local_size_x = 16, local_size_y = 16) in;
layout(binding = 0) uniform sampler2D layer;   // Σ, a
layout(binding = 1) uniform sampler2D opaque;  // the opaque layer, blurred
layout(binding = 0, rgba32f) uniform writeonly image2D result;

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, imageSize(result)))) return;
    vec4 front = texelFetch(layer, p, 0), back = texelFetch(opaque, p, 0);
    imageStore(result, p, vec4(front.rgb + (1.0 - front.a) * back.rgb, back.a));
}
