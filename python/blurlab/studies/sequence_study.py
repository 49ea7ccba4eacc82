"""`blurlab study --sequence`: every method before TAA, after it and inside its history, on
sequences of the chosen scenes (docs/spec.md §21.4), written as sequence.csv, a looping
animation of each method's worst frames beside the reference, and sequence.html with an
accuracy-against-stability chart per scene (docs/temporal.md)."""

from __future__ import annotations

import concurrent.futures
import datetime
import html
import os
from pathlib import Path

import pandas as pd

from ..io import images as io
from ..io import video
from ..metrics import get
from ..scene import scenes
from ..sizes import DEFAULT_SIZE
from ..temporal.sequences import ORDERS
from . import interactive, temporal
from .evaluation import PhaseClock, phase_lines, write_phases

ANIMATED_ORDER = "blur_then_taa"  # the order every method takes, the one the animations show
WORST_FRAMES = 6

# What each phase of phases.json counts.
PHASES = {
    "sequences": "each scene's sequence: its frames' times and references, rendered",
    "runs": "every method in every order over the frames, with TAA and the per-frame metrics",
    "animations": "each method's worst frames beside the reference, downloaded; their WebP "
    "encodes run on threads beside the runs (what is counted is the wait for them)",
    "html": "sequence.csv and sequence.html",
}


def run_sequence_study(
    ctx,
    scene_names=None,
    size=DEFAULT_SIZE,
    out="out/sequence",
    reference_samples: int | None = None,
    frames: int = 8,
    warmup: int = 4,
    fps: float = 60.0,
    progress: bool = True,
) -> Path:
    """Runs the sequence study and returns the path of sequence.html. Each phase is timed
    (PHASES): phases.json and, with `progress`, the console."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    names = list(scene_names or scenes.names())
    methods = temporal.sequence_methods()
    animations: dict[str, dict[str, str]] = {}
    clock = PhaseClock()
    threads = os.cpu_count() or 1
    # WebP encodes release the GIL, so they run beside the GPU work; at most two a thread are
    # queued, each holding its frames on the host (6 frames of 3840x1080 RGBA at 1080p).
    encodes: list[concurrent.futures.Future] = []

    with concurrent.futures.ThreadPoolExecutor(threads) as pool:

        def keep(scene: str, method: str, order: str, run) -> None:
            if order != ANIMATED_ORDER:
                return
            with clock("animations"):
                folder = out / "animations" / scenes.label(scene)
                folder.mkdir(parents=True, exist_ok=True)
                path = folder / f"{method}.webp"
                shown = run.side_by_side(run.worst_frames("psnr", WORST_FRAMES))
                while sum(not e.done() for e in encodes) >= 2 * threads:
                    concurrent.futures.wait(encodes, return_when="FIRST_COMPLETED")
                encodes.append(pool.submit(video.write, path, shown, run.fps))
            animations.setdefault(scene, {})[method] = path.relative_to(out).as_posix()

        table = temporal.evaluate_orders(
            ctx,
            names,
            methods,
            size,
            frames,
            warmup,
            reference_samples or 64,
            fps,
            on_run=keep,
            clock=clock,
        )
        with clock("animations"):
            for encode in encodes:
                encode.result()  # raises a failed one's error
    with clock("html"):
        io.write_text(out / "sequence.csv", table.to_csv(index=False))
        summary = temporal.orders_summary(table)
        page = _html(ctx.info(), size, fps, frames, warmup, table, summary, animations)
        report = io.write_text(out / "sequence.html", page)
    write_phases(out, clock, PHASES, ctx.info(), size, len(table))
    if progress:
        print(phase_lines(clock, "study --sequence"))
    return report


def stability_chart(rows: pd.DataFrame, title: str):
    """A plotly Figure of one scene's rows: PSNR against temporal instability, a trace per
    order, a point per method."""
    import plotly.graph_objects as go

    fig = go.Figure()
    for order in ORDERS:
        group = rows[rows["order"] == order]
        if group.empty:
            continue
        hover = [
            f"<b>{r.method}</b><br>{order}<br>PSNR {r.psnr:.4g} dB<br>"
            f"instability {r.temporal_instability:.4g}"
            for r in group.itertuples()
        ]
        fig.add_trace(
            go.Scatter(
                x=group["temporal_instability"],
                y=group["psnr"],
                mode="markers",
                name=order,
                text=hover,
                hovertemplate="%{text}<extra></extra>",
                marker={"size": 9, "opacity": 0.85},
            )
        )
    fig.update_layout(
        title={"text": title, "x": 0.0, "xanchor": "left"},
        xaxis={"title": {"text": get("temporal_instability").axis_title}},
        yaxis={"title": {"text": get("psnr").axis_title}},
        height=420,
        legend={"title": {"text": "order (click to hide / show)"}},
    )
    return fig


def _html(info, size, fps, frames, warmup, table, summary, animations) -> str:
    e = html.escape
    when = datetime.datetime.now().strftime("%Y-%m-%d %H:%M")
    parts = [
        "<!doctype html><meta charset='utf-8'><title>blurlab sequence study</title>",
        f"<style>{interactive.PAGE_STYLE}.gallery figure,.gallery img{{width:340px}}"
        ".gallery img{image-rendering:pixelated}</style>",
        "<h1>blurlab sequence study: accuracy against stability</h1>",
        f"<p>{e(when)} · device <b>{e(info['renderer'])}</b> · {size[0]}×{size[1]} · "
        f"{fps:g} fps, 180° shutter · {frames} frames measured after {warmup} · data: "
        "<a href='sequence.csv'>sequence.csv</a></p>",
        "<p>Each method runs on every frame alone (<code>none</code>), before TAA "
        "(<code>blur_then_taa</code>), after it (<code>taa_then_blur</code>) and with its "
        "output fed back as TAA's history (<code>blur_in_history</code>), docs/spec.md §21.4. "
        "PSNR is that of the mean squared error over the measured frames; temporal "
        "instability compares each frame's change with the reference's (§21.3). Up and to "
        "the left is better.</p>",
        "<h2>Per method: the order with the best median PSNR over the scenes</h2>",
        summary["winners"].to_html(index=False, float_format=lambda v: f"{v:.3g}", border=0),
    ]
    for index, (scene, rows) in enumerate(table.groupby("scene", sort=False)):
        label = scenes.label(scene)
        chart = stability_chart(rows, label)
        parts.append(f"<h2>{e(label)}</h2>")
        parts.append(interactive.chart_html(chart, index == 0, f"stability-{index}"))
        parts.append(
            f"<p>The {WORST_FRAMES} frames with the lowest PSNR of each method before TAA, "
            "looping: the output on the left, the reference on the right.</p>"
        )
        parts.append("<div class='gallery'>")
        for method, src in animations.get(scene, {}).items():
            parts.append(
                f"<figure><img src='{e(src)}' alt='{e(method)}'>"
                f"<figcaption>{e(method)}</figcaption></figure>"
            )
        parts.append("</div>")
    return "\n".join(parts) + "\n"
