// What every post-process pass shares: its shader compiled for the compute backend (the
// default; docs/gpu.md) and, on demand, for the fragment backend, and a way to run it over a
// target. One shader file serves both, selected by STAGE_COMPUTE / STAGE_FRAGMENT.
#pragma once

#include <array>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "gl/program.h"

namespace blurlab {

class Context;
class FullscreenDraw;
class Texture;

enum class Backend { compute, fragment };

// "compute" or "fragment"; throws std::invalid_argument naming both otherwise.
Backend parse_backend(const std::string& name);

// A texture for a sampler's texture unit, and one for an image unit with its access.
struct TextureUnitBinding {
  int unit;
  const Texture* texture;
};
struct ImageUnitBinding {
  int unit;
  const Texture* texture;
  GLenum access;
};

class PostProcessPass {
 public:
  // `defines` go into every program of the pass.
  PostProcessPass(std::shared_ptr<Context> context, std::string shader, Defines defines = {});
  virtual ~PostProcessPass();

  // The shader file, relative to the shader folder.
  const std::string& shader() const { return shader_; }

 protected:
  // The program for `backend` and the current variant, compiled on first use.
  Program& program(Backend backend);
  // Binds `inputs` to texture units 0, 1, ... and runs the program once per texel of
  // `target` (compute: image unit 0, write-only; fragment: the framebuffer's color attachment).
  // With `group_per_texel`, the compute backend runs one whole work group per texel.
  void run(Backend backend, const std::vector<const Texture*>& inputs, const Texture& target,
           bool group_per_texel = false);
  // What every run comes down to: binds `textures` and `images`, then runs the program once per
  // texel of `target` (compute: a work group per local_size block, per texel with
  // `group_per_texel`; fragment: `target` drawn as the framebuffer's color attachment).
  void run_bound(Backend backend, const std::vector<TextureUnitBinding>& textures,
                 const std::vector<ImageUnitBinding>& images, const Texture& target,
                 bool group_per_texel);

  std::shared_ptr<Context> context_;

 private:
  Defines defines(Backend backend) const;

  std::string shader_;
  Defines defines_;
  std::map<std::pair<Backend, Defines>, std::shared_ptr<Program>> programs_;
  std::unique_ptr<FullscreenDraw> fullscreen_;
};

}  // namespace blurlab
