// SSIM reduction for sweeps (docs/spec.md §6) — shaders/passes/ssim.comp, NumPy twins
// blurlab.metrics.ssim and mse, tests/test_ssim_gpu.py.
//
// Mean SSIM (Wang et al. 2004) of the luminance of two images clipped to [0, 1]: Gaussian window
// σ = 1.5 with 11 taps (radius 5), reflect padding as np.pad(mode="reflect"), C1 = 0.01²,
// C2 = 0.03². No parameters: the window is fixed so that the GPU value equals the NumPy one.
// `mse_ssim` also returns the squared error of the same dispatch (one pass, one read-back).
#pragma once

#include <cstddef>
#include <memory>
#include <utility>

namespace blurlab {

class Context;
class PairReduction;
class ReductionQueue;
class Program;
class Texture;

class SsimReductionPass {
 public:
  static constexpr double sigma = 1.5;
  static constexpr int radius = 5;

  // Work groups cover tile_columns x tile_rows pixels (the layouts give the same value up to float
  // rounding: benchmarks compare their speed). tile_columns 32: shaders/passes/ssim.comp, each
  // invocation computes rows_per_thread pixels of one column; tile_rows in {8, 16, 32},
  // rows_per_thread in {1, 2, 4, 8} dividing tile_rows. tile_columns 64, 128 or 256: strips,
  // shaders/passes/ssim_strip.comp, each invocation walks its column down the whole strip;
  // tile_rows in {16, 32} and rows_per_thread == tile_rows.
  SsimReductionPass(std::shared_ptr<Context> context, int tile_rows = 32, int rows_per_thread = 4,
                    int tile_columns = 32);
  ~SsimReductionPass();
  // Mean over pixels of the SSIM map of a and b, both RGB(A) float textures of one size.
  double mean_ssim(const Texture& a, const Texture& b);
  // (Σ over pixels and RGB of (clamp(a) - clamp(b))², mean SSIM) from one dispatch.
  std::pair<double, double> mse_ssim(const Texture& a, const Texture& b);
  // mse_ssim without the wait: its (Σ SSIM, Σ squared error) are the next reduction of `queue`,
  // summed in that order; returns its index.
  size_t issue_mse_ssim(const Texture& a, const Texture& b, ReductionQueue& queue);
  // Prepares a reference that many tests are compared with, into two textures of its size.
  // Tiles: its clipped colour and luminance to colour_luminance (RGBA32F) and the Gaussian mean
  // and variance of its luminance to moments (RG32F). Strips: its clipped colour and the
  // Gaussian mean of its luminance to colour_luminance, its luminance and the Gaussian variance
  // to moments (so the border texels a strip reads beside its own cost 8 bytes, not 16).
  void prepare(const Texture& reference, const Texture& colour_luminance, const Texture& moments);
  // mse_ssim(reference, test) of a reference prepared by `prepare`: blurs three moments, not five.
  std::pair<double, double> mse_ssim_prepared(const Texture& colour_luminance,
                                              const Texture& moments, const Texture& test);
  // mse_ssim_prepared without the wait: its (Σ squared error, Σ SSIM) are the next reduction of
  // `queue`, summed in that order; returns its index.
  size_t issue_mse_ssim_prepared(const Texture& colour_luminance, const Texture& moments,
                                 const Texture& test, ReductionQueue& queue);

 private:
  enum class Variant { ssim, fused, prepare, prepared };
  bool strips() const { return tile_columns_ != 32; }
  Program& program(Variant variant);  // compiled on first use
  // The prepared variant with `moments` bound, after checking the prepared textures.
  Program& prepared_program(const Texture& colour_luminance, const Texture& moments);

  std::shared_ptr<Context> context_;
  int tile_columns_, tile_rows_, rows_per_thread_;
  std::shared_ptr<Program> programs_[4];
  std::unique_ptr<PairReduction> reduction_;
};

}  // namespace blurlab
