#include "gl/context.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "gl/buffer.h"
#include "gl/loader.h"

#ifndef EGL_PLATFORM_SURFACELESS_MESA
#define EGL_PLATFORM_SURFACELESS_MESA 0x31DD
#endif
#ifndef EGL_DRM_DEVICE_FILE_EXT
#define EGL_DRM_DEVICE_FILE_EXT 0x3233
#endif
#ifndef EGL_CUDA_DEVICE_NV
#define EGL_CUDA_DEVICE_NV 0x323A
#endif

namespace blurlab {
namespace {

bool has_token(const char* list, const std::string& token) {
  if (!list) return false;
  std::istringstream words(list);
  std::string word;
  while (words >> word)
    if (word == token) return true;
  return false;
}

std::string egl_error_text() {
  char text[32];
  std::snprintf(text, sizeof text, "EGL error 0x%04x", static_cast<unsigned>(eglGetError()));
  return text;
}

// eglInitialize/eglTerminate are not reference counted, and every context on one device shares
// one EGLDisplay: count users so the last one to go terminates it.
std::mutex display_mutex;
std::map<EGLDisplay, int> display_users;

void release_display(EGLDisplay display) {
  std::lock_guard<std::mutex> lock(display_mutex);
  if (--display_users[display] == 0) {
    display_users.erase(display);
    eglTerminate(display);
  }
}

}  // namespace

std::vector<EglDevice> Context::devices() {
  load_egl();
  std::vector<EglDevice> result;
  const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  if (!has_token(client, "EGL_EXT_device_enumeration") && !has_token(client, "EGL_EXT_device_base"))
    return result;
  EGLint count = 0;
  if (!eglQueryDevicesEXT(0, nullptr, &count) || count <= 0) return result;
  std::vector<EGLDeviceEXT> handles(count);
  eglQueryDevicesEXT(count, handles.data(), &count);
  for (EGLint i = 0; i < count; ++i) {
    EglDevice d;
    d.index = i;
    const char* ext = eglQueryDeviceStringEXT(handles[i], EGL_EXTENSIONS);
    d.extensions = ext ? ext : "";
    d.kind = has_token(ext, "EGL_MESA_device_software") ? "software" : "gpu";
    const char* drm_file = has_token(ext, "EGL_EXT_device_drm")
                               ? eglQueryDeviceStringEXT(handles[i], EGL_DRM_DEVICE_FILE_EXT)
                               : nullptr;
    if (d.kind == "software") {
      d.name = "software";
    } else if (drm_file) {
      d.name = drm_file;
    } else if (has_token(ext, "EGL_NV_device_cuda")) {
      // NVIDIA lists EGL_EXT_device_drm but may have no DRM node inside a container.
      EGLAttrib cuda = -1;
      if (eglQueryDeviceAttribEXT) eglQueryDeviceAttribEXT(handles[i], EGL_CUDA_DEVICE_NV, &cuda);
      d.name = "cuda:" + std::to_string(cuda);
    } else {
      d.name = "device " + std::to_string(i);
    }
    result.push_back(d);
  }
  return result;
}

namespace {
// The most issued passes a context leaves unfinished: BLURLAB_PASSES_IN_FLIGHT where it is set
// (0: no bound), else Context::kPassesInFlight (docs/spec.md §6.3).
size_t passes_in_flight_bound() {
  const char* in_flight = std::getenv("BLURLAB_PASSES_IN_FLIGHT");
  if (!in_flight || !*in_flight) return Context::kPassesInFlight;
  char* end = nullptr;
  const long bound = std::strtol(in_flight, &end, 10);
  if (*end != '\0' || bound < 0 || bound > 1000000)
    throw std::invalid_argument(
        std::string("blurlab: BLURLAB_PASSES_IN_FLIGHT must be a whole number from 0 (no bound) "
                    "to 1000000, not '") +
        in_flight + "'");
  return static_cast<size_t>(bound);
}

// Whether a glClientWaitSync found its fence reached.
bool fence_reached(GLenum waited) {
  return waited == GL_ALREADY_SIGNALED || waited == GL_CONDITION_SATISFIED;
}
}  // namespace

std::shared_ptr<Context> Context::create(const DeviceRequest& request, std::string shader_dir) {
  // Read before any device is tried: a bad value is the caller's error, not a device's.
  const size_t passes_in_flight = passes_in_flight_bound();
  load_egl();
  const std::vector<EglDevice> devices = Context::devices();
  std::vector<EGLDeviceEXT> handles(devices.size());
  if (!devices.empty()) {
    EGLint count = static_cast<EGLint>(handles.size());
    eglQueryDevicesEXT(count, handles.data(), &count);
  }

  // Candidates in order of preference; each is tried until one gives a 4.5 core context.
  struct Candidate {
    const EglDevice* device;  // nullptr: the surfaceless platform
  };
  std::vector<Candidate> candidates;
  const std::string& mode = request.mode;
  if (mode == "index") {
    if (request.index < 0 || request.index >= static_cast<int>(devices.size())) {
      std::ostringstream s;
      s << "blurlab: EGL device " << request.index << " does not exist; this machine has "
        << devices.size() << " EGL device(s)";
      for (const auto& d : devices)
        s << "\n  " << d.index << ": " << d.kind << " (" << d.name << ")";
      throw std::invalid_argument(s.str());
    }
    candidates.push_back({&devices[request.index]});
  } else {
    if (mode == "auto" || mode == "gpu")
      for (const auto& d : devices)
        if (d.kind == "gpu") candidates.push_back({&d});
    if (mode == "auto" || mode == "software") {
      for (const auto& d : devices)
        if (d.kind == "software") candidates.push_back({&d});
      const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
      if (has_token(client, "EGL_MESA_platform_surfaceless")) candidates.push_back({nullptr});
    }
  }
  if (candidates.empty()) {
    if (mode == "software")
      throw std::runtime_error(
          "blurlab: device='software' was asked for, but EGL offers neither Mesa's software "
          "device nor its surfaceless platform. On Debian/Ubuntu: `apt-get install libegl-mesa0 "
          "libgl1-mesa-dri`.");
    if (mode == "gpu")
      throw std::runtime_error(
          "blurlab: device='gpu' was asked for, but EGL lists no hardware GPU. Install the "
          "NVIDIA driver with its EGL library (libnvidia-egl), or use device='auto' or "
          "'software' for Mesa's llvmpipe.");
    throw std::runtime_error(std::string("blurlab: EGL found no device to render on. ") +
                             kEglInstallHint);
  }

  if (!eglGetPlatformDisplayEXT)
    throw std::runtime_error(std::string("blurlab: the system's EGL lacks EGL_EXT_platform_base "
                                         "(eglGetPlatformDisplayEXT). ") +
                             kEglInstallHint);
  std::string failures;
  for (const Candidate& c : candidates) {
    EGLDisplay display;
    std::string platform;
    if (c.device) {
      display =
          eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, handles[c.device->index], nullptr);
      platform = "device";
    } else {
      display =
          eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
      platform = "surfaceless";
    }
    std::shared_ptr<Context> ctx(new Context());
    ctx->shader_dir_ = shader_dir;
    ctx->max_passes_in_flight_ = passes_in_flight;
    ctx->passes_per_fence_ = std::max<size_t>(1, passes_in_flight / kFencesInFlight);
    try {
      if (display == EGL_NO_DISPLAY)
        throw std::runtime_error("no EGL display (" + egl_error_text() + ")");
      ctx->create_on(display, platform, c.device);
      // The surfaceless platform renders on whatever Mesa or the vendor picks; "software"
      // promises llvmpipe, so a hardware renderer there is not an answer.
      if (mode == "software" && !ctx->is_software())
        throw std::runtime_error("the renderer is " + ctx->info_.at("renderer") +
                                 ", not a software rasterizer");
      return ctx;
    } catch (const std::exception& e) {
      failures += std::string("\n  ") +
                  (c.device ? c.device->kind + " device " + std::to_string(c.device->index)
                            : "surfaceless platform") +
                  ": " + e.what();
    }
  }
  throw std::runtime_error(
      "blurlab: could not create an OpenGL 4.5 core context on any EGL device:" + failures +
      "\nblurlab needs OpenGL 4.5 core: Mesa 20 or newer (llvmpipe), or a current NVIDIA "
      "driver. " +
      kEglInstallHint);
}

