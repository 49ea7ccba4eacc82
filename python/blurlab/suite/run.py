"""`blurlab suite run` (docs/spec.md §24): every category of the suite for the methods asked and
the built-in methods they are ranked against, into a card (card.json and card.html).

Single-frame categories are sweeps (blurlab.studies.sweep): each method at its declared
defaults on every scene of the category, at its size, shutter and reference, rows kept in
`OUT/rows/CATEGORY.csv` and keyed as sweeps key them, so a run resumes; with a Dask cluster
their evaluations run on its workers. The sequence category runs on this process's context
(blurlab.suite.sequence_rows), as `blurlab study --sequence` does.
"""

from __future__ import annotations

import datetime
import json
import time
from pathlib import Path

import numpy as np
import pandas as pd

from ..io import images as io
from ..methods import blur, method, method_instant
from ..metrics import error_map, get
from ..metrics.hdr import exposure
from ..scene import scenes
from ..studies import comparator, identity, plots
from ..studies.evaluation import REFERENCE_OPTIONS
from ..studies.sweep import sweep, sweep_methods
from ..version import __version__
from . import captured, content, field_rows, figures, page
from . import definition as d
from .sequence_rows import run_sequences

CARD_FORMAT = 1  # the layout of card.json (blurlab.suite.compare reads it)


def builtin_methods() -> list[str]:
    """The field every method is ranked against: the built-in methods a sweep evaluates."""
    return [n for n in sweep_methods() if method(n).source is None]


def check_methods(names) -> list[str]:
    """`names` checked (each registered and single-frame), in order, each once; None: every
    single-frame method registered (the built-ins and any loaded method folders)."""
    if names is None:
        return sweep_methods()
    if isinstance(names, str) or not names:
        raise ValueError("blurlab suite: methods must be a non-empty list of method names")
    checked = []
    for name in names:
        m = method(name)  # an unknown name raises, naming the registered ones
        if not m.sweepable:
            raise ValueError(
                f"blurlab suite: {name} blends frames itself; the suite scores methods that "
                f"run on one frame ({', '.join(sweep_methods())})"
            )
        if name not in checked:
            checked.append(name)
    return checked


