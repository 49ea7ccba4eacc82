#version 450
// The two-sided motion of a frame that has none of its own, docs/spec.md §17.1: constant velocity
// around the instant, M_prev = f·M and M_next = (1 − f)·M (f the instant's place in the shutter),
// packed as (M_prev, M_next). One float32 product per component, as the NumPy twin
// (Frame.motion_prev and motion_next derived from motion) computes it.
layout(local_size_x = 16, local_size_y = 16) in;
layout(binding = 0) uniform sampler2D motion;
layout(binding = 0, rgba32f) uniform writeonly image2D motion_sides;
uniform float share_prev;
uniform float share_next;

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, imageSize(motion_sides)))) return;
    vec2 m = texelFetch(motion, p, 0).xy;
    imageStore(motion_sides, p, vec4(m * share_prev, m * share_next));
}
