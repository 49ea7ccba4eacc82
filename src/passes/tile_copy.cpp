#include "passes/tile_copy.h"

#include "gl/texture.h"

namespace blurlab {

TileCopyPass::TileCopyPass(std::shared_ptr<Context> context)
    : PostProcessPass(std::move(context), "passes/tile_copy.glsl") {}

void TileCopyPass::run(const Texture& color, const Texture& result) {
  if (color.width() != result.width() || color.height() != result.height())
    throw std::invalid_argument("blurlab: color and result differ in size");
  PostProcessPass::run(Backend::compute, {&color}, result);
}

}  // namespace blurlab