def run_suite(
    ctx,
    out,
    methods=None,
    preset: str = "software",
    assets=None,
    cluster=None,
    progress: bool = False,
    pictures: bool = True,
    captures=None,
    field_from=None,
) -> dict:
    """Runs the suite at `preset` for `methods` (default: every single-frame method registered)
    and writes OUT/card.json and OUT/card.html; returns the card. `assets`: the folder holding
    the authored category's glTF files (without it that category is skipped, and the card
    says why). `cluster`: a Dask client, cluster or scheduler address for the single-frame
    categories (bl.sweep's `cluster`); `ctx` runs the sequences and the pictures.
    `captures`: blurlab.suite.captured.Capture of an engine's frames, scored as the captured
    category (§24.1) where given. `field_from`: the folder of an earlier card whose rows are
    taken where their keys match (blurlab.suite.field_rows), so that only the rows it lacks
    (a new method's) are evaluated."""
    d.check_preset(preset)
    asked = check_methods(methods)
    field = builtin_methods()
    everyone = field + [n for n in asked if n not in field]
    # The authored files and the captures are checked before anything runs: a file of other
    # content is refused now, not after the other categories.
    authored = {
        c.name: d.authored_paths(c, preset, assets) for c in d.categories() if c.needs_assets
    }
    captures = list(captures or ())
    captured_digests = captured.digests(captures) if captures else None
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    taken = field_rows.take_rows(out, field_from) if field_from is not None else 0
    suite = content.suite_identity(preset, captured_digests)
    definition = d.definition(preset)
    if captures:
        first = captured.opened(captures[0])[0].size()
        definition["categories"][captured.NAME] = {
            "size": list(first),
            "reference": {"samples": "files"},
            "metrics": list(captured.metrics()),
            "captures": captured_digests,
        }
    info = ctx.info()
    card = {
        "format": CARD_FORMAT,
        "suite": {**suite, "definition": definition},
        "device": {"device": info["device"], "renderer": info["renderer"], "clock": info["timer"]},
        "date": datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%dT%H:%M:%SZ"),
        "blurlab_version": __version__,
        "methods": {n: {"builtin": n in field, "digest": content.method_digest(n)} for n in asked},
        "field": field,
        # the code of the methods ranked against: blurlab's own (a built-in's digest)
        "field_digest": identity.code_digest(ctx.shader_dir),
        "categories": {},
        "images": {},  # per category: its first scene's pictures (category_images_html)
        "run": {},
    }
    images: dict[str, dict] = {}
    looks: dict[str, str] = {}  # per category: its comparator's HTML (card.html only)
    start = time.perf_counter()
    resumed = 0
    seconds = {}
    for category in d.categories():
        began = time.perf_counter()
        entry, table, count = _run_category(
            ctx, category, preset, everyone, out, authored.get(category.name), cluster, progress
        )
        resumed += count
        if table is not None:
            entry["methods"] = figures.category_figures(
                table, category.metrics, category.primary, asked, field
            )
            if pictures and category.kind == d.FRAMES:
                files = authored.get(category.name, ([], None))[0]
                images[category.name], looks[category.name] = _pictures(
                    ctx, category, preset, entry, out, files
                )
        card["categories"][category.name] = entry
        seconds[category.name] = round(time.perf_counter() - began, 3)
    if captures:
        began = time.perf_counter()
        card["categories"][captured.NAME] = _captured_category(
            ctx, captures, list(captured_digests), asked, field
        )
        seconds[captured.NAME] = round(time.perf_counter() - began, 3)
    card["images"] = images
    card["run"] = {
        "wall_s": round(time.perf_counter() - start, 3),
        "category_s": seconds,
        "resumed_rows": resumed,
        "rows_taken_from_field_card": taken,
    }
    io.write_text(out / "card.json", json.dumps(card, indent=1, sort_keys=False) + "\n")
    io.write_text(out / "card.html", page.card_html(card, looks))
    return card


def _run_category(ctx, category, preset, names, out: Path, files, cluster, progress):
    """(card entry, rows or None, rows resumed) of one category; `files`: authored_paths' answer
    for a category of files."""
    chosen = category.at(preset)
    entry = {"status": "measured", "doc": category.doc, "primary": category.primary}
    items: list = list(chosen.scenes)
    if category.needs_assets:
        items, why = files
        if why is not None:
            return {**entry, "status": "skipped", "reason": why}, None, 0
    rows = out / "rows"
    rows.mkdir(exist_ok=True)
    if category.kind == d.SEQUENCE:
        table, resumed = run_sequences(
            ctx, category, preset, names, rows / f"{category.name}.jsonl"
        )
        entry["scenes"] = list(chosen.scenes)
        return entry, table, resumed
    table = sweep(
        None if cluster is not None else ctx,
        [scenes.get(item) if not isinstance(item, Path) else scenes.gltf(item) for item in items],
        {name: {} for name in names},
        size=chosen.size,
        reference_samples=chosen.reference_samples,
        metrics=category.metrics,
        out=rows / f"{category.name}.csv",
        progress=progress,
        cluster=cluster,
    )
    entry["scenes"] = list(chosen.scenes)
    return entry, table, int(table.attrs.get("resumed", 0))


def _captured_category(ctx, captures, labels, asked, field) -> dict:
    """The captured category's card entry (`labels`: the captures' names, as their digests
    were taken): the methods that run on a captured G-buffer, ranked against the built-in
    methods that do; the others are named with the reason."""
    field_kept, left_out = captured.runnable(field)
    asked_kept, _ = captured.runnable(asked)
    entry = {
        "status": "measured",
        "doc": captured.DOC,
        "primary": captured.PRIMARY,
        "scenes": labels,
        "left_out": {n: why for n, why in left_out.items() if n in asked},
    }
    if not asked_kept:
        return {**entry, "status": "skipped", "reason": "no method asked runs on a capture"}
    names = field_kept + [n for n in asked_kept if n not in field_kept]
    table = captured.captured_rows(ctx, captures, names)
    entry["methods"] = figures.category_figures(
        table, captured.metrics(), captured.PRIMARY, asked_kept, field_kept
    )
    return entry


