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

namespace {
constexpr std::array<int, 2> tile{32, 32};  // squared_error.comp's
}

double ErrorReductionPass::squared_error(const Texture& a, const Texture& b) {
  return reduction_->sums(*program_, a, b, tile, 1)[0];
}

size_t ErrorReductionPass::issue_squared_error(const Texture& a, const Texture& b,
                                               ReductionQueue& queue) {
  return reduction_->issue(*program_, a, b, tile, 1, queue);
}

}  // namespace blurlab
