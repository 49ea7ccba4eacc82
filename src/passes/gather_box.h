// gather_box, docs/spec.md §4 ("Blurry things") — shaders/passes/gather_box.glsl, NumPy twin
// blurlab.reference.gathers.gather_box, tests/test_gather_box.py.
#pragma once

#include "passes/gather_params.h"
#include "passes/post_process.h"

namespace blurlab {

class GatherBoxPass : public PostProcessPass {
 public:
  explicit GatherBoxPass(std::shared_ptr<Context> context);
  // color RGBA32F, motion RG32F -> result RGBA32F.
  void run(const Texture& color, const Texture& motion, const Texture& result,
           const GatherParams& params, Backend backend);
};

}  // namespace blurlab
