#include "passes/gather_box.h"

#include "gl/texture.h"

namespace blurlab {

GatherBoxPass::GatherBoxPass(std::shared_ptr<Context> context)
    : PostProcessPass(std::move(context), "passes/gather_box.glsl") {}

void GatherBoxPass::run(const Texture& color, const Texture& motion, const Texture& result,
                        const GatherParams& params, Backend backend) {
  params.validate();
  if (motion.width() != color.width() || motion.height() != color.height())
    throw std::invalid_argument("blurlab: color and motion differ in size");
  Program& p = program(backend);
  p.set_uniform("ignore_outside", {params.edge == "ignore" ? 1.0 : 0.0});
  p.set_uniform("taps", {double(params.taps)});
  p.set_uniform("intensity", {params.intensity});
  p.set_uniform("centered", {params.centered ? 1.0 : 0.0});
  PostProcessPass::run(backend, {&color, &motion}, result);
}

}  // namespace blurlab
