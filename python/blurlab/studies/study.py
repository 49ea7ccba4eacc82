"""`blurlab study`: every built-in scene, every single-frame method at its default grid; writes
results.csv, charts, image grids and report.html into one folder."""

from __future__ import annotations

import concurrent.futures
import contextlib
import dataclasses
import datetime
import html
import os
import re
import sys
import time
from pathlib import Path

import pandas as pd

from .. import metrics
from ..core.context import Context
from ..docs_link import docs_anchor
from ..io import images as io
from ..methods import blur, method, method_instant, methods
from ..metrics import check_names, get, registered
from ..scene import scenes
from ..sizes import DEFAULT_SIZE
from . import comparator, interactive, objects, peers, plots, rankings, transparency, workers
from .cluster import account_table
from .evaluation import SETUP_PHASES, PhaseClock, phase_lines, picture_key, write_phases
from .gallery import write_pictures
from .sweep import default_grids, middle_point, sweep

BUDGETS_MS = (0.1, 1.0, 10.0, 100.0)


# What each phase of phases.json counts (the report's "Where the time went" says the same).
PHASES = {
    "references": "the converged references (the sweep's, and any the report still needs)",
    "g_buffers": "the G-buffers the methods run on, one per scene and instant",
    "evaluations": "every configuration timed (repeats) and scored (PSNR, SSIM, FLIP, ...)",
    "sweep_on_cluster": "the whole sweep on Dask workers (references included)",
    "images": "each scene's pictures: the methods' images at their middle points, error "
    "maps, crops, the image grid (begun as soon as the sweep has evaluated the scene and "
    "encoded on threads while it goes on: what is counted is this thread's part and the wait "
    "at the end)",
    "charts": "Pareto charts (PNG and interactive) and parameter curves (the PNGs drawn in "
    "processes of their own: what is counted is the wait for them)",
    "features": "each scene's features for results.csv (measured on threads from the sweep's "
    "G-buffer as soon as the scene is evaluated, else on its G-buffer rendered once more: what "
    "is counted is this thread's part and the wait at the end)",
    "per_object": "the per-object table of textured_spin (its own renders; the sweep's reference)",
    "peers": "the peers' renders (EEVEE)",
    "transparency": transparency.REPORT_PHASE,
    "html": "the report's HTML",
}


