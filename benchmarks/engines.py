"""The engines' motion blur side by side (issue 17): every engine method (engine_*),
gather_coverage, reconstruct_guertin2014 and reconstruct_mcguire2012 at their defaults, on
every built-in and failure scene. PSNR, SSIM and FLIP against the converged reference, and ms
per pass (median of --runs timed runs after one warm-up; on llvmpipe glFinish and a wall clock,
on a GPU timer queries). Prints the table, writes it as JSON (--json), as Markdown (--markdown)
and as a Pareto chart of median ms against median PSNR (--chart); the last two by default
beside the JSON. With --peers eevee, Blender's EEVEE post-process blur (1 sample, 1 step,
through blurlab.blender; needs the `blender` extra) joins on every scene Blender can reproduce,
scored against the same reference; its time is Blender's wall time, not a pass time, so it
stays out of the ms columns and the chart.

    python benchmarks/engines.py [--device gpu] [--size 640x360] [--runs 5] [--json PATH]
        [--markdown PATH] [--chart PATH] [--scenes a,b,...] [--methods a,b,...]
        [--peers eevee] [--film-filter 0.5] [--references temporal,antialiased]
        [--reference-samples auto] [--config gather_coverage:samples=16 ...]

--film-filter σ adds gather_coverage with its Gaussian film filter of σ px (docs/spec.md
§17.6) as a row of its own, timed with its fourth pass. With --peers eevee too, EEVEE's row of
each scene holds film_match_flat_db: its image against blurlab's sharp frame under that filter,
PSNR where nothing moves (studies.peers.film_match); the Markdown lists it per scene.

--config METHOD:KEY=VALUE,... (repeatable) adds a row of that method with those parameters,
labelled with them: e.g. --config gather_coverage:samples=16,film_filter=0.5.

--references temporal,antialiased also scores every row against the antialiased reference
(docs/spec.md §11: sub-pixel positions too, the one-pixel box-filtered image that EEVEE's and
Cycles' filtered pixels aim at): columns psnr_aa, ssim_aa and flip_aa beside psnr, ssim and flip,
and a second block in the Markdown. The ms, the chart and the time ratios stay on the temporal
reference, which is always scored. --reference-samples N renders both references with N
samples instead of choosing N from each scene's motion (auto, as sweeps do).

--variants times gather_coverage's pass layouts instead of the table, on each scene: every
tile-pass work-group layout (methods.eevee.TILE_PICK_VARIANTS; a layout applies where the
tile passes run a work group per tile, on a GPU), the dilation by gather or by scatter
(methods.eevee.DILATION_VARIANTS), every gather variant
(methods.coverage.GATHER_VARIANTS) and every film-filter layout
(methods.coverage.FILM_VARIANTS, at σ = --film-filter or 0.5), ms per pass beside
reconstruct_guertin2014's total, and whether each gives the right result: the tiles of one
thread per tile bit for bit, the first gather variant's colour bit for bit, the film filter
within 1e-5 of its twin on the same gather. Each row runs the other passes at their defaults.
Then the fastest right layout of each kind (median over the scenes) together: issue 17's time
goal, gather_coverage's total without and with the film filter over guertin2014's.

    python benchmarks/engines.py --variants --size 1920x1080 --runs 20
        --scenes teapot_pass,fan,skinned_arm,vehicle,near_plane --json PATH
"""

from __future__ import annotations

import argparse
import contextlib
import statistics
import time

import pandas as pd

import blurlab as bl
from blurlab.methods import coverage, eevee, plans
from blurlab.studies import peers
from blurlab.twins import coverage as coverage_twin
from blurlab.twins import eevee as eevee_twin
from blurlab.twins import film as film_twin

from common import (
    add_config_argument,
    back_to_back_ms,
    describe,
    median_passes,
    method_runs,
    open_context,
    save,
)

