"""Random scenes (docs/spec.md §22): procedural scenes drawn from a seed, so that a claim can be
checked on scenes nobody tuned a method for.

``random(seed, **ranges)`` builds one from NumPy's PCG64 generator (``np.random.default_rng``):
the same seed and ranges give the same scene, bit for bit, on every machine. Each scene has a
textured background wall, objects at several depths (boxes, spheres, cylinders, thin bars,
textured planes, the skinned arm) moving linearly, spinning or along curves, still occluders in
front of them, a camera that may pan, yaw or dolly, and, with the probabilities the ranges set,
HDR emitters and translucent glass or particles. Speeds are drawn in pixels per shutter at
1920x1080 (`REFERENCE_HEIGHT`); at other sizes motion scales with the image.
"""

from __future__ import annotations

import colorsys
import functools
import hashlib
import json
import math
from dataclasses import dataclass

import numpy as np

from .. import mesh
from ..model import Camera, DirectionalLight, Material, Scene
from ..motion import Motion, compose, quaternion
from ..particles import Particle
from ..particles import particles as add_particles
from .builtin import two_bone_arm
from .parts import checker, rotation_x, translation
from .transparency import streaked_glass


@functools.cache
def _checker(size: int, squares: int) -> np.ndarray:
    """(size, size, 1) float32 checkerboard of 0 and 1, shared read-only: a textured scene
    scales it (parts.checker at 512 texels costs more than the rest of a scene)."""
    pattern = checker(size, squares)[..., :1].copy()
    pattern.setflags(write=False)
    return pattern


# Speeds and thin widths are given in pixels of an image this tall (1080p).
REFERENCE_HEIGHT = 1080
# The aspect objects are placed for (16:9); at other aspects a few land off the sides.
PLACEMENT_ASPECT = 16 / 9
SHUTTER = (0.0, 1.0 / 60.0)
# The prefix of a random scene's name: "random:SEED" (docs/spec.md §22.1).
PREFIX = "random:"

MESHES = ("box", "sphere", "cylinder", "thin_bar", "textured_plane", "skinned_arm")
TEXTURES = ("flat", "checker", "noise", "fine")
MOTIONS = ("linear", "spin", "curved")
CAMERA_MOTIONS = ("pan", "yaw", "dolly")


@dataclass(frozen=True)
class Range:
    """One of `random`'s ranges: its default, its kind and what it sets. Kinds: "count" (a
    pair of integers lo <= hi, drawn uniformly), "interval" (a pair of numbers 0 < lo <= hi),
    "probability" (a number in [0, 1]) and "choices" (a non-empty subset of `options`)."""

    default: object
    kind: str
    doc: str
    upper: float = math.inf  # the largest value a count or interval may take
    options: tuple = ()


RANGES = {
    "objects": Range((2, 5), "count", "objects in front of the wall", upper=32),
    "occluders": Range((0, 3), "count", "still posts and slats at their own depths", upper=16),
    "speed_px": Range(
        (0.3, 200.0),
        "interval",
        "pixels a moving thing travels per shutter at 1080p, drawn log-uniformly",
        upper=2000.0,
    ),
    "fov_y": Range((35.0, 65.0), "interval", "the camera's vertical field of view, degrees", 150),
    "camera_motion": Range(0.5, "probability", "chance that the camera moves"),
    "hdr": Range(0.15, "probability", "chance of 1 to 4 emitters of 10 to 3000"),
    "translucency": Range(0.15, "probability", "chance of a glass pane or particles"),
    "meshes": Range(MESHES, "choices", "the meshes objects are drawn from", options=MESHES),
    "textures": Range(
        TEXTURES, "choices", "the textures surfaces are drawn from", options=TEXTURES
    ),
    "motions": Range(MOTIONS, "choices", "how objects move", options=MOTIONS),
    "camera_motions": Range(
        CAMERA_MOTIONS, "choices", "how the camera moves when it moves", options=CAMERA_MOTIONS
    ),
}


def check_ranges(ranges: dict) -> dict:
    """Every range, the given ones validated and the rest at their defaults; raises ValueError
    or TypeError saying which range is wrong and what it takes."""
    unknown = sorted(set(ranges) - set(RANGES))
    if unknown:
        raise ValueError(
            f"blurlab: random scenes have no range {unknown}; there are {list(RANGES)}"
        )
    return {name: _check(name, ranges.get(name, spec.default)) for name, spec in RANGES.items()}