def run_study(
    ctx: Context,
    scene_names=None,
    size=DEFAULT_SIZE,
    out="out/study",
    reference_samples: int | None = None,
    metrics=None,
    grids=None,
    progress: bool = True,
    cluster=None,
    peer_names=(),
    chart_processes: int | None = None,
) -> Path:
    """Runs the study and returns the path of report.html. With `cluster` (as bl.sweep takes
    it) the sweep runs on Dask workers; `ctx` still renders the report's images. `metrics`
    as bl.sweep takes them: None measures HDR scenes (bl.scenes.names("hdr")) with the HDR
    metrics too, ranks them by an HDR metric and shows their images tone-mapped. `peer_names`
    ("eevee") adds Blender's EEVEE as rows scored against the same references with the same
    metrics (peers.csv); a scene Blender cannot reproduce gets rows that say why, and its
    section of the report says so too.
    Each phase is timed (PHASES): phases.json, the report's last table and, with `progress`,
    the console. `chart_processes`: how many processes draw the matplotlib charts (default
    default_chart_processes(); 0 draws them in this one). With a random scene among the scenes,
    every row gets its scene's bl.scenes.FEATURES (docs/spec.md §22.2)."""
    clock = PhaseClock()
    peer_names = peers.check_peers(peer_names)
    if metrics is not None:  # checked before any work
        metrics = check_names(metrics, "blurlab study")
        if all(get(n).higher_is_better is None for n in metrics):
            raise ValueError(
                f"blurlab study: ranks each scene by a metric with a direction; {list(metrics)} "
                "has none"
            )
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    # Independent PNG encodes run side by side (zlib and NumPy release the GIL), the charts in
    # their processes: this thread waits for both at the end.
    with (
        chart_pool(chart_processes) as charts,
        concurrent.futures.ThreadPoolExecutor(os.cpu_count() or 1) as pool,
    ):
        work = ReportWork(pool, charts)
        names = list(scene_names or scenes.names())
        grids = grids or default_grids()
        # Per scene, what the sweep rendered and each method's picture (its grid's middle point):
        # the report shows the same, without rendering or blurring them again.
        shown = {picture_key(m, middle_point(g)) for m, g in grids.items()}
        pictured = pictured_scenes(names)
        caches: dict = {
            scenes.get(item).name: {"keep_colours": shown if item in pictured else set()}
            for item in names
        }
        featured = any(scenes.parse_random_name(item) is not None for item in names)
        galleries: dict = {}
        measuring: dict = {}  # scene name: the future of its features

        def after_scene(scene, cache: dict) -> None:
            """What begins as soon as the sweep has evaluated a scene, on threads while the GPU
            evaluates the next ones: a pictured scene's gallery, and with random scenes the
            scene's features, measured on the sweep's own G-buffer at the shutter's centre."""
            reference = cache.get("reference")
            if cache.get("keep_colours") and reference is not None:
                galleries[scene.name] = _gallery(
                    ctx, scene, size, out, grids, cache, work, clock, reference.samples
                )
            centre = cache.get("frames", {}).get(("center", 1))
            if featured and centre:
                with clock("features"):  # the fields' downloads; the measure runs on a thread
                    measuring[scene.name] = pool.submit(
                        scenes.features, scenes.frame_arrays(centre[0])
                    )

        def beside_the_sweep() -> float:
            return clock.seconds.get("images", 0.0) + clock.seconds.get("features", 0.0)

        start = time.perf_counter()
        before = beside_the_sweep()
        table = sweep(
            None if cluster is not None else ctx,
            names,
            grids,
            size,
            reference_samples=reference_samples,
            metrics=metrics,
            out=out / "results.csv",
            progress=progress,
            cluster=cluster,
            caches=caches,
            on_scene=after_scene,
        )
        # what began during the sweep is counted as images and features, not as evaluations
        swept = time.perf_counter() - start - (beside_the_sweep() - before)
        if featured:
            with clock("features"):  # joined to every row; results.csv written anew
                measured = {name: job.result() for name, job in measuring.items()}
                table = scenes.with_features(
                    ctx, table, map(scenes.get, names), size, out, measured=measured
                )
        worker_accounts = table.attrs.get("workers")  # where each worker's time went (cluster)
        if cluster is not None:
            clock.add("sweep_on_cluster", swept)
        else:
            for phase in SETUP_PHASES:
                spent = sum(
                    c["clock"].seconds.get(phase, 0.0) for c in caches.values() if "clock" in c
                )
                clock.add(phase, spent)
                swept -= spent
            clock.add("evaluations", swept)
        info = ctx.info()
        sections = []
        spin_reference = None  # textured_spin's, for the per-object table
        for item in names:
            scene = scenes.get(item)
            cache = caches.pop(scene.name, {})  # freed with the section
            if scene.name == "textured_spin":
                spin_reference = cache.get("reference")
            sections.append(
                _scene_section(
                    ctx,
                    scene,
                    table,
                    size,
                    out,
                    grids,
                    not sections,
                    cache,
                    work,
                    clock,
                    pictures=item in pictured,
                    gallery=galleries.pop(scene.name, None),
                )
            )
        curves: list = []
        for name in grids:
            curves += _parameter_curves(table, name, method(name).study_curves, out, curves, work)
        per_object = None
        if "textured_spin" in names:  # the OGRE paper's test matrix
            with clock("per_object"):
                per_object = objects.object_errors(
                    ctx, size, reference_samples=reference_samples, reference=spin_reference
                )
                per_object.to_csv(out / "per_object.csv", index=False)
        peer_rows = None
        if peer_names:
            with clock("peers"):
                peer_rows = peers.peer_table(
                    ctx,
                    {s["scene"]: scenes.get(item) for s, item in zip(sections, names, strict=True)},
                    size,
                    {s["scene"]: s["reference_samples"] for s in sections},
                    metrics,
                )
                peer_rows.to_csv(out / "peers.csv", index=False)
        with clock("images"):
            for write in work.pictures_written:
                write.result()  # raises a failed one's error
        with clock("charts"):
            for drawing in work.charts_drawn:
                drawing.result()
        # the phases in the order PHASES lists them, whatever order they began in (the images
        # and features of a scene begin during the sweep)
        clock.seconds = {
            **{k: clock.seconds[k] for k in PHASES if k in clock.seconds},
            **clock.seconds,
        }
        with clock("html"):
            report = _html(info, size, table, sections, curves, per_object, peer_rows, clock)
            path = io.write_text(out / "report.html", report)
        workers = {} if worker_accounts is None else {"workers": worker_accounts}
        write_phases(out, clock, PHASES, info, size, len(table), **workers)
        if progress:
            print(phase_lines(clock))
            if worker_accounts is not None:
                print(f"the sweep on the cluster:\n{account_table(worker_accounts, swept)}")
        return path


