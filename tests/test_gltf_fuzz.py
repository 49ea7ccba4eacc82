"""Fuzzing the glTF reader: 1000 mutated .gltf and 1000 mutated .glb files from a seeded
mutator, and 300 files with several animations, their animations mutated, each loaded with a
random `animation` choice. Every file either loads into a scene that renders (or refuses clearly
to) or raises GltfError naming the file (or, for a malformed choice, a TypeError or ValueError
saying what is allowed): no other exception, no crash, and none takes longer than 5 s."""

from __future__ import annotations

import io as bytes_io
import json
import math
import random
import time
import warnings

import numpy as np
import pytest
from gltf_writer import GltfBuilder, box_triangles
from PIL import Image

import blurlab as bl
from blurlab.scene.gltf import GltfError

FILES_PER_FORMAT = 1000
SLOWEST_ALLOWED_S = 5.0
ODD_VALUES = [
    -1, 0, 1, 2, 3, 7, 255, 65535, 2**31, 10**9, 10**18, -(10**9), 0.5, -0.0, 1e308, -1e308,
    "x", "", None, True, [], {}, [1, 2], {"a": 1}, "../../etc/passwd", "http://example.com/a",
    math.nan, "BLEND", "MASK", "blend",
]  # fmt: skip


def rich_document() -> GltfBuilder:
    """Nodes in a hierarchy, a skin, every interpolation, a texture, a camera, and BLEND and
    MASK materials (docs/spec.md §20)."""
    b = GltfBuilder()
    p, n, i = box_triangles()
    png = bytes_io.BytesIO()
    Image.fromarray(np.full((2, 2, 4), 200, np.uint8), "RGBA").save(png, format="PNG")
    material = b.texture_material(png.getvalue(), factor=(0.9, 0.5, 0.2, 0.8), alpha_mode="BLEND")
    masked = b.material((0.3, 0.6, 0.3, 0.7), alpha_mode="MASK", alpha_cutoff=0.4)
    child = b.node(root=False, mesh=b.mesh(p, i, n, uvs=np.zeros((len(p), 2)), material=material))
    parent = b.node(children=[child], translation=[0.5, 0, 0])
    j1 = b.node(root=False, translation=[1, 0, 0])
    j0 = b.node(children=[j1])
    skin = b.skin([j0, j1], [np.eye(4), np.eye(4)])
    joints = np.tile([0, 1, 0, 0], (len(p), 1))
    weights = np.tile([0.5, 0.5, 0, 0], (len(p), 1))
    b.node(mesh=b.mesh(p, i, n, joints=joints, weights=weights, material=masked), skin=skin)
    b.animate(parent, "translation", [0, 1], [[0, 0, 0], [1, 0, 0]])
    b.animate(child, "rotation", [0, 1], [[0, 0, 0, 1], [0, 0, 0.7071, 0.7071]], "STEP")
    b.animate(j1, "scale", [0, 1], [[0, 0, 0], [1, 1, 1], [0, 0, 0]] * 2, "CUBICSPLINE")
    b.node(camera=b.camera(0.8, 0.1, 100.0), translation=[0, 0, 5])
    return b


def mutate_json(doc: dict, rng: random.Random) -> dict:
    """Replaces, deletes or duplicates a few values anywhere in the JSON tree."""
    for _ in range(rng.randint(1, 4)):
        parents, stack = [], [doc]
        while stack:  # every (container, key) of the tree
            node = stack.pop()
            items = node.items() if isinstance(node, dict) else enumerate(node)
            for k, v in items:
                parents.append((node, k))
                if isinstance(v, (dict, list)):
                    stack.append(v)
        container, key = rng.choice(parents)
        action = rng.random()
        if action < 0.15 and isinstance(container, dict):
            del container[key]
        elif (
            action < 0.3
            and isinstance(container[key], (int, float))
            and not isinstance(container[key], bool)
        ):
            container[key] = container[key] + rng.choice([-1, 1, 2**20, -(2**20)])
        elif action < 0.4 and isinstance(container[key], list):
            container[key] = container[key] * rng.randint(0, 3)
        else:
            container[key] = rng.choice(ODD_VALUES)
    return doc


