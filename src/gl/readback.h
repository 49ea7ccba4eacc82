// Asynchronous texture download: the copy into a pixel-pack buffer is queued with a fence, so the
// caller can queue more GPU work (or more downloads) before waiting; read() then takes the bytes
// through GL.
// docs/gpu.md measured 2-3 GB/s for a plain glReadPixels on the H100; this path overlaps transfers.
#pragma once

#include <memory>

#include "gl/gl.h"

namespace blurlab {

class Buffer;
class Context;
class Texture;

class PendingDownload : NotCopyable {
 public:
  explicit PendingDownload(const Texture& texture);
  ~PendingDownload();

  // True once the GPU has finished the copy (never blocks).
  bool done();
  // Blocks until the copy is complete.
  void wait();
  // Waits, then reads the image's size() bytes into `destination` with glGetNamedBufferSubData
  // (the buffer is not mapped). On the H100 the copy once differed from a synchronous download
  // right after a long translucent reference, read either way (docs/foundation.md).
  void read(void* destination);
  size_t size() const;

 private:
  std::shared_ptr<Context> context_;
  std::shared_ptr<Buffer> buffer_;
  size_t bytes_;  // the image's, at most the pooled buffer's size
  GLsync fence_ = nullptr;
};

}  // namespace blurlab
