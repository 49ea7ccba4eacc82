"""engine_eevee on the filter promises (tests/filter_promises.py): random frames and
rendered scenes match its twin; a still frame comes back unchanged, the output stays inside the
input range, zero, tiny and huge motion give no NaN, the same seed gives the same bits. TRIED says
how: the frame, the parameters that let its blur reach far enough to be tested, and the frames and
scenes it must match its twin on."""

from __future__ import annotations

from filter_promises import Tried, promise_tests, two_sided_frame

METHOD = "engine_eevee"
SCENES = ("teapot_pass", "fan", "skinned_arm", "crossing")
TRIED = Tried(
    two_sided_frame,
    {"tile_size": 16},
    {"max_blur": 1e6, "tile_size": 16},
    random=(
        ((160, 90), {}),
        ((97, 61), {"tile_size": 8, "samples": 5, "max_blur": 40.0, "depth_scale": 2.0}),
        ((130, 70), {"tile_size": 16, "samples": 1, "exposure": 2.5, "seed": 9}),
        ((40, 30), {"tile_size": 4, "samples": 12, "max_blur": 6.0, "depth_scale": 0.5}),
    ),
    scenes=tuple((scene, {"tile_size": 16}) for scene in SCENES),
)
(
    test_random_frames_match_the_twin,
    test_rendered_scenes_match_the_twin,
    test_keeps_the_filter_promises,
) = promise_tests(METHOD, TRIED)
