// Bindings of src/gl: Context, Texture, Program, Timer, PendingDownload. Argument checking that
// needs Python types lives in python/blurlab/context.py; these functions only convert.
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <vector>

#include "bindings/bindings.h"
#include "gl/context.h"
#include "gl/program.h"
#include "gl/readback.h"
#include "gl/texture.h"
#include "gl/timer.h"

namespace py = pybind11;

namespace blurlab {
namespace {

PixelType pixel_type(const std::string& dtype) {
  if (dtype == "uint8") return PixelType::u8;
  if (dtype == "float16") return PixelType::f16;
  if (dtype == "float32") return PixelType::f32;
  if (dtype == "uint32") return PixelType::u32;
  throw std::invalid_argument(
      "blurlab: texture dtype must be uint8, float16, float32 or uint32, not " + dtype);
}

std::string dtype_name(PixelType type) {
  switch (type) {
    case PixelType::u8: return "uint8";
    case PixelType::f16: return "float16";
    case PixelType::f32: return "float32";
    case PixelType::u32: return "uint32";
  }
  return "";
}

GLenum image_access(const std::string& access) {
  if (access == "read") return GL_READ_ONLY;
  if (access == "write") return GL_WRITE_ONLY;
  if (access == "read_write") return GL_READ_WRITE;
  throw std::invalid_argument(
      "blurlab: image access must be 'read', 'write' or 'read_write', not '" + access + "'");
}

void upload_level(Texture& texture, int level, const py::array& array) {
  if (!(array.flags() & py::array::c_style))
    throw std::invalid_argument("blurlab: upload needs a C-contiguous array");
  if (py::str(array.dtype()).cast<std::string>() != dtype_name(texture.format().type))
    throw std::invalid_argument("blurlab: upload dtype does not match the texture's " +
                                dtype_name(texture.format().type));
  const size_t bytes = static_cast<size_t>(array.nbytes());
  const void* data = array.data();
  py::gil_scoped_release release;
  texture.upload_level(level, data, bytes);
}

void upload(Texture& texture, const py::array& array) {
  upload_level(texture, 0, array);
}

py::array download(const Texture& texture) {
  py::array out(py::dtype(dtype_name(texture.format().type)),
                {texture.height(), texture.width(), texture.format().channels});
  void* data = out.mutable_data();
  const size_t bytes = static_cast<size_t>(out.nbytes());
  {
    py::gil_scoped_release release;
    texture.download(data, bytes);
  }
  return out;
}

// The bytes of a finished download, read through GL into a new array (any number of times).
py::array download_result(PendingDownload& pending) {
  py::array_t<uint8_t> out(static_cast<py::ssize_t>(pending.size()));
  void* destination = out.mutable_data();
  {
    py::gil_scoped_release release;
    pending.read(destination);
  }
  return std::move(out);
}

}  // namespace

void bind_gl(py::module_& m) {
  py::class_<EglDevice>(m, "EglDevice")
      .def_readonly("index", &EglDevice::index)
      .def_readonly("kind", &EglDevice::kind)
      .def_readonly("name", &EglDevice::name)
      .def_readonly("extensions", &EglDevice::extensions);

  py::class_<Context, std::shared_ptr<Context>>(m, "Context")
      .def(py::init([](const std::string& mode, int index, std::string shader_dir) {
             return Context::create(DeviceRequest{mode, index}, std::move(shader_dir));
           }),
           py::arg("mode"), py::arg("index"), py::arg("shader_dir"))
      .def_static("devices", &Context::devices)
      .def("info", &Context::info)
      .def("live_objects", &Context::live_objects)
      .def("gl_errors", &Context::gl_errors)
      .def("reset_status", &Context::reset_status)
      .def("memory", &Context::memory)
      .def("finish", &Context::finish, py::call_guard<py::gil_scoped_release>())
      .def_property_readonly("waits", &Context::waits)
      .def_property_readonly("fence_timeouts", &Context::fence_timeouts)
      .def_property_readonly("pacing_waits", &Context::pacing_waits)
      .def_property_readonly("stale_readbacks", &Context::stale_readbacks)
      .def("make_current", &Context::make_current)
      .def_property_readonly("software", &Context::is_software)
      .def_property_readonly("max_texture_size", &Context::max_texture_size)
      .def_property_readonly("shader_dir", &Context::shader_dir)
      .def(
          "texture",
          [](const std::shared_ptr<Context>& ctx, int width, int height, int channels,
             const std::string& dtype, int levels) {
            return std::make_shared<Texture>(ctx, width, height,
                                             texture_format(pixel_type(dtype), channels), levels);
          },
          py::arg("width"), py::arg("height"), py::arg("channels"), py::arg("dtype"),
          py::arg("levels") = 1);

  py::class_<Texture, std::shared_ptr<Texture>>(m, "Texture")
      .def_property_readonly("glo", &Texture::id)
      .def_property_readonly("width", &Texture::width)
      .def_property_readonly("height", &Texture::height)
      .def_property_readonly("channels", [](const Texture& t) { return t.format().channels; })
      .def_property_readonly("dtype", [](const Texture& t) { return dtype_name(t.format().type); })
      .def_property_readonly("internal_format",
                             [](const Texture& t) { return t.format().internal; })
      .def("upload", &upload, py::arg("array"))
      .def("download", &download)
      .def("download_async", [](const Texture& t) { return std::make_shared<PendingDownload>(t); })
      .def("clear", py::overload_cast<>(&Texture::clear))
      .def("clear_to",
           [](Texture& t, const std::vector<float>& value) {
             if (static_cast<int>(value.size()) != t.format().channels)
               throw std::invalid_argument("blurlab: clear value needs one float per channel");
             t.clear(value.data());
           })
      .def("generate_mipmaps", &Texture::generate_mipmaps)
      .def("upload_level", &upload_level, py::arg("level"), py::arg("array"))
      .def("use_mipmaps", &Texture::use_mipmaps)
      .def("copy_from", &Texture::copy_from, py::arg("source"), py::arg("x"), py::arg("y"))
      .def_property_readonly("levels", &Texture::levels);

  py::class_<PendingDownload, std::shared_ptr<PendingDownload>>(m, "PendingDownload")
      .def("done", &PendingDownload::done)
      .def("result_bytes", &download_result);

  py::class_<Program, std::shared_ptr<Program>>(m, "Program")
      .def_static("compute", &Program::compute, py::arg("context"), py::arg("path"),
                  py::arg("defines"))
      .def_static("graphics", &Program::graphics, py::arg("context"), py::arg("vertex_path"),
                  py::arg("fragment_path"), py::arg("defines"))
      .def_property_readonly("glo", &Program::id)
      .def_property_readonly("name", &Program::name)
      .def_property_readonly("local_size", &Program::local_size)
      .def_property_readonly("uniforms",
                             [](const Program& p) {
                               std::map<std::string, GLenum> types;
                               for (const auto& [name, u] : p.uniforms()) types[name] = u.type;
                               return types;
                             })
      .def("set_uniform", &Program::set_uniform, py::arg("name"), py::arg("values"))
      .def(
          "bind_image",
          [](Program& p, int unit, const Texture& t, const std::string& access) {
            p.bind_image(unit, t, image_access(access));
          },
          py::arg("unit"), py::arg("texture"), py::arg("access"))
      .def("bind_texture", &Program::bind_texture, py::arg("unit"), py::arg("texture"))
      .def("dispatch", &Program::dispatch, py::arg("x"), py::arg("y"), py::arg("z"));

  py::class_<Timer, std::shared_ptr<Timer>>(m, "Timer")
      .def(py::init<std::shared_ptr<Context>>(), py::arg("context"))
      .def("start", &Timer::start)
      .def("stop", &Timer::stop, py::call_guard<py::gil_scoped_release>())
      .def("end", &Timer::end)
      .def("result", &Timer::result, py::call_guard<py::gil_scoped_release>())
      .def_property_readonly("clock", &Timer::clock);

  m.def("translate_shader_log", &translate_shader_log, py::arg("log"), py::arg("files"));
}

}  // namespace blurlab
