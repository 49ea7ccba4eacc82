#version 450
// composite_motion (docs/spec.md §20.4, HDRP's option): where the translucent layer's coverage
// reaches motion_coverage, its dominant fragment's motion and depth replace the opaque ones.
// NumPy twin: blurlab.twins.translucency.chosen_motion.
layout(local_size_x = 16, local_size_y = 16) in;
layout(binding = 0) uniform sampler2D translucent;         // Σ, a
layout(binding = 1) uniform sampler2D translucent_motion;  // motion xy, depth, count
layout(binding = 2) uniform sampler2D motion;              // the opaque layer's
layout(binding = 3) uniform sampler2D depth;
layout(binding = 0, rg32f) uniform writeonly image2D chosen_motion;
layout(binding = 1, r32f) uniform writeonly image2D chosen_depth;
uniform float motion_coverage;

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, imageSize(chosen_motion)))) return;
    vec4 layer = texelFetch(translucent_motion, p, 0);
    // A pixel with no dominant fragment has depth +inf there.
    bool own = texelFetch(translucent, p, 0).a >= motion_coverage &&
               layer.z < uintBitsToFloat(0x7f800000u);
    imageStore(chosen_motion, p, vec4(own ? layer.xy : texelFetch(motion, p, 0).xy, 0.0, 0.0));
    imageStore(chosen_depth, p, vec4(own ? layer.z : texelFetch(depth, p, 0).r));
}
