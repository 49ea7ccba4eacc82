"""Peers in the study (`blurlab study --peers eevee`) and in the engines benchmark: Blender's
EEVEE rendering the same scenes, scored against the same references as the methods. Their time
is Blender's wall time on its own device, not a GPU pass time, and the table says so."""

from __future__ import annotations

from collections.abc import Callable

import pandas as pd

from .. import blender, metrics
from ..blender.crosscheck import psnr_in, regions
from ..core.context import Context
from ..core.references import Reference
from ..twins.film import film_filter

PEERS = ("eevee",)
# (row label, EEVEE render samples, motion-blur steps): the real-time post-process filter
# alone, and Blender's defaults.
EEVEE_ROWS = (
    ("EEVEE post-process (1 sample, 1 step)", 1, 1),
    ("EEVEE default (64 samples, 1 step)", 64, 1),
)
# The scores a peer row can carry: each registered LDR metric of the temporal reference
# (NumPy implementations: a peer's image is an array), under its own name, and against the
# antialiased reference (docs/spec.md §11) with "_aa" after it.
SCORES = {
    name: metrics.get(name).numpy
    for name in metrics.registered()
    if not metrics.get(name).hdr and metrics.get(name).reference == "temporal"
}
ANTIALIASED = "_aa"


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
    wanted: tuple[str, ...] | None = None,
    configurations=EEVEE_ROWS,
) -> pd.DataFrame:
    """peer_rows for each of `scenes` ({name: Scene}), against references of the sweep's N for
    that scene (`reference_samples`), rendered only for the scenes Blender can reproduce.
    `wanted`: the metrics, as a sweep takes them; None: each scene's defaults, as a sweep
    computes them (metrics.default_names)."""
    rows = []
    for name, scene in scenes.items():
        n = reference_samples[name]

        def reference(antialias: bool, scene=scene, n=n) -> Reference:
            return ctx.reference(scene, size, samples=n, antialias=antialias, progress=False)

        scores = metrics.default_names(scene.hdr) if wanted is None else wanted
        rows += peer_rows(ctx, name, scene, size, reference, scores, configurations)
    return pd.DataFrame(rows)


def unscored(rows: pd.DataFrame, scene: str) -> dict[str, list[str]]:
    """{note: labels} of the peer `rows` (peer_table's) that have no numbers on `scene`, by the
    note that says why (e.g. a material Blender cannot render)."""
    if rows.empty:
        return {}
    noted = rows[(rows["scene"] == scene) & (rows["note"].fillna("") != "")]
    return {note: list(group["method"]) for note, group in noted.groupby("note", sort=False)}


def peer_rows(
    ctx: Context,
    name: str,
    scene,
    size,
    reference: Callable[[bool], Reference],
    wanted: tuple[str, ...],
    configurations=EEVEE_ROWS,
    film_sigma: float = 0.0,
) -> list[dict]:
    """One row per peer configuration (label, samples, steps) on scene `name`: PSNR against the
    temporal reference, the other SCORES `wanted` (ssim, flip; psnr_aa, ssim_aa, flip_aa
    against the antialiased reference), Blender's wall time and device. `reference(antialias)`
    gives the scene's reference; it is called only when Blender can reproduce the scene, and a
    scene it cannot gets rows that say why instead of numbers. With `film_sigma` > 0 each row
    also holds film_match_flat_db (film_match)."""
    try:
        blender.check_reproducible(scene)
    except ValueError as error:
        return [
            {"scene": name, "method": label, "note": str(error)} for label, *_ in configurations
        ]
    references = {"": reference(False)}
    if any(w.endswith(ANTIALIASED) for w in wanted):
        references[ANTIALIASED] = reference(True)
    temporal = references[""]
    filtered_flat = film_reference(ctx, scene, size, temporal.color, film_sigma)
    rows = []
    for label, samples, steps in configurations:
        result = blender.render(scene, size, engine="EEVEE", samples=samples, steps=steps)
        row = {
            "scene": name,
            "method": label,
            "psnr": metrics.psnr(temporal.color, result.color),
            "time": f"{result.wall_s:.1f} s Blender wall time "
            f"({result.render_s:.1f} s rendering), {result.device}",
            "wall_s": result.wall_s,
            "render_s": result.render_s,
            "device": result.device,
            "reference_samples": temporal.samples,
            "note": "",
        }
        for suffix, ref in references.items():
            for metric, score in SCORES.items():
                if metric + suffix in wanted and metric + suffix not in row:
                    row[metric + suffix] = score(ref.color, result.color)
        if film_sigma > 0:
            row["film_match_flat_db"] = film_match(result.color, filtered_flat)
        rows.append(row)
    return rows


def film_reference(ctx: Context, scene, size, temporal, sigma: float):
    """What film_match compares a peer's image with, once per scene: (blurlab's sharp frame
    under a Gaussian film filter of `sigma` px, docs/spec.md §17.6 step 4; the pixels that
    motion leaves alone and no edge is near, the flat region of
    blurlab.blender.crosscheck.regions). None for `sigma` 0 or a scene with no such pixel."""
    if sigma <= 0:
        return None
    flat = regions(ctx, scene, size, temporal)["flat"]
    if not flat.any():
        return None
    return film_filter(ctx.render(scene, size).color, sigma), flat


def film_match(image, filtered_flat) -> float | None:
    """PSNR (dB) of a peer's `image` against film_reference's filtered frame over its flat
    pixels: how closely that filter is the peer's own pixel filter. None without one."""
    if filtered_flat is None:
        return None
    filtered, flat = filtered_flat
    return float(psnr_in(image, filtered, flat))
