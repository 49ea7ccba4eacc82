#include "passes/gather_weighted.h"

#include "gl/texture.h"

namespace blurlab {

GatherWeightedPass::GatherWeightedPass(std::shared_ptr<Context> context)
    : PostProcessPass(std::move(context), "passes/gather_weighted.glsl") {}

void GatherWeightedPass::run(const Texture& color, const Texture& motion, const Texture& result,
                             const GatherParams& params, Backend backend) {
  params.validate();
  if (motion.width() != color.width() || motion.height() != color.height())
    throw std::invalid_argument("blurlab: color and motion differ in size");
  Program& p = program(backend);
  p.set_uniform("ignore_outside", {params.edge == "ignore" ? 1.0 : 0.0});
  PostProcessPass::run(backend, {&color, &motion}, result);
}

}  // namespace blurlab
