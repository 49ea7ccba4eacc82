#include "passes/reconstruct_urho3d.h"

#include "gl/texture.h"

namespace blurlab {

ReconstructUrho3dPass::ReconstructUrho3dPass(std::shared_ptr<Context> context)
    : PostProcessPass(std::move(context), "passes/reconstruct_urho3d.glsl") {}

void ReconstructUrho3dPass::run(const Texture& color, const Texture& depth, const Texture& motion,
                                const Texture& neighbor_max, const Texture& jitter,
                                const Texture& result, const McGuire2012Params& params, float far) {
  params.validate();
  if (!(far > 0.0f) || !std::isfinite(far))
    throw std::invalid_argument("blurlab: far = " + std::to_string(far) +
                                " must be finite and > 0 (depth units)");
  if (jitter.width() != 64 || jitter.height() != 64 || jitter.format().internal != GL_R32F)
    throw std::invalid_argument("blurlab: the jitter texture must be 64 x 64 float32");
  for (const Texture* t : {&depth, &motion, &result})
    if (t->width() != color.width() || t->height() != color.height())
      throw std::invalid_argument("blurlab: color, depth, motion and result differ in size");
  Program& p = program(Backend::fragment);
  p.set_uniform("k", {double(params.k)});
  p.set_uniform("samples", {double(params.samples)});
  p.set_uniform("soft_z", {params.soft_z});
  p.set_uniform("exposure", {params.exposure});
  p.set_uniform("far", {far});
  PostProcessPass::run(Backend::fragment, {&color, &depth, &motion, &neighbor_max, &jitter},
                       result);
}

}  // namespace blurlab
