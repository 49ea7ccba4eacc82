"""A sweep's out-file returns a row only for the configuration that made it (docs/reliability.md,
"Resuming a sweep"): one test per component of a row's identity. Each reruns a sweep into a
file written with one component changed and checks the rerun's numbers against the same sweep
made fresh, with no file."""

from __future__ import annotations

import json
import shutil

import numpy as np
import pandas as pd
import pytest
from gltf_writer import GltfBuilder, box_triangles
from method_picks import pick

import blurlab as bl
from blurlab.studies import identity, recommend

SIZE = (32, 18)
GATHER = pick(kind="gather", params=("taps",))  # a gather with taps
GRID = {GATHER: {"taps": [4]}}
OPTIONS = {"size": SIZE, "reference_samples": 8, "progress": False, "repeats": 1}
METRICS = ("psnr", "ssim")


def fresh(ctx, scenes=("fan",), **changes):
    """The sweep with `changes`, made anew (no out-file)."""
    return bl.sweep(ctx, list(scenes), GRID, **{**OPTIONS, "metrics": METRICS, **changes})


def rerun(ctx, out, scenes=("fan",), **changes):
    return bl.sweep(ctx, list(scenes), GRID, out=out, **{**OPTIONS, "metrics": METRICS, **changes})


def same_numbers(a: pd.DataFrame, b: pd.DataFrame, columns) -> None:
    assert len(a) == len(b) == 1
    for column in columns:
        assert a[column].iloc[0] == pytest.approx(b[column].iloc[0], rel=0, abs=0), column


def test_reference_samples_the_stale_row_case(ctx, tmp_path):
    out = tmp_path / "r.csv"
    first = rerun(ctx, out)
    second = rerun(ctx, out, reference_samples=64)
    same_numbers(second, fresh(ctx, reference_samples=64), METRICS)
    assert second["reference_samples"].iloc[0] == 64
    assert first["psnr"].iloc[0] != second["psnr"].iloc[0]
    assert len(pd.read_csv(out)) == 2  # both configurations kept, each with its identity
    # and each configuration's rerun returns its own row from the file, not a new evaluation
    assert rerun(ctx, out)["identity"].iloc[0] == first["identity"].iloc[0]
    assert len(pd.read_csv(out)) == 2


def _tamper(out, column="psnr", value=99.0):
    """Gives every row of `out` a value no evaluation makes: a row returned from the file
    shows it."""
    table = pd.read_csv(out, dtype=str)
    table[column] = str(value)
    table.to_csv(out, index=False)


def test_device_rows_of_another_renderer_are_not_returned(ctx, tmp_path, monkeypatch):
    out = tmp_path / "r.csv"
    real = ctx.info()
    # a GPU that is not this machine's, on any machine
    names = ["NVIDIA H100 80GB HBM3/PCIe/SSE2", "NVIDIA H200/PCIe/SSE2"]
    other = next(name for name in names if name != real["renderer"])
    gpu = {**real, "device": "gpu", "renderer": other}
    monkeypatch.setattr(ctx, "info", lambda: gpu)
    rerun(ctx, out)  # a "GPU" run into the file
    monkeypatch.undo()
    _tamper(out)
    again = rerun(ctx, out)
    assert again["renderer"].iloc[0] == real["renderer"]
    same_numbers(again, fresh(ctx), METRICS)
    # ... and the GPU's row is still in the file, under its own identity
    table = pd.read_csv(out)
    assert sorted(table["renderer"]) == sorted([real["renderer"], gpu["renderer"]])


def test_shutter(ctx, tmp_path):
    out = tmp_path / "r.csv"
    rerun(ctx, out, shutter=(0.0, 1 / 60))
    _tamper(out)
    same_numbers(rerun(ctx, out, shutter=(0.0, 1 / 30)), fresh(ctx, shutter=(0.0, 1 / 30)), METRICS)


