// What the error reductions of docs/spec.md §6 share (ErrorReductionPass, SsimReductionPass): a
// compute program over two images of one size in work groups of one tile each, each writing its
// partial sums to a storage buffer, read back and added up in double precision on the CPU.
// ReductionQueue defers that read-back (docs/spec.md §6.3): many reductions, one wait.
#pragma once

#include <array>
#include <cstddef>
#include <memory>
#include <vector>

#include "gl/gl.h"

namespace blurlab {

class Buffer;
class Context;
class Program;
class Texture;

// Partial sums of reductions issued but not read yet. Each reduction writes its partials to its
// own range of one storage buffer (ranges aligned as GL requires of bound storage ranges). seal()
// queues a fence after them; read() waits on that fence (once per batch instead of once per
// reduction), reads the buffer back and adds each reduction's partials up in double in the order
// PairReduction::sums does: the totals are those of sums, bit for bit.
//
// Each work group writes its `components` sums and then a ticket, a number unique to the
// reduction (the uniform reduction_ticket, a whole float in 1 .. 2^24 - 1). read() checks every
// group's ticket: where one is missing, the partials read back are not what the reduction's pass
// wrote (docs/spec.md §6.3), and read() throws StaleReadback instead of returning them.
class ReductionQueue : NotCopyable {
 public:
  explicit ReductionQueue(Context* context);
  ~ReductionQueue();

  struct Reservation {
    size_t index;  // the reduction's place in the batch
    float ticket;  // what each of its work groups writes after its sums
  };
  // Room for `groups` work groups of one reduction (`components` sums and the ticket each,
  // interleaved), bound to storage buffer 0 for the dispatch that writes them.
  Reservation reserve(size_t groups, int components);
  // Ends the batch: queues a fence after its dispatches, without waiting, so the GPU can go on
  // while the CPU issues another batch (in another queue). No reduction can be reserved again
  // before read(). Nothing happens when the queue is empty.
  void seal();
  // The totals of every reduction reserved since the last read or clear, in order (one vector
  // of `components` sums each); empties the queue. Seals the batch if it is not; one wait for
  // the fence, none when empty. Throws StaleReadback (the queue emptied) if a work group's
  // ticket is missing from what was read back.
  std::vector<std::vector<double>> read();
  // Forgets the reductions not read (their partials are never fetched).
  void clear();
  size_t pending() const { return entries_.size(); }
  // Gives back the last reservation (its dispatch failed).
  void drop_last();

 private:
  struct Entry {
    size_t offset, groups;  // offset in floats
    int components;
    float ticket;
    size_t stride() const { return size_t(components) + 1; }  // floats a group writes
    size_t end() const { return offset + groups * stride(); }
  };
  void drop_fence();

  Context* context_;
  size_t alignment_;                // GL_SHADER_STORAGE_BUFFER_OFFSET_ALIGNMENT, in floats
  size_t used_ = 0;                 // floats reserved in buffer_
  std::unique_ptr<Buffer> buffer_;  // the dispatches write here
  void* fence_ = nullptr;           // GLsync after the sealed batch's dispatches
  std::vector<Entry> entries_;
};

class PairReduction {
 public:
  explicit PairReduction(Context* context);
  ~PairReduction();
  // Binds a and b to texture units 0 and 1 and the partial sums to storage buffer 0, runs
  // `program` over ⌈W/X⌉ × ⌈H/Y⌉ groups, each covering `tile` (X, Y) pixels and writing
  // `components` partials and the reduction's ticket (interleaved; `program` declares the
  // uniform float reduction_ticket), and returns the sum of each component's partials.
  // Throws std::invalid_argument, naming both sizes, if a and b differ in size or lack RGB.
  std::vector<double> sums(Program& program, const Texture& a, const Texture& b,
                           std::array<int, 2> tile, int components);
  // sums() without the wait: the partials go to `queue`, whose read() returns the totals.
  // Returns the reduction's index in the queue's batch.
  size_t issue(Program& program, const Texture& a, const Texture& b, std::array<int, 2> tile,
               int components, ReductionQueue& queue);

 private:
  ReductionQueue own_;  // sums(): a batch of one
};

}  // namespace blurlab
