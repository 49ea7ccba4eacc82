"""The G-buffer pass from Python: evaluates a scene's motion at shutter open, close and the
instant, builds the matrices, and runs src/passes/gbuffer on the context."""

from __future__ import annotations

import math
import weakref
from contextlib import nullcontext
from dataclasses import dataclass
from numbers import Real

import numpy as np

from .. import _core
from ..scene.blur_scales import scaled_scene
from ..scene.model import Scene
from ..scene.translucency import check_fragment_capacity, translucent_layer
from ..sizes import DEFAULT_SIZE
from .frame import MOTION_FORMATS, Frame

INSTANTS = ("center", "close", "open")


def instant_time(instant: str | float, shutter: tuple[float, float]) -> float:
    """The time at which the G-buffer is rendered (docs/spec.md §1 "Instant")."""
    t0, t1 = shutter
    if isinstance(instant, str):
        if instant not in INSTANTS:
            raise ValueError(
                f"blurlab: instant must be one of {INSTANTS} or a time, not {instant!r}"
            )
        return {"center": (t0 + t1) / 2, "close": t1, "open": t0}[instant]
    if isinstance(instant, bool) or not isinstance(instant, Real) or not t0 <= instant <= t1:
        raise ValueError(f"blurlab: instant time {instant!r} is outside the shutter [{t0}, {t1}]")
    return float(instant)


def check_size(size, limit: int) -> tuple[int, int]:
    try:
        width, height = (int(v) for v in size)
    except (TypeError, ValueError, OverflowError):
        raise ValueError(f"blurlab: size must be (W, H), not {size!r}") from None
    if (
        any(isinstance(v, bool) for v in size)
        or (width, height) != tuple(size)
        or not (1 <= width <= limit and 1 <= height <= limit)
    ):
        raise ValueError(f"blurlab: size {size!r} must be two integers in 1..{limit} (W, H)")
    return width, height


def check_shutter(shutter) -> tuple[float, float]:
    try:
        t0, t1 = (float(v) for v in shutter)
    except (TypeError, ValueError, OverflowError):
        raise ValueError(f"blurlab: shutter must be (t0, t1), not {shutter!r}") from None
    if not (math.isfinite(t0) and math.isfinite(t1)) or t1 < t0:
        raise ValueError(f"blurlab: shutter (t0, t1) must be finite with t1 >= t0, not {shutter!r}")
    return t0, t1


def check_jitter(jitter) -> tuple[float, float]:
    try:
        dx, dy = jitter
    except (TypeError, ValueError):
        raise ValueError(f"blurlab: jitter must be (dx, dy) pixels, not {jitter!r}") from None
    if not all(
        isinstance(v, Real) and not isinstance(v, bool) and math.isfinite(v) for v in (dx, dy)
    ):
        raise ValueError(f"blurlab: jitter (dx, dy) must be two finite numbers, not {jitter!r}")
    return float(dx), float(dy)


def camera_matrices(scene: Scene, size, times, guard: int = 0, jitter=(0.0, 0.0)) -> dict:
    """View and (y-flipped) projection matrices at open, close and the instant, float64.

    With a guard band the projection covers `guard` more pixels on every side of `size`.
    """
    width, height = size
    projection = scene.camera.projection(width / height)
    projection[0] *= width / (width + 2 * guard)
    projection[1] *= height / (height + 2 * guard)
    if jitter[0] or jitter[1]:  # a shift in normalized device coordinates, after projection
        shift = np.eye(4)
        shift[0, 3] = 2 * jitter[0] / (width + 2 * guard)
        shift[1, 3] = 2 * jitter[1] / (height + 2 * guard)
        projection = shift @ projection
    views = [scene.camera.view(t) for t in times]

    def rotation_only(view):
        r = view.copy()
        r[:3, 3] = 0.0
        return projection @ r

    return {
        "projection": projection,
        "view": np.stack(views),
        "view_projection": np.stack([projection @ v for v in views]),
        "eye": scene.camera.world(times[2])[:3, 3],
        "sky_from_clip": np.linalg.inv(rotation_only(views[2])),
        "sky_projection": np.stack([rotation_only(views[0]), rotation_only(views[1])]),
        "times": np.array(times),
        "near": scene.camera.near,
        "far": scene.camera.far,
    }


