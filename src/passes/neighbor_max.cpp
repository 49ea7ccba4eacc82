#include "passes/neighbor_max.h"

#include "gl/texture.h"

namespace blurlab {

NeighborMaxPass::NeighborMaxPass(std::shared_ptr<Context> context)
    : PostProcessPass(std::move(context), "passes/neighbor_max.glsl") {}

void NeighborMaxPass::run(const Texture& tile_max, const Texture& neighbor_max, Backend backend,
                          bool diagonal_reach) {
  if (tile_max.width() != neighbor_max.width() || tile_max.height() != neighbor_max.height())
    throw std::invalid_argument("blurlab: TileMax and NeighborMax must have the same size");
  program(backend).set_uniform("diagonal_reach", {diagonal_reach ? 1.0 : 0.0});
  PostProcessPass::run(backend, {&tile_max}, neighbor_max);
}

}  // namespace blurlab
