"""The metric registry (blurlab.metrics.registry): one declaration per metric, read by sweeps,
charts, the report, recommend and docs/metrics.md. A metric registered here, in the test, flows
into a sweep table and its charts without any other module knowing its name."""

from __future__ import annotations

import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from method_picks import pick

import blurlab as bl
from blurlab.metrics import Metric
from blurlab.studies import interactive, plots

ROOT = Path(__file__).resolve().parents[1]
SIZE = (48, 32)
# A plain gather with a tap count, for the blurs and sweeps below.
GATHER = pick(kind="gather", params=("taps",))
DIRECTED = [n for n in bl.metrics.registered() if bl.metrics.get(n).higher_is_better is not None]


def mean_error_map(reference, test) -> float:
    """The toy metric: the mean of the error map (docs/spec.md §6)."""
    return float(bl.metrics.error_map(reference, test).mean())


def toy(**changes) -> Metric:
    fields = dict(
        name="mean_error",
        label="mean |error|",
        numpy=mean_error_map,
        higher_is_better=False,
        range=(0.0, 1.0),
        default=True,
        doc="Mean over pixels of the error map: the mean absolute RGB difference.",
        spec="§6",
    )
    return Metric(**{**fields, **changes})


@pytest.fixture
def toy_metric():
    metric = bl.metrics.register(toy())
    yield metric
    bl.metrics.unregister(metric.name)


@pytest.fixture(scope="module")
def pair(ctx):
    """A reference and a blurred frame of fan, as arrays."""
    scene = bl.scenes.fan()
    reference = ctx.reference(scene, SIZE, samples=16, progress=False).color
    frame = ctx.render(scene, SIZE, instant=bl.method_instant(GATHER, {}))
    blurred = bl.blur(ctx, frame, GATHER, taps=4).color
    return reference, blurred


def test_the_metric_docs_are_generated_from_the_registry():
    text = (ROOT / "docs" / "metrics.md").read_text()
    assert text == bl.metrics.reference_page(), (
        "docs/metrics.md is out of date: regenerate it with `blurlab metrics > docs/metrics.md`"
    )


def test_the_metrics_command_prints_the_reference_page():
    printed = subprocess.run(
        [sys.executable, "-m", "blurlab", "metrics"], capture_output=True, text=True, check=True
    ).stdout
    assert printed == bl.metrics.reference_page()
    for name in bl.metrics.registered():
        assert f"## {name}: " in printed and bl.metrics.get(name).spec in printed


def test_registering_twice_or_asking_for_an_unknown_name_is_an_error(toy_metric):
    with pytest.raises(ValueError, match="'mean_error' is registered already"):
        bl.metrics.register(toy())
    with pytest.raises(ValueError, match=r"no metric 'nope'; registered metrics: \['psnr'"):
        bl.metrics.get("nope")
    with pytest.raises(ValueError, match="no metric 'nope'"):
        bl.metrics.unregister("nope")
    with pytest.raises(TypeError, match="takes a Metric"):
        bl.metrics.register("psnr")


@pytest.mark.parametrize(
    "changes, match",
    [
        ({"name": "mean error"}, "identifier"),
        ({"spec": "6.1"}, "docs/spec.md section"),
        ({"higher_is_better": None}, "give `best` exactly when"),
        ({"best": 0.0}, "give `best` exactly when"),
        ({"range": (1.0, 0.0)}, "low < high"),
        ({"reference": "cycles"}, "reference must be one of"),
        ({"reduction": "mae"}, "reduction must be None or one of"),
        ({"numpy": None}, "must be callable"),
    ],
)
def test_a_bad_declaration_says_what_is_wrong(changes, match):
    with pytest.raises((ValueError, TypeError), match=match):
        toy(**changes)


def test_sweeps_refuse_unknown_metrics_and_list_the_registered_ones(ctx):
    with pytest.raises(ValueError, match=r"unknown metrics \['mae'\]; choose from \['psnr', "):
        bl.sweep(ctx, ["fan"], [GATHER], SIZE, metrics=("psnr", "mae"), progress=False)
    with pytest.raises(TypeError, match="list of names"):
        bl.sweep(ctx, ["fan"], [GATHER], SIZE, metrics="psnr", progress=False)


@pytest.mark.parametrize("name", bl.metrics.registered())
def test_identical_images_score_the_best_value_and_others_stay_in_range(name, pair):
    metric = bl.metrics.get(name)
    reference, blurred = pair
    if metric.sequence:  # two frames: the reference changes, the test holds still
        reference, blurred = np.stack([reference, blurred]), np.stack([reference, reference])
    if metric.higher_is_better is None:
        best = metric.best
    else:
        best = metric.range[1] if metric.higher_is_better else metric.range[0]
    assert metric.numpy(reference, reference) == pytest.approx(best, abs=1e-9)
    value = metric.numpy(reference, blurred)
    assert metric.range[0] <= value <= metric.range[1] and math.isfinite(value)
    assert metric.goodness(value) < metric.goodness(best)


