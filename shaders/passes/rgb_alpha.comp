#version 450
// One texture's RGB with another's alpha, docs/spec.md §21.4: a sequence's output keeps the
// frame's alpha, a method after TAA reads TAA's colour with the frame's alpha, and the history of
// "blur_in_history" is the blurred colour with the history's count in alpha. No value is changed.
layout(local_size_x = 16, local_size_y = 16) in;
layout(binding = 0) uniform sampler2D rgb;
layout(binding = 1) uniform sampler2D alpha;
layout(binding = 0, rgba32f) uniform writeonly image2D result;

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, imageSize(result)))) return;
    imageStore(result, p, vec4(texelFetch(rgb, p, 0).rgb, texelFetch(alpha, p, 0).a));
}
