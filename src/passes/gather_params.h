// Parameters of the engines' gathers, docs/spec.md §4.
//
// | name      | default   | allowed                        |
// |-----------|-----------|--------------------------------|
// | taps      | 10        | 2 .. 256 (gather_box)          |
// | intensity | 1         | 0 .. 1000 (gather_box)         |
// | centered  | false     | gather_box's direction         |
// | edge      | "clamp"   | "clamp", "ignore" ("guard" is clamp on a frame rendered with a
//                           margin, handled by the Python side)                               |
#pragma once

#include <cmath>
#include <stdexcept>
#include <string>

namespace blurlab {

struct GatherParams {
  int taps = 10;
  float intensity = 1.0f;
  bool centered = false;
  std::string edge = "clamp";

  void validate() const {
    if (taps < 2 || taps > 256)
      throw std::invalid_argument("blurlab: taps = " + std::to_string(taps) +
                                  " is outside 2..256 (n)");
    // Tap positions stay below 2^31 pixels (GLSL's float-to-int range) for motion up to the
    // 2^20 px that shaders/common/inputs.glsl keeps.
    if (!std::isfinite(intensity) || intensity < 0.0f || intensity > 1000.0f)
      throw std::invalid_argument("blurlab: intensity = " + std::to_string(intensity) +
                                  " is outside 0..1000");
    if (edge != "clamp" && edge != "ignore")
      throw std::invalid_argument("blurlab: edge must be 'clamp' or 'ignore' here, not '" + edge +
                                  "'");
  }
};

}  // namespace blurlab
