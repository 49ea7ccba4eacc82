#include "passes/error_reduction.h"

#include "gl/context.h"
#include "gl/program.h"
#include "passes/pair_reduction.h"

namespace blurlab {

ErrorReductionPass::ErrorReductionPass(std::shared_ptr<Context> context)
    : context_(std::move(context)),
      program_(Program::compute(context_, "passes/squared_error.comp", {})),
      reduction_(std::make_unique<PairReduction>(context_.get())) {}

ErrorReductionPass::~ErrorReductionPass() = default;

double ErrorReductionPass::squared_error(const Texture& a, const Texture& b) {
  return reduction_->sums(*program_, a, b, {32, 32}, 1)[0];  // squared_error.comp's tile
}

}  // namespace blurlab
