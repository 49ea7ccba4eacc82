"""FovVideoVDP as an optional metric of sequences (blurlab.metrics.perceptual, docs/spec.md
§21.3) and the agreement of blurlab's metrics with it (blurlab.studies.perceptual_agreement).
The tests that run the model skip where the extra blurlab[perceptual] is not installed."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
from method_picks import EXAMPLE, pick

import blurlab as bl
from blurlab.metrics import perceptual
from blurlab.studies import perceptual_agreement as agreement

# Two methods to score: the example filter and a plain gather.
METHODS = [EXAMPLE, pick(kind="gather", params=("taps",))]
needs_model = pytest.mark.skipif(
    not perceptual.available(), reason="needs blurlab[perceptual] (pyfvvdp, torch)"
)


def test_the_metric_is_registered_exactly_where_it_is_installed():
    if perceptual.available():
        metric = bl.metrics.get("fovvideovdp")
        assert metric.sequence and metric.higher_is_better and metric.unit == "JOD"
        return
    assert "fovvideovdp" not in bl.metrics.registered()
    with pytest.raises(ValueError, match=r"not installed here.*blurlab\[perceptual\]"):
        bl.metrics.get("fovvideovdp")
    with pytest.raises(ValueError, match=r"unknown metrics \['nope'\].*not installed"):
        bl.metrics.check_names(["nope", "fovvideovdp"], "bl.sweep", sequences=True)
    with pytest.raises(ImportError, match=r"blurlab\[perceptual\]"):
        perceptual.fovvideovdp(np.zeros((2, 8, 8, 3)), np.zeros((2, 8, 8, 3)))


@needs_model
def test_fovvideovdp_is_10_for_the_reference_and_falls_with_noise():
    rng = np.random.default_rng(1)
    reference = rng.random((4, 24, 32, 4)).astype(np.float32)
    assert perceptual.fovvideovdp(reference, reference) == pytest.approx(10.0, abs=1e-3)
    slight = reference + rng.normal(0, 0.02, reference.shape).astype(np.float32)
    strong = reference + rng.normal(0, 0.2, reference.shape).astype(np.float32)
    mild, bad = perceptual.fovvideovdp(reference, slight), perceptual.fovvideovdp(reference, strong)
    assert 10.0 > mild > bad
    with pytest.raises(ValueError, match="differ in shape"):
        perceptual.fovvideovdp(reference, reference[:, :8])
    with pytest.raises(ValueError, match="fps must be"):
        perceptual.fovvideovdp(reference, reference, fps=0.0)


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
    taus = agreement.taus(table)
    assert taus.loc["a", "psnr"] == pytest.approx(1.0)
    assert taus.loc["a", "flip"] == pytest.approx(-1 / 3)  # m3 first, then m1, m2
    assert taus.loc["a", "temporal_instability"] == pytest.approx(1 / 3)
    assert np.allclose(taus.loc["b"], 1.0)
    summary = agreement.agreement(table).set_index("metric")
    assert summary.loc["psnr", "tau_mean"] == pytest.approx(1.0)
    assert summary.loc["flip", "tau_mean"] == pytest.approx(1 / 3)
    low, high = summary.loc["flip", ["tau_low", "tau_high"]]
    assert low == pytest.approx(-1 / 3) and high == pytest.approx(1.0)  # two sequences
    assert summary.loc["flip", "same_best"] == 0.5  # FLIP's best on "a" is m3, not m1


@needs_model
def test_scores_rank_methods_on_a_rendered_sequence(ctx):
    table = agreement.scores(ctx, ["fan"], (32, 18), METHODS, 2, 1, 4)
    assert list(table["method"]) == METHODS
    assert np.isfinite(table[["psnr", "flip", "temporal_instability"]].to_numpy()).all()
    assert (table["fovvideovdp"] <= 10.0).all()
