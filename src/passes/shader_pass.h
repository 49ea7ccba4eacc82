// A post-process pass known only by its shader (issue "the house", after Falcor's
// RenderPass::reflect()): its inputs, outputs and parameters are the shader's own samplers, images
// and uniforms, found by name in the linked program. One generic pass instead of a class per
// shader: Python checks a pass's parameters once against reflect() and hands over plain values,
// which are not checked again here.
//
// Units come from the shader: each sampler and image is bound at the unit its
// `layout(binding = N)` gave it. Outputs of the compute backend are bound GL_READ_WRITE, whatever
// the shader declares: valid for writeonly, readonly and read-modify-write images alike
// (accumulate.comp's `sum`), and the same bits as the dedicated passes' GL_WRITE_ONLY
// (tests/test_shader_pass.py). Inputs are bound with the texture's own sampler state (nearest,
// clamp to edge); the post-process shaders read them with texelFetch, which ignores it.
#pragma once

#include <array>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "gl/buffer.h"
#include "passes/post_process.h"

namespace blurlab {

// Textures by name, in the caller's order (the first output sets the dispatch's size).
using NamedTextures = std::vector<std::pair<std::string, const Texture*>>;
// Uniform values by name, as Program::set_uniform takes them (a mat4 row by row).
using UniformValues = std::map<std::string, std::vector<double>>;

// One run of a ShaderPass resolved to what GL needs: the program, the units its textures and
// images go to (indices into the caller's list of textures), its uniforms converted, and the
// work-group counts. DispatchPlan replays it.
struct ResolvedRun {
  Program* program = nullptr;
  Backend backend = Backend::compute;
  std::vector<std::pair<int, size_t>> textures;  // (texture unit, texture index)
  std::vector<std::pair<int, size_t>> images;    // (image unit, texture index)
  size_t target = 0;                             // texture index of the first output
  std::vector<PreparedUniform> uniforms;
  std::array<int, 3> groups{1, 1, 1};  // compute work groups
};

// What a ShaderPass takes on one backend, by name.
struct ShaderReflection {
  struct Binding {
    std::string type;    // GLSL type: "sampler2D", "image2D", "vec4"
    int unit = 0;        // texture or image unit; a fragment output's color attachment
    std::string format;  // images: the declared format ("rgba32f"), "" if unknown
  };
  struct Value {
    std::string type;  // "float", "uint", "mat4", ...
    int count = 0;     // values that run() takes for it: components x array size
  };
  std::map<std::string, Binding> samplers;
  std::map<std::string, Binding> images;
  std::map<std::string, Binding> fragment_outputs;
  std::map<std::string, Value> uniforms;
};

class ShaderPass : public PostProcessPass {
 public:
  // `shader`: relative to the shader folder, compiled with STAGE_COMPUTE or STAGE_FRAGMENT and
  // `defines`.
  ShaderPass(std::shared_ptr<Context> context, std::string shader, Defines defines = {});

  // Runs the shader once per texel of the first output. `inputs` must name every sampler of the
  // program; `outputs` every image (compute), or the one fragment output (fragment: drawn as the
  // framebuffer's color attachment). Throws std::invalid_argument naming the shader and the name
  // that is unknown or missing, and (through Program::set_uniform) a uniform whose name or value
  // count is wrong.
  void run(const NamedTextures& inputs, const NamedTextures& outputs, const UniformValues& uniforms,
           Backend backend, bool group_per_texel = false);

  // run() dispatched indirectly (glDispatchComputeIndirect, compute only): the work-group counts
  // are list `slot` of `counts`, an R32UI texture of 4 texels per list, (x, y, z, unused) from
  // left to right, as a classify pass wrote them on the GPU (python/blurlab/methods/tiles.py). The
  // counts are copied on the GPU into the pass's indirect buffer; nothing comes back to the host.
  // The shader finds its list by its own uniforms and gl_WorkGroupID. Throws
  // std::invalid_argument for a `counts` texture of another kind or a slot outside it.
  void run_indirect(const NamedTextures& inputs, const NamedTextures& outputs,
                    const UniformValues& uniforms, const Texture& counts, int slot);

  // What run() would do with these arguments, checked as run() checks them, without running it:
  // every texture named must be one of `textures`, and the result refers to them by index.
  ResolvedRun resolve(const NamedTextures& inputs, const NamedTextures& outputs,
                      const UniformValues& uniforms, Backend backend, bool group_per_texel,
                      const std::vector<const Texture*>& textures);

  // The program's samplers, images, fragment outputs and uniforms on `backend` (compiling it if
  // need be).
  ShaderReflection reflect(Backend backend);

 private:
  // The units of the textures and images that a run names, in its order, checked once per
  // program and list of names: a sweep runs each pass thousands of times with the same names.
  struct Units {
    std::vector<int> samplers;
    std::vector<int> images;
    // Per sampler and image, in the order given: whether the shader reads it as integers.
    std::vector<bool> integer_samplers;
    std::vector<bool> integer_images;
  };
  // Throws unless each texture's kind (uint32 or not) is what its sampler or image reads: GL
  // gives undefined values, not an error, for a float texture read as integers or the reverse.
  void check_kinds(const Program& p, const Units& u, const NamedTextures& inputs,
                   const NamedTextures& outputs) const;
  const Units& units(const Program& p, const NamedTextures& inputs, const NamedTextures& outputs,
                     Backend backend);
  std::map<std::pair<const Program*, std::string>, Units> units_;
  std::unique_ptr<Buffer> indirect_;  // run_indirect's work-group counts, made on first use
};

}  // namespace blurlab
