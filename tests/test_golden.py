"""Every method's output on fixed frames against the golden record (tests/golden.py says what the
cases are and how to record them), on the default device: llvmpipe on CI, the GPU where EGL
finds one. Bits where this renderer's hashes are recorded; llvmpipe's images within
golden.IMAGE_TOLERANCE on every renderer (docs/reliability.md)."""

from __future__ import annotations

import json

import pytest
from golden import (
    device_id,
    digest,
    hash_files,
    hash_problems,
    image_problems,
    load_images,
    outputs,
    recorded_for,
)


@pytest.fixture(scope="module")
def made(ctx) -> dict:
    return outputs(ctx)


def test_outputs_have_the_recorded_hashes_where_this_renderer_has_a_file(ctx, made):
    path = recorded_for(device_id(ctx))
    if path is None:
        pytest.skip(
            f"no hashes recorded on {device_id(ctx)}; test_outputs_match_the_recorded_images "
            "checks this renderer (record with `python tests/golden.py --record`)"
        )
    recorded = json.loads(path.read_text())["hashes"]
    problems = hash_problems(recorded, made)
    assert not problems, f"{len(problems)} of {len(recorded)} cases: {problems[:5]}"


def test_outputs_match_the_recorded_images(made):
    stored = load_images()
    problems = image_problems(stored, made)
    assert not problems, f"{len(problems)} of {len(stored['cases'])} cases: {problems[:5]}"


def test_a_changed_pixel_fails_both_checks(made):
    stored = load_images()
    case = next(str(c) for c, i in zip(stored["cases"], stored["image_of"], strict=True) if i >= 0)
    assert "teapot_pass" in case or "occluder" in case, case
    changed = dict(made)
    changed[case] = made[case].copy()
    changed[case][30, 40, 0] += 1.0
    recorded = {c: digest(value) for c, value in made.items()}
    assert hash_problems(recorded, made) == []
    assert hash_problems(recorded, changed) == [f"{case}: bits changed"]
    found = image_problems(stored, changed)
    assert len(found) == 1 and found[0].startswith(f"{case}: differs by "), found
    assert found[0].endswith("at (y, x, c) (30, 40, 0)"), found[0]


def test_each_hash_file_names_one_renderer_and_holds_hashes():
    devices = []
    for path in hash_files():
        record = json.loads(path.read_text())
        devices.append((record["renderer"], record["version"]))
        assert all(
            value.startswith("error: ") or len(value) == 64 for value in record["hashes"].values()
        ), path.name
    assert "llvmpipe_hashes.json" in [path.name for path in hash_files()]
    assert len(set(devices)) == len(devices), f"two files record the same renderer: {devices}"
