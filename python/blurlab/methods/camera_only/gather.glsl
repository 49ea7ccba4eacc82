#version 450
// camera_only's gather, docs/spec.md §4: the box gather of common/box_gather.glsl along the
// motion camera_motion.glsl wrote. Compute (default) or fragment. NumPy twin: twin.py,
// camera_only.
#include "common/box_gather.glsl"

#define PASS_AT box_gather_at
#include "common/pass_main.glsl"
