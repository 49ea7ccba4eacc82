// What every post-process pass shares: its shader compiled for the compute backend (the
// default; docs/gpu.md) and, on demand, for the fragment backend, and a way to run it over a
// target. One shader file serves both, selected by STAGE_COMPUTE / STAGE_FRAGMENT.
//
// A compute pass can also be restricted to the tiles of one class of a tile classification
// (Jimenez 2014; ClassifyTilesPass): it is then compiled with TILE_LIST defined, so that
// shaders/common/tile_list.glsl maps each invocation to a pixel of a listed tile, and run by
// an indirect dispatch whose work-group count the classification wrote.
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
class TileLists;

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

// The uniform that the tile-list variant of a compute pass reads (common/tile_list.glsl); the
// pass sets it itself.
inline constexpr char kTileListK[] = "tile_list_k";

class PostProcessPass {
 public:
  // `defines` go into every program of the pass.
  PostProcessPass(std::shared_ptr<Context> context, std::string shader, Defines defines = {});
  virtual ~PostProcessPass();

  // The shader file, relative to the shader folder.
  const std::string& shader() const { return shader_; }

  // Restricts the following compute runs to the tiles of class `tile_class` in `lists`
  // (their k must be the pass's tile size); nullptr lifts the restriction. A restricted pass
  // writes only the pixels of those tiles and leaves the rest of its target as it was.
  void restrict_to_tiles(std::shared_ptr<const TileLists> lists, int tile_class);

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
  // `group_per_texel`, or over the listed tiles when restricted; fragment: `target` drawn as the
  // framebuffer's color attachment).
  void run_bound(Backend backend, const std::vector<TextureUnitBinding>& textures,
                 const std::vector<ImageUnitBinding>& images, const Texture& target,
                 bool group_per_texel);

  // True while restrict_to_tiles holds a tile class.
  bool restricted() const { return tile_lists_ != nullptr; }

  // Compiles the shader with `defines` for the program() and run() calls made while the
  // returned guard lives (e.g. TileMax's TILE_BOUNDS output).
  class Variant {
   public:
    Variant(PostProcessPass& pass, Defines defines);
    ~Variant();
    Variant(const Variant&) = delete;
    Variant& operator=(const Variant&) = delete;

   private:
    PostProcessPass& pass_;
    Defines previous_;
  };

  std::shared_ptr<Context> context_;
  // Set by passes whose shader takes a whole listed tile per work group (WHOLE_TILES).
  bool whole_tiles_ = false;

 private:
  Defines defines(Backend backend) const;

  std::string shader_;
  Defines defines_;
  Defines variant_;
  std::shared_ptr<const TileLists> tile_lists_;
  int tile_class_ = 0;
  std::map<std::pair<Backend, Defines>, std::shared_ptr<Program>> programs_;
  std::unique_ptr<FullscreenDraw> fullscreen_;
};

}  // namespace blurlab
