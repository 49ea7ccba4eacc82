"""Recorded dispatch plans (docs/spec.md §18: a Python call of a method must cost little more
than its GPU time). The first untimed run of a method on a frame with a given set of parameters
is recorded pass by pass; later identical calls replay the recording through one C++ call
(_core.DispatchPlan) that binds the programs, textures, uniforms and work-group counts resolved
when it was recorded, instead of validating parameters, building uniform dicts and looking up
programs and units pass by pass. docs/spec.md §18 says when a run is recorded and replayed.

A recording is kept only when the run was nothing but PassRunner.run calls over the frame's
textures, the method's own outputs and scratch textures it writes before reading them: anything
else (a tile-class restriction, a pass run outside PassRunner.run, a lookup texture) makes it
unfit, and such calls always take the ordinary path.
"""

from __future__ import annotations

import contextvars
import math
from contextlib import contextmanager
from dataclasses import dataclass

from .. import _core
from ..core.context import Context
from ..core.gl import ShaderPass, Texture, Timing

_RECORDER: contextvars.ContextVar[Recorder | None] = contextvars.ContextVar(
    "blurlab_recorder", default=None
)


@dataclass(frozen=True)
class RecordedRun:
    """One ShaderPass.run of a recorded method run, with the arguments it was given."""

    shader: ShaderPass
    inputs: dict[str, Texture]
    outputs: dict[str, Texture]
    uniforms: dict
    backend: str
    group_per_texel: bool


class Recorder:
    """The passes of one method run, in order, and whether the run can be replayed."""

    def __init__(self):
        self.runs: list[RecordedRun] = []
        self.timing_names: list[str] = []
        self.fit = True

    def unfit(self) -> None:
        """The run did GPU work that a plan cannot replay."""
        self.fit = False


_ENABLED: contextvars.ContextVar[bool] = contextvars.ContextVar("blurlab_plans", default=True)


def enabled() -> bool:
    """False inside `disabled()`."""
    return _ENABLED.get()


@contextmanager
def disabled():
    """Inside the block, every call takes the ordinary path: nothing is recorded or replayed.
    For measuring what plans save (`blurlab bench call_overhead`) and for ruling them out."""
    token = _ENABLED.set(False)
    try:
        yield
    finally:
        _ENABLED.reset(token)


def active_recorder() -> Recorder | None:
    """The recorder of the method run in progress, if it is being recorded."""
    return _RECORDER.get()


@contextmanager
def recording(recorder: Recorder | None):
    """Inside the block, PassRunner.run and timed report to `recorder` (None: nothing is
    recorded)."""
    token = _RECORDER.set(recorder)
    try:
        yield recorder
    finally:
        _RECORDER.reset(token)


@dataclass(frozen=True)
class Plan:
    """A replayable method run: the textures it reads from the frame (by name, and the very
    textures recorded, so that a frame whose textures changed records again), the outputs it
    makes (name, shape, dtype), the scratch textures it writes and drops (shape, dtype), and
    what the BlurResult reports."""

    context: Context
    core: _core.DispatchPlan
    inputs: tuple[tuple[str, Texture], ...]
    outputs: tuple[tuple[str, tuple[int, ...], str], ...]
    scratch: tuple[tuple[tuple[int, ...], str], ...]
    values: dict
    backend: str
    timing_names: tuple[str, ...]

    def run(self) -> tuple[dict[str, Texture], dict[str, Timing]]:
        """Replays the plan on the recorded inputs into fresh pooled outputs: (outputs,
        timings), the timings "untimed" as an untimed run reports them."""
        ctx = self.context
        outputs = {name: ctx.pooled(shape, dtype) for name, shape, dtype in self.outputs}
        scratch = [ctx.pooled(shape, dtype) for shape, dtype in self.scratch]
        textures = [texture.native for _, texture in self.inputs]
        textures.extend(texture.native for texture in outputs.values())
        textures.extend(texture.native for texture in scratch)
        try:
            self.core.run(textures)
        except BaseException:
            ctx.recycle(*outputs.values())
            raise
        finally:
            ctx.recycle(*scratch)
        return outputs, {name: Timing(math.nan, "untimed") for name in self.timing_names}

    def matches(self, ctx: Context, inputs: dict[str, Texture]) -> bool:
        """True when the plan was recorded on `ctx` with these very input textures."""
        if ctx is not self.context:
            return False
        for name, texture in self.inputs:
            if inputs.get(name) is not texture:
                return False
        return True


def make_plan(
    ctx: Context,
    recorder: Recorder,
    inputs: dict[str, Texture],
    outputs: dict[str, Texture],
    values: dict,
    backend: str,
) -> Plan | None:
    """The plan of a recorded run, or None where the run cannot be replayed: it did other GPU
    work, read a texture that is neither an input, an output nor written earlier in the run (a
    lookup texture, whose contents a replay could not vouch for), left an output unwritten, or
    returned an input as an output. Textures the run wrote and then dropped (scratch levels
    back in the pool) are taken from the pool for each replay and given back after it."""
    if not recorder.fit or not recorder.runs:
        return None
    input_ids = {id(t) for t in inputs.values()}
    output_ids = {id(t) for t in outputs.values()}
    if input_ids & output_ids:
        return None
    written: set[int] = set()
    scratch: dict[int, Texture] = {}
    for run in recorder.runs:
        for t in run.inputs.values():
            if id(t) not in input_ids and id(t) not in written:
                return None
        for t in run.outputs.values():
            if id(t) in input_ids:
                return None
            if id(t) not in output_ids:
                scratch.setdefault(id(t), t)
            written.add(id(t))
    if not output_ids <= written:
        return None
    read = {id(t) for run in recorder.runs for t in run.inputs.values()}
    used_inputs = tuple((name, t) for name, t in inputs.items() if id(t) in read)
    slots = [t for _, t in used_inputs] + list(outputs.values()) + list(scratch.values())
    core = _core.DispatchPlan(ctx.native, [t.native for t in slots])
    for run in recorder.runs:
        core.add(
            run.shader.native,
            {name: t.native for name, t in run.inputs.items()},
            {name: t.native for name, t in run.outputs.items()},
            run.uniforms,
            run.backend,
            run.group_per_texel,
        )
    return Plan(
        ctx,
        core,
        used_inputs,
        tuple((name, t.shape, t.dtype_name) for name, t in outputs.items()),
        tuple((t.shape, t.dtype_name) for t in scratch.values()),
        dict(values),
        backend,
        tuple(recorder.timing_names),
    )
