#include "passes/ssim_reduction.h"

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "gl/context.h"
#include "gl/program.h"
#include "gl/texture.h"
#include "passes/pair_reduction.h"

namespace blurlab {

namespace {

// The normalized Gaussian taps exp(-x² / 2σ²), x = -radius..radius, computed in double as
// blurlab.metrics._gaussian_blur does and written as a GLSL float array with round-trip digits.
std::string gaussian_weights(double sigma, int radius) {
  std::vector<double> w;
  double sum = 0.0;
  for (int x = -radius; x <= radius; ++x) {
    w.push_back(std::exp(-double(x) * x / (2.0 * sigma * sigma)));
    sum += w.back();
  }
  std::string out = "float[" + std::to_string(w.size()) + "](";
  char text[32];
  for (size_t i = 0; i < w.size(); ++i) {
    std::snprintf(text, sizeof text, "%.9e", w[i] / sum);
    out += (i ? ", " : "") + std::string(text);
  }
  return out + ")";
}

}  // namespace

SsimReductionPass::SsimReductionPass(std::shared_ptr<Context> context, int tile_rows,
                                     int rows_per_thread)
    : context_(std::move(context)),
      tile_rows_(tile_rows),
      rows_per_thread_(rows_per_thread),
      reduction_(std::make_unique<PairReduction>(context_.get())) {
  const bool tile_ok = tile_rows == 8 || tile_rows == 16 || tile_rows == 32;
  const bool rows_ok =
      rows_per_thread == 1 || rows_per_thread == 2 || rows_per_thread == 4 || rows_per_thread == 8;
  if (!tile_ok || !rows_ok || rows_per_thread > tile_rows)
    throw std::invalid_argument(
        "blurlab.SsimReductionPass: tile_rows must be 8, 16 or 32 and rows_per_thread 1, 2, 4 or "
        "8, at most tile_rows; got " +
        std::to_string(tile_rows) + " and " + std::to_string(rows_per_thread));
  ssim_ = compile(false);
}

SsimReductionPass::~SsimReductionPass() = default;

std::shared_ptr<Program> SsimReductionPass::compile(bool squared_error) const {
  return Program::compute(context_, "passes/ssim.comp",
                          {{"RADIUS", std::to_string(radius)},
                           {"WEIGHTS", gaussian_weights(sigma, radius)},
                           {"TILE_Y", std::to_string(tile_rows_)},
                           {"ROWS", std::to_string(rows_per_thread_)},
                           {"SQUARED_ERROR", squared_error ? "1" : "0"}});
}

double SsimReductionPass::mean_ssim(const Texture& a, const Texture& b) {
  const double total = reduction_->sums(*ssim_, a, b, {32, tile_rows_}, 1)[0];
  return total / (double(a.width()) * a.height());
}

std::pair<double, double> SsimReductionPass::mse_ssim(const Texture& a, const Texture& b) {
  if (!fused_) fused_ = compile(true);
  const auto totals = reduction_->sums(*fused_, a, b, {32, tile_rows_}, 2);
  return {totals[1], totals[0] / (double(a.width()) * a.height())};
}

}  // namespace blurlab
