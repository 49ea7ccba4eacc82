#include "passes/pair_reduction.h"

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "gl/buffer.h"
#include "gl/context.h"
#include "gl/program.h"
#include "gl/texture.h"

namespace blurlab {

namespace {

std::string size_of(const Texture& t) {
  return std::to_string(t.width()) + "x" + std::to_string(t.height());
}

size_t storage_alignment_floats() {
  GLint bytes = 0;
  glGetIntegerv(GL_SHADER_STORAGE_BUFFER_OFFSET_ALIGNMENT, &bytes);
  check_gl("querying the storage buffer offset alignment");
  const size_t align = std::max<size_t>(size_t(std::max(bytes, 1)), sizeof(float));
  return (align + sizeof(float) - 1) / sizeof(float);
}

}  // namespace

ReductionQueue::ReductionQueue(Context* context) : context_(context) {
  context_->make_current();
  alignment_ = storage_alignment_floats();
}

ReductionQueue::~ReductionQueue() {
  drop_fence();
}

void ReductionQueue::drop_fence() {
  if (!fence_) return;
  context_->release(nullptr, [fence = static_cast<GLsync>(fence_)] { glDeleteSync(fence); });
  fence_ = nullptr;
}

namespace {
// Tickets run through the whole floats 1 .. 2^24 - 1 (exact, never zero, denormal or NaN), one
// per reduction of the process: a range that no pass of this reduction wrote, whether it holds
// zeros, another reduction's partials or garbage, lacks this one's.
std::atomic<uint32_t> tickets_issued{0};
constexpr uint32_t ticket_count = (1u << 24) - 1u;
}  // namespace

ReductionQueue::Reservation ReductionQueue::reserve(size_t groups, int components) {
  if (fence_)
    throw std::logic_error("blurlab: a sealed batch of reductions must be read before the next");
  const float ticket = float(1u + tickets_issued.fetch_add(1u) % ticket_count);
  const Entry entry{(used_ + alignment_ - 1) / alignment_ * alignment_, groups, components, ticket};
  const size_t end = entry.end();
  if (!buffer_ || buffer_->size() < end * sizeof(float)) {
    // Grow geometrically; partials already written move over on the GPU, in command order.
    const size_t floats = std::max(end, buffer_ ? 2 * buffer_->size() / sizeof(float) : end);
    auto grown = std::make_unique<Buffer>(context_, floats * sizeof(float), Buffer::Usage::storage);
    if (buffer_ && used_ > 0)
      glCopyNamedBufferSubData(buffer_->id(), grown->id(), 0, 0,
                               static_cast<GLsizeiptr>(used_ * sizeof(float)));
    buffer_ = std::move(grown);
  }
  glBindBufferRange(GL_SHADER_STORAGE_BUFFER, 0, buffer_->id(),
                    static_cast<GLintptr>(entry.offset * sizeof(float)),
                    static_cast<GLsizeiptr>((end - entry.offset) * sizeof(float)));
  check_gl("binding a reduction's partial sums");
  entries_.push_back(entry);
  used_ = end;
  return {entries_.size() - 1, ticket};
}

void ReductionQueue::seal() {
  if (fence_ || entries_.empty()) return;
  fence_ = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
  glFlush();  // else the batch may wait in the command queue until someone waits on it
  check_gl("queueing the fence of a batch of partial sums");
}

std::vector<std::vector<double>> ReductionQueue::read() {
  std::vector<std::vector<double>> totals;
  if (entries_.empty()) return totals;
  seal();
  const auto entries = std::move(entries_);
  std::vector<float> host(used_);
  try {
    context_->wait_for_fence(static_cast<GLsync>(fence_), "waiting for partial sums");
    // Read from the buffer the dispatches wrote, through GL, which orders the read after them;
    // the tickets below check that it did.
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glGetNamedBufferSubData(buffer_->id(), 0, static_cast<GLsizeiptr>(host.size() * sizeof(float)),
                            host.data());
    check_gl("reading partial sums");
  } catch (...) {
    clear();
    throw;
  }
  clear();
  totals.reserve(entries.size());
  size_t stale = 0, groups = 0;
  for (const Entry& e : entries) {
    std::vector<double> out(e.components, 0.0);
    const float* partials = host.data() + e.offset;
    for (size_t g = 0; g < e.groups; ++g) {
      const float* group = partials + g * e.stride();
      for (int c = 0; c < e.components; ++c) out[c] += group[c];
      stale += group[e.components] != e.ticket;
    }
    groups += e.groups;
    totals.push_back(std::move(out));
  }
  if (stale) {
    context_->count_stale_readback();
    throw StaleReadback("blurlab: " + std::to_string(stale) + " of " + std::to_string(groups) +
                        " work groups' partial sums read back lack their reduction's ticket: the "
                        "GPU returned data its reduction passes did not write (docs/spec.md "
                        "§6.3); evaluate them again");
  }
  return totals;
}

void ReductionQueue::drop_last() {
  entries_.pop_back();
  used_ = entries_.empty() ? 0 : entries_.back().end();
}

void ReductionQueue::clear() {
  drop_fence();
  entries_.clear();
  used_ = 0;
}

PairReduction::PairReduction(Context* context) : own_(context) {}

PairReduction::~PairReduction() = default;

std::vector<double> PairReduction::sums(Program& program, const Texture& a, const Texture& b,
                                        std::array<int, 2> tile, int components) {
  own_.clear();
  issue(program, a, b, tile, components, own_);
  return own_.read().front();
}

size_t PairReduction::issue(Program& program, const Texture& a, const Texture& b,
                            std::array<int, 2> tile, int components, ReductionQueue& queue) {
  if (a.width() != b.width() || a.height() != b.height())
    throw std::invalid_argument("blurlab: compared images differ in size: " + size_of(a) + " and " +
                                size_of(b));
  if (a.format().channels < 3 || b.format().channels < 3)
    throw std::invalid_argument("blurlab: compared images need RGB channels");
  const int gx = (a.width() + tile[0] - 1) / tile[0], gy = (a.height() + tile[1] - 1) / tile[1];
  program.bind_texture(0, a);
  program.bind_texture(1, b);
  const auto [index, ticket] = queue.reserve(size_t(gx) * gy, components);
  try {
    program.set_uniform("reduction_ticket", {double(ticket)});
    program.dispatch(gx, gy, 1);
  } catch (...) {
    queue.drop_last();
    throw;
  }
  return index;
}

}  // namespace blurlab
