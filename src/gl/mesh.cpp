#include "gl/mesh.h"

#include <algorithm>
#include <array>
#include <iterator>

#include "gl/context.h"

namespace blurlab {

Mesh::Mesh(std::shared_ptr<Context> context, const MeshData& data)
    : context_(std::move(context)),
      triangle_count_(data.triangle_count),
      skinned_(data.bone_indices != nullptr) {
  if (data.vertex_count == 0 || data.triangle_count == 0)
    throw std::invalid_argument("blurlab: a mesh needs at least one vertex and one triangle");
  if (!data.positions || !data.normals || !data.texcoords || !data.indices ||
      (data.bone_indices == nullptr) != (data.bone_weights == nullptr))
    throw std::invalid_argument("blurlab: mesh data is missing an attribute");
  context_->make_current();
  glCreateVertexArrays(1, &vao_);
  glCreateBuffers(6, buffers_);
  auto attribute = [&](int slot, GLuint location, const void* values, size_t components,
                       bool integer) {
    const size_t bytes = data.vertex_count * components * 4;
    glNamedBufferStorage(buffers_[slot], static_cast<GLsizeiptr>(bytes), values, 0);
    glVertexArrayVertexBuffer(vao_, location, buffers_[slot], 0,
                              static_cast<GLsizei>(components * 4));
    if (integer)
      glVertexArrayAttribIFormat(vao_, location, static_cast<GLint>(components), GL_UNSIGNED_INT,
                                 0);
    else
      glVertexArrayAttribFormat(vao_, location, static_cast<GLint>(components), GL_FLOAT, GL_FALSE,
                                0);
    glVertexArrayAttribBinding(vao_, location, location);
    glEnableVertexArrayAttrib(vao_, location);
  };
  attribute(0, kPosition, data.positions, 3, false);
  attribute(1, kNormal, data.normals, 3, false);
  attribute(2, kTexcoord, data.texcoords, 2, false);
  if (skinned_) {
    attribute(3, kBoneIndex, data.bone_indices, 4, true);
    attribute(4, kBoneWeight, data.bone_weights, 4, false);
  }
  glNamedBufferStorage(buffers_[5], static_cast<GLsizeiptr>(data.triangle_count * 3 * 4),
                       data.indices, 0);
  glVertexArrayElementBuffer(vao_, buffers_[5]);
  check_gl("creating a mesh");
  context_->track("mesh", +1);
}

Mesh::~Mesh() {
  std::array<GLuint, 6> buffers;
  std::copy(std::begin(buffers_), std::end(buffers_), buffers.begin());
  context_->release("mesh", [vao = vao_, buffers] {
    glDeleteVertexArrays(1, &vao);
    glDeleteBuffers(6, buffers.data());
  });
}

void Mesh::draw() const {
  glBindVertexArray(vao_);
  if (!skinned_) {
    // Unskinned meshes read bone weights of zero from the constant attribute.
    glVertexAttrib4f(kBoneWeight, 0.f, 0.f, 0.f, 0.f);
    glVertexAttribI4ui(kBoneIndex, 0, 0, 0, 0);
  }
  glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(triangle_count_ * 3), GL_UNSIGNED_INT, nullptr);
}

}  // namespace blurlab
