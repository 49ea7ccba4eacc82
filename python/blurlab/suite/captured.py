"""The suite's captured category (docs/spec.md §24.1): captured frames join the suite when they
are given. Each capture is an engine's G-buffer (one EXR or a pattern of them,
blurlab.io.capture) with a reference of the same shutter from files, as `blurlab study
--capture` reads them (§16.6). Every method that runs on a captured G-buffer is scored on every
frame at its declared defaults; a frame is a unit of the card's statistics. The captures'
bytes are part of the suite's hash, so cards with other captures, or none, do not compare."""

from __future__ import annotations

import dataclasses
import hashlib

import pandas as pd

from ..core.render import check_size
from ..studies import capture_study, identity
from ..studies.evaluation import Settings

NAME = "captured"
PRIMARY = "psnr"
DOC = (
    "An engine's captured G-buffers (colour, depth, motion) against references of the same "
    "shutter from files, scored per frame; given to `blurlab suite run --capture`"
)
TIMED_RUNS = 3


@dataclasses.dataclass(frozen=True)
class Capture:
    """One captured shot: its G-buffer files and its reference's (a file or a `####` pattern
    each), read in `convention` with `shutter_fraction` (bl.capture.sequence)."""

    capture: str
    reference: str
    convention: str = "blurlab"
    shutter_fraction: float = 1.0


def captures_of(captures, references, convention="blurlab", shutter_fraction=1.0) -> list:
    """Captures pairing each of `captures` with the reference at the same place in
    `references`; an error where the counts differ."""
    captures, references = list(captures or ()), list(references or ())
    if len(captures) != len(references):
        raise ValueError(
            f"blurlab suite: {len(captures)} capture(s) and {len(references)} reference(s): "
            "each --capture needs its --reference, in the same order"
        )
    pairs = zip(captures, references, strict=True)
    return [Capture(str(c), str(r), convention, shutter_fraction) for c, r in pairs]


def opened(given: Capture):
    """(capture, reference) sequences of `given`, checked against each other: an error names
    the file that is missing, of another size or of another frame count."""
    shot, reference, _ = capture_study.open_inputs(
        given.capture,
        given.reference,
        convention=given.convention,
        shutter_fraction=given.shutter_fraction,
    )
    return shot, reference


def digests(captures: list[Capture]) -> dict[str, str]:
    """{label: digest of the capture's and the reference's files and how they are read}, the
    part of the suite's hash the captures make."""
    out = {}
    for given in captures:
        shot, reference = opened(given)
        h = hashlib.sha256(f"{given.convention}:{given.shutter_fraction}".encode())
        for path in (*shot.paths, *reference.paths):
            h.update(path.name.encode() + b"\0" + path.read_bytes())
        label = capture_study.shot_label(shot)
        if label in out:
            raise ValueError(f"blurlab suite: two captures are named {label!r}; rename one")
        out[label] = h.hexdigest()[: identity.HASH_CHARS]
    return out


def runnable(names) -> tuple[list[str], dict[str, str]]:
    """(the methods of `names` whose defaults run on a captured G-buffer, {method: why not})."""
    kept, left_out = capture_study.capture_grids({name: {} for name in names})
    return [n for n in names if n in kept], left_out


def metrics() -> tuple[str, ...]:
    """The category's metrics: the study's LDR defaults against one reference."""
    return capture_study.capture_metrics(None, 1)


def captured_rows(ctx, captures: list[Capture], names) -> pd.DataFrame:
    """One row per (capture frame, method) for `names` (each runnable), the frame named
    "label@frame" where a capture has more than one: the unit the card's statistics take."""
    rows = []
    for given in captures:
        shot, reference = opened(given)
        size = check_size(shot.size(), ctx.max_texture_size)
        settings = Settings(size, None, 0, metrics(), TIMED_RUNS, readback_batch=16)
        label = capture_study.shot_label(shot)
        kept = {name: [{}] for name in names}
        found, _ = capture_study.method_rows(ctx, shot, reference, kept, settings, label, 0)
        for row in found:
            if len(shot) > 1:
                row["scene"] = f"{label}@{row['frame']}"
            rows.append(row)
    return pd.DataFrame(rows)
