"""gather_coverage on the filter promises (tests/filter_promises.py): random frames and
rendered scenes match its twin; a still frame comes back unchanged, the output stays inside the
input range, zero, tiny and huge motion give no NaN, the same seed gives the same bits. TRIED says
how: the frame, the parameters that let its blur reach far enough to be tested, and the frames and
scenes it must match its twin on."""

from __future__ import annotations

from filter_promises import Tried, promise_tests, two_sided_frame

METHOD = "gather_coverage"
SCENES = ("teapot_pass", "fan", "skinned_arm", "crossing")
TRIED = Tried(
    two_sided_frame,
    inside={"max_blur": 40.0},
    huge={"max_blur": 50.0},
    random=(
        ((160, 90), {}),
        ((97, 61), {"tile_percent": 20.0, "samples": 5, "max_blur": 60.0, "soft_z": 2.0}),
        ((130, 70), {"samples": 2, "exposure": 2.5, "seed": 9}),
        ((40, 30), {"tile_percent": 1.0, "samples": 16, "max_blur": 10.0, "soft_z": 0.01}),
        ((160, 90), {"film_filter": 0.5}),
        ((64, 48), {"film_filter": 1.3, "samples": 6}),
        ((160, 90), {"film_filter": 0.5, "film_through_taps": True}),
        ((61, 37), {"film_filter": 0.7, "film_through_taps": True, "samples": 5, "seed": 4}),
        ((160, 90), {"tap_spacing": 3.0}),
        ((97, 61), {"tap_spacing": 1.5, "samples": 15, "early_exit": 6.0}),
        ((130, 70), {"uniform_tolerance": 8.0, "samples": 7, "seed": 2}),
        ((97, 61), {"half_res_above": 6.0, "tap_spacing": 2.0}),
    ),
    scenes=tuple((scene, {}) for scene in (*SCENES, "occluder", "moire")),
)
(
    test_random_frames_match_the_twin,
    test_rendered_scenes_match_the_twin,
    test_keeps_the_filter_promises,
) = promise_tests(METHOD, TRIED)
