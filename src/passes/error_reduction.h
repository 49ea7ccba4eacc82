// Squared-error reduction for sweeps (docs/spec.md §6) — shaders/passes/squared_error.comp, NumPy
// twin blurlab.metrics.mse, tests/test_metrics.py.
#pragma once

#include <memory>

namespace blurlab {

class Context;
class PairReduction;
class Program;
class Texture;

class ErrorReductionPass {
 public:
  explicit ErrorReductionPass(std::shared_ptr<Context> context);
  ~ErrorReductionPass();
  // Σ over pixels and RGB of (clamp(a) - clamp(b))², both RGBA32F of one size.
  double squared_error(const Texture& a, const Texture& b);

 private:
  std::shared_ptr<Context> context_;
  std::shared_ptr<Program> program_;
  std::unique_ptr<PairReduction> reduction_;
};

}  // namespace blurlab
