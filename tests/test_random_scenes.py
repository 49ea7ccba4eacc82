"""Random scenes (docs/spec.md §22): deterministic by seed, ranges validated and obeyed, and
the features a study splits results by."""

from __future__ import annotations

import importlib
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from golden import GOLDEN_DIR, IMAGE_TOLERANCE, color_problems
from method_picks import EXAMPLE, pick

import blurlab as bl
from blurlab import cli
from blurlab.scene.scenes.features import features, features_of, thin_share
from blurlab.scene.scenes.parts import add_wall, flat_scene
from blurlab.studies import study
from blurlab.studies.identity import scene_digest
from blurlab_bench.random_scenes import counts_of, worker_counts

SIZE = (160, 90)
SEEDS = (0, 1, 2)
# Hashes the G-buffers of SEEDS in a process of its own; argv[1]: the device.
HASHES = (
    "import sys; import blurlab as bl; ctx = bl.Context(sys.argv[1]); "
    f"print(*(bl.scenes.gbuffer_digest(ctx.render(bl.scenes.random(s), {SIZE})) for s in {SEEDS}))"
)


# llvmpipe's G-buffers of a few random scenes (a moving camera, HDR emitters, translucency
# among them), which every renderer must match within the golden tolerance (docs/spec.md §22.3).
STORED = GOLDEN_DIR / "random_scenes_gbuffers.npz"
STORED_SEEDS = (1, 3, 5, 7)
STORED_SIZE = (96, 54)


def stored_gbuffers(ctx) -> dict[str, np.ndarray]:
    """Colour clipped to [0, 1] (HDR emitters differ by thousands where an edge moves a pixel),
    object ids and motion of STORED_SEEDS at STORED_SIZE."""
    made = {}
    for seed in STORED_SEEDS:
        frame = ctx.render(bl.scenes.random(seed), STORED_SIZE)
        made[f"{seed}_color"] = np.clip(frame.color[..., :3], 0.0, 1.0)
        made[f"{seed}_object_id"] = frame.object_id
        made[f"{seed}_motion"] = frame.motion
    return made


def gbuffer_problems(made: dict, stored: dict) -> list[str]:
    """Colour within IMAGE_TOLERANCE; object ids equal on all but IMAGE_TOLERANCE["share_beyond"]
    of the pixels (an edge that rasterizes a pixel over), and where equal, motion within 0.01 px
    + 0.1 % on all but twice that share."""
    problems, share = [], IMAGE_TOLERANCE["share_beyond"]
    for seed in STORED_SEEDS:
        problems += [
            f"seed {seed}: {p}"
            for p in color_problems(made[f"{seed}_color"], stored[f"{seed}_color"])
        ]
        same = made[f"{seed}_object_id"] == stored[f"{seed}_object_id"]
        if (~same).mean() > share:
            problems.append(f"seed {seed}: {(~same).mean():.2%} of object ids differ")
        motion, recorded = made[f"{seed}_motion"][same], stored[f"{seed}_motion"][same]
        off = np.linalg.norm(motion - recorded, axis=-1) > 0.01 + 1e-3 * np.linalg.norm(
            recorded, axis=-1
        )
        if off.mean() > share * 2:
            problems.append(f"seed {seed}: motion differs at {off.mean():.2%} of the pixels")
    return problems


def test_random_scenes_match_llvmpipes_gbuffers_within_the_golden_tolerance(ctx):
    with np.load(STORED) as stored:
        assert not gbuffer_problems(stored_gbuffers(ctx), dict(stored))


def test_the_gbuffer_comparison_fails_on_another_scene(ctx):
    with np.load(STORED) as stored:
        stored = dict(stored)
    made = stored_gbuffers(ctx)
    made["3_color"], made["3_object_id"] = stored["5_color"][..., :3], stored["5_object_id"]
    problems = gbuffer_problems(made, stored)
    assert any(p.startswith("seed 3:") and "object ids" in p for p in problems)


