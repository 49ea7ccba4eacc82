#include "gl/program.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

#include "gl/context.h"
#include "gl/texture.h"

namespace blurlab {
namespace {

bool is_absolute(const std::string& path) {
  return !path.empty() && path[0] == '/';
}

std::string parent_dir(const std::string& path) {
  const auto slash = path.rfind('/');
  return slash == std::string::npos ? std::string(".") : path.substr(0, slash);
}

bool readable(const std::string& path) {
  return std::ifstream(path).good();
}

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ShaderError("blurlab: shader file not found: " + path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

bool is_identifier(const std::string& s) {
  static const std::regex identifier("[A-Za-z_][A-Za-z0-9_]*");
  return std::regex_match(s, identifier);
}

class SourceBuilder {
 public:
  SourceBuilder(std::string shader_dir) : shader_dir_(std::move(shader_dir)) {}

  ShaderSource build(const std::string& path, const Defines& defines) {
    const std::string main_path = is_absolute(path) ? path : shader_dir_ + "/" + path;
    if (!readable(main_path))
      throw ShaderError("blurlab: shader file not found: " + path + " (looked in " + shader_dir_ +
                        ")");
    std::istringstream lines(read_text(main_path));
    files_.push_back(main_path);
    included_.insert(main_path);
    std::string line;
    int number = 0;
    bool have_version = false;
    std::string body;
    while (std::getline(lines, line)) {
      ++number;
      if (!have_version && line.rfind("#version", 0) == 0) {
        have_version = true;
        out_ += line + "\n";
        for (const auto& [name, value] : defines) {
          if (!is_identifier(name))
            throw std::invalid_argument("blurlab: shader define name '" + name +
                                        "' is not a GLSL identifier");
          if (value.find('\n') != std::string::npos)
            throw std::invalid_argument("blurlab: shader define " + name +
                                        " has a newline in its value");
          out_ += "#define " + name + " " + value + "\n";
        }
        out_ += "#line " + std::to_string(number + 1) + " 0\n";
        continue;
      }
      if (!have_version)
        throw ShaderError("blurlab: " + main_path + ":" + std::to_string(number) +
                          ": the first line must be #version");
      emit_line(line, 0, number);
    }
    return {out_, files_};
  }

 private:
  void emit_line(const std::string& line, int file_index, int number) {
    static const std::regex include_line(R"(^\s*#\s*include\s+\"([^\"]+)\"\s*$)");
    std::smatch m;
    if (!std::regex_match(line, m, include_line)) {
      out_ += line + "\n";
      return;
    }
    const std::string& including = files_[file_index];
    std::string target = parent_dir(including) + "/" + m[1].str();
    if (!readable(target)) target = shader_dir_ + "/" + m[1].str();
    if (!readable(target))
      throw ShaderError("blurlab: " + including + ":" + std::to_string(number) + ": #include \"" +
                        m[1].str() + "\" not found beside the file or in " + shader_dir_);
    // Include-once: the common files define functions, which may not be defined twice.
    if (included_.insert(target).second) {
      if (++depth_ > 32)
        throw ShaderError("blurlab: #include nested more than 32 deep at " + target);
      const int index = static_cast<int>(files_.size());
      files_.push_back(target);
      out_ += "#line 1 " + std::to_string(index) + "\n";
      std::istringstream lines(read_text(target));
      std::string inner;
      int inner_number = 0;
      while (std::getline(lines, inner)) emit_line(inner, index, ++inner_number);
      --depth_;
    }
    out_ += "#line " + std::to_string(number + 1) + " " + std::to_string(file_index) + "\n";
  }

  std::string shader_dir_;
  std::string out_;
  std::vector<std::string> files_;
  std::set<std::string> included_;
  int depth_ = 0;
};

// The info log of a shader or program `id`, read by its kind's getters.
template <typename GetInt, typename GetLog>
std::string info_log(GLuint id, GetInt get_int, GetLog get_log) {
  GLint length = 0;
  get_int(id, GL_INFO_LOG_LENGTH, &length);
  std::string log(std::max(length, 1), '\0');
  get_log(id, length, nullptr, log.data());
  return log;
}

GLuint compile(GLenum stage, const ShaderSource& source) {
  GLuint shader = glCreateShader(stage);
  const char* text = source.text.c_str();
  glShaderSource(shader, 1, &text, nullptr);
  glCompileShader(shader);
  GLint ok = GL_FALSE;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    const std::string log = info_log(shader, glGetShaderiv, glGetShaderInfoLog);
    glDeleteShader(shader);
    throw ShaderError("blurlab: " + source.files[0] + " failed to compile:\n" +
                      translate_shader_log(log.c_str(), source.files));
  }
  return shader;
}

// The image format qualifiers of GLSL 4.50.
bool is_image_format(const std::string& token) {
  static const std::set<std::string> formats = {
      "rgba32f",     "rgba16f",    "rg32f",     "rg16f",     "r11f_g11f_b10f",
      "r32f",        "r16f",       "rgba16",    "rgb10_a2",  "rgba8",
      "rg16",        "rg8",        "r16",       "r8",        "rgba16_snorm",
      "rgba8_snorm", "rg16_snorm", "rg8_snorm", "r16_snorm", "r8_snorm",
      "rgba32i",     "rgba16i",    "rgba8i",    "rg32i",     "rg16i",
      "rg8i",        "r32i",       "r16i",      "r8i",       "rgba32ui",
      "rgba16ui",    "rgb10_a2ui", "rgba8ui",   "rg32ui",    "rg16ui",
      "rg8ui",       "r32ui",      "r16ui",     "r8ui"};
  return formats.count(token) > 0;
}

// `text` without the lines of #ifdef / #ifndef branches that its own #defines (the program's
// defines among them, which come first) rule out. Branches of any other #if count as taken: the
// caller then sees every declaration in them.
std::string active_lines(const std::string& text) {
  static const std::regex directive(R"(^\s*#\s*(\w+)\s*(\w*))");
  std::set<std::string> defined;
  std::vector<int> branches;  // per open #if: 1 taken, 0 ruled out, -1 not known
  auto taken = [&] {
    for (int b : branches)
      if (b == 0) return false;
    return true;
  };
  std::string kept;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    std::smatch m;
    const std::string word = std::regex_search(line, m, directive) ? m[1].str() : "";
    if (word == "ifdef" || word == "ifndef") {
      branches.push_back(taken() ? int(defined.count(m[2].str()) == (word == "ifdef")) : 0);
    } else if (word == "if") {
      branches.push_back(taken() ? -1 : 0);
    } else if ((word == "else" || word == "elif") && !branches.empty()) {
      const int before = branches.back();
      branches.pop_back();  // the enclosing branches decide whether this one can be taken
      const int now = (word == "else" && before >= 0) ? 1 - before : -1;
      branches.push_back(taken() ? now : 0);
    } else if (word == "endif" && !branches.empty()) {
      branches.pop_back();
    } else if (taken()) {
      if (word == "define") defined.insert(m[2].str());
      if (word == "undef") defined.erase(m[2].str());
      kept += line + '\n';
    }
  }
  return kept;
}

// Image name -> format qualifier from the declarations `layout(..., FORMAT) ... uniform ...
// imageXX name;` in the branches of `text` that its #defines take (active_lines). A name whose
// declarations there disagree, or whose format is a macro, gets "".
std::map<std::string, std::string> declared_image_formats(const std::string& source) {
  static const std::regex declaration(
      R"(layout\s*\(([^)]*)\)([\w\s]*)\b[iu]?image[0-9A-Z]\w*\s+(\w+)\s*;)");
  static const std::regex uniform_word(R"(\buniform\b)");
  const std::string text = active_lines(source);
  std::map<std::string, std::string> formats;
  for (std::sregex_iterator it(text.begin(), text.end(), declaration), end; it != end; ++it) {
    const std::string qualifiers = (*it)[2].str();
    if (!std::regex_search(qualifiers, uniform_word)) continue;
    std::string format;
    std::istringstream items((*it)[1].str());
    for (std::string item; std::getline(items, item, ',');) {
      item.erase(0, item.find_first_not_of(" \t\n"));
      item.erase(item.find_last_not_of(" \t\n") + 1);
      if (is_image_format(item)) format = item;
    }
    const std::string name = (*it)[3].str();
    auto [known, inserted] = formats.emplace(name, format);
    if (!inserted && known->second != format) known->second = "";
  }
  return formats;
}

// GLSL names of the uniform types; the samplers' and images' names say which they are.
const std::map<GLenum, std::string>& type_names() {
  static const std::map<GLenum, std::string> names = {
      {GL_FLOAT, "float"},
      {GL_FLOAT_VEC2, "vec2"},
      {GL_FLOAT_VEC3, "vec3"},
      {GL_FLOAT_VEC4, "vec4"},
      {GL_INT, "int"},
      {GL_INT_VEC2, "ivec2"},
      {GL_INT_VEC3, "ivec3"},
      {GL_INT_VEC4, "ivec4"},
      {GL_UNSIGNED_INT, "uint"},
      {GL_UNSIGNED_INT_VEC2, "uvec2"},
      {GL_UNSIGNED_INT_VEC3, "uvec3"},
      {GL_UNSIGNED_INT_VEC4, "uvec4"},
      {GL_BOOL, "bool"},
      {GL_BOOL_VEC2, "bvec2"},
      {GL_BOOL_VEC3, "bvec3"},
      {GL_BOOL_VEC4, "bvec4"},
      {GL_FLOAT_MAT2, "mat2"},
      {GL_FLOAT_MAT3, "mat3"},
      {GL_FLOAT_MAT4, "mat4"},
      {GL_SAMPLER_1D, "sampler1D"},
      {GL_SAMPLER_2D, "sampler2D"},
      {GL_SAMPLER_3D, "sampler3D"},
      {GL_SAMPLER_CUBE, "samplerCube"},
      {GL_SAMPLER_2D_SHADOW, "sampler2DShadow"},
      {GL_SAMPLER_1D_ARRAY, "sampler1DArray"},
      {GL_SAMPLER_2D_ARRAY, "sampler2DArray"},
      {GL_SAMPLER_2D_ARRAY_SHADOW, "sampler2DArrayShadow"},
      {GL_SAMPLER_2D_MULTISAMPLE, "sampler2DMS"},
      {GL_SAMPLER_CUBE_SHADOW, "samplerCubeShadow"},
      {GL_SAMPLER_BUFFER, "samplerBuffer"},
      {GL_SAMPLER_2D_RECT, "sampler2DRect"},
      {GL_SAMPLER_CUBE_MAP_ARRAY, "samplerCubeArray"},
      {GL_INT_SAMPLER_2D, "isampler2D"},
      {GL_INT_SAMPLER_3D, "isampler3D"},
      {GL_INT_SAMPLER_2D_ARRAY, "isampler2DArray"},
      {GL_INT_SAMPLER_BUFFER, "isamplerBuffer"},
      {GL_UNSIGNED_INT_SAMPLER_2D, "usampler2D"},
      {GL_UNSIGNED_INT_SAMPLER_3D, "usampler3D"},
      {GL_UNSIGNED_INT_SAMPLER_2D_ARRAY, "usampler2DArray"},
      {GL_UNSIGNED_INT_SAMPLER_BUFFER, "usamplerBuffer"},
      {GL_IMAGE_1D, "image1D"},
      {GL_IMAGE_2D, "image2D"},
      {GL_IMAGE_3D, "image3D"},
      {GL_IMAGE_CUBE, "imageCube"},
      {GL_IMAGE_BUFFER, "imageBuffer"},
      {GL_IMAGE_2D_ARRAY, "image2DArray"},
      {GL_INT_IMAGE_2D, "iimage2D"},
      {GL_INT_IMAGE_3D, "iimage3D"},
      {GL_INT_IMAGE_2D_ARRAY, "iimage2DArray"},
      {GL_INT_IMAGE_BUFFER, "iimageBuffer"},
      {GL_UNSIGNED_INT_IMAGE_2D, "uimage2D"},
      {GL_UNSIGNED_INT_IMAGE_3D, "uimage3D"},
      {GL_UNSIGNED_INT_IMAGE_2D_ARRAY, "uimage2DArray"},
      {GL_UNSIGNED_INT_IMAGE_BUFFER, "uimageBuffer"},
  };
  return names;
}

}  // namespace

