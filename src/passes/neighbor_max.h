// NeighborMax, docs/spec.md §3.3 — shaders/passes/neighbor_max.glsl, NumPy twin
// blurlab.reference.mcguire2012.neighbor_max, tests/test_neighbor_max.py.
#pragma once

#include "passes/post_process.h"

namespace blurlab {

class NeighborMaxPass : public PostProcessPass {
 public:
  explicit NeighborMaxPass(std::shared_ptr<Context> context);
  // tile_max and neighbor_max: the tile grid, RG32F. diagonal_reach: the dilation of
  // reconstruct_guertin2014 (diagonal tiles only where their motion reaches the center tile).
  void run(const Texture& tile_max, const Texture& neighbor_max, Backend backend,
           bool diagonal_reach = false);
};

}  // namespace blurlab
