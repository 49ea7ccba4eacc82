"""Failure cases: each isolates one way post-process blur breaks (docs/failure_cases.md)."""

from __future__ import annotations

import math

import numpy as np

from .. import mesh
from ..model import Camera, Material, Scene
from ..motion import Motion
from .builtin import fan
from .parts import checker, flat_scene, rotation_x, translation, turning_camera, walled_scene


def thin_bar() -> Scene:
    """A bar 0.05 units wide crossing 1.2 units per shutter: far faster than its own width."""
    scene = walled_scene("thin_bar")
    scene.add(
        mesh.box((0.05, 1.6, 0.05)),
        Material((1.0, 0.9, 0.2)),
        Motion.linear((-0.6, 0, 0.5), (72.0, 0, 0)),
        name="bar",
    )
    return scene


def near_plane() -> Scene:
    """A large triangle sweeping through the near plane during the shutter."""
    scene = walled_scene("near_plane", Camera((0.0, 0.0, 2.0), (0.0, 0.0, 0.0), fov_y=60, near=0.1))
    triangle = mesh.Mesh(
        [[-1.5, -1.0, 0.0], [1.5, -1.0, 0.0], [0.0, 1.2, 0.0]],
        [[0, 0, 1]] * 3,
        [[0, 0], [1, 0], [0.5, 1]],
        [[0, 1, 2]],
        name="triangle",
    )
    scene.add(
        triangle,
        Material((0.9, 0.3, 0.3)),
        Motion.linear((0.3, 0, 0.6), (0, 0, 90.0)),
        name="triangle",
    )
    return scene


def crossing() -> Scene:
    """Two boxes moving in opposite directions, overlapping at mid-shutter."""
    scene = walled_scene("crossing")
    scene.add(
        mesh.box((0.6, 0.6, 0.2)),
        Material((0.2, 0.5, 0.9)),
        Motion.linear((-0.4, 0.1, 0.6), (48.0, 0, 0)),
        name="right_mover",
    )
    scene.add(
        mesh.box((0.6, 0.6, 0.2)),
        Material((0.9, 0.4, 0.2)),
        Motion.linear((0.4, -0.1, 0.3), (-48.0, 0, 0)),
        name="left_mover",
    )
    return scene


def crossed_motions() -> Scene:
    """A bar moving right in front of a bar moving down, crossing at mid-shutter: two
    directions of motion inside the same tiles, which a filter keeping one direction per tile
    blurs along one axis."""
    scene = walled_scene("crossed_motions")
    scene.add(
        mesh.box((0.12, 1.0, 0.1)),
        Material((0.9, 0.3, 0.2)),
        Motion.linear((-0.3, 0, 0.6), (36.0, 0, 0)),
        name="rightward",
    )
    scene.add(
        mesh.box((1.0, 0.12, 0.1)),
        Material((0.2, 0.6, 0.9)),
        Motion.linear((0, 0.3, 0.3), (0, -36.0, 0)),
        name="downward",
    )
    return scene


def long_motion() -> Scene:
    """A sphere moving about a third of the image per shutter: far longer than k = 20 px."""
    scene = walled_scene("long_motion")
    scene.add(
        mesh.sphere(0.3),
        Material((0.3, 0.8, 0.4)),
        Motion.linear((-1.0, 0, 0.4), (120.0, 0, 0)),
        name="sphere",
    )
    return scene


def edge_exit() -> Scene:
    """A box leaving through the right edge of the image during the shutter."""
    scene = walled_scene("edge_exit")
    scene.add(
        mesh.box((0.7, 0.7, 0.2)),
        Material((0.9, 0.8, 0.2)),
        Motion.linear((1.55, 0, 0.4), (60.0, 0, 0)),
        name="box",
    )
    return scene


def subpixel() -> Scene:
    """A textured sphere moving 0.1 to 1 pixel per shutter (at 640 x 360): what 8-bit motion
    storage loses."""
    scene = walled_scene("subpixel")
    scene.add(
        mesh.sphere(0.5),
        Material(texture=checker(256, 16)),
        Motion.linear((0, 0, 0.4), (0.3, 0.0, 0.0), (0, 1, 0), 0.6),
        name="sphere",
    )
    return scene


