"""Rows of an earlier card taken into a new one (`blurlab suite run --field-from CARD`,
docs/spec.md §24.4): a card for one new method then evaluates that method's rows only, and
takes the built-in field's rows, which rank it, from a card already made on the same device.

Rows are copied, never trusted: a row is used only where its key is one the new run would
make (scene content, method, parameters, size, shutter, reference, metric set, device and
code), so rows of other code, another device or another suite are carried along and ignored.
"""

from __future__ import annotations

import csv
import io
from pathlib import Path

from ..io import images as files
from ..studies.identity import IDENTITY
from .sequence_rows import read_runs, run_line


def take_rows(out: Path, card) -> int:
    """Adds to OUT/rows the rows of the card folder `card` (an earlier `suite run --out`)
    whose keys OUT does not hold yet; returns how many. Each file is rewritten atomically;
    a row cut short by an interrupted run is left out."""
    source = Path(card) / "rows"
    if not source.is_dir():
        raise ValueError(
            f"blurlab suite: --field-from {card}: no rows/ folder there; give the --out folder "
            "of an earlier `blurlab suite run`"
        )
    target = Path(out) / "rows"
    target.mkdir(parents=True, exist_ok=True)
    if source.resolve() == target.resolve():
        return 0
    added = 0
    for path in sorted(source.iterdir()):
        if path.suffix == ".csv":
            added += _take_csv(path, target / path.name)
        elif path.suffix == ".jsonl":
            added += _take_lines(path, target / path.name)
    return added


def _csv_rows(path: Path) -> tuple[list[str], list[dict]]:
    """(header, whole rows) of a sweep's rows file; none where it does not exist."""
    if not path.exists():
        return [], []
    with path.open(newline="", encoding="utf-8") as f:
        reader = csv.DictReader(f)
        header = list(reader.fieldnames or [])
        rows = [r for r in reader if None not in r and None not in r.values() and r.get(IDENTITY)]
    return header, rows


def _take_csv(source: Path, target: Path) -> int:
    header, rows = _csv_rows(target)
    their_header, theirs = _csv_rows(source)
    held = {r[IDENTITY] for r in rows}
    new = [r for r in theirs if r[IDENTITY] not in held]
    if not new:
        return 0
    header += [c for c in their_header if c not in header]
    text = io.StringIO()
    writer = csv.DictWriter(text, header, restval="")
    writer.writeheader()
    writer.writerows(rows + new)
    files.write_text(target, text.getvalue())
    return len(new)


def _take_lines(source: Path, target: Path) -> int:
    mine = read_runs(target)
    new = {k: e for k, e in read_runs(source).items() if k not in mine}
    if new:
        text = "".join(run_line(e) for e in (*mine.values(), *new.values()))
        files.write_text(target, text)
    return len(new)
