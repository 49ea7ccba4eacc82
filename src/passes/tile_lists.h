// The per-class tile lists of a tile classification (ClassifyTilesPass, classify_tiles.h) that
// restricted post-process passes read (PostProcessPass::restrict_to_tiles). Apart from the
// classification so that post_process.cpp need not include a pass.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "gl/gl.h"

namespace blurlab {

class Buffer;
class Context;

enum TileClass : int { tile_still = 0, tile_uniform = 1, tile_full = 2 };

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

}  // namespace blurlab
