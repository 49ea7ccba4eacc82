#include "passes/reconstruct_mcguire2012.h"

#include "gl/texture.h"

namespace blurlab {

void set_filter_uniforms(Program& p, const McGuire2012Params& params) {
  params.validate();
  p.set_uniform("k", {double(params.k)});
  p.set_uniform("samples", {double(params.samples)});
  p.set_uniform("soft_z", {params.soft_z});
  p.set_uniform("exposure", {params.exposure});
  p.set_uniform("seed", {double(params.seed)});
  p.set_uniform("jitter_tiles", {params.jitter_tiles ? 1.0 : 0.0});
  p.set_uniform("adaptive_samples", {params.adaptive_samples ? 1.0 : 0.0});
  p.set_uniform("early_exit", {params.early_exit});
}

ReconstructMcGuire2012Pass::ReconstructMcGuire2012Pass(std::shared_ptr<Context> context)
    : PostProcessPass(std::move(context), "passes/reconstruct_mcguire2012.glsl") {}

void ReconstructMcGuire2012Pass::run(const Texture& color, const Texture& depth,
                                     const Texture& motion, const Texture& neighbor_max,
                                     const Texture& result, const McGuire2012Params& params,
                                     Backend backend) {
  params.validate();
  for (const Texture* t : {&depth, &motion, &result})
    if (t->width() != color.width() || t->height() != color.height())
      throw std::invalid_argument("blurlab: color, depth, motion and result differ in size");
  set_filter_uniforms(program(backend), params);
  PostProcessPass::run(backend, {&color, &depth, &motion, &neighbor_max}, result);
}

}  // namespace blurlab
