#include "gl/buffer.h"

#include "gl/context.h"

namespace blurlab {

Buffer::Buffer(Context* context, size_t bytes, Usage usage) : context_(context), bytes_(bytes) {
  if (bytes == 0) throw std::invalid_argument("blurlab: a GL buffer needs at least one byte");
  context_->make_current();
  glCreateBuffers(1, &id_);
  // Client storage for the pixel-pack targets of downloads, which the CPU reads back through GL
  // (glGetNamedBufferSubData; readback.h).
  const GLbitfield flags =
      usage == Usage::readback ? GL_CLIENT_STORAGE_BIT : GL_DYNAMIC_STORAGE_BIT;
  glNamedBufferStorage(id_, static_cast<GLsizeiptr>(bytes), nullptr, flags);
  check_created("creating a GL buffer", [this] { glDeleteBuffers(1, &id_); });
  context_->track("buffer", +1);
}

Buffer::~Buffer() {
  context_->release("buffer", [id = id_] { glDeleteBuffers(1, &id); });
}

}  // namespace blurlab
