"""`blurlab study --capture`: every method on a G-buffer an engine captured, scored against a
reference of the same shutter from a file, with the engine's own blurred output, also from a
file, as a row beside them (docs/spec.md §16.6, docs/engine_output.md). A file pattern
(`shot.####.exr`) gives a sequence: each frame is scored, and the temporal metric
(docs/spec.md §21.3) compares how the outputs change from frame to frame with the reference.
Writes results.csv (one row per method configuration and one for the engine's output; a
sequence's metrics are the means over its frames, its PSNR that of the mean squared error),
frames.csv (a sequence's rows per frame) and report.html into one folder."""

from __future__ import annotations

import concurrent.futures
import dataclasses
import datetime
import html
import json
import math
import os
import re
from pathlib import Path

import numpy as np
import pandas as pd

from ..core.context import Context
from ..core.frame import Frame
from ..core.render import check_size
from ..docs_link import docs_anchor
from ..io import capture
from ..io import images as io
from ..methods import method, method_instant, methods
from ..metrics import (
    REFERENCES,
    check_names,
    cpu_scores,
    default_names,
    get,
    psnr_from_mse,
    temporal_instability,
)
from . import interactive
from .evaluation import Settings, evaluate_scene, picture_key, release_prepared
from .gallery import write_pictures
from .sweep import default_grids, grid_points

ENGINE_OUTPUT = "engine_output"  # the engine's row's default name
# The instant of a captured G-buffer: engines centre their motion-blur shutter on the frame
# they render, and each convention's motion is read as spanning that shutter (§16.1).
CAPTURE_INSTANT = "center"
# The methods' output colours kept from one frame of a sequence to the next (for the temporal
# metric), at most: configurations beyond it are evaluated in further passes over the files.
KEPT_BYTES = 1 << 30
NAME = re.compile(r"[A-Za-z0-9_.-]{1,64}")
TAA_NOTE = (
    "The engine's output is what the engine shows: it already carries the engine's temporal "
    "anti-aliasing (TAA), its upscaling and whatever else runs after its blur. The methods "
    "blur the captured G-buffer's colour, which has its TAA too where the engine captured it "
    "after TAA, but none of them runs a TAA of its own here: a gap between the engine's row "
    "and a method's can be its TAA (its jitter, history and clamping), not its blur."
)


@dataclasses.dataclass(frozen=True)
class CapturedShot:
    """What a sweep's evaluation needs of a scene, for a captured frame: its name, and that
    its colours are scored as LDR (an engine's displayed output)."""

    name: str
    hdr: bool = False


@dataclasses.dataclass
class FileReference:
    """A reference read from a file, uploaded once for the GPU metrics. It has no N: blurlab
    did not make it."""

    color: np.ndarray
    texture: object
    samples: int | None = None


def capture_grids(grids=None) -> tuple[dict[str, list[dict]], dict[str, str]]:
    """({method: its points that run on a capture}, {method: why none does}) for `grids`
    ({name: grid}, default every sweepable method's default grid). A capture is one G-buffer
    at the centre of the shutter: a method that renders sub-frames, blends a sequence or
    expects the G-buffer at shutter close cannot be run on it honestly, nor can `steps` > 1
    (renders of parts of the shutter)."""
    grids = default_grids() if grids is None else grids
    kept, left_out = {}, {}
    for name, grid in grids.items():
        m = method(name)
        if m.renders:
            left_out[name] = "renders sub-frames of the scene itself; a capture has no scene"
            continue
        if not m.sweepable:
            left_out[name] = "blends a sequence of frames of its own"
            continue
        points = [
            point
            for point in grid_points(grid)
            if point.get("steps", 1) == 1
            and method_instant(name, {k: v for k, v in point.items() if k != "steps"})
            == CAPTURE_INSTANT
        ]
        if points:
            kept[name] = points
        else:
            left_out[name] = (
                "expects the G-buffer at shutter close (or steps > 1); a capture's is at the "
                "centre of its shutter"
            )
    return kept, left_out


