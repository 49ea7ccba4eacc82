// A 2D texture with immutable storage, one mip level, nearest filtering and clamp-to-edge.
//
// Orientation (docs/architecture.md "Arrays"): texel row 0 holds image row 0, the top of the image.
// Arrays move to and from textures with no flip; the one place that reconciles this with GL's
// bottom-left window origin is the projection used by raster passes.
#pragma once

#include <cstddef>
#include <memory>
#include <string>

#include "gl/gl.h"

namespace blurlab {

class Context;

enum class PixelType { u8, f16, f32, u32 };

struct TextureFormat {
  PixelType type;
  int channels;         // 1..4
  GLenum internal;      // e.g. GL_RGBA32F
  GLenum pixel_format;  // GL_RED, GL_RG, GL_RGB, GL_RGBA (GL_RED_INTEGER... for u32)
  GLenum pixel_type;    // GL_UNSIGNED_BYTE, GL_HALF_FLOAT, GL_FLOAT, GL_UNSIGNED_INT
  size_t bytes_per_texel;
  std::string image_layout;  // GLSL image format qualifier, "" where images cannot bind it
};

// Throws std::invalid_argument for channels outside 1..4.
TextureFormat texture_format(PixelType type, int channels);

class Texture : NotCopyable {
 public:
  // `levels` > 1 allocates a mipmap chain (material textures); passes use one level.
  Texture(std::shared_ptr<Context> context, int width, int height, const TextureFormat& format,
          int levels = 1);
  ~Texture();

  // Whole-image transfers of tightly packed rows, row 0 first.
  void upload(const void* data, size_t bytes);
  // One mip level, for textures whose levels are made by the caller rather than by averaging
  // (a tonal art map's levels each hold their own strokes, docs/spec.md §5).
  void upload_level(int level, const void* data, size_t bytes);
  void download(void* data, size_t bytes) const;
  // Clears every texel to zero, or to `value` (as many floats as the texture has channels).
  void clear();
  void clear(const float* value);
  // Fills levels 1.. from level 0 and samples with trilinear filtering and repeat wrapping,
  // as a material texture should be.
  void generate_mipmaps();
  // Trilinear filtering and repeat wrapping over the levels as they are (uploaded level by level).
  void use_mipmaps();
  // Copies this texture's size worth of texels from `source` starting at (x, y) there (a crop).
  void copy_from(const Texture& source, int x, int y);
  int levels() const { return levels_; }

  GLuint id() const { return id_; }
  int width() const { return width_; }
  int height() const { return height_; }
  const TextureFormat& format() const { return format_; }
  size_t byte_size() const {
    return static_cast<size_t>(width_) * height_ * format_.bytes_per_texel;
  }
  const std::shared_ptr<Context>& context() const { return context_; }

 private:
  std::shared_ptr<Context> context_;
  GLuint id_ = 0;
  int width_, height_;
  TextureFormat format_;
  int levels_;
};

}  // namespace blurlab
