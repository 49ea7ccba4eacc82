"""The engines' methods and their peers under other names (docs/spec.md §17: engine_* and the
methods declared engine_peer, such as those of §17.7-17.9) take their place in every study from
the registry alone: the sweeps that the study, `recommend` and the failure suite run, the
transparency study's single-frame methods, the engines benchmark (and so `--peers eevee`), and
the failure suite's table on the scene where two motions cross inside one tile."""

from __future__ import annotations

import numpy as np
from method_picks import builtin, picks

import blurlab as bl
from blurlab.studies import failures, transparency
from blurlab.studies.sweep import sweep_methods
from blurlab_bench.quality import engine_methods

# The engines' filters, by their prefix, and the peers their declarations name.
PEERS = tuple(n for n in builtin() if n.startswith("engine_") or bl.method(n).engine_peer)


def test_every_study_lists_them():
    assert picks(role="engine_peer") and set(picks(role="engine_peer")) < set(PEERS)
    for listing in (sweep_methods(), transparency.single_frame_methods(), engine_methods()):
        assert set(PEERS) <= set(listing), listing


def test_the_failure_suite_scores_them_on_crossed_motions(ctx):
    assert "crossed_motions" in bl.scenes.names("failure")
    table = failures.evaluate(
        ctx,
        ["crossed_motions"],
        PEERS,
        size=(48, 27),
        frames=2,
        reference_samples=8,
        progress=False,
    )
    assert sorted(table.method) == sorted(PEERS)
    assert np.isfinite(table.psnr).all() and (table.psnr > 15).all(), table[["method", "psnr"]]
    assert (table[["nan", "inf", "outside_input_range"]] == 0).all().all()
