// Runs a fragment shader once per texel of a target texture: one triangle over the viewport,
// drawn into a framebuffer whose only attachment is the target. The fragment backend of the
// post-process passes (docs/gpu.md: kept as the engines' baseline, measured beside compute).
#pragma once

#include <memory>

#include "gl/gl.h"

namespace blurlab {

class Context;
class Program;
class Texture;

class FullscreenDraw : NotCopyable {
 public:
  explicit FullscreenDraw(std::shared_ptr<Context> context);
  ~FullscreenDraw();

  // Draws `program` (vertex stage: shaders/common/fullscreen.vert) over all of `target`.
  void draw(const Program& program, const Texture& target);

 private:
  std::shared_ptr<Context> context_;
  GLuint framebuffer_ = 0, vao_ = 0;
};

}  // namespace blurlab
