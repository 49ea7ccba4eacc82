#include "gl/gl.h"

#include <cstdio>

namespace blurlab {

std::string gl_error_name(GLenum error) {
  switch (error) {
    case GL_INVALID_ENUM: return "GL_INVALID_ENUM";
    case GL_INVALID_VALUE: return "GL_INVALID_VALUE";
    case GL_INVALID_OPERATION: return "GL_INVALID_OPERATION";
    case GL_INVALID_FRAMEBUFFER_OPERATION: return "GL_INVALID_FRAMEBUFFER_OPERATION";
    case GL_OUT_OF_MEMORY: return "GL_OUT_OF_MEMORY";
    case GL_STACK_OVERFLOW: return "GL_STACK_OVERFLOW";
    case GL_STACK_UNDERFLOW: return "GL_STACK_UNDERFLOW";
    case GL_CONTEXT_LOST:
      return "GL_CONTEXT_LOST (the GPU reset this context and everything it held is lost; make "
             "a new blurlab.Context)";
    default: {
      char hex[16];
      std::snprintf(hex, sizeof hex, "0x%04X", error);
      return std::string("GL error ") + hex;
    }
  }
}

std::string reset_status_name() {
  switch (glGetGraphicsResetStatus()) {
    case GL_NO_ERROR: return "none";
    case GL_GUILTY_CONTEXT_RESET: return "guilty";
    case GL_INNOCENT_CONTEXT_RESET: return "innocent";
    default: return "unknown";
  }
}

void check_gl(const char* what) {
  std::string errors;
  bool lost = false;
  // GL keeps one flag per error kind; drain them all so none is left for the next call. A lost
  // context sets GL_CONTEXT_LOST on every call, so it is named once.
  for (int i = 0; i < 16; ++i) {
    GLenum e = glGetError();
    if (e == GL_NO_ERROR) break;
    if (e == GL_CONTEXT_LOST) {
      lost = true;
      continue;
    }
    if (!errors.empty()) errors += ", ";
    errors += gl_error_name(e);
  }
  if (lost)
    throw ContextLost(std::string(what) + " failed: " + gl_error_name(GL_CONTEXT_LOST) +
                      "; reset status: " + reset_status_name());
  if (!errors.empty()) throw GLError(std::string(what) + " failed: " + errors);
}

}  // namespace blurlab
