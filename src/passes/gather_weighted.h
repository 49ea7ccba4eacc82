// gather_weighted, docs/spec.md §4 (ogldev tutorial 41) — shaders/passes/gather_weighted.glsl,
// NumPy twin blurlab.reference.gathers.gather_weighted, tests/test_gather_weighted.py.
#pragma once

#include "passes/gather_params.h"
#include "passes/post_process.h"

namespace blurlab {

class GatherWeightedPass : public PostProcessPass {
 public:
  explicit GatherWeightedPass(std::shared_ptr<Context> context);
  // color RGBA32F, motion RG32F -> result RGBA32F; uses params.edge only.
  void run(const Texture& color, const Texture& motion, const Texture& result,
           const GatherParams& params, Backend backend);
};

}  // namespace blurlab
