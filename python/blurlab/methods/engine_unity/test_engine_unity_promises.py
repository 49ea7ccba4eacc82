"""engine_unity on the filter promises (tests/filter_promises.py): random frames and
rendered scenes match its twin; a still frame comes back unchanged, the output stays inside the
input range, zero, tiny and huge motion give no NaN, the same seed gives the same bits. TRIED says
how: the frame, the parameters that let its blur reach far enough to be tested, and the frames and
scenes it must match its twin on."""

from __future__ import annotations

from filter_promises import Tried, promise_tests

METHOD = "engine_unity"
SCENES = ("teapot_pass", "fan", "skinned_arm", "crossing")
TRIED = Tried(
    inside={"max_radius": 15.0},
    huge={"max_radius": 50.0},
    random=(
        ((160, 90), {}),
        ((97, 61), {"samples": 4, "max_radius": 12.0, "depth_factor": 3.0}),
        ((130, 70), {"samples": 32, "max_radius": 40.0, "exposure": 2.5, "seed": 9}),
        ((40, 30), {"samples": 7, "max_radius": 1.0, "far": 4.0}),
    ),
    scenes=tuple((scene, {}) for scene in SCENES),
)
(
    test_random_frames_match_the_twin,
    test_rendered_scenes_match_the_twin,
    test_keeps_the_filter_promises,
) = promise_tests(METHOD, TRIED)
