// Common include for every GL-facing file: the GL 4.5 core and EGL 1.5 entry points that glad2
// generates at build time (CMakeLists.txt), and the error types that the bindings translate into
// Python exceptions.
#pragma once

#include <glad/egl.h>
#include <glad/gl.h>

#include <stdexcept>
#include <string>

namespace blurlab {

// A GL call failed or left an error set; raised as blurlab.GLError (a RuntimeError).
struct GLError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The GPU reset the context (GL_CONTEXT_LOST): every texture, buffer and program it held is
// gone, and the work since the reset did nothing. Raised as blurlab.ContextLost, a GLError;
// sweeps on a cluster open a new context and evaluate the chunk again.
struct ContextLost : GLError {
  using GLError::GLError;
};

// What glGetGraphicsResetStatus says of the current context: "none", "guilty" (its own work
// caused the reset), "innocent" or "unknown". Always "none" without reset notification.
std::string reset_status_name();

// A shader failed to load, compile or link; raised as blurlab.ShaderError (a RuntimeError).
struct ShaderError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// A reduction's partial sums, read back after its fence, are not what its pass wrote: the ticket
// each work group writes beside its sums is missing (docs/spec.md §6.3). Raised as
// blurlab.StaleReadback (a RuntimeError); sweeps evaluate the batch again.
struct StaleReadback : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The base of every class that owns GL objects or a context: one owner each, never copied.
struct NotCopyable {
  NotCopyable() = default;
  NotCopyable(const NotCopyable&) = delete;
  NotCopyable& operator=(const NotCopyable&) = delete;
};

// Reads and clears every pending GL error; throws GLError naming `what` if there was one.
// Called after each operation so that no error is left set for the next caller.
void check_gl(const char* what);

// check_gl after the calls that made a GL object: on an error the object is deleted (`destroy`),
// the error its deletion may set is cleared, and the GLError thrown.
template <typename Destroy>
void check_created(const char* what, Destroy destroy) {
  try {
    check_gl(what);
  } catch (...) {
    destroy();
    glGetError();
    throw;
  }
}

std::string gl_error_name(GLenum error);

}  // namespace blurlab
