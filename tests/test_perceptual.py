"""ColorVideoVDP and FovVideoVDP as optional metrics of sequences (blurlab.metrics.perceptual,
docs/spec.md §21.3) and the agreement of blurlab's metrics with them
(blurlab.studies.perceptual_agreement). The tests that run a model skip where it is not
installed (the extra blurlab[perceptual])."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
from method_picks import EXAMPLE, pick

import blurlab as bl
from blurlab.metrics import perceptual
from blurlab.studies import perceptual_agreement as agreement
from blurlab_bench import core

# Two methods to score: the example filter and a plain gather.
METHODS = [EXAMPLE, pick(kind="gather", params=("taps",))]
MODELS = list(perceptual.MODELS)  # colorvideovdp, fovvideovdp
FUNCTIONS = {"colorvideovdp": perceptual.colorvideovdp, "fovvideovdp": perceptual.fovvideovdp}


def installed(name):
    """`name` as a parameter that skips where its model is not installed."""
    reason = f"needs blurlab[perceptual] ({', '.join(perceptual.model(name).modules)})"
    return pytest.param(
        name, marks=pytest.mark.skipif(not perceptual.available(name), reason=reason)
    )


@pytest.mark.parametrize("name", MODELS)
def test_the_metric_is_registered_exactly_where_it_is_installed(name):
    if perceptual.available(name):
        metric = bl.metrics.get(name)
        assert metric.sequence and metric.higher_is_better and metric.unit == "JOD"
        assert metric.spec == "§21.3" and metric.label == perceptual.model(name).label
        return
    assert name not in bl.metrics.registered()
    with pytest.raises(ValueError, match=r"not installed here.*blurlab\[perceptual\]"):
        bl.metrics.get(name)
    with pytest.raises(ValueError, match=r"unknown metrics \['nope'\].*not installed"):
        bl.metrics.check_names(["nope", name], "bl.sweep", sequences=True)
    label = perceptual.model(name).label
    with pytest.raises(ImportError, match=rf"{name} needs {label}: .*blurlab\[perceptual\]"):
        FUNCTIONS[name](np.zeros((2, 8, 8, 3)), np.zeros((2, 8, 8, 3)))
    with pytest.raises(
        ImportError, match=rf"with {label} \({name}\) needs .*blurlab\[perceptual\]"
    ):
        agreement.scores(None, ["fan"], (32, 18), METHODS, model=name)


def test_a_model_is_one_of_the_declared():
    with pytest.raises(ValueError, match=r"model must be one of 'colorvideovdp', 'fovvideovdp'"):
        agreement.require("vmaf")
    with pytest.raises(ValueError, match=r"no model 'vmaf'"):
        perceptual.judge("vmaf", np.zeros((2, 8, 8, 3)), np.zeros((2, 8, 8, 3)))


@pytest.mark.parametrize("name", [installed(n) for n in MODELS])
def test_a_model_gives_10_for_the_reference_and_less_with_noise(name):
    judged = FUNCTIONS[name]
    rng = np.random.default_rng(1)
    reference = rng.random((4, 24, 32, 4)).astype(np.float32)
    assert judged(reference, reference) == pytest.approx(10.0, abs=1e-3)
    slight = reference + rng.normal(0, 0.02, reference.shape).astype(np.float32)
    strong = reference + rng.normal(0, 0.2, reference.shape).astype(np.float32)
    mild, bad = judged(reference, slight), judged(reference, strong)
    assert 10.0 > mild > bad
    assert bl.metrics.get(name).numpy(reference, strong) == bad
    with pytest.raises(ValueError, match="differ in shape"):
        judged(reference, reference[:, :8])
    with pytest.raises(ValueError, match="fps must be"):
        judged(reference, reference, fps=0.0)


def test_kendall_tau_per_sequence_and_its_summary():
    # On "a" PSNR orders the three methods as FovVideoVDP does, FLIP reverses them, and
    # instability swaps two; on "b" every metric agrees with it.
    table = pd.DataFrame(
        [
            ("a", "m1", 30.0, 0.10, 0.010, 9.0),
            ("a", "m2", 25.0, 0.20, 0.030, 8.0),
            ("a", "m3", 20.0, 0.05, 0.020, 7.0),
            ("b", "m1", 20.0, 0.30, 0.030, 6.0),
            ("b", "m2", 25.0, 0.20, 0.020, 7.0),
            ("b", "m3", 30.0, 0.10, 0.010, 8.0),
        ],
        columns=["scene", "method", "psnr", "flip", "temporal_instability", "fovvideovdp"],
    )
    taus = agreement.taus(table, model="fovvideovdp")
    assert taus.loc["a", "psnr"] == pytest.approx(1.0)
    assert taus.loc["a", "flip"] == pytest.approx(-1 / 3)  # m3 first, then m1, m2
    assert taus.loc["a", "temporal_instability"] == pytest.approx(1 / 3)
    assert np.allclose(taus.loc["b"], 1.0)
    summary = agreement.agreement(table, model="fovvideovdp").set_index("metric")
    assert summary.loc["psnr", "tau_mean"] == pytest.approx(1.0)
    assert summary.loc["flip", "tau_mean"] == pytest.approx(1 / 3)
    low, high = summary.loc["flip", ["tau_low", "tau_high"]]
    assert low == pytest.approx(-1 / 3) and high == pytest.approx(1.0)  # two sequences
    assert summary.loc["flip", "same_best"] == 0.5  # FLIP's best on "a" is m3, not m1
    # the model's column is the one named: ColorVideoVDP (the default) reverses FovVideoVDP
    table["colorvideovdp"] = -table["fovvideovdp"]
    assert agreement.taus(table).loc["a", "psnr"] == pytest.approx(-1.0)


def test_each_model_keeps_a_record_of_its_own():
    record = {"benchmark": "perceptual_agreement", "device": "llvmpipe", "params": {}}
    keys = [core.record_key({**record, "params": {"model": m}}) for m in MODELS]
    assert len(set(keys)) == len(MODELS)
    assert core.record_key(record) == keys[MODELS.index(agreement.MODEL.default)]


@pytest.mark.parametrize("name", [installed(n) for n in MODELS])
def test_scores_rank_methods_on_a_rendered_sequence(ctx, name):
    # ctx's llvmpipe has loaded libLLVM before the model loads: the order that crashed torch's
    # triton, which now loads apart from it
    table = agreement.scores(ctx, ["fan"], (32, 18), METHODS, 2, 1, 4, model=name)
    assert list(table["method"]) == METHODS
    assert np.isfinite(table[["psnr", "flip", "temporal_instability"]].to_numpy()).all()
    assert (table[name] <= 10.0).all()
