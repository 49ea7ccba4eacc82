#include "gl/loader.h"

#include <dlfcn.h>

#include <cstring>
#include <mutex>

namespace blurlab {

const char* const kEglInstallHint =
    "Install an EGL driver: Mesa's software rasterizer on Debian/Ubuntu with "
    "`apt-get install libegl1 libegl-mesa0 libgl1-mesa-dri`, or the NVIDIA driver (with its "
    "EGL library) for a GPU.";

namespace {

std::mutex load_mutex;
void* egl_library = nullptr;
PFNEGLGETPROCADDRESSPROC get_proc_address = nullptr;
PFNEGLGETDISPLAYPROC real_get_display = nullptr;
bool gl_loaded = false;

// Core functions come straight from the library; extension functions only through
// eglGetProcAddress.
GLADapiproc egl_symbol(void*, const char* name) {
  if (void* symbol = dlsym(egl_library, name)) return reinterpret_cast<GLADapiproc>(symbol);
  return reinterpret_cast<GLADapiproc>(get_proc_address(name));
}

// glad reads the EGL version from a display, falling back to eglGetDisplay(EGL_DEFAULT_DISPLAY),
// which would open a window-system display that blurlab never uses. Answering "no display" makes
// it read the client version (EGL 1.5 on glvnd, Mesa and NVIDIA) instead.
EGLDisplay EGLAPIENTRY no_default_display(EGLNativeDisplayType) {
  return EGL_NO_DISPLAY;
}

GLADapiproc egl_symbol_for_loading(void* userptr, const char* name) {
  if (std::strcmp(name, "eglGetDisplay") == 0) {
    real_get_display = reinterpret_cast<PFNEGLGETDISPLAYPROC>(egl_symbol(userptr, name));
    return reinterpret_cast<GLADapiproc>(&no_default_display);
  }
  return egl_symbol(userptr, name);
}

GLADapiproc gl_symbol(void*, const char* name) {
  return reinterpret_cast<GLADapiproc>(get_proc_address(name));
}

}  // namespace

void load_egl() {
  std::lock_guard<std::mutex> lock(load_mutex);
  if (egl_library) return;
  void* library = dlopen("libEGL.so.1", RTLD_LAZY | RTLD_LOCAL);
  if (!library) {
    const char* why = dlerror();
    throw std::runtime_error(std::string("blurlab: libEGL.so.1 could not be loaded (") +
                             (why ? why : "unknown reason") + "). " + kEglInstallHint);
  }
  auto get = reinterpret_cast<PFNEGLGETPROCADDRESSPROC>(dlsym(library, "eglGetProcAddress"));
  if (!get) {
    dlclose(library);
    throw std::runtime_error(std::string("blurlab: libEGL.so.1 has no eglGetProcAddress. ") +
                             kEglInstallHint);
  }
  egl_library = library;
  get_proc_address = get;
  const int version = gladLoadEGLUserPtr(EGL_NO_DISPLAY, egl_symbol_for_loading, nullptr);
  glad_eglGetDisplay = real_get_display;
  if (version < GLAD_MAKE_VERSION(1, 5)) {
    egl_library = nullptr;
    dlclose(library);
    throw std::runtime_error("blurlab: the system's EGL offers version " +
                             std::to_string(GLAD_VERSION_MAJOR(version)) + "." +
                             std::to_string(GLAD_VERSION_MINOR(version)) +
                             " to clients, blurlab needs 1.5. " + kEglInstallHint);
  }
}

void load_gl() {
  std::lock_guard<std::mutex> lock(load_mutex);
  if (gl_loaded) return;
  const int version = gladLoadGLUserPtr(gl_symbol, nullptr);
  if (!version)
    throw std::runtime_error(
        "blurlab: the OpenGL entry points could not be loaded through eglGetProcAddress");
  // glad loads only what the current context's version offers: a context below 4.5 (which the
  // caller then refuses) must not leave the pointers half loaded for the next one.
  gl_loaded = version >= GLAD_MAKE_VERSION(4, 5);
}

bool has_gl_extension(const char* name) {
  GLint count = 0;
  glGetIntegerv(GL_NUM_EXTENSIONS, &count);
  for (GLint i = 0; i < count; ++i) {
    const GLubyte* extension = glGetStringi(GL_EXTENSIONS, static_cast<GLuint>(i));
    if (extension && std::strcmp(reinterpret_cast<const char*>(extension), name) == 0) return true;
  }
  return false;
}

}  // namespace blurlab