BASELINES = ("reconstruct_guertin2014", "reconstruct_mcguire2012")
EEVEE = "eevee (Blender)"
# EEVEE's real-time filter alone: one render sample, one motion-blur step.
EEVEE_POST_PROCESS = ((EEVEE, 1, 1),)
COMBINED = ("gather_coverage",)  # the filter built from the engines' best parts (spec §17.6)
# Each reference the rows can be scored against, and its columns' suffix (studies.peers).
REFERENCES = {"temporal": "", "antialiased": peers.ANTIALIASED}


def engine_methods() -> list[str]:
    """The engines' methods from the registry, the filter that combines them, then the filters
    they are measured against."""
    engines = [name for name in bl.methods() if name.startswith("engine_")]
    return engines + list(COMBINED) + list(BASELINES)


def measure(
    ctx,
    scene_name: str,
    size,
    runs: int,
    methods,
    with_eevee: bool,
    references=("temporal",),
    reference_samples: int | str = "auto",
    film_sigma: float = 0.0,
) -> list[dict]:
    """`methods`: (label, method, parameters) of each row (common.method_runs). Every
    method's pass times first, back to back, then every method's errors: the CPU
    metrics (FLIP takes seconds at 1080p) leave the GPU idle, and a GPU that idles clocks
    down, so timing a method right after them measured it about 3x slower on the H100 than a
    busy GPU runs it (docs/benchmarks.md, "engines.py and speed_floor.py"). Scores against
    each of `references` (REFERENCES), both of the temporal one's N; `film_sigma` > 0 gives
    EEVEE's rows film_match_flat_db."""
    scene = bl.scenes.get(scene_name)
    frame = ctx.render(scene, size)
    reference = ctx.reference(scene, size, samples=reference_samples, progress=False)
    rendered = {False: reference}
    if "antialiased" in references:
        rendered[True] = ctx.reference(
            scene, size, samples=reference.samples, antialias=True, progress=False
        )
    outputs, times, passes, queued = {}, {}, {}, {}
    for name, method, params in methods:
        # warm-up: shaders compiled, textures pooled
        outputs[name] = bl.blur(ctx, frame, method, **params)
        times[name] = []
        for _ in range(runs):
            timed = bl.blur(ctx, frame, method, **params)
            times[name].append(timed.total_ms)
            passes[name] = {key: t.ms for key, t in timed.timings.items()}
            del timed
        queued[name] = calls_ms(ctx, frame, method, **params)
    rows = []
    for name, _, _ in methods:
        color = outputs.pop(name).color
        row = {"scene": scene_name, "method": name}
        row.update(scores(rendered[False].color, color))
        row |= {
            "ms": statistics.median(times[name]),
            "back_to_back_ms": queued[name],
            "passes": passes[name],
            "reference_samples": reference.samples,
        }
        if True in rendered:
            row.update(scores(rendered[True].color, color, REFERENCES["antialiased"]))
        rows.append(row)
    if with_eevee:
        wanted = [m + REFERENCES[r] for r in references for m in peers.SCORES]
        rows += peers.peer_rows(
            ctx,
            scene_name,
            scene,
            size,
            rendered.__getitem__,
            tuple(wanted),
            EEVEE_POST_PROCESS,
            film_sigma,
        )
    return rows


def scores(reference, color, suffix: str = "") -> dict:
    """PSNR, SSIM and FLIP of `color` against `reference`, named with `suffix` after each."""
    return {m + suffix: score(reference, color) for m, score in peers.SCORES.items()}


def calls_ms(ctx, frame, method: str, **params) -> float:
    """GPU ms per untimed call of `method` on `frame`, calls issued back to back
    (common.back_to_back_ms): no per-pass timers, no GPU waiting for Python."""
    return back_to_back_ms(ctx, lambda: bl.blur(ctx, frame, method, timed=False, **params))


def tile_grids(result) -> tuple:
    """gather_coverage's (tiles, dilated tiles) from a result's buffers; where the gather
    resolved the scatter dilation's keys itself, the keys decoded as it decodes them."""
    buffers = result.buffers
    if "reach_keys" in buffers:
        return buffers["tiles"], eevee_twin.resolve_reach_keys(
            buffers["reach_keys"], buffers["tiles"]
        )
    return buffers["tiles"], buffers["dilated"]