void Context::create_on(EGLDisplay display, const std::string& platform, const EglDevice* device) {
  EGLint major = 0, minor = 0;
  if (!eglInitialize(display, &major, &minor))
    throw std::runtime_error("eglInitialize failed (" + egl_error_text() + ")");
  {
    std::lock_guard<std::mutex> lock(display_mutex);
    display_users[display]++;
  }
  display_ = display;
  if (!eglBindAPI(EGL_OPENGL_API))
    throw std::runtime_error("the display has no desktop OpenGL (" + egl_error_text() + ")");

  const char* display_ext = eglQueryString(display, EGL_EXTENSIONS);
  EGLConfig config = EGL_NO_CONFIG_KHR;
  if (!has_token(display_ext, "EGL_KHR_no_config_context")) {
    const EGLint wanted[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT,
                             EGL_NONE};
    EGLint n = 0;
    if (!eglChooseConfig(display, wanted, &config, 1, &n) || n < 1)
      throw std::runtime_error("no EGL config for desktop OpenGL (" + egl_error_text() + ")");
  }
  // Asked first: to be told when the GPU resets the context (EGL 1.5). A reset loses every
  // texture, and without notification the calls after it do nothing and report no error, so
  // a read-back returns whatever the memory held. Where the driver refuses, a plain context;
  // BLURLAB_RESET_NOTIFICATION=0 asks for the plain one, to compare a driver's resets with and
  // without notification (docs/gpu.md).
  const char* notification = std::getenv("BLURLAB_RESET_NOTIFICATION");
  const bool ask_notification = !(notification && std::string(notification) == "0");
  EGLint attributes[] = {EGL_CONTEXT_MAJOR_VERSION,
                         4,
                         EGL_CONTEXT_MINOR_VERSION,
                         5,
                         EGL_CONTEXT_OPENGL_PROFILE_MASK,
                         EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                         EGL_CONTEXT_OPENGL_RESET_NOTIFICATION_STRATEGY,
                         EGL_LOSE_CONTEXT_ON_RESET,
                         EGL_NONE};
  if (ask_notification && (major > 1 || (major == 1 && minor >= 5)))
    context_ = eglCreateContext(display, config, EGL_NO_CONTEXT, attributes);
  if (context_ == EGL_NO_CONTEXT) {
    eglGetError();  // the refusal of the notification, not a failure yet
    attributes[6] = EGL_NONE;
    context_ = eglCreateContext(display, config, EGL_NO_CONTEXT, attributes);
  }
  if (context_ == EGL_NO_CONTEXT)
    throw std::runtime_error("eglCreateContext for OpenGL 4.5 core failed (" + egl_error_text() +
                             ")");
  owner_ = std::this_thread::get_id();
  if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context_))
    throw std::runtime_error("eglMakeCurrent without a surface failed (" + egl_error_text() + ")");
  load_gl();
  GLint gl_major = 0, gl_minor = 0;
  glGetIntegerv(GL_MAJOR_VERSION, &gl_major);
  glGetIntegerv(GL_MINOR_VERSION, &gl_minor);
  if (gl_major * 10 + gl_minor < 45)
    throw std::runtime_error("the context offers OpenGL " + std::to_string(gl_major) + "." +
                             std::to_string(gl_minor) + ", blurlab needs 4.5");

  auto str = [](GLenum name) {
    const GLubyte* s = glGetString(name);
    return std::string(s ? reinterpret_cast<const char*>(s) : "");
  };
  info_["vendor"] = str(GL_VENDOR);
  info_["renderer"] = str(GL_RENDERER);
  info_["version"] = str(GL_VERSION);
  info_["glsl_version"] = str(GL_SHADING_LANGUAGE_VERSION);
  info_["egl_version"] = std::to_string(major) + "." + std::to_string(minor);
  info_["egl_platform"] = platform;
  const std::string& renderer = info_["renderer"];
  bool software_renderer = renderer.find("llvmpipe") != std::string::npos ||
                           renderer.find("softpipe") != std::string::npos;
  software_ = device ? device->kind == "software" : software_renderer;
  info_["device"] = software_ ? "software" : "gpu";
  info_["device_index"] = device ? std::to_string(device->index) : "-1";
  info_["device_name"] = device ? device->name : "surfaceless";
  info_["timer"] = timer_queries_valid() ? "gl_time_elapsed" : "wall_glfinish";
  const char* sync = std::getenv("BLURLAB_SYNC_PASSES");
  sync_passes_ = sync && std::string(sync) == "1";
  info_["sync_passes"] = sync_passes_ ? "on" : "off";
  info_["passes_in_flight"] =
      max_passes_in_flight_ ? std::to_string(max_passes_in_flight_) : "unbounded";
  info_["passes_per_fence"] = max_passes_in_flight_ ? std::to_string(passes_per_fence_) : "none";
  GLint strategy = 0;
  glGetIntegerv(GL_RESET_NOTIFICATION_STRATEGY, &strategy);
  info_["reset_notification"] = strategy == GL_LOSE_CONTEXT_ON_RESET ? "lose_context" : "none";
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max_texture_size_);
  info_["max_texture_size"] = std::to_string(max_texture_size_);
  // Transfers move tightly packed rows of any width.
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  check_gl("context setup");
}

