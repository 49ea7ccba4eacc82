// Squared-error reduction for sweeps (docs/spec.md §6) — shaders/passes/squared_error.comp, NumPy
// twin blurlab.metrics.mse, tests/test_metrics.py.
#pragma once

#include <cstddef>
#include <memory>

namespace blurlab {

class Context;
class PairReduction;
class ReductionQueue;
class Program;
class Texture;

class ErrorReductionPass {
 public:
  explicit ErrorReductionPass(std::shared_ptr<Context> context);
  ~ErrorReductionPass();
  // Σ over pixels and RGB of (clamp(a) - clamp(b))², both RGBA32F of one size.
  double squared_error(const Texture& a, const Texture& b);
  // squared_error without the wait: its total is the next reduction of `queue`; returns its index.
  size_t issue_squared_error(const Texture& a, const Texture& b, ReductionQueue& queue);

 private:
  std::shared_ptr<Context> context_;
  std::shared_ptr<Program> program_;
  std::unique_ptr<PairReduction> reduction_;
};

}  // namespace blurlab
