#include "gl/fullscreen.h"

#include "gl/context.h"
#include "gl/program.h"
#include "gl/texture.h"

namespace blurlab {

FullscreenDraw::FullscreenDraw(std::shared_ptr<Context> context) : context_(std::move(context)) {
  context_->make_current();
  glCreateFramebuffers(1, &framebuffer_);
  glCreateVertexArrays(1, &vao_);
  check_gl("creating a full-screen draw");
}

FullscreenDraw::~FullscreenDraw() {
  context_->release(nullptr, [framebuffer = framebuffer_, vao = vao_] {
    glDeleteFramebuffers(1, &framebuffer);
    glDeleteVertexArrays(1, &vao);
  });
}

void FullscreenDraw::draw(const Program& program, const Texture& target) {
  context_->make_current();
  glNamedFramebufferTexture(framebuffer_, GL_COLOR_ATTACHMENT0, target.id(), 0);
  glNamedFramebufferDrawBuffer(framebuffer_, GL_COLOR_ATTACHMENT0);
  if (glCheckNamedFramebufferStatus(framebuffer_, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw GLError("blurlab: cannot render into this texture (framebuffer incomplete)");
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
  glViewport(0, 0, target.width(), target.height());
  // State a shared context may have changed (moderngl users' passes).
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);
  glDisable(GL_SCISSOR_TEST);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glUseProgram(program.id());
  glBindVertexArray(vao_);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glMemoryBarrier(GL_ALL_BARRIER_BITS);
  check_gl(("drawing " + program.name()).c_str());
  context_->after_pass(program.name());
}

}  // namespace blurlab