def _check(name: str, value):
    spec = RANGES[name]
    if spec.kind == "probability":
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise TypeError(f"blurlab: random range {name} is a probability, not {value!r}")
        if not (math.isfinite(value) and 0.0 <= value <= 1.0):
            raise ValueError(f"blurlab: random range {name} must be in [0, 1], not {value}")
        return float(value)
    if spec.kind == "choices":
        if isinstance(value, str) or not isinstance(value, (list, tuple)) or not value:
            raise TypeError(
                f"blurlab: random range {name} is a non-empty list of {spec.options}, not {value!r}"
            )
        wrong = [v for v in value if v not in spec.options]
        if wrong:
            raise ValueError(f"blurlab: random range {name} takes {spec.options}, not {wrong}")
        return tuple(dict.fromkeys(value))  # in the order given, each once
    integer = spec.kind == "count"
    numbers = (int,) if integer else (int, float)
    if (
        not isinstance(value, (list, tuple))
        or len(value) != 2
        or any(isinstance(v, bool) or not isinstance(v, numbers) for v in value)
    ):
        what = "integers" if integer else "numbers"
        raise TypeError(f"blurlab: random range {name} is a pair (lo, hi) of {what}, not {value!r}")
    lo, hi = value
    lowest = 0 if integer else 0.0
    if not (math.isfinite(lo) and math.isfinite(hi)) or not (
        (lo >= lowest if integer else lo > lowest) and lo <= hi <= spec.upper
    ):
        bound = "0 <=" if integer else "0 <"
        raise ValueError(
            f"blurlab: random range {name} needs {bound} lo <= hi <= {spec.upper:g}, not {value!r}"
        )
    return (int(lo), int(hi)) if integer else (float(lo), float(hi))


def random_name(seed: int, ranges: dict | None = None) -> str:
    """'random:SEED' for the default ranges, else 'random:SEED:' and a hash of the ranges that
    differ from their defaults: a random scene's name is its identity (docs/spec.md §22.1)."""
    seed = check_seed(seed)
    checked, defaults = check_ranges(ranges or {}), check_ranges({})
    changed = {k: v for k, v in checked.items() if v != defaults[k]}
    if not changed:
        return f"{PREFIX}{seed}"
    text = json.dumps(changed, sort_keys=True)
    return f"{PREFIX}{seed}:{hashlib.sha256(text.encode()).hexdigest()[:8]}"


def parse_name(name: str) -> int | None:
    """The seed of the name 'random:SEED', None for any other name."""
    if not isinstance(name, str) or not name.startswith(PREFIX):
        return None
    digits = name[len(PREFIX) :]
    if not digits.isdigit():
        raise ValueError(
            f"blurlab: a random scene is named 'random:SEED' with SEED an integer >= 0, not "
            f"{name!r}; one of other ranges is made by bl.scenes.random(seed, **ranges)"
        )
    return int(digits)


def check_seed(seed) -> int:
    """`seed` as an int, or a ValueError saying what a seed may be."""
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or not 0 <= seed < 2**63:
        raise ValueError(f"blurlab: a random scene's seed is an integer in [0, 2^63), not {seed!r}")
    return int(seed)


def random(seed: int, **ranges) -> Scene:
    """A procedural scene drawn from `seed` within `ranges` (see `RANGES`; docs/spec.md §22)."""
    seed = check_seed(seed)
    checked = check_ranges(ranges)
    return _Builder(np.random.default_rng(seed), checked, random_name(seed, ranges)).scene


