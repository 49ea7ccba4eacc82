"""Files with several animations (docs/spec.md §15.1): by default every animation plays, as one,
when no two drive the same (node, property); a conflict is refused naming both; a choice by
index, name or list plays those alone, and a warning names the animations left out."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from gltf_writer import GltfBuilder, box_triangles

import blurlab as bl
from blurlab.cli_args import parse_animation
from blurlab.scene.gltf import GltfError

SIZE = (64, 36)
CAMERA = bl.Camera((0.0, 0.0, 9.0), (0.0, 0.0, 0.0), fov_y=50)
SHUTTER = (0.2, 0.6)


def quarter_turn(k):
    half = k * math.pi / 4  # a quarter turn about z per unit of k, as (x, y, z, w)
    return [0.0, 0.0, math.sin(half), math.cos(half)]


# Five channels on four nodes (one a child), as an exporter that writes one animation per
# object does: (node, property, key times, key values).
def five_channels(nodes):
    return [
        (nodes[0], "translation", [0, 1], [[-3, 0, 0], [-1, 1, 0]]),
        (nodes[1], "rotation", [0, 0.5, 1], [quarter_turn(0), quarter_turn(1), quarter_turn(2)]),
        (nodes[2], "scale", [0, 1], [[1, 1, 1], [0.4, 1.6, 1]]),
        (nodes[3], "translation", [0.2, 0.8], [[0, -2, 0], [1.5, -1, 0]]),
        (nodes[3], "rotation", [0, 1], [quarter_turn(0), quarter_turn(-1)]),
    ]


def five_node_file(path, merged: bool, names=None):
    """Four boxes animated by five animations, or by the same channels in one."""
    b = GltfBuilder()
    p, n, i = box_triangles(0.8)
    child = b.node(root=False, mesh=b.mesh(p, i, n), translation=[0.0, 1.2, 0.0])
    nodes = [
        b.node(mesh=b.mesh(p, i, n)),
        b.node(mesh=b.mesh(p, i, n), translation=[1.0, 1.0, 0.0]),
        b.node(mesh=b.mesh(p, i, n), translation=[2.5, -1.0, 0.0], children=[child]),
        child,
    ]
    for k, (node, path_, times, values) in enumerate(five_channels(nodes)):
        a = 0 if merged else k
        name = None if names is None else names[a]
        b.animate(node, path_, times, values, animation=a, name=name)
    return b.save(path)


def load_quietly(path, **kwargs):
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # the default choice of a disjoint file warns of nothing
        return bl.scenes.gltf(path, camera=CAMERA, shutter=SHUTTER, **kwargs)


def test_five_animations_play_as_the_same_file_merged_bit_for_bit(ctx, tmp_path):
    apart = load_quietly(five_node_file(tmp_path / "apart.glb", merged=False))
    merged = load_quietly(five_node_file(tmp_path / "merged.glb", merged=True))
    assert len(apart.objects) == 4
    frames = [ctx.render(scene, SIZE) for scene in (apart, merged)]
    for field in ("color", "motion", "depth", "object_id"):
        a, b = (np.asarray(getattr(f, field)) for f in frames)
        assert np.array_equal(a, b), field
    assert np.abs(frames[0].motion).max() > 2, "the scene should move"
    references = [ctx.reference(scene, SIZE, samples=8).color for scene in (apart, merged)]
    assert np.array_equal(references[0], references[1])
    one = load_with_warning(tmp_path / "apart.glb", 0, "left out animation 1, animation 2")
    assert not np.array_equal(ctx.render(one, SIZE).motion, frames[0].motion)


def load_with_warning(path, animation, words):
    with pytest.warns(UserWarning, match=words):
        return bl.scenes.gltf(path, animation=animation, camera=CAMERA, shutter=SHUTTER)


def conflicting_file(path):
    b = GltfBuilder()
    p, n, i = box_triangles(1.0)
    box = b.node(mesh=b.mesh(p, i, n), name="Cube")
    b.animate(box, "translation", [0, 1], [[0, 0, 0], [2, 0, 0]], animation=0, name="Slide")
    b.animate(box, "scale", [0, 1], [[1, 1, 1], [2, 2, 2]], animation=0)
    b.animate(box, "translation", [0, 1], [[0, 0, 0], [0, 2, 0]], animation=1, name="Lift")
    b.animate(box, "rotation", [0, 1], [quarter_turn(0), quarter_turn(1)], animation=2)
    return b.save(path)


def test_two_animations_driving_one_property_are_refused_naming_both(tmp_path):
    path = conflicting_file(tmp_path / "conflict.gltf")
    message = (
        r"conflict\.gltf: animation 0 'Slide' and animation 1 'Lift' both drive the "
        r"translation of node 0 \('Cube'\); choose which to play with animation="
    )
    with pytest.raises(GltfError, match=message):
        bl.scenes.gltf(path)
    with pytest.raises(GltfError, match=message):
        bl.scenes.gltf(path, animation=["Slide", "Lift"])
    with pytest.raises(GltfError, match=message):
        bl.scenes.get(str(path))  # wherever a file is a scene name, the same rule
    # Animations 0 and 2 drive different properties of the same node: both play.
    scene = load_with_warning(
        path,
        [0, 2],
        r"plays animation 0 'Slide', animation 2; left out "
        r"animation 1 'Lift'$",
    )
    motion = scene.objects[0].motion
    assert np.allclose(motion.transform(1.0)[:3, 3], [2, 0, 0])  # Slide's translation
    assert np.allclose(motion.transform(1.0)[:3, :3], [[0, -2, 0], [2, 0, 0], [0, 0, 2]])


def test_a_choice_by_index_name_or_list_and_the_warning_for_what_is_left_out(tmp_path):
    names = ["A", "B", "C", "D", "E"]
    path = five_node_file(tmp_path / "named.gltf", merged=False, names=names)
    by_name = load_with_warning(
        path,
        ["B", "D"],
        "plays animation 1 'B', animation 3 'D'; left "
        "out animation 0 'A', animation 2 'C', animation 4 'E'",
    )
    by_index = load_with_warning(path, [1, 3], "left out animation 0 'A'")
    for t in (0.0, 0.5, 1.0):
        for a, b in zip(by_name.objects, by_index.objects, strict=True):
            assert np.array_equal(a.model(t), b.model(t))
    assert np.array_equal(by_name.objects[0].model(1.0), np.eye(4))  # A is left out
    rest = load_with_warning(path, None, r"plays none \(the rest pose\); left out animation 0")
    assert all(
        np.array_equal(o.model(0.7), rest.objects[k].model(0.0)) for k, o in enumerate(rest.objects)
    )
    assert load_quietly(path, animation="all").objects[0].model(1.0)[0, 3] == -1.0


@pytest.mark.parametrize(
    ("animation", "error", "message"),
    [
        (7, GltfError, "animation is 7; allowed 0..4"),
        ("Z", GltfError, r"no animation named 'Z'; the file's animations are \['A', 'B'"),
        ([0, "A"], GltfError, "picks one animation twice"),
        ([], ValueError, "empty list"),
        ([1, 1], ValueError, "names one twice"),
        (["all", 1], ValueError, '"all" stands alone'),
        (-1, ValueError, "negative"),
        (True, TypeError, "animation True is not allowed"),
        (1.0, TypeError, 'allowed: None, "all", an index, a name'),
        ([None], TypeError, "animation None is not allowed"),
    ],
)
def test_bad_animation_choices_say_what_is_allowed(tmp_path, animation, error, message):
    path = five_node_file(tmp_path / "named.gltf", merged=False, names=list("ABCDE"))
    with pytest.raises(error, match=message):
        bl.scenes.gltf(path, animation=animation)


def test_a_file_without_animations(tmp_path):
    b = GltfBuilder()
    p, n, i = box_triangles(1.0)
    b.node(mesh=b.mesh(p, i, n))
    path = b.save(tmp_path / "still.gltf")
    assert load_quietly(path).objects[0].model(3.0)[0, 3] == 0  # "all" of none: the rest pose
    with pytest.raises(GltfError, match="animation 0 asked for; the file has none"):
        bl.scenes.gltf(path, animation=0)


def test_the_command_line_follows_the_same_rule_and_offers_the_choice(tmp_path):
    from test_cli import assert_one_line_error, run_cli

    path = str(conflicting_file(tmp_path / "conflict.gltf"))
    both = ("animation 0 'Slide' and animation 1 'Lift'", "animation=")
    assert_one_line_error(run_cli("recommend", path, "--budget-ms", "1"), *both)
    out = str(tmp_path / "study")
    assert_one_line_error(run_cli("study", "--scenes", path, "--out", out), *both)
    built_in = run_cli("recommend", "fan", "--budget-ms", "1", "--animation", "0")
    assert_one_line_error(built_in, "--animation is for .gltf/.glb files")
    assert parse_animation("Slide,2") == ["Slide", 2]
    assert parse_animation("none") is None
    assert parse_animation("3") == 3