def coverage_variants(ctx, scene_names, size, runs: int, sigma: float) -> list[dict]:
    """--variants: one row per scene and layout (see the module's doc)."""
    method = bl.method(COMBINED[0])
    rows = []
    for scene_name in scene_names:
        frame = ctx.render(bl.scenes.get(scene_name), size)
        guertin, _ = median_passes(ctx, frame, "reconstruct_guertin2014", runs)
        values = method.defaults(frame)
        s = coverage_twin.tile_size(size[1], values["tile_percent"])
        limit = coverage_twin.max_blur_px(size[1], values["max_blur"])
        with eevee.DILATION_LAYOUT.use("gather"):  # the reference bits: one thread a tile
            _, tiles, dilated, _ = eevee.dilated_tiles(
                ctx,
                frame,
                {},
                method.params,
                values,
                (size[1], size[0]),
                s,
                limit,
                group_per_tile=False,
                length_steps=coverage_twin.TILE_LENGTH_STEPS,
            )
        one_thread = (tiles.download(), dilated.download())
        ctx.recycle(tiles, dilated)
        base = {"scene": scene_name, "guertin_ms": sum(guertin.values())}
        for kind in ("tiles", "dilation"):  # each layout's tiles against one thread's
            for variant in LAYOUTS[kind].variants:
                with LAYOUTS[kind].use(variant):
                    passes, result = median_passes(ctx, frame, method.name, runs)
                same = all(
                    (got == expected).all()
                    for got, expected in zip(tile_grids(result), one_thread, strict=True)
                )
                rows.append(
                    {**base, "layout": f"{kind} {variant}", "passes": passes, "right": same}
                )
        first_gather = None
        for variant in coverage.GATHER_VARIANTS:
            with coverage.GATHER_LAYOUT.use(variant):
                passes, result = median_passes(ctx, frame, method.name, runs)
            first_gather = result.color if first_gather is None else first_gather
            same = bool((result.color == first_gather).all())
            rows.append({**base, "layout": f"gather {variant}", "passes": passes, "right": same})
        filmed = []
        for variant in coverage.FILM_VARIANTS:
            with coverage.FILM_LAYOUT.use(variant):
                passes, result = median_passes(ctx, frame, method.name, runs, film_filter=sigma)
            rows.append({**base, "layout": f"film {variant}", "passes": passes})
            filmed.append((rows[-1], result))
        # The twin after every timing: seconds of NumPy would leave the GPU idle, and an idle
        # GPU clocks down (the docstring of measure).
        for row, result in filmed:
            expected = film_twin.film_filter(result.buffers["unfiltered"], sigma)
            row["right"] = float(abs(result.color - expected).max()) <= 1e-5
        print(f"{scene_name}: done", flush=True)
    print("\n| scene | layout | ms per pass | total ms | / guertin2014 | right |")
    print("|---|---|---|---|---|---|")
    for row in rows:
        row["ms"] = sum(row["passes"].values())
        row["over_guertin"] = row["ms"] / row["guertin_ms"]
        passes = ", ".join(f"{key} {ms:.4f}" for key, ms in row["passes"].items())
        print(
            f"| {row['scene']} | {row['layout']} | {passes} | {row['ms']:.4f} | "
            f"{row['over_guertin']:.2f}x | {row['right']} |"
        )
    return rows


# The passes each kind of layout changes (the film's are every pass named film*).
TILE_PASSES = ("reach_keys_clear", "tile_flatten", "tile_dilate", "tile_resolve")
# The dilation's variants move work between the tile passes and the gather: count both.
LAYOUT_PASSES = {
    "tiles": TILE_PASSES,
    "dilation": (*TILE_PASSES, "gather"),
    "gather": ("gather",),
    "film": (),
}