def gbuffer_hashes(ctx) -> list[str]:
    return [bl.scenes.gbuffer_digest(ctx.render(bl.scenes.random(s), SIZE)) for s in SEEDS]


def test_a_seed_gives_the_same_gbuffer_twice_in_a_process_and_in_another(ctx):
    first = gbuffer_hashes(ctx)
    assert first == gbuffer_hashes(ctx)
    assert len(set(first)) == len(SEEDS)
    done = subprocess.run(
        [sys.executable, "-c", HASHES, ctx.info()["device"]],
        capture_output=True,
        text=True,
        timeout=120,
        check=True,
    )
    assert done.stdout.split() == first


def test_the_name_is_the_identity_seed_and_ranges_included():
    scene = bl.scenes.get("random:7")
    assert scene.name == "random:7" == bl.scenes.random_name(7)
    assert scene_digest(scene) == scene_digest(bl.scenes.random(7))
    assert scene_digest(scene) != scene_digest(bl.scenes.random(8))
    narrow = bl.scenes.random(7, speed_px=(1.0, 2.0))
    assert narrow.name.startswith("random:7:") and narrow.name != scene.name
    assert narrow.name == bl.scenes.random_name(7, {"speed_px": (1, 2)})
    # a range given at its default is no change
    assert bl.scenes.random(7, hdr=0.15).name == "random:7"


@pytest.mark.parametrize(
    "ranges, error, message",
    [
        ({"speed": (1, 2)}, ValueError, "no range"),
        ({"objects": (3, 1)}, ValueError, "lo <= hi"),
        ({"objects": (-1, 2)}, ValueError, "0 <= lo"),
        ({"objects": (1.5, 2)}, TypeError, "pair"),
        ({"objects": 3}, TypeError, "pair"),
        ({"speed_px": (0.0, 10.0)}, ValueError, "0 < lo"),
        ({"speed_px": (1.0, float("inf"))}, ValueError, "lo <= hi"),
        ({"fov_y": (30.0, 170.0)}, ValueError, "150"),
        ({"hdr": 1.5}, ValueError, r"\[0, 1\]"),
        ({"hdr": True}, TypeError, "probability"),
        ({"meshes": ("box", "cone")}, ValueError, "cone"),
        ({"meshes": ()}, TypeError, "non-empty"),
        ({"textures": "flat"}, TypeError, "non-empty list"),
    ],
)
def test_bad_ranges_say_what_is_wrong(ranges, error, message):
    with pytest.raises(error, match=message):
        bl.scenes.random(0, **ranges)


@pytest.mark.parametrize("seed", [-1, 1.5, True, 2**63, "3"])
def test_bad_seeds_are_refused(seed):
    with pytest.raises(ValueError, match="seed"):
        bl.scenes.random(seed)


def test_a_bad_random_name_is_refused():
    with pytest.raises(ValueError, match="random:SEED"):
        bl.scenes.get("random:x")


def test_the_ranges_are_obeyed():
    for seed in range(6):
        bare = bl.scenes.random(
            seed, objects=(0, 0), occluders=(0, 0), hdr=0.0, translucency=0.0, camera_motion=0.0
        )
        assert [o.name for o in bare.objects] == ["wall"] and bare.camera.motion is None
        lit = bl.scenes.random(seed, hdr=1.0, translucency=1.0, camera_motion=1.0)
        assert lit.hdr and lit.translucent and lit.camera.motion is not None
        bars = bl.scenes.random(seed, objects=(3, 3), meshes=("thin_bar",), occluders=(2, 2))
        names = [o.name for o in bars.objects]
        assert sum(n.startswith("thin_bar") for n in names) == 3
        assert sum(n.startswith("occluder") for n in names) == 2


