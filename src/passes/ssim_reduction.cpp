#include "passes/ssim_reduction.h"

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "gl/context.h"
#include "gl/gl.h"
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
                                     int rows_per_thread, int tile_columns)
    : context_(std::move(context)),
      tile_columns_(tile_columns),
      tile_rows_(tile_rows),
      rows_per_thread_(rows_per_thread),
      reduction_(std::make_unique<PairReduction>(context_.get())) {
  if (strips()) {
    const bool columns_ok = tile_columns == 64 || tile_columns == 128 || tile_columns == 256;
    const bool rows_ok = tile_rows == 16 || tile_rows == 32;
    if (!columns_ok || !rows_ok || rows_per_thread != tile_rows)
      throw std::invalid_argument(
          "blurlab.SsimReductionPass: strips (tile_columns 64, 128 or 256) need tile_rows 16 or 32 "
          "and rows_per_thread equal to tile_rows; got " +
          std::to_string(tile_columns) + ", " + std::to_string(tile_rows) + " and " +
          std::to_string(rows_per_thread));
  } else {
    const bool tile_ok = tile_rows == 8 || tile_rows == 16 || tile_rows == 32;
    const bool rows_ok = rows_per_thread == 1 || rows_per_thread == 2 || rows_per_thread == 4 ||
                         rows_per_thread == 8;
    if (tile_columns != 32 || !tile_ok || !rows_ok || rows_per_thread > tile_rows)
      throw std::invalid_argument(
          "blurlab.SsimReductionPass: tile_rows must be 8, 16 or 32 and rows_per_thread 1, 2, 4 "
          "or 8, at most tile_rows (tile_columns 32; 64, 128 or 256 for strips); got " +
          std::to_string(tile_rows) + " and " + std::to_string(rows_per_thread) +
          " (tile_columns " + std::to_string(tile_columns) + ")");
  }
  program(Variant::ssim);  // a layout the shader cannot tile fails here
}

SsimReductionPass::~SsimReductionPass() = default;

Program& SsimReductionPass::program(Variant variant) {
  auto& slot = programs_[static_cast<int>(variant)];
  if (!slot) {
    auto flag = [&](bool on) { return std::string(on ? "1" : "0"); };
    Defines defines = {
        {"RADIUS", std::to_string(radius)},
        {"WEIGHTS", gaussian_weights(sigma, radius)},
        {"SQUARED_ERROR", flag(variant == Variant::fused || variant == Variant::prepared)},
        {"PREPARE", flag(variant == Variant::prepare)},
        {"PREPARED", flag(variant == Variant::prepared)}};
    if (strips()) {
      defines.push_back({"GROUP_X", std::to_string(tile_columns_)});
      defines.push_back({"STRIP", std::to_string(tile_rows_)});
    } else {
      defines.push_back({"TILE_Y", std::to_string(tile_rows_)});
      defines.push_back({"ROWS", std::to_string(rows_per_thread_)});
    }
    slot = Program::compute(context_, strips() ? "passes/ssim_strip.comp" : "passes/ssim.comp",
                            defines);
  }
  return *slot;
}

double SsimReductionPass::mean_ssim(const Texture& a, const Texture& b) {
  const double total =
      reduction_->sums(program(Variant::ssim), a, b, {tile_columns_, tile_rows_}, 1)[0];
  return total / (double(a.width()) * a.height());
}

std::pair<double, double> SsimReductionPass::mse_ssim(const Texture& a, const Texture& b) {
  const auto totals =
      reduction_->sums(program(Variant::fused), a, b, {tile_columns_, tile_rows_}, 2);
  return {totals[1], totals[0] / (double(a.width()) * a.height())};
}

size_t SsimReductionPass::issue_mse_ssim(const Texture& a, const Texture& b,
                                         ReductionQueue& queue) {
  return reduction_->issue(program(Variant::fused), a, b, {tile_columns_, tile_rows_}, 2, queue);
}

namespace {

void check_prepared(const Texture& reference, const Texture& colour_luminance,
                    const Texture& moments) {
  const bool sizes = colour_luminance.width() == reference.width() &&
                     colour_luminance.height() == reference.height() &&
                     moments.width() == reference.width() && moments.height() == reference.height();
  if (!sizes)
    throw std::invalid_argument(
        "blurlab: a prepared SSIM reference's textures must have the reference's size");
  if (colour_luminance.format().internal != GL_RGBA32F || moments.format().internal != GL_RG32F)
    throw std::invalid_argument(
        "blurlab: a prepared SSIM reference needs an RGBA32F colour_luminance and RG32F moments");
}

}  // namespace

void SsimReductionPass::prepare(const Texture& reference, const Texture& colour_luminance,
                                const Texture& moments) {
  if (reference.format().channels < 3)
    throw std::invalid_argument("blurlab: compared images need RGB channels");
  check_prepared(reference, colour_luminance, moments);
  Program& prepare = program(Variant::prepare);
  prepare.bind_texture(0, reference);
  prepare.bind_image(0, colour_luminance, GL_WRITE_ONLY);
  prepare.bind_image(1, moments, GL_WRITE_ONLY);
  prepare.dispatch((reference.width() + tile_columns_ - 1) / tile_columns_,
                   (reference.height() + tile_rows_ - 1) / tile_rows_, 1);
}

std::pair<double, double> SsimReductionPass::mse_ssim_prepared(const Texture& colour_luminance,
                                                               const Texture& moments,
                                                               const Texture& test) {
  const auto totals = reduction_->sums(prepared_program(colour_luminance, moments),
                                       colour_luminance, test, {tile_columns_, tile_rows_}, 2);
  return {totals[1], totals[0] / (double(test.width()) * test.height())};
}

size_t SsimReductionPass::issue_mse_ssim_prepared(const Texture& colour_luminance,
                                                  const Texture& moments, const Texture& test,
                                                  ReductionQueue& queue) {
  return reduction_->issue(prepared_program(colour_luminance, moments), colour_luminance, test,
                           {tile_columns_, tile_rows_}, 2, queue);
}

Program& SsimReductionPass::prepared_program(const Texture& colour_luminance,
                                             const Texture& moments) {
  check_prepared(colour_luminance, colour_luminance, moments);
  Program& prepared = program(Variant::prepared);
  prepared.bind_texture(2, moments);
  return prepared;
}

}  // namespace blurlab
