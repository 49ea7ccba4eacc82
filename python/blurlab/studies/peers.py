"""Peers in the study (`blurlab study --peers eevee`): Blender's EEVEE rendering the same scenes,
scored against the same references as the methods. Their time is Blender's wall time on its
own device, not a GPU pass time, and the table says so."""

from __future__ import annotations

import pandas as pd

from .. import blender, metrics
from ..context import Context

PEERS = ("eevee",)
# (row label, EEVEE render samples, motion-blur steps): the real-time post-process filter
# alone, and Blender's defaults.
EEVEE_ROWS = (
    ("EEVEE post-process (1 sample, 1 step)", 1, 1),
    ("EEVEE default (64 samples, 1 step)", 64, 1),
)


def check_peers(peers) -> tuple[str, ...]:
    """The peers asked for, checked before any work (bpy missing fails here, not hours in)."""
    peers = tuple(peers or ())
    unknown = [p for p in peers if p not in PEERS]
    if unknown:
        raise ValueError(f"blurlab study: unknown peers {unknown}; choose from {PEERS}")
    if peers and not blender.available():
        raise ImportError(blender.INSTALL)
    return peers


def peer_table(
    ctx: Context,
    scenes: dict,
    size,
    reference_samples: dict,
    wanted: tuple[str, ...],
    configurations=EEVEE_ROWS,
) -> pd.DataFrame:
    """One row per peer configuration (label, samples, steps) and scene: PSNR (and SSIM, FLIP,
    psnr_aa if `wanted`) against the scene's temporal reference with the sweep's N, Blender's
    wall time and device. A scene Blender cannot reproduce gets a row that says why instead of
    numbers."""
    rows = []
    for name, scene in scenes.items():
        n = reference_samples[name]
        try:
            blender.check_reproducible(scene)
        except ValueError as error:
            rows += [
                {"scene": name, "method": label, "note": str(error)} for label, *_ in configurations
            ]
            continue
        temporal = ctx.reference(scene, size, samples=n, progress=False).color
        antialiased = None
        if "psnr_aa" in wanted:
            antialiased = ctx.reference(scene, size, samples=n, antialias=True, progress=False)
        for label, samples, steps in configurations:
            result = blender.render(scene, size, engine="EEVEE", samples=samples, steps=steps)
            row = {
                "scene": name,
                "method": label,
                "psnr": metrics.psnr(temporal, result.color),
                "time": f"{result.wall_s:.1f} s Blender wall time "
                f"({result.render_s:.1f} s rendering), {result.device}",
                "wall_s": result.wall_s,
                "render_s": result.render_s,
                "device": result.device,
                "reference_samples": n,
                "note": "",
            }
            if "ssim" in wanted:
                row["ssim"] = metrics.ssim(temporal, result.color)
            if "flip" in wanted:
                row["flip"] = metrics.flip(temporal, result.color)
            if antialiased is not None:
                row["psnr_aa"] = metrics.psnr(antialiased.color, result.color)
            rows.append(row)
    return pd.DataFrame(rows)
