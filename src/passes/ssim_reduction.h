// SSIM reduction for sweeps (docs/spec.md §6) — shaders/passes/ssim.comp, NumPy twin
// blurlab.metrics.ssim, tests/test_ssim_gpu.py.
//
// Mean SSIM (Wang et al. 2004) of the luminance of two images clipped to [0, 1]: Gaussian window
// σ = 1.5 with 11 taps (radius 5), reflect padding as np.pad(mode="reflect"), C1 = 0.01²,
// C2 = 0.03². No parameters: the window is fixed so that the GPU value equals the NumPy one.
#pragma once

#include <memory>

namespace blurlab {

class Context;
class PairReduction;
class Program;
class Texture;

class SsimReductionPass {
 public:
  static constexpr double sigma = 1.5;
  static constexpr int radius = 5;

  explicit SsimReductionPass(std::shared_ptr<Context> context);
  ~SsimReductionPass();
  // Mean over pixels of the SSIM map of a and b, both RGB(A) float textures of one size.
  double mean_ssim(const Texture& a, const Texture& b);

 private:
  std::shared_ptr<Context> context_;
  std::shared_ptr<Program> program_;
  std::unique_ptr<PairReduction> reduction_;
};

}  // namespace blurlab
