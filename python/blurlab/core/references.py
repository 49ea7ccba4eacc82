"""The converged reference (docs/spec.md §1 "Reference"): N full renders across the shutter,
averaged in float32 on the GPU. ``ctx.reference(...)`` and ``bl.reference_samples_needed``."""

from __future__ import annotations

import dataclasses
import math
import weakref
from contextlib import nullcontext
from dataclasses import dataclass, field

import numpy as np

from ..scene.blur_scales import scaled_scene
from ..scene.model import Scene
from ..scene.sampling import shutter_samples
from ..sizes import DEFAULT_SIZE
from ..twins.sub_frames import sample_times
from .frame import Frame
from .render import (
    check_fragment_capacity,
    check_shutter,
    check_size,
    render,
    render_base,
    render_targets,
    still_draws,
)


@dataclass
class Reference:
    """A converged (or, with small N, banded) image of a shutter interval."""

    samples: int
    times: np.ndarray
    stratified: bool
    seed: int
    # G-buffer pass + accumulation by GL timer queries; with a wall clock (software contexts)
    # the whole loop, its Python work included, over N.
    ms_per_subframe: float
    clock: str
    texture: object = field(repr=False)  # the (H, W, 4) float32 sum on the GPU
    auto: bool = False  # N was chosen from the scene's motion (samples="auto")
    antialias: bool = False  # sub-frames at sub-pixel positions (docs/spec.md §11)
    positions: np.ndarray | None = None  # (N, 2) in the pixel from its top-left, antialias
    _color: np.ndarray | None = field(default=None, repr=False)

    @property
    def color(self) -> np.ndarray:
        if self._color is None:
            self._color = self.texture.download()
        return self._color

    def detached(self) -> Reference:
        """A copy holding the image in memory and no texture: picklable, for another process
        (a Dask worker that helps on this scene imports it instead of rendering it again)."""
        # Read back without keeping the copy here: the holder needs only its texture.
        color = self._color if self._color is not None else self.texture.download()
        return dataclasses.replace(self, texture=None, _color=color)

    def attached(self, ctx) -> Reference:
        """A detached reference on `ctx`: its image uploaded, the same bits as the original."""
        if self._color is None:
            raise ValueError("blurlab: Reference.attached needs a detached reference's image")
        texture = ctx.pooled(self._color.shape)
        texture.upload(self._color)
        result = dataclasses.replace(self, texture=texture)
        weakref.finalize(result, ctx.recycle, texture)
        return result


# A million sub-frames is hours even on the GPU; more is a mistake, not a reference.
MAX_SAMPLES = 1 << 20