def open_inputs(
    capture_path, reference_path, engine_output_path=None, **read_options
) -> tuple[capture.CapturedSequence, capture.CapturedSequence, capture.CapturedSequence | None]:
    """The capture (read with `read_options`: convention, shutter_fraction, ...), the reference
    and the engine's output as sequences, checked against each other: the same number of
    frames, every frame of one size. A ValueError names the files that differ."""
    shot = capture.sequence(capture_path, **read_options)
    reference = capture.sequence(reference_path)
    outputs = capture.sequence(engine_output_path) if engine_output_path is not None else None
    size = shot.size()
    for what, other in (("reference", reference), ("engine output", outputs)):
        if other is None:
            continue
        if len(other) != len(shot):
            raise ValueError(
                f"blurlab study: the {what} {other.pattern} has {len(other)} "
                f"frame{'s' if len(other) != 1 else ''}, the capture {shot.pattern} "
                f"{len(shot)}; each frame of the capture needs its own"
            )
        here = other.size()
        if here != size:
            raise ValueError(
                f"blurlab study: the {what} {other.paths[0].name} is {here[0]}x{here[1]}, the "
                f"capture {shot.paths[0].name} {size[0]}x{size[1]}; they must be the same size"
            )
    return shot, reference, outputs


def capture_metrics(metrics, frames: int) -> tuple[str, ...]:
    """The metrics of a capture study: `metrics` checked, or by default the study's LDR
    defaults that score against one reference, and for a sequence temporal_instability. The
    file reference stands for both kinds of reference (docs/spec.md §11)."""
    if metrics is None:
        names = tuple(n for n in default_names(False) if get(n).reference == "temporal")
        return names + (("temporal_instability",) if frames > 1 else ())
    names = check_names(metrics, "blurlab study --capture", sequences=frames > 1)
    if not any(get(n).higher_is_better is not None for n in names):
        raise ValueError(f"blurlab study: ranks by a metric with a direction; {names} has none")
    return names


def run_capture_study(
    ctx: Context,
    capture_path,
    reference_path,
    engine_output_path=None,
    *,
    engine_name: str = ENGINE_OUTPUT,
    convention: str = "blurlab",
    shutter_fraction: float = 1.0,
    out="out/capture",
    metrics=None,
    grids=None,
    repeats: int = 3,
) -> Path:
    """Runs the capture study and returns the path of report.html.

    `capture_path`: a multi-layer EXR of colour, depth and motion (Blender's Combined, Depth
    and Vector, or the other names bl.Frame.from_exr finds), or a pattern of them
    (bl.capture.sequence), read in `convention` with `shutter_fraction`. `reference_path`: the
    converged image of the same shutter, or a pattern of one per frame. `engine_output_path`:
    the engine's own blurred output, likewise, scored as the row `engine_name`. `metrics`,
    `grids` and `repeats` as bl.sweep takes them (metrics default: capture_metrics)."""
    if not NAME.fullmatch(str(engine_name)) or engine_name in methods():
        raise ValueError(
            "blurlab study: --engine-name must be 1 to 64 letters, digits, '_', '.' or '-', and "
            f"no method's name, not {engine_name!r}"
        )
    if isinstance(repeats, bool) or not isinstance(repeats, int) or repeats < 0:
        raise ValueError(
            f"blurlab study: repeats must be an integer >= 1, or 0 to score without timing, "
            f"not {repeats!r}"
        )
    shot, reference, outputs = open_inputs(
        capture_path,
        reference_path,
        engine_output_path,
        convention=convention,
        shutter_fraction=shutter_fraction,
    )
    size = check_size(shot.size(), ctx.max_texture_size)
    names = capture_metrics(metrics, len(shot))
    kept, left_out = capture_grids(grids)
    if not kept and outputs is None:
        raise ValueError(
            f"blurlab study: nothing to score on a capture: no method runs on one "
            f"({', '.join(left_out) or 'none given'}) and there is no engine output"
        )
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    label = shot_label(shot)
    shown_frame = len(shot) // 2
    settings = Settings(
        size, None, 0, tuple(n for n in names if not get(n).sequence), repeats, readback_batch=16
    )
    frame_rows, images = method_rows(ctx, shot, reference, kept, settings, label, shown_frame)
    engine = None
    if outputs is not None:
        rows, engine = _engine_rows(outputs, reference, settings.metrics, engine_name, label)
        frame_rows += rows
    table = _summary(frame_rows, names, shot, reference, outputs)
    io.write_text(out / "results.csv", table.to_csv(index=False))
    if len(shot) > 1:
        io.write_text(out / "frames.csv", pd.DataFrame(frame_rows).to_csv(index=False))
    shown = dict(images)
    if engine is not None:
        shown[engine_name] = engine
    with concurrent.futures.ThreadPoolExecutor(os.cpu_count() or 1) as pool:
        gallery, encodes = write_pictures(label, reference.color(shown_frame), shown, out, pool)
        for encode in encodes:
            encode.result()
    page = _html(ctx.info(), shot, reference, outputs, table, names, left_out, gallery)
    return io.write_text(out / "report.html", page)


