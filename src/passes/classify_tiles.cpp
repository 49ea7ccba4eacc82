#include "passes/classify_tiles.h"

#include "gl/context.h"
#include "gl/texture.h"

namespace blurlab {

ClassifyTilesPass::ClassifyTilesPass(std::shared_ptr<Context> context)
    : PostProcessPass(std::move(context), "passes/classify_tiles.glsl") {}

void ClassifyTilesPass::run(const Texture& tile_bounds, const Texture& neighbor_max,
                            const Texture& tile_class, TileLists& lists, float still_threshold,
                            float uniform_spread) {
  for (const Texture* t : {&tile_bounds, &tile_class})
    if (t->width() != neighbor_max.width() || t->height() != neighbor_max.height())
      throw std::invalid_argument(
          "blurlab: tile_bounds, neighbor_max and tile_class differ in size");
  if (lists.grid_width() != neighbor_max.width() || lists.grid_height() != neighbor_max.height())
    throw std::invalid_argument("blurlab: the tile lists were made for another tile grid");
  lists.reset();
  Program& p = program(Backend::compute);
  p.set_uniform("still_threshold", {still_threshold});
  p.set_uniform("uniform_spread", {uniform_spread});
  p.set_uniform("list_first", {double(lists.list_first())});
  p.set_uniform("list_stride", {double(lists.list_stride())});
  lists.bind_list(0, -1);
  PostProcessPass::run(Backend::compute, {&tile_bounds, &neighbor_max}, tile_class);
}

}  // namespace blurlab