def test_antialiased_reference(ctx, tmp_path):
    out = tmp_path / "r.csv"
    rerun(ctx, out, metrics=["psnr"])
    _tamper(out)
    again = rerun(ctx, out, metrics=["psnr_aa"])
    same_numbers(again, fresh(ctx, metrics=["psnr_aa"]), ["psnr_aa"])
    assert json.loads(again["reference"].iloc[0])["kinds"] == ["antialiased"]


def test_untimed_rows_never_answer_a_timed_sweep(ctx, tmp_path):
    out = tmp_path / "r.csv"
    untimed = rerun(ctx, out, repeats=0)
    assert np.isnan(untimed["total_ms"].iloc[0])
    _tamper(out)
    timed = rerun(ctx, out, repeats=1)
    assert timed["total_ms"].iloc[0] > 0
    same_numbers(timed, fresh(ctx), METRICS)
    # the untimed configuration gets its own row back from the file
    assert rerun(ctx, out, repeats=0)["psnr"].iloc[0] == 99.0
    assert len(pd.read_csv(out)) == 2


def test_metric_set(ctx, tmp_path):
    out = tmp_path / "r.csv"
    rerun(ctx, out, metrics=["psnr"])
    again = rerun(ctx, out, metrics=["psnr", "flip"])
    same_numbers(again, fresh(ctx, metrics=["psnr", "flip"]), ["psnr", "flip"])
    assert json.loads(again["metric_set"].iloc[0]) == ["psnr", "flip"]


def test_blurlab_version(ctx, tmp_path, monkeypatch):
    out = tmp_path / "r.csv"
    monkeypatch.setattr(identity, "version", lambda: "0.0.1")
    rerun(ctx, out)
    monkeypatch.undo()
    _tamper(out)
    again = rerun(ctx, out)
    same_numbers(again, fresh(ctx), METRICS)
    assert again["blurlab_version"].iloc[0] == bl.__version__


def test_rows_of_other_code_are_not_returned(ctx, tmp_path):
    """A row carries a digest of the code that computed it (blurlab's modules, its core and the
    context's shaders): rows from an edited shader folder are evaluated anew, rows from an
    identical copy of the folder are returned (the digest is of the files, not the folder)."""
    out = tmp_path / "r.csv"
    edited, identical = tmp_path / "edited", tmp_path / "identical"
    shutil.copytree(ctx.shader_dir, edited)
    shutil.copytree(ctx.shader_dir, identical)
    shader = edited / "common" / "random.glsl"  # an include most passes share
    shader.write_text(shader.read_text() + "\n// an edit that changes no pixel\n")
    assert identity.code_digest(edited) != identity.code_digest(ctx.shader_dir)
    assert identity.code_digest(identical) == identity.code_digest(ctx.shader_dir)
    rerun(bl.Context(shader_dir=edited), out)
    _tamper(out)
    again = rerun(ctx, out)
    same_numbers(again, fresh(ctx), METRICS)
    assert again[identity.CODE].iloc[0] == identity.code_digest(ctx.shader_dir)
    _tamper(out)
    assert rerun(bl.Context(shader_dir=identical), out)["psnr"].iloc[0] == 99.0


def _spinning_box(path, spin: float):
    """A glTF box turning `spin` radians about z in the first 1/60 s, moving right."""
    b = GltfBuilder()
    p, n, i = box_triangles(1.0)
    node = b.node(mesh=b.mesh(p, i, n))
    half = [0.0, 0.0, np.sin(spin / 2), np.cos(spin / 2)]
    b.animate(node, "rotation", [0.0, 1 / 60], [[0.0, 0.0, 0.0, 1.0], half])
    b.animate(node, "translation", [0.0, 1 / 60], [[-0.5, 0.0, 0.0], [0.5, 0.0, 0.0]])
    return b.save(path)


