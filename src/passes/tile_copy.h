// The still class of the tile classification (docs/classify_and_steps.md): color copied —
// shaders/passes/tile_copy.glsl, NumPy twin blurlab.reference.classify.classified,
// tests/test_tile_copy.py. Restrict it to the still tiles with restrict_to_tiles.
#pragma once

#include "passes/post_process.h"

namespace blurlab {

class TileCopyPass : public PostProcessPass {
 public:
  explicit TileCopyPass(std::shared_ptr<Context> context);
  // color RGBA32F -> result RGBA32F, same size; compute only.
  void run(const Texture& color, const Texture& result);
};

}  // namespace blurlab
