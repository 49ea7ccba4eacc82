"""engine_godot on the filter promises (tests/filter_promises.py): random frames and
rendered scenes match its twin; a still frame comes back unchanged, the output stays inside the
input range, zero, tiny and huge motion give no NaN, the same seed gives the same bits. TRIED says
how: the frame, the parameters that let its blur reach far enough to be tested, and the frames and
scenes it must match its twin on."""

from __future__ import annotations

from filter_promises import Tried, promise_tests

METHOD = "engine_godot"
# Its twin checks are in its own tests (test_engine_godot.py); its promises are here.
TRIED = Tried(inside={"k": 15}, huge={"k": 256})
_, _, test_keeps_the_filter_promises = promise_tests(METHOD, TRIED)