def _pictures(ctx, category, preset, entry: dict, out: Path, files) -> tuple[dict, str]:
    """({label: PNG path relative to OUT}, the comparator's HTML): the reference and each card
    method's output, with the best built-in method, on the category's first scene at its
    settings (tone-mapped with the reference's exposure where the category is HDR); the
    comparator shows the same outputs beside the reference, zoomable to single pixels, with
    an exposure control where the category is HDR (pictures in OUT/look/)."""
    chosen = category.at(preset)
    first = chosen.scenes[0]
    scene = scenes.gltf(files[0]) if category.needs_assets else scenes.get(first)
    reference = ctx.reference(
        scene,
        chosen.size,
        scene.shutter,
        samples=chosen.reference_samples,
        progress=False,
        antialias=category.antialias,
        **REFERENCE_OPTIONS,
    ).color
    hdr = get(category.primary).hdr
    scale = exposure(reference) if hdr else None
    folder = out / "images" / category.name
    folder.mkdir(parents=True, exist_ok=True)
    shown = list(entry["methods"])
    shown += [b for b in (m["versus"] for m in entry["methods"].values()) if b not in shown]
    paths = {"reference": _write(folder / "reference.png", reference, scale)}
    outputs = {}
    frames = {}  # one G-buffer per instant the shown methods read
    for name in shown:
        instant = method_instant(name, {})
        if instant not in frames:
            frames[instant] = ctx.render(scene, chosen.size, scene.shutter, instant=instant)
        outputs[name] = blur(ctx, frames[instant], name, timed=False).color
        paths[name] = _write(folder / f"{name}.png", outputs[name], scale)
    if hdr:  # the comparator's exposure control needs the linear colours: pictures of its own
        look, _ = comparator.write_comparator(
            category.name, reference, outputs, out, hdr=True, exposure=scale
        )
    else:  # the comparator shows the card's own pictures, beside their error maps
        look = _comparator_of_pictures(category.name, reference, outputs, paths, folder, out)
    pictures = {
        "scene": scenes.label(first),
        "images": {k: v.relative_to(out).as_posix() for k, v in paths.items()},
    }
    return pictures, look


def _comparator_of_pictures(name, reference, outputs, paths, folder: Path, out: Path) -> str:
    """The comparator of an SDR category over the pictures `paths` already written: each
    output's error map (as the comparator draws them, on one scale) is written beside them."""
    errors = {who: error_map(reference[..., :3], color[..., :3]) for who, color in outputs.items()}
    vmax = plots.error_scale(errors.values())
    files = {}
    for who, error in errors.items():
        error_png = io.write(folder / f"{who}_error.png", plots.error_colours(error, vmax))
        files[who] = (paths[who].relative_to(out).as_posix(), error_png.relative_to(out).as_posix())
    height, width = reference.shape[:2]
    relative = paths["reference"].relative_to(out).as_posix()
    return comparator.comparator_of_files(name, (width, height), relative, files, vmax)


def _write(path: Path, color: np.ndarray, scale: float | None) -> Path:
    rgb = np.asarray(color)[..., :3]
    return io.write(path, plots.tone_mapped(rgb, scale) if scale is not None else rgb)


def card_rows(card: dict) -> pd.DataFrame:
    """A card's figures as one row per (category, method): the primary metric's median and
    interval, rank, win rate, the method it was measured against, and ms."""
    rows = []
    for name, entry in card["categories"].items():
        for who, f in entry.get("methods", {}).items():
            primary = f["metrics"][entry["primary"]]
            rows.append(
                {
                    "category": name,
                    "method": who,
                    "metric": entry["primary"],
                    "median": primary["median"],
                    "low": primary["low"],
                    "high": primary["high"],
                    "rank": f"{f['rank']} of {f['of']}",
                    "versus": f["versus"],
                    "win_rate": f["win_rate"],
                    "ms": f["ms"],
                }
            )
    return pd.DataFrame(rows)
