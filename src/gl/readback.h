// Asynchronous texture download: the copy into a persistently mapped pixel-pack buffer is queued
// with a fence, so the caller can queue more GPU work (or more downloads) before waiting.
// docs/gpu.md measured 2-3 GB/s for a plain glReadPixels on the H100; this path overlaps transfers.
#pragma once

#include <memory>

#include "gl/gl.h"

namespace blurlab {

class Buffer;
class Context;
class Texture;

class PendingDownload {
 public:
  explicit PendingDownload(const Texture& texture);
  ~PendingDownload();
  PendingDownload(const PendingDownload&) = delete;
  PendingDownload& operator=(const PendingDownload&) = delete;

  // True once the GPU has finished the copy (never blocks).
  bool done();
  // Blocks until the copy is complete; the data then lies at mapped().
  void wait();
  const void* mapped() const;
  size_t size() const;
  // Hands the pixel-pack buffer over (for zero-copy arrays) or back to the context's pool.
  std::shared_ptr<Buffer> take_buffer();
  const std::shared_ptr<Context>& context() const { return context_; }

 private:
  std::shared_ptr<Context> context_;
  std::shared_ptr<Buffer> buffer_;
  GLsync fence_ = nullptr;
};

}  // namespace blurlab
