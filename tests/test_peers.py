"""studies.peers: the rows Blender's EEVEE adds to a table, scored against blurlab's
references (the engines benchmark and `blurlab study --peers eevee` read them)."""

from __future__ import annotations

import math

import pytest

import blurlab as bl
from blurlab.studies import peers

needs_bpy = pytest.mark.skipif(
    not bl.blender.available(), reason="bpy is not installed (pip install 'blurlab[blender]')"
)


def test_a_scene_blender_refuses_renders_no_reference():
    def reference(antialias):
        raise AssertionError("a reference rendered for a scene Blender cannot reproduce")

    rows = peers.peer_rows(None, "fan", bl.scenes.get("fan"), (16, 9), reference, ("psnr_aa",))
    assert [row["method"] for row in rows] == [label for label, *_ in peers.EEVEE_ROWS]
    assert all("Blinn-Phong" in row["note"] and "psnr" not in row for row in rows)


@needs_bpy
def test_eevee_rows_score_against_both_references_and_match_the_film_filter(ctx):
    scene, size = bl.scenes.get("crossing"), (80, 45)
    references = {
        aa: ctx.reference(scene, size, samples=16, antialias=aa, progress=False)
        for aa in (False, True)
    }
    wanted = ("psnr_aa", "ssim_aa")
    (row,) = peers.peer_rows(
        ctx, "crossing", scene, size, references.__getitem__, wanted, [("EEVEE", 1, 1)], 0.5
    )
    assert "flip_aa" not in row and "ssim" not in row and row["reference_samples"] == 16
    for key in ("psnr", "psnr_aa"):
        assert 15 < row[key] < 80
    assert 0 < row["ssim_aa"] <= 1
    # EEVEE's pixel filter is close to a Gaussian of σ = 0.5 px (docs/engines.md), so the
    # film-filtered sharp frame matches it where nothing moves, far better than PSNR overall.
    assert math.isfinite(row["film_match_flat_db"])
    assert row["film_match_flat_db"] > row["psnr"] + 3
