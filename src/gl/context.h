// An OpenGL 4.5 core context created through EGL with no display (no window, no X server).
// Device choice: a hardware GPU where EGL enumerates one, else Mesa's software device
// (llvmpipe), else Mesa's surfaceless platform. docs/architecture.md, "What Python sees of the
// context".
#pragma once

#include <atomic>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "gl/gl.h"

namespace blurlab {

class Buffer;

// One EGL device as eglQueryDevicesEXT lists it.
struct EglDevice {
  int index = 0;
  std::string kind;        // "gpu" or "software"
  std::string name;        // DRM node, CUDA ordinal or "software"
  std::string extensions;  // the device's EGL extension string
};

// What the caller asks for: mode "auto", "gpu" or "software", or mode "index" with `index`.
struct DeviceRequest {
  std::string mode = "auto";
  int index = -1;
};

class Context : public std::enable_shared_from_this<Context>, NotCopyable {
 public:
  static std::shared_ptr<Context> create(const DeviceRequest& request, std::string shader_dir);
  static std::vector<EglDevice> devices();
  ~Context();

  // Makes this context current on the calling thread. Throws if the thread is not the one that
  // created the context: a GL context is current on one thread at a time.
  void make_current();
  // For destructors, which may run on any thread and must not throw: true if current now.
  // Never true on a thread other than the owner: taking the context away from its thread would
  // leave the owner unable to make it current again. (The object's GL name then leaks, and
  // live_objects() still counts it.)
  bool try_make_current() noexcept;
  // Frees a GL object: now, where this thread owns the context, else at the owner's next
  // make_current(). Destructors call it, since Python may drop the last reference to an object
  // on any thread; `kind` (or nullptr) is what track() counted. Never throws.
  void release(const char* kind, std::function<void()> free) noexcept;
  // Reads and clears every pending GL error, without throwing: the names of the errors that
  // were set ("GL_INVALID_VALUE", ...), empty if none. Tests assert it after each call.
  std::vector<std::string> gl_errors();
  // Whether the GPU reset this context since it was made: "none", "guilty" (its own work
  // caused it), "innocent" or "unknown". Always "none" where info()["reset_notification"] is
  // "none": the driver would not tell.
  std::string reset_status();
  // Video memory in KiB where the driver reports it (GL_NVX_gpu_memory_info: "total",
  // "available"); empty on drivers without it, llvmpipe included.
  std::map<std::string, long long> memory();

  // After each pass: where BLURLAB_SYNC_PASSES=1 was set when the context was made, waits for the
  // GPU and checks for errors, so that a GPU fault or reset is reported by the pass that caused
  // it (ContextLost names it) rather than by a later read. Otherwise it keeps at most
  // kPassesInFlight issued passes unfinished (BLURLAB_PASSES_IN_FLIGHT=N: N, 0 for no bound):
  // a fence after every (bound / kFencesInFlight)th pass, and a wait for the oldest fence
  // beyond kFencesInFlight of them (docs/spec.md §6.3).
  void after_pass(const std::string& what);
  // Loops that issue without reading (a benchmark's untimed calls, a reference's sub-frames)
  // queue seconds of draws, and the H100's driver reset a benchmark's context in one. 32 passes
  // are at most about half a second of the slowest pass there (a 14 ms G-buffer at 1080p), and a
  // CPU that outruns the GPU waits only while 32 are queued, so the GPU is never left idle.
  static constexpr size_t kPassesInFlight = 32;
  // A fence after every pass cost the H100 a quarter of a short filter's time (guertin2014's
  // 0.085 ms a call became 0.109 at 1080p, queue_depth): the next pass no longer overlaps the
  // last. Four fences over the bound's passes check it about as closely with an eighth of the
  // fences, for +1 % (queue_depth).
  static constexpr size_t kFencesInFlight = 4;
  // Waits of that bound (not counted in waits(): nothing is read).
  long long pacing_waits() const { return pacing_waits_; }

  const std::map<std::string, std::string>& info() const { return info_; }
  bool is_software() const { return software_; }
  // llvmpipe's timer queries report nonsense (docs/gpu.md), so software contexts time by wall
  // clock.
  bool timer_queries_valid() const { return !software_; }
  const std::string& shader_dir() const { return shader_dir_; }
  int max_texture_size() const { return max_texture_size_; }
  void finish();

  // CPU waits for the GPU (glFinish, a timer query's result, a texture download, an
  // asynchronous download's fence), counted so that tests can show a loop issues none per step.
  void count_wait() { ++waits_; }
  long long waits() const { return waits_; }
  // Blocks until `fence` is signalled, counting one wait; throws GLError naming `what` if the
  // wait fails. It waits a second at a time: GL_TIMEOUT_IGNORED is defined for glWaitSync, not
  // glClientWaitSync, and a wait a driver cut short would let the caller read a result the GPU
  // had not finished.
  void wait_for_fence(GLsync fence, const char* what);
  // Waits of wait_for_fence that the driver ended before the fence was signalled (each then
  // waited again): nonzero only on a busy GPU, and a sign of long work, not of an error.
  long long fence_timeouts() const { return fence_timeouts_; }
  // Batches of partial sums that ReductionQueue::read found not written by their passes (a
  // missing ticket) and refused: each is evaluated again by its caller.
  long long stale_readbacks() const { return stale_readbacks_; }
  void count_stale_readback() { ++stale_readbacks_; }

  // Live GL objects by kind ("texture", "buffer", "program", "query"), so tests can show that
  // freeing objects returns the count to where it was.
  void track(const char* kind, int delta);
  // On the owner's thread, releases queued by other threads are done first.
  std::map<std::string, int> live_objects();

  // Pool of the pixel-pack buffers of asynchronous downloads, in client memory: allocating one
  // for every download would cost more than the copy itself.
  std::shared_ptr<Buffer> take_pack_buffer(size_t bytes);
  void return_pack_buffer(std::shared_ptr<Buffer> buffer);

 private:
  Context() = default;
  void create_on(EGLDisplay display, const std::string& platform, const EglDevice* device);

  EGLDisplay display_ = EGL_NO_DISPLAY;
  EGLContext context_ = EGL_NO_CONTEXT;
  std::thread::id owner_;
  bool software_ = false;
  bool sync_passes_ = false;
  // The bound on unfinished passes (0: none); the passes between two fences and those issued
  // since the last; the fences issued under the bound, oldest first.
  size_t max_passes_in_flight_ = 0;
  size_t passes_per_fence_ = 1;
  size_t passes_since_fence_ = 0;
  std::deque<GLsync> passes_in_flight_;
  long long pacing_waits_ = 0;  // the owner thread's, as fence_timeouts_
  void bound_passes_in_flight();
  void drop_passes_in_flight();
  int max_texture_size_ = 0;
  std::string shader_dir_;
  std::map<std::string, std::string> info_;
  void run_deferred();

  // Guards live_, deferred_ and spare_pack_buffers_ (destructors may run on any thread).
  mutable std::mutex mutex_;
  std::map<std::string, int> live_;
  long long waits_ = 0;  // the owner thread's: every wait runs there
  long long fence_timeouts_ = 0;
  long long stale_readbacks_ = 0;  // the owner thread's, as fence_timeouts_
  // Declared before spare_pack_buffers_: a spare buffer destroyed with the context queues its
  // release here, so this must still exist then.
  std::vector<std::pair<std::string, std::function<void()>>> deferred_;
  std::atomic<bool> has_deferred_{false};
  std::vector<std::shared_ptr<Buffer>> spare_pack_buffers_;
};

}  // namespace blurlab