def render(
    ctx,
    scene: Scene,
    size=DEFAULT_SIZE,
    shutter=None,
    instant: str | float = "center",
    motion_format: str = "rg32f",
    maxlen: float | None = None,
    guard: int = 0,
    jitter=(0.0, 0.0),
) -> Frame:
    """Renders the G-buffer of `scene`; see Context.render."""
    if not isinstance(scene, Scene):
        raise TypeError(f"blurlab: render needs a blurlab Scene, not {type(scene).__name__}")
    size = check_size(size, ctx.max_texture_size)
    shutter = check_shutter(scene.shutter if shutter is None else shutter)
    scene = scaled_scene(scene, shutter)  # the frame keeps it: its methods pivot on this t_c
    time = instant_time(instant, shutter)
    if motion_format not in MOTION_FORMATS:
        raise ValueError(
            f"blurlab: motion_format must be one of {MOTION_FORMATS}, not {motion_format!r}"
        )
    if maxlen is None:
        maxlen = math.hypot(*size)  # docs/spec.md §2: the image diagonal
    if not (isinstance(maxlen, Real) and math.isfinite(maxlen) and maxlen > 0):
        raise ValueError(f"blurlab: maxlen must be a finite number of pixels > 0, not {maxlen!r}")
    jitter = check_jitter(jitter)
    # The pass's time is read when first asked for: the call itself does not wait for the GPU.
    targets, camera, timing = render_targets(
        ctx, scene, size, shutter, time, guard, jitter, sides=True, timers=ctx.lazy_timers
    )
    timings = {"gbuffer": timing}
    if "translucent" in targets:
        check_fragment_capacity(targets["most_fragments"], scene)
    if motion_format != "rg32f":
        exact = targets["motion"]
        targets["motion"], timings["motion_encoding"] = encode_motion(
            ctx, exact, motion_format, maxlen
        )
        ctx.recycle(exact)
    # Nothing is read back here: the frame's arrays are downloaded when first asked for.
    frame = Frame.from_textures(
        targets,
        shutter=shutter,
        time=time,
        motion_format=motion_format,
        camera=camera,
        timings=timings,
        scene=scene,
    )
    # The targets go back to the pool when the frame is freed: frame.textures live as long as
    # the frame does.
    weakref.finalize(frame, ctx.recycle, *targets.values())
    return frame


def render_targets(
    ctx,
    scene: Scene,
    size,
    shutter,
    time: float,
    guard: int = 0,
    jitter=(0.0, 0.0),
    sides: bool = False,
    timers=None,
    most_fragments=None,
    color_only: bool = False,
    base: StaticBase | None = None,
):
    """Runs the G-buffer pass into pooled textures: (targets, camera matrices, Timing).
    `sides` adds the target "motion_sides": M_prev in RG, M_next in BA (docs/spec.md §17.1).
    `timers`: a Context.deferred_timers() batch that times the pass (the Timing is filled when
    the batch ends) or Context.lazy_timers (read when first asked for); None waits for the time
    here; False leaves the pass untimed (Timing None).

    `guard` > 0 renders a margin of that many pixels around the image (the frustum widened to
    match), for methods whose taps leave the image ("Blurry things": guard band). `jitter`
    = (dx, dy) pixels moves the image content, so that the pixel centers show the points at
    (x + 0.5 - dx, y + 0.5 - dy) of the unjittered image (sub-pixel sample positions).

    Scenes with translucent surfaces get the targets of `translucent_layer`; `most_fragments`
    (a cleared 1 x 1 uint32 texture) collects their largest fragment count over several calls,
    else each call adds its own as targets["most_fragments"].

    `color_only` renders the colour alone (the same bits), for a reference's sub-frames: depth,
    motion and ids are neither allocated nor written, and the background is cleared, not drawn
    (docs/spec.md §1, Background). Scenes with translucent surfaces get the depth too, which
    their fragments are tested against. `base` (with `color_only`; render_base made it at the
    same size, guard and jitter): its objects are not drawn again, the rest are drawn over it.
    """
    if isinstance(guard, bool) or not isinstance(guard, int) or guard < 0:
        raise ValueError(f"blurlab: guard must be an integer >= 0 pixels, not {guard!r}")
    if base is not None and not color_only:
        raise ValueError("blurlab: a render over a base keeps the colour alone (color_only)")
    if base is not None and any(t.context is not ctx for t in base.textures.values()):
        raise ValueError("blurlab: that base was made by another context; make one with this one")
    width, height = size[0] + 2 * guard, size[1] + 2 * guard
    check_size((width, height), ctx.max_texture_size)
    times = (shutter[0], shutter[1], time)
    camera = camera_matrices(scene, size, times, guard, jitter)
    camera_uniforms, light = _frame_uniforms(scene, camera)
    draws, layered = _draw_lists(ctx, scene, times, skipped=0 if base is None else base.draws)
    # Every target is fully overwritten (the background, drawn or cleared, or the base's copy
    # covers every pixel), so pooled textures need no clearing.
    shapes = target_shapes((width, height), sides)
    if color_only:  # translucent fragments are tested against the opaque depth: it is kept
        shapes = {name: shapes[name] for name in ("color", "depth") if name == "color" or layered}
    targets = {name: ctx.pooled(shape) for name, shape in shapes.items()}
    if base is not None:  # the base's images, its depth buffer kept by the pass
        for name, texture in base.textures.items():
            targets[name].native.copy_from(texture.native, 0, 0)
    natives = [
        targets[name].native if name in targets else None
        for name in ("color", "depth", "motion", "object_id")
    ]
    gbuffer = gbuffer_pass(ctx)
    with _pass_clock(ctx, timers) as timing:
        gbuffer.render(
            *natives,
            camera_uniforms,
            light,
            draws,
            motion_sides=targets["motion_sides"].native if sides else None,
            over_base=0 if base is None else base.token,
        )
        if layered:
            translucent_layer(
                ctx, gbuffer, targets, camera_uniforms, light, layered, scene, most_fragments
            )
    return targets, camera, timing


