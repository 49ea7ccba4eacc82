"""Captured frames join the suite when given (docs/spec.md §24.1): an engine's G-buffers and
references of the same shutter from files are the captured category, each frame a unit of the
card's statistics, the files' bytes part of the suite's hash."""

from __future__ import annotations

import numpy as np
import pytest

import blurlab as bl
from blurlab.io import capture
from blurlab.studies.capture_study import capture_grids
from blurlab.suite import run_suite, suite_identity
from blurlab.suite.captured import Capture, captures_of, digests

SIZE = (48, 27)
FRAMES = 2
CHANNELS = [f"ViewLayer.Combined.{c}" for c in "RGBA"] + ["ViewLayer.Depth.Z"]
CHANNELS += [f"ViewLayer.Vector.{c}" for c in "XYZW"]
# Chosen by what they do: a method whose defaults run on a capture, and one whose defaults
# read the G-buffer at shutter close, which a capture does not have.
AT_CENTRE = next(n for n in bl.methods() if capture_grids({n: {}})[0])
AT_CLOSE = next(n for n in bl.methods() if "shutter close" in capture_grids({n: {}})[1].get(n, ""))


@pytest.fixture(scope="module")
def shot(ctx, tmp_path_factory):
    """FRAMES frames of a built-in scene as Blender writes them (shot.####.exr) and their
    references (reference.####.exr)."""
    folder = tmp_path_factory.mktemp("shot")
    scene = bl.scenes.get("fan")
    for i in range(FRAMES):
        shutter = (0.25 * i, 0.25 * i + 1.0)
        frame = ctx.render(scene, SIZE, shutter)
        vector = capture.motion_from_blurlab(frame.motion, "blender")
        layers = np.concatenate([frame.color, frame.depth[..., None], vector], axis=2)
        bl.io.write(folder / f"shot.{i + 1:04d}.exr", layers, channel_names=CHANNELS)
        reference = ctx.reference(scene, SIZE, shutter, samples=8, progress=False).color
        bl.io.write(folder / f"reference.{i + 1:04d}.exr", reference)
    return Capture(str(folder / "shot.####.exr"), str(folder / "reference.####.exr"), "blender")


def test_a_card_with_captures_ranks_each_frame_and_hashes_the_files(ctx, shot, tmp_path):
    card = run_suite(
        ctx, tmp_path / "card", [AT_CENTRE, AT_CLOSE], "tiny", pictures=False, captures=[shot]
    )
    entry = card["categories"]["captured"]
    assert entry["status"] == "measured" and entry["scenes"] == ["shot"]
    figures = entry["methods"][AT_CENTRE]
    assert figures["units"] == FRAMES  # each frame is a unit
    assert 1 <= figures["rank"] <= figures["of"]
    assert np.isfinite(figures["metrics"]["psnr"]["median"])
    # the method that reads the G-buffer at shutter close is named, with why
    assert AT_CLOSE not in entry["methods"] and "shutter close" in entry["left_out"][AT_CLOSE]
    # the captures are part of the hash: a card without them, or with other bytes, differs
    assert card["suite"]["parts"]["captured"]
    assert card["suite"]["hash"] != suite_identity("tiny")["hash"]
    assert card["suite"]["definition"]["categories"]["captured"]["captures"] == digests([shot])
    assert "<h2>captured</h2>" in (tmp_path / "card" / "card.html").read_text()


def test_other_bytes_give_another_digest(shot, tmp_path):
    before = digests([shot])
    other = Capture(shot.capture, shot.reference, shot.convention, shutter_fraction=0.5)
    assert digests([other]) != before


def test_bad_captures_are_refused_naming_what_is_wrong(ctx, shot, tmp_path):
    with pytest.raises(ValueError, match="each --capture needs its --reference"):
        captures_of([shot.capture], [])
    missing = Capture(shot.capture, str(tmp_path / "nothing.####.exr"))
    with pytest.raises(FileNotFoundError, match="nothing.####.exr"):
        run_suite(ctx, tmp_path / "card", [AT_CENTRE], "tiny", captures=[missing])
    one = Capture(shot.capture, shot.reference.replace("####", "0001"))
    with pytest.raises(ValueError, match="has 1 frame, the capture .* 2"):
        run_suite(ctx, tmp_path / "card", [AT_CENTRE], "tiny", captures=[one])
    assert not (tmp_path / "card").exists()  # refused before anything ran
