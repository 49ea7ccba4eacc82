// Accumulation of sub-frames for the converged reference, docs/spec.md §1 — shaders/passes/
// accumulate.comp, NumPy twin blurlab.reference.accumulation, tests/test_reference.py.
#pragma once

#include <memory>

namespace blurlab {

class Context;
class Program;
class Texture;

class AccumulatePass {
 public:
  explicit AccumulatePass(std::shared_ptr<Context> context);
  // sum (RGBA32F) += weight * color (RGBA32F), in place.
  void run(const Texture& color, const Texture& sum, float weight);

 private:
  std::shared_ptr<Context> context_;
  std::shared_ptr<Program> program_;
};

}  // namespace blurlab
