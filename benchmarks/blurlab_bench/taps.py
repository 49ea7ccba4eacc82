"""What "just enough taps" gives gather_coverage (docs/spec.md §17.6.1): each lever alone and all
together, without and with the film filter, on the built-in and failure scenes: PSNR against
the antialiased reference, time relative to reconstruct_guertin2014 on the same frame, and the
distribution of taps per pixel."""

from __future__ import annotations

import statistics

import numpy as np

from blurlab import metrics
from blurlab.methods import blur, coverage
from blurlab.methods.params import Param
from blurlab.scene import scenes
from blurlab.sizes import DEFAULT_SIZE

from .core import Benchmark, register
from .timing import film_method, median_passes, split, untimed_calls_ms

# The time every row is measured against: Guertin 2014's filter.
BASELINE = "reconstruct_guertin2014"
TODAY = "today"  # the label of the defaults' row
LEVERS = ("tap_spacing", "early_exit", "uniform_tolerance", "half_res_above")


def lever_configs(p) -> list[tuple[str, dict]]:
    """(label, gather_coverage parameters): the defaults, each lever alone at the benchmark's
    value, then all together; each once more with the film filter where film_filter > 0."""
    levers = {key: {key: p[key]} for key in LEVERS}
    together = {key: value for lever in levers.values() for key, value in lever.items()}
    plain = [(TODAY, {}), *levers.items(), ("all", together)]
    if p["film_filter"] <= 0:
        return plain
    film = {"film_filter": p["film_filter"]}
    return plain + [(f"{label}, film", {**params, **film}) for label, params in plain]


def tap_counts(taps: np.ndarray) -> dict:
    """The distribution of taps per pixel: mean, p50, p90, max and the share with none."""
    return {
        "mean": float(taps.mean()),
        "p50": float(np.percentile(taps, 50)),
        "p90": float(np.percentile(taps, 90)),
        "max": float(taps.max()),
        "none": float((taps == 0).mean()),
    }


def _scene_rows(ctx, name, size, p, configs) -> list[dict]:
    """Every configuration's pass times first, back to back, then its error and taps: CPU work
    leaves the GPU idle, and an idle GPU clocks down."""
    scene = scenes.get(name)
    frame = ctx.render(scene, size)
    samples = p["reference_samples"] or "auto"
    reference = ctx.reference(scene, size, samples=samples, antialias=True, progress=False)
    runs = [(BASELINE, BASELINE, {})]
    runs += [(label, film_method(), params) for label, params in configs]
    timed = {}
    for label, method_name, params in runs:
        passes, _ = median_passes(ctx, frame, method_name, p["runs"], **params)
        queued = untimed_calls_ms(ctx, frame, method_name, **params) if p["back_to_back"] else None
        timed[label] = (passes["total"], queued)
    base_ms, base_queued = timed[BASELINE]
    rows = []
    tiles = None  # the tile lines, the same in every configuration
    counted = {}  # the taps of each setting of the levers, the same with and without the film
    for label, method_name, params in runs:
        result = blur(ctx, frame, method_name, **params)
        ms, queued = timed[label]
        row = {
            "scene": name,
            "config": label,
            "psnr_aa": metrics.psnr(reference.color, result.color),
            "ms": ms,
            "ratio": ms / base_ms,
            "b2b_ratio": None if queued is None else queued / base_queued,
        }
        if method_name == film_method():
            if tiles is None:
                tiles = coverage.tile_lines(frame, result, **params)
            levers = tuple((key, params.get(key)) for key in LEVERS)
            if levers not in counted:
                plan = coverage.tap_plan(frame, tiles=tiles, **params)
                counted[levers] = {
                    f"taps_{k}": v for k, v in tap_counts(plan.taps_per_pixel()).items()
                }
                counted[levers] |= {
                    "fast": float(plan.fast.mean()),
                    "half": float(plan.half.mean()),
                }
            row |= counted[levers]
        rows.append(row)
        del result  # back to the pool
    return rows


