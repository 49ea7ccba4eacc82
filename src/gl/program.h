// GLSL programs loaded from files. `#include "file"` is resolved first beside the including file,
// then in the shader folder; `#define`s are injected after `#version`. Every file gets a source
// string number through `#line`, so a compile error is reported as file:line with the driver's
// log.
#pragma once

#include <array>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "gl/gl.h"

namespace blurlab {

class Context;
class Texture;

using Defines = std::vector<std::pair<std::string, std::string>>;

struct ShaderSource {
  std::string text;                // what is handed to glShaderSource
  std::vector<std::string> files;  // source string number -> file path
};

// Throws ShaderError if a file is missing or includes itself.
ShaderSource load_shader_source(const std::string& path, const std::string& shader_dir,
                                const Defines& defines);

// Rewrites "N:L(C)" (Mesa) and "N(L)" (NVIDIA) prefixes of a driver log into "file:L".
std::string translate_shader_log(const std::string& log, const std::vector<std::string>& files);

// An active uniform outside uniform blocks, as the linked program reports it. Arrays go by their
// name without "[0]".
struct UniformInfo {
  GLenum type = 0;
  GLint location = -1;
  int array_size = 1;
  // Samplers and images: the unit that layout(binding = N) gave them; -1 for other types.
  int unit = -1;
  // Images: the declaration's format qualifier (e.g. "rgba32f"). GL does not report it, so it is
  // read from the source: "" where it is a macro or differs between #if branches.
  std::string format;
};

// A fragment shader's `out` variable: its type and color attachment.
struct FragmentOutput {
  GLenum type = 0;
  int location = 0;
};

bool is_sampler_type(GLenum type);
bool is_image_type(GLenum type);
// Whether a sampler or image type reads integers (isampler2D, usampler2D, uimage2D...).
bool is_integer_texture_type(GLenum type);
// The GLSL name of a uniform type ("vec2", "mat4", "sampler2D"), or its GL enum in hex.
std::string glsl_type_name(GLenum type);
// Values that Program::set_uniform takes per array element: 1..4 for scalars and vectors, 16 for
// mat4; 0 for the types it does not set.
int uniform_components(GLenum type);

// A uniform's value checked and converted to the type GL takes, ready to upload: what
// Program::set_uniform sends, kept so that a DispatchPlan uploads it again without the checks.
struct PreparedUniform {
  enum class Kind { floats, ints, uints };
  Kind kind = Kind::floats;
  GLint location = -1;
  GLsizei count = 1;   // array elements
  int components = 1;  // per element: 1..4, 16 for mat4
  std::vector<float> floats;
  std::vector<GLint> ints;
  std::vector<GLuint> uints;
};

class Program : NotCopyable {
 public:
  // A compute program from one file.
  static std::shared_ptr<Program> compute(std::shared_ptr<Context> context, const std::string& path,
                                          const Defines& defines);
  // A raster program from a vertex and a fragment file.
  static std::shared_ptr<Program> graphics(std::shared_ptr<Context> context,
                                           const std::string& vertex_path,
                                           const std::string& fragment_path,
                                           const Defines& defines);
  ~Program();

  GLuint id() const { return id_; }
  const std::string& name() const { return name_; }
  // The compute work-group size declared by the shader (0s for raster programs).
  std::array<int, 3> local_size() const { return local_size_; }
  // Active uniforms by name.
  const std::map<std::string, UniformInfo>& uniforms() const { return uniforms_; }
  // A raster program's fragment outputs (none for compute programs).
  const std::map<std::string, FragmentOutput>& outputs() const { return outputs_; }

  // Sets a uniform of scalar or vector float, int, uint or bool type, mat4, or an array of those
  // from `values`: all elements, one after the other; a mat4 as 16 values row by row (NumPy's
  // order), uploaded transposed. Throws std::invalid_argument naming the program and the uniform
  // if it does not exist or the count does not match. Integers must be whole and in range, as
  // converting others is undefined behaviour.
  void set_uniform(const std::string& name, const std::vector<double>& values);
  // set_uniform in two steps: the checks and conversion (throwing as set_uniform does), and the
  // upload alone (the context current; GL errors left for the caller to check).
  PreparedUniform prepare_uniform(const std::string& name, const std::vector<double>& values) const;
  void apply_uniform(const PreparedUniform& uniform) const;
  void bind_image(int unit, const Texture& texture, GLenum access);
  void bind_texture(int unit, const Texture& texture);
  // Runs the compute program over groups.x × groups.y × groups.z work groups.
  void dispatch(int groups_x, int groups_y, int groups_z);
  // Runs it over the work-group counts that the GPU finds at byte `offset` of `buffer`
  // (glDispatchComputeIndirect: three uints), as written there by earlier passes.
  void dispatch_indirect(GLuint buffer, GLintptr offset);
  // The largest work-group count along each axis (GL_MAX_COMPUTE_WORK_GROUP_COUNT).
  std::array<int, 3> max_groups() const { return max_groups_; }

 private:
  Program(std::shared_ptr<Context> context, std::string name);
  void link(const std::vector<GLuint>& shaders, const std::vector<const ShaderSource*>& sources);
  std::shared_ptr<Context> context_;
  std::string name_;
  GLuint id_ = 0;
  std::array<int, 3> local_size_{0, 0, 0};
  std::array<int, 3> max_groups_{0, 0, 0};  // GL_MAX_COMPUTE_WORK_GROUP_COUNT, read once
  std::map<std::string, UniformInfo> uniforms_;
  std::map<std::string, FragmentOutput> outputs_;
};

}  // namespace blurlab
