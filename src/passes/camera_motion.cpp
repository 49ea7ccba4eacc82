#include "passes/camera_motion.h"

#include "gl/context.h"
#include "gl/texture.h"

namespace blurlab {

CameraMotionPass::CameraMotionPass(std::shared_ptr<Context> context)
    : context_(std::move(context)),
      program_(Program::compute(context_, "passes/camera_motion.glsl", {})) {}

void CameraMotionPass::run(const Texture& depth, const Texture& motion,
                           const CameraMotionMatrices& m) {
  if (depth.width() != motion.width() || depth.height() != motion.height())
    throw std::invalid_argument("blurlab: depth and motion differ in size");
  context_->make_current();
  const GLuint id = program_->id();
  auto matrices = [&](const char* name, const float* values, int count) {
    glProgramUniformMatrix4fv(id, glGetUniformLocation(id, name), count, GL_TRUE, values);
  };
  matrices("view_from_clip", m.view_from_clip, 1);
  matrices("world_from_view", m.world_from_view, 1);
  matrices("clip_from_world", &m.clip_from_world[0][0], 2);
  matrices("sky_from_clip", m.sky_from_clip, 1);
  matrices("sky_projection", &m.sky_projection[0][0], 2);
  glProgramUniform1f(id, glGetUniformLocation(id, "near"), m.near);
  program_->bind_texture(0, depth);
  program_->bind_image(0, motion, GL_WRITE_ONLY);
  program_->dispatch((motion.width() + 15) / 16, (motion.height() + 15) / 16, 1);
}

}  // namespace blurlab
