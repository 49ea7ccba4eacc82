#include "passes/reconstruct_guertin2014.h"

#include "gl/texture.h"
#include "passes/reconstruct_mcguire2012.h"

namespace blurlab {

ReconstructGuertin2014Pass::ReconstructGuertin2014Pass(std::shared_ptr<Context> context)
    : PostProcessPass(std::move(context), "passes/reconstruct_guertin2014.glsl") {}

void ReconstructGuertin2014Pass::run(const Texture& color, const Texture& depth,
                                     const Texture& motion, const Texture& neighbor_max,
                                     const Texture& result, const Guertin2014Params& params,
                                     Backend backend) {
  params.validate();
  for (const Texture* t : {&depth, &motion, &result})
    if (t->width() != color.width() || t->height() != color.height())
      throw std::invalid_argument("blurlab: color, depth, motion and result differ in size");
  Program& p = program(backend);
  set_filter_uniforms(p, params);
  p.set_uniform("gamma", {params.gamma});
  p.set_uniform("kappa", {params.kappa});
  PostProcessPass::run(backend, {&color, &depth, &motion, &neighbor_max}, result);
}

}  // namespace blurlab
