"""benchmarks/engines.py's references (--references, --reference-samples) and its Markdown, on
hand-made tables; studies.peers.peer_rows, which scores EEVEE there, with bpy where it is."""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import pandas as pd
import pytest

import blurlab as bl
from blurlab.studies import peers

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
import engines  # noqa: E402  (a script folder, not a package)

import common  # noqa: E402

needs_bpy = pytest.mark.skipif(
    not bl.blender.available(), reason="bpy is not installed (pip install 'blurlab[blender]')"
)


def score_row(scene, method, psnr, psnr_aa, ms=None, **extra) -> dict:
    row = {"scene": scene, "method": method, "psnr": psnr, "ssim": 0.9, "flip": 0.05}
    row |= {"psnr_aa": psnr_aa, "ssim_aa": 0.8, "flip_aa": 0.06}
    if ms is not None:
        row |= {"ms": ms, "back_to_back_ms": ms / 2}
    return row | extra


def table() -> pd.DataFrame:
    """Two methods on three scenes; EEVEE renders two of them (b is refused). Against the
    temporal reference `fast` beats EEVEE on a only, against the antialiased one on c only."""
    eevee = engines.EEVEE
    return pd.DataFrame(
        [
            score_row("a", "fast", 40.0, 30.0, 1.0),
            score_row("a", "slow", 20.0, 20.0, 3.0),
            score_row("a", eevee, 35.0, 35.0, film_match_flat_db=44.25),
            score_row("b", "fast", 38.0, 31.0, 1.0),
            score_row("b", "slow", 22.0, 21.0, 5.0),
            {"scene": "b", "method": eevee, "note": "Blinn-Phong"},
            score_row("c", "fast", 30.0, 36.0, 2.0),
            score_row("c", "slow", 24.0, 22.0, 4.0),
            score_row("c", eevee, 33.0, 34.0, film_match_flat_db=None),
        ]
    )


def blocks(text: str) -> list[list[str]]:
    """The Markdown's tables, each as its lines."""
    out, current = [], []
    for line in text.splitlines() + [""]:
        if line.startswith("|"):
            current.append(line)
        elif current:
            out.append(current)
            current = []
    return out


def cells(block: list[str], label: str) -> list[str]:
    row = next(line for line in block if line.startswith(f"| {label} |"))
    return [c.strip() for c in row.strip("|").split("|")][1:]


def test_the_temporal_reference_alone_gives_one_block_without_a_heading():
    text = engines.markdown(table().drop(columns="film_match_flat_db"))
    assert "Against the" not in text and "film filter" not in text
    (block,) = blocks(text)
    assert cells(block, "a") == [
        "40.00 / 0.900 / 0.050",
        "20.00 / 0.900 / 0.050",
        "35.00 / 0.900 / 0.050",
    ]
    assert cells(block, "b")[2] == "–"
    assert cells(block, "**median ms**") == ["**1.000**", "**4.000**", "–"]
    assert cells(block, "**scenes better than EEVEE**") == ["**1 of 2**", "**0 of 2**", "–"]


def test_the_antialiased_reference_adds_a_block_of_its_scores():
    text = engines.markdown(table(), ("temporal", "antialiased"), 0.5)
    assert text.index("Against the temporal reference:") < text.index(
        "Against the antialiased reference:"
    )
    temporal, antialiased = blocks(text)
    assert cells(temporal, "**median PSNR**")[:2] == ["**38.00**", "**22.00**"]
    assert cells(antialiased, "c") == [
        "36.00 / 0.800 / 0.060",
        "22.00 / 0.800 / 0.060",
        "34.00 / 0.800 / 0.060",
    ]
    assert cells(antialiased, "**median PSNR**") == ["**31.00**", "**21.00**", "**34.50**"]
    assert cells(antialiased, "**median PSNR, the 2 scenes EEVEE renders**")[0] == "**33.00**"
    assert cells(antialiased, "**scenes better than EEVEE**")[:2] == ["**1 of 2**", "**0 of 2**"]
    assert not any(line.startswith("| **median ms") for line in antialiased)
    # the film match of each scene EEVEE renders, none for b, which it does not
    assert text.rstrip().endswith("a 44.25, c –")
    assert "σ = 0.5 px" in text


def test_reference_options_refuse_what_they_cannot_do():
    assert engines.reference_list("temporal,antialiased") == ("temporal", "antialiased")
    for bad in ("antialiased", "temporal,filtered", ""):
        with pytest.raises(argparse.ArgumentTypeError, match="temporal among them"):
            engines.reference_list(bad)
    assert engines.reference_samples("auto") == "auto"
    assert engines.reference_samples("1024") == 1024
    for bad in ("0", "-3", "1e3", "many"):
        with pytest.raises(argparse.ArgumentTypeError, match="auto or a whole number"):
            engines.reference_samples(bad)


def test_config_rows_carry_their_parameters_and_bad_ones_are_refused():
    config = common.method_config("gather_coverage:samples=16,film_filter=0.5,seed=3")
    assert config == ("gather_coverage", {"samples": 16, "film_filter": 0.5, "seed": 3})
    assert common.method_config("gather_coverage:packed_inputs=true")[1] == {"packed_inputs": True}
    parser = argparse.ArgumentParser()  # as engines.py and crosscheck.py take it
    common.add_config_argument(parser)
    given = ["--config", "gather_coverage:samples=4", "--config", "engine_unity:quality=8"]
    assert parser.parse_args(given).config == [
        ("gather_coverage", {"samples": 4}),
        ("engine_unity", {"quality": 8}),
    ]
    runs = engines.method_runs(["reconstruct_guertin2014"], 0.0, [config])
    assert runs[-1] == (
        "gather_coverage, samples=16, film_filter=0.5, seed=3",
        "gather_coverage",
        config[1],
    )
    for bad in ("gather_coverage:samples", "gather_coverage:samples=many", ":k=3", "x:=3"):
        with pytest.raises(argparse.ArgumentTypeError, match="METHOD:KEY=VALUE"):
            common.method_config(bad)


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


def test_every_layout_times_and_checks_on_a_small_scene(ctx):
    # --variants in-process, tiny: every layout of every kind gives the right tiles (or keys
    # that decode to them) and image, and the time goal runs with the fastest of each kind.
    rows = engines.coverage_variants(ctx, ["fan"], (48, 27), 1, 0.5)
    layouts = {row["layout"] for row in rows}
    assert {"dilation gather", "dilation scatter", "dilation scatter_in_gather"} <= layouts
    assert all(row["right"] for row in rows), [r["layout"] for r in rows if not r["right"]]
    summary = engines.layout_summary(rows)
    assert set(summary["fastest"]) == set(engines.LAYOUTS)
    goal = engines.time_goal(ctx, ["fan"], (48, 27), 1, 0.5, summary["fastest"])
    assert goal["b2b_ms"]["median_of_ratios"] > 0
