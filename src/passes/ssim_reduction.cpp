#include "passes/ssim_reduction.h"

#include <cmath>
#include <cstdio>
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

SsimReductionPass::SsimReductionPass(std::shared_ptr<Context> context)
    : context_(std::move(context)),
      program_(Program::compute(
          context_, "passes/ssim.comp",
          {{"RADIUS", std::to_string(radius)}, {"WEIGHTS", gaussian_weights(sigma, radius)}})),
      reduction_(std::make_unique<PairReduction>(context_.get())) {}

SsimReductionPass::~SsimReductionPass() = default;

double SsimReductionPass::mean_ssim(const Texture& a, const Texture& b) {
  return reduction_->sum(*program_, a, b) / (double(a.width()) * a.height());
}

}  // namespace blurlab