def mutate_bytes(data: bytes, rng: random.Random) -> bytes:
    data = bytearray(data)
    action = rng.random()
    if action < 0.25:
        return bytes(data[: rng.randrange(len(data))])  # truncated
    for _ in range(rng.randint(1, 8)):
        at = rng.randrange(len(data))
        if action < 0.6:
            data[at] = rng.randrange(256)  # a flipped byte, often in the JSON chunk
        elif action < 0.8:
            data[at : at + 4] = rng.randrange(2**32).to_bytes(4, "little")
        else:
            del data[at : at + rng.randint(1, 16)]
    return bytes(data)


def _load_all(ctx, paths, animations=None) -> tuple[int, float]:
    loaded, slowest = 0, 0.0
    for k, path in enumerate(paths):
        start = time.perf_counter()
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                if animations is None:
                    scene = bl.scenes.gltf(path)
                else:
                    scene = bl.scenes.gltf(path, animation=animations[k])
            loaded += 1
            try:  # a scene that loads renders, or says clearly why not (a transform overflows)
                frame = ctx.render(scene, (16, 16))
                assert np.isfinite(frame.motion).all()
            except ValueError as error:
                assert str(error).startswith("blurlab")
        except GltfError as error:  # naming the file once, and its cause once
            assert str(error).startswith(f"blurlab.scene.gltf: {path.name}: "), str(error)
            assert str(error).count("blurlab") == 1, str(error)
        except (TypeError, ValueError) as error:  # a malformed choice, refused before reading
            assert animations is not None and str(error).startswith("blurlab.scene.gltf: animation")
        except Exception as error:  # noqa: BLE001 - the point of the test
            pytest.fail(f"{path.name}: {type(error).__name__}: {error}")
        slowest = max(slowest, time.perf_counter() - start)
    return loaded, slowest


def test_mutated_gltf_files_load_or_fail_clearly(ctx, tmp_path):
    rng = random.Random(20261123)
    base = json.loads(rich_document().save(tmp_path / "base.gltf").read_text())
    paths = []
    for k in range(FILES_PER_FORMAT):
        doc = mutate_json(json.loads(json.dumps(base)), rng)
        path = tmp_path / f"m{k}.gltf"
        try:
            path.write_text(json.dumps(doc))
        except ValueError:  # a value JSON cannot hold
            path.write_text(json.dumps(doc, allow_nan=True))
        paths.append(path)
    loaded, slowest = _load_all(ctx, paths)
    print(f"gltf fuzz: {loaded}/{len(paths)} loaded, the rest refused; slowest {slowest:.3f} s")
    assert slowest < SLOWEST_ALLOWED_S
    assert 0 < loaded < len(paths)  # the mutator really makes both kinds


def test_mutated_glb_files_load_or_fail_clearly(ctx, tmp_path):
    rng = random.Random(20261124)
    base = rich_document().save(tmp_path / "base.glb").read_bytes()
    paths = []
    for k in range(FILES_PER_FORMAT):
        path = tmp_path / f"m{k}.glb"
        path.write_bytes(mutate_bytes(base, rng))
        paths.append(path)
    loaded, slowest = _load_all(ctx, paths)
    print(f"glb fuzz: {loaded}/{len(paths)} loaded, the rest refused; slowest {slowest:.3f} s")
    assert slowest < SLOWEST_ALLOWED_S
    assert 0 < loaded < len(paths)


ANIMATION_CHOICES = [
    "all", None, 0, 1, 2, 3, -1, 10**9, "Slide", "Spin", "Spin again", "missing", "", [0, 1],
    ["Slide", 2], [1, 2], [2, 2], [0, "Slide"], [], ["all"], ["all", 0], [None], True, 1.5,
    ("Spin",), {"a": 1}, np.int64(1),
]  # fmt: skip