bool is_sampler_type(GLenum type) {
  return glsl_type_name(type).find("sampler") != std::string::npos;
}

bool is_image_type(GLenum type) {
  return glsl_type_name(type).find("image") != std::string::npos;
}

bool is_integer_texture_type(GLenum type) {
  const std::string name = glsl_type_name(type);
  return name.rfind("isampler", 0) == 0 || name.rfind("usampler", 0) == 0 ||
         name.rfind("iimage", 0) == 0 || name.rfind("uimage", 0) == 0;
}

std::string glsl_type_name(GLenum type) {
  auto it = type_names().find(type);
  if (it != type_names().end()) return it->second;
  std::ostringstream hex;
  hex << "0x" << std::hex << type;
  return hex.str();
}

int uniform_components(GLenum type) {
  switch (type) {
    case GL_FLOAT:
    case GL_INT:
    case GL_UNSIGNED_INT:
    case GL_BOOL: return 1;
    case GL_FLOAT_VEC2:
    case GL_INT_VEC2:
    case GL_UNSIGNED_INT_VEC2:
    case GL_BOOL_VEC2: return 2;
    case GL_FLOAT_VEC3:
    case GL_INT_VEC3:
    case GL_UNSIGNED_INT_VEC3:
    case GL_BOOL_VEC3: return 3;
    case GL_FLOAT_VEC4:
    case GL_INT_VEC4:
    case GL_UNSIGNED_INT_VEC4:
    case GL_BOOL_VEC4: return 4;
    case GL_FLOAT_MAT4: return 16;
    default: return 0;
  }
}

