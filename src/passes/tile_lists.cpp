#include "passes/tile_lists.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "gl/buffer.h"
#include "gl/context.h"

namespace blurlab {
namespace {

uint32_t round_up(uint32_t value, uint32_t multiple) {
  return (value + multiple - 1) / multiple * multiple;
}

}  // namespace

TileLists::TileLists(std::shared_ptr<Context> context, int grid_width, int grid_height, int k)
    : context_(std::move(context)), grid_width_(grid_width), grid_height_(grid_height), k_(k) {
  if (k < 1 || k > 256)
    throw std::invalid_argument("blurlab: k = " + std::to_string(k) + " is outside 1..256");
  if (grid_width < 1 || grid_height < 1 || grid_width > 65535 || grid_height > 65535)
    throw std::invalid_argument("blurlab: a tile grid must be 1..65535 tiles per side");
  context_->make_current();
  GLint max_groups = 0, alignment = 4;
  glGetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_COUNT, 0, &max_groups);
  glGetIntegerv(GL_SHADER_STORAGE_BUFFER_OFFSET_ALIGNMENT, &alignment);
  const uint64_t tiles = uint64_t(grid_width) * grid_height;
  if (tiles > uint64_t(max_groups))
    throw std::invalid_argument("blurlab: tile classification lists one work group per tile, and " +
                                std::to_string(tiles) + " tiles of k = " + std::to_string(k) +
                                " exceed this device's limit of " + std::to_string(max_groups) +
                                " work groups; use a larger k");
  // Each list starts at a multiple of the binding alignment, so one class binds as a range.
  const uint32_t words = std::max<uint32_t>(1, uint32_t(alignment) / 4);
  list_first_ = round_up(6 * kClasses, words);
  list_stride_ = round_up(uint32_t(tiles), words);
  const size_t bytes = size_t(list_first_ + kClasses * list_stride_) * 4;
  buffer_ = std::make_unique<Buffer>(context_.get(), bytes, Buffer::Usage::storage);
  reset();
}

TileLists::~TileLists() = default;

GLuint TileLists::buffer() const {
  return buffer_->id();
}

void TileLists::reset() {
  const uint32_t blocks = uint32_t((k_ + 7) / 8);
  std::array<uint32_t, 6 * kClasses> commands{};
  for (int c = 0; c < kClasses; ++c) {
    commands[6 * c + 1] = blocks * blocks;
    commands[6 * c + 2] = commands[6 * c + 4] = commands[6 * c + 5] = 1;
  }
  context_->make_current();
  glNamedBufferSubData(buffer_->id(), 0, sizeof(commands), commands.data());
  check_gl("resetting tile lists");
}

std::array<uint32_t, TileLists::kClasses> TileLists::counts() const {
  std::array<uint32_t, 6 * kClasses> commands{};
  context_->make_current();
  glGetNamedBufferSubData(buffer_->id(), 0, sizeof(commands), commands.data());
  check_gl("reading tile counts");
  std::array<uint32_t, kClasses> result{};
  for (int c = 0; c < kClasses; ++c) result[c] = commands[6 * c];
  return result;
}

std::vector<std::array<int, 2>> TileLists::tiles(int tile_class) const {
  if (tile_class < 0 || tile_class >= kClasses)
    throw std::invalid_argument("blurlab: tile class " + std::to_string(tile_class) +
                                " is outside 0.." + std::to_string(kClasses - 1));
  const uint32_t count = counts()[tile_class];
  std::vector<uint32_t> packed(count);
  if (count)
    glGetNamedBufferSubData(buffer_->id(), GLintptr(list_first_ + tile_class * list_stride_) * 4,
                            GLsizeiptr(count) * 4, packed.data());
  check_gl("reading a tile list");
  std::vector<std::array<int, 2>> result;
  result.reserve(count);
  for (uint32_t p : packed) result.push_back({int(p & 0xffffu), int(p >> 16)});
  return result;
}

void TileLists::bind_list(int binding, int tile_class) const {
  context_->make_current();
  if (tile_class < 0) {
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding, buffer_->id());
  } else {
    glBindBufferRange(GL_SHADER_STORAGE_BUFFER, binding, buffer_->id(),
                      GLintptr(list_first_ + tile_class * list_stride_) * 4,
                      GLsizeiptr(list_stride_) * 4);
  }
  check_gl("binding a tile list");
}

}  // namespace blurlab