@pytest.mark.parametrize("name", [n for n in bl.metrics.registered() if bl.metrics.get(n).gpu])
def test_each_gpu_implementation_matches_its_numpy_one(ctx, name, pair):
    metric = bl.metrics.get(name)
    reference, blurred = pair
    on_gpu = metric.gpu(ctx, ctx.upload(reference), ctx.upload(blurred))
    assert on_gpu == pytest.approx(metric.numpy(reference, blurred), abs=metric.tolerance)


def test_pareto_fronts_follow_each_metrics_direction():
    rows = pd.DataFrame(
        {
            "total_ms": [1.0, 2.0, 3.0, 4.0],
            "psnr": [20.0, 30.0, 25.0, 40.0],
            "flip": [0.5, 0.2, 0.3, 0.1],
            "energy_ratio": [0.5, 0.9, 1.05, 1.5],
        }
    )
    assert list(plots.pareto_front(rows, "psnr")["total_ms"]) == [1.0, 2.0, 4.0]
    assert list(plots.pareto_front(rows, "flip")["total_ms"]) == [1.0, 2.0, 4.0]
    # Best at 1: 0.9 is closer than 0.5, 1.05 closer still, 1.5 farther.
    assert list(plots.pareto_front(rows, "energy_ratio")["total_ms"]) == [1.0, 2.0, 3.0]
    # Charted: every metric with a direction, HDR ones first; energy_ratio is tabled only.
    assert plots.charted_metrics(rows) == ["psnr", "flip"]


def test_a_registered_metric_flows_into_a_sweep_table_and_the_charts(ctx, toy_metric, pair):
    # Registered here and nowhere else: default=True puts it in every sweep without metrics=.
    table = bl.sweep(
        ctx,
        ["fan"],
        {GATHER: {"taps": [2, 4]}},
        SIZE,
        reference_samples=16,
        repeats=1,
        progress=False,
    )
    assert list(table.columns[table.columns.get_loc("psnr") :][:5]) == [
        *bl.metrics.default_names(False)[:4],
        "mean_error",
    ]
    reference, blurred = pair  # taps=4 on the same frame and reference
    row = table[table["param_taps"] == 4].iloc[0]
    assert row["mean_error"] == pytest.approx(mean_error_map(reference, blurred), abs=1e-7)
    assert table["mean_error"].nunique() == 2
    # The interactive chart offers it, titled from its declaration.
    figure = interactive.pareto_chart(table)
    buttons = {b.label: b.args[1]["yaxis.title.text"] for b in figure.layout.updatemenus[0].buttons}
    assert buttons["MEAN_ERROR"] == "mean |error|, lower is better"
    assert buttons["PSNR"] == "PSNR (dB), higher is better"
    # The static chart too, and its front keeps the lower errors.
    figure = plots.pareto(table, "fan", "mean_error")
    assert figure.axes[0].get_ylabel() == "mean |error|, lower is better"
    front = plots.pareto_front(table, "mean_error")
    assert front["mean_error"].iloc[-1] == table["mean_error"].min()
    assert "## mean_error: mean |error|" in bl.metrics.reference_page()


def test_gpu_reductions_are_issued_once_per_pass(ctx, pair):
    # psnr and ssim share one fused pass against the prepared reference; psnr_aa needs the
    # squared error against the other reference; flip its own pass.
    calls = []

    class Recording:
        def mse(self, test, reference):
            calls.append(("mse", reference))
            return 0.25

        def mse_ssim(self, prepared, test):
            calls.append(("mse_ssim", prepared))
            return (0.01, 0.5)

        def flip(self, reference, test):
            calls.append(("flip", reference))
            return 0.125

    chosen = [bl.metrics.get(n) for n in ("psnr", "ssim", "flip", "psnr_aa")]
    textures = {"temporal": "T", "antialiased": "A"}
    issued = bl.metrics.issue_reductions(
        Recording(), chosen, textures, lambda kind: "prepared " + kind, "test"
    )
    assert calls == [("mse_ssim", "prepared temporal"), ("flip", "T"), ("mse", "A")]
    values = bl.metrics.reduced_values(chosen, issued)
    assert values == {
        "psnr": pytest.approx(20.0),
        "ssim": 0.5,
        "flip": 0.125,
        "psnr_aa": pytest.approx(10 * np.log10(4.0)),
    }
