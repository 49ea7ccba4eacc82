// Parameters of the reconstruction filter, docs/spec.md §3 (McGuire et al., I3D 2012). The same
// names in C++, Python (bl.blur(..., k=20, samples=15, ...)) and the docs.
//
// | name     | default                          | allowed             |
// |----------|----------------------------------|---------------------|
// | k        | 20 (tile size = largest blur, px) | 1 .. 256           |
// | samples  | 15                               | 1 .. 256            |
// | soft_z   | 0.01 x the frame's depth range   | > 0, finite         |
// | exposure | 1                                | 0 .. 1000           |
// | seed     | 0                                | 0 .. 2^32 - 1       |
//
// Options of the filters (docs/guertin2014.md "Options"); off by default, so docs/spec.md §3.4
// holds:
//
// | name             | default | allowed                                             |
// |------------------|---------|-----------------------------------------------------|
// | jitter_tiles     | false   | jittered NeighborMax lookup (Unity / KinoMotion)    |
// | adaptive_samples | false   | S scaled with the neighborhood's motion length      |
// | early_exit       | 0       | finite, >= 0: pixels whose 2|vN| is under it return C |
#pragma once

#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>

namespace blurlab {

struct McGuire2012Params {
  int k = 20;
  int samples = 15;
  float soft_z = 0.01f;
  float exposure = 1.0f;
  uint32_t seed = 0;
  bool jitter_tiles = false;
  bool adaptive_samples = false;
  float early_exit = 0.0f;

  // Throws std::invalid_argument naming the parameter, its value and the allowed range.
  void validate() const {
    if (k < 1 || k > 256)
      throw std::invalid_argument("blurlab: k = " + std::to_string(k) +
                                  " is outside 1..256 (tile size in pixels)");
    if (samples < 1 || samples > 256)
      throw std::invalid_argument("blurlab: samples = " + std::to_string(samples) +
                                  " is outside 1..256");
    if (!(soft_z > 0.0f) || !std::isfinite(soft_z))
      throw std::invalid_argument("blurlab: soft_z = " + std::to_string(soft_z) +
                                  " must be finite and > 0 (depth units)");
    // Above 1000 x the largest motion (2^20 px, shaders/common/inputs.glsl) half-vectors
    // would overflow float32.
    if (!std::isfinite(exposure) || exposure < 0.0f || exposure > 1000.0f)
      throw std::invalid_argument("blurlab: exposure = " + std::to_string(exposure) +
                                  " is outside 0..1000");
    if (!std::isfinite(early_exit) || early_exit < 0.0f)
      throw std::invalid_argument("blurlab: early_exit = " + std::to_string(early_exit) +
                                  " must be finite and >= 0 (pixels; 0 = off)");
  }
};

}  // namespace blurlab