def layout_summary(rows: list[dict]) -> dict:
    """Per layout, the median over the scenes of the ms of the passes it changes, and whether
    it was right on every scene; per kind, the fastest layout that was right everywhere."""
    summary = {}
    for row in rows:
        kind, _ = row["layout"].split(" ", 1)
        names = LAYOUT_PASSES[kind]
        ms = sum(t for key, t in row["passes"].items() if key in names or key.startswith(kind))
        entry = summary.setdefault(row["layout"], {"kind": kind, "ms": [], "right": True})
        entry["ms"].append(ms)
        entry["right"] &= row["right"]
    print("\n| layout | median ms of its passes | right on every scene |")
    print("|---|---|---|")
    fastest = {}
    for layout, entry in summary.items():
        entry["median_ms"] = statistics.median(entry.pop("ms"))
        print(f"| {layout} | {entry['median_ms']:.4f} | {entry['right']} |")
        best = fastest.get(entry["kind"])
        if entry["right"] and (best is None or entry["median_ms"] < summary[best]["median_ms"]):
            fastest[entry["kind"]] = layout
    print("fastest right layouts: " + ", ".join(fastest.values()))
    return {"layouts": summary, "fastest": fastest}


LAYOUTS = {
    "tiles": eevee.TILE_PICK_LAYOUT,
    "dilation": eevee.DILATION_LAYOUT,
    "gather": coverage.GATHER_LAYOUT,
    "film": coverage.FILM_LAYOUT,
}


def time_goal(ctx, scene_names, size, runs: int, sigma: float, fastest: dict) -> dict:
    """Issue 17's time goal with the `fastest` layouts together: per scene gather_coverage's
    total ms without and with the film filter over guertin2014's, timed back to back; the
    median of the per-scene ratios and the ratio of the medians."""
    rows = []
    for scene_name in scene_names:
        frame = ctx.render(bl.scenes.get(scene_name), size)
        with contextlib.ExitStack() as stack:
            for kind, layout in fastest.items():
                stack.enter_context(LAYOUTS[kind].use(layout.split(" ", 1)[1]))
            plain, _ = median_passes(ctx, frame, COMBINED[0], runs)
            filmed, _ = median_passes(ctx, frame, COMBINED[0], runs, film_filter=sigma)
            row = {
                "scene": scene_name,
                "b2b_ms": calls_ms(ctx, frame, COMBINED[0]),
                "b2b_film_ms": calls_ms(ctx, frame, COMBINED[0], film_filter=sigma),
            }
        # A layout's use() block turns dispatch plans off: guertin2014 runs without them too,
        # so that calls back to back compare like with like (the table's ratios, with plans on
        # both sides, run a little lower).
        with plans.disabled():
            guertin, _ = median_passes(ctx, frame, "reconstruct_guertin2014", runs)
            row["b2b_guertin_ms"] = calls_ms(ctx, frame, "reconstruct_guertin2014")
        row["guertin_ms"] = sum(guertin.values())
        row["ms"], row["film_ms"] = sum(plain.values()), sum(filmed.values())
        rows.append(row)
    goal = {"layouts": fastest, "rows": rows}
    print(f"\ntime goal with {', '.join(fastest.values())} (film_filter = {sigma:g}):")
    keys = {"ms": "guertin_ms", "film_ms": "guertin_ms"}
    keys |= {"b2b_ms": "b2b_guertin_ms", "b2b_film_ms": "b2b_guertin_ms"}
    for key, baseline in keys.items():
        goal[key] = ratio_summary([row[key] for row in rows], [row[baseline] for row in rows])
        label = ("with film" if "film" in key else "without film") + (
            ", calls back to back" if key.startswith("b2b") else ", per-pass timers"
        )
        print(
            f"  {label}: median per-scene ratio {goal[key]['median_of_ratios']:.2f}x, "
            f"ratio of medians {goal[key]['ratio_of_medians']:.2f}x, "
            f"{goal[key]['scenes_within_1_5']} of {len(rows)} scenes within 1.5x"
        )
    return goal


