"""One scene's evaluations for a sweep: every configuration timed back to back, then each one's
error against the scene's reference. Local sweeps (blurlab.studies.sweep) and Dask workers
(blurlab.studies.cluster) both run them here.
"""

from __future__ import annotations

import contextlib
import json
import math
import statistics
import time
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path

from .. import metrics as m
from .._core import StaleReadback
from ..core.context import Context
from ..core.references import default_reference_samples
from ..core.render import check_shutter
from ..io import images as io
from ..methods import blur_steps, method_instant, render_steps
from ..scene.model import Scene


@dataclass(frozen=True)
class Settings:
    """What every evaluation of one sweep shares; small and picklable, so workers get it too."""

    size: tuple[int, int]
    shutter: tuple[float, float] | None
    reference_samples: int | None
    metrics: tuple[str, ...] | None  # None: scene_metrics(scene) on each scene
    repeats: int  # timed runs of each configuration; 0 scores without timing (no warm-up)
    # Evaluations whose GPU metrics are read back together (metrics.MetricQueue); 1 reads each
    # one's scalars before the next evaluation starts.
    readback_batch: int = 1


# The phases a scene cache's PhaseClock (cache["clock"]) counts: what a scene costs once per
# process before its first evaluation, and each method's first, untimed run in a call of
# evaluate_scene (its compiles and the first use of new textures).
REFERENCES, G_BUFFERS, WARM_UP = "references", "g_buffers", "warm_up"
SETUP_PHASES = (REFERENCES, G_BUFFERS)

# Runs of an evaluation whose metrics came back stale (docs/spec.md §6.3) before the sweep
# gives up.
STALE_ATTEMPTS = 3
# A row's column of the reads of its GPU metrics that were refused before the values it holds:
# a results file keeps it, so a sweep resumed from one still knows which rows were scored again.
STALE_COLUMN = "stale_readbacks"


# How a sweep's references are made besides N and antialias (ctx.reference's arguments): part
# of every row's identity (blurlab.studies.identity).
REFERENCE_OPTIONS = {"stratified": True, "seed": 0, "guard": 0}


def reference_kinds(metric_names) -> list[str]:
    """The references (metrics.REFERENCES: temporal, antialiased) that `metric_names` score
    against, in the registry's order."""
    return [k for k in m.REFERENCES if any(m.get(n).reference == k for n in metric_names)]


def scene_metrics(scene: Scene) -> tuple[str, ...]:
    """The metrics a sweep computes on `scene` when none are named: the registered defaults,
    the HDR ones on HDR scenes only (`Scene.hdr`, docs/spec.md §6.2)."""
    return m.default_names(scene.hdr)


