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

void check_gl(const char* what) {
  std::string errors;
  // GL keeps one flag per error kind; drain them all so none is left for the next call.
  for (int i = 0; i < 16; ++i) {
    GLenum e = glGetError();
    if (e == GL_NO_ERROR) break;
    if (!errors.empty()) errors += ", ";
    errors += gl_error_name(e);
  }
  if (!errors.empty()) throw GLError(std::string(what) + " failed: " + errors);
}

}  // namespace blurlab
