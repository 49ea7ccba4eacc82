"""Particles: camera-facing quads, each with its own path, size, colour, alpha, blend mode and
lifetime (docs/spec.md §20.2).

A particle is a scene object whose transform at time t places a unit quad at its position,
turned to face the camera as the camera is at t and scaled to its size. The renderer evaluates
every transform at each instant it draws (shutter open and close, the G-buffer's instant, every
sub-frame of the reference), so the quads face the camera at each of them and their motion
vectors and the reference agree.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from .mesh import Mesh
from .model import Camera, Material, Scene, SceneObject
from .motion import Motion

# Texels across the soft particles' round alpha texture.
SOFT_TEXELS = 32


@dataclass(eq=False)
class Particle:
    """One particle. ``position``: (x, y, z) at t = 0, moving with ``velocity`` (units per
    second), or a function of t giving (x, y, z). ``size``: the quad's side, > 0. ``color``
    (RGB in [0, 1]), ``alpha`` in [0, 1], ``blend`` "blend" | "additive" | "mask" | "opaque" as
    `blurlab.Material` takes them; ``emission_strength`` > 0 makes it glow with its colour
    (sparks). ``lifetime`` = (birth, death) seconds: outside it the quad has no size. ``soft``:
    alpha falls off smoothly from the centre to a round edge (a texture's alpha channel)."""

    position: Sequence[float] | Callable[[float], Sequence[float]]
    velocity: Sequence[float] = (0.0, 0.0, 0.0)
    size: float = 0.1
    color: Sequence[float] = (1.0, 1.0, 1.0)
    alpha: float = 1.0
    blend: str = "blend"
    emission_strength: float = 0.0
    lifetime: tuple[float, float] = (-math.inf, math.inf)
    soft: bool = True

    def __post_init__(self):
        if not callable(self.position):
            self.position = _finite(self.position, "particle position", 3)
        self.velocity = _finite(self.velocity, "particle velocity", 3)
        if isinstance(self.size, bool) or not isinstance(self.size, (int, float)):
            raise TypeError(f"blurlab: particle size must be a number > 0, not {self.size!r}")
        if not (math.isfinite(self.size) and self.size > 0):
            raise ValueError(f"blurlab: particle size must be finite and > 0, not {self.size}")
        birth, death = (float(v) for v in self.lifetime)
        if math.isnan(birth) or math.isnan(death) or not birth <= death:
            raise ValueError(
                f"blurlab: particle lifetime must be (birth, death) with birth <= death, "
                f"not {self.lifetime!r}"
            )
        self.lifetime = (birth, death)
        if not isinstance(self.soft, bool):
            raise TypeError(f"blurlab: particle soft must be True or False, not {self.soft!r}")

    def at(self, t: float) -> np.ndarray:
        """The particle's centre at time t."""
        if callable(self.position):
            return _finite(self.position(t), "particle position(t)", 3)
        return self.position + self.velocity * t

    def material(self) -> Material:
        color = tuple(float(c) for c in _finite(self.color, "particle color", 3))
        glow = self.emission_strength > 0
        return Material(
            color=color,
            texture=soft_texture() if self.soft else None,
            emission=color if glow else (0.0, 0.0, 0.0),
            emission_strength=self.emission_strength,
            alpha=self.alpha,
            blend=self.blend,
        )


@dataclass(eq=False)
class Billboard(Motion):
    """A particle's transform: its quad at its position, facing `camera` as it is at t."""

    particle: Particle
    camera: Camera

    def transform(self, t: float) -> np.ndarray:
        birth, death = self.particle.lifetime
        size = self.particle.size if birth <= t <= death else 0.0
        m = np.eye(4)
        # The camera's right, up and back axes: the quad's x, y and normal.
        m[:3, :3] = self.camera.world(t)[:3, :3] * size
        m[:3, 3] = self.particle.at(t)
        return m


def particles(scene: Scene, particles: Sequence[Particle], name: str = "particle") -> list:
    """Adds each particle to `scene` as a camera-facing quad; returns their SceneObjects."""
    if not isinstance(scene, Scene):
        raise TypeError(f"blurlab: particles need a blurlab Scene, not {type(scene).__name__}")
    added: list[SceneObject] = []
    for i, particle in enumerate(particles):
        if not isinstance(particle, Particle):
            raise TypeError(
                f"blurlab: particles must be blurlab.Particle, not {type(particle).__name__}"
            )
        motion = Billboard(particle, scene.camera)
        added.append(scene.add(quad(), particle.material(), motion, name=f"{name} {i}"))
    return added


def quad() -> Mesh:
    """A unit square in the XY plane, facing +z (the camera's back axis once turned)."""
    positions = [(-0.5, -0.5, 0.0), (0.5, -0.5, 0.0), (0.5, 0.5, 0.0), (-0.5, 0.5, 0.0)]
    uvs = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]
    return Mesh(positions, [(0.0, 0.0, 1.0)] * 4, uvs, [(0, 1, 2), (0, 2, 3)], name="quad")


def soft_texture() -> np.ndarray:
    """White with alpha 1 − r² inside the unit circle, 0 outside (r: distance from the
    centre over the half side), float32 RGBA."""
    centers = (np.arange(SOFT_TEXELS) + 0.5) / SOFT_TEXELS * 2.0 - 1.0
    x, y = np.meshgrid(centers, centers)
    rgba = np.ones((SOFT_TEXELS, SOFT_TEXELS, 4), np.float32)
    rgba[..., 3] = np.clip(1.0 - (x * x + y * y), 0.0, 1.0)
    return rgba


def _finite(value, what: str, size: int) -> np.ndarray:
    v = np.asarray(value, dtype=np.float64)
    if v.shape != (size,) or not np.isfinite(v).all():
        raise ValueError(f"blurlab: {what} must be {size} finite numbers, not {value!r}")
    return v