def camera_yaw() -> Scene:
    """The camera turning fast: screen paths curve, straight motion vectors approximate them."""
    scene = walled_scene("camera_yaw", turning_camera(60, 9.0), wall=30.0)
    scene.add(mesh.box((0.5, 0.5, 0.5)), Material((0.8, 0.3, 0.3)), Motion.static((0, 0, 1.0)))
    return scene


def occluder() -> Scene:
    """A still post in front of a moving box: only the depth test keeps the post sharp."""
    scene = walled_scene("occluder")
    scene.add(
        mesh.box((0.8, 0.8, 0.3)),
        Material((0.3, 0.5, 0.9)),
        Motion.linear((-0.3, 0, 0.0), (40.0, 0, 0)),
        name="mover",
    )
    scene.add(
        mesh.box((0.15, 1.8, 0.15)),
        Material((0.95, 0.95, 0.9)),
        Motion.static((0, 0, 1.2)),
        name="post",
    )
    return scene


def moire() -> Scene:
    """A fine, high-contrast checkerboard in fast rotation (the OGRE paper saw moire here)."""
    scene = flat_scene("moire")
    scene.background = np.array([0.5, 0.5, 0.5, 1.0])
    disc = mesh.cylinder(1.2, 0.02, 96).transformed(rotation_x(math.pi / 2))
    scene.add(
        disc,
        Material(texture=checker(512, 64)),
        Motion.linear(spin_axis=(0, 0, 1), spin_rate=-20.0),
        name="disc",
    )
    return scene


def fast_fan() -> Scene:
    """A fan turning more than one blade width per shutter."""
    scene = fan()
    scene.name = "fast_fan"
    scene.objects[1].motion = Motion.linear(spin_axis=(0, 0, 1), spin_rate=-60.0)
    return scene


def racing_road() -> Scene:
    """A chase camera tracking a fast car down a road: the car stays put on screen while the
    road and the posts beside it stream past, their depth changing over the shutter."""
    speed = 90.0  # units/s: 1.5 units over the 1/60 s shutter
    drive = Motion.linear(velocity=(0.0, 0.0, -speed))
    camera = Camera((0.0, 1.1, 3.2), (0.0, 0.2, -6.0), fov_y=55, motion=drive)
    scene = Scene(camera, name="racing_road", background=(0.5, 0.65, 0.85, 1.0))
    scene.add(
        mesh.plane(8.0, 120.0, uv_repeat=40).transformed(translation(0, -0.25, -50.0)),
        Material(texture=checker(256, 8, 0.2, 0.5)),
        name="road",
    )
    for i in range(30):
        for side in (-1, 1):
            scene.add(
                mesh.box((0.15, 1.2, 0.15)),
                Material((0.85, 0.85, 0.8) if i % 2 else (0.8, 0.2, 0.15)),
                Motion.static((side * 2.6, 0.35, 2.0 - 3.0 * i)),
                name=f"post{i}{'lr'[side > 0]}",
            )
    scene.add(
        mesh.box((1.0, 0.45, 2.0)), Material((0.1, 0.3, 0.8), specular=0.5), drive, name="car"
    )
    return scene


def reverse_near_plane() -> Scene:
    """The camera backing away past posts close beside it: posts in front of the camera at
    the shutter's close were behind its near plane at its open, so their motion vectors have no
    true start."""
    # 1 unit back and 0.15 aside over the 1/60 s shutter, at the origin at its centre.
    back = Motion.linear(velocity=(9.0, 0.0, 60.0))
    camera = Camera((-0.075, 0.0, -0.5), (-0.075, 0.0, -1.5), fov_y=70, near=0.1, motion=back)
    scene = flat_scene("reverse_near_plane", camera)
    wall = mesh.plane(30.0, 30.0, uv_repeat=6).transformed(
        translation(0, 0, -8.0) @ rotation_x(math.pi / 2)
    )
    scene.add(wall, Material(texture=checker(256, 8, 0.2, 0.6)), name="wall")
    for i in range(10):
        for side in (-1, 1):
            scene.add(
                mesh.box((0.1, 0.6, 0.1)),
                Material((0.9, 0.5, 0.2) if (i + (side > 0)) % 2 else (0.2, 0.6, 0.9)),
                Motion.static((side * 0.4, 0.0, -0.4 - 0.7 * i)),
                name=f"post{i}{'lr'[side > 0]}",
            )
    return scene
