// What the error reductions of docs/spec.md §6 share (ErrorReductionPass, SsimReductionPass): a
// compute program over two images of one size in work groups of one tile each, each writing its
// partial sums to a storage buffer, read back and added up in double precision on the CPU.
#pragma once

#include <array>
#include <memory>
#include <vector>

namespace blurlab {

class Buffer;
class Context;
class Program;
class Texture;

class PairReduction {
 public:
  explicit PairReduction(Context* context);
  ~PairReduction();
  // Binds a and b to texture units 0 and 1 and the partial sums to storage buffer 0, runs
  // `program` over ⌈W/X⌉ × ⌈H/Y⌉ groups, each covering `tile` (X, Y) pixels and writing
  // `components` partials (interleaved), and returns the sum of each component's partials.
  // Throws std::invalid_argument, naming both sizes, if a and b differ in size or lack RGB.
  std::vector<double> sums(Program& program, const Texture& a, const Texture& b,
                           std::array<int, 2> tile, int components);

 private:
  Context* context_;
  std::unique_ptr<Buffer> partials_;
  std::vector<float> host_;
};

}  // namespace blurlab
