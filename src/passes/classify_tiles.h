// Tile classification (Jimenez, "Next Generation Post Processing in Call of Duty: Advanced
// Warfare", SIGGRAPH 2014 course) on top of TileMax / NeighborMax (docs/spec.md §3.2-3.3):
// shaders/passes/classify_tiles.glsl, NumPy twin blurlab.twins.classify.classify_tiles,
// tests/test_classify_tiles.py. docs/classify_and_steps.md defines the classes. Its two
// values (still_threshold, uniform_spread) are declared and validated in Python
// (blurlab/methods/classification.py) and arrive here as plain numbers.
#pragma once

#include <memory>
#include <string>

#include "passes/post_process.h"
#include "passes/tile_lists.h"

namespace blurlab {

class ClassifyTilesPass : public PostProcessPass {
 public:
  explicit ClassifyTilesPass(std::shared_ptr<Context> context);
  // tile_bounds: the grid, RGBA32F (min V.x, min V.y, max V.x, max V.y per tile, from
  // tile_max.glsl with TILE_BOUNDS); neighbor_max: the grid, RG32F; tile_class: the grid, R32F
  // (0 still, 1 uniform, 2 full). Resets `lists` and appends every tile to its class's list.
  void run(const Texture& tile_bounds, const Texture& neighbor_max, const Texture& tile_class,
           TileLists& lists, float still_threshold, float uniform_spread);
};

}  // namespace blurlab