Context::~Context() {
  if (context_ != EGL_NO_CONTEXT) {
    if (try_make_current()) {
      run_deferred();
      spare_pack_buffers_.clear();
      glFinish();
      drop_passes_in_flight();
    }
    if (eglGetCurrentContext() == context_)
      eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(display_, context_);
  }
  if (display_ != EGL_NO_DISPLAY) release_display(display_);
}

void Context::make_current() {
  if (std::this_thread::get_id() != owner_)
    throw std::runtime_error(
        "blurlab: this Context belongs to the thread that created it; an OpenGL context is "
        "current on one thread at a time. Create a Context in each thread that renders.");
  if (eglGetCurrentContext() != context_ &&
      !eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_))
    throw std::runtime_error("blurlab: eglMakeCurrent failed (" + egl_error_text() + ")");
  if (has_deferred_.load()) run_deferred();
}

void Context::release(const char* kind, std::function<void()> free) noexcept {
  if (try_make_current()) {
    free();
    if (kind) track(kind, -1);
    return;
  }
  try {
    std::lock_guard<std::mutex> lock(mutex_);
    deferred_.emplace_back(kind ? kind : "", std::move(free));
    has_deferred_ = true;
  } catch (...) {
    // No memory to queue the release: the object leaks (live_objects() still counts it).
  }
}

