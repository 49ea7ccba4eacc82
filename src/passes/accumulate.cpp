#include "passes/accumulate.h"

#include <cmath>
#include <stdexcept>

#include "gl/context.h"
#include "gl/program.h"
#include "gl/texture.h"

namespace blurlab {

AccumulatePass::AccumulatePass(std::shared_ptr<Context> context)
    : context_(std::move(context)),
      program_(Program::compute(context_, "passes/accumulate.comp", {})) {}

void AccumulatePass::run(const Texture& color, const Texture& sum, float weight) {
  if (color.width() != sum.width() || color.height() != sum.height())
    throw std::invalid_argument("blurlab: accumulation needs color and sum of one size");
  if (!std::isfinite(weight)) throw std::invalid_argument("blurlab: weight must be finite");
  program_->set_uniform("weight", {weight});
  program_->bind_texture(0, color);
  program_->bind_image(0, sum, GL_READ_WRITE);
  program_->dispatch((sum.width() + 15) / 16, (sum.height() + 15) / 16, 1);
}

}  // namespace blurlab
