#include "passes/uniform_gather.h"

#include "gl/texture.h"

namespace blurlab {

UniformGatherPass::UniformGatherPass(std::shared_ptr<Context> context)
    : PostProcessPass(std::move(context), "passes/uniform_gather.glsl") {}

void UniformGatherPass::run(const Texture& color, const Texture& neighbor_max,
                            const Texture& result, const McGuire2012Params& params) {
  params.validate();
  if (color.width() != result.width() || color.height() != result.height())
    throw std::invalid_argument("blurlab: color and result differ in size");
  const int k = params.k;
  if (neighbor_max.width() != (color.width() + k - 1) / k ||
      neighbor_max.height() != (color.height() + k - 1) / k)
    throw std::invalid_argument("blurlab: NeighborMax must be ceil(W/k) x ceil(H/k)");
  Program& p = program(Backend::compute);
  p.set_uniform("k", {double(k)});
  p.set_uniform("samples", {double(params.samples)});
  p.set_uniform("seed", {double(params.seed)});
  PostProcessPass::run(Backend::compute, {&color, &neighbor_max}, result);
}

}  // namespace blurlab
