// Motion-vector storage formats, docs/spec.md §2: encodes rg32f motion into rg16f, rgba8_offset or
// rgba8_polar and decodes it back, so a study can see what a method reading that format gets.
// Shader: shaders/passes/motion_encoding.comp; NumPy twin: blurlab.twins.motion_encoding.
#pragma once

#include <map>
#include <memory>
#include <string>

namespace blurlab {

class Context;
class Program;
class Texture;

class MotionEncodingPass {
 public:
  explicit MotionEncodingPass(std::shared_ptr<Context> context);

  // motion (rg32f) -> stored (format's texture) -> decoded (rg32f). `format` is one of
  // "rg16f", "rgba8_offset", "rgba8_polar"; maxlen > 0 (pixels) scales the 8-bit formats.
  void run(const Texture& motion, const Texture& stored, const Texture& decoded,
           const std::string& format, float maxlen);

 private:
  std::shared_ptr<Program> program(const std::string& format, bool encode);
  std::shared_ptr<Context> context_;
  std::map<std::string, std::shared_ptr<Program>> programs_;
};

}  // namespace blurlab
