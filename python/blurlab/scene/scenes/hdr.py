"""HDR scenes: emissive lights far brighter than 1, blurred before tone mapping (docs/hdr.md)."""

from __future__ import annotations

import colorsys
import math

import numpy as np

from .. import mesh
from ..model import Camera, DirectionalLight, Material, Scene
from ..motion import Motion, quaternion
from .parts import checker, rotation_x, translation


def _night(name: str, camera: Camera) -> Scene:
    """A dark scene under a dim moonlight, so that emission carries the image."""
    return Scene(
        camera,
        name=name,
        light=DirectionalLight((0.3, 1.0, 0.5), (0.05, 0.05, 0.07), (0.02, 0.02, 0.03)),
        background=(0.004, 0.005, 0.012, 1.0),
    )


def _glowing(color, strength: float) -> Material:
    """A black surface that only emits: a lamp, a sign's tube, a spark."""
    return Material((0.0, 0.0, 0.0), emission=color, emission_strength=strength)


def night_street() -> Scene:
    """Headlights and tail lights passing a still camera at night along a street with neon
    signs: cars at 30 and 22 units/s, lamps of 2000 (head) and 400 (tail), signs of 30."""
    scene = _night("night_street", Camera((0.0, 1.2, 7.0), (0.0, 0.9, 0.0), fov_y=45))
    scene.add(
        mesh.plane(60, 20, uv_repeat=15).transformed(translation(0, -0.3, 0)),
        Material(texture=checker(low=0.1, high=0.2)),
        name="road",
    )
    scene.add(
        mesh.plane(60, 8).transformed(translation(0, 3.7, -4.0) @ rotation_x(math.pi / 2)),
        Material((0.25, 0.22, 0.2)),
        name="facade",
    )
    for i, (x, y, color) in enumerate(
        ((-3.5, 2.4, (1.0, 0.15, 0.6)), (-0.5, 2.8, (0.1, 0.9, 1.0)), (2.8, 2.2, (1.0, 0.6, 0.1)))
    ):
        scene.add(
            mesh.box((1.6, 0.12, 0.05)),
            _glowing(color, 30.0),
            Motion.static((x, y, -3.9)),
            name=f"sign{i}",
        )
    for x0, speed, z in ((-3.0, 30.0, 1.2), (2.5, -22.0, -1.2)):
        ahead = math.copysign(1.0, speed)  # +1: the car drives along +x
        car = Motion.linear((x0, 0.0, z), (speed, 0.0, 0.0))
        scene.add(
            mesh.box((2.2, 0.6, 1.0)).transformed(translation(0, 0.15, 0)),
            Material((0.08, 0.09, 0.1), specular=0.5),
            car,
            name="car",
        )
        for side in (-0.35, 0.35):
            for end, color, strength in (
                (1.0, (1.0, 0.95, 0.85), 2000.0),  # headlight
                (-1.0, (1.0, 0.05, 0.02), 400.0),  # tail light
            ):
                scene.add(
                    mesh.sphere(0.07, 12, 6),
                    _glowing(color, strength),
                    Motion.linear((x0 + ahead * end * 1.12, 0.2, z + side), (speed, 0.0, 0.0)),
                    name="headlight" if end > 0 else "tail_light",
                )
    return scene


def sparks() -> Scene:
    """Sixty small sparks of 500 to 10^4 flying from one point at 10 to 60 units/s in every
    direction, over a dark wall."""
    scene = _night("sparks", Camera((0.0, 0.0, 5.0), (0.0, 0.0, 0.0), fov_y=45))
    scene.add(
        mesh.plane(16, 10).transformed(translation(0, 0, -2.0) @ rotation_x(math.pi / 2)),
        Material(texture=checker(256, 16, 0.15, 0.3)),
        name="wall",
    )
    rng = np.random.default_rng(24)  # fixed: the scene is the same every time
    spark = mesh.sphere(0.025, 8, 4)
    for i in range(60):
        direction = rng.normal(size=3)
        direction /= np.linalg.norm(direction)
        speed = rng.uniform(10.0, 60.0)
        t = rng.uniform(0.01, 0.04)  # how long it has flown at the shutter's open
        color = (1.0, rng.uniform(0.45, 0.8), rng.uniform(0.05, 0.2))
        scene.add(
            spark,
            _glowing(color, float(10.0 ** rng.uniform(math.log10(500.0), 4.0))),
            Motion.linear(direction * speed * t, direction * speed),
            name=f"spark{i}",
        )
    return scene


def spinning_ring() -> Scene:
    """A thin ring of 300 turning about a vertical axis at 25 rad/s over a dark background,
    with a dim lamp of 8 at its centre that stays still."""
    scene = _night("spinning_ring", Camera((0.0, 0.0, 4.0), (0.0, 0.0, 0.0), fov_y=45))
    ring = mesh.torus(1.0, 0.02, 96, 8).transformed(rotation_x(math.pi / 2))
    scene.add(
        ring,
        _glowing((0.6, 0.8, 1.0), 300.0),
        Motion.linear(spin_axis=(0, 1, 0), spin_rate=25.0, rotation=quaternion((0, 1, 0), 0.3)),
        name="ring",
    )
    scene.add(mesh.sphere(0.1, 16, 8), _glowing((1.0, 0.9, 0.7), 8.0), name="lamp")
    return scene


def neon_pan() -> Scene:
    """The camera sweeping fast across a row of street lamps of 1000 and neon tubes of 50 on a
    dark facade, turning at 6 rad/s about a vertical axis 5 units ahead of it: every light
    streaks with the camera's motion."""
    camera = Camera(
        (0.0, 1.0, 5.0),
        (0.0, 1.0, 0.0),
        fov_y=50,
        motion=Motion.linear(spin_axis=(0, 1, 0), spin_rate=6.0),
    )
    scene = _night("neon_pan", camera)
    scene.add(
        mesh.plane(40, 12).transformed(translation(0, 0, -1.0) @ rotation_x(math.pi / 2)),
        Material(texture=checker(512, 32, 0.08, 0.18)),
        name="facade",
    )
    for i in range(-4, 5):
        scene.add(
            mesh.sphere(0.08, 12, 6),
            _glowing((1.0, 0.85, 0.6), 1000.0),
            Motion.static((1.6 * i, 2.2, -0.6)),
            name=f"lamp{i + 4}",
        )
        hue = colorsys.hsv_to_rgb((i + 4) / 9, 0.85, 1.0)
        scene.add(
            mesh.box((0.05, 0.9, 0.05)),
            _glowing(hue, 50.0),
            Motion.static((1.6 * i + 0.8, 0.6, -0.8)),
            name=f"tube{i + 4}",
        )
    return scene
