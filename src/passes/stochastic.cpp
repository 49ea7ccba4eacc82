#include "passes/stochastic.h"

#include <stdexcept>
#include <string>

#include "gl/context.h"
#include "gl/program.h"
#include "gl/texture.h"

namespace blurlab {

StochasticPass::StochasticPass(std::shared_ptr<Context> context)
    : context_(std::move(context)),
      program_(Program::compute(context_, "passes/stochastic.comp", {})) {}

void StochasticPass::run(const Texture& color, const Texture& sum, int slice, int position,
                         int slices, uint32_t seed) {
  if (slices < 1 || slices > 64)
    throw std::invalid_argument("blurlab: slices K = " + std::to_string(slices) +
                                " is outside 1..64");
  if (slice < 0 || slice >= slices || position < 0 || position > 3)
    throw std::invalid_argument("blurlab: slice or sample position out of range");
  if (color.width() != sum.width() || color.height() != sum.height())
    throw std::invalid_argument("blurlab: slice render and sum differ in size");
  program_->set_uniform("slice", {double(slice)});
  program_->set_uniform("position", {double(position)});
  program_->set_uniform("slices", {double(slices)});
  program_->set_uniform("seed", {double(seed)});
  program_->bind_texture(0, color);
  program_->bind_image(0, sum, GL_READ_WRITE);
  program_->dispatch((sum.width() + 15) / 16, (sum.height() + 15) / 16, 1);
}

}  // namespace blurlab
