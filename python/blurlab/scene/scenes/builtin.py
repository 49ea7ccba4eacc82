"""The five built-in scenes: a teapot passing, a fan, a vehicle, a textured spinner and a
skinned arm."""

from __future__ import annotations

import math

import numpy as np

from .. import mesh
from ..model import Camera, DirectionalLight, Material, Scene
from ..motion import Bone, Motion, Skeleton, quaternion
from .parts import checker, rainbow, rotation_x, translation


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
        mesh.plane(8, 8).transformed(rotation_x(math.pi / 2) @ translation(0, 0, -0.5)),
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
        mesh.plane(200, 12, uv_repeat=50).transformed(translation(0, -0.3, 0)),
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
                mesh.box((2.2, 0.5, 1.0)).transformed(translation(0, 0.25, 0)),
                mesh.box((1.1, 0.45, 0.9)).transformed(translation(-0.2, 0.72, 0)),
            ]
        ),
        Material((0.8, 0.1, 0.1), specular=0.5),
        car,
        name="car",
    )
    wheel = mesh.cylinder(0.3, 0.2).transformed(rotation_x(math.pi / 2))
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
    tube, skeleton = two_bone_arm(30.0)
    scene.add(
        tube,
        Material((0.9, 0.75, 0.55), specular=0.2),
        Motion.static((0.0, 0.0, 0.0)),
        skeleton,
        name="arm",
    )
    return scene


def two_bone_arm(spin_rate: float) -> tuple[mesh.Mesh, Skeleton]:
    """A tube from x = 0 to 2 (radius 0.15) and its two bones: the outer half turns about +z
    at its middle at `spin_rate` rad/s."""
    skeleton = Skeleton(
        [
            Bone(-1, np.eye(4)),
            Bone(
                0, translation(1.0, 0, 0), Motion.linear(spin_axis=(0, 0, 1), spin_rate=spin_rate)
            ),
        ]
    )
    return mesh.tube(2.0, 0.15), skeleton