class _Builder:
    """Draws one scene. The order of draws is part of what a seed means: change it and every
    seed names another scene."""

    def __init__(self, rng: np.random.Generator, ranges: dict, name: str):
        self.rng, self.ranges = rng, ranges
        self.fov = float(rng.uniform(*ranges["fov_y"]))
        self.tan = math.tan(math.radians(self.fov) / 2)
        self.shutter = SHUTTER[1] - SHUTTER[0]
        self.centre = 0.5 * (SHUTTER[0] + SHUTTER[1])
        self.wall_depth = float(rng.uniform(8.0, 14.0))
        light = DirectionalLight(
            direction=(rng.uniform(-0.6, 0.6), 1.0, rng.uniform(0.2, 1.0)),
            color=(0.6, 0.6, 0.6),
            ambient=(0.4, 0.4, 0.42),
        )
        camera = Camera((0.0, 0.0, 0.0), (0.0, 0.0, -1.0), fov_y=self.fov, near=0.1, far=100.0)
        self.scene = Scene(camera, light, background=(0.05, 0.05, 0.07, 1.0), name=name)
        self.scene.shutter = SHUTTER
        self.camera_motion()
        self.wall()
        for _ in range(self.count("objects")):
            self.object()
        for _ in range(self.count("occluders")):
            self.occluder()
        if rng.random() < ranges["hdr"]:
            for _ in range(int(rng.integers(1, 5))):
                self.emitter()
        if rng.random() < ranges["translucency"]:
            self.translucent()

    # --- draws -------------------------------------------------------------------------------

    def count(self, name: str) -> int:
        lo, hi = self.ranges[name]
        return int(self.rng.integers(lo, hi + 1))

    def speed_px(self) -> float:
        lo, hi = self.ranges["speed_px"]
        return float(math.exp(self.rng.uniform(math.log(lo), math.log(hi))))

    def choice(self, name: str) -> str:
        options = self.ranges[name]
        return options[int(self.rng.integers(len(options)))]

    def unit_per_px(self, depth: float) -> float:
        """World units per pixel of a 1080p image at `depth` along the view axis."""
        return 2.0 * depth * self.tan / REFERENCE_HEIGHT

    def velocity(self, pixels: float, depth: float) -> np.ndarray:
        """Units per second that cross `pixels` per shutter at `depth`, in a random direction
        mostly across the view."""
        angle = self.rng.uniform(0.0, 2.0 * math.pi)
        direction = np.array([math.cos(angle), math.sin(angle), self.rng.uniform(-0.3, 0.3)])
        direction /= np.linalg.norm(direction[:2])
        return direction * pixels * self.unit_per_px(depth) / self.shutter

    def place(self, depth: float, spread: float = 0.75) -> np.ndarray:
        """A point at `depth` whose image lies within `spread` of the frame's half extents."""
        x = self.rng.uniform(-spread, spread) * depth * self.tan * PLACEMENT_ASPECT
        y = self.rng.uniform(-spread, spread) * depth * self.tan
        return np.array([x, y, -depth])

    def orientation(self) -> np.ndarray:
        axis = self.rng.normal(size=3)
        return quaternion(
            axis if np.linalg.norm(axis) > 1e-9 else (0, 1, 0), self.rng.uniform(0, 6.3)
        )

    def colour(self) -> tuple:
        h, s, v = self.rng.uniform(0, 1), self.rng.uniform(0.2, 0.9), self.rng.uniform(0.4, 0.95)
        return colorsys.hsv_to_rgb(h, s, v)

    def texture(self, kind: str | None = None) -> np.ndarray | None:
        """None (flat), or a (S, S, 1) float32 grey texture of the drawn kind."""
        kind = kind or self.choice("textures")
        low, high = (np.float32(v) for v in sorted(self.rng.uniform(0.05, 0.95, size=2)))
        if kind == "flat":
            return None
        if kind == "checker":
            return low + (high - low) * _checker(256, int(self.rng.choice([4, 8, 16])))
        if kind == "fine":  # a texel or two per square: aliases unless filtered
            return low + (high - low) * _checker(512, int(self.rng.choice([128, 256])))
        cells = int(self.rng.choice([4, 8, 16]))  # value noise: a coarse grid, bilinear
        grid = self.rng.uniform(low, high, size=(cells + 1, cells + 1))
        t = np.linspace(0, cells, 256, endpoint=False)
        i, f = t.astype(int), t - t.astype(int)
        rows = grid[i] * (1 - f)[:, None] + grid[i + 1] * f[:, None]
        value = rows[:, i] * (1 - f) + rows[:, i + 1] * f
        return value[..., None].astype(np.float32)

    def material(self, kind: str | None = None) -> Material:
        texture = self.texture(kind)
        tint = self.colour()  # the colour, or what the texture multiplies
        specular = float(self.rng.choice([0.0, 0.0, 0.3, 0.6]))
        return Material(tint, texture, specular=specular)

    # --- parts -------------------------------------------------------------------------------

    def camera_motion(self) -> None:
        rng = self.rng
        if not rng.random() < self.ranges["camera_motion"]:
            return
        kind = self.choice("camera_motions")
        pixels = self.speed_px()
        reference_depth = 4.0  # the depth at which a pan moves the image `pixels`
        if kind == "pan":
            velocity = self.velocity(pixels, reference_depth)
            velocity[2] = 0.0
            motion = Motion.linear(-velocity * self.centre, velocity)
        elif kind == "yaw":
            angle = pixels * math.radians(self.fov) / REFERENCE_HEIGHT
            rate = angle / self.shutter * rng.choice([-1.0, 1.0])
            axis = (rng.uniform(-0.2, 0.2), 1.0, 0.0)  # near-vertical, through the camera
            motion = Motion.linear(
                spin_axis=axis,
                spin_rate=float(rate),
                rotation=quaternion(axis, -rate * self.centre),  # facing -z at the centre
            )
        else:  # dolly: the frame's top edge at the reference depth moves `pixels`
            travel = min(pixels * reference_depth / (REFERENCE_HEIGHT / 2), 1.0)
            velocity = np.array([0.0, 0.0, travel * rng.choice([-1.0, 1.0]) / self.shutter])
            motion = Motion.linear(-velocity * self.centre, velocity)
        self.scene.camera.motion = motion

    def wall(self) -> None:
        """The background: a plane facing the camera, wide enough for every camera motion."""
        d = self.wall_depth
        height = 2.0 * d * self.tan * 2.5
        width = height * PLACEMENT_ASPECT * 1.5
        texture = self.texture()
        repeat = 1.0 if texture is None else float(self.rng.choice([2.0, 4.0]))
        plane = mesh.plane(width, height, uv_repeat=repeat)
        plane = plane.transformed(translation(0, 0, -d) @ rotation_x(math.pi / 2))
        self.scene.add(plane, Material(self.colour(), texture), name="wall")

    def object(self) -> None:
        rng = self.rng
        kind = self.choice("meshes")
        depth = float(rng.uniform(2.5, self.wall_depth - 1.5))
        size = float(math.exp(rng.uniform(math.log(0.06), math.log(0.4))))  # of frame height
        extent = size * 2.0 * depth * self.tan  # world units
        position = self.place(depth)
        pixels = self.speed_px()
        skeleton = None
        material = self.material("checker" if kind == "textured_plane" else None)
        if kind == "box":
            shape = mesh.box(tuple(extent * rng.uniform(0.5, 1.5, size=3)))
        elif kind == "sphere":
            shape = mesh.sphere(extent / 2)
        elif kind == "cylinder":
            shape = mesh.cylinder(extent / 2, extent * rng.uniform(0.5, 2.0))
        elif kind == "thin_bar":
            width = rng.uniform(1.0, 4.0) * self.unit_per_px(depth)
            shape = mesh.box((width, extent * 2.0, width))
        elif kind == "textured_plane":
            material = self.material(self.choice_textured())
            shape = mesh.plane(extent * 1.5, extent).transformed(rotation_x(math.pi / 2))
        else:  # skinned_arm: its outer half swings `pixels` at the tip; the arm itself is still
            reach = extent / 2.0  # mesh units to world: the tube is 2 long, 1 per bone
            rate = pixels * self.unit_per_px(depth) / (reach * self.shutter)
            shape, skeleton = two_bone_arm(float(rate * rng.choice([-1.0, 1.0])))
            rotation = quaternion((0, 0, 1), rng.uniform(0, 6.3))
            motion = Motion.static(position, rotation, scale=reach)
            self.scene.add(
                shape, material, motion, skeleton, name=f"{kind}{len(self.scene.objects)}"
            )
            return
        shape, motion = self.object_motion(shape, position, depth, extent, pixels)
        self.scene.add(shape, material, motion, name=f"{kind}{len(self.scene.objects)}")

    def choice_textured(self) -> str:
        """A texture kind other than flat, where the ranges allow one."""
        textured = [t for t in self.ranges["textures"] if t != "flat"] or ["checker"]
        return textured[int(self.rng.integers(len(textured)))]

    def object_motion(self, shape, position, depth, extent, pixels):
        """(shape, motion): the drawn motion, and the shape moved off its pivot where the motion
        is a curved path around that pivot."""
        rng = self.rng
        kind = self.choice("motions")
        rotation = self.orientation()
        if kind == "linear":
            velocity = self.velocity(pixels, depth)
            return shape, Motion.linear(
                position - velocity * self.centre, velocity, rotation=rotation
            )
        if kind == "spin":  # its rim moves `pixels`
            rate = pixels * self.unit_per_px(depth) / (extent / 2 * self.shutter)
            axis = rng.normal(size=3)
            return shape, Motion.linear(position, spin_axis=axis, spin_rate=rate, rotation=rotation)
        # curved: around a pivot `radius` away, the path's arc `pixels` long
        radius = extent * rng.uniform(0.5, 1.5)
        rate = pixels * self.unit_per_px(depth) / (radius * self.shutter) * rng.choice([-1, 1])
        axis = (rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3), 1.0)
        offset = shape.transformed(translation(radius, 0, 0) @ compose(rotation=rotation))
        start = quaternion(axis, rng.uniform(0, 6.3) - rate * self.centre)
        return offset, Motion.linear(position, spin_axis=axis, spin_rate=rate, rotation=start)

    def occluder(self) -> None:
        """A still post or slat at its own depth, in front of most of the scene."""
        rng = self.rng
        depth = float(rng.uniform(1.2, self.wall_depth - 2.0))
        width = rng.uniform(0.01, 0.08) * 2.0 * depth * self.tan
        length = 2.0 * depth * self.tan * 1.2
        size = (width, length, width) if rng.random() < 0.6 else (length, width, width)
        position = self.place(depth, spread=0.6)
        self.scene.add(
            mesh.box(size),
            self.material(),
            Motion.static(position),
            name=f"occluder{len(self.scene.objects)}",
        )

    def emitter(self) -> None:
        """A small glowing sphere or bar of strength 10 to 3000, moving."""
        rng = self.rng
        depth = float(rng.uniform(2.0, self.wall_depth - 1.0))
        extent = rng.uniform(0.005, 0.02) * 2.0 * depth * self.tan
        if rng.random() < 0.5:
            shape = mesh.sphere(extent, 12, 6)
        else:
            shape = mesh.box((extent * 8, extent, extent))
        warm = colorsys.hsv_to_rgb(rng.uniform(0.0, 0.6), rng.uniform(0.2, 0.9), 1.0)
        strength = float(10.0 ** rng.uniform(1.0, math.log10(3000.0)))
        glow = Material((0.0, 0.0, 0.0), emission=warm, emission_strength=strength)
        position = self.place(depth)
        velocity = self.velocity(self.speed_px(), depth)
        motion = Motion.linear(
            position - velocity * self.centre, velocity, rotation=self.orientation()
        )
        self.scene.add(shape, glow, motion, name="emitter")

    def translucent(self) -> None:
        """A streaked glass pane, still or moving, or 4 to 12 soft particles drifting."""
        rng = self.rng
        depth = float(rng.uniform(1.5, 5.0))
        if rng.random() < 0.5:
            extent = rng.uniform(0.3, 0.7) * 2.0 * depth * self.tan
            pane = mesh.plane(extent * 1.4, extent).transformed(rotation_x(math.pi / 2))
            tint = tuple(float(c) for c in rng.uniform(0.4, 1.0, size=3))
            glass = Material(texture=streaked_glass(tint=tint), blend="blend")
            velocity = self.velocity(self.speed_px(), depth) * float(rng.random() < 0.5)
            motion = Motion.linear(self.place(depth, 0.4) - velocity * self.centre, velocity)
            self.scene.add(pane, glass, motion, name="glass")
            return
        additive = bool(rng.random() < 0.3)
        chosen = []
        for _ in range(int(rng.integers(4, 13))):
            d = float(rng.uniform(1.5, 5.0))
            velocity = self.velocity(self.speed_px(), d)
            chosen.append(
                Particle(
                    tuple(self.place(d, 0.6) - velocity * self.centre),
                    velocity=tuple(velocity),
                    size=float(rng.uniform(0.05, 0.2) * 2.0 * d * self.tan),
                    color=self.colour(),
                    alpha=float(rng.uniform(0.3, 0.8)),
                    blend="additive" if additive else "blend",
                )
            )
        add_particles(self.scene, chosen, "particle")
