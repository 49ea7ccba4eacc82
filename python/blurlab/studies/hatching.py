"""Measurements that compare the two hatching schemes (docs/hatching.md): ``tone_reproduction``
renders a flat-lit patch for a ramp of target tones and measures its mean ink;
``temporal_coherence`` renders a slowly turning teapot under a moving light and counts the
stroke pixels that appear or vanish from frame to frame.
"""

from __future__ import annotations

import math

import numpy as np

from ..hatching.tam import TAM, default_tam
from ..scene import mesh as meshes
from ..scene.model import Camera, DirectionalLight, Material, Scene
from ..scene.motion import Motion
from ..twins import hatching as ref


def patch_scene(darkness: float, hatched: Material) -> Scene:
    """A plane facing the camera that fills a square image, lit so that its intensity is
    exactly 1 − darkness (Lambert, no ambient), showing `scale` × `scale` TAM tiles."""
    intensity = 1.0 - float(darkness)
    light = DirectionalLight(
        direction=(math.sqrt(max(0.0, 1.0 - intensity**2)), 0.0, intensity),
        color=(1.0, 1.0, 1.0),
        ambient=(0.0, 0.0, 0.0),
    )
    # fov 30° at distance 0.5/tan(15°): the view is exactly one unit across at the plane.
    camera = Camera(position=(0, 0, 0.5 / math.tan(math.radians(15))), fov_y=30.0)
    scene = Scene(camera, light, background=(1, 1, 1), name="hatching_patch")
    # 2 × 2 units with uv 0..2: one TAM tile per unit (scale 1) across the view.
    plane = meshes.plane(2.0, 2.0, uv_repeat=2.0).transformed(meshes.rotation_x(math.pi / 2))
    scene.add(plane, hatched, name="patch")
    return scene


def ink_of(frame, paper=(1.0, 1.0, 1.0)) -> np.ndarray:
    """(H, W) ink = 1 − luminance(color) / luminance(paper) of a frame's color."""
    weights = np.array([0.2126, 0.7152, 0.0722])
    lum = frame.color[..., :3].astype(np.float64) @ weights
    return np.clip(1.0 - lum / float(np.dot(paper, weights)), 0.0, 1.0)