def test_speeds_follow_the_range_in_pixels_at_1080p(ctx):
    """The same seed at two speeds: the same scene, its motion scaled; at 1/5 of 1080p a speed
    of 50 px per shutter is about 10 px."""
    size = (384, 216)
    speeds = {}
    for px in (5.0, 50.0):
        scene = bl.scenes.random(
            3,
            objects=(1, 1),
            occluders=(0, 0),
            meshes=("sphere",),
            motions=("linear",),
            camera_motion=0.0,
            hdr=0.0,
            translucency=0.0,
            speed_px=(px, px),
        )
        frame = ctx.render(scene, size)
        moving = np.linalg.norm(frame.motion, axis=-1)[frame.object_id == 1]
        speeds[px] = float(np.median(moving))
    assert 0.7 * 10 <= speeds[50.0] <= 1.5 * 10
    assert 8 <= speeds[50.0] / speeds[5.0] <= 12


def test_features_of_constructed_cases(ctx):
    still_wall = flat_scene("wall_only")
    add_wall(still_wall)
    wall = bl.scenes.features(ctx.render(still_wall, SIZE))
    assert wall["depth_complexity"] == 1.0  # the wall covers every pixel, nothing else
    # a GPU leaves about 1e-5 px on still geometry (two projections of one point)
    assert wall["motion_p99"] < 1e-3 and wall["moving_share"] == 0.0
    assert wall["camera_motion_share"] == 0.0 and wall["thin_share"] == 0.0
    assert not wall["has_hdr"] and not wall["has_translucency"]
    boxed = flat_scene("wall_and_box")
    add_wall(boxed)
    boxed.add(bl.mesh.box((1.0, 1.0, 0.2)), bl.Material(), bl.Motion.static((0, 0, 0.5)))
    assert 1.05 < bl.scenes.features(ctx.render(boxed, SIZE))["depth_complexity"] < 1.5

    yaw = bl.scenes.features(ctx.render(bl.scenes.get("camera_yaw"), SIZE))
    assert yaw["camera_motion_share"] > 0.99 and yaw["motion_p50"] > 1
    teapot = bl.scenes.features(ctx.render(bl.scenes.get("teapot_pass"), SIZE))
    assert teapot["camera_motion_share"] == 0.0 and teapot["motion_p99"] > 1
    assert teapot["motion_p50"] <= teapot["motion_p90"] <= teapot["motion_p99"]
    lit = bl.scenes.features(ctx.render(bl.scenes.random(2, hdr=1.0, translucency=1.0), SIZE))
    assert lit["has_hdr"] and lit["has_translucency"]


def test_thin_share_counts_runs_no_longer_than_3_percent_of_the_height():
    ids = np.zeros((90, 160), np.int32)
    ids[:, 40] = 1  # one column: thin
    ids[:, 80:100] = 2  # 20 columns: not thin (the limit is max(2, 2.7) px)
    assert thin_share(ids) == pytest.approx(90 / (90 * 160))
    ids[:, 120:122] = 3  # two more columns: thin
    assert thin_share(ids) == pytest.approx(3 * 90 / (90 * 160))


def test_features_need_a_rendered_frame():
    frame = bl.Frame(np.zeros((4, 4, 4)), np.ones((4, 4)), np.zeros((4, 4, 2)))
    with pytest.raises(ValueError, match="ctx.render"):
        bl.scenes.features(frame)


def test_study_over_random_scenes_carries_the_features(tmp_path, monkeypatch):
    monkeypatch.setattr(study, "default_grids", lambda: {pick(params=("taps",)): {"taps": [5]}})
    monkeypatch.setattr(study, "RANDOM_SCENES_PICTURED", 1)  # the first pictured, not the next
    out = tmp_path / "study"
    argv = ["study", "--random", "2", "--seed", "4", "--size", "160x90"]
    assert cli.main([*argv, "--reference-samples", "16", "--out", str(out)]) == 0
    table = pd.read_csv(out / "results.csv")
    assert sorted(table["scene"].unique()) == ["random:4", "random:5"]
    for column in bl.scenes.FEATURES:
        assert table[column].notna().all(), column
    assert (out / "report.html").is_file()
    assert (out / "random_4_reference.png").is_file() and (out / "random_5_pareto.png").is_file()
    assert not list(out.glob("random_5_*reference*")) and not list(out.glob("random_5_*error*"))
    assert "study --scenes random:5</code> pictures this one" in (out / "report.html").read_text()


