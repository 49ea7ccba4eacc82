#include "passes/post_process.h"

#include "gl/context.h"
#include "gl/fullscreen.h"
#include "gl/texture.h"

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

Defines PostProcessPass::defines(Backend backend) const {
  Defines d{{backend == Backend::compute ? "STAGE_COMPUTE" : "STAGE_FRAGMENT", "1"}};
  d.insert(d.end(), defines_.begin(), defines_.end());
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
  Program& p = program(backend);
  for (const TextureUnitBinding& t : textures) p.bind_texture(t.unit, *t.texture);
  for (const ImageUnitBinding& i : images) p.bind_image(i.unit, *i.texture, i.access);
  if (backend == Backend::compute) {
    if (group_per_texel) {
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
