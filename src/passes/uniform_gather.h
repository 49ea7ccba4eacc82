// The uniform class of the tile classification (docs/classify_and_steps.md): docs/spec.md §3.4 with
// V[X] = V[Y] = NeighborMax and f = b = 1, colors only — shaders/passes/uniform_gather.glsl,
// NumPy twin blurlab.reference.classify.uniform_gather, tests/test_uniform_gather.py. Its
// parameters are the filter's k, samples and seed (McGuire2012Params). Restrict it to the
// uniform tiles with restrict_to_tiles.
#pragma once

#include "passes/mcguire2012_params.h"
#include "passes/post_process.h"

namespace blurlab {

class UniformGatherPass : public PostProcessPass {
 public:
  explicit UniformGatherPass(std::shared_ptr<Context> context);
  // color RGBA32F, neighbor_max (tile grid) RG32F -> result RGBA32F; compute only.
  void run(const Texture& color, const Texture& neighbor_max, const Texture& result,
           const McGuire2012Params& params);
};

}  // namespace blurlab
