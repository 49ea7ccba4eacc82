"""GPU passes of a method: the frame's textures, a pass's declaration (`Pass`), its uniforms and
#defines from the method's parameters, and running it timed (or recorded for a plan)."""

from __future__ import annotations

import contextvars
import math
from collections.abc import Callable
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path

from ..core.context import Context
from ..core.frame import Frame
from ..core.gl import Texture, Timing
from . import plans
from .params import Param


def frame_textures(ctx: Context, frame: Frame) -> dict[str, Texture]:
    """The frame's textures on `ctx`: the rendered ones where the frame came from this context;
    color, depth and motion uploaded from its arrays otherwise, once per frame (only those
    missing: a frame whose colour was replaced keeps its other textures)."""
    textures = frame.textures
    names = ("color", "depth", "motion")
    if any(k in textures and textures[k].context is not ctx for k in names):
        textures = {}  # another context's: this one uploads its own
    missing = [k for k in names if k not in textures]
    if missing:
        textures = {**textures, **{k: ctx.upload(getattr(frame, k)) for k in missing}}
        frame.textures = textures
    return textures


@dataclass(frozen=True)
class Pass:
    """One GPU pass of a method: the shader it runs and the method parameters it takes as
    uniforms of the same names. Its inputs and outputs are the shader's own samplers and images
    (ShaderPass.reflect lists them); `name` keys its timing."""

    name: str
    shader: str  # under shaders/, or a method folder's own (shader_beside)
    params: tuple[str, ...] = ()


def shader_beside(module_file: str, name: str) -> str:
    """The path of shader `name` in the folder of the module `module_file` (a method folder's
    method.py passes its own __file__): a built-in method's shaders sit beside it."""
    return str(Path(module_file).resolve().parent / name)


def pass_uniforms(params: dict[str, Param], values: dict, names) -> dict:
    """The uniforms of the parameters `names` from validated `values`: the same names; a
    choice becomes its index among the declared choices (see choice_defines)."""
    uniforms = {}
    for key in names:
        kind = params[key].kind
        uniforms[key] = kind.index(values[key]) if isinstance(kind, tuple) else values[key]
    return uniforms


def choice_defines(params: dict[str, Param], names) -> dict[str, int]:
    """#defines that name each choice's index, KEY_CHOICE (EDGE_IGNORE = 1), so that a shader
    compares a choice uniform with a name derived from the one declaration."""
    defines = {}
    for key in names:
        kind = params[key].kind
        if isinstance(kind, tuple):
            for index, choice in enumerate(kind):
                defines[f"{key}_{choice}".upper()] = index
    return defines


@dataclass
class PassRunner:
    """The passes of one method call: the call's context and timings, the method's parameter
    declarations and their validated values, bound once for every pass the call runs."""

    ctx: Context
    params: dict[str, Param]
    values: dict
    timings: dict = field(default_factory=dict)

    def run(
        self,
        step: Pass,
        inputs: dict[str, Texture],
        outputs: dict[str, Texture],
        backend: str = "compute",
        uniforms: dict | None = None,
        defines: dict | None = None,
        group_per_texel: bool = False,
    ) -> None:
        """Runs `step` with the method's validated values (and any pass-level `uniforms`),
        timed under step.name."""
        ctx, params = self.ctx, self.params
        extra = tuple(sorted(defines.items())) if defines else ()

        def make():
            all_defines = {**choice_defines(params, step.params), **dict(extra)}
            return ctx.shader_pass(step.shader, all_defines)

        shader = ctx.cached(("PassRunner", step, id(params), extra), make)
        all_uniforms = {**pass_uniforms(params, self.values, step.params), **(uniforms or {})}

        def run():
            shader.run(inputs, outputs, all_uniforms, backend, group_per_texel)

        recorder = plans.active_recorder()
        if recorder is not None:
            recorder.runs.append(
                plans.RecordedRun(shader, inputs, outputs, all_uniforms, backend, group_per_texel)
            )
            recorder.timing_names.append(step.name)
        _timed(ctx, self.timings, step.name, run)

    def run_result(
        self, step: Pass, inputs: dict[str, Texture], backend: str, dtype="float32", **options
    ) -> Texture:
        """Runs `step` into its one output `result`, an RGBA image of inputs["color"]'s size
        from the context's pool (a method's blurred colour), and returns it; `options` as run's."""
        result = self.ctx.pooled(inputs["color"].shape[:2] + (4,), dtype)
        self.run(step, inputs, {"result": result}, backend, **options)
        return result


def run_pass(
    ctx: Context,
    timings: dict,
    step: Pass,
    params: dict[str, Param],
    values: dict,
    inputs: dict[str, Texture],
    outputs: dict[str, Texture],
    backend: str = "compute",
    **options,
) -> None:
    """One pass outside a PassRunner: PassRunner(ctx, params, values, timings).run(...), with
    `options` its uniforms, defines and group_per_texel."""
    PassRunner(ctx, params, values, timings).run(step, inputs, outputs, backend, **options)


_TIMED: contextvars.ContextVar[bool] = contextvars.ContextVar("blurlab_timed", default=True)


@contextmanager
def timers(on: bool):
    """Within it, passes run timed (on) or untimed (off): blur(timed=...)."""
    token = _TIMED.set(on)
    try:
        yield
    finally:
        _TIMED.reset(token)


def timing_on() -> bool:
    """Whether the passes run now are timed: False inside blur(timed=False), for methods that
    time their own GPU work (stochastic's sub-frame renders)."""
    return _TIMED.get()


def timed(ctx: Context, timings: dict, name: str, fn: Callable) -> None:
    """Runs one pass, timed by the context's clock unless blur(timed=False) asked otherwise
    (the Timing then says clock "untimed" and NaN ms). GPU work run this way, outside
    PassRunner.run, is not recorded: a method run that has any is never replayed
    (blurlab.methods.plans)."""
    recorder = plans.active_recorder()
    if recorder is not None:
        recorder.unfit()
    _timed(ctx, timings, name, fn)


def _timed(ctx: Context, timings: dict, name: str, fn: Callable) -> None:
    if not timing_on():
        fn()
        timings[name] = Timing(math.nan, "untimed")
        return
    with ctx.timer() as timing:
        fn()
    timings[name] = timing
