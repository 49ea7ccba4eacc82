#include "passes/dispatch_plan.h"

#include <stdexcept>
#include <string>

#include "gl/context.h"
#include "gl/fullscreen.h"
#include "gl/texture.h"

namespace blurlab {

DispatchPlan::DispatchPlan(std::shared_ptr<Context> context,
                           const std::vector<const Texture*>& textures)
    : context_(std::move(context)), recording_(textures) {
  for (const Texture* t : textures) {
    if (t == nullptr) throw std::invalid_argument("blurlab: a dispatch plan's texture is None");
    shapes_.push_back({t->width(), t->height(), t->format().internal});
  }
}

DispatchPlan::~DispatchPlan() = default;

void DispatchPlan::add(std::shared_ptr<ShaderPass> pass, const NamedTextures& inputs,
                       const NamedTextures& outputs, const UniformValues& uniforms, Backend backend,
                       bool group_per_texel) {
  steps_.push_back(pass->resolve(inputs, outputs, uniforms, backend, group_per_texel, recording_));
  passes_.push_back(std::move(pass));
}

void DispatchPlan::run(const std::vector<const Texture*>& textures) {
  if (textures.size() != shapes_.size())
    throw std::invalid_argument("blurlab: the dispatch plan takes " +
                                std::to_string(shapes_.size()) + " textures, got " +
                                std::to_string(textures.size()));
  for (size_t i = 0; i < textures.size(); ++i) {
    const Texture* t = textures[i];
    if (t == nullptr)
      throw std::invalid_argument("blurlab: texture " + std::to_string(i) +
                                  " of the dispatch plan is None");
    if (t->width() != shapes_[i].width || t->height() != shapes_[i].height ||
        t->format().internal != shapes_[i].internal)
      throw std::invalid_argument("blurlab: texture " + std::to_string(i) +
                                  " of the dispatch plan differs in size or format from the "
                                  "recorded one");
  }
  context_->make_current();
  for (const ResolvedRun& step : steps_) {
    for (const PreparedUniform& u : step.uniforms) step.program->apply_uniform(u);
    for (const auto& [unit, index] : step.textures) glBindTextureUnit(unit, textures[index]->id());
    // Read-write, as ShaderPass::run binds its outputs (shader_pass.h).
    for (const auto& [unit, index] : step.images) {
      const Texture& t = *textures[index];
      glBindImageTexture(unit, t.id(), 0, GL_FALSE, 0, GL_READ_WRITE, t.format().internal);
    }
    if (step.backend == Backend::compute) {
      glUseProgram(step.program->id());
      glDispatchCompute(step.groups[0], step.groups[1], step.groups[2]);
      // Later passes, downloads and draws read what this pass wrote.
      glMemoryBarrier(GL_ALL_BARRIER_BITS);
      context_->after_pass(step.program->name());
    } else {
      if (!fullscreen_) fullscreen_ = std::make_unique<FullscreenDraw>(context_);
      fullscreen_->draw(*step.program, *textures[step.target]);
    }
  }
  check_gl("replaying a dispatch plan");
}

}  // namespace blurlab