ShaderSource load_shader_source(const std::string& path, const std::string& shader_dir,
                                const Defines& defines) {
  return SourceBuilder(shader_dir).build(path, defines);
}

std::string translate_shader_log(const std::string& log, const std::vector<std::string>& files) {
  static const std::regex mesa(R"(^(\d+):(\d+)\((\d+)\):?)");
  static const std::regex nvidia(R"(^(\d+)\((\d+)\)\s*:?)");
  std::istringstream in(log);
  std::string line, out;
  while (std::getline(in, line)) {
    std::smatch m;
    auto file = [&](const std::string& index) {
      const size_t i = std::stoul(index);
      return i < files.size() ? files[i] : "<source " + index + ">";
    };
    if (std::regex_search(line, m, mesa))
      line = file(m[1]) + ":" + m[2].str() + ":" + m[3].str() + ":" + m.suffix().str();
    else if (std::regex_search(line, m, nvidia))
      line = file(m[1]) + ":" + m[2].str() + ":" + m.suffix().str();
    out += line + "\n";
  }
  return out;
}

Program::Program(std::shared_ptr<Context> context, std::string name)
    : context_(std::move(context)), name_(std::move(name)) {}

std::shared_ptr<Program> Program::compute(std::shared_ptr<Context> context, const std::string& path,
                                          const Defines& defines) {
  context->make_current();
  const ShaderSource source = load_shader_source(path, context->shader_dir(), defines);
  std::shared_ptr<Program> program(new Program(context, path));
  GLuint shader = compile(GL_COMPUTE_SHADER, source);
  program->link({shader}, {&source});
  GLint size[3] = {0, 0, 0};
  glGetProgramiv(program->id_, GL_COMPUTE_WORK_GROUP_SIZE, size);
  program->local_size_ = {size[0], size[1], size[2]};
  for (int i = 0; i < 3; ++i)
    glGetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_COUNT, i, &program->max_groups_[i]);
  check_gl("creating a compute program");
  return program;
}