void Context::run_deferred() {
  std::vector<std::pair<std::string, std::function<void()>>> work;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    work.swap(deferred_);
    has_deferred_ = false;
  }
  for (auto& [kind, free] : work) {
    free();
    if (!kind.empty()) track(kind.c_str(), -1);
  }
}

bool Context::try_make_current() noexcept {
  if (std::this_thread::get_id() != owner_) return false;
  if (eglGetCurrentContext() == context_) return true;
  return eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_) == EGL_TRUE;
}

std::vector<std::string> Context::gl_errors() {
  make_current();
  std::vector<std::string> errors;
  for (int i = 0; i < 16; ++i) {
    const GLenum e = glGetError();
    if (e == GL_NO_ERROR) break;
    errors.push_back(gl_error_name(e));
  }
  return errors;
}

void Context::after_pass(const std::string& what) {
  if (sync_passes_) {
    count_wait();
    glFinish();
    check_gl(("running " + what + " (BLURLAB_SYNC_PASSES)").c_str());
  } else if (max_passes_in_flight_ > 0) {
    bound_passes_in_flight();
  }
}

void Context::bound_passes_in_flight() {
  if (++passes_since_fence_ < passes_per_fence_) return;
  passes_since_fence_ = 0;
  passes_in_flight_.push_back(glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0));
  while (!passes_in_flight_.empty() &&
         fence_reached(glClientWaitSync(passes_in_flight_.front(), 0, 0))) {
    glDeleteSync(passes_in_flight_.front());
    passes_in_flight_.pop_front();
  }
  const size_t fences = std::max<size_t>(1, max_passes_in_flight_ / passes_per_fence_);
  while (passes_in_flight_.size() > fences) {
    ++pacing_waits_;
    // A second at a time, as wait_for_fence: a reset context's fences may never signal, and
    // its next read raises ContextLost.
    while (!fence_reached(
        glClientWaitSync(passes_in_flight_.front(), GL_SYNC_FLUSH_COMMANDS_BIT, 1000000000ull))) {
      if (reset_status_name() != "none") return drop_passes_in_flight();
    }
    glDeleteSync(passes_in_flight_.front());
    passes_in_flight_.pop_front();
  }
}

