#include "passes/shader_pass.h"

#include <set>
#include <stdexcept>

#include "gl/context.h"
#include "gl/texture.h"

namespace blurlab {
namespace {

std::string joined(const std::vector<std::string>& names) {
  std::string list;
  for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
  return list.empty() ? "(none)" : list;
}

// The program's uniforms of one kind (samplers or images), by name.
std::vector<std::string> names_of(const Program& p, bool (*kind)(GLenum)) {
  std::vector<std::string> names;
  for (const auto& [name, u] : p.uniforms())
    if (kind(u.type)) names.push_back(name);
  return names;
}

// The units of `given` into `units` and whether each reads integers into `integer`, in the
// order given; each must be a uniform of `kind`, and every such uniform must be given, or the
// shader would read whatever an earlier pass left at its unit.
void units_of(const Program& p, const NamedTextures& given, bool (*kind)(GLenum), const char* what,
              std::vector<int>& units, std::vector<bool>& integer) {
  const std::vector<std::string> known = names_of(p, kind);
  std::set<std::string> seen;
  for (const auto& [name, texture] : given) {
    auto it = p.uniforms().find(name);
    if (it == p.uniforms().end() || !kind(it->second.type))
      throw std::invalid_argument("blurlab: " + p.name() + " has no " + what + " '" + name +
                                  "'; its " + what + "s are: " + joined(known));
    units.push_back(it->second.unit);
    integer.push_back(is_integer_texture_type(it->second.type));
    seen.insert(name);
  }
  std::vector<std::string> missing;
  for (const std::string& name : known)
    if (!seen.count(name)) missing.push_back(name);
  if (!missing.empty())
    throw std::invalid_argument("blurlab: " + p.name() + ": no texture given for its " + what +
                                "(s) " + joined(missing));
}

}  // namespace

ShaderPass::ShaderPass(std::shared_ptr<Context> context, std::string shader, Defines defines)
    : PostProcessPass(std::move(context), std::move(shader), std::move(defines)) {}

const ShaderPass::Units& ShaderPass::units(const Program& p, const NamedTextures& inputs,
                                           const NamedTextures& outputs, Backend backend) {
  std::string names;
  for (const auto& [name, texture] : inputs) names += name + ',';
  names += '|';
  for (const auto& [name, texture] : outputs) names += name + ',';
  auto found = units_.find({&p, names});
  if (found != units_.end()) return found->second;
  if (outputs.empty())
    throw std::invalid_argument("blurlab: " + p.name() + " needs at least one output");
  Units u;
  units_of(p, inputs, is_sampler_type, "sampler", u.samplers, u.integer_samplers);
  if (backend == Backend::compute) {
    units_of(p, outputs, is_image_type, "image", u.images, u.integer_images);
  } else {
    std::vector<std::string> known;
    for (const auto& [name, output] : p.outputs()) known.push_back(name);
    if (outputs.size() != 1 || !p.outputs().count(outputs.front().first))
      throw std::invalid_argument("blurlab: " + p.name() +
                                  " draws one output, its fragment output: " + joined(known));
  }
  return units_.emplace(std::make_pair(&p, names), std::move(u)).first->second;
}

void ShaderPass::check_kinds(const Program& p, const Units& u, const NamedTextures& inputs,
                             const NamedTextures& outputs) const {
  auto check = [&](const NamedTextures& given, const std::vector<bool>& integer, const char* what) {
    for (size_t i = 0; i < integer.size(); ++i) {
      const bool uint_texture = given[i].second->format().type == PixelType::u32;
      if (uint_texture != integer[i])
        throw std::invalid_argument(
            "blurlab: " + p.name() + ": " + what + " '" + given[i].first + "' reads " +
            (integer[i] ? "integers" : "floats") + ", but its texture is " +
            (uint_texture ? "uint32" : "not an integer texture") + "; give it a " +
            (integer[i] ? "uint32" : "uint8, float16 or float32") + " texture");
    }
  };
  check(inputs, u.integer_samplers, "sampler");
  check(outputs, u.integer_images, "image");
}

void ShaderPass::run(const NamedTextures& inputs, const NamedTextures& outputs,
                     const UniformValues& uniforms, Backend backend, bool group_per_texel) {
  Program& p = program(backend);
  const Units& u = units(p, inputs, outputs, backend);
  check_kinds(p, u, inputs, outputs);
  std::vector<TextureUnitBinding> textures;
  textures.reserve(inputs.size());
  for (size_t i = 0; i < inputs.size(); ++i) textures.push_back({u.samplers[i], inputs[i].second});
  std::vector<ImageUnitBinding> images;
  images.reserve(u.images.size());
  // Read-write suits every declaration; see shader_pass.h.
  for (size_t i = 0; i < u.images.size(); ++i)
    images.push_back({u.images[i], outputs[i].second, GL_READ_WRITE});
  for (const auto& [name, values] : uniforms) p.set_uniform(name, values);
  run_bound(backend, textures, images, *outputs.front().second, group_per_texel);
}

void ShaderPass::run_indirect(const NamedTextures& inputs, const NamedTextures& outputs,
                              const UniformValues& uniforms, const Texture& counts, int slot) {
  const TextureFormat& f = counts.format();
  if (f.type != PixelType::u32 || f.channels != 1 || counts.height() != 1 ||
      counts.width() % 4 != 0)
    throw std::invalid_argument("blurlab: " + shader() +
                                ": the work-group counts must be a uint32 texture of one row "
                                "and 4 texels per list");
  const int lists = counts.width() / 4;
  if (slot < 0 || slot >= lists)
    throw std::invalid_argument("blurlab: " + shader() + ": list " + std::to_string(slot) +
                                " is outside 0.." + std::to_string(lists - 1));
  Program& p = program(Backend::compute);
  const Units& u = units(p, inputs, outputs, Backend::compute);
  check_kinds(p, u, inputs, outputs);
  for (size_t i = 0; i < inputs.size(); ++i) p.bind_texture(u.samplers[i], *inputs[i].second);
  for (size_t i = 0; i < u.images.size(); ++i)
    p.bind_image(u.images[i], *outputs[i].second, GL_READ_WRITE);  // as run() binds them
  for (const auto& [name, values] : uniforms) p.set_uniform(name, values);
  const size_t bytes = size_t(counts.width()) * sizeof(GLuint);
  if (!indirect_ || indirect_->size() != bytes)
    indirect_ = std::make_unique<Buffer>(context_.get(), bytes, Buffer::Usage::storage);
  // The counts, GPU to GPU: the texture's row read into the buffer as a pixel-pack target.
  context_->make_current();
  glBindBuffer(GL_PIXEL_PACK_BUFFER, indirect_->id());
  glGetTextureImage(counts.id(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT, GLsizei(bytes), nullptr);
  glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
  glMemoryBarrier(GL_COMMAND_BARRIER_BIT | GL_PIXEL_BUFFER_BARRIER_BIT);
  check_gl(("copying the work-group counts of " + shader()).c_str());
  p.dispatch_indirect(indirect_->id(), GLintptr(slot) * 4 * sizeof(GLuint));
}

ResolvedRun ShaderPass::resolve(const NamedTextures& inputs, const NamedTextures& outputs,
                                const UniformValues& uniforms, Backend backend,
                                bool group_per_texel, const std::vector<const Texture*>& textures) {
  ResolvedRun r;
  Program& p = program(backend);
  const Units& u = units(p, inputs, outputs, backend);
  check_kinds(p, u, inputs, outputs);
  auto index_of = [&](const Texture* t) {
    for (size_t i = 0; i < textures.size(); ++i)
      if (textures[i] == t) return i;
    throw std::invalid_argument("blurlab: " + shader() +
                                ": a texture of the run is not among the plan's textures");
  };
  r.program = &p;
  r.backend = backend;
  for (size_t i = 0; i < inputs.size(); ++i)
    r.textures.emplace_back(u.samplers[i], index_of(inputs[i].second));
  for (size_t i = 0; i < u.images.size(); ++i) {
    if (outputs[i].second->format().image_layout.empty())
      throw std::invalid_argument(
          "blurlab: a 3-channel texture cannot be bound as an image "
          "(image load/store has formats of 1, 2 and 4 channels)");
    r.images.emplace_back(u.images[i], index_of(outputs[i].second));
  }
  r.target = index_of(outputs.front().second);
  for (const auto& [name, values] : uniforms) r.uniforms.push_back(p.prepare_uniform(name, values));
  if (backend == Backend::compute) {
    const Texture& target = *outputs.front().second;
    const auto local = p.local_size();
    r.groups = group_per_texel ? std::array<int, 3>{target.width(), target.height(), 1}
                               : std::array<int, 3>{(target.width() + local[0] - 1) / local[0],
                                                    (target.height() + local[1] - 1) / local[1], 1};
    for (int i = 0; i < 3; ++i)
      if (r.groups[i] < 1 || r.groups[i] > p.max_groups()[i])
        throw std::invalid_argument("blurlab: work-group count " + std::to_string(r.groups[i]) +
                                    " along axis " + std::to_string(i) + " is outside 1.." +
                                    std::to_string(p.max_groups()[i]));
  }
  return r;
}

ShaderReflection ShaderPass::reflect(Backend backend) {
  const Program& p = program(backend);
  ShaderReflection r;
  for (const auto& [name, u] : p.uniforms()) {
    const std::string type = glsl_type_name(u.type);
    if (is_sampler_type(u.type))
      r.samplers[name] = {type, u.unit, ""};
    else if (is_image_type(u.type))
      r.images[name] = {type, u.unit, u.format};
    else
      r.uniforms[name] = {type, uniform_components(u.type) * u.array_size};
  }
  for (const auto& [name, output] : p.outputs())
    r.fragment_outputs[name] = {glsl_type_name(output.type), output.location, ""};
  return r;
}

}  // namespace blurlab
