// TileMax, docs/spec.md §3.2 — shaders/passes/tile_max.glsl, NumPy twin
// blurlab.reference.mcguire2012.tile_max, tests/test_tile_max.py.
#pragma once

#include "passes/mcguire2012_params.h"
#include "passes/post_process.h"

namespace blurlab {

class TileMaxPass : public PostProcessPass {
 public:
  explicit TileMaxPass(std::shared_ptr<Context> context);
  // motion: (H, W) RG32F; tile_max: (ceil(H/k), ceil(W/k)) RG32F.
  void run(const Texture& motion, const Texture& tile_max, const McGuire2012Params& params,
           Backend backend);
  // The same on the compute backend, also writing each tile's component-wise bounds of V
  // (min V.x, min V.y, max V.x, max V.y) into tile_bounds (the grid, RGBA32F) for the tile
  // classification (ClassifyTilesPass).
  void run_with_bounds(const Texture& motion, const Texture& tile_max, const Texture& tile_bounds,
                       const McGuire2012Params& params);
};

}  // namespace blurlab
