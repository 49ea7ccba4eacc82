#include "gl/program.h"

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

GLuint compile(GLenum stage, const ShaderSource& source) {
  GLuint shader = glCreateShader(stage);
  const char* text = source.text.c_str();
  glShaderSource(shader, 1, &text, nullptr);
  glCompileShader(shader);
  GLint ok = GL_FALSE;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    GLint length = 0;
    glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
    std::string log(std::max(length, 1), '\0');
    glGetShaderInfoLog(shader, length, nullptr, log.data());
    glDeleteShader(shader);
    throw ShaderError("blurlab: " + source.files[0] + " failed to compile:\n" +
                      translate_shader_log(log.c_str(), source.files));
  }
  return shader;
}

}  // namespace

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
  program->link({shader});
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
  program->link({vertex, fragment});
  check_gl("creating a raster program");
  return program;
}

void Program::link(const std::vector<GLuint>& shaders) {
  id_ = glCreateProgram();
  context_->track("program", +1);
  for (GLuint s : shaders) glAttachShader(id_, s);
  glLinkProgram(id_);
  for (GLuint s : shaders) glDeleteShader(s);  // the program keeps them while it lives
  GLint ok = GL_FALSE;
  glGetProgramiv(id_, GL_LINK_STATUS, &ok);
  if (!ok) {
    GLint length = 0;
    glGetProgramiv(id_, GL_INFO_LOG_LENGTH, &length);
    std::string log(std::max(length, 1), '\0');
    glGetProgramInfoLog(id_, length, nullptr, log.data());
    throw ShaderError("blurlab: " + name_ + " failed to link:\n" + log);
  }
  GLint count = 0;
  glGetProgramInterfaceiv(id_, GL_UNIFORM, GL_ACTIVE_RESOURCES, &count);
  for (GLint i = 0; i < count; ++i) {
    const GLenum props[] = {GL_TYPE, GL_BLOCK_INDEX, GL_NAME_LENGTH};
    GLint values[3];
    glGetProgramResourceiv(id_, GL_UNIFORM, i, 3, props, 3, nullptr, values);
    if (values[1] != -1) continue;  // members of uniform blocks are set through their buffer
    std::string uniform(values[2], '\0');
    glGetProgramResourceName(id_, GL_UNIFORM, i, values[2], nullptr, uniform.data());
    uniform.resize(uniform.find('\0') == std::string::npos ? uniform.size() : uniform.find('\0'));
    uniforms_[uniform] = static_cast<GLenum>(values[0]);
  }
}

Program::~Program() {
  if (id_) context_->release("program", [id = id_] { glDeleteProgram(id); });
}

void Program::set_uniform(const std::string& name, const std::vector<double>& v) {
  auto it = uniforms_.find(name);
  if (it == uniforms_.end()) {
    std::string known;
    for (const auto& [n, t] : uniforms_) known += (known.empty() ? "" : ", ") + n;
    throw std::invalid_argument("blurlab: " + name_ + " has no uniform '" + name +
                                "'; its uniforms are: " + (known.empty() ? "(none)" : known));
  }
  context_->make_current();
  const GLint loc = glGetUniformLocation(id_, name.c_str());
  auto need = [&](size_t n) {
    if (v.size() != n)
      throw std::invalid_argument("blurlab: uniform '" + name + "' takes " + std::to_string(n) +
                                  " value(s), got " + std::to_string(v.size()));
  };
  auto f = [&](size_t i) { return static_cast<float>(v[i]); };
  // Converting a double outside an integer type's range is undefined behaviour: refuse it.
  auto whole = [&](size_t i, double low, double high, const char* what) {
    if (!(v[i] >= low && v[i] <= high) || v[i] != std::floor(v[i]))
      throw std::invalid_argument("blurlab: uniform '" + name + "' takes " + what + ", got " +
                                  std::to_string(v[i]));
    return v[i];
  };
  auto i32 = [&](size_t i) {
    return static_cast<GLint>(whole(i, -2147483648.0, 2147483647.0, "integers in -2^31..2^31-1"));
  };
  auto u32 = [&](size_t i) {
    return static_cast<GLuint>(whole(i, 0.0, 4294967295.0, "integers in 0..2^32-1"));
  };
  switch (it->second) {
    case GL_FLOAT:
      need(1);
      glProgramUniform1f(id_, loc, f(0));
      break;
    case GL_FLOAT_VEC2:
      need(2);
      glProgramUniform2f(id_, loc, f(0), f(1));
      break;
    case GL_FLOAT_VEC3:
      need(3);
      glProgramUniform3f(id_, loc, f(0), f(1), f(2));
      break;
    case GL_FLOAT_VEC4:
      need(4);
      glProgramUniform4f(id_, loc, f(0), f(1), f(2), f(3));
      break;
    case GL_INT:
    case GL_BOOL:
      need(1);
      glProgramUniform1i(id_, loc, i32(0));
      break;
    case GL_INT_VEC2:
      need(2);
      glProgramUniform2i(id_, loc, i32(0), i32(1));
      break;
    case GL_INT_VEC3:
      need(3);
      glProgramUniform3i(id_, loc, i32(0), i32(1), i32(2));
      break;
    case GL_INT_VEC4:
      need(4);
      glProgramUniform4i(id_, loc, i32(0), i32(1), i32(2), i32(3));
      break;
    case GL_UNSIGNED_INT:
      need(1);
      glProgramUniform1ui(id_, loc, u32(0));
      break;
    case GL_UNSIGNED_INT_VEC2:
      need(2);
      glProgramUniform2ui(id_, loc, u32(0), u32(1));
      break;
    default:
      throw std::invalid_argument("blurlab: uniform '" + name +
                                  "' is of a type that set_uniform does not set (a sampler, "
                                  "image or matrix); bind textures and images by unit");
  }
  check_gl(("setting uniform " + name).c_str());
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
}

void Program::dispatch_indirect(GLuint buffer, GLintptr offset) {
  if (local_size_[0] == 0)
    throw std::invalid_argument("blurlab: " + name_ + " is not a compute program");
  if (offset % 4 != 0)
    throw std::invalid_argument("blurlab: an indirect dispatch offset must be a multiple of 4");
  context_->make_current();
  glUseProgram(id_);
  glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, buffer);
  glDispatchComputeIndirect(offset);
  glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, 0);
  glMemoryBarrier(GL_ALL_BARRIER_BITS);
  check_gl(("dispatching " + name_ + " indirectly").c_str());
}

}  // namespace blurlab
