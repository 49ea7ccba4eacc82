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

PostProcessPass::PostProcessPass(std::shared_ptr<Context> context, std::string shader)
    : context_(std::move(context)), shader_(std::move(shader)) {}

PostProcessPass::~PostProcessPass() = default;

Program& PostProcessPass::program(Backend backend) {
  auto it = programs_.find(backend);
  if (it != programs_.end()) return *it->second;
  std::shared_ptr<Program> p = backend == Backend::compute
                                   ? Program::compute(context_, shader_, {{"STAGE_COMPUTE", "1"}})
                                   : Program::graphics(context_, "common/fullscreen.vert", shader_,
                                                       {{"STAGE_FRAGMENT", "1"}});
  programs_[backend] = p;
  return *p;
}

void PostProcessPass::run(Backend backend, const std::vector<const Texture*>& inputs,
                          const Texture& target, bool group_per_texel) {
  Program& p = program(backend);
  for (size_t unit = 0; unit < inputs.size(); ++unit)
    p.bind_texture(static_cast<int>(unit), *inputs[unit]);
  if (backend == Backend::compute) {
    p.bind_image(0, target, GL_WRITE_ONLY);
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
