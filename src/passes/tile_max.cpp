#include "passes/tile_max.h"

#include "gl/context.h"
#include "gl/texture.h"

namespace blurlab {

// Largest tile side scanned by one thread. On a GPU a work group per tile pays off above 8 x 8
// pixels; llvmpipe runs a group's threads as SIMD lanes and its barriers are costly, so there
// one thread per tile is faster up to 32 x 32 (benchmarks/reconstruct.py, docs/benchmarks.md).
int largest_tile_for_one_thread(const Context& context) {
  return context.is_software() ? 32 : 8;
}

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
  const bool group_per_tile = k > largest_tile_for_one_thread(*context_);
  if (backend == Backend::compute) p.set_uniform("group_per_tile", {group_per_tile ? 1.0 : 0.0});
  PostProcessPass::run(backend, {&motion}, tile_max, group_per_tile);
}

void TileMaxPass::run_with_bounds(const Texture& motion, const Texture& tile_max,
                                  const Texture& tile_bounds, const McGuire2012Params& params) {
  if (tile_bounds.width() != tile_max.width() || tile_bounds.height() != tile_max.height() ||
      tile_bounds.format().channels != 4)
    throw std::invalid_argument("blurlab: tile_bounds must be an RGBA texture of the tile grid");
  Variant bounds(*this, {{"TILE_BOUNDS", "1"}});
  program(Backend::compute).bind_image(1, tile_bounds, GL_WRITE_ONLY);
  run(motion, tile_max, params, Backend::compute);
}

}  // namespace blurlab