def box_filter(image: np.ndarray, width: int) -> np.ndarray:
    """Mean over a width × width box around each pixel (wrapping at the edges, as the TAM does
    on a patch that shows whole tiles)."""
    if width <= 1:
        return image.astype(np.float64)
    out = np.zeros(image.shape, np.float64)
    for dy in range(width):
        for dx in range(width):
            out += np.roll(image, (dy - width // 2, dx - width // 2), axis=(0, 1))
    return out / (width * width)


def tone_reproduction(
    ctx,
    scheme: str,
    tam: TAM | None = None,
    steps: int = 64,
    size: int = 128,
    spacing_texels: float = 8.0,
) -> dict:
    """Renders the flat-lit patch at `steps` target tones (darkness 0..1) and measures its ink.

    The patch shows one TAM tile across `size` pixels. Ink is box-filtered over one stroke
    spacing (`spacing_texels` TAM texels at the level GL picks, in pixels) before it is
    averaged; the spread of the filtered ink says how even the tone is. Returns target,
    measured (mean ink), spread (std of the filtered ink), expected (what the TAM itself
    predicts, blurlab.twins.hatching.patch_ink), the mean absolute tone error and the
    number of distinguishable steps (a step counts when its tone differs from the last counted
    one by at least half the spacing of the targets).
    """
    tam = tam or default_tam()
    target = np.linspace(0.0, 1.0, steps)
    hatched = Material.hatching(scheme, tam, 1.0)
    pixels_per_texel = size / tam.sizes[0]
    level = int(np.clip(round(-math.log2(pixels_per_texel)), 0, len(tam.sizes) - 1))
    box = max(1, round(spacing_texels * size / tam.sizes[level]))
    measured, spread = [], []
    for d in target:
        frame = ctx.render(patch_scene(d, hatched), (size, size), shutter=(0.0, 0.0))
        filtered = box_filter(ink_of(frame), box)
        measured.append(filtered.mean())
        spread.append(filtered.std())
    measured = np.array(measured)
    return {
        "scheme": scheme,
        "target": target,
        "measured": measured,
        "spread": np.array(spread),
        "expected": ref.patch_ink(tam, scheme, target, level),
        "mean_abs_error": float(np.abs(measured - target).mean()),
        "distinguishable_steps": distinguishable_steps(measured, 0.5 / (steps - 1)),
        "size": size,
        "level": level,
        "box_pixels": box,
    }


def distinguishable_steps(tones: np.ndarray, threshold: float) -> int:
    """How many of the (increasing) tones differ from the last counted one by >= threshold."""
    count, last = 1, tones[0]
    for tone in tones[1:]:
        if abs(tone - last) >= threshold:
            count, last = count + 1, tone
    return count


def pair_scene(scheme: str | None, tam: TAM | None = None, motion: Motion | None = None) -> Scene:
    """The teapot and the torus side by side on white paper (the seed's Figures 3–8), hatched
    with `scheme` ("six_way" or "threshold"), or shaded white Lambert when it is None. The
    teapot takes `motion` if given."""

    def surface(scale: float) -> Material:
        return Material((1, 1, 1)) if scheme is None else Material.hatching(scheme, tam, scale)

    scene = Scene(
        Camera(position=(0, 0.9, 3.2), look_at=(0, 0.4, 0), fov_y=40),
        DirectionalLight(direction=(0.6, 0.8, 0.5), ambient=(0.05, 0.05, 0.05)),
        background=(1, 1, 1),
        name="hatching_pair",
    )
    left = np.eye(4)
    left[0, 3] = -0.7
    right = meshes.rotation_x(math.radians(60))
    right[:3, 3] = (0.8, 0.45, 0)
    scene.add(meshes.teapot().transformed(left), surface(2.0), motion, name="teapot")
    scene.add(meshes.torus().transformed(right), surface(4.0), name="torus")
    return scene


def coherence_scene(
    scheme: str,
    tam: TAM | None = None,
    scale: float = 2.0,
    frame_time: float = 1 / 30,
    spin_per_frame: float = math.radians(1.0),
) -> Scene:
    """The teapot turning slowly about y (`spin_per_frame` radians a frame), for
    temporal_coherence; its light is set per frame there."""
    camera = Camera(position=(0.0, 0.9, 2.6), look_at=(0.0, 0.45, 0.0), fov_y=40.0)
    scene = Scene(camera, background=(1, 1, 1), name="hatching_teapot")
    motion = Motion.linear(spin_axis=(0, 1, 0), spin_rate=spin_per_frame / frame_time)
    scene.add(meshes.teapot(), Material.hatching(scheme, tam, scale), motion, name="teapot")
    return scene


def light_at(frame: int, frames: int, moving: bool = True) -> DirectionalLight:
    """The coherence study's light: it sweeps 60° around the teapot over the frames, against
    the teapot's turn (so the two add up, as seen from the surface)."""
    angle = math.radians(30.0 - (60.0 * frame / max(frames - 1, 1) if moving else 0.0))
    return DirectionalLight(
        direction=(math.sin(angle), 0.8, math.cos(angle)), ambient=(0.05, 0.05, 0.05)
    )


def temporal_coherence(
    ctx,
    scheme: str,
    tam: TAM | None = None,
    frames: int = 32,
    size=(320, 240),
    moving_light: bool = True,
    frame_time: float = 1 / 30,
    spin_per_frame: float = math.radians(1.0),
) -> dict:
    """Stroke pixels that pop (appear or vanish) from frame to frame on the slowly turning
    teapot, per frame pair. A pixel is a stroke where its ink is > 0.5.

    - ``pop_fraction`` (same pose): frame n is rendered twice at its own pose, once under its
      own light and once under frame n−1's light turned with the object from n−1 to n, so that
      every surface point gets the intensity it had one frame before (exact for Lambert). Pixel
      for pixel, what differs is what the tone change did: no resampling is involved.
    - ``reprojected_pop_fraction``: frame n against frame n−1 itself, each pixel led back by its
      motion vector (the shutter spans n−1 to n) and the previous ink read bilinearly there; it
      adds what the turning itself changes (mip levels, foreshortening) and the resampling
      error. Pixels whose point was not on the teapot one frame before are left out.
    - ``ink_change``: mean |ink_n − ink under n−1's light| on the teapot (same pose): blended
      strokes fading count here even where they stay on one side of 0.5.

    Fractions are pops / stroke pixels of either image.
    """
    scene = coherence_scene(scheme, tam, frame_time=frame_time, spin_per_frame=spin_per_frame)
    teapot = scene.objects[0]
    previous = None
    same_pose, reprojected, change = [], [], []
    for n in range(frames):
        t = n * frame_time
        light = light_at(n, frames, moving_light)
        scene.light = light
        frame = ctx.render(scene, size, shutter=(t - frame_time, t), instant="close")
        ink = ink_of(frame)
        on = frame.object_id >= 0
        if previous is not None:
            prev_ink, prev_on, prev_light = previous
            turn = teapot.model(t)[:3, :3] @ np.linalg.inv(teapot.model(t - frame_time)[:3, :3])
            scene.light = DirectionalLight(
                turn @ prev_light.direction, prev_light.color, prev_light.ambient
            )
            before = ink_of(ctx.render(scene, size, shutter=(t, t)))
            same_pose.append(_pops(ink, before, on))
            change.append(float(np.abs(ink - before)[on].mean()))
            h, w = ink.shape
            y, x = np.mgrid[0:h, 0:w] + 0.5
            sx, sy = x - frame.motion[..., 0], y - frame.motion[..., 1]
            ix = np.clip(np.floor(sx).astype(int), 0, w - 1)
            iy = np.clip(np.floor(sy).astype(int), 0, h - 1)
            inside = (sx >= 0) & (sx < w) & (sy >= 0) & (sy < h)
            valid = on & inside & prev_on[iy, ix]
            reprojected.append(_pops(ink, _bilinear(prev_ink, sx, sy), valid))
        previous = (ink, on, light)
    same_pose, reprojected = np.array(same_pose), np.array(reprojected)
    return {
        "scheme": scheme,
        "moving_light": moving_light,
        "pop_fraction": same_pose,
        "mean_pop_fraction": float(same_pose.mean()),
        "reprojected_pop_fraction": reprojected,
        "mean_reprojected_pop_fraction": float(reprojected.mean()),
        "ink_change": np.array(change),
        "mean_ink_change": float(np.mean(change)),
        "frames": frames,
        "size": tuple(size),
    }


def _pops(ink: np.ndarray, before: np.ndarray, where: np.ndarray) -> float:
    """Pixels that are a stroke (ink > 0.5) in one image and not the other, over the pixels
    that are a stroke in either, among `where`."""
    now, then = ink > 0.5, before > 0.5
    strokes = (where & (now | then)).sum()
    return float((where & (now != then)).sum() / max(strokes, 1))


def _bilinear(image: np.ndarray, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Samples `image` at pixel coordinates (x, y) (centers at +0.5), clamped at the edges."""
    h, w = image.shape
    px, py = x - 0.5, y - 0.5
    x0 = np.clip(np.floor(px).astype(int), 0, w - 1)
    y0 = np.clip(np.floor(py).astype(int), 0, h - 1)
    x1, y1 = np.clip(x0 + 1, 0, w - 1), np.clip(y0 + 1, 0, h - 1)
    fx, fy = np.clip(px - x0, 0, 1), np.clip(py - y0, 0, 1)
    top = image[y0, x0] * (1 - fx) + image[y0, x1] * fx
    bottom = image[y1, x0] * (1 - fx) + image[y1, x1] * fx
    return top * (1 - fy) + bottom * fy