def default_chart_processes() -> int:
    """Chart processes by default: a quarter of the cores, 1 to 4 (on 2 cores one process,
    so that the charts do not take the renderer's cores during the sweep)."""
    return max(1, min(4, (os.cpu_count() or 1) // 4))


@contextlib.contextmanager
def chart_pool(processes: int | None = None):
    """An executor for the matplotlib charts. matplotlib holds the GIL while it draws, so
    threads would not overlap it: worker processes (blurlab.studies.workers) import it at
    once, which overlaps its import (and, on a fresh machine, its font cache) with the sweep.
    0 processes, or no `sys.executable` to start them with: an executor that runs each job as
    it is submitted."""
    processes = default_chart_processes() if processes is None else processes
    if isinstance(processes, bool) or not isinstance(processes, int) or processes < 0:
        raise ValueError(
            f"blurlab study: chart_processes must be an integer >= 0, not {processes!r}"
        )
    if processes == 0 or not sys.executable:  # no interpreter to start (an embedded Python)
        yield InlineExecutor()
        return
    with workers.ProcessWorkers(processes, warm_up=plots.load_matplotlib) as pool:
        yield pool


class InlineExecutor(concurrent.futures.Executor):
    """Runs each submitted call at once, in the caller's thread; its future holds the result
    or the exception."""

    def submit(self, fn, /, *args, **kwargs):
        future: concurrent.futures.Future = concurrent.futures.Future()
        try:
            future.set_result(fn(*args, **kwargs))
        except BaseException as error:  # handed to whoever reads the future, as a pool would
            future.set_exception(error)
        return future


_CURVE_TITLES = {
    "samples": "S sweep (the thesis's Table 5.2, with accuracy)",
    "k": "k sweep (the thesis's Table 5.3, with accuracy)",
}


def _parameter_curves(
    table, name: str, params: tuple[str, ...], out: Path, earlier, work: ReportWork
) -> list:
    """Time and error against each of `params` for method `name`, the others fixed (the
    thesis's tables 5.2 and 5.3): [(title, png name)] of the charts, each left drawing on
    `work`. A chart is curve_<param>.png unless an `earlier` one took that name."""
    rows = table[table["method"] == name]
    columns = [f"param_{p}" for p in params]
    if len(rows) == 0 or any(c not in rows or rows[c].nunique() < 2 for c in columns):
        return []
    curves = []
    for param in params:
        fixed = {}
        for other in params:
            if other != param:
                values = set(rows[f"param_{other}"])
                # The other parameter at its declared default where the grid has it.
                usual = method(name).params[other].default
                fixed[other] = usual if usual in values else int(rows[f"param_{other}"].iloc[0])
        png = f"curve_{param}.png"
        if png in {file for _, file in earlier}:
            png = f"curve_{name}_{param}.png"
        work.draw(plots.parameter_curves, (table, name, param, fixed), out / png)
        curves.append((_CURVE_TITLES.get(param, f"{param} sweep of {name}"), png))
    return curves


def _metric_columns(rows) -> list[str]:
    """The registered metrics that `rows` has values of, in registry order."""
    return [n for n in registered() if n in rows and rows[n].notna().any()]


def _ranking_metric(rows) -> str:
    """The metric the rows are ranked by: the first the charts offer (plots.charted_metrics:
    on HDR scenes an HDR one, as clipped PSNR cannot see their lights)."""
    return plots.charted_metrics(rows)[0]


@dataclasses.dataclass
class ReportWork:
    """The report's work left running: pictures on `pictures` (threads), matplotlib charts on
    `charts` (processes), and the futures of each, which the study waits for at the end."""

    pictures: concurrent.futures.Executor
    charts: concurrent.futures.Executor
    pictures_written: list = dataclasses.field(default_factory=list)
    charts_drawn: list = dataclasses.field(default_factory=list)

    def draw(self, chart, args: tuple, path: Path) -> None:
        """Draws chart(*args) (a function of blurlab.studies.plots) into `path`."""
        self.charts_drawn.append(self.charts.submit(plots.draw_and_save, chart, args, path))


# A study with random scenes pictures the first few of them. The rest have their tables and
# charts: a gallery of each of 100 random scenes at 1080p is 4,000 PNGs, gigabytes of report,
# and most of the study's time (docs/performance.md).
RANDOM_SCENES_PICTURED = 3


def pictured_scenes(names) -> set:
    """The items of `names` whose section has pictures: every named scene, and the first
    RANDOM_SCENES_PICTURED random ones."""
    randoms = [n for n in names if scenes.parse_random_name(n) is not None]
    return {n for n in names if n not in randoms[RANDOM_SCENES_PICTURED:]}


def _scene_section(
    ctx,
    scene,
    table,
    size,
    out: Path,
    grids,
    first: bool,
    cache: dict,
    work: ReportWork,
    clock,
    pictures: bool = True,
    gallery: tuple | None = None,
) -> dict:
    """One scene's part of the report. `cache`: what the sweep rendered for the scene (its
    reference and G-buffers, reused here); pictures and charts are left running on `work`.
    Without `pictures`, the section has no images (and nothing is rendered for them).
    `gallery`: what _gallery gave for the scene where the study began it during the sweep."""
    rows = table[table["scene"] == scene.name]
    name = _file_name(scene.name)
    rank = _ranking_metric(rows)
    samples = int(rows["reference_samples"].iloc[0])
    with clock("charts"):
        work.draw(plots.pareto, (rows, scene.name, rank), out / f"{name}_pareto.png")  # papers
        chart = interactive.chart_html(
            interactive.pareto_chart(rows, f"{scene.name}: time against error"),
            first,
            f"pareto-{name}",
        )
    if gallery is not None:
        gallery, exposure = gallery
    elif pictures:
        gallery, exposure = _gallery(ctx, scene, size, out, grids, cache, work, clock, samples)
    else:
        gallery, exposure = (
            f"<p>No pictures: a study pictures its first {RANDOM_SCENES_PICTURED} random scenes "
            f"only; <code>blurlab study --scenes {html.escape(scene.name)}</code> pictures this "
            "one.</p>",
            None,
        )
    best = []
    for budget in BUDGETS_MS:
        within = rows[rows["total_ms"] <= budget]
        if len(within):
            ranked = get(rank).goodness(within[rank]).sort_values(ascending=False)
            top = within.loc[ranked.index[0]]
            best.append((budget, top["method"], top["params"], top["total_ms"], top[rank]))
        else:  # say so, and how fast the fastest configuration is, for comparison
            fastest = rows.sort_values("total_ms").iloc[0]
            best.append(
                (
                    budget,
                    f"nothing within budget (fastest: {fastest['method']})",
                    fastest["params"],
                    fastest["total_ms"],
                    fastest[rank],
                )
            )
    return {
        "name": name,
        "scene": scene.name,
        "title": scene.name if scene.source is None else f"{scene.name} (from {scene.source})",
        "rows": rows,
        "best": best,
        "chart": chart,
        "gallery": gallery
        + transparency.report(
            ctx, scene, grids, size, out, work, clock, samples, cache.get("reference_aa")
        ),
        "reference_samples": int(rows["reference_samples"].iloc[0]),
        "rank": rank,
        "exposure": exposure,
        "pictured": pictures,
    }


def _file_name(scene_name: str) -> str:
    """What a scene's files are named after: its name, safe in a URL."""
    return re.sub(r"[^A-Za-z0-9_.-]", "_", scene_name)


def _gallery(ctx, scene, size, out: Path, grids, cache: dict, work: ReportWork, clock, samples):
    """(the gallery's HTML, the exposure of an HDR scene's pictures or None): each method at the
    middle of its grid beside the reference, encoded on `work` into files named after the
    scene."""
    name = _file_name(scene.name)
    reference = cache.get("reference")
    if reference is None or reference.samples != samples:  # rows read back from results.csv
        with clock("references"):
            reference = ctx.reference(scene, size, samples=samples, progress=False)
    with clock("images"):
        # Images: each method at the middle of its grid, against the reference.
        frames, colours = cache.get("frames", {}), cache.get("colours", {})
        images = {}
        for method_name, grid in grids.items():
            point = middle_point(grid)
            instant = method_instant(method_name, point)
            kept = colours.get(picture_key(method_name, point))
            if kept is not None:
                images[method_name] = kept
                continue
            if (instant, 1) in frames:
                frame = frames[(instant, 1)][0]
            else:
                frame = ctx.render(scene, size, instant=instant)
            images[method_name] = blur(ctx, frame, method_name, **point).color
        look, writes, shown_reference, exposure = "", [], reference.color, None
        if scene.hdr:  # the comparator's exposure control needs the linear colours
            exposure = metrics.exposure(reference.color)  # every picture tone-mapped alike
            look, writes = comparator.write_comparator(
                name, reference.color, images, out, hdr=True, exposure=exposure, pool=work.pictures
            )
            shown_reference = plots.tone_mapped(reference.color, exposure)
            images = {k: plots.tone_mapped(v, exposure) for k, v in images.items()}
        gallery, encodes = write_pictures(
            name, shown_reference, images, out, work.pictures, look=not scene.hdr
        )
        work.pictures_written.extend(encodes + writes)
    return gallery + look, exposure


def _html_table(table: pd.DataFrame, number: str = ".4g") -> str:
    """A table of the report: no index, each float as `number` formats it."""
    return table.to_html(index=False, float_format=lambda v: f"{v:{number}}", border=0)


def _equal_renders(count: int) -> str:
    """The methods of the per-object table (blurlab.studies.objects) at `count` renders each."""
    compared = [n for n in methods() if method(n).renders_for is not None]
    at = [
        f"{n} ({', '.join(f'{k} = {v}' for k, v in method(n).renders_for(count).items())})"
        for n in compared
    ]
    return f"{' against '.join(at)}: the same {count} renders"


def _html(info, size, table, sections, curves, per_object=None, peer_rows=None, clock=None) -> str:
    e = html.escape
    when = datetime.datetime.now().strftime("%Y-%m-%d %H:%M")
    parts = [
        "<!doctype html><meta charset='utf-8'><title>blurlab study</title>",
        f"<style>{interactive.PAGE_STYLE}</style>{comparator.assets_html()}",
        "<h1>blurlab study: speed against accuracy</h1>",
        f"<p>{e(when)} · device <b>{e(info['renderer'])}</b> ({e(info['version'])}) · "
        f"{size[0]}×{size[1]} · times by <code>{e(info['timer'])}</code> · "
        f"{len(table)} evaluations · data: <a href='results.csv'>results.csv</a></p>",
        "<p>Each method runs on the G-buffer rendered at the instant it expects; its error is "
        "measured against the converged reference of the same shutter (the mean of N renders). "
        "Time is the sum of the method's passes; methods that render "
        f"({e(', '.join(n for n in methods() if method(n).renders))}) include their renders. "
        f"The {docs_anchor('metrics', 'metrics')}:</p>",
        "<ul>"
        + "".join(
            f"<li><code>{e(n)}</code>: {e(get(n).axis_title)} (docs/spec.md {get(n).spec})</li>"
            for n in _metric_columns(table)
        )
        + "</ul>",
    ]
    for s in sections:
        parts.append(
            f"<h2>{e(s['title'])}</h2><p>reference: N = {s['reference_samples']} sub-frames</p>"
        )
        if s["exposure"] is not None:
            parts.append(
                "<p><b>HDR scene</b>: its lights are far brighter than 1, so it is ranked by "
                f"{e(get(s['rank']).label)} and every image below is tone-mapped alike: "
                "Reinhard's "
                f"x / (1 + x) per channel of x = {s['exposure']:.4g} × the linear colour (the "
                "exposure that brings the reference's log-average luminance to 0.18), then "
                "sRGB. Error maps are of these tone-mapped images; see docs/hdr.md.</p>"
            )
        parts.append(
            "<table><tr><th>budget</th><th>best method within it</th><th>parameters"
            f"</th><th>ms</th><th>{s['rank'].upper()}</th></tr>"
        )
        for budget, name, params, ms, value in s["best"]:
            parts.append(
                f"<tr><td>{budget} ms</td><td>{e(name)}</td><td>{e(params)}</td>"
                f"<td>{ms:.3f}</td><td>{value:.2f}</td></tr>"
            )
        parts.append("</table>")
        parts.append(s["chart"])
        unscored = peers.unscored(peer_rows, s["scene"]) if peer_rows is not None else {}
        if unscored:  # why a peer has no numbers here (its rows' notes)
            items = [f"<li>{e(', '.join(who))}: {e(why)}</li>" for why, who in unscored.items()]
            parts.append("<p>Peers not scored on this scene:</p><ul>" + "".join(items) + "</ul>")
        parts.append(
            f"<p>The same chart as a picture: <a href='{e(s['name'])}_pareto.png'>"
            f"{e(s['name'])}_pareto.png</a></p>"
        )
        if s["pictured"]:
            parts.append(
                "<p>Each image at full size on click, with its error map (the colour bar is "
                "shared by the scene):</p>"
            )
        parts.append(s["gallery"])
        columns = ["method", "params", "total_ms", *_metric_columns(s["rows"])]
        if "exposure" in s["rows"] and s["rows"]["exposure"].notna().any():
            columns.append("exposure")
        shown = s["rows"][columns].sort_values("total_ms")
        parts.append(_html_table(shown))
    if per_object is not None:
        parts.append(
            "<h2>Per object: the OGRE paper's Table 1, with accuracy (textured_spin)</h2>"
            "<p>Each sphere's PSNR inside its box (its pixels, widened by half its motion) "
            f"against the reference; {e(_equal_renders(16))}. Times are the whole "
            "frame's. Data: <a href='per_object.csv'>per_object.csv</a>.</p>"
        )
        parts.append(_html_table(per_object, ".2f"))
    if peer_rows is not None:
        parts.append(
            "<h2>Peers: Blender's EEVEE</h2><p>The same scenes rendered by EEVEE, scored "
            "against the same references. Their time is Blender's wall time for the whole "
            "render (start, scene, shader compilation, rendering) on the device named, not a "
            "GPU pass time: do not read it against the methods' milliseconds. Data: "
            "<a href='peers.csv'>peers.csv</a>.</p>"
        )
        columns = ("scene", "method", *registered(), "time", "note")
        shown = [c for c in columns if c in peer_rows]
        parts.append(_html_table(peer_rows[shown]))
    parts += [f"<h2>{e(title)}</h2><p><img src='{e(image)}'></p>" for title, image in curves]
    parts.append(rankings.report_section(table) or "")  # from RANKING_MIN_SCENES scenes on
    if clock is not None:
        total = clock.total()
        parts.append(
            f"<h2>Where the time went</h2><p>{total:.1f} s of wall clock until this page was "
            "written (<a href='phases.json'>phases.json</a> has the final figures):</p>"
            "<table><tr><th>phase</th><th>s</th><th>share</th><th>what it counts</th></tr>"
        )
        for phase, seconds in clock.seconds.items():
            parts.append(
                f"<tr><td>{phase}</td><td>{seconds:.1f}</td><td>{100 * seconds / total:.0f} %"
                f"</td><td style='text-align:left'>{e(PHASES[phase])}</td></tr>"
            )
        parts.append("</table>")
    where = docs_anchor("study", "blurlab's docs")  # the built site, the pages, or a name
    parts.append(
        f"<p>Made by <code>blurlab study</code>; {where} say what each method and number means.</p>"
    )
    return "\n".join(parts)


__all__ = ["run_study", "write_pictures"]
