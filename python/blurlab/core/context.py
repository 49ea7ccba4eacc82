"""``blurlab.Context``: the GL context of core.gl with the two shortcuts that render on it.

The GL context itself (core.gl) knows nothing of scenes or references; this class sits above
render and references in the core, so ``ctx.render`` and ``ctx.reference`` need no upward
import.
"""

from __future__ import annotations

from ..sizes import DEFAULT_SIZE
from .gl import GLContext
from .references import reference_render
from .render import render


class Context(GLContext):
    """An OpenGL 4.5 core context with no display, and blurlab's renders on it.

    ``device``: ``"auto"`` (a GPU if EGL finds one, else Mesa's llvmpipe), ``"gpu"`` (fails
    without one), ``"software"`` (llvmpipe), or an int that picks an EGL device by index
    (see ``Context.devices()``).
    """

    def render(
        self,
        scene,
        size=DEFAULT_SIZE,
        shutter=None,
        instant="center",
        motion_format="rg32f",
        maxlen=None,
        jitter=(0.0, 0.0),
    ):
        """Renders the G-buffer of `scene` at `size` = (W, H) and returns a ``bl.Frame``.

        ``shutter`` = (t0, t1) seconds (default: the scene's); ``instant`` is "center" (the
        reconstruction filters' choice), "close", "open" or a time in [t0, t1]. Motion is always
        t0 -> t1. ``motion_format`` stores motion as rg32f, rg16f, rgba8_offset or rgba8_polar
        (docs/spec.md §2, ``maxlen`` pixels, default the image diagonal) and returns what a method
        reading that format would decode. ``jitter`` = (dx, dy) pixels shifts the projection so
        that pixel centers show the unshifted image at (x + 0.5 - dx, y + 0.5 - dy), +y down
        (docs/spec.md §12): sub-pixel sample positions; motion is unchanged.
        """
        return render(self, scene, size, shutter, instant, motion_format, maxlen, jitter=jitter)

    # ctx.reference(scene, size, shutter, samples, ...): its parameters and doc are
    # reference_render's, declared once there.
    reference = reference_render
