#include "passes/ssim_reduction.h"

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "gl/buffer.h"
#include "gl/context.h"
#include "gl/program.h"
#include "gl/texture.h"

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
          {{"RADIUS", std::to_string(radius)}, {"WEIGHTS", gaussian_weights(sigma, radius)}})) {}

SsimReductionPass::~SsimReductionPass() = default;

double SsimReductionPass::mean_ssim(const Texture& a, const Texture& b) {
  if (a.width() != b.width() || a.height() != b.height())
    throw std::invalid_argument(
        "blurlab: compared images differ in size: " + std::to_string(a.width()) + "x" +
        std::to_string(a.height()) + " and " + std::to_string(b.width()) + "x" +
        std::to_string(b.height()));
  if (a.format().channels < 3 || b.format().channels < 3)
    throw std::invalid_argument("blurlab: compared images need RGB channels");
  const int gx = (a.width() + 15) / 16, gy = (a.height() + 15) / 16;
  const size_t groups = size_t(gx) * gy;
  if (!partials_ || partials_->size() < groups * sizeof(float))
    partials_ =
        std::make_unique<Buffer>(context_.get(), groups * sizeof(float), Buffer::Usage::storage);
  program_->bind_texture(0, a);
  program_->bind_texture(1, b);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, partials_->id());
  program_->dispatch(gx, gy, 1);
  host_.resize(groups);
  glGetNamedBufferSubData(partials_->id(), 0, static_cast<GLsizeiptr>(groups * sizeof(float)),
                          host_.data());
  check_gl("reading back partial SSIM sums");
  double sum = 0.0;
  for (float v : host_) sum += v;
  return sum / (double(a.width()) * a.height());
}

}  // namespace blurlab
