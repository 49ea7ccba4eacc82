#include "gl/buffer.h"

#include "gl/context.h"

namespace blurlab {

Buffer::Buffer(Context* context, size_t bytes, Usage usage) : context_(context), bytes_(bytes) {
  if (bytes == 0) throw std::invalid_argument("blurlab: a GL buffer needs at least one byte");
  context_->make_current();
  glCreateBuffers(1, &id_);
  if (usage == Usage::readback) {
    // Client storage + persistent coherent mapping: the GPU writes straight into memory the CPU
    // reads, with no map/unmap per download (docs/gpu.md: sweeps must not stall on readback).
    const GLbitfield flags = GL_MAP_READ_BIT | GL_MAP_PERSISTENT_BIT | GL_MAP_COHERENT_BIT;
    glNamedBufferStorage(id_, static_cast<GLsizeiptr>(bytes), nullptr,
                         flags | GL_CLIENT_STORAGE_BIT);
    mapped_ = glMapNamedBufferRange(id_, 0, static_cast<GLsizeiptr>(bytes), flags);
  } else {
    glNamedBufferStorage(id_, static_cast<GLsizeiptr>(bytes), nullptr, GL_DYNAMIC_STORAGE_BIT);
  }
  try {
    check_gl("creating a GL buffer");
  } catch (...) {
    glDeleteBuffers(1, &id_);
    glGetError();
    throw;
  }
  context_->track("buffer", +1);
}

Buffer::~Buffer() {
  context_->release("buffer", [id = id_, mapped = mapped_ != nullptr] {
    if (mapped) glUnmapNamedBuffer(id);
    glDeleteBuffers(1, &id);
  });
}

}  // namespace blurlab
