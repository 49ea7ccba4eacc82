"""The four ways to blur translucency (docs/spec.md §20.4) measured on the transparency scenes
(bl.scenes.names("transparency")): PSNR and FLIP of each (scene, method, approach) against the
antialiased reference, their medians per approach, what the layered approach gains over the
best of the other three, and what the translucent layer costs next to today's filter.
docs/transparency.md shows the numbers of the transparency benchmark."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import pandas as pd

from .. import metrics
from ..core.references import default_reference_samples
from ..docs_link import docs_anchor
from ..io import images as io
from ..methods import blur, layers, method_instant, translucent_layer_method
from ..methods import method as method_info
from ..methods import methods as method_names
from ..methods.layers import TRANSLUCENCY
from ..scene import scenes
from ..twins import translucency as translucency_twin
from . import plots

APPROACHES = TRANSLUCENCY.kind
# What the study's "transparency" phase counts (blurlab.studies.study.PHASES).
REPORT_PHASE = (
    "each transparency scene under the four ways to blur translucency (its G-buffers, blurs "
    "and GPU metrics; the sweep's antialiased reference, or its own where the sweep made none)"
)


def single_frame_methods() -> list[str]:
    """Every post-process method that blurs one frame (the registry's filters and gathers):
    each takes every translucency option (docs/spec.md §20.4)."""
    kinds = ("filter", "gather")
    return [n for n in method_names() if method_info(n).kind in kinds]


def evaluate(
    ctx,
    scene_names=None,
    methods=None,
    size=(320, 180),
    reference_samples=None,
    shown=None,
    references=None,
):
    """One row per (scene, method, approach): psnr and flip against the antialiased reference
    of the scene's shutter (N = reference_samples, or max(64, 2 x the longest motion)).
    `shown`: a dict that receives, per scene, the reference and the images of the method that
    blurs the translucent layer (the first method where it is not among `methods`) under each
    approach, for pictures. `references`: {scene name: its antialiased Reference} already made
    (a study's sweep makes them for psnr_aa, with the same options), used where its N is the
    one asked for.

    Both metrics are issued on the GPU and read back once per scene (a MetricQueue): nothing
    but the scalars and the pictured method's images leaves the GPU."""
    rows = []
    methods = methods or single_frame_methods()
    pictured = translucent_layer_method()
    pictured = pictured if pictured in methods else methods[0]
    for name in scene_names or scenes.names("transparency"):
        scene = scenes.get(name)
        n = reference_samples or default_reference_samples(ctx.render(scene, size))
        reference = (references or {}).get(name)
        reusable = reference is not None and reference.texture is not None
        if not (reusable and reference.antialias and reference.samples == n):
            reference = ctx.reference(scene, size, samples=n, antialias=True, progress=False)
        queue = metrics.MetricQueue(ctx)
        frames = {}
        images = {}
        issued = []
        for method in methods:
            instant = method_instant(method)
            if instant not in frames:
                frames[instant] = ctx.render(scene, size, instant=instant)
            for approach in APPROACHES:
                out = blur(ctx, frames[instant], method, timed=False, translucency=approach)
                if method == pictured:
                    images[approach] = out.color
                color = out.textures["color"]
                mse, flip = (
                    queue.mse(reference.texture, color),
                    queue.flip(reference.texture, color),
                )
                issued.append((method, approach, mse, flip))
        values = queue.read()
        for method, approach, mse, flip in issued:
            rows.append(
                {
                    "scene": name,
                    "method": method,
                    "translucency": approach,
                    "psnr": metrics.psnr_from_mse(values[mse]),
                    "flip": values[flip],
                    "reference_samples": n,
                }
            )
        if shown is not None:
            shown[name] = (pictured, reference.color, images)
    return pd.DataFrame(rows)


def summary(table: pd.DataFrame) -> dict:
    """Median psnr and flip per approach, and the layered approach's margin over the best of
    the other three per (scene, method) (psnr: layered − best; flip: best − layered; positive
    when layered is better), as medians and per scene."""
    medians = table.groupby("translucency")[["psnr", "flip"]].median().reindex(list(APPROACHES))
    wide = table.pivot_table(index=["scene", "method"], columns="translucency")
    others = [a for a in APPROACHES if a != "layered"]
    gain = pd.DataFrame(
        {
            "psnr": wide["psnr"]["layered"] - wide["psnr"][others].max(axis=1),
            "flip": wide["flip"][others].min(axis=1) - wide["flip"]["layered"],
        }
    )
    return {
        "median_per_approach": medians,
        "layered_gain": gain,
        "median_layered_gain_db": float(gain["psnr"].median()),
        "median_layered_gain_flip": float(gain["flip"].median()),
        "median_gain_per_scene": gain.groupby(level="scene").median(),
    }


def opaque_scene(name: str):
    """The built-in scene `name` without its translucent objects."""
    scene = scenes.get(name)
    scene.objects = [obj for obj in scene.objects if not obj.material.translucent]
    return scene


def drawn_opaque_scene(name: str):
    """The built-in scene `name` with its translucent objects drawn opaque, alpha ignored: how
    blurlab drew a blended surface before it had a translucent layer, so the method sees the
    surfaces and their own motion in its G-buffer (the cost the transparency benchmark sets
    the layered approach against)."""
    scene = scenes.get(name)
    for obj in scene.objects:
        if obj.material.translucent:
            obj.material = dataclasses.replace(obj.material, blend="opaque")
    return scene


def layer_error(ctx, shown: dict, size, reference_samples=None) -> pd.DataFrame:
    """What limits the layered approach on each scene of `shown` (as evaluate fills it) that
    has a translucent layer: PSNR against the scene's reference of the coverage gather's
    blurred layer composited over the exact blur of the opaque layer (the reference of the
    scene without its translucent objects, same N), so the layer's blur is the only error.
    Where it lies far above layered's own PSNR, the method's blur of the opaque layer is what
    layered loses there, and no better layer blur can win it back."""
    rows = []
    for name, (_, reference, _) in shown.items():
        scene = scenes.get(name)
        if not scene.translucent:
            continue
        frame = ctx.render(scene, size, instant=method_instant(translucent_layer_method()))
        n = reference_samples or default_reference_samples(frame)
        opaque = opaque_scene(name)
        exact = ctx.reference(opaque, size, samples=n, antialias=True, progress=False).color
        layer = blur(ctx, layers.translucent_frame(ctx, frame), translucent_layer_method())
        composite = translucency_twin.over(layer.color, exact)
        rows.append({"scene": name, "psnr": metrics.psnr(composite, reference)})
    return pd.DataFrame(rows, columns=["scene", "psnr"])


def report(
    ctx, scene, grids, size, out, work, clock, reference_samples=None, reference=None
) -> str:
    """The study's report on a transparency scene (bl.scenes.names("transparency"); "" for any
    other scene, or where `grids` has no one-frame method): each one-frame method of `grids` at
    its defaults under the four approaches, scored by evaluate (<scene>_transparency.csv), a
    table of their PSNR, and the reference beside the method that blurs the layer under each
    approach with |error| (<scene>_translucency.png, left encoding on `work`, the study's
    ReportWork). Timed as the phase "transparency" of `clock`. `reference`: the scene's
    antialiased reference where the sweep made one (used if its N is `reference_samples`)."""
    methods = [m for m in grids if m in single_frame_methods()]
    if scene.name not in scenes.names("transparency") or not methods:
        return ""
    shown: dict = {}
    with clock("transparency"):
        table = evaluate(
            ctx, [scene.name], methods, size, reference_samples, shown, {scene.name: reference}
        )
    out = Path(out)
    table.to_csv(out / f"{scene.name}_transparency.csv", index=False)
    method, reference, images = shown[scene.name]
    picture = f"{scene.name}_translucency.png"
    grid = plots.image_grid_picture
    work.pictures_written.append(
        work.pictures.submit(lambda: io.write(out / picture, grid(reference, images)))
    )
    psnr = table.pivot(index="method", columns="translucency", values="psnr")[list(APPROACHES)]
    return (
        "<h3>Four ways to blur its translucent surfaces</h3><p>PSNR (dB) of each one-frame "
        "method at its defaults under each <code>translucency</code> option (docs/spec.md "
        f"§20.4, {docs_anchor('transparency', 'transparency')}) against the antialiased "
        f"reference, FLIP too in <a href='{scene.name}_transparency.csv'>"
        f"{scene.name}_transparency.csv</a>:</p>"
        + psnr.reset_index().to_html(index=False, float_format=lambda v: f"{v:.2f}", border=0)
        + f"<p>The reference, then <code>{method}</code> under each, with |error| below:</p>"
        f"<p><img src='{picture}'></p>"
    )


def gallery(ctx, scene_name: str, size, method: str | None = None, reference_samples=None):
    """A figure: the antialiased reference and `method` (default: the method that blurs the
    translucent layer, the coverage gather) under each approach, with |error|."""
    method = method or translucent_layer_method()
    shown: dict = {}
    evaluate(ctx, [scene_name], [method], size, reference_samples, shown)
    _, reference, images = shown[scene_name]
    return plots.image_grid(
        reference, images, title=f"{scene_name} ({method}): {scenes.describe(scene_name)}"
    )