std::shared_ptr<Program> Program::graphics(std::shared_ptr<Context> context,
                                           const std::string& vertex_path,
                                           const std::string& fragment_path,
                                           const Defines& defines) {
  context->make_current();
  const ShaderSource vs = load_shader_source(vertex_path, context->shader_dir(), defines);
  const ShaderSource fs = load_shader_source(fragment_path, context->shader_dir(), defines);
  std::shared_ptr<Program> program(new Program(context, vertex_path + " + " + fragment_path));
  GLuint vertex = compile(GL_VERTEX_SHADER, vs);
  GLuint fragment = 0;
  try {
    fragment = compile(GL_FRAGMENT_SHADER, fs);
  } catch (...) {
    glDeleteShader(vertex);
    throw;
  }
  program->link({vertex, fragment}, {&vs, &fs});
  check_gl("creating a raster program");
  return program;
}

void Program::link(const std::vector<GLuint>& shaders,
                   const std::vector<const ShaderSource*>& sources) {
  id_ = glCreateProgram();
  context_->track("program", +1);
  for (GLuint s : shaders) glAttachShader(id_, s);
  glLinkProgram(id_);
  for (GLuint s : shaders) glDeleteShader(s);  // the program keeps them while it lives
  GLint ok = GL_FALSE;
  glGetProgramiv(id_, GL_LINK_STATUS, &ok);
  if (!ok) {
    const std::string log = info_log(id_, glGetProgramiv, glGetProgramInfoLog);
    throw ShaderError("blurlab: " + name_ + " failed to link:\n" + log);
  }
  std::map<std::string, std::string> formats;
  for (const ShaderSource* source : sources)
    for (auto& [image, format] : declared_image_formats(source->text))
      formats.emplace(image, format);
  auto resource_name = [&](GLenum interface, GLint index, GLint length) {
    std::string name(length, '\0');
    glGetProgramResourceName(id_, interface, index, length, nullptr, name.data());
    name.resize(name.find('\0') == std::string::npos ? name.size() : name.find('\0'));
    return name;
  };
  GLint count = 0;
  glGetProgramInterfaceiv(id_, GL_UNIFORM, GL_ACTIVE_RESOURCES, &count);
  for (GLint i = 0; i < count; ++i) {
    const GLenum props[] = {GL_TYPE, GL_BLOCK_INDEX, GL_NAME_LENGTH, GL_LOCATION, GL_ARRAY_SIZE};
    GLint values[5];
    glGetProgramResourceiv(id_, GL_UNIFORM, i, 5, props, 5, nullptr, values);
    if (values[1] != -1) continue;  // members of uniform blocks are set through their buffer
    std::string uniform = resource_name(GL_UNIFORM, i, values[2]);
    if (uniform.size() > 3 && uniform.compare(uniform.size() - 3, 3, "[0]") == 0)
      uniform.resize(uniform.size() - 3);
    UniformInfo info;
    info.type = static_cast<GLenum>(values[0]);
    info.location = values[3];
    info.array_size = std::max(values[4], 1);
    if (is_sampler_type(info.type) || is_image_type(info.type)) {
      // Set by layout(binding = N), or 0 without one.
      glGetUniformiv(id_, info.location, &info.unit);
      if (is_image_type(info.type) && formats.count(uniform)) info.format = formats[uniform];
    }
    uniforms_[uniform] = info;
  }
  glGetProgramInterfaceiv(id_, GL_PROGRAM_OUTPUT, GL_ACTIVE_RESOURCES, &count);
  for (GLint i = 0; i < count; ++i) {
    const GLenum props[] = {GL_NAME_LENGTH, GL_TYPE, GL_LOCATION};
    GLint values[3];
    glGetProgramResourceiv(id_, GL_PROGRAM_OUTPUT, i, 3, props, 3, nullptr, values);
    outputs_[resource_name(GL_PROGRAM_OUTPUT, i, values[0])] = {GLenum(values[1]), values[2]};
  }
}