# study's options that go with --capture, and their defaults (given without it, refused).
CAPTURE_OPTIONS = {
    "capture": None,
    "reference": None,
    "engine_output": None,
    "engine_name": ENGINE_OUTPUT,
    "convention": "blurlab",
    "shutter_fraction": 1.0,
}


def add_capture_options(study) -> None:
    """`blurlab study`'s options for a capture (an argparse parser's)."""
    group = study.add_argument_group(
        "your engine's capture (docs/engine_output.md)",
        "score every method on a G-buffer an engine captured (at its own size; --size does "
        "not apply), against a reference from a file, the engine's own output beside them",
    )
    add_capture_file_options(group)
    group.add_argument(
        "--engine-output",
        metavar="PATH",
        help="with --capture: the engine's own blurred output (EXR, or a pattern), a row "
        "beside the methods",
    )
    group.add_argument(
        "--engine-name",
        default=ENGINE_OUTPUT,
        help=f"with --capture: the engine output's row (default {ENGINE_OUTPUT})",
    )


def add_capture_file_options(group, repeated: bool = False) -> None:
    """--capture, --reference, --convention and --shutter-fraction, for `blurlab study` and
    `blurlab suite run`; `repeated`: --capture and --reference may each be given more than
    once, paired in order."""
    action = "append" if repeated else "store"
    again = " (again for another capture)" if repeated else ""
    group.add_argument(
        "--capture",
        metavar="PATH",
        action=action,
        help="a multi-layer EXR of colour, depth and motion (Blender's Combined, Depth, "
        f"Vector), or a pattern shot.####.exr (# = the frame number) for a sequence{again}",
    )
    group.add_argument(
        "--reference",
        metavar="PATH",
        action=action,
        help="with --capture: the converged image of the same shutter (EXR), or a pattern"
        + (", one for each --capture in order" if repeated else ""),
    )
    group.add_argument(
        "--convention",
        default="blurlab",
        help=f"the capture's motion: {', '.join(capture.MOTION_CONVENTIONS)} (default "
        "blurlab; docs/spec.md §16.1)",
    )
    group.add_argument(
        "--shutter-fraction",
        type=float,
        default=1.0,
        metavar="S",
        help="the shutter as a fraction of the frame, for motion stored per frame (default 1)",
    )


def capture_command(ctx: Context, args) -> bool:
    """`blurlab study --capture ...`: runs it and says so (True); without --capture, refuses
    its options and returns False (the study of blurlab's scenes goes on)."""
    if args.capture is None:
        stray = [k for k, default in CAPTURE_OPTIONS.items() if getattr(args, k) != default]
        if stray:
            options = ", ".join("--" + name.replace("_", "-") for name in stray)
            raise ValueError(f"study: {options} {'is' if len(stray) == 1 else 'are'} for --capture")
        return False
    others = {
        "--scenes": args.scenes,
        "--random": args.random is not None,
        "--transparency": args.transparency,
        "--peers": args.peers,
        "--sequence": args.sequence,
        "--reference-samples": args.reference_samples is not None,
        "--scheduler/--workers": args.scheduler or args.workers,
    }
    given = [option for option, value in others.items() if value]
    if given:
        raise ValueError(
            f"study --capture scores the methods on the captured G-buffer; {', '.join(given)} "
            "are for the study of blurlab's scenes"
        )
    if args.reference is None:
        raise ValueError("study --capture needs --reference PATH, the image to score against")
    info = ctx.info()
    print(f"device: {info['device']} ({info['renderer']}); capture {args.capture}")
    report = run_capture_study(
        ctx,
        args.capture,
        args.reference,
        args.engine_output,
        engine_name=args.engine_name,
        convention=args.convention,
        shutter_fraction=args.shutter_fraction,
        out=args.out,
        metrics=None if args.metrics == "auto" else tuple(args.metrics.split(",")),
    )
    print(f"wrote {report} and {Path(args.out) / 'results.csv'}")
    return True


