// stochastic, docs/spec.md §4 (the OGRE paper): adds one jittered time-slice render's share to the
// output — shaders/passes/stochastic.comp, NumPy twin blurlab.reference.stochastic,
// tests/test_stochastic.py.
#pragma once

#include <cstdint>
#include <memory>

namespace blurlab {

class Context;
class Program;
class Texture;

class StochasticPass {
 public:
  explicit StochasticPass(std::shared_ptr<Context> context);
  // sum (RGBA32F) += the share of `color`, the render of slice `slice` (0..slices-1) at
  // rotated-grid position `position` (0..3).
  void run(const Texture& color, const Texture& sum, int slice, int position, int slices,
           uint32_t seed);

 private:
  std::shared_ptr<Context> context_;
  std::shared_ptr<Program> program_;
};

}  // namespace blurlab