Program::~Program() {
  if (id_) context_->release("program", [id = id_] { glDeleteProgram(id); });
}

void Program::set_uniform(const std::string& name, const std::vector<double>& v) {
  const PreparedUniform u = prepare_uniform(name, v);
  context_->make_current();
  apply_uniform(u);
  check_gl(("setting uniform " + name).c_str());
}

PreparedUniform Program::prepare_uniform(const std::string& name,
                                         const std::vector<double>& v) const {
  auto it = uniforms_.find(name);
  if (it == uniforms_.end()) {
    std::string known;
    for (const auto& [n, u] : uniforms_)
      if (uniform_components(u.type)) known += (known.empty() ? "" : ", ") + n;
    throw std::invalid_argument("blurlab: " + name_ + " has no uniform '" + name +
                                "'; its uniforms are: " + (known.empty() ? "(none)" : known));
  }
  const UniformInfo& u = it->second;
  const int components = uniform_components(u.type);
  if (components == 0)
    throw std::invalid_argument("blurlab: " + name_ + ": uniform '" + name + "' is a " +
                                glsl_type_name(u.type) +
                                ", which set_uniform does not set; bind textures and images by "
                                "unit");
  const size_t count = size_t(components) * u.array_size;
  if (v.size() != count)
    throw std::invalid_argument("blurlab: " + name_ + ": uniform '" + name + "' takes " +
                                std::to_string(count) + " value(s), got " +
                                std::to_string(v.size()));
  // Converting a double outside an integer type's range is undefined behaviour: refuse it.
  auto whole = [&](double x, double low, double high, const char* what) {
    if (!(x >= low && x <= high) || x != std::floor(x))
      throw std::invalid_argument("blurlab: " + name_ + ": uniform '" + name + "' takes " + what +
                                  ", got " + std::to_string(x));
    return x;
  };
  PreparedUniform p;
  p.location = u.location;
  p.count = u.array_size;
  p.components = components;
  switch (u.type) {
    case GL_FLOAT:
    case GL_FLOAT_VEC2:
    case GL_FLOAT_VEC3:
    case GL_FLOAT_VEC4:
    case GL_FLOAT_MAT4:
      p.kind = PreparedUniform::Kind::floats;
      p.floats.assign(v.begin(), v.end());
      break;
    case GL_UNSIGNED_INT:
    case GL_UNSIGNED_INT_VEC2:
    case GL_UNSIGNED_INT_VEC3:
    case GL_UNSIGNED_INT_VEC4:
      p.kind = PreparedUniform::Kind::uints;
      for (double x : v)
        p.uints.push_back(
            static_cast<GLuint>(whole(x, 0.0, 4294967295.0, "integers in 0..2^32-1")));
      break;
    default:  // int and bool, which GL sets through the int calls
      p.kind = PreparedUniform::Kind::ints;
      for (double x : v)
        p.ints.push_back(
            static_cast<GLint>(whole(x, -2147483648.0, 2147483647.0, "integers in -2^31..2^31-1")));
      break;
  }
  return p;
}

