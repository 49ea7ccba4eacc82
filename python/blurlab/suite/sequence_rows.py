"""The suite's sequence category (docs/spec.md §24.1): each method before TAA over a sequence of
each scene, one row per measured frame, kept in a keyed file so that a run resumes.

A sequence is run by temporal.sequences (frames, jitter, TAA, references) and measured by its
GPU reductions (per-frame MSE, and the temporal instability of each frame against the one
before, §21.3). Each (scene, method) is one line of `rows/sequences.jsonl`, keyed by a hash of
what determines its numbers (as sweeps key rows: blurlab.studies.identity); a line cut short
by a crash is ignored and its run made again.
"""

from __future__ import annotations

import json
from pathlib import Path

import pandas as pd

from .. import metrics
from ..methods import method
from ..scene import scenes
from ..studies import identity
from ..studies.sweep import drop_partial_line
from ..temporal.sequences import sequence
from . import definition as d


def _key(scene, scene_name: str, name: str, settings: dict, device: dict) -> str:
    return identity.row_identity(
        {
            "scene": scene_name,
            identity.SCENE_DIGEST: identity.scene_digest(scene),
            "method": name,
            "backend": method(name).backends[0],
            "params": "{}",
            "sequence": settings,
            **device,
            identity.VERSION: identity.version(),
        }
    )


def _finished(path: Path) -> dict:
    """{key: entry} of the file's whole lines."""
    if path.exists():
        drop_partial_line(path)  # so that the next line starts on a line of its own
    return read_runs(path)


def read_runs(path: Path) -> dict:
    """{key: entry} of a sequence rows file's whole lines (none where it does not exist); the
    file is only read."""
    done = {}
    if path.exists():
        for line in path.read_text().splitlines():
            try:
                entry = json.loads(line)
            except json.JSONDecodeError:  # not a whole entry: made again
                continue
            if isinstance(entry, dict) and isinstance(entry.get("key"), str):
                done[entry["key"]] = entry
    return done


def run_line(entry: dict) -> str:
    """A run's entry as its line of the rows file."""
    return json.dumps(entry, sort_keys=True, separators=(",", ":")) + "\n"


def _append(path: Path, entry: dict) -> None:
    """One write of one whole line: an interrupt leaves finished lines only."""
    with path.open("ab", buffering=0) as f:
        f.write(run_line(entry).encode())


def run_sequences(ctx, category: d.Category, preset: str, names: list[str], path: Path):
    """(table, resumed): one row per (scene, frame, method) of the measured frames, with psnr,
    temporal_instability and the method's ms that frame; and how many (scene, method) runs
    came from `path` rather than being run."""
    chosen = category.at(preset)
    plan = category.sequences
    frames, warmup = plan.frames[preset], plan.warmup[preset]
    settings = category.settings(preset)
    device = identity.device_identity(ctx)
    path.parent.mkdir(parents=True, exist_ok=True)
    done = _finished(path)
    resumed = 0
    rows = []
    for scene_name in chosen.scenes:
        scene = scenes.get(scene_name)
        keys = {name: _key(scene, scene_name, name, settings, device) for name in names}
        missing = [name for name in names if keys[name] not in done]
        resumed += len(names) - len(missing)
        if missing:
            seq = sequence(
                ctx,
                scene,
                chosen.size,
                plan.fps,
                warmup + frames,
                plan.shutter_angle,
                reference_samples=chosen.reference_samples,
                antialias=category.antialias,
            )
            for name in missing:
                run = seq.run(name, plan.order, metrics=("psnr",))
                entry = {
                    "key": keys[name],
                    "scene": scene_name,
                    "method": name,
                    "mse": run.frame_mse[warmup:].tolist(),
                    "temporal_instability": run.pair_instability[warmup:].tolist(),
                    "ms": run.blur_ms[warmup:].tolist(),
                    "clock": ctx.info()["timer"],
                }
                _append(path, entry)
                done[keys[name]] = entry
            del seq  # its references go back to the pool before the next scene's
        for name in names:
            rows += _frame_rows(done[keys[name]], scene_name, name)
    return pd.DataFrame(rows), resumed


def _frame_rows(entry: dict, scene_name: str, name: str) -> list[dict]:
    """One row per measured frame; the first frame's instability pairs it with the last
    warm-up frame. A frame is named "scene@i", the unit the statistic is taken over."""
    rows = []
    for i, (mse, unstable, ms) in enumerate(
        zip(entry["mse"], entry["temporal_instability"], entry["ms"], strict=True)
    ):
        rows.append(
            {
                "scene": f"{scene_name}@{i}",
                "method": name,
                "params": "{}",
                "psnr": metrics.psnr_from_mse(mse),
                "temporal_instability": unstable,
                "total_ms": ms,
                "clock": entry["clock"],
            }
        )
    return rows