def time_ratios(table: pd.DataFrame, baseline: str = BASELINES[0]) -> dict:
    """Each method's time over `baseline`'s (issue 17: gather_coverage ≤ 1.5x guertin2014's):
    the median of the per-scene ratios and the ratio of the medians, by the per-pass timers
    (ms) and by calls back to back (back_to_back_ms)."""
    timed = table[table.method != EEVEE]
    ratios = {}
    for clock in ("ms", "back_to_back_ms"):
        by = timed.pivot(index="scene", columns="method", values=clock)
        if baseline not in by:
            return {}
        for method in by.columns:
            ratios.setdefault(method, {})[clock] = ratio_summary(
                by[method].tolist(), by[baseline].tolist()
            )
    return ratios


def ratio_summary(times: list[float], baselines: list[float]) -> dict:
    """Issue 17's time goal over scenes: the median of the per-scene ratios times / baselines,
    the ratio of their medians, and on how many scenes the ratio is at most 1.5."""
    ratios = [t / b for t, b in zip(times, baselines, strict=True)]
    return {
        "median_of_ratios": float(statistics.median(ratios)),
        "ratio_of_medians": float(statistics.median(times) / statistics.median(baselines)),
        "scenes_within_1_5": int(sum(r <= 1.5 for r in ratios)),
    }


def markdown(table: pd.DataFrame, references=("temporal",), film_sigma: float = 0.0) -> str:
    """Per reference (REFERENCES; the temporal one alone: no heading) one row per scene of
    PSNR / SSIM / FLIP per method, then the median PSNR per method, after the first block's
    also the median ms; with EEVEE, the medians over the scenes it renders and how many of them
    each method wins. Then, where EEVEE's rows hold film_match_flat_db, that figure per scene
    (film filter of `film_sigma` px)."""
    methods = list(dict.fromkeys(table["method"]))
    blocks = []
    for reference in references:
        lines = [] if len(references) == 1 else [f"Against the {reference} reference:", ""]
        lines += score_block(table, methods, REFERENCES[reference], timed=not blocks)
        blocks.append("\n".join(lines) + "\n")
    if "film_match_flat_db" in table:
        blocks.append(film_match_line(table, film_sigma) + "\n")
    return "\n".join(blocks)


def film_match_line(table: pd.DataFrame, film_sigma: float) -> str:
    """EEVEE's film_match_flat_db per scene it renders, in one sentence."""
    eevee = table[(table.method == EEVEE) & table.psnr.notna()].set_index("scene")
    cells = [
        f"{scene} {db:.2f}" if pd.notna(db) else f"{scene} –"
        for scene, db in eevee.film_match_flat_db.items()
    ]
    return (
        f"EEVEE's image against blurlab's sharp frame under a film filter of σ = {film_sigma:g} "
        "px, PSNR (dB) where nothing moves and no edge is near (–: no such pixel): "
        + ", ".join(cells)
    )


def score_block(table: pd.DataFrame, methods: list[str], suffix: str, timed: bool) -> list[str]:
    """markdown's table of the scores named with `suffix` (REFERENCES), its ms lines if
    `timed`."""
    psnr, ssim, flip = (m + suffix for m in peers.SCORES)
    lines = [
        "| scene | " + " | ".join(methods) + " |",
        "|---|" + "---|" * len(methods),
    ]
    for scene, rows in table.groupby("scene", sort=False):
        by = rows.set_index("method")
        cells = [
            f"{by[psnr][m]:.2f} / {by[ssim][m]:.3f} / {by[flip][m]:.3f}"
            if m in by.index and pd.notna(by[psnr][m])
            else "–"
            for m in methods
        ]
        lines.append(f"| {scene} | " + " | ".join(cells) + " |")

    def line(label, values, fmt):
        cells = [f"**{fmt(values[m])}**" if pd.notna(values.get(m)) else "–" for m in methods]
        return f"| **{label}** | " + " | ".join(cells) + " |"

    columns = [psnr, "ms", "back_to_back_ms"] if timed else [psnr]
    medians = table.groupby("method", sort=False)[columns].median()
    lines.append(line("median PSNR", medians[psnr], "{:.2f}".format))
    if timed:
        lines.append(line("median ms", medians.ms, "{:.3f}".format))
        lines.append(
            line("median ms, calls back to back", medians.back_to_back_ms, "{:.3f}".format)
        )
    eevee = table[(table.method == EEVEE) & table[psnr].notna()].set_index("scene")[psnr]
    if len(eevee):
        shared = table[table.scene.isin(eevee.index)]
        lines.append(
            line(
                f"median PSNR, the {len(eevee)} scenes EEVEE renders",
                shared.groupby("method")[psnr].median(),
                "{:.2f}".format,
            )
        )
        wins = {
            m: int((rows.set_index("scene")[psnr] > eevee).reindex(eevee.index).sum())
            for m, rows in shared.groupby("method")
            if m != EEVEE
        }
        lines.append(line("scenes better than EEVEE", wins, f"{{}} of {len(eevee)}".format))
    return lines


