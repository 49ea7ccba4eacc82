#include "gl/texture.h"

#include <algorithm>
#include <cstdint>

#include "gl/context.h"

namespace blurlab {

TextureFormat texture_format(PixelType type, int channels) {
  if (channels < 1 || channels > 4)
    throw std::invalid_argument("blurlab: a texture has 1 to 4 channels, not " +
                                std::to_string(channels));
  static const GLenum layouts[] = {GL_RED, GL_RG, GL_RGB, GL_RGBA};
  static const GLenum u8[] = {GL_R8, GL_RG8, GL_RGB8, GL_RGBA8};
  static const GLenum f16[] = {GL_R16F, GL_RG16F, GL_RGB16F, GL_RGBA16F};
  static const GLenum f32[] = {GL_R32F, GL_RG32F, GL_RGB32F, GL_RGBA32F};
  // Unsigned integers (atomic keys): sampled as usampler2D, never filtered.
  static const GLenum u32[] = {GL_R32UI, GL_RG32UI, GL_RGB32UI, GL_RGBA32UI};
  static const GLenum integer_layouts[] = {GL_RED_INTEGER, GL_RG_INTEGER, GL_RGB_INTEGER,
                                           GL_RGBA_INTEGER};
  // Image load/store has no three-channel formats.
  static const char* u8_image[] = {"r8", "rg8", "", "rgba8"};
  static const char* f16_image[] = {"r16f", "rg16f", "", "rgba16f"};
  static const char* f32_image[] = {"r32f", "rg32f", "", "rgba32f"};
  static const char* u32_image[] = {"r32ui", "rg32ui", "", "rgba32ui"};
  const int i = channels - 1;
  switch (type) {
    case PixelType::u8:
      return {type, channels, u8[i], layouts[i], GL_UNSIGNED_BYTE, size_t(channels), u8_image[i]};
    case PixelType::f16:
      return {type,        channels, f16[i], layouts[i], GL_HALF_FLOAT, size_t(2 * channels),
              f16_image[i]};
    case PixelType::f32:
      return {type, channels, f32[i], layouts[i], GL_FLOAT, size_t(4 * channels), f32_image[i]};
    case PixelType::u32:
      return {
          type,        channels, u32[i], integer_layouts[i], GL_UNSIGNED_INT, size_t(4 * channels),
          u32_image[i]};
  }
  throw std::invalid_argument("blurlab: unknown pixel type");
}

Texture::Texture(std::shared_ptr<Context> context, int width, int height,
                 const TextureFormat& format, int levels)
    : context_(std::move(context)),
      width_(width),
      height_(height),
      format_(format),
      levels_(levels) {
  const int limit = context_->max_texture_size();
  if (width < 1 || height < 1 || width > limit || height > limit)
    throw std::invalid_argument("blurlab: texture size " + std::to_string(width) + "x" +
                                std::to_string(height) + " is outside 1.." + std::to_string(limit) +
                                " (GL_MAX_TEXTURE_SIZE) per side");
  if (levels < 1) throw std::invalid_argument("blurlab: a texture has at least one level");
  context_->make_current();
  glCreateTextures(GL_TEXTURE_2D, 1, &id_);
  glTextureStorage2D(id_, levels, format_.internal, width, height);
  glTextureParameteri(id_, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTextureParameteri(id_, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glTextureParameteri(id_, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(id_, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  check_created("creating a texture", [this] { glDeleteTextures(1, &id_); });
  context_->track("texture", +1);
}

Texture::~Texture() {
  context_->release("texture", [id = id_] { glDeleteTextures(1, &id); });
}

void Texture::upload(const void* data, size_t bytes) {
  if (bytes != byte_size())
    throw std::invalid_argument("blurlab: upload of " + std::to_string(bytes) +
                                " bytes into a texture of " + std::to_string(byte_size()));
  context_->make_current();
  glTextureSubImage2D(id_, 0, 0, 0, width_, height_, format_.pixel_format, format_.pixel_type,
                      data);
  check_gl("texture upload");
}

void Texture::upload_level(int level, const void* data, size_t bytes) {
  if (level < 0 || level >= levels_)
    throw std::invalid_argument("blurlab: level " + std::to_string(level) + " is outside 0.." +
                                std::to_string(levels_ - 1));
  const int w = std::max(1, width_ >> level), h = std::max(1, height_ >> level);
  const size_t expected = static_cast<size_t>(w) * h * format_.bytes_per_texel;
  if (bytes != expected)
    throw std::invalid_argument("blurlab: upload of " + std::to_string(bytes) +
                                " bytes into level " + std::to_string(level) + " of " +
                                std::to_string(expected));
  context_->make_current();
  glTextureSubImage2D(id_, level, 0, 0, w, h, format_.pixel_format, format_.pixel_type, data);
  check_gl("texture level upload");
}

void Texture::download(void* data, size_t bytes) const {
  if (bytes != byte_size())
    throw std::invalid_argument("blurlab: download of a texture of " + std::to_string(byte_size()) +
                                " bytes into " + std::to_string(bytes));
  context_->make_current();
  context_->count_wait();
  glGetTextureImage(id_, 0, format_.pixel_format, format_.pixel_type, static_cast<GLsizei>(bytes),
                    data);
  check_gl("texture download");
}

void Texture::clear() {
  context_->make_current();
  glClearTexImage(id_, 0, format_.pixel_format, format_.pixel_type, nullptr);
  check_gl("texture clear");
}

void Texture::clear(const float* value) {
  if (format_.type == PixelType::u32)
    throw std::invalid_argument("blurlab: an unsigned integer texture clears to zero only");
  context_->make_current();
  glClearTexImage(id_, 0, format_.pixel_format, GL_FLOAT, value);
  check_gl("texture clear");
}

void Texture::copy_from(const Texture& source, int x, int y) {
  if (source.format().internal != format_.internal)
    throw std::invalid_argument("blurlab: copy between textures of different formats");
  if (x < 0 || y < 0 || x + width_ > source.width() || y + height_ > source.height())
    throw std::invalid_argument("blurlab: the copied region lies outside the source texture");
  context_->make_current();
  glCopyImageSubData(source.id(), GL_TEXTURE_2D, 0, x, y, 0, id_, GL_TEXTURE_2D, 0, 0, 0, 0, width_,
                     height_, 1);
  check_gl("texture copy");
}

void Texture::generate_mipmaps() {
  context_->make_current();
  glGenerateTextureMipmap(id_);
  use_mipmaps();
}

void Texture::use_mipmaps() {
  context_->make_current();
  glTextureParameteri(id_, GL_TEXTURE_MIN_FILTER,
                      levels_ > 1 ? GL_LINEAR_MIPMAP_LINEAR : GL_LINEAR);
  glTextureParameteri(id_, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTextureParameteri(id_, GL_TEXTURE_WRAP_S, GL_REPEAT);
  glTextureParameteri(id_, GL_TEXTURE_WRAP_T, GL_REPEAT);
  check_gl("setting mipmap sampling");
}

}  // namespace blurlab