def shot_label(shot: capture.CapturedSequence) -> str:
    """A name for the shot in rows and file names: its file name up to the frame number."""
    stem = Path(shot.pattern).name.split(capture.FRAME_NUMBER)[0].split(".")[0]
    return re.sub(r"[^A-Za-z0-9_.-]", "_", stem).strip("._") or "capture"


def method_rows(ctx, shot, reference, kept: dict, settings: Settings, label, shown_frame):
    """Every configuration of `kept` on every frame: the rows (one per frame, with "frame" and,
    for a sequence, the frame pair's share of temporal_instability), and each method's middle
    point's colour on frame `shown_frame`. Configurations whose kept colours would pass
    KEPT_BYTES go in further passes over the files."""
    jobs = [
        (name, point, None, f"{name} {json.dumps(point, sort_keys=True)}")
        for name, points in kept.items()
        for point in points
    ]
    shown = {picture_key(name, points[len(points) // 2]) for name, points in kept.items()}
    per_job = settings.size[0] * settings.size[1] * 16  # an RGBA float32 colour
    group = max(1, KEPT_BYTES // per_job if len(shot) > 1 else len(jobs))
    rows, images = [], {}
    for start in range(0, len(jobs), group):
        chosen = jobs[start : start + group]
        keep = {picture_key(name, point) for name, point, _, _ in chosen}
        previous = None
        for i in range(len(shot)):
            frame = Frame(**shot[i])
            ref = _uploaded(ctx, finite_color(reference, i, "reference"))
            cache = {
                "frames": {(CAPTURE_INSTANT, 1): [frame]},
                "reference": ref,
                "reference_aa": ref,  # the file's reference stands for both kinds
                "keep_colours": keep if len(shot) > 1 else keep & shown,
            }
            try:
                evaluated = list(evaluate_scene(ctx, CapturedShot(label), chosen, settings, cache))
            finally:
                release_prepared(cache)
                ctx.recycle(ref.texture)
            colours = cache.get("colours", {})
            for _, row in evaluated:
                row["frame"] = shot.numbers[i]
                row["source"] = "method"
                point_key = picture_key(row["method"], json.loads(row["params"]))
                if previous is not None:
                    row["temporal_instability"] = _pair_instability(
                        previous[0], ref.color, previous[1][point_key], colours[point_key]
                    )
                rows.append(row)
            if i == shown_frame:
                images.update({k[0]: v for k, v in colours.items() if k in shown})
            previous = (ref.color, colours)
    return rows, images


def finite_color(files: capture.CapturedSequence, index: int, what: str) -> np.ndarray:
    """Frame `index`'s colour from `files`, a reference or an engine's output; a NaN or an
    infinity there would make every score of its frame NaN, so it is refused, naming the file."""
    colour = files.color(index)
    bad = ~np.isfinite(colour[..., :3])
    if bad.any():
        raise ValueError(
            f"blurlab study: the {what} {files.paths[index].name} has {int(bad.sum())} NaN or "
            "infinite colour values; a reference and an engine's output must be finite"
        )
    return colour


def _uploaded(ctx, color: np.ndarray) -> FileReference:
    texture = ctx.pooled(color.shape)
    texture.upload(np.ascontiguousarray(color, np.float32))
    return FileReference(color, texture)


def _pair_instability(reference_before, reference_now, output_before, output_now) -> float:
    """One frame pair's share of temporal_instability: the metric on the two frames."""
    return temporal_instability(
        np.stack([reference_before, reference_now]), np.stack([output_before, output_now])
    )


def _engine_rows(outputs, reference, wanted, engine_name: str, label):
    """The engine's output scored frame by frame as the methods are (each metric's NumPy
    definition, as a peer's row is), and its colour on the shown frame."""
    rows, previous, shown = [], None, None
    shown_frame = len(outputs) // 2
    for i in range(len(outputs)):
        ref = finite_color(reference, i, "reference")
        colour = finite_color(outputs, i, "engine output")
        row = {
            "scene": label,
            "method": engine_name,
            "params": "{}",
            "source": str(outputs.paths[i].name),
            "frame": outputs.numbers[i],
            **cpu_scores(wanted, dict.fromkeys(REFERENCES, ref), colour),
        }
        if previous is not None:
            row["temporal_instability"] = _pair_instability(previous[0], ref, previous[1], colour)
        rows.append(row)
        previous = (ref, colour)
        if i == shown_frame:
            shown = colour
    return rows, shown


def _summary(frame_rows: list, names, shot, reference, outputs) -> pd.DataFrame:
    """One row per configuration and one for the engine: the first frame's row, with each
    per-frame metric and time its mean over the frames and temporal_instability the mean of
    the frame pairs' shares. A PSNR (a metric reduced from the squared error) is that of the
    mean squared error over the frames, as `blurlab study --sequence` takes it: a frame that
    matches its reference exactly would otherwise make the mean infinite."""
    table = pd.DataFrame(frame_rows)
    averaged = [
        c
        for c in table.columns
        if c in names or c == "total_ms" or c.startswith("ms_") or c == "temporal_instability"
    ]
    rows = []
    for _, group in table.groupby(["method", "params"], sort=False):
        row = group.iloc[0].to_dict()
        for column in averaged:
            values = group[column].dropna()
            if not len(values):
                row[column] = math.nan
            elif column in names and get(column).reduction == "squared_error":
                row[column] = psnr_from_mse(float(np.mean(10.0 ** (-values / 10.0))))
            else:
                row[column] = float(values.mean())
        row.update(frames=len(group), capture=shot.pattern, reference=reference.pattern)
        if row["source"] != "method":
            row["source"] = outputs.pattern
        row.pop("frame", None)
        rows.append(row)
    return pd.DataFrame(rows)


def _html(info, shot, reference, outputs, table, names, left_out, gallery) -> str:
    e = html.escape
    rank = next(n for n in names if get(n).higher_is_better is not None)
    ordered = table.assign(_goodness=get(rank).goodness(table[rank])).sort_values(
        "_goodness", ascending=False
    )
    columns = [c for c in ("method", "params", "total_ms", *names) if c in ordered]
    when = datetime.datetime.now().strftime("%Y-%m-%d %H:%M")
    frames = len(shot)
    inputs = [("capture", shot.pattern), ("reference", reference.pattern)]
    if outputs is not None:
        inputs.append(("engine output", outputs.pattern))
    parts = [
        "<!doctype html><meta charset='utf-8'><title>blurlab study: a capture</title>",
        f"<style>{interactive.PAGE_STYLE}</style>",
        "<h1>blurlab study: the methods on a captured G-buffer</h1>",
        f"<p>{e(when)} · device <b>{e(info['renderer'])}</b> · {frames} frame"
        f"{'s' if frames > 1 else ''} · data: <a href='results.csv'>results.csv</a>"
        + (" and <a href='frames.csv'>frames.csv</a>" if frames > 1 else "")
        + "</p><ul>"
        + "".join(f"<li>{e(what)}: <code>{e(path)}</code></li>" for what, path in inputs)
        + f"<li>convention: <code>{e(str(shot.options.get('convention', 'blurlab')))}</code>, "
        f"shutter fraction {shot.options.get('shutter_fraction', 1.0)}</li></ul>",
        "<p>Each method blurs the captured G-buffer; every row, the engine's output's too, is "
        "scored against the reference from the file"
        + (
            ", each metric its mean over the frames (PSNR: that of the mean squared error)"
            if frames > 1
            else ""
        )
        + ". Time is the sum of the method's passes on this device; the engine's output has "
        "none (its time is the engine's). The metrics "
        f"({docs_anchor('metrics', 'metrics')}):</p><ul>"
        + "".join(f"<li><code>{e(n)}</code>: {e(get(n).axis_title)}</li>" for n in names)
        + "</ul>",
        f"<p><b>TAA.</b> {e(TAA_NOTE)}</p>",
        f"<h2>Every row, best {e(get(rank).label)} first</h2>",
        ordered[columns].to_html(index=False, float_format=lambda v: f"{v:.4g}", border=0),
    ]
    if left_out:
        parts.append(
            "<p>Methods not run on a capture:</p><ul>"
            + "".join(f"<li>{e(n)}: {e(why)}</li>" for n, why in left_out.items())
            + "</ul>"
        )
    shown = f"frame {shot.numbers[frames // 2]}" if frames > 1 else "the frame"
    parts.append(f"<h2>Images ({e(shown)}, each method at the middle of its grid)</h2>" + gallery)
    parts.append(
        "<p>Made by <code>blurlab study --capture</code>; "
        f"{docs_anchor('engine_output', 'Your engine’s output')} says how to make the files.</p>"
    )
    return "\n".join(parts)


__all__ = [
    "ENGINE_OUTPUT",
    "add_capture_options",
    "capture_command",
    "capture_grids",
    "open_inputs",
    "run_capture_study",
]
