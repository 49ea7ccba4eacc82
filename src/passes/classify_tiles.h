// Tile classification (Jimenez, "Next Generation Post Processing in Call of Duty: Advanced
// Warfare", SIGGRAPH 2014 course) on top of TileMax / NeighborMax (docs/spec.md §3.2-3.3):
// shaders/passes/classify_tiles.glsl, NumPy twin blurlab.reference.classify.classify_tiles,
// tests/test_classify_tiles.py. docs/classify_and_steps.md defines the classes.
//
// | name            | default | allowed       | meaning                                       |
// |-----------------|---------|---------------|-----------------------------------------------|
// | still_threshold | 0.51    | finite, >= 0  | |NeighborMax| at or below it: still (SPEC §3.4) |
// | uniform_spread  | 0.5     | finite, >= 0  | largest |V - NeighborMax| of a uniform tile, px |
#pragma once

#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>

#include "passes/post_process.h"
#include "passes/tile_lists.h"

namespace blurlab {

struct ClassifyParams {
  float still_threshold = 0.51f;
  float uniform_spread = 0.5f;

  // Throws std::invalid_argument naming the parameter, its value and the allowed range.
  void validate() const {
    if (!std::isfinite(still_threshold) || still_threshold < 0.0f)
      throw std::invalid_argument("blurlab: still_threshold = " + std::to_string(still_threshold) +
                                  " must be finite and >= 0 (pixels)");
    if (!std::isfinite(uniform_spread) || uniform_spread < 0.0f)
      throw std::invalid_argument("blurlab: uniform_spread = " + std::to_string(uniform_spread) +
                                  " must be finite and >= 0 (pixels)");
  }
};

class ClassifyTilesPass : public PostProcessPass {
 public:
  explicit ClassifyTilesPass(std::shared_ptr<Context> context);
  // tile_bounds: the grid, RGBA32F (min V.x, min V.y, max V.x, max V.y per tile, from
  // TileMaxPass::run_with_bounds); neighbor_max: the grid, RG32F; tile_class: the grid, R32F
  // (0 still, 1 uniform, 2 full). Resets `lists` and appends every tile to its class's list.
  void run(const Texture& tile_bounds, const Texture& neighbor_max, const Texture& tile_class,
           TileLists& lists, const ClassifyParams& params);
};

}  // namespace blurlab
