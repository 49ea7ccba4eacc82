"""The cross-check of docs/crosscheck.md: three scenes of its own (a box, an occluder in front
of a still object, a sphere under a moving camera) and the measurements that compare a blurlab
image with a Blender one: object masks, coverage centroids, PSNR by region. Used by
the crosscheck benchmark (`blurlab bench crosscheck`) and notebooks/05_crosscheck.ipynb."""

from __future__ import annotations

import numpy as np

from ..scene import mesh
from ..scene.model import Camera, DirectionalLight, Material, Scene
from ..scene.motion import Motion, quaternion
from ..scene.particles import Particle, particles

UNLIT = DirectionalLight(color=(0, 0, 0), ambient=(1, 1, 1))
STILL = 1e-3  # |temporal reference - sharp render| above this: touched by motion blur


def box_scene() -> Scene:
    """A box translating and spinning in front of a still backdrop; still camera."""
    camera = Camera((0.0, 0.3, 5.0), (0, 0, 0), fov_y=40)
    scene = Scene(camera, UNLIT, background=(0.05, 0.05, 0.1, 1), shutter=(0, 0.5), name="box")
    scene.add(mesh.plane(3.0, 1.6), Material((0.3, 0.5, 0.8)), backdrop((0, -0.1, -1.0)))
    spin = Motion.linear((-1.0, 0, 0), (2.4, 0, 0), spin_axis=(0.3, 1, 0.2), spin_rate=3.0)
    scene.add(mesh.box((0.8, 0.8, 0.8)), Material((0.9, 0.6, 0.2)), spin, name="box")
    return scene


def occluder_scene() -> Scene:
    """A bar sliding in front of a still disc-like cylinder: an occluder over a still object."""
    camera = Camera((0, 0, 6.0), (0, 0, 0), fov_y=35)
    scene = Scene(camera, UNLIT, background=(0.1, 0.1, 0.1, 1), shutter=(0, 0.5), name="occluder")
    standing = Motion.static((0.2, 0, -0.5), rotation=quaternion((1, 0, 0), np.pi / 2))
    scene.add(mesh.cylinder(0.9, 0.2), Material((0.2, 0.8, 0.3)), standing, name="disc")
    bar = Motion.linear((-1.2, 0, 0.8), (3.0, 0, 0))
    scene.add(mesh.box((0.3, 2.2, 0.3)), Material((0.9, 0.9, 0.9)), bar, name="bar")
    return scene


def sphere_camera_scene() -> Scene:
    """A Lambert sphere on a floor, lit by the directional light; the camera pans and turns."""
    pan = Motion.linear(velocity=(0.8, 0, 0), spin_axis=(0, 1, 0), spin_rate=0.4)
    camera = Camera((0, 0.6, 4.0), (0, 0, 0), fov_y=45, motion=pan)
    light = DirectionalLight((0.4, 1.0, 0.6), (0.8, 0.8, 0.8), (0.2, 0.2, 0.2))
    scene = Scene(
        camera, light, background=(0.1, 0.1, 0.2, 1), shutter=(0, 0.5), name="sphere_camera"
    )
    scene.add(mesh.sphere(0.7), Material((0.9, 0.5, 0.2)), name="sphere")
    scene.add(mesh.box((4, 0.2, 3)), Material((0.3, 0.7, 0.4)), Motion.static((0, -0.8, 0)))
    return scene


def backdrop(position):
    """A still plane facing +z (mesh.plane lies in xz, facing +y)."""
    return Motion.static(position, rotation=quaternion((1, 0, 0), np.pi / 2))


def glass_scene() -> Scene:
    """A tinted pane (blend) and a small additive square crossing over a still backdrop:
    translucency as Cycles' transparent-BSDF mixes draw it (docs/spec.md §20.1)."""
    camera = Camera((0.0, 0.0, 5.0), (0, 0, 0), fov_y=40)
    scene = Scene(camera, UNLIT, background=(0.05, 0.05, 0.1, 1), shutter=(0, 0.5), name="glass")
    scene.add(mesh.plane(3.0, 1.6), Material((0.3, 0.5, 0.8)), backdrop((0, -0.1, -1.0)))
    pane = Material((0.9, 0.6, 0.2), alpha=0.4, blend="blend")
    scene.add(mesh.plane(0.8, 0.8), pane, facing_motion((-0.8, 0, 0), (2.4, 0, 0)), name="pane")
    glow = Material((0.2, 0.9, 0.3), alpha=0.6, blend="additive")
    scene.add(mesh.plane(0.3, 0.3), glow, facing_motion((0.6, -0.3, 0.5), (-1.5, 1.0, 0)))
    return scene