def evaluate_scene(
    ctx: Context, scene: Scene, jobs: Sequence[tuple], settings: Settings, cache: dict
) -> Iterator[tuple[tuple, dict]]:
    """Evaluates `jobs` = [(method, point, backend, key)] of one scene; yields (key, row) as
    each row is finished. `cache` holds the scene's frames and reference between calls (a
    worker keeps one per scene it has worked on); where cache["keep_colours"] holds a job's
    (method, params JSON), its output colour is kept in cache["colours"] under that key.
    Nothing is rendered that `cache` holds already: with every job's frames (by instant and
    steps) and the references there, `scene` needs only its name and `hdr` (a captured frame,
    blurlab.studies.capture_study)."""
    size = settings.size
    info = ctx.info()
    wanted = settings.metrics if settings.metrics is not None else scene_metrics(scene)
    chosen = [m.get(n) for n in wanted]
    kinds = reference_kinds(wanted)
    # Timing first, every configuration back to back: the GPU stays busy, so its clocks stay
    # up. Computing SSIM and FLIP between runs left it idle long enough to clock down, and
    # single runs after that were several times slower on the H100. Each method runs once
    # untimed first: it compiles (and, on llvmpipe, JITs), and the GPU wakes up.
    timings = {}
    warmed: set = set()
    for name, point, backend, key in jobs if settings.repeats else ():
        frames, reference = _scene_inputs(ctx, scene, name, point, settings, cache)
        params = _without_steps(point)
        if (name, backend) not in warmed:
            with _phase(cache, WARM_UP):
                blur_steps(ctx, frames, name, backend, **params)
            warmed.add((name, backend))
        runs = []
        for _ in range(settings.repeats):
            result = blur_steps(ctx, frames, name, backend, **params)
            runs.append({p: t.ms for p, t in result.timings.items()})
            clock = result.clock
            del result  # back to the pool before the next run
        timings[key] = (runs, clock)
    # Then the error of each configuration, one untimed run each. The GPU metrics go in
    # batches of settings.readback_batch evaluations, each read back once the next is issued,
    # so the GPU works through one batch while the CPU issues the next (docs/spec.md §6.3).
    batches = m.MetricBatches(ctx, settings.readback_batch) if settings.readback_batch > 1 else None
    immediate = _ImmediateMetrics(ctx)

    def issue(queue, references: dict, color) -> dict:
        return m.issue_reductions(
            queue,
            chosen,
            {kind: ref.texture for kind, ref in references.items()},
            lambda kind, refs=references: _prepared_reference(ctx, refs[kind], cache, kind),
            color,
        )

    def scored_again(key: tuple, row: dict, job: tuple) -> tuple[tuple, dict]:
        """`row` with its GPU metrics from a new run of `job`, read back at once: for an
        evaluation whose partial sums came back without their tickets (§6.3)."""
        name, point, backend = job
        for _ in range(STALE_ATTEMPTS):
            row[STALE_COLUMN] += 1  # the read just refused
            frames, reference = _scene_inputs(ctx, scene, name, point, settings, cache)
            result = blur_steps(ctx, frames, name, backend, timed=False, **_without_steps(point))
            references = _references(ctx, scene, settings, kinds, reference, cache)
            try:
                gpu = issue(immediate, references, result.textures["color"])
            except StaleReadback:
                continue
            return _finished_row(key, row, gpu, chosen)
        raise StaleReadback(
            f"blurlab: the GPU metrics of {name} {json.dumps(point, sort_keys=True)} on "
            f"{scene.name} came back without their tickets {STALE_ATTEMPTS} times in a row "
            "(docs/spec.md §6.3): no value of them can be trusted"
        )

    def finished(ready: list) -> Iterator[tuple[tuple, dict]]:
        """The rows of MetricBatches' (item, values) pairs; a batch refused is scored again."""
        for (key, row, indices, job), values in ready:
            if values is None:
                yield scored_again(key, row, job)
            else:
                got = {reduction: values[i] for reduction, i in indices.items()}
                yield _finished_row(key, row, got, chosen)

    for name, point, backend, key in jobs:
        queue = batches.queue if batches is not None else immediate
        frames, reference = _scene_inputs(ctx, scene, name, point, settings, cache)
        # An untimed sweep (repeats 0) has no pass times: total_ms is NaN, clock None.
        runs, clock = timings.get(key, ([], None))
        result = blur_steps(ctx, frames, name, backend, timed=False, **_without_steps(point))
        color = result.textures["color"]
        row = {
            "scene": scene.name,
            "method": name,
            "backend": result.backend,
            "params": json.dumps(point, sort_keys=True),
            **{f"param_{k}": v for k, v in point.items()},
            **{f"ms_{p}": statistics.median(r[p] for r in runs) for p in (runs[0] if runs else ())},
            "total_ms": statistics.median(sum(r.values()) for r in runs) if runs else math.nan,
            "repeats": settings.repeats,
            "clock": clock,
            # What the parameters given as "auto" chose on this scene.
            **{f"auto_{k}": json.dumps(v) for k, v in result.auto.items()},
        }
        # The metrics with a GPU reduction are reduced there (docs/spec.md §6): no image is
        # read back for them. Their columns come in the order asked, filled in when read back.
        row.update(dict.fromkeys(wanted))
        references = _references(ctx, scene, settings, kinds, reference, cache)
        try:
            gpu = issue(queue, references, color)
        except StaleReadback:  # read at once (the immediate queue): scored again below
            gpu = None
        # The pictures a caller shows (the study's middle points): kept, not blurred again.
        kept_as = picture_key(name, point)
        if kept_as in cache.get("keep_colours", ()):
            cache.setdefault("colours", {})[kept_as] = result.color
        unbatched = [metric for metric in chosen if metric.reduction is None]
        # Those with a GPU version run on the textures, read back at once; the rest on the CPU.
        on_gpu = [metric.name for metric in unbatched if metric.gpu is not None]
        on_cpu = [metric.name for metric in unbatched if metric.gpu is None]
        if on_gpu:
            textures = {kind: ref.texture for kind, ref in references.items()}
            arguments = lambda n, refs=references: _gpu_arguments(refs, cache, n)  # noqa: E731
            row.update(m.gpu_scores(ctx, on_gpu, textures, color, arguments))
        if on_cpu:  # from the images read back
            colours = {kind: ref.color for kind, ref in references.items()}
            row.update(m.cpu_scores(on_cpu, colours, result.color))
        if any(metric.hdr for metric in unbatched):  # the one psnr_tm, ssim_tm, pictures use
            row["exposure"] = _of_reference(
                cache, "exposures", "temporal", reference, lambda r=reference: m.exposure(r.color)
            )
        row.update(
            {
                "device": info["device"],
                "renderer": info["renderer"],
                "width": size[0],
                "height": size[1],
                "reference_samples": reference.samples,
                "shutter": json.dumps([frames[0].shutter[0], frames[-1].shutter[1]]),
                STALE_COLUMN: 0,
            }
        )
        # Its textures go back to the pool before the next evaluation; a queued reduction
        # still reads them first (GL runs commands in the order issued).
        del result, color
        job = (name, point, backend)
        if batches is not None:
            yield from finished(batches.add((key, row, gpu, job)))
        elif gpu is None:
            yield scored_again(key, row, job)
        else:
            yield _finished_row(key, row, gpu, chosen)
    if batches is not None:
        yield from finished(batches.flush())


