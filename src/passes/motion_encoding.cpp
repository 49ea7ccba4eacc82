#include "passes/motion_encoding.h"

#include <algorithm>
#include <cctype>
#include <cmath>

#include "gl/context.h"
#include "gl/program.h"
#include "gl/texture.h"

namespace blurlab {

MotionEncodingPass::MotionEncodingPass(std::shared_ptr<Context> context)
    : context_(std::move(context)) {}

std::shared_ptr<Program> MotionEncodingPass::program(const std::string& format, bool encode) {
  const std::string key = format + (encode ? "/encode" : "/decode");
  auto it = programs_.find(key);
  if (it != programs_.end()) return it->second;
  std::string macro = "FORMAT_" + format;
  std::transform(macro.begin(), macro.end(), macro.begin(), ::toupper);
  auto p = Program::compute(context_, "passes/motion_encoding.comp",
                            {{macro, "1"}, {encode ? "ENCODE" : "DECODE", "1"}});
  programs_[key] = p;
  return p;
}

void MotionEncodingPass::run(const Texture& motion, const Texture& stored, const Texture& decoded,
                             const std::string& format, float maxlen) {
  const bool half = format == "rg16f";
  if (!half && format != "rgba8_offset" && format != "rgba8_polar")
    throw std::invalid_argument(
        "blurlab: motion format must be rg16f, rgba8_offset or "
        "rgba8_polar here (rg32f needs no encoding), not '" +
        format + "'");
  if (!(maxlen > 0.0f) || !std::isfinite(maxlen))
    throw std::invalid_argument("blurlab: maxlen must be a finite number > 0 pixels");
  const TextureFormat want =
      half ? texture_format(PixelType::f16, 2) : texture_format(PixelType::u8, 4);
  if (stored.format().internal != want.internal)
    throw std::invalid_argument("blurlab: the stored texture for " + format + " must be " +
                                (half ? "(H, W, 2) float16" : "(H, W, 4) uint8"));
  for (const Texture* t : {&motion, &decoded})
    if (t->format().internal != GL_RG32F)
      throw std::invalid_argument("blurlab: motion textures must be (H, W, 2) float32");
  auto encode = program(format, true), decode = program(format, false);
  const int gx = (motion.width() + 15) / 16, gy = (motion.height() + 15) / 16;
  // rg16f ignores maxlen, and the compiler drops the unused uniform.
  if (!half) encode->set_uniform("maxlen", {maxlen});
  encode->bind_image(0, motion, GL_READ_ONLY);
  encode->bind_image(1, stored, GL_WRITE_ONLY);
  encode->dispatch(gx, gy, 1);
  if (!half) decode->set_uniform("maxlen", {maxlen});
  decode->bind_image(0, stored, GL_READ_ONLY);
  decode->bind_image(1, decoded, GL_WRITE_ONLY);
  decode->dispatch(gx, gy, 1);
}

}  // namespace blurlab