def pareto_chart(table: pd.DataFrame, renderer: str, clock: str, size):
    """Median ms against median PSNR over the scenes, one point per method, front marked."""
    timed = table[table.method != EEVEE]  # Blender's wall time is not a pass time
    medians = timed.groupby("method", sort=False)[["psnr", "ms"]].median().reset_index()
    medians = medians.rename(columns={"ms": "total_ms"})
    medians = medians.assign(
        scene="median over scenes", renderer=renderer, clock=clock, width=size[0], height=size[1]
    )
    # Issue 17's time goal, drawn where guertin2014 ran: 1.5 times its median.
    guertin = medians.loc[medians.method == "reconstruct_guertin2014", "total_ms"]
    budget = 1.5 * float(guertin.iloc[0]) if len(guertin) else None
    label = f"1.5 × guertin2014 ({budget:.3g} ms)" if budget else None
    return bl.plots.pareto(medians, "median over scenes", budget_ms=budget, budget_label=label)


def reference_list(text: str) -> tuple[str, ...]:
    """--references: names of REFERENCES, comma-separated, the temporal one among them."""
    names = tuple(dict.fromkeys(text.split(",")))
    unknown = [n for n in names if n not in REFERENCES]
    if unknown or "temporal" not in names:
        raise argparse.ArgumentTypeError(
            f"{text!r}: give names from {', '.join(REFERENCES)}, comma-separated, temporal among "
            "them (the ms, the chart and the time ratios are scored against it)"
            + (f"; unknown: {', '.join(unknown)}" if unknown else "")
        )
    return names


