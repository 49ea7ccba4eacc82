#include "passes/tile_max.h"

#include "gl/texture.h"

namespace blurlab {

TileMaxPass::TileMaxPass(std::shared_ptr<Context> context)
    : PostProcessPass(std::move(context), "passes/tile_max.glsl") {}

void TileMaxPass::run(const Texture& motion, const Texture& tile_max,
                      const McGuire2012Params& params, Backend backend) {
  params.validate();
  const int k = params.k;
  if (tile_max.width() != (motion.width() + k - 1) / k ||
      tile_max.height() != (motion.height() + k - 1) / k)
    throw std::invalid_argument("blurlab: the TileMax texture must be ceil(W/k) x ceil(H/k)");
  Program& p = program(backend);
  p.set_uniform("k", {double(k)});
  p.set_uniform("exposure", {params.exposure});
  PostProcessPass::run(backend, {&motion}, tile_max, /*group_per_texel=*/true);
}

}  // namespace blurlab
