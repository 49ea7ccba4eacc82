"""What the built-in scenes share: procedural textures, the flat test scene with its wall and
turning camera, and the matrices they place objects with."""

from __future__ import annotations

import colorsys
import math

import numpy as np

from .. import mesh
from ..model import Camera, DirectionalLight, Material, Scene
from ..motion import Motion


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


def flat_scene(name: str, camera: Camera | None = None) -> Scene:
    """A scene lit by ambient light only, so colors are the materials' own."""
    return Scene(
        camera or Camera((0.0, 0.0, 4.0), (0.0, 0.0, 0.0), fov_y=45),
        name=name,
        light=DirectionalLight(color=(0.3, 0.3, 0.3), ambient=(0.7, 0.7, 0.7)),
    )


def turning_camera(fov_y: float, spin_rate: float) -> Camera:
    """The camera at (0, 0, 4) looking at the origin, turning about +y at `spin_rate` rad/s."""
    return Camera(
        (0.0, 0.0, 4.0),
        (0.0, 0.0, 0.0),
        fov_y=fov_y,
        motion=Motion.linear(spin_axis=(0, 1, 0), spin_rate=spin_rate),
    )


def add_wall(scene: Scene, texture=None, z: float = -1.0, size: float = 12.0) -> None:
    wall = mesh.plane(size, size).transformed(rotation_x(math.pi / 2) @ translation(0, 0, z))
    scene.add(
        wall,
        Material(texture=checker(512, 32, 0.2, 0.6) if texture is None else texture),
        name="wall",
    )


def walled_scene(name: str, camera: Camera | None = None, wall: float = 12.0) -> Scene:
    """flat_scene `name` with add_wall's checkered wall, `wall` units wide, behind."""
    scene = flat_scene(name, camera)
    add_wall(scene, size=wall)
    return scene


def translation(x, y, z) -> np.ndarray:
    m = np.eye(4)
    m[:3, 3] = (x, y, z)
    return m


def rotation_x(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[1, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1.0]])