def several_animations() -> GltfBuilder:
    """Three named animations on a parent and its child: Slide and Spin drive different
    nodes, "Spin again" drives the child's rotation as Spin does."""
    b = GltfBuilder()
    p, n, i = box_triangles()
    child = b.node(root=False, mesh=b.mesh(p, i, n), translation=[1, 0, 0])
    parent = b.node(mesh=b.mesh(p, i, n), children=[child])
    b.animate(parent, "translation", [0, 1], [[0, 0, 0], [1, 0, 0]], animation=0, name="Slide")
    turn = [[0, 0, 0, 1], [0, 0, 0.7071, 0.7071]]
    b.animate(child, "rotation", [0, 1], turn, animation=1, name="Spin")
    b.animate(child, "rotation", [0, 2], turn, "STEP", animation=2, name="Spin again")
    b.animate(parent, "scale", [0, 1], [[1, 1, 1], [2, 2, 2]], animation=2)
    return b


def test_mutated_animations_and_random_choices_load_or_fail_clearly(ctx, tmp_path):
    rng = random.Random(20261127)
    base = json.loads(several_animations().save(tmp_path / "base.gltf").read_text())
    paths, choices = [], []
    for k in range(300):
        doc = json.loads(json.dumps(base))
        if k % 3:  # two in three files have their animations mutated
            mutate_json(doc["animations"], rng)
        path = tmp_path / f"a{k}.gltf"
        path.write_text(json.dumps(doc))
        paths.append(path)
        choices.append(rng.choice(ANIMATION_CHOICES))
    loaded, slowest = _load_all(ctx, paths, choices)
    print(
        f"animation fuzz: {loaded}/{len(paths)} loaded, the rest refused; slowest {slowest:.3f} s"
    )
    assert slowest < SLOWEST_ALLOWED_S
    assert 0 < loaded < len(paths)


def test_the_unmutated_base_files_load(tmp_path):
    for suffix in (".gltf", ".glb"):
        scene = bl.scenes.gltf(rich_document().save(tmp_path / f"base{suffix}"))
        assert len(scene.objects) == 2
        assert math.isclose(scene.camera.fov_y, math.degrees(0.8))


@pytest.mark.parametrize(
    "field, value, message",
    [
        ("alphaMode", "ADDITIVE", "alphaMode 'ADDITIVE' is not one of"),
        ("alphaMode", "blend", "alphaMode 'blend' is not one of"),
        ("alphaMode", 2, "alphaMode .2. is not one of"),
        ("alphaCutoff", 1.5, r"alphaCutoff 1.5 is outside \[0, 1\]"),
        ("alphaCutoff", -0.1, r"alphaCutoff -0.1 is outside \[0, 1\]"),
        ("alphaCutoff", math.nan, "alphaCutoff must be 1 finite numbers"),
    ],
)
def test_bad_alpha_fields_are_refused(tmp_path, field, value, message):
    doc = json.loads(rich_document().save(tmp_path / "base.gltf").read_text())
    doc["materials"][0][field] = value
    path = tmp_path / "bad.gltf"
    path.write_text(json.dumps(doc, allow_nan=True))
    with pytest.raises(GltfError, match=message):
        bl.scenes.gltf(path)


def test_blend_and_mask_materials_are_honoured(tmp_path):
    scene = bl.scenes.gltf(rich_document().save(tmp_path / "base.gltf"))
    blends = sorted((obj.material.blend, obj.material.alpha) for obj in scene.objects)
    assert blends == [("blend", pytest.approx(0.8)), ("mask", pytest.approx(0.7))]
    cutoffs = sorted(obj.material.alpha_cutoff for obj in scene.objects)
    assert cutoffs == pytest.approx([0.4, 0.5])