def _coverage_taps(ctx, size, p, out) -> None:
    configs = lever_configs(p)
    rows = []
    for name in split(p["scenes"]) or scenes.names() + scenes.names("failure"):
        rows += _scene_rows(ctx, name, size, p, configs)
    for label in [BASELINE] + [label for label, _ in configs]:
        mine = [r for r in rows if r["config"] == label]
        out.figure(f"{label}: median PSNR", statistics.median(r["psnr_aa"] for r in mine), "dB")
        if label == BASELINE:
            continue
        # against the defaults with the same film filter
        today = TODAY + label.partition(",")[1] + label.partition(",")[2]
        was = {r["scene"]: r["psnr_aa"] for r in rows if r["config"] == today}
        lost = statistics.median(was[r["scene"]] - r["psnr_aa"] for r in mine)
        out.figure(f"{label}: median dB below {today}", lost, "dB")
        out.figure(f"{label}: median time / {BASELINE}", _median(mine, "ratio"), "x")
        if p["back_to_back"]:
            ratio = _median(mine, "b2b_ratio")
            out.figure(f"{label}: median time / {BASELINE}, calls back to back", ratio, "x")
        out.figure(f"{label}: mean taps per pixel", _mean(mine, "taps_mean"), "taps")
        out.figure(f"{label}: pixels with no tap", _mean(mine, "taps_none"), "share")
        out.figure(f"{label}: pixels on the uniform path", _mean(mine, "fast"), "share")
        out.figure(f"{label}: pixels on the half-resolution path", _mean(mine, "half"), "share")
    keys = ["scene", "config", "psnr_aa", "ms", "ratio", "b2b_ratio"]
    keys += ["taps_mean", "taps_p50", "taps_p90", "taps_max", "taps_none", "fast", "half"]
    out.table(
        "gather_coverage's levers ("
        + ", ".join(f"{key}={p[key]:g}" for key in LEVERS)
        + f") against {BASELINE}; PSNR against the antialiased reference; taps per pixel over "
        "both half-shutters",
        [
            ("scene", ""),
            ("config", ""),
            ("PSNR", "dB"),
            ("per-pass timers", "ms"),
            (f"/ {BASELINE}", "x"),
            (f"/ {BASELINE}, back to back", "x"),
            ("taps mean", "taps"),
            ("taps p50", "taps"),
            ("taps p90", "taps"),
            ("taps max", "taps"),
            ("no tap", "share"),
            ("uniform path", "share"),
            ("half resolution", "share"),
        ],
        [[r.get(k) for k in keys] for r in rows],
    )


def _median(rows, key) -> float:
    return statistics.median(r[key] for r in rows)


def _mean(rows, key) -> float:
    return statistics.mean(r[key] for r in rows)


register(
    Benchmark(
        "coverage_taps",
        "Just-enough-taps levers of gather_coverage (per-tile sample counts, early exit, "
        "uniform-motion path, half resolution for long blurs) alone and together, with and "
        "without the film filter, on every built-in and failure scene: PSNR against the "
        "antialiased reference, time against "
        "reconstruct_guertin2014, taps per pixel",
        {
            "runs": Param(5, int, "timed runs per configuration (medians)", 1, 1000),
            "scenes": Param("", str, "comma-separated scenes (empty: built-in + failure)"),
            "reference_samples": Param(0, int, "N of the reference (0: from the motion)", 0),
            "back_to_back": Param(True, bool, "time calls back to back too (slow on llvmpipe)"),
            "film_filter": Param(0.5, float, "σ px of the film-filter rows (0: none)", 0, 4),
            "tap_spacing": Param(
                1.0, float, "tap_spacing of the lever's rows", 0, 1000, low_open=True
            ),
            "early_exit": Param(1.0, float, "early_exit of the lever's rows", 0, 1000),
            "uniform_tolerance": Param(
                0.5, float, "uniform_tolerance of the lever's rows", 0, 1000, low_open=True
            ),
            "half_res_above": Param(
                16.0, float, "half_res_above of the lever's rows", 0, 1000, low_open=True
            ),
        },
        _coverage_taps,
        {"tiny": (64, 36), "software": DEFAULT_SIZE, "gpu": (1920, 1080)},
        {
            "tiny": {"runs": 1, "scenes": "teapot_pass", "reference_samples": 8},
            "software": {"runs": 3, "back_to_back": False},
            "gpu": {"runs": 10},
        },
    )
)
