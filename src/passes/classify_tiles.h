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

#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "gl/gl.h"
#include "passes/post_process.h"

namespace blurlab {

class Buffer;

enum TileClass : int { tile_still = 0, tile_uniform = 1, tile_full = 2 };

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

// One GL buffer holding, for each class, two indirect dispatch commands — {tiles in the class,
// 8 x 8 blocks per tile, 1} and {tiles in the class, 1, 1} for passes that take a whole tile
// per work group — and the list of its tiles (x | y << 16), which ClassifyTilesPass fills with
// atomic counters and restricted passes (PostProcessPass::restrict_to_tiles) read.
class TileLists {
 public:
  static constexpr int kClasses = 3;
  // A grid of grid_width x grid_height tiles of k x k pixels.
  TileLists(std::shared_ptr<Context> context, int grid_width, int grid_height, int k);
  ~TileLists();
  TileLists(const TileLists&) = delete;
  TileLists& operator=(const TileLists&) = delete;

  // Every count back to zero (before a classification).
  void reset();
  // The number of tiles in each class, read back from the GPU.
  std::array<uint32_t, kClasses> counts() const;
  // The listed tiles of one class as (x, y) pairs, in the order the GPU appended them.
  std::vector<std::array<int, 2>> tiles(int tile_class) const;

  int k() const { return k_; }
  int grid_width() const { return grid_width_; }
  int grid_height() const { return grid_height_; }
  GLuint buffer() const;
  GLintptr command_offset(int tile_class, bool whole_tiles) const {
    return GLintptr(2 * tile_class + (whole_tiles ? 1 : 0)) * 12;
  }
  // Where class lists start and how far apart they are, in 32-bit words.
  uint32_t list_first() const { return list_first_; }
  uint32_t list_stride() const { return list_stride_; }
  // Binds one class's list to shader storage binding `binding` (the TileList block of
  // shaders/common/tile_list.glsl), or the whole buffer when tile_class is -1.
  void bind_list(int binding, int tile_class) const;

 private:
  std::shared_ptr<Context> context_;
  int grid_width_, grid_height_, k_;
  uint32_t list_first_ = 0, list_stride_ = 0;
  std::unique_ptr<Buffer> buffer_;
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
