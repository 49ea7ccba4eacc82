// A triangle mesh on the GPU: positions, normals, texture coordinates and, for skinned meshes,
// up to four bone indices and weights per vertex. One vertex array object, one buffer per
// attribute, 32-bit indices.
#pragma once

#include <cstdint>
#include <memory>

#include "gl/gl.h"

namespace blurlab {

class Context;

// Attribute locations shared with shaders/passes/gbuffer.vert.
enum MeshAttribute : GLuint {
  kPosition = 0,
  kNormal = 1,
  kTexcoord = 2,
  kBoneIndex = 3,
  kBoneWeight = 4
};

struct MeshData {
  const float* positions = nullptr;        // vertex_count × 3
  const float* normals = nullptr;          // vertex_count × 3
  const float* texcoords = nullptr;        // vertex_count × 2
  const uint32_t* bone_indices = nullptr;  // vertex_count × 4, or nullptr
  const float* bone_weights = nullptr;     // vertex_count × 4, or nullptr
  const uint32_t* indices = nullptr;       // triangle_count × 3
  size_t vertex_count = 0;
  size_t triangle_count = 0;
};

class Mesh : NotCopyable {
 public:
  Mesh(std::shared_ptr<Context> context, const MeshData& data);
  ~Mesh();

  void draw() const;
  bool skinned() const { return skinned_; }
  size_t triangle_count() const { return triangle_count_; }

 private:
  std::shared_ptr<Context> context_;
  GLuint vao_ = 0;
  GLuint buffers_[6] = {0, 0, 0, 0, 0, 0};
  size_t triangle_count_;
  bool skinned_;
};

}  // namespace blurlab
