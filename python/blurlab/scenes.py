"""Built-in scenes. Each is a few lines; motion is in units per second, shutter 1/60 s.

``names()`` lists them, ``get(name)`` builds one; ``get`` and ``gltf`` also load scene files.
"""

from __future__ import annotations

import colorsys
import math
import os
from pathlib import Path

import numpy as np

from . import gltf as gltf_files
from . import mesh
from .blur_scales import CameraHeld
from .motion import Bone, Motion, Skeleton, quaternion
from .particles import Particle
from .particles import particles as add_particles
from .scene import Camera, DirectionalLight, Material, Scene


def checker(size: int = 256, squares: int = 8, low: float = 0.0, high: float = 1.0) -> np.ndarray:
    """(size, size, 3) float32 linear checkerboard between `low` and `high`."""
    y, x = np.mgrid[0:size, 0:size] * squares // size
    value = np.where((x + y) % 2 == 0, high, low)
    return np.repeat(value[..., None], 3, axis=2).astype(np.float32)


def rainbow(size: int = 256, stripes: int = 6) -> np.ndarray:
    """(size, size, 3) float32 vertical stripes through the hues."""
    hues = (np.arange(size) * stripes // size) / stripes
    row = np.array([colorsys.hsv_to_rgb(h, 0.9, 0.9) for h in hues], dtype=np.float32)
    return np.broadcast_to(row, (size, size, 3)).copy()


def teapot_pass() -> Scene:
    """A teapot passing in front of a box and a sphere (the Urho3D thesis's first scene)."""
    scene = Scene(Camera((0.0, 1.2, 5.0), (0.0, 0.5, 0.0), fov_y=45), name="teapot_pass")
    scene.add(
        mesh.plane(12, 12, uv_repeat=6), Material(texture=checker(low=0.3, high=0.6)), name="floor"
    )
    scene.add(
        mesh.box((1.0, 1.0, 1.0)),
        Material((0.2, 0.4, 0.8)),
        Motion.static((-1.2, 0.5, -1.5), quaternion((0, 1, 0), 0.5)),
        name="box",
    )
    scene.add(
        mesh.sphere(0.5),
        Material((0.3, 0.7, 0.3), specular=0.4),
        Motion.static((1.3, 0.5, -1.0)),
        name="sphere",
    )
    scene.add(
        mesh.teapot(),
        Material((0.85, 0.35, 0.2), specular=0.6, shininess=48),
        Motion.linear((-0.2, 0.0, 0.6), (24.0, 0.0, 0.0), (0, 1, 0), 3.0),
        name="teapot",
    )
    return scene


def fan() -> Scene:
    """A four-blade fan turning clockwise as the camera sees it (the thesis's Table 5.1)."""
    scene = Scene(Camera((0.0, 0.0, 3.0), (0.0, 0.0, 0.0), fov_y=45), name="fan")
    scene.light = DirectionalLight((0.3, 0.5, 1.0))
    scene.add(
        mesh.plane(8, 8).transformed(_rotate_x(math.pi / 2) @ _move(0, 0, -0.5)),
        Material(texture=checker(low=0.2, high=0.5)),
        name="wall",
    )
    scene.add(
        mesh.fan(4),
        Material((0.9, 0.85, 0.7), specular=0.3),
        Motion.linear(spin_axis=(0, 0, 1), spin_rate=-18.0),
        name="fan",
    )
    return scene


def vehicle() -> Scene:
    """A car of boxes and cylinders driving along +x with spinning wheels; the camera follows."""
    speed = 20.0
    camera = Camera(
        (0.0, 1.5, 6.0), (0.0, 0.5, 0.0), fov_y=45, motion=Motion.linear(velocity=(speed, 0, 0))
    )
    scene = Scene(camera, name="vehicle", background=(0.45, 0.6, 0.8, 1.0))
    scene.add(
        mesh.plane(200, 12, uv_repeat=50).transformed(_move(0, -0.3, 0)),
        Material(texture=checker(low=0.25, high=0.45)),
        name="road",
    )
    for i in range(-12, 13):
        scene.add(
            mesh.box((0.15, 1.5, 0.15)),
            Material((0.6, 0.6, 0.55)),
            Motion.static((i * 2.5, 0.45, -2.5)),
            name=f"post{i}",
        )
    car = Motion.linear((-0.5, 0.0, 0.0), (speed, 0.0, 0.0))
    scene.add(
        mesh.Mesh.merge(
            [
                mesh.box((2.2, 0.5, 1.0)).transformed(_move(0, 0.25, 0)),
                mesh.box((1.1, 0.45, 0.9)).transformed(_move(-0.2, 0.72, 0)),
            ]
        ),
        Material((0.8, 0.1, 0.1), specular=0.5),
        car,
        name="car",
    )
    wheel = mesh.cylinder(0.3, 0.2).transformed(_rotate_x(math.pi / 2))
    spin = -speed / 0.3  # rolling without slipping
    for x in (-0.7, 0.7):
        for z in (-0.5, 0.5):
            scene.add(
                wheel,
                Material(texture=checker(64, 4, 0.05, 0.4)),
                Motion.linear((x - 0.5, 0.0, z), (speed, 0, 0), (0, 0, 1), spin),
                name="wheel",
            )
    return scene


def textured_spin() -> Scene:
    """The OGRE paper's test matrix: low-, medium-, high-contrast and rainbow textures on
    spheres in slow and fast rotation, the row translating slowly."""
    scene = Scene(Camera((0.0, 0.0, 6.0), (0.0, 0.0, 0.0), fov_y=45), name="textured_spin")
    textures = [checker(low=0.4, high=0.6), checker(low=0.25, high=0.75), checker(), rainbow()]
    for row, rate in ((0.75, 2.0), (-0.75, 12.0)):
        for i, texture in enumerate(textures):
            scene.add(
                mesh.sphere(0.6),
                Material(texture=texture),
                Motion.linear((-2.4 + 1.6 * i, row, 0), (3.0, 0, 0), (0, 1, 0), rate),
                name=f"sphere{i}_{'slow' if rate < 5 else 'fast'}",
            )
    return scene


def skinned_arm() -> Scene:
    """A two-bone tube bending at its middle (skinned: motion vectors from the bones at t0
    and t1)."""
    scene = Scene(Camera((1.0, 0.5, 4.0), (1.0, 0.5, 0.0), fov_y=45), name="skinned_arm")
    skeleton = Skeleton(
        [
            Bone(-1, np.eye(4)),
            Bone(0, _move(1.0, 0, 0), Motion.linear(spin_axis=(0, 0, 1), spin_rate=30.0)),
        ]
    )
    scene.add(
        mesh.tube(2.0, 0.15),
        Material((0.9, 0.75, 0.55), specular=0.2),
        Motion.static((0.0, 0.0, 0.0)),
        skeleton,
        name="arm",
    )
    return scene


# --- failure cases: each isolates one way post-process blur breaks (docs/failure_cases.md) ---


def _flat(name: str, camera: Camera | None = None) -> Scene:
    """A scene lit by ambient light only, so colors are the materials' own."""
    return Scene(
        camera or Camera((0.0, 0.0, 4.0), (0.0, 0.0, 0.0), fov_y=45),
        name=name,
        light=DirectionalLight(color=(0.3, 0.3, 0.3), ambient=(0.7, 0.7, 0.7)),
    )


def _turning(fov_y: float, spin_rate: float) -> Camera:
    """The camera at (0, 0, 4) looking at the origin, turning about +y at `spin_rate` rad/s."""
    return Camera(
        (0.0, 0.0, 4.0),
        (0.0, 0.0, 0.0),
        fov_y=fov_y,
        motion=Motion.linear(spin_axis=(0, 1, 0), spin_rate=spin_rate),
    )


def _wall(scene: Scene, texture=None, z: float = -1.0, size: float = 12.0) -> None:
    wall = mesh.plane(size, size).transformed(_rotate_x(math.pi / 2) @ _move(0, 0, z))
    scene.add(
        wall,
        Material(texture=checker(512, 32, 0.2, 0.6) if texture is None else texture),
        name="wall",
    )


def thin_bar() -> Scene:
    """A bar 0.05 units wide crossing 1.2 units per shutter: far faster than its own width."""
    scene = _flat("thin_bar")
    _wall(scene)
    scene.add(
        mesh.box((0.05, 1.6, 0.05)),
        Material((1.0, 0.9, 0.2)),
        Motion.linear((-0.6, 0, 0.5), (72.0, 0, 0)),
        name="bar",
    )
    return scene


def near_plane() -> Scene:
    """A large triangle sweeping through the near plane during the shutter."""
    scene = _flat("near_plane", Camera((0.0, 0.0, 2.0), (0.0, 0.0, 0.0), fov_y=60, near=0.1))
    _wall(scene)
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
    scene = _flat("crossing")
    _wall(scene)
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


def long_motion() -> Scene:
    """A sphere moving about a third of the image per shutter: far longer than k = 20 px."""
    scene = _flat("long_motion")
    _wall(scene)
    scene.add(
        mesh.sphere(0.3),
        Material((0.3, 0.8, 0.4)),
        Motion.linear((-1.0, 0, 0.4), (120.0, 0, 0)),
        name="sphere",
    )
    return scene


def edge_exit() -> Scene:
    """A box leaving through the right edge of the image during the shutter."""
    scene = _flat("edge_exit")
    _wall(scene)
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
    scene = _flat("subpixel")
    _wall(scene)
    scene.add(
        mesh.sphere(0.5),
        Material(texture=checker(256, 16)),
        Motion.linear((0, 0, 0.4), (0.3, 0.0, 0.0), (0, 1, 0), 0.6),
        name="sphere",
    )
    return scene


def camera_yaw() -> Scene:
    """The camera turning fast: screen paths curve, straight motion vectors approximate them."""
    scene = _flat("camera_yaw", _turning(60, 9.0))
    _wall(scene, size=30.0)
    scene.add(mesh.box((0.5, 0.5, 0.5)), Material((0.8, 0.3, 0.3)), Motion.static((0, 0, 1.0)))
    return scene


def occluder() -> Scene:
    """A still post in front of a moving box: only the depth test keeps the post sharp."""
    scene = _flat("occluder")
    _wall(scene)
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
    scene = _flat("moire")
    scene.background = np.array([0.5, 0.5, 0.5, 1.0])
    disc = mesh.cylinder(1.2, 0.02, 96).transformed(_rotate_x(math.pi / 2))
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


# --- benchmark scenes: built for one measurement each ---------------------------------------


def mostly_still() -> Scene:
    """A still room (checkered wall, a box and a sphere) with one small textured card sliding
    across it: most tiles are still, the card's inside moves uniformly, its edges do not. The
    scene the removed tile classification was measured on (docs/classify_and_steps.md)."""
    scene = _flat("mostly_still")
    _wall(scene)
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
    scene = _flat("fps_weapon", camera)
    wall = mesh.plane(40, 12, uv_repeat=2).transformed(_move(0, 0, -7) @ _rotate_x(math.pi / 2))
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
            mesh.cylinder(0.02, 0.3).transformed(_rotate_x(math.pi / 2) @ _move(0, 0.15, 0.03)),
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
        mesh.plane(60, 60, uv_repeat=30).transformed(_move(0, -0.3, 0)),
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
            mesh.box((2.2, 0.5, 1.0)).transformed(_move(0, 0.0, 0)),
            mesh.box((1.1, 0.45, 0.9)).transformed(_move(-0.2, 0.47, 0)),
        ]
    )
    scene.add(
        body.transformed(_move(0, 0, -radius)),
        Material((0.8, 0.1, 0.1), specular=0.5),
        turn,
        name="car",
    )
    return scene