def test_an_edited_gltf_file_is_evaluated_anew(ctx, tmp_path):
    out = tmp_path / "r.csv"
    path = _spinning_box(tmp_path / "box.glb", 0.5)
    first = rerun(ctx, out, [path])
    _spinning_box(path, 1.0)  # the same name, other content
    second = rerun(ctx, out, [path])
    same_numbers(second, fresh(ctx, [path]), METRICS)
    assert second["psnr"].iloc[0] != first["psnr"].iloc[0]
    assert second["scene"].iloc[0] == first["scene"].iloc[0] == "box.glb"
    assert second["scene_digest"].iloc[0] != first["scene_digest"].iloc[0]


def test_an_external_buffer_of_a_gltf_file_is_part_of_its_content(tmp_path):
    path = _spinning_box(tmp_path / "box.glb", 40.0)
    # The same document with its buffer in a file beside it.
    data = path.read_bytes()
    length = int.from_bytes(data[12:16], "little")
    document = json.loads(data[20 : 20 + length])
    binary = data[20 + length + 8 :]
    document["buffers"] = [{"byteLength": document["buffers"][0]["byteLength"], "uri": "b.bin"}]
    gltf = tmp_path / "box.gltf"
    gltf.write_text(json.dumps(document))
    (tmp_path / "b.bin").write_bytes(binary)
    assert identity.scene_files(gltf) == [gltf, tmp_path / "b.bin"]
    before = identity.scene_digest(bl.scenes.get(gltf))
    # The last bit of the last key's float: a motion a hair longer.
    (tmp_path / "b.bin").write_bytes(binary[:-4] + bytes([binary[-4] ^ 1]) + binary[-3:])
    assert identity.scene_digest(bl.scenes.get(gltf)) != before


def test_a_built_in_scene_changed_under_its_name(ctx, tmp_path):
    out = tmp_path / "r.csv"
    rerun(ctx, out)
    _tamper(out)
    scene = bl.scenes.get("fan")
    scene.objects[1].motion.spin_rate *= 2  # the same name, other motion
    changed = rerun(ctx, out, [scene])
    same_numbers(changed, fresh(ctx, [scene]), METRICS)
    assert identity.scene_digest(bl.scenes.get("fan")) == identity.scene_digest(
        bl.scenes.get("fan")
    )


def test_a_file_without_identities_is_evaluated_anew_and_kept(ctx, tmp_path):
    out = tmp_path / "r.csv"
    rerun(ctx, out)
    table = pd.read_csv(out).drop(columns=["identity"])
    table["psnr"] = 99.0
    table.to_csv(out, index=False)
    same_numbers(rerun(ctx, out), fresh(ctx), METRICS)
    assert sorted(pd.read_csv(out)["psnr"])[-1] == 99.0


def test_recommend_measures_an_edited_file_anew(ctx, tmp_path, monkeypatch):
    calls = []

    def counted_sweep(ctx, scenes, *args, **kwargs):
        calls.append(identity.scene_digest(scenes[0]))
        row = {"method": GATHER, "params": "{}", "total_ms": 1.0, "psnr": 30.0, "ssim": 0.9}
        return pd.DataFrame([row])

    monkeypatch.setattr(recommend, "sweep", counted_sweep)
    monkeypatch.setattr(recommend, "_CACHE", {})
    path = _spinning_box(tmp_path / "box.glb", 40.0)
    bl.recommend(ctx, path, SIZE, target_psnr=20)
    bl.recommend(ctx, path, SIZE, budget_ms=5)  # the same scene: cached
    assert len(calls) == 1
    _spinning_box(path, 80.0)
    bl.recommend(ctx, path, SIZE, target_psnr=20)
    assert len(calls) == 2 and calls[0] != calls[1]


def test_a_texture_file_named_by_path_is_part_of_the_content(tmp_path):
    image = tmp_path / "t.png"
    bl.io.write(image, np.full((4, 4, 3), 0.5, np.float32))
    scene = bl.scenes.get("fan")
    scene.objects[0].material.texture = str(image)
    before = identity.scene_digest(scene)
    bl.io.write(image, np.full((4, 4, 3), 0.25, np.float32))
    assert identity.scene_digest(scene) != before