namespace {

// GL's setters of 1 to 4 components of one element type: the one for `components` sets `count`
// elements at `location` of `program` (none for another count).
template <typename T, typename Setter>
void set_vectors(const std::array<Setter, 4>& setters, GLuint program, GLint location,
                 GLsizei count, int components, const T* values) {
  if (components >= 1 && components <= 4) setters[components - 1](program, location, count, values);
}

}  // namespace

void Program::apply_uniform(const PreparedUniform& u) const {
  const GLint loc = u.location;
  const GLsizei n = u.count;
  const int c = u.components;
  switch (u.kind) {
    case PreparedUniform::Kind::floats:
      // Row by row, as NumPy holds matrices; GL's default is column by column.
      if (c == 16) glProgramUniformMatrix4fv(id_, loc, n, GL_TRUE, u.floats.data());
      set_vectors(std::array{glProgramUniform1fv, glProgramUniform2fv, glProgramUniform3fv,
                             glProgramUniform4fv},
                  id_, loc, n, c, u.floats.data());
      break;
    case PreparedUniform::Kind::uints:
      set_vectors(std::array{glProgramUniform1uiv, glProgramUniform2uiv, glProgramUniform3uiv,
                             glProgramUniform4uiv},
                  id_, loc, n, c, u.uints.data());
      break;
    case PreparedUniform::Kind::ints:
      set_vectors(std::array{glProgramUniform1iv, glProgramUniform2iv, glProgramUniform3iv,
                             glProgramUniform4iv},
                  id_, loc, n, c, u.ints.data());
      break;
  }
}

void Program::bind_image(int unit, const Texture& texture, GLenum access) {
  if (texture.format().image_layout.empty())
    throw std::invalid_argument(
        "blurlab: a 3-channel texture cannot be bound as an image "
        "(image load/store has formats of 1, 2 and 4 channels)");
  context_->make_current();
  glBindImageTexture(unit, texture.id(), 0, GL_FALSE, 0, access, texture.format().internal);
  check_gl("binding an image");
}

void Program::bind_texture(int unit, const Texture& texture) {
  context_->make_current();
  glBindTextureUnit(unit, texture.id());
  check_gl("binding a texture");
}

void Program::dispatch(int groups_x, int groups_y, int groups_z) {
  if (local_size_[0] == 0)
    throw std::invalid_argument("blurlab: " + name_ + " is not a compute program");
  context_->make_current();
  const int groups[3] = {groups_x, groups_y, groups_z};
  for (int i = 0; i < 3; ++i)
    if (groups[i] < 1 || groups[i] > max_groups_[i])
      throw std::invalid_argument("blurlab: work-group count " + std::to_string(groups[i]) +
                                  " along axis " + std::to_string(i) + " is outside 1.." +
                                  std::to_string(max_groups_[i]));
  glUseProgram(id_);
  glDispatchCompute(groups_x, groups_y, groups_z);
  // Later passes, downloads and draws read what this pass wrote.
  glMemoryBarrier(GL_ALL_BARRIER_BITS);
  check_gl(("dispatching " + name_).c_str());
  context_->after_pass(name_);
}

void Program::dispatch_indirect(GLuint buffer, GLintptr offset) {
  if (local_size_[0] == 0)
    throw std::invalid_argument("blurlab: " + name_ + " is not a compute program");
  context_->make_current();
  glUseProgram(id_);
  glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, buffer);
  glDispatchComputeIndirect(offset);
  glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, 0);
  glMemoryBarrier(GL_ALL_BARRIER_BITS);
  check_gl(("dispatching " + name_ + " indirectly").c_str());
  context_->after_pass(name_);
}

}  // namespace blurlab
