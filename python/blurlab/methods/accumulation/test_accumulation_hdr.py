"""accumulation keeps HDR values (docs/hdr.md): on a still scene it averages N equal renders at
the pixel centres, so a 1000x pixel, and every other, comes back to float32 rounding. What
every method keeps is in tests/test_hdr.py."""

from __future__ import annotations

import numpy as np
from test_hdr import BRIGHT, SIZE, lamp_scene

import blurlab as bl

METHOD = "accumulation"


def test_a_bright_pixel_passes_its_still_path_unchanged(ctx):
    frame = ctx.render(lamp_scene(), SIZE, instant=bl.method_instant(METHOD, {}))
    color = frame.color
    assert (color[..., :3] == BRIGHT).all(axis=-1).sum() >= 1
    frame.motion[...] = 0.0
    out = bl.blur(ctx, frame, METHOD).color
    np.testing.assert_allclose(out, color, rtol=1e-5)  # N renders times 1/N each
