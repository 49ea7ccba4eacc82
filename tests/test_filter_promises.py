"""The filter promises (tests/filter_promises.py) on the example method, on each of its
backends: random frames and a rendered scene match its twin; a still frame comes back unchanged,
the output stays inside the input range, zero, tiny and huge motion give no NaN, the same seed
gives the same bits. Each filter that is tried on the promises says how in its folder
(python/blurlab/methods/<name>/test_<name>_promises.py: the frame, the parameters that let its
blur reach far enough to be tested, the frames and scenes it must match its twin on) and binds
the same tests (filter_promises.promise_tests)."""

from __future__ import annotations

from filter_promises import Tried, promise_tests
from method_picks import EXAMPLE

import blurlab as bl

TRIED = Tried(
    backends=bl.method(EXAMPLE).backends,
    random=(((160, 90), {}), ((97, 61), {"k": 8, "samples": 3, "seed": 9})),
    scenes=(("teapot_pass", {}), ("crossing", {})),
)
(
    test_random_frames_match_the_twin,
    test_rendered_scenes_match_the_twin,
    test_keeps_the_filter_promises,
) = promise_tests(EXAMPLE, TRIED)