@dataclass
class StaticBase:
    """What every sub-frame of a reference shares where the camera stands still (docs/spec.md
    §11): the scene's first `draws` opaque objects, still over the shutter, drawn once. Its
    `textures` ("color", and "depth" for translucent scenes) are copied into each sub-frame's
    targets; its depth buffer is kept by the context's G-buffer pass under `token`."""

    draws: int
    textures: dict
    token: int


def still_draws(scene: Scene, size, sample_times, guard: int = 0) -> int:
    """How many of the scene's opaque objects, from the first in draw order, look the same at
    every one of `sample_times` (the matrices the pass receives, float32, are equal; no
    skeleton), seen by a camera whose instant matrices and eye are equal too: 0 where the
    camera moves. Sub-frames at those times (pixel centers, no jitter) can share a base of
    those objects (render_base) and draw only the rest."""
    times = [float(t) for t in sample_times]
    if len(times) < 2:
        return 0
    f32 = lambda a: np.asarray(a, dtype=np.float32)  # noqa: E731  (as the pass receives them)

    def seen_from(t):
        camera = camera_matrices(scene, size, (t, t, t), guard)
        return f32(camera["view_projection"][2]), f32(camera["eye"])

    first = seen_from(times[0])
    for t in times[1:]:
        if not all(np.array_equal(a, b) for a, b in zip(seen_from(t), first, strict=True)):
            return 0
    count = 0
    for obj in scene.objects:
        if obj.material.translucent:
            continue  # drawn into the fragment lists of every sub-frame, not into the base
        if obj.skeleton is not None:
            break
        model = f32(obj.model(times[0]))
        if not all(np.array_equal(f32(obj.model(t)), model) for t in times[1:]):
            break
        count += 1
    return count


def render_base(
    ctx, scene: Scene, size, shutter, time: float, draws: int, guard: int = 0, timers=None
):
    """(StaticBase of the scene's first `draws` opaque objects at `time`, its Timing): they are
    drawn alone, colour only, and the G-buffer pass keeps their depth. `draws` comes from
    still_draws over the sub-frames' times; `timers` as render_targets takes them."""
    times = (shutter[0], shutter[1], time)
    camera = camera_matrices(scene, size, times, guard)
    camera_uniforms, light = _frame_uniforms(scene, camera)
    opaque, _ = _draw_lists(ctx, scene, times)
    width, height = size[0] + 2 * guard, size[1] + 2 * guard
    shapes = target_shapes((width, height))
    names = ("color", "depth") if scene.translucent else ("color",)
    textures = {name: ctx.pooled(shapes[name]) for name in names}
    gbuffer = gbuffer_pass(ctx)
    with _pass_clock(ctx, timers) as timing:
        gbuffer.render(
            textures["color"].native,
            textures["depth"].native if "depth" in textures else None,
            None,
            None,
            camera_uniforms,
            light,
            opaque[:draws],
        )
        token = gbuffer.keep_base()
    return StaticBase(draws, textures, token), timing


def _pass_clock(ctx, timers):
    """The block that times a pass as render_targets' `timers` asks: a batch's timer, the lazy
    ones, the context's own (None: waits), or none (False)."""
    if timers is False:
        return nullcontext()
    return ctx.timer() if timers is None else timers.timer()


