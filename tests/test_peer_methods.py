"""The engines' peers of docs/spec.md §17.7-17.9 (engine_unreal5, engine_jimenez2014,
gather_pixel) take their place in every study from the registry alone: the sweeps that the
study, `recommend` and the failure suite run, the transparency study's single-frame methods,
the engines benchmark (and so `--peers eevee`), and the failure suite's table on the scene
where two motions cross inside one tile."""

from __future__ import annotations

import numpy as np

import blurlab as bl
from blurlab.studies import failures, transparency
from blurlab.studies.sweep import sweep_methods
from blurlab_bench.quality import engine_methods

NEW = ("engine_unreal5", "engine_jimenez2014", "gather_pixel")


def test_every_study_lists_them():
    for listing in (sweep_methods(), transparency.single_frame_methods(), engine_methods()):
        assert set(NEW) <= set(listing), listing


def test_the_failure_suite_scores_them_on_crossed_motions(ctx):
    assert "crossed_motions" in bl.scenes.names("failure")
    table = failures.evaluate(
        ctx, ["crossed_motions"], NEW, size=(48, 27), frames=2, reference_samples=8, progress=False
    )
    assert sorted(table.method) == sorted(NEW)
    assert np.isfinite(table.psnr).all() and (table.psnr > 15).all()
    assert (table[["nan", "inf", "outside_input_range"]] == 0).all().all()