def reference_samples(text: str) -> int | str:
    """--reference-samples: auto or a whole number of samples, at least 1."""
    if text == "auto":
        return text
    if not text.isdigit() or int(text) < 1:
        raise argparse.ArgumentTypeError(f"{text!r}: give auto or a whole number >= 1")
    return int(text)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--device", default="auto")
    parser.add_argument("--size", default="640x360")
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--scenes", default=None, help="comma-separated; default: all")
    parser.add_argument("--methods", default=None, help="comma-separated; default: all")
    parser.add_argument("--peers", choices=peers.PEERS, default=None, help="Blender's EEVEE too")
    parser.add_argument("--film-filter", type=float, default=0.0, help="σ, px; 0: no extra row")
    parser.add_argument(
        "--references",
        type=reference_list,
        default=("temporal",),
        help=f"comma-separated, from {', '.join(REFERENCES)}; temporal is always scored",
    )
    parser.add_argument(
        "--reference-samples",
        type=reference_samples,
        default="auto",
        help="N of both references; auto (default): from each scene's motion, as sweeps do",
    )
    add_config_argument(parser)
    parser.add_argument("--variants", action="store_true", help="gather_coverage's layouts only")
    parser.add_argument(
        "--layout",
        action="append",
        default=[],
        metavar="KIND=VARIANT",
        help=f"run the table with a pass layout other than the default; KIND: {', '.join(LAYOUTS)}",
    )
    parser.add_argument("--json", default=None)
    parser.add_argument("--markdown", default=None)
    parser.add_argument("--chart", default=None, help="PNG or SVG: median ms against PSNR")
    args = parser.parse_args()
    ctx = open_context(args.device)
    size = tuple(int(v) for v in args.size.split("x"))
    scenes = (
        args.scenes.split(",") if args.scenes else bl.scenes.names() + bl.scenes.names("failure")
    )
    if args.variants:
        record = {**describe(ctx), "size": args.size, "runs": args.runs}
        sigma = args.film_filter or 0.5
        record["film_filter"] = sigma
        # Where this is false (llvmpipe) the tile passes run one thread per tile and the
        # tile layouts do not apply: their rows then time the same passes.
        record["tile_groups"] = eevee.tile_groups(ctx)
        print(f"tile passes with a work group per tile: {record['tile_groups']}")
        record["rows"] = coverage_variants(ctx, scenes, size, args.runs, sigma)
        record["summary"] = layout_summary(record["rows"])
        fastest = record["summary"]["fastest"]
        record["goal"] = time_goal(ctx, scenes, size, args.runs, sigma, fastest)
        save(args.json, record)
        return
    for item in args.layout:  # as defaults, so that calls back to back still replay plans
        kind, _, variant = item.partition("=")
        if kind not in LAYOUTS:
            parser.error(f"--layout {item}: KIND is one of {', '.join(LAYOUTS)}")
        LAYOUTS[kind].make_default(variant)
    names = args.methods.split(",") if args.methods else engine_methods()
    methods = method_runs(names, args.film_filter, args.config)
    if args.peers:
        peers.check_peers([args.peers])
    record = {**describe(ctx), "size": args.size, "runs": args.runs, "methods": names}
    record["film_filter"] = args.film_filter
    if args.layout:
        record["layouts"] = list(args.layout)
    # Keys only where asked for: a record of the defaults reads as it always did.
    if args.references != ("temporal",):
        record["references"] = list(args.references)
    if args.reference_samples != "auto":
        record["reference_samples"] = args.reference_samples
    start = time.perf_counter()
    rows = []
    for scene_name in scenes:
        rows += measure(
            ctx,
            scene_name,
            size,
            args.runs,
            methods,
            bool(args.peers),
            args.references,
            args.reference_samples,
            args.film_filter,
        )
        print(f"{scene_name}: done", flush=True)
    record["seconds"] = round(time.perf_counter() - start, 1)
    table = pd.DataFrame(rows)
    print(f"\n{record['date']}  {record['renderer']}  {args.size}")
    shown = [m + REFERENCES[r] for r in args.references for m in peers.SCORES]
    for metric in [*shown, "ms"]:
        print(f"\n{metric}")
        print(table.pivot(index="scene", columns="method", values=metric).round(3).to_string())
    if "film_match_flat_db" in table:
        print("\n" + film_match_line(table, args.film_filter))
    if args.json:  # benchmarks/gpu.sh passes --json only: the table and chart go beside it
        args.markdown = args.markdown or args.json.removesuffix(".json") + ".md"
        args.chart = args.chart or args.json.removesuffix(".json") + "_pareto.png"
    if args.markdown:
        with open(args.markdown, "w") as f:
            f.write(markdown(table, args.references, args.film_filter))
    if args.chart:
        clock = bl.blur(ctx, ctx.render(bl.scenes.get(scenes[0]), (8, 8)), names[0]).clock
        bl.plots.save(pareto_chart(table, record["renderer"], clock, size), args.chart)
    record["over_guertin"] = time_ratios(table)
    print(f"\ntime over {BASELINES[0]} (median per-scene ratio; ratio of medians):")
    for method, clocks in record["over_guertin"].items():
        cells = [
            f"{c}: {r['median_of_ratios']:.2f}x; {r['ratio_of_medians']:.2f}x"
            for c, r in clocks.items()
        ]
        print(f"  {method}: " + " | ".join(cells))
    record["rows"] = rows
    save(args.json, record)


if __name__ == "__main__":
    main()
