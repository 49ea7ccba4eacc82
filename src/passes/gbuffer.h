// G-buffer pass, docs/spec.md §1: one raster pass writes linear color (RGBA32F,
// unclamped: emissive materials reach 10^4), positive linear
// view depth (R32F), motion t0→t1 in pixels with +y down (RG32F) and the object id (R32F, −1 for
// the background) at the G-buffer's instant; where a `motion_sides` target is given, also the
// two-sided motion (RGBA32F): M_prev = instant − t0 in RG, M_next = t1 − instant in BA, pixels,
// +y down (docs/spec.md §17.1).
//
// Motion is divided per fragment: the vertex shader hands the clip positions at t0 and t1 to
// the rasterizer, which interpolates them perspective-correctly, and the fragment shader divides
// by w. Dividing per vertex breaks on triangles clipped at the near plane ("Blurry things").
// Skinned vertices use the bone matrices at t0, t1 and the instant.
//
// Only the colour target is required. Without a motion target (nor `motion_sides`), every
// background output is a constant, so the targets are cleared to it before the draws instead of
// a background triangle being shaded after them (docs/spec.md §1, Background).
//
// All matrices are row-major float[16] (NumPy's order). Every projection here has y flipped, so
// that framebuffer row 0 (GL's bottom) holds image row 0 (the top): the one place where GL's
// bottom-left origin is reconciled with blurlab's top-left arrays.
#pragma once

#include <memory>
#include <vector>

#include "gl/gl.h"

namespace blurlab {

class Buffer;
class Context;
class Mesh;
class Program;
class Texture;

struct GBufferCamera {
  float view_projection[3][16];  // t0, t1, instant
  float eye[3];                  // camera position at the instant, world space
  float near;                    // near-plane distance
  // Points at infinity, for background motion: instant clip → world direction, and world
  // direction → clip at t0 and t1 (rotation only; translation does not move them).
  float sky_from_clip[16];
  float sky_projection[2][16];
};

struct GBufferLight {
  float direction[3];  // toward the light, world space
  float color[3];
  float ambient[3];
  float background[4];
};

// Tonal-art-map hatching (docs/spec.md §5) replaces the shading with color · (1 − ink). The maps
// are mip chains made level by level.
struct GBufferHatching {
  enum class Scheme { none = 0, six_way = 1, threshold = 2 } scheme = Scheme::none;
  float scale = 1.0f;                 // TAM repeats per unit of texture coordinate
  std::shared_ptr<Texture> tam_low;   // six_way: tones 1–3 in RGB; threshold: in R, the
                                      // darkness at which each texel turns to ink
  std::shared_ptr<Texture> tam_high;  // six_way: tones 4–6 in RGB; threshold: unused
};

// How a material's alpha is used (docs/spec.md §20): opaque ignores it; mask discards fragments
// with alpha < cutoff; blend and additive are translucent, drawn only into fragment lists.
enum class AlphaMode { opaque = 0, mask = 1, blend = 2, additive = 3 };

struct GBufferMaterial {
  float color[4] = {1, 1, 1, 1};
  AlphaMode alpha_mode = AlphaMode::opaque;
  float alpha_cutoff = 0.5f;
  float emission[3] = {0, 0, 0};  // emitted radiance (colour x strength), added unclamped
  float specular = 0.0f;
  float shininess = 32.0f;
  std::shared_ptr<Texture> texture;  // optional albedo map, multiplied with color
  GBufferHatching hatching;
};

struct GBufferDraw {
  std::shared_ptr<Mesh> mesh;
  float model[3][16] = {};   // t0, t1, instant
  std::vector<float> bones;  // bone_count matrices at t0, then at t1, then at the instant
  int bone_count = 0;
  GBufferMaterial material;
  int object_id = 0;
};

struct GBufferTargets {
  std::shared_ptr<Texture> color, depth, motion, object_id;
  std::shared_ptr<Texture> motion_sides;  // optional: two-sided motion (docs/spec.md §17.1)
  // Optional, all or none: per-pixel fragment lists of translucent surfaces (docs/spec.md §20).
  // Given, the pass writes no colour, depth or motion target and draws no background: each
  // fragment nearer than `opaque_depth` (R32F, linear) is appended to its pixel's list. Fragment
  // k of pixel (x, y) goes to texel (x + (k / rows)·W, y + (k % rows)·H) of `fragment_surface`
  // (blocks of W x H, blurlab.translucency.fragment_layout; premultiplied colour,
  // coverage) and `fragment_motion` (depth, motion, alpha mode); `fragment_counts` (R32UI,
  // cleared by the caller) counts every fragment, those past the capacity too.
  std::shared_ptr<Texture> fragment_counts, fragment_surface, fragment_motion, opaque_depth;
};

class GBufferPass : NotCopyable {
 public:
  explicit GBufferPass(std::shared_ptr<Context> context);
  ~GBufferPass();

  // `over_base` (a token from keep_base, 0 for none): the draws go over a kept base instead of
  // a cleared image. The depth buffer starts as the base's; the caller has copied the base's
  // colour (and linear depth) into the targets. Only for passes without motion (the background
  // a constant) and without fragment lists.
  void render(const GBufferTargets& targets, const GBufferCamera& camera, const GBufferLight& light,
              const std::vector<GBufferDraw>& draws, int over_base = 0);

  // Keeps the depth buffer of the last render as the base that later renders may draw over
  // (the objects every sub-frame of a reference shares, drawn once: docs/spec.md §11); returns
  // its token. A new base replaces the last one, whose token is then refused.
  int keep_base();

 private:
  // The program's uniform locations, looked up once: a draw sets ten of them.
  struct Locations {
    GLint view_projection, sky_from_clip, sky_projection, eye, near, size, light_direction,
        light_color, ambient, background_color, background, model, bone_count, material_color,
        material_emission, material_specular, material_shininess, has_texture, object_id,
        hatching_scale, alpha_mode, alpha_cutoff, layer_capacity;
  };
  // One program per hatching scheme (HATCHING = 0, 1, 2) and target (LAYERS = 0: the G-buffer,
  // 1: fragment lists), each with only its own code: llvmpipe runs every branch of a shader,
  // taken or not. Built on first use.
  struct Variant {
    std::shared_ptr<Program> program;
    Locations locations{};
  };
  const Variant& variant(GBufferHatching::Scheme scheme, bool layers = false);
  void resize_depth(int width, int height);
  void set_frame_uniforms(const Variant& variant, const GBufferCamera& camera,
                          const GBufferLight& light, int width, int height);
  void draw_background(const Variant& variant);
  std::shared_ptr<Context> context_;
  Variant variants_[2][3];
  std::unique_ptr<Buffer> bones_;
  size_t bones_capacity_ = 0;
  GLuint framebuffer_ = 0, depth_buffer_ = 0, empty_vao_ = 0;
  int depth_width_ = 0, depth_height_ = 0;
  // The kept base's depth (keep_base): its size and token; tokens are never reused.
  GLuint base_depth_ = 0;
  int base_width_ = 0, base_height_ = 0, base_token_ = 0, last_token_ = 0;
};

}  // namespace blurlab