class _ImmediateMetrics:
    """MetricQueue's calls answered at once (readback_batch 1): each returns the metric's
    value, read back before the next evaluation starts."""

    def __init__(self, ctx):
        self._ctx = ctx

    def mse(self, a, b) -> float:
        return m.gpu_mse(self._ctx, a, b)

    def mse_ssim(self, prepared, test) -> tuple[float, float]:
        return m.gpu_mse_ssim(self._ctx, prepared, test)

    def flip(self, reference, test) -> float:
        return m.gpu_flip(self._ctx, reference, test)


def picture_key(method_name: str, point: dict) -> tuple[str, str]:
    """How a configuration's output colour is named in a scene cache's "keep_colours" and
    "colours": its method and its parameters as the row's "params" JSON."""
    return method_name, json.dumps(point, sort_keys=True)


def _finished_row(key: tuple, row: dict, got: dict, chosen: list) -> tuple[tuple, dict]:
    """(key, row) with the GPU metrics of `chosen` filled in from `got`, the values of
    metrics.issue_reductions' reductions."""
    row.update(m.reduced_values(chosen, got))
    return key, row


class PhaseClock:
    """Wall-clock seconds of each phase of a study, in the order each was first entered:
    `with clock("charts"): ...` adds to a phase, `clock.add(phase, s)` too."""

    def __init__(self):
        self.seconds: dict[str, float] = {}
        self.start = time.perf_counter()

    @contextlib.contextmanager
    def __call__(self, phase: str):
        start = time.perf_counter()
        try:
            yield
        finally:
            self.add(phase, time.perf_counter() - start)

    def add(self, phase: str, seconds: float) -> None:
        self.seconds[phase] = self.seconds.get(phase, 0.0) + seconds

    def total(self) -> float:
        return time.perf_counter() - self.start


def write_phases(
    out: Path, clock: PhaseClock, descriptions: dict, info: dict, size, rows: int, **more
) -> None:
    """A study's phases.json in folder `out`: its size, renderer (`info`, the context's),
    evaluations (`rows`), total and per-phase seconds with what each phase counts
    (`descriptions`), and `more`."""
    timing = {
        "size": [int(size[0]), int(size[1])],
        "renderer": info["renderer"],
        "evaluations": rows,
        "total_s": clock.total(),
        "phases_s": clock.seconds,
        "phases": {k: descriptions[k] for k in clock.seconds},
        **more,
    }
    io.write_text(Path(out) / "phases.json", json.dumps(timing, indent=1) + "\n")


