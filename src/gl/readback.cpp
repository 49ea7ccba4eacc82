#include "gl/readback.h"

#include "gl/buffer.h"
#include "gl/context.h"
#include "gl/texture.h"

namespace blurlab {

PendingDownload::PendingDownload(const Texture& texture)
    : context_(texture.context()), bytes_(texture.byte_size()) {
  buffer_ = context_->take_pack_buffer(texture.byte_size());
  context_->make_current();
  const auto& f = texture.format();
  glBindBuffer(GL_PIXEL_PACK_BUFFER, buffer_->id());
  glGetTextureImage(texture.id(), 0, f.pixel_format, f.pixel_type,
                    static_cast<GLsizei>(texture.byte_size()), nullptr);
  glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
  glMemoryBarrier(GL_CLIENT_MAPPED_BUFFER_BARRIER_BIT);
  fence_ = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
  // Without a flush the copy may sit in the command queue until someone waits on it.
  glFlush();
  check_gl("queueing an asynchronous download");
}

PendingDownload::~PendingDownload() {
  // The buffer goes back to the pool once the GPU has finished writing it.
  context_->release(nullptr,
                    [fence = fence_, buffer = std::move(buffer_), context = context_.get()] {
                      bool written = true;
                      if (fence) {
                        try {
                          context->wait_for_fence(fence, "waiting for a dropped download");
                        } catch (...) {
                          written = false;  // the GPU may still write it: not pooled again
                        }
                        glDeleteSync(fence);
                      }
                      if (buffer && written) context->return_pack_buffer(buffer);
                    });
}

bool PendingDownload::done() {
  if (!fence_) return true;
  context_->make_current();
  GLint status = GL_UNSIGNALED;
  glGetSynciv(fence_, GL_SYNC_STATUS, 1, nullptr, &status);
  return status == GL_SIGNALED;
}

void PendingDownload::wait() {
  if (!fence_) return;
  const GLsync fence = fence_;
  fence_ = nullptr;
  try {
    context_->wait_for_fence(fence, "waiting for an asynchronous download");
  } catch (...) {
    glDeleteSync(fence);
    throw;
  }
  glDeleteSync(fence);
}

void PendingDownload::read(void* destination) {
  wait();
  context_->make_current();
  glGetNamedBufferSubData(buffer_->id(), 0, static_cast<GLsizeiptr>(bytes_), destination);
  check_gl("reading a finished download");
}

size_t PendingDownload::size() const {
  return bytes_;
}

}  // namespace blurlab