# --- HDR scenes: emissive lights far brighter than 1, blurred before tone mapping (docs/hdr.md) --


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
        mesh.plane(60, 20, uv_repeat=15).transformed(_move(0, -0.3, 0)),
        Material(texture=checker(low=0.1, high=0.2)),
        name="road",
    )
    scene.add(
        mesh.plane(60, 8).transformed(_move(0, 3.7, -4.0) @ _rotate_x(math.pi / 2)),
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
            mesh.box((2.2, 0.6, 1.0)).transformed(_move(0, 0.15, 0)),
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
        mesh.plane(16, 10).transformed(_move(0, 0, -2.0) @ _rotate_x(math.pi / 2)),
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
    ring = mesh.torus(1.0, 0.02, 96, 8).transformed(_rotate_x(math.pi / 2))
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
        mesh.plane(40, 12).transformed(_move(0, 0, -1.0) @ _rotate_x(math.pi / 2)),
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


# --- transparency: where translucent surfaces break post-process blur (docs/transparency.md) ---


def _before_wall(name: str, camera: Camera | None = None, wall: float = 12.0) -> Scene:
    """A flat-lit scene with the checkered wall behind, for the transparency cases."""
    scene = _flat(name, camera)
    _wall(scene, size=wall)
    return scene


def _facing(position) -> Motion:
    """Turns mesh.plane (normal +y) to face the camera (+z) at `position`."""
    return Motion.static(position, quaternion((1, 0, 0), math.pi / 2))


def streaked_glass(size: int = 64, tint=(0.6, 0.8, 0.9), clear: float = 0.15) -> np.ndarray:
    """(size, size, 4) float32 glass: `tint` at alpha `clear`, with opaque-ish diagonal
    streaks (alpha 0.7) that show where the pane is and how it moves."""
    y, x = np.mgrid[0:size, 0:size]
    rgba = np.empty((size, size, 4), np.float32)
    rgba[..., :3] = tint
    rgba[..., 3] = np.where((x + y) % (size // 4) < size // 16, 0.7, clear)
    return rgba


def leaves(size: int = 64, count: int = 5) -> np.ndarray:
    """(size, size, 4) float32 green leaves: alpha 1 inside `count` x `count` round leaves,
    0 between them (for alpha masking)."""
    centers = (np.arange(size) + 0.5) / size * count
    x, y = np.meshgrid(centers % 1.0 - 0.5, centers % 1.0 - 0.5)
    rgba = np.empty((size, size, 4), np.float32)
    rgba[..., :3] = (0.25, 0.6, 0.2)
    rgba[..., 3] = (x * x * 4 + y * y < 0.16).astype(np.float32)
    return rgba


def car_behind_window() -> Scene:
    """A car driving behind a still, streaked window: the glass takes the car's motion."""
    scene = _before_wall("car_behind_window")
    scene.add(
        mesh.box((1.2, 0.5, 0.4)),
        Material((0.85, 0.15, 0.1)),
        Motion.linear((-0.7, -0.2, 0.3), (60.0, 0, 0)),
        name="car",
    )
    glass = Material(texture=streaked_glass(), blend="blend")
    scene.add(mesh.plane(1.4, 1.0), glass, _facing((0, 0, 1.0)), name="window")
    return scene


def moving_glass() -> Scene:
    """A streaked glass pane sliding over a still wall: the pane writes no motion."""
    scene = _before_wall("moving_glass")
    glass = Material(texture=streaked_glass(tint=(0.9, 0.7, 0.4)), blend="blend")
    scene.add(
        mesh.plane(1.2, 1.2),
        glass,
        Motion.linear(
            (-0.5, 0, 0.8),
            (60.0, 0, 0),
            rotation=quaternion((1, 0, 0), math.pi / 2),
        ),
        name="pane",
    )
    return scene


def sparks_over_mover() -> Scene:
    """Additive sparks flying up over a box moving the other way."""
    scene = _before_wall("sparks_over_mover")
    scene.add(
        mesh.box((0.8, 0.8, 0.3)),
        Material((0.2, 0.4, 0.85)),
        Motion.linear((0.4, 0, 0.1), (-40.0, 0, 0)),
        name="box",
    )
    rng = np.random.default_rng(11)
    sparks = [
        Particle(
            (rng.uniform(-0.8, 0.8), rng.uniform(-0.8, 0.2), rng.uniform(0.5, 0.9)),
            velocity=(rng.uniform(-10, 10), rng.uniform(40, 80), 0.0),
            size=rng.uniform(0.06, 0.12),
            color=(1.0, 0.7, 0.3),
            alpha=0.9,
            blend="additive",
            emission_strength=0.8,
        )
        for _ in range(24)
    ]
    add_particles(scene, sparks, "spark")
    return scene


def smoke_pan() -> Scene:
    """Soft alpha smoke near the camera while the camera pans over a wall and a post."""
    scene = _before_wall("smoke_pan", _turning(45, 4.0), wall=30.0)
    scene.max_layers = 32
    scene.add(mesh.box((0.3, 1.6, 0.3)), Material((0.8, 0.6, 0.2)), Motion.static((0.5, 0, 0)))
    rng = np.random.default_rng(5)
    smoke = [
        Particle(
            (rng.uniform(-1.2, 1.2), rng.uniform(-0.6, 0.6), rng.uniform(1.0, 2.0)),
            velocity=(0.0, 3.0, 0.0),
            size=rng.uniform(0.4, 0.8),
            color=(0.75, 0.75, 0.78),
            alpha=0.45,
        )
        for _ in range(20)
    ]
    add_particles(scene, smoke, "smoke")
    return scene


def foliage_spin() -> Scene:
    """Alpha-masked leaves spinning in front of a wall: cut-out edges, no translucency."""
    scene = _before_wall("foliage_spin")
    foliage = Material(texture=leaves(), blend="mask", alpha_cutoff=0.5)
    spin = Motion.linear(
        (0, 0, 0.5),
        spin_axis=(0, 0, 1),
        spin_rate=12.0,
        rotation=quaternion((1, 0, 0), math.pi / 2),
    )
    scene.add(mesh.plane(1.6, 1.6), foliage, spin, name="leaves")
    return scene


_SCENES = {f.__name__: f for f in (teapot_pass, fan, vehicle, textured_spin, skinned_arm)}
_BENCHMARKS = {f.__name__: f for f in (mostly_still, fps_weapon, tracked_car)}
_HDR = {f.__name__: f for f in (night_street, sparks, spinning_ring, neon_pan)}
_FAILURES = {
    f.__name__: f
    for f in (
        thin_bar,
        near_plane,
        crossing,
        long_motion,
        edge_exit,
        subpixel,
        camera_yaw,
        occluder,
        moire,
        fast_fan,
    )
}


_TRANSPARENCY = {
    f.__name__: f
    for f in (car_behind_window, moving_glass, sparks_over_mover, smoke_pan, foliage_spin)
}


_TAGGED = {
    "failure": _FAILURES,
    "benchmark": _BENCHMARKS,
    "hdr": _HDR,
    "transparency": _TRANSPARENCY,
}
TAGS = tuple(_TAGGED)


def names(tag: str | None = None) -> list[str]:
    """The built-in scenes; `tag="failure"` lists the failure cases instead, `"benchmark"`
    the scenes built for one benchmark, `"hdr"` the scenes lit by emission far above 1,
    `"transparency"` the translucent, additive and masked failure cases (docs/transparency.md)."""
    if tag is None:
        return list(_SCENES)
    if tag not in _TAGGED:
        raise ValueError(f"blurlab: scene tag must be None or one of {TAGS}, not {tag!r}")
    return list(_TAGGED[tag])


def _builder(name: str):
    for registry in (_SCENES, *_TAGGED.values()):
        if name in registry:
            return registry[name]
    everything = names() + [n for tag in TAGS for n in names(tag)]
    raise ValueError(
        f"blurlab: no built-in scene {name!r}; there are {everything}, or give a .gltf/.glb path"
    )


def describe(name: str) -> str:
    """One sentence on what the built-in scene `name` shows (its docstring's first line)."""
    return " ".join(_builder(name).__doc__.split("\n\n")[0].split())


FILE_SUFFIXES = (".gltf", ".glb")


def gltf(
    path,
    animation: int | str | list | None = gltf_files.ALL_ANIMATIONS,
    camera=None,
    size_hint=None,
    shutter=None,
) -> Scene:
    """A scene from a glTF 2.0 file (.gltf or .glb), animated: `blurlab.gltf.load`."""
    return gltf_files.load(path, animation, camera, size_hint, shutter)


def is_file(item) -> bool:
    """Whether `item` names a scene file rather than a built-in scene."""
    return isinstance(item, os.PathLike) or str(item).lower().endswith(FILE_SUFFIXES)


def label(item) -> str:
    """How tables and reports name a scene: a built-in name, or a file's name."""
    return Path(item).name if is_file(item) else str(item)


def get(name) -> Scene:
    """A built-in scene by name, or a scene file (.gltf, .glb) by path."""
    return gltf(name) if is_file(name) else _builder(name)()


def _move(x, y, z) -> np.ndarray:
    m = np.eye(4)
    m[:3, 3] = (x, y, z)
    return m


def _rotate_x(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[1, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1.0]])
