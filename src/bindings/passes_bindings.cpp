// Bindings of src/passes and src/gl/mesh: array conversion only. The Python side
// (python/blurlab/render.py) validates arguments and builds the matrices.
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cstring>
#include <optional>

#include "bindings/bindings.h"
#include "gl/context.h"
#include "gl/mesh.h"
#include "gl/texture.h"
#include "passes/dispatch_plan.h"
#include "passes/error_reduction.h"
#include "passes/gbuffer.h"
#include "passes/motion_encoding.h"
#include "passes/pair_reduction.h"
#include "passes/shader_pass.h"
#include "passes/ssim_reduction.h"

namespace py = pybind11;

namespace blurlab {
namespace {

using Floats = py::array_t<float, py::array::c_style | py::array::forcecast>;
using Uints = py::array_t<uint32_t, py::array::c_style | py::array::forcecast>;

void require_size(const py::array& a, size_t count, const char* what) {
  if (static_cast<size_t>(a.size()) != count)
    throw std::invalid_argument(std::string("blurlab: ") + what + " has " +
                                std::to_string(a.size()) + " values, expected " +
                                std::to_string(count));
}

void copy_floats(float* dst, const Floats& src, size_t count, const char* what) {
  require_size(src, count, what);
  std::memcpy(dst, src.data(), count * sizeof(float));
}

std::shared_ptr<Mesh> make_mesh(const std::shared_ptr<Context>& ctx, const Floats& positions,
                                const Floats& normals, const Floats& texcoords,
                                const Uints& indices, std::optional<Uints> bone_indices,
                                std::optional<Floats> bone_weights) {
  MeshData d;
  d.vertex_count = static_cast<size_t>(positions.size()) / 3;
  d.triangle_count = static_cast<size_t>(indices.size()) / 3;
  require_size(positions, d.vertex_count * 3, "positions");
  require_size(normals, d.vertex_count * 3, "normals");
  require_size(texcoords, d.vertex_count * 2, "texcoords");
  require_size(indices, d.triangle_count * 3, "indices");
  d.positions = positions.data();
  d.normals = normals.data();
  d.texcoords = texcoords.data();
  d.indices = indices.data();
  if (bone_indices && bone_weights) {
    require_size(*bone_indices, d.vertex_count * 4, "bone_indices");
    require_size(*bone_weights, d.vertex_count * 4, "bone_weights");
    d.bone_indices = bone_indices->data();
    d.bone_weights = bone_weights->data();
  }
  return std::make_shared<Mesh>(ctx, d);
}

// A float array member as a NumPy copy of `shape`, and set from any array of as many values.
template <typename Owner>
void float_array(py::class_<Owner>& cls, const char* name, float* (*member)(Owner&),
                 std::vector<py::ssize_t> shape) {
  size_t count = 1;
  for (py::ssize_t n : shape) count *= size_t(n);
  cls.def_property(
      name, [member, shape](Owner& o) { return Floats(shape, member(o)); },
      [member, count, name](Owner& o, const Floats& values) {
        copy_floats(member(o), values, count, name);
      });
}

// A dict of name -> _core.Texture, in the dict's order (the first output sets the dispatch).
NamedTextures named_textures(const py::dict& dict, const ShaderPass& pass, const char* what) {
  NamedTextures textures;
  for (const auto& [key, value] : dict) {
    const std::string name = key.cast<std::string>();
    if (!py::isinstance<Texture>(value))
      throw std::invalid_argument("blurlab: " + pass.shader() + ": " + what + " '" + name +
                                  "' must be a _core.Texture, not " +
                                  std::string(py::str(value.get_type().attr("__name__"))));
    textures.emplace_back(name, &value.cast<const Texture&>());
  }
  return textures;
}

// Uniform values: a number becomes one value, a bool 0 or 1, a sequence or NumPy array its
// values flattened row by row (a mat4 as NumPy holds it).
UniformValues uniform_values(const py::dict& dict, const ShaderPass& pass) {
  UniformValues values;
  for (const auto& [key, value] : dict) {
    const std::string name = key.cast<std::string>();
    auto refuse = [&] {
      return std::invalid_argument("blurlab: " + pass.shader() + ": uniform '" + name +
                                   "' takes numbers, not " +
                                   std::string(py::str(value.get_type().attr("__name__"))));
    };
    if (value.is_none() || py::isinstance<py::str>(value) || py::isinstance<py::bytes>(value))
      throw refuse();
    auto array = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(value);
    if (!array) throw refuse();
    values[name].assign(array.data(), array.data() + array.size());
  }
  return values;
}

py::dict bindings_dict(const std::map<std::string, ShaderReflection::Binding>& bindings,
                       const char* unit_key, bool with_format) {
  py::dict d;
  for (const auto& [name, b] : bindings) {
    py::dict entry;
    entry["type"] = b.type;
    entry[unit_key] = b.unit;
    if (with_format) entry["format"] = b.format;
    d[py::str(name)] = entry;
  }
  return d;
}

}  // namespace

void bind_passes(py::module_& m) {
  py::class_<Mesh, std::shared_ptr<Mesh>>(m, "Mesh")
      .def(py::init(&make_mesh), py::arg("context"), py::arg("positions"), py::arg("normals"),
           py::arg("texcoords"), py::arg("indices"), py::arg("bone_indices") = py::none(),
           py::arg("bone_weights") = py::none())
      .def_property_readonly("skinned", &Mesh::skinned)
      .def_property_readonly("triangle_count", &Mesh::triangle_count);

  // One draw of the G-buffer pass, built by python/blurlab/render.py. Arrays are copied in and
  // out (row-major, as NumPy holds them) with their sizes checked.
  py::class_<GBufferHatching> hatching(m, "GBufferHatching");
  py::enum_<GBufferHatching::Scheme>(hatching, "Scheme")
      .value("none", GBufferHatching::Scheme::none)
      .value("six_way", GBufferHatching::Scheme::six_way)
      .value("threshold", GBufferHatching::Scheme::threshold);
  hatching.def(py::init<>())
      .def_readwrite("scheme", &GBufferHatching::scheme)
      .def_readwrite("scale", &GBufferHatching::scale)
      .def_readwrite("tam_low", &GBufferHatching::tam_low)
      .def_readwrite("tam_high", &GBufferHatching::tam_high);

  py::enum_<AlphaMode>(m, "AlphaMode")
      .value("opaque", AlphaMode::opaque)
      .value("mask", AlphaMode::mask)
      .value("blend", AlphaMode::blend)
      .value("additive", AlphaMode::additive);

  py::class_<GBufferMaterial> material(m, "GBufferMaterial");
  material.def(py::init<>())
      .def_readwrite("alpha_mode", &GBufferMaterial::alpha_mode)
      .def_readwrite("alpha_cutoff", &GBufferMaterial::alpha_cutoff)
      .def_readwrite("specular", &GBufferMaterial::specular)
      .def_readwrite("shininess", &GBufferMaterial::shininess)
      .def_readwrite("texture", &GBufferMaterial::texture)
      .def_readwrite("hatching", &GBufferMaterial::hatching);
  float_array<GBufferMaterial>(material, "color", [](GBufferMaterial& o) { return o.color; }, {4});
  float_array<GBufferMaterial>(material, "emission", [](GBufferMaterial& o) { return o.emission; },
                               {3});

  py::class_<GBufferDraw> draw(m, "GBufferDraw");
  draw.def(py::init<>())
      .def_readwrite("mesh", &GBufferDraw::mesh)
      .def_readwrite("material", &GBufferDraw::material)
      .def_readwrite("object_id", &GBufferDraw::object_id)
      .def_readonly("bone_count", &GBufferDraw::bone_count)
      // (3, B, 4, 4): B bone matrices at t0, t1 and the instant; None for an unskinned mesh.
      .def_property(
          "bones",
          [](GBufferDraw& d) -> py::object {
            if (d.bone_count == 0) return py::none();
            return Floats(
                {py::ssize_t(3), py::ssize_t(d.bone_count), py::ssize_t(4), py::ssize_t(4)},
                d.bones.data());
          },
          [](GBufferDraw& d, std::optional<Floats> bones) {
            d.bones.clear();
            d.bone_count = 0;
            if (!bones) return;
            const int count = static_cast<int>(bones->size() / 48);
            require_size(*bones, size_t(count) * 48, "bone matrices");
            d.bones.assign(bones->data(), bones->data() + bones->size());
            d.bone_count = count;
          });
  float_array<GBufferDraw>(draw, "model", [](GBufferDraw& o) { return &o.model[0][0]; }, {3, 4, 4});

  py::class_<GBufferPass, std::shared_ptr<GBufferPass>>(m, "GBufferPass")
      .def(py::init<std::shared_ptr<Context>>(), py::arg("context"))
      .def(
          "render",
          [](GBufferPass& pass, std::shared_ptr<Texture> color, std::shared_ptr<Texture> depth,
             std::shared_ptr<Texture> motion, std::shared_ptr<Texture> object_id,
             const py::dict& camera, const py::dict& light, const std::vector<GBufferDraw>& draws,
             std::shared_ptr<Texture> motion_sides, std::shared_ptr<Texture> fragment_counts,
             std::shared_ptr<Texture> fragment_surface, std::shared_ptr<Texture> fragment_motion,
             std::shared_ptr<Texture> opaque_depth, int over_base) {
            GBufferCamera c;
            copy_floats(&c.view_projection[0][0], camera["view_projection"].cast<Floats>(), 48,
                        "view_projection");
            copy_floats(c.eye, camera["eye"].cast<Floats>(), 3, "eye");
            c.near = camera["near"].cast<float>();
            copy_floats(c.sky_from_clip, camera["sky_from_clip"].cast<Floats>(), 16,
                        "sky_from_clip");
            copy_floats(&c.sky_projection[0][0], camera["sky_projection"].cast<Floats>(), 32,
                        "sky_projection");
            GBufferLight l;
            copy_floats(l.direction, light["direction"].cast<Floats>(), 3, "light direction");
            copy_floats(l.color, light["color"].cast<Floats>(), 3, "light color");
            copy_floats(l.ambient, light["ambient"].cast<Floats>(), 3, "ambient");
            copy_floats(l.background, light["background"].cast<Floats>(), 4, "background");
            pass.render({color, depth, motion, object_id, motion_sides, fragment_counts,
                         fragment_surface, fragment_motion, opaque_depth},
                        c, l, draws, over_base);
          },
          py::arg("color"), py::arg("depth"), py::arg("motion"), py::arg("object_id"),
          py::arg("camera"), py::arg("light"), py::arg("draws"),
          py::arg("motion_sides") = py::none(), py::arg("fragment_counts") = py::none(),
          py::arg("fragment_surface") = py::none(), py::arg("fragment_motion") = py::none(),
          py::arg("opaque_depth") = py::none(), py::arg("over_base") = 0)
      .def("keep_base", &GBufferPass::keep_base);

  py::class_<PostProcessPass, std::shared_ptr<PostProcessPass>>(m, "PostProcessPass");

  // Runs issue GL commands and do not wait for the GPU, so they keep the GIL.
  py::class_<ShaderPass, PostProcessPass, std::shared_ptr<ShaderPass>>(m, "ShaderPass")
      .def(py::init<std::shared_ptr<Context>, std::string, Defines>(), py::arg("context"),
           py::arg("shader"), py::arg("defines") = Defines{})
      .def_property_readonly("shader", &ShaderPass::shader)
      .def(
          "run",
          [](ShaderPass& pass, const py::dict& inputs, const py::dict& outputs,
             const py::dict& uniforms, const std::string& backend, bool group_per_texel) {
            pass.run(named_textures(inputs, pass, "input"), named_textures(outputs, pass, "output"),
                     uniform_values(uniforms, pass), parse_backend(backend), group_per_texel);
          },
          py::arg("inputs"), py::arg("outputs"), py::arg("uniforms"),
          py::arg("backend") = "compute", py::arg("group_per_texel") = false)
      .def(
          "run_indirect",
          [](ShaderPass& pass, const py::dict& inputs, const py::dict& outputs,
             const py::dict& uniforms, const Texture& counts, int slot) {
            pass.run_indirect(named_textures(inputs, pass, "input"),
                              named_textures(outputs, pass, "output"),
                              uniform_values(uniforms, pass), counts, slot);
          },
          py::arg("inputs"), py::arg("outputs"), py::arg("uniforms"), py::arg("counts"),
          py::arg("slot"))
      .def(
          "reflect",
          [](ShaderPass& pass, const std::string& backend) {
            const ShaderReflection r = pass.reflect(parse_backend(backend));
            py::dict uniforms;
            for (const auto& [name, u] : r.uniforms) {
              py::dict entry;
              entry["type"] = u.type;
              entry["count"] = u.count;
              uniforms[py::str(name)] = entry;
            }
            py::dict d;
            d["samplers"] = bindings_dict(r.samplers, "unit", false);
            d["images"] = bindings_dict(r.images, "unit", true);
            d["fragment_outputs"] = bindings_dict(r.fragment_outputs, "location", false);
            d["uniforms"] = uniforms;
            return d;
          },
          py::arg("backend") = "compute");

  // Recorded ShaderPass runs replayed by one call (dispatch_plan.h; blurlab.methods.core).
  py::class_<DispatchPlan, std::shared_ptr<DispatchPlan>>(m, "DispatchPlan")
      .def(py::init<std::shared_ptr<Context>, const std::vector<const Texture*>&>(),
           py::arg("context"), py::arg("textures"))
      .def(
          "add",
          [](DispatchPlan& plan, std::shared_ptr<ShaderPass> pass, const py::dict& inputs,
             const py::dict& outputs, const py::dict& uniforms, const std::string& backend,
             bool group_per_texel) {
            plan.add(pass, named_textures(inputs, *pass, "input"),
                     named_textures(outputs, *pass, "output"), uniform_values(uniforms, *pass),
                     parse_backend(backend), group_per_texel);
          },
          py::arg("shader_pass"), py::arg("inputs"), py::arg("outputs"), py::arg("uniforms"),
          py::arg("backend"), py::arg("group_per_texel"))
      .def("run", &DispatchPlan::run, py::arg("textures"))
      .def_property_readonly("steps", &DispatchPlan::steps);

  py::class_<ReductionQueue, std::shared_ptr<ReductionQueue>>(m, "ReductionQueue")
      .def(py::init([](std::shared_ptr<Context> context) {
             return std::make_shared<ReductionQueue>(context.get());
           }),
           py::arg("context"), py::keep_alive<1, 2>())
      .def(
          "reserve",
          [](ReductionQueue& q, size_t groups, int components) {
            if (groups < 1 || components < 1)
              throw std::invalid_argument(
                  "blurlab: a reduction needs at least one work group and one component");
            const auto r = q.reserve(groups, components);
            return py::make_tuple(r.index, r.ticket);
          },
          py::arg("groups"), py::arg("components"),
          "Room for a reduction of `groups` work groups bound to storage buffer 0: (index, "
          "ticket). Each group writes its `components` sums and then the ticket; read() refuses "
          "a batch where one is missing (StaleReadback).")
      .def("seal", &ReductionQueue::seal)
      .def("read", &ReductionQueue::read, py::call_guard<py::gil_scoped_release>())
      .def("clear", &ReductionQueue::clear)
      .def_property_readonly("pending", &ReductionQueue::pending);

  py::class_<ErrorReductionPass, std::shared_ptr<ErrorReductionPass>>(m, "ErrorReductionPass")
      .def(py::init<std::shared_ptr<Context>>(), py::arg("context"))
      .def("squared_error", &ErrorReductionPass::squared_error, py::arg("a"), py::arg("b"),
           py::call_guard<py::gil_scoped_release>())
      .def("issue_squared_error", &ErrorReductionPass::issue_squared_error, py::arg("a"),
           py::arg("b"), py::arg("queue"));

  py::class_<SsimReductionPass, std::shared_ptr<SsimReductionPass>>(m, "SsimReductionPass")
      .def(py::init<std::shared_ptr<Context>, int, int, int>(), py::arg("context"),
           py::arg("tile_rows") = 32, py::arg("rows_per_thread") = 4, py::arg("tile_columns") = 32)
      .def("mean_ssim", &SsimReductionPass::mean_ssim, py::arg("a"), py::arg("b"),
           py::call_guard<py::gil_scoped_release>())
      .def("mse_ssim", &SsimReductionPass::mse_ssim, py::arg("a"), py::arg("b"),
           py::call_guard<py::gil_scoped_release>())
      .def("issue_mse_ssim", &SsimReductionPass::issue_mse_ssim, py::arg("a"), py::arg("b"),
           py::arg("queue"))
      .def("prepare", &SsimReductionPass::prepare, py::arg("reference"),
           py::arg("colour_luminance"), py::arg("moments"),
           py::call_guard<py::gil_scoped_release>())
      .def("mse_ssim_prepared", &SsimReductionPass::mse_ssim_prepared, py::arg("colour_luminance"),
           py::arg("moments"), py::arg("test"), py::call_guard<py::gil_scoped_release>())
      .def("issue_mse_ssim_prepared", &SsimReductionPass::issue_mse_ssim_prepared,
           py::arg("colour_luminance"), py::arg("moments"), py::arg("test"), py::arg("queue"));

  py::class_<MotionEncodingPass, std::shared_ptr<MotionEncodingPass>>(m, "MotionEncodingPass")
      .def(py::init<std::shared_ptr<Context>>(), py::arg("context"))
      .def("run", &MotionEncodingPass::run, py::arg("motion"), py::arg("stored"),
           py::arg("decoded"), py::arg("format"), py::arg("maxlen"));
}

}  // namespace blurlab