def test_a_study_measures_the_features_on_its_sweeps_frames_and_renders_none_again(
    ctx, tmp_path, monkeypatch
):
    # the module, not the function bl.scenes.features that its package exports by that name
    feature_module = importlib.import_module("blurlab.scene.scenes.features")
    rendered_again = []
    measure_on_a_new_render = feature_module.features_of
    monkeypatch.setattr(
        feature_module,
        "features_of",
        lambda ctx, scenes, *args, **kw: (
            rendered_again.extend(s.name for s in scenes)
            or measure_on_a_new_render(ctx, scenes, *args, **kw)
        ),
    )
    argv = ["study", "--random", "2", "--seed", "4", "--size", "160x90", "--reference-samples"]
    # a method that renders at the shutter's centre, where the features are measured
    monkeypatch.setattr(study, "default_grids", lambda: {EXAMPLE: {}})
    assert bl.method_instant(EXAMPLE) == "center"
    assert cli.main([*argv, "16", "--out", str(tmp_path / "centre")]) == 0
    assert rendered_again == []  # each from the sweep's own frame
    first = pd.read_csv(tmp_path / "centre" / "results.csv")
    # the same features as measured on a render of their own
    table = first.drop(columns=list(bl.scenes.FEATURES))
    scenes = [bl.scenes.get(name) for name in ("random:4", "random:5")]
    again = bl.scenes.with_features(ctx, table, scenes, (160, 90))
    assert rendered_again == ["random:4", "random:5"]
    columns = list(bl.scenes.FEATURES)
    assert first[columns].equals(again[columns])
    # a sweep with no frame at the centre leaves them to be rendered again
    rendered_again.clear()
    close = pick(params=("taps",))
    assert bl.method_instant(close) == "close"
    monkeypatch.setattr(study, "default_grids", lambda: {close: {"taps": [5]}})
    assert cli.main([*argv, "16", "--out", str(tmp_path / "close")]) == 0
    assert rendered_again == ["random:4", "random:5"]


def test_study_refuses_a_bad_seed():
    with pytest.raises(SystemExit):
        cli.main(["study", "--random", "2", "--seed", "-3"])


if __name__ == "__main__":  # python tests/test_random_scenes.py --record  (on llvmpipe only)
    if sys.argv[1:] != ["--record"]:
        sys.exit("usage: python tests/test_random_scenes.py --record")
    context = bl.Context("software")
    np.savez_compressed(STORED, **stored_gbuffers(context))
    print(f"wrote {Path(STORED)}")


def test_features_of_a_set_equal_each_frames_own(ctx):
    # measured on threads while the next scene renders, in the order given
    scenes = [bl.scenes.random(seed) for seed in (1, 2, 3)]
    threaded = features_of(ctx, scenes, (64, 36))
    assert threaded == [features(ctx.render(scene, (64, 36))) for scene in scenes]


@pytest.mark.parametrize("text", ["0", "1,x", "", "65", "4,-1"])
def test_the_benchmarks_worker_counts_are_checked(text):
    with pytest.raises(ValueError, match="worker counts in 1..64"):
        worker_counts(text)
    assert worker_counts("1,4") == [1, 4]


@pytest.mark.parametrize("text", ["", "-1", "1,x", "65"])
def test_the_benchmarks_gpu_counts_are_checked(text):
    with pytest.raises(ValueError, match="gpu counts in 0..64"):
        counts_of(text, "gpus", 0)
    assert counts_of("0,1,4", "gpus", 0) == [0, 1, 4]
