// blurlab._core: the C++ core as Python sees it. One bind_* function per area; no logic here.
#include <pybind11/pybind11.h>

#include "bindings/bindings.h"
#include "gl/gl.h"

namespace py = pybind11;

PYBIND11_MODULE(_core, m) {
  m.doc() = "blurlab's C++ core: headless OpenGL through EGL, textures, programs and timers.";
  py::register_exception<blurlab::ShaderError>(m, "ShaderError", PyExc_RuntimeError);
  auto gl_error = py::register_exception<blurlab::GLError>(m, "GLError", PyExc_RuntimeError);
  // After GLError, so that its translator is tried first for the subclass.
  py::register_exception<blurlab::ContextLost>(m, "ContextLost", gl_error.ptr());
  py::register_exception<blurlab::StaleReadback>(m, "StaleReadback", PyExc_RuntimeError);
  blurlab::bind_gl(m);
  blurlab::bind_passes(m);
}
