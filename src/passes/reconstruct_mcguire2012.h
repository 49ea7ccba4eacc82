// Reconstruct, docs/spec.md §3.4 — shaders/passes/reconstruct_mcguire2012.glsl, NumPy twin
// blurlab.reference.mcguire2012.reconstruct_mcguire2012, tests/test_reconstruct_mcguire2012.py.
#pragma once

#include "passes/mcguire2012_params.h"
#include "passes/post_process.h"

namespace blurlab {

// Sets the uniforms that docs/spec.md §3's parameters and the filters' options give every
// reconstruct shader (k, samples, soft_z, exposure, seed, jitter_tiles, adaptive_samples,
// early_exit), after validating them.
void set_filter_uniforms(Program& program, const McGuire2012Params& params);

class ReconstructMcGuire2012Pass : public PostProcessPass {
 public:
  explicit ReconstructMcGuire2012Pass(std::shared_ptr<Context> context);
  // color RGBA32F, depth R32F, motion RG32F, neighbor_max (tile grid) RG32F -> result RGBA32F.
  void run(const Texture& color, const Texture& depth, const Texture& motion,
           const Texture& neighbor_max, const Texture& result, const McGuire2012Params& params,
           Backend backend);
};

}  // namespace blurlab