def reference_render(
    ctx,
    scene: Scene,
    size=DEFAULT_SIZE,
    shutter=None,
    samples: int | str = 256,
    stratified: bool = True,
    seed: int = 0,
    progress: bool | None = None,
    guard: int = 0,
    antialias: bool = False,
) -> Reference:  # noqa: E501
    """The converged reference of `scene` over `shutter` (``ctx.reference``): the mean of
    `samples` full renders at t_i = t0 + (i + u_i)/N·(t1 - t0), u_i = 0.5 or hashed when
    `stratified` (docs/spec.md §1), accumulated in float32 on the GPU; a progress bar for
    N >= 64. `samples="auto"` takes N from the scene's motion: max(64, 2 x the longest motion in
    pixels), at most 1024, as sweeps do; the Reference says so (`auto`).

    ``antialias=True`` also gives each sub-frame a sub-pixel position: (time, x, y) from an
    Owen-scrambled Sobol sequence (`seed` picks the scramble), so the mean is the one-pixel
    box-filtered image a path tracer converges to. ``antialias=False`` (the default) samples
    pixel centers as the methods' G-buffers do, isolating motion-blur error from aliasing
    (docs/spec.md §11)."""
    if not isinstance(scene, Scene):
        raise TypeError(f"blurlab: reference needs a blurlab Scene, not {type(scene).__name__}")
    auto = isinstance(samples, str) and samples == "auto"
    if auto:  # N from the motion over the shutter, as sweeps choose it
        samples = default_reference_samples(render(ctx, scene, size, shutter))
    if isinstance(samples, bool) or not isinstance(samples, int) or not 1 <= samples <= MAX_SAMPLES:
        raise ValueError(
            f"blurlab: reference samples N must be an integer in 1..{MAX_SAMPLES} or 'auto', "
            f"not {samples!r}"
        )
    if isinstance(seed, bool) or not isinstance(seed, int) or not 0 <= seed < 2**32:
        raise ValueError(f"blurlab: seed must be an integer in 0..2^32-1, not {seed!r}")
    if not isinstance(antialias, bool):
        raise ValueError(f"blurlab: antialias must be True or False, not {antialias!r}")
    if antialias and not stratified:
        raise ValueError(
            "blurlab: antialias=True draws (time, x, y) together from a scrambled Sobol "
            "sequence; stratified=False (pixel-center times at stratum centers) is for the "
            "temporal reference only"
        )
    size = check_size(size, ctx.max_texture_size)
    shutter = check_shutter(scene.shutter if shutter is None else shutter)
    scene = scaled_scene(scene, shutter)  # blur scales pivot on the shutter's centre (§12.1)
    positions = None
    if antialias:
        times, positions = shutter_samples(shutter, samples, seed)
    else:
        times = sample_times(shutter, samples, bool(stratified), seed)
    width, height = size[0] + 2 * guard, size[1] + 2 * guard
    total = ctx.pooled((height, width, 4))
    total.clear()
    show = samples >= 64 if progress is None else bool(progress)
    iterator = times
    if show:
        from tqdm.auto import tqdm

        iterator = tqdm(times, desc=f"reference N={samples}", unit="sub-frame", leave=False)
    # No result read per sub-frame (docs/spec.md §11): GL timer queries time each sub-frame
    # and are read once after the loop; a wall clock (software contexts) can only time by waiting
    # (glFinish), so there one timer spans the whole loop instead.
    per_subframe = not ctx.software
    timings = []
    # Translucent surfaces (docs/spec.md §20): every sub-frame's fragment count is checked once,
    # after the loop, so the loop never waits for a result (only, past the context's bound on
    # unfinished passes, for the GPU to catch up).
    most_fragments = ctx.pooled((1, 1), "uint32") if scene.translucent else None
    if most_fragments is not None:
        most_fragments.clear()
    # Where the camera stands still, the objects that stand still too are drawn once, into a
    # base every sub-frame starts from (still_draws; the same bits: the draws over it are those
    # that followed them). Antialiased sub-frames each see the scene from their own position.
    still = 0 if positions is not None else still_draws(scene, size, times, guard)
    base = None
    with nullcontext() if per_subframe else ctx.timer() as whole, ctx.deferred_timers() as timers:
        sub_frame_timers = timers if per_subframe else False  # False: the pass runs untimed
        if still:
            base, timing = render_base(
                ctx, scene, size, shutter, float(times[0]), still, guard, timers=sub_frame_timers
            )
            timings.append(timing)
        for i, t in enumerate(iterator):
            jitter = (0.0, 0.0) if positions is None else tuple(0.5 - positions[i])
            targets, _, timing = render_targets(
                ctx,
                scene,
                size,
                shutter,
                float(t),
                guard,
                jitter,
                timers=sub_frame_timers,
                most_fragments=most_fragments,
                color_only=True,  # the mean of the colours is all a reference keeps
                base=base,
            )
            with timers.timer() if per_subframe else nullcontext() as add:
                accumulate(ctx, targets["color"], total, 1.0 / samples)
            ctx.recycle(*targets.values())
            timings += [timing, add]
    if base is not None:
        ctx.recycle(*base.textures.values())
    if most_fragments is not None:
        try:
            check_fragment_capacity(most_fragments, scene)
        finally:
            ctx.recycle(most_fragments)
    if per_subframe:
        elapsed, clock = sum(timing.ms for timing in timings), timings[-1].clock
    else:
        elapsed, clock = whole.ms, whole.clock
    result = Reference(
        samples,
        times,
        bool(stratified),
        seed,
        elapsed / samples,
        clock,
        total,
        auto,
        antialias,
        positions,
    )
    weakref.finalize(result, ctx.recycle, total)
    return result


def accumulate(ctx, color, total, weight: float) -> None:
    """total += weight · color on the GPU, in float32 (shaders/passes/accumulate.comp): the
    sum of sub-frames here, of steps and of trail's frames in blurlab.methods."""
    ctx.shader_pass("passes/accumulate.comp").run(
        {"color": color}, {"sum": total}, {"weight": weight}
    )


def reference_samples_needed(frame: Frame) -> int:
    """N for the reference of `frame`'s shutter: at least the longest motion in pixels
    (docs/spec.md §1), so that consecutive sub-frames move by at most one pixel."""
    return max(1, math.ceil(frame.longest_motion))


MAX_DEFAULT_SAMPLES = 1024


def default_reference_samples(frame: Frame) -> int:
    """The N that sweeps use when none is given: max(64, 2 x the longest motion in pixels),
    capped at 1024 (a point racing through the near plane can "move" thousands of pixels)."""
    return min(MAX_DEFAULT_SAMPLES, max(64, 2 * reference_samples_needed(frame)))
