// What every post-process pass shares: its shader compiled for the compute backend (the
// default; GPU.md) and, on demand, for the fragment backend, and a way to run it over a
// target. One shader file serves both, selected by STAGE_COMPUTE / STAGE_FRAGMENT.
#pragma once

#include <array>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "gl/program.h"

namespace blurlab {

class Context;
class FullscreenDraw;
class Texture;

enum class Backend { compute, fragment };

// "compute" or "fragment"; throws std::invalid_argument naming both otherwise.
Backend parse_backend(const std::string& name);

class PostProcessPass {
 public:
  PostProcessPass(std::shared_ptr<Context> context, std::string shader);
  virtual ~PostProcessPass();

 protected:
  // The program for `backend`, compiled on first use.
  Program& program(Backend backend);
  // Binds `inputs` to texture units 0, 1, ... and runs the program once per texel of
  // `target` (compute: image unit 0; fragment: the framebuffer's color attachment). With
  // `group_per_texel`, the compute backend runs one whole work group per texel.
  void run(Backend backend, const std::vector<const Texture*>& inputs, const Texture& target,
           bool group_per_texel = false);

  std::shared_ptr<Context> context_;

 private:
  std::string shader_;
  std::map<Backend, std::shared_ptr<Program>> programs_;
  std::unique_ptr<FullscreenDraw> fullscreen_;
};

}  // namespace blurlab
