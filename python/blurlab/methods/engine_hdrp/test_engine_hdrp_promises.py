"""engine_hdrp on the filter promises (tests/filter_promises.py): random frames and
rendered scenes match its twin; a still frame comes back unchanged, the output stays inside the
input range, zero, tiny and huge motion give no NaN, the same seed gives the same bits. TRIED says
how: the frame, the parameters that let its blur reach far enough to be tested, and the frames and
scenes it must match its twin on."""

from __future__ import annotations

from filter_promises import Tried, promise_tests

METHOD = "engine_hdrp"
TRIED = Tried(
    inside={"fast_ratio": 0.2},
    huge={"maximum_velocity": 65024.0},
    random=(
        ((160, 90), {}),
        ((97, 61), {"samples": 4, "maximum_velocity": 12.0, "depth_comparison_extent": 0.3}),
        ((130, 70), {"samples": 12, "intensity": 2.5, "seed": 9, "fast_ratio": 0.05}),
        ((150, 80), {"scatter": True, "minimum_velocity": 6.0}),
        ((40, 30), {"samples": 64, "minimum_velocity": 0.0, "fast_ratio": 1.0}),
    ),
    scenes=(
        ("teapot_pass", {}),
        ("fan", {}),
        ("crossing", {}),
        ("fan", {"scatter": True}),
        ("camera_yaw", {"camera_clamp_mode": "rotation"}),
        ("vehicle", {"camera_clamp_mode": "separate", "translation_clamp": 0.01}),
        ("vehicle", {"camera_clamp_mode": "full", "scatter": True}),
        ("vehicle", {"camera_motion_blur": False}),
    ),
)
(
    test_random_frames_match_the_twin,
    test_rendered_scenes_match_the_twin,
    test_keeps_the_filter_promises,
) = promise_tests(METHOD, TRIED)
