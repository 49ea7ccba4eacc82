// Run-time loading of EGL and GL: the module links neither libEGL nor libGL. It opens the
// system's libEGL.so.1 (glvnd, Mesa or NVIDIA) by name, and takes every GL entry point from
// eglGetProcAddress, so one binary runs on whichever EGL driver the machine has.
#pragma once

#include "gl/gl.h"

namespace blurlab {

// What to install when EGL is missing or finds no device.
extern const char* const kEglInstallHint;

// Opens libEGL.so.1 and loads the EGL 1.5 client entry points and client extensions, once per
// process. Throws std::runtime_error naming the reason and kEglInstallHint when it cannot.
void load_egl();

// Loads the GL 4.5 core entry points with a context current; once per process, from the first
// context that offers 4.5. The pointers
// eglGetProcAddress hands out dispatch on the current context, so they serve every context.
void load_gl();

// Whether the current context lists a GL extension (asked per context: two contexts on
// different devices differ).
bool has_gl_extension(const char* name);

}  // namespace blurlab
