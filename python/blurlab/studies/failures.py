"""The failure-case suite: every single-frame method on every failure scene (bl.scenes.names
("failure"), and the transparency cases of bl.scenes.names("transparency")), measured for error
against the reference, NaN/Inf, colors outside the input range, flicker over an animation, the
jitter's noise, and sensitivity to k and soft_z. docs/failure_cases.md explains each failure
with these numbers."""

from __future__ import annotations

import numpy as np
import pandas as pd

from .. import metrics as m
from ..core.references import default_reference_samples
from ..methods import blur, method, method_instant, methods
from ..scene import scenes
from . import plots
from .sweep import sweep_methods


def animation(ctx, scene, name: str, size, frames: int, params: dict):
    """`frames` consecutive frames, frame n covering the shutter moved on by n shutter lengths,
    each blurred with seed n where the method has one: (outputs, sharp colors, motions)."""
    t0, t1 = scene.shutter
    step = t1 - t0
    outputs, colors, motions = [], [], []
    for n in range(frames):
        shutter = (t0 + n * step, t1 + n * step)
        frame = ctx.render(scene, size, shutter, instant=method_instant(name, params))
        extra = {"seed": n} if "seed" in method(name).params else {}
        outputs.append(blur(ctx, frame, name, **params, **extra).color)
        colors.append(frame.color)
        motions.append(frame.motion)
    return np.stack(outputs), np.stack(colors), np.stack(motions)


def still_pixels(colors: np.ndarray, motions: np.ndarray) -> np.ndarray:
    """Pixels whose sharp color never changes and which never move: blur has no business
    changing them from one frame to the next."""
    unchanged = np.abs(np.diff(colors, axis=0)).max(axis=(0, 3)) == 0
    return unchanged & (np.abs(motions).max(axis=(0, 3)) == 0)


def evaluate(
    ctx,
    scene_names=None,
    methods=None,
    size=(320, 180),
    frames: int = 16,
    reference_samples: int | None = None,
    progress: bool = True,
) -> pd.DataFrame:
    """One row per (failure scene, method) at the method's default parameters; HDR scenes
    (bl.scenes.names("hdr") may be given too) get the HDR metrics as well."""
    scene_names = list(scene_names or scenes.names("failure") + scenes.names("transparency"))
    methods = list(methods or sweep_methods())
    rows = []
    bar = None
    if progress:
        from tqdm.auto import tqdm

        bar = tqdm(total=len(scene_names) * len(methods), desc="failure cases", unit="case")
    for scene_name in scene_names:
        scene = scenes.get(scene_name)
        frame = ctx.render(scene, size)
        n = reference_samples or default_reference_samples(frame)
        reference = ctx.reference(scene, size, samples=n, progress=False)
        by_instant = {"center": frame}  # methods share the G-buffer of their instant
        for name in methods:
            instant = method_instant(name, {})
            if instant not in by_instant:
                by_instant[instant] = ctx.render(scene, size, instant=instant)
            instant_frame = by_instant[instant]
            out = blur(ctx, instant_frame, name).color
            lo, hi = instant_frame.color.min(axis=(0, 1)), instant_frame.color.max(axis=(0, 1))
            outside = ((out < lo - 1e-5) | (out > hi + 1e-5)).any(axis=-1).sum()
            outputs, colors, motions = animation(ctx, scene, name, size, frames, {})
            still = still_pixels(colors, motions)
            seeded = "seed" in method(name).params
            row = {
                "scene": scene_name,
                "method": name,
                "psnr": m.psnr(reference.color, out),
                "ssim": m.ssim(reference.color, out),
                "nan": int(np.isnan(out).sum()),
                "inf": int(np.isinf(out).sum()),
                "outside_input_range": np.nan if method(name).renders else int(outside),
                "flicker": m.flicker(outputs, still) if still.any() else np.nan,
                "still_pixels": int(still.sum()),
                "seed_noise": _seed_noise(ctx, instant_frame, name, out) if seeded else 0.0,
                "reference_samples": n,
            }
            if scene.hdr:  # clipped PSNR cannot see its lights (docs/spec.md §6.2)
                row.update(m.hdr_scores(reference.color, out))
            if method(name).kind == "filter":
                row.update(_sensitivity(ctx, reference.color, frame, name))
            rows.append(row)
            if bar:
                bar.update()
    if bar:
        bar.close()
    return pd.DataFrame(rows)


def _seed_noise(ctx, frame, name: str, out: np.ndarray) -> float:
    """Mean |out(seed 0) - out(seed 1)| over RGB on one frame: the jitter's noise alone, which
    `flicker` cannot see where no pixel is still (a turning camera)."""
    other = blur(ctx, frame, name, seed=1).color
    return float(np.abs(other[..., :3] - out[..., :3]).mean())


K_VALUES = (10, 20, 40)
SOFT_Z_FACTORS = (0.1, 1, 10, 100)  # x the default; 100 x spans the scene: no depth test left


def _sensitivity(ctx, reference: np.ndarray, frame, name: str) -> dict:
    """PSNR (dB) for each k in K_VALUES and soft_z in SOFT_Z_FACTORS x default, and the
    spread (max - min) of each."""
    by_k = {k: m.psnr(reference, blur(ctx, frame, name, k=k).color) for k in K_VALUES}
    soft_z = blur(ctx, frame, name).params["soft_z"]
    by_z = {
        f: m.psnr(reference, blur(ctx, frame, name, soft_z=soft_z * f).color)
        for f in SOFT_Z_FACTORS
    }
    return {
        **{f"psnr_k{k}": v for k, v in by_k.items()},
        **{f"psnr_soft_z_x{f:g}": v for f, v in by_z.items()},
        "k_spread_db": max(by_k.values()) - min(by_k.values()),
        "soft_z_spread_db": max(by_z.values()) - min(by_z.values()),
    }


def gallery_methods() -> list[str]:
    """The methods the gallery shows: those that ask for it in the registry."""
    return [name for name in methods() if method(name).gallery]


def gallery(ctx, scene_name: str, size, methods=None, reference_samples=None):
    """A figure: the reference, each method's image (at the instant it declares) and its
    |error| map below it; `methods` default to gallery_methods()."""
    methods = gallery_methods() if methods is None else methods
    scene = scenes.get(scene_name)
    n = reference_samples or default_reference_samples(ctx.render(scene, size))
    reference = ctx.reference(scene, size, samples=n, progress=False)
    images = {}
    for name in methods:
        frame = ctx.render(scene, size, instant=method_instant(name, {}))
        images[name.replace("reconstruct_", "")] = blur(ctx, frame, name).color
    return plots.image_grid(
        reference.color, images, title=f"{scene_name}: {scenes.describe(scene_name)}"
    )
