// A recorded sequence of ShaderPass runs, replayed by one call (docs/spec.md §18: a Python call of
// a method must cost little more than its GPU time). Recording resolves each run once: programs,
// texture and image units, uniforms converted to GL's types, work-group counts. A replay binds the
// textures it is given in the recorded places, uploads the uniforms and dispatches, with no name
// lookups and one GL error check at the end. The textures are arguments of each replay, so one plan
// serves every call that has textures of the recorded sizes and formats.
#pragma once

#include <memory>
#include <vector>

#include "passes/shader_pass.h"

namespace blurlab {

class Context;
class FullscreenDraw;
class Texture;

class DispatchPlan : NotCopyable {
 public:
  // `textures` are the plan's textures at recording time, in the order replays hand them over;
  // their sizes and formats are what every replay must match.
  DispatchPlan(std::shared_ptr<Context> context, const std::vector<const Texture*>& textures);
  ~DispatchPlan();

  // Appends `pass`.run(inputs, outputs, uniforms, backend, group_per_texel) as it would run with
  // the recording's textures, checked as run() checks it (ShaderPass::resolve).
  void add(std::shared_ptr<ShaderPass> pass, const NamedTextures& inputs,
           const NamedTextures& outputs, const UniformValues& uniforms, Backend backend,
           bool group_per_texel);

  // Runs the recorded passes in order on `textures`, which must match the recording's in number,
  // size and format (std::invalid_argument otherwise, before any GL call).
  void run(const std::vector<const Texture*>& textures);

  size_t steps() const { return steps_.size(); }

 private:
  struct Shape {
    int width, height;
    GLenum internal;
  };
  std::shared_ptr<Context> context_;
  std::vector<const Texture*> recording_;  // only during add(): the recording's textures
  std::vector<Shape> shapes_;
  std::vector<std::shared_ptr<ShaderPass>> passes_;  // keep the recorded programs alive
  std::vector<ResolvedRun> steps_;
  std::unique_ptr<FullscreenDraw> fullscreen_;
};

}  // namespace blurlab
