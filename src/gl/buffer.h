// A GL buffer object with immutable storage. `readback` buffers live in client memory (the
// pixel-pack targets of asynchronous downloads, read back with glGetNamedBufferSubData);
// `storage` buffers are plain device memory for shader storage and atomics.
#pragma once

#include <cstddef>

#include "gl/gl.h"

namespace blurlab {

class Context;

class Buffer : NotCopyable {
 public:
  enum class Usage { storage, readback };
  // The buffer must not outlive `context`; its owner keeps the context alive.
  Buffer(Context* context, size_t bytes, Usage usage);
  ~Buffer();

  GLuint id() const { return id_; }
  size_t size() const { return bytes_; }

 private:
  Context* context_;
  GLuint id_ = 0;
  size_t bytes_;
};

}  // namespace blurlab
