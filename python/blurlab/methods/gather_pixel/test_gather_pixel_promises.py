"""gather_pixel on the filter promises (tests/filter_promises.py): random frames and
rendered scenes match its twin; a still frame comes back unchanged, the output stays inside the
input range, zero, tiny and huge motion give no NaN, the same seed gives the same bits. TRIED says
how: the frame, the parameters that let its blur reach far enough to be tested, and the frames and
scenes it must match its twin on."""

from __future__ import annotations

from filter_promises import Tried, promise_tests

METHOD = "gather_pixel"
BOTH = ("compute", "fragment")
TRIED = Tried(
    backends=BOTH,
    random=(
        ((160, 90), {}),
        ((97, 61), {"samples": 1, "spacing": 0.5, "depth_extent": 0.05}),
        ((130, 70), {"samples": 16, "spacing": 1.0, "exposure": 2.5, "seed": 9}),
    ),
    scenes=(("teapot_pass", {}), ("crossing", {})),
)
(
    test_random_frames_match_the_twin,
    test_rendered_scenes_match_the_twin,
    test_keeps_the_filter_promises,
) = promise_tests(METHOD, TRIED)
