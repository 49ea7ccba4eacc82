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

double PairReduction::sum(Program& program, const Texture& a, const Texture& b) {
  if (a.width() != b.width() || a.height() != b.height())
    throw std::invalid_argument("blurlab: compared images differ in size: " + size_of(a) + " and " +
                                size_of(b));
  if (a.format().channels < 3 || b.format().channels < 3)
    throw std::invalid_argument("blurlab: compared images need RGB channels");
  const auto local = program.local_size();
  const int gx = (a.width() + local[0] - 1) / local[0], gy = (a.height() + local[1] - 1) / local[1];
  const size_t groups = size_t(gx) * gy;
  if (!partials_ || partials_->size() < groups * sizeof(float))
    partials_ = std::make_unique<Buffer>(context_, groups * sizeof(float), Buffer::Usage::storage);
  program.bind_texture(0, a);
  program.bind_texture(1, b);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, partials_->id());
  program.dispatch(gx, gy, 1);
  host_.resize(groups);
  glGetNamedBufferSubData(partials_->id(), 0, static_cast<GLsizeiptr>(groups * sizeof(float)),
                          host_.data());
  check_gl("reading back partial sums");
  double sum = 0.0;
  for (float v : host_) sum += v;
  return sum;
}

}  // namespace blurlab
