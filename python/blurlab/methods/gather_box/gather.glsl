#version 450
// gather_box, docs/spec.md §4 ("Blurry things"): n equal taps along the G-buffer's motion, the
// box gather of common/box_gather.glsl. Compute (default) or fragment. NumPy twin: twin.py,
// gather_box.
#include "common/box_gather.glsl"

#define PASS_AT box_gather_at
#include "common/pass_main.glsl"