def _frame_uniforms(scene: Scene, camera: dict) -> tuple[dict, dict]:
    """The G-buffer pass's camera and light uniforms, float32."""
    f32 = lambda a: np.ascontiguousarray(a, dtype=np.float32)  # noqa: E731
    camera_uniforms = {
        k: f32(camera[k]) for k in ("view_projection", "eye", "sky_from_clip", "sky_projection")
    }
    camera_uniforms["near"] = float(scene.camera.near)
    light = {
        "direction": f32(scene.light.direction / np.linalg.norm(scene.light.direction)),
        "color": f32(scene.light.color),
        "ambient": f32(scene.light.ambient),
        "background": f32(scene.background),
    }
    return camera_uniforms, light


def _draw_lists(ctx, scene: Scene, times, skipped: int = 0) -> tuple[list, list]:
    """The pass's draws at `times` (open, close, instant): (opaque, translucent), each in the
    scene's order, leaving out the first `skipped` opaque objects (a base holds them)."""
    f32 = lambda a: np.ascontiguousarray(a, dtype=np.float32)  # noqa: E731
    draws, layered = [], []
    for object_id, obj in enumerate(scene.objects):
        m = obj.material
        if not m.translucent and skipped > 0:
            skipped -= 1
            continue
        draw = _core.GBufferDraw()
        draw.mesh = ctx.gpu_mesh(obj.mesh)
        draw.model = f32([obj.model(t) for t in times])
        if obj.skeleton is not None:
            draw.bones = f32([obj.skeleton.matrices(t) for t in times])
        draw.object_id = object_id
        draw.material.color = f32(m.color * (1.0, 1.0, 1.0, m.alpha))
        draw.material.alpha_mode = getattr(_core.AlphaMode, m.blend)
        draw.material.alpha_cutoff = float(m.alpha_cutoff)
        draw.material.emission = f32(m.radiance)
        draw.material.specular = float(m.specular)
        draw.material.shininess = float(m.shininess)
        draw.material.texture = ctx.gpu_material_texture(m)
        if m.hatch is not None:
            m.hatch.draw(ctx, draw.material.hatching)
        (layered if m.translucent else draws).append(draw)
    return draws, layered


def target_shapes(size, sides: bool = False) -> dict[str, tuple[int, ...]]:
    """The G-buffer pass's float32 targets at `size` = (W, H), guard band included: colour,
    depth, motion, object id, and with `sides` the two-sided motion."""
    width, height = size
    shapes = {
        "color": (height, width, 4),
        "depth": (height, width),
        "motion": (height, width, 2),
        "object_id": (height, width),
    }
    if sides:
        shapes["motion_sides"] = (height, width, 4)
    return shapes


def gbuffer_pass(ctx) -> _core.GBufferPass:
    """The context's G-buffer pass (its program compiles on first use)."""
    return ctx.cached("gbuffer", lambda: _core.GBufferPass(ctx.native))


def encode_motion(ctx, motion, motion_format: str, maxlen: float):
    """Runs the motion-encoding pass on an rg32f motion texture: returns the decoded texture
    (what a method reading `motion_format` sees) and the pass's Timing."""
    width, height = motion.width, motion.height
    if motion_format == "rg16f":
        stored = ctx.pooled((height, width, 2), "float16")
    else:
        stored = ctx.pooled((height, width, 4), "uint8")
    decoded = ctx.pooled((height, width, 2))
    encoding = ctx.cached("motion_encoding", lambda: _core.MotionEncodingPass(ctx.native))
    with ctx.timer() as timing:
        encoding.run(motion.native, stored.native, decoded.native, motion_format, float(maxlen))
    ctx.recycle(stored)
    return decoded, timing


def stored_motion(ctx, motion: np.ndarray, motion_format: str, maxlen: float) -> np.ndarray:
    """(H, W, 2) motion as a method reading `motion_format` would see it, computed on the GPU
    (the precision study of docs/spec.md §2)."""
    if motion_format not in MOTION_FORMATS:
        raise ValueError(f"blurlab: motion_format must be one of {MOTION_FORMATS}")
    motion = np.asarray(motion, dtype=np.float32)
    if motion.ndim != 3 or motion.shape[2] != 2:
        raise ValueError(f"blurlab: motion must be (H, W, 2), not {motion.shape}")
    if motion_format == "rg32f":
        return motion.copy()
    decoded, _ = encode_motion(ctx, ctx.upload(motion), motion_format, maxlen)
    result = decoded.download()
    ctx.recycle(decoded)
    return result
