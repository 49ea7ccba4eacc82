// camera_only's motion, docs/spec.md §4 (Urho3D thesis §2.3.2): motion from depth and the camera's
// transforms alone — shaders/passes/camera_motion.glsl, NumPy twin
// blurlab.reference.gathers.camera_motion, tests/test_camera_only.py.
#pragma once

#include <memory>

#include "gl/program.h"

namespace blurlab {

class Context;
class Texture;

struct CameraMotionMatrices {
  float view_from_clip[16];  // row-major, as every matrix handed over from Python
  float world_from_view[16];
  float clip_from_world[2][16];  // t0, t1
  float sky_from_clip[16];
  float sky_projection[2][16];
  float near;
};

class CameraMotionPass {
 public:
  explicit CameraMotionPass(std::shared_ptr<Context> context);
  // depth R32F -> motion RG32F.
  void run(const Texture& depth, const Texture& motion, const CameraMotionMatrices& matrices);

 private:
  std::shared_ptr<Context> context_;
  std::shared_ptr<Program> program_;
};

}  // namespace blurlab