def phase_lines(clock: PhaseClock, title: str = "study") -> str:
    """The console's table of a study's phases: seconds and share of the whole."""
    total = clock.total()
    lines = [f"{title}: {total:.1f} s"]
    for phase, seconds in clock.seconds.items():
        lines.append(f"  {phase:<17}{seconds:8.1f} s {100 * seconds / total:5.1f} %")
    return "\n".join(lines)


def _phase(cache: dict, phase: str):
    """Times a block into the scene cache's PhaseClock, cache["clock"]: the study splits its
    sweep's time into references, G-buffers and evaluations with it, and a cluster's workers
    report their warm-up runs (compiles, first use of new textures) apart too."""
    return cache.setdefault("clock", PhaseClock())(phase)


def _reference(ctx, scene, settings: Settings, samples: int, cache: dict, antialias=False):
    """The scene's temporal (or antialiased) reference with `samples` sub-frames, made once."""
    key = "reference_aa" if antialias else "reference"
    if key not in cache:
        with _phase(cache, REFERENCES):
            cache[key] = ctx.reference(
                scene,
                settings.size,
                check_shutter(scene.shutter if settings.shutter is None else settings.shutter),
                samples=samples,
                progress=False,
                antialias=antialias,
                **REFERENCE_OPTIONS,
            )
    return cache[key]


def _references(ctx, scene, settings: Settings, kinds, temporal, cache: dict) -> dict:
    """{kind: the scene's reference} for `kinds` (metrics.REFERENCES): the temporal one given,
    the antialiased one (docs/spec.md §11) of the same N, made once."""
    return {
        kind: temporal
        if kind == "temporal"
        else _reference(ctx, scene, settings, temporal.samples, cache, antialias=True)
        for kind in kinds
    }


def _of_reference(cache: dict, group: str, key, reference, make, release=None):
    """make()'s value for `reference`, made once per reference the scene's cache holds: kept
    beside it in cache[group][key], so that a new reference makes it anew (`release` frees
    the value it replaces)."""
    made = cache.setdefault(group, {})
    held = made.get(key)
    if held is None or held[0] is not reference:
        if held is not None and release is not None:
            release(held[1])
        held = made[key] = (reference, make())
    return held[1]


def _prepared_reference(ctx, reference, cache: dict, kind: str) -> m.PreparedReference:
    """`reference` prepared for gpu_mse_ssim, once per reference of each kind."""
    return _of_reference(
        cache,
        "prepared_references",
        kind,
        reference,
        lambda: m.prepare_reference(ctx, reference.texture),
        release=m.PreparedReference.release,
    )


def _gpu_arguments(references: dict, cache: dict, name: str) -> dict:
    """Metric `name`'s gpu_arguments of its reference, made once per reference."""
    metric = m.get(name)
    reference = references[metric.reference]
    make = (lambda: metric.gpu_arguments(reference.color)) if metric.gpu_arguments else dict
    return _of_reference(cache, "gpu_arguments", name, reference, make)


def release_prepared(cache: dict) -> None:
    """Returns the references a scene cache prepared for gpu_mse_ssim to the context's pool:
    for a caller whose cache lives for one frame of many (a captured sequence)."""
    for _, prepared in cache.pop("prepared_references", {}).values():
        prepared.release()


def _without_steps(point: dict) -> dict:
    return {k: v for k, v in point.items() if k != "steps"}


def _scene_inputs(ctx, scene, name, point, settings: Settings, cache: dict):
    """The frames at the method's instant (one, or one per step of the shutter: `steps` in
    the point) and the scene's reference, each made once."""
    params = _without_steps(point)
    instant = method_instant(name, params)
    steps = point.get("steps", 1)
    frames = cache.setdefault("frames", {})
    with _phase(cache, G_BUFFERS):
        if (instant, 1) not in frames:
            frames[(instant, 1)] = [
                ctx.render(scene, settings.size, settings.shutter, instant=instant)
            ]
        if (instant, steps) not in frames:
            frames[(instant, steps)] = render_steps(
                ctx, scene, name, steps, settings.size, settings.shutter, **params
            )
    n = settings.reference_samples
    if n is None:  # once per scene: it reads the whole motion buffer back (55 ms at 1080p)
        if "default_samples" not in cache:
            cache["default_samples"] = default_reference_samples(frames[(instant, 1)][0])
        n = cache["default_samples"]
    return frames[(instant, steps)], _reference(ctx, scene, settings, n, cache)