void Context::drop_passes_in_flight() {
  for (GLsync fence : passes_in_flight_) glDeleteSync(fence);
  passes_in_flight_.clear();
}

std::string Context::reset_status() {
  make_current();
  return reset_status_name();
}

std::map<std::string, long long> Context::memory() {
  make_current();
  std::map<std::string, long long> result;
  if (has_gl_extension("GL_NVX_gpu_memory_info")) {
    GLint total = 0, available = 0;
    glGetIntegerv(0x9048, &total);      // GPU_MEMORY_INFO_TOTAL_AVAILABLE_MEMORY_NVX
    glGetIntegerv(0x9049, &available);  // GPU_MEMORY_INFO_CURRENT_AVAILABLE_VIDMEM_NVX
    check_gl("querying video memory");
    result["total"] = total;
    result["available"] = available;
  }
  return result;
}

void Context::finish() {
  make_current();
  count_wait();
  glFinish();
}

void Context::wait_for_fence(GLsync fence, const char* what) {
  make_current();
  count_wait();
  constexpr GLuint64 one_second = 1000000000ull;
  GLbitfield flags = GL_SYNC_FLUSH_COMMANDS_BIT;  // else an unflushed fence is never reached
  for (;;) {
    const GLenum waited = glClientWaitSync(fence, flags, one_second);
    if (fence_reached(waited)) return;
    if (waited != GL_TIMEOUT_EXPIRED) {
      check_gl(what);  // GL_CONTEXT_LOST raises ContextLost
      throw GLError(std::string("blurlab: ") + what + " failed");
    }
    // A fence of a context the GPU reset may never signal: raise rather than wait for ever.
    const std::string status = reset_status_name();
    if (status != "none")
      throw ContextLost(std::string("blurlab: ") + what + " failed: the GPU reset this context (" +
                        status + ")");
    ++fence_timeouts_;
    flags = 0;
  }
}

void Context::track(const char* kind, int delta) {
  std::lock_guard<std::mutex> lock(mutex_);
  live_[kind] += delta;
}

std::map<std::string, int> Context::live_objects() {
  if (has_deferred_.load() && try_make_current()) run_deferred();
  std::lock_guard<std::mutex> lock(mutex_);
  return live_;
}

std::shared_ptr<Buffer> Context::take_pack_buffer(size_t bytes) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    for (auto it = spare_pack_buffers_.begin(); it != spare_pack_buffers_.end(); ++it) {
      if ((*it)->size() == bytes) {
        auto buffer = *it;
        spare_pack_buffers_.erase(it);
        return buffer;
      }
    }
  }
  return std::make_shared<Buffer>(this, bytes, Buffer::Usage::readback);
}

void Context::return_pack_buffer(std::shared_ptr<Buffer> buffer) {
  std::lock_guard<std::mutex> lock(mutex_);
  // A few spares cover a pipelined readback; more would only hold pinned memory.
  if (spare_pack_buffers_.size() < 8) spare_pack_buffers_.push_back(std::move(buffer));
}

}  // namespace blurlab
