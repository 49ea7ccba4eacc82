#include "passes/post_process.h"

#include "gl/context.h"
#include "gl/fullscreen.h"
#include "gl/texture.h"
#include "passes/tile_lists.h"

namespace blurlab {

Backend parse_backend(const std::string& name) {
  if (name == "compute") return Backend::compute;
  if (name == "fragment") return Backend::fragment;
  throw std::invalid_argument("blurlab: backend must be 'compute' or 'fragment', not '" + name +
                              "'");
}

PostProcessPass::PostProcessPass(std::shared_ptr<Context> context, std::string shader,
                                 Defines defines)
    : context_(std::move(context)), shader_(std::move(shader)), defines_(std::move(defines)) {}

PostProcessPass::~PostProcessPass() = default;

PostProcessPass::Variant::Variant(PostProcessPass& pass, Defines defines)
    : pass_(pass), previous_(std::move(pass.variant_)) {
  pass_.variant_ = std::move(defines);
}

PostProcessPass::Variant::~Variant() {
  pass_.variant_ = std::move(previous_);
}

void PostProcessPass::restrict_to_tiles(std::shared_ptr<const TileLists> lists, int tile_class) {
  if (lists && (tile_class < 0 || tile_class >= TileLists::kClasses))
    throw std::invalid_argument("blurlab: tile class " + std::to_string(tile_class) +
                                " is outside 0.." + std::to_string(TileLists::kClasses - 1));
  tile_lists_ = std::move(lists);
  tile_class_ = tile_class;
}

Defines PostProcessPass::defines(Backend backend) const {
  Defines d{{backend == Backend::compute ? "STAGE_COMPUTE" : "STAGE_FRAGMENT", "1"}};
  d.insert(d.end(), defines_.begin(), defines_.end());
  d.insert(d.end(), variant_.begin(), variant_.end());
  if (tile_lists_ && backend == Backend::compute) {
    d.emplace_back("TILE_LIST", "1");
    if (whole_tiles_) d.emplace_back("WHOLE_TILES", "1");
  }
  return d;
}

Program& PostProcessPass::program(Backend backend) {
  const Defines d = defines(backend);
  auto it = programs_.find({backend, d});
  if (it != programs_.end()) return *it->second;
  std::shared_ptr<Program> p =
      backend == Backend::compute
          ? Program::compute(context_, shader_, d)
          : Program::graphics(context_, "common/fullscreen.vert", shader_, d);
  programs_[{backend, d}] = p;
  return *p;
}

void PostProcessPass::run(Backend backend, const std::vector<const Texture*>& inputs,
                          const Texture& target, bool group_per_texel) {
  std::vector<TextureUnitBinding> textures;
  for (size_t unit = 0; unit < inputs.size(); ++unit)
    textures.push_back({static_cast<int>(unit), inputs[unit]});
  std::vector<ImageUnitBinding> images;
  if (backend == Backend::compute) images.push_back({0, &target, GL_WRITE_ONLY});
  run_bound(backend, textures, images, target, group_per_texel);
}

void PostProcessPass::run_bound(Backend backend, const std::vector<TextureUnitBinding>& textures,
                                const std::vector<ImageUnitBinding>& images, const Texture& target,
                                bool group_per_texel) {
  if (tile_lists_ && backend != Backend::compute)
    throw std::invalid_argument("blurlab: tile lists run on the compute backend only");
  Program& p = program(backend);
  for (const TextureUnitBinding& t : textures) p.bind_texture(t.unit, *t.texture);
  for (const ImageUnitBinding& i : images) p.bind_image(i.unit, *i.texture, i.access);
  if (backend == Backend::compute) {
    if (tile_lists_) {
      const TileLists& lists = *tile_lists_;
      if (lists.grid_width() != (target.width() + lists.k() - 1) / lists.k() ||
          lists.grid_height() != (target.height() + lists.k() - 1) / lists.k())
        throw std::invalid_argument("blurlab: the tile lists were made for another image size");
      p.set_uniform(kTileListK, {double(lists.k())});
      lists.bind_list(0, tile_class_);
      p.dispatch_indirect(lists.buffer(), lists.command_offset(tile_class_, whole_tiles_));
    } else if (group_per_texel) {
      p.dispatch(target.width(), target.height(), 1);
    } else {
      const auto local = p.local_size();
      p.dispatch((target.width() + local[0] - 1) / local[0],
                 (target.height() + local[1] - 1) / local[1], 1);
    }
  } else {
    if (!fullscreen_) fullscreen_ = std::make_unique<FullscreenDraw>(context_);
    fullscreen_->draw(p, target);
  }
}

}  // namespace blurlab
