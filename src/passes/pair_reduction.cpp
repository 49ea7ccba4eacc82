#include "passes/pair_reduction.h"

#include <stdexcept>
#include <string>

#include "gl/buffer.h"
#include "gl/context.h"
#include "gl/program.h"
#include "gl/texture.h"

namespace blurlab {

namespace {

std::string size_of(const Texture& t) {
  return std::to_string(t.width()) + "x" + std::to_string(t.height());
}

}  // namespace

PairReduction::PairReduction(Context* context) : context_(context) {}

PairReduction::~PairReduction() = default;

std::vector<double> PairReduction::sums(Program& program, const Texture& a, const Texture& b,
                                        std::array<int, 2> tile, int components) {
  if (a.width() != b.width() || a.height() != b.height())
    throw std::invalid_argument("blurlab: compared images differ in size: " + size_of(a) + " and " +
                                size_of(b));
  if (a.format().channels < 3 || b.format().channels < 3)
    throw std::invalid_argument("blurlab: compared images need RGB channels");
  const int gx = (a.width() + tile[0] - 1) / tile[0], gy = (a.height() + tile[1] - 1) / tile[1];
  const size_t count = size_t(gx) * gy * components;
  if (!partials_ || partials_->size() < count * sizeof(float))
    partials_ = std::make_unique<Buffer>(context_, count * sizeof(float), Buffer::Usage::storage);
  program.bind_texture(0, a);
  program.bind_texture(1, b);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, partials_->id());
  program.dispatch(gx, gy, 1);
  host_.resize(count);
  glGetNamedBufferSubData(partials_->id(), 0, static_cast<GLsizeiptr>(count * sizeof(float)),
                          host_.data());
  check_gl("reading back partial sums");
  std::vector<double> out(components, 0.0);
  for (size_t i = 0; i < count; ++i) out[i % components] += host_[i];
  return out;
}

}  // namespace blurlab
