// Reconstruct of Guertin, McGuire, Nowrouzezahrai (HPG 2014), docs/guertin2014.md —
// shaders/passes/reconstruct_guertin2014.glsl, NumPy twin
// blurlab.reference.guertin2014.reconstruct_guertin2014, tests/test_reconstruct_guertin2014.py.
#pragma once

#include "passes/guertin2014_params.h"
#include "passes/post_process.h"

namespace blurlab {

class ReconstructGuertin2014Pass : public PostProcessPass {
 public:
  explicit ReconstructGuertin2014Pass(std::shared_ptr<Context> context);
  // color RGBA32F, depth R32F, motion RG32F, neighbor_max (tile grid, the direction-keeping
  // dilation) RG32F -> result RGBA32F.
  void run(const Texture& color, const Texture& depth, const Texture& motion,
           const Texture& neighbor_max, const Texture& result, const Guertin2014Params& params,
           Backend backend);
};

}  // namespace blurlab
