"""Benchmark scenes, each built for one measurement (mostly still frames, blur scales)."""

from __future__ import annotations

import math

from .. import mesh
from ..blur_scales import CameraHeld
from ..model import Camera, Material, Scene
from ..motion import Motion, quaternion
from .parts import checker, flat_scene, rainbow, rotation_x, translation, walled_scene


def mostly_still() -> Scene:
    """A still room (checkered wall, a box and a sphere) with one small textured card sliding
    across it: most tiles are still, the card's inside moves uniformly, its edges do not. The
    scene the removed tile classification was measured on (docs/classify_and_steps.md)."""
    scene = walled_scene("mostly_still")
    scene.add(
        mesh.box((0.5, 0.5, 0.5)),
        Material((0.2, 0.4, 0.8)),
        Motion.static((-1.1, -0.4, -0.3), quaternion((0, 1, 0), 0.5)),
        name="box",
    )
    scene.add(
        mesh.sphere(0.3), Material((0.3, 0.7, 0.3)), Motion.static((1.2, 0.5, -0.2)), name="sphere"
    )
    scene.add(
        mesh.box((1.0, 0.7, 0.02)),
        Material(texture=rainbow(256, 8)),
        Motion.linear((-0.1, 0.1, 0.5), (9.0, 0.0, 0.0)),
        name="card",
    )
    return scene


def fps_weapon() -> Scene:
    """A first-person view: the camera turns fast across a room of crates while the weapon it
    carries recoils; the weapon's motion_blur is 0, as engines draw it, so it stays sharp on
    screen while the room blurs (docs/spec.md §12.1)."""
    camera = Camera(
        (0.0, 1.6, 0.0),
        (0.0, 1.5, -5.0),
        fov_y=60,
        motion=Motion.linear(spin_axis=(0, 1, 0), spin_rate=3.0),
    )
    scene = flat_scene("fps_weapon", camera)
    wall = mesh.plane(40, 12, uv_repeat=2).transformed(
        translation(0, 0, -7) @ rotation_x(math.pi / 2)
    )
    scene.add(wall, Material(texture=checker(512, 32, 0.2, 0.6)), name="wall")
    floor = mesh.plane(40, 40, uv_repeat=10)
    scene.add(floor, Material(texture=checker(256, 8, 0.15, 0.35)), name="floor")
    for i, (x, z) in enumerate(((-3.0, -4.0), (-0.6, -5.5), (1.8, -3.5), (3.6, -5.0))):
        scene.add(
            mesh.box((1.0, 1.0, 1.0)),
            Material(texture=checker(64, 4, 0.3, 0.7)),
            Motion.static((x, 0.5, z), quaternion((0, 1, 0), 0.4 * i)),
            name=f"crate{i}",
        )
    gun = mesh.Mesh.merge(
        [
            mesh.box((0.08, 0.12, 0.35)),
            mesh.cylinder(0.02, 0.3).transformed(
                rotation_x(math.pi / 2) @ translation(0, 0.15, 0.03)
            ),
        ]
    )
    recoil = Motion.linear((0.22, -0.2, -0.5), (0.0, 0.4, 0.8), (1, 0, 0), 1.5)
    scene.add(
        gun, Material((0.25, 0.25, 0.28)), CameraHeld(camera, recoil), name="weapon", motion_blur=0
    )
    return scene


def tracked_car() -> Scene:
    """A panning shot: a car drives round a bend at 20 units/s while the camera, standing at
    the bend's centre, turns to keep it in frame; the car is nearly still on screen and the
    road and posts behind it blur."""
    radius, speed = 8.0, 20.0
    turn = Motion.linear(spin_axis=(0, 1, 0), spin_rate=speed / radius)  # about the bend's centre
    camera = Camera((0.0, 0.8, 0.0), (0.0, 0.3, -radius), fov_y=40, motion=turn)
    scene = Scene(camera, name="tracked_car", background=(0.45, 0.6, 0.8, 1.0))
    scene.add(
        mesh.plane(60, 60, uv_repeat=30).transformed(translation(0, -0.3, 0)),
        Material(texture=checker(low=0.25, high=0.45)),
        name="road",
    )
    for i in range(24):
        angle = 2 * math.pi * i / 24
        scene.add(
            mesh.box((0.2, 1.6, 0.2)),
            Material((0.7, 0.7, 0.65)),
            Motion.static((14 * math.sin(angle), 0.5, -14 * math.cos(angle))),
            name=f"post{i}",
        )
    body = mesh.Mesh.merge(
        [
            mesh.box((2.2, 0.5, 1.0)).transformed(translation(0, 0.0, 0)),
            mesh.box((1.1, 0.45, 0.9)).transformed(translation(-0.2, 0.47, 0)),
        ]
    )
    scene.add(
        body.transformed(translation(0, 0, -radius)),
        Material((0.8, 0.1, 0.1), specular=0.5),
        turn,
        name="car",
    )
    return scene
