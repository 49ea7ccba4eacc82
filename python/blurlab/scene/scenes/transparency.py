"""Transparency scenes: where translucent surfaces break post-process blur
(docs/transparency.md)."""

from __future__ import annotations

import math

import numpy as np

from .. import mesh
from ..model import Material, Scene
from ..motion import Motion, quaternion
from ..particles import Particle
from ..particles import particles as add_particles
from .parts import turning_camera, walled_scene


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
    scene = walled_scene("car_behind_window")
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
    scene = walled_scene("moving_glass")
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
    scene = walled_scene("sparks_over_mover")
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
    scene = walled_scene("smoke_pan", turning_camera(45, 4.0), wall=30.0)
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
    scene = walled_scene("foliage_spin")
    foliage = Material(texture=leaves(), blend="mask", alpha_cutoff=0.5)
    spin = Motion.linear(
        (0, 0, 0.5),
        spin_axis=(0, 0, 1),
        spin_rate=12.0,
        rotation=quaternion((1, 0, 0), math.pi / 2),
    )
    scene.add(mesh.plane(1.6, 1.6), foliage, spin, name="leaves")
    return scene
