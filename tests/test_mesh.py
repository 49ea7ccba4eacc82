"""Meshes: primitives, the teapot, OBJ files and their errors."""

from __future__ import annotations

import numpy as np
import pytest

import blurlab as bl

PRIMITIVES = ["plane", "box", "sphere", "cylinder", "torus", "torus_knot", "teapot", "fan", "tube"]


@pytest.mark.parametrize("name", PRIMITIVES)
def test_primitives_are_well_formed(name):
    mesh = getattr(bl.mesh, name)()
    assert mesh.positions.dtype == np.float32 and mesh.indices.dtype == np.uint32
    np.testing.assert_allclose(np.linalg.norm(mesh.normals, axis=1), 1.0, atol=1e-5)
    assert mesh.uvs.shape == (len(mesh.positions), 2)
    assert mesh.indices.max() < len(mesh.positions)


def test_teapot_is_newells_patches_at_unit_height():
    mesh = bl.mesh.teapot(segments=4)
    assert len(mesh.indices) == 32 * 4 * 4 * 2
    assert mesh.positions[:, 1].min() == pytest.approx(0.0, abs=1e-6)
    assert mesh.positions[:, 1].max() == pytest.approx(1.0, abs=1e-6)  # the lid's knob
    # The spout reaches further than the handle: x from about -3.0 to 3.43 of 3.15 units.
    assert mesh.positions[:, 0].max() > -mesh.positions[:, 0].min()


def test_sphere_normals_point_outward():
    mesh = bl.mesh.sphere(2.0)
    dots = np.sum(mesh.positions * mesh.normals, axis=1)
    assert (dots > 0).all()


def test_obj_with_quads_negative_indices_and_no_normals(tmp_path):
    path = tmp_path / "quad.obj"
    path.write_text(
        "# a unit square as one quad\n"
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
        "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
        "f -4/-4 -3/-3 -2/-2 -1/-1\n"
    )
    mesh = bl.mesh.load(path)
    assert len(mesh.indices) == 2 and len(mesh.positions) == 4
    np.testing.assert_allclose(np.abs(mesh.normals[:, 2]), 1.0)
    # OBJ's v grows upward; blurlab's grows down the image.
    corner = np.argmin(np.linalg.norm(mesh.positions - [0, 1, 0], axis=1))
    np.testing.assert_allclose(mesh.uvs[corner], [0, 0])


def test_obj_renders(ctx, tmp_path):
    path = tmp_path / "tri.obj"
    path.write_text("v -1 -1 0\nv 1 -1 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1\n")
    scene = bl.Scene(bl.Camera((0, 0, 3), (0, 0, 0)))
    scene.add(bl.mesh.load(path))
    frame = ctx.render(scene, (64, 36))
    assert (frame.object_id == 0).sum() > 100


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("v 0 0 0\nv 1 0 0\nf 1 2 3\n", r":3: index 3 refers to no element"),
        ("v 0 0 zero\n", r":1: could not convert"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n", r":4: a face needs at least 3 corners"),
        ("v 0 0 0\n", "has no faces"),
    ],
)
def test_malformed_obj_names_the_line(tmp_path, text, message):
    path = tmp_path / "bad.obj"
    path.write_text(text)
    with pytest.raises(OSError, match=message):
        bl.mesh.load(path)


def test_missing_and_binary_obj(tmp_path):
    with pytest.raises(FileNotFoundError, match="no such file"):
        bl.mesh.load(tmp_path / "absent.obj")
    binary = tmp_path / "binary.obj"
    binary.write_bytes(bytes(range(256)))
    with pytest.raises(OSError):
        bl.mesh.load(binary)


def test_mesh_validation():
    with pytest.raises(ValueError, match="indices outside"):
        bl.Mesh([[0, 0, 0]] * 3, [[0, 0, 1]] * 3, [[0, 0]] * 3, [[0, 1, 3]])
    with pytest.raises(ValueError, match="NaN or inf"):
        bl.Mesh([[0, 0, np.nan]] * 3, [[0, 0, 1]] * 3, [[0, 0]] * 3, [[0, 1, 2]])
    with pytest.raises(ValueError, match="sum to 1"):
        bl.Mesh(
            [[0, 0, 0]] * 3,
            [[0, 0, 1]] * 3,
            [[0, 0]] * 3,
            [[0, 1, 2]],
            np.zeros((3, 4), np.uint32),
            np.full((3, 4), 0.5),
        )


def test_skinned_mesh_needs_a_skeleton():
    scene = bl.Scene()
    with pytest.raises(ValueError, match="skeleton"):
        scene.add(bl.mesh.tube())
    with pytest.raises(ValueError, match="skeleton"):
        scene.add(bl.mesh.box(), skeleton=bl.Skeleton([bl.Bone(-1, np.eye(4))]))