def particles_scene() -> Scene:
    """Soft round particles (alpha from a texture), blended and additive, drifting over a still
    backdrop."""
    camera = Camera((0.0, 0.0, 5.0), (0, 0, 0), fov_y=40)
    scene = Scene(camera, UNLIT, background=(0.05, 0.05, 0.1, 1), shutter=(0, 0.5), name="puffs")
    scene.add(mesh.plane(3.0, 1.6), Material((0.6, 0.3, 0.3)), backdrop((0, -0.1, -1.0)))
    puffs = [
        Particle(
            (-0.9 + 0.45 * i, 0.1 * (i % 3) - 0.1, 0.2 * i),
            velocity=(0.8, 0.4, 0),
            size=0.7,
            color=(0.8, 0.8, 0.85),
            alpha=0.5,
            blend="additive" if i % 2 else "blend",
        )
        for i in range(5)
    ]
    particles(scene, puffs, "puff")
    return scene


def facing_motion(start, velocity) -> Motion:
    """A plane (mesh.plane lies in xz) turned to face +z, moving linearly."""
    return Motion.linear(start, velocity, rotation=quaternion((1, 0, 0), np.pi / 2))


SCENES = {"box": box_scene, "occluder": occluder_scene, "sphere_camera": sphere_camera_scene}
# Translucent scenes whose Cycles ground truth the transparency_cycles benchmark compares.
TRANSLUCENT_SCENES = {"glass": glass_scene, "puffs": particles_scene}
TRACKED = {"box": "box", "occluder": "bar", "sphere_camera": "sphere"}


def mask_scene(scene: Scene, name: str) -> Scene:
    """The same geometry, unlit: object `name` white, the rest black (still occluding)."""
    masked = Scene(scene.camera, UNLIT, (0, 0, 0, 1), scene.shutter, scene.name + "_mask")
    for obj in scene.objects:
        white = obj.name == name
        masked.add(obj.mesh, Material((1, 1, 1) if white else (0, 0, 0)), obj.motion)
    return masked


def coverage_stats(coverage: np.ndarray) -> dict:
    y, x = np.indices(coverage.shape)
    area = float(coverage.sum())
    return {
        "area": area,
        "centroid": [float((coverage * x).sum() / area), float((coverage * y).sum() / area)],
    }


def psnr_in(a, b, where) -> float:
    mse = float(np.mean((a[..., :3][where] - b[..., :3][where]) ** 2))
    return float("inf") if mse == 0 else 10 * np.log10(1.0 / mse)


def dilate(mask: np.ndarray, radius: int) -> np.ndarray:
    out = mask.copy()
    padded = np.pad(mask, radius)
    h, w = mask.shape
    for dy in range(2 * radius + 1):
        for dx in range(2 * radius + 1):
            out |= padded[dy : dy + h, dx : dx + w]
    return out


def iou(a: np.ndarray, b: np.ndarray) -> float:
    """Intersection over union of the pixels more than half covered in each."""
    return float(((a > 0.5) & (b > 0.5)).sum() / ((a > 0.5) | (b > 0.5)).sum())


def regions(ctx, scene, size, temporal) -> dict:
    """Pixel regions: still edges (within 2 px of an object boundary, untouched by blur),
    moving (touched by blur, widened by 2 px), flat (the rest)."""
    sharp = ctx.render(scene, size)
    ids = sharp.object_id
    boundary = np.zeros(ids.shape, bool)
    boundary[:, 1:] |= ids[:, 1:] != ids[:, :-1]
    boundary[:, :-1] |= ids[:, 1:] != ids[:, :-1]
    boundary[1:] |= ids[1:] != ids[:-1]
    boundary[:-1] |= ids[1:] != ids[:-1]
    moving = dilate(np.abs(temporal - sharp.color)[..., :3].max(-1) > STILL, 2)
    near_edge = dilate(boundary, 2)
    return {
        "still_edges": near_edge & ~moving,
        "moving": moving,
        "flat": ~near_edge & ~moving,
    }
