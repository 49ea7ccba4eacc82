#version 450
// A pass with one function per tile class (tests/test_tile_lists.py): class 0 copies the colour,
// class 1 averages 5 taps along the pixel's motion, class 2 averages 9. With OVER_LIST it runs
// over one class's tile list (indirect dispatch); without, over every tile, each tile taking the
// function its class (tile_class_in) names. Both must write the same bits. Tiles are 16 px.
#ifdef OVER_LIST
#define TILE_LISTS_READ 1
#define TILE_LIST_SAMPLER 3
#endif
#include "common/inputs.glsl"
#include "common/tile_lists.glsl"

layout(local_size_x = 16, local_size_y = 16) in;
layout(binding = 0) uniform sampler2D color;
layout(binding = 1) uniform sampler2D motion;
layout(binding = 2) uniform usampler2D tile_class_in;
layout(binding = 0, rgba32f) uniform image2D result;

vec4 along(ivec2 x, int taps) {
    ivec2 size = textureSize(color, 0);
    vec2 m = sanitize_motion(texelFetch(motion, x, 0).xy);
    vec4 sum = vec4(0.0);
    for (int i = 0; i < taps; ++i) {
        float s = float(i) / float(taps - 1) - 0.5;
        ivec2 y = clamp(ivec2(floor(vec2(x) + 0.5 + s * m)), ivec2(0), size - 1);
        sum += texelFetch(color, y, 0);
    }
    return sum / float(taps);
}

void main() {
    ivec2 grid = textureSize(tile_class_in, 0);
#ifdef OVER_LIST
    ivec2 tile = listed_tile(grid.x);
    int cls = tile_class;
#else
    ivec2 tile = ivec2(gl_WorkGroupID.xy);
    int cls = int(texelFetch(tile_class_in, tile, 0).x);
#endif
    ivec2 x = tile * 16 + ivec2(gl_LocalInvocationID.xy);
    if (any(greaterThanEqual(x, imageSize(result)))) return;
    vec4 c = cls == 0 ? texelFetch(color, x, 0) : along(x, cls == 1 ? 5 : 9);
    imageStore(result, x, c);
}
