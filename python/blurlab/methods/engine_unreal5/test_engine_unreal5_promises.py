"""engine_unreal5 on the filter promises (tests/filter_promises.py): random frames and
rendered scenes match its twin; a still frame comes back unchanged, the output stays inside the
input range, zero, tiny and huge motion give no NaN, the same seed gives the same bits. TRIED says
how: the frame, the parameters that let its blur reach far enough to be tested, and the frames and
scenes it must match its twin on."""

from __future__ import annotations

from filter_promises import Tried, promise_tests

METHOD = "engine_unreal5"
TRIED = Tried(
    random=(
        ((160, 90), {}),
        ((160, 90), {"directions": 2}),
        ((97, 61), {"quality": 1, "max_blur": 12.0, "depth_extent": 0.05, "directions": 2}),
        ((130, 70), {"quality": 4, "max_blur": 30.0, "exposure": 2.5, "seed": 9}),
        ((40, 30), {"quality": 2, "max_blur": 1.0, "half_res_gather": 0, "directions": 2}),
    ),
    scenes=tuple(
        (scene, {"directions": directions})
        for scene in ("teapot_pass", "fan", "crossed_motions")
        for directions in (1, 2)
    ),
)
(
    test_random_frames_match_the_twin,
    test_rendered_scenes_match_the_twin,
    test_keeps_the_filter_promises,
) = promise_tests(METHOD, TRIED)
