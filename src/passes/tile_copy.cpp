#include "passes/tile_copy.h"

#include "gl/texture.h"

namespace blurlab {

TileCopyPass::TileCopyPass(std::shared_ptr<Context> context)
    : PostProcessPass(std::move(context), "passes/tile_copy.glsl") {
  whole_tiles_ = true;  // a copy is too cheap per pixel to pay for a work group per 8 x 8 block
}

void TileCopyPass::run(const Texture& color, const Texture& result) {
  if (color.width() != result.width() || color.height() != result.height())
    throw std::invalid_argument("blurlab: color and result differ in size");
  PostProcessPass::run(Backend::compute, {&color}, result);
}

}  // namespace blurlab
