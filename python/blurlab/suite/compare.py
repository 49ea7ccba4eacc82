"""`blurlab suite compare CARD...` (docs/spec.md §24.4): cards of the same suite (the same
version, preset and hash) side by side, one table per category. Cards of other suites are
refused with the hashes that differ and the part (definition, scenes, code) that makes them
differ."""

from __future__ import annotations

import json
from pathlib import Path

import pandas as pd

from .run import CARD_FORMAT, card_rows

MAX_CARD_BYTES = 64 << 20  # a card of every method at the gpu preset is far smaller


def load_card(path) -> dict:
    """A card.json (or a folder holding one), checked to be a card this blurlab reads."""
    path = Path(path)
    if path.is_dir():
        path = path / "card.json"
    if not path.is_file():
        raise ValueError(f"blurlab suite: no card at {path} (give card.json or its folder)")
    if path.stat().st_size > MAX_CARD_BYTES:
        raise ValueError(f"blurlab suite: {path} is larger than any card ({MAX_CARD_BYTES} bytes)")
    try:
        card = json.loads(path.read_text(encoding="utf-8"))
    except (UnicodeDecodeError, json.JSONDecodeError) as error:
        raise ValueError(f"blurlab suite: {path} is not a card's JSON: {error}") from None
    if not isinstance(card, dict) or card.get("format") != CARD_FORMAT:
        raise ValueError(
            f"blurlab suite: {path} is not a suite card of format {CARD_FORMAT} "
            "(blurlab suite run writes one)"
        )
    for key in ("suite", "device", "date", "categories", "methods"):
        if key not in card:
            raise ValueError(f"blurlab suite: the card {path} lacks {key!r}")
    card["path"] = str(path)
    return card


def check_same_suite(cards: list[dict]) -> None:
    """Raises, naming each card's suite hash and the parts that differ, unless all are one."""
    first = cards[0]["suite"]
    for card in cards[1:]:
        suite = card["suite"]
        if suite["hash"] == first["hash"]:
            continue
        parts = [
            p for p in first.get("parts", {}) if first["parts"][p] != suite.get("parts", {}).get(p)
        ]
        raise ValueError(
            "blurlab suite: the cards measured other suites: "
            f"{cards[0]['path']} has v{first['version']} {first['preset']} hash {first['hash']}, "
            f"{card['path']} has v{suite['version']} {suite['preset']} hash {suite['hash']}"
            + (f" (they differ in: {', '.join(parts)})" if parts else "")
            + "; compare cards of one suite version and preset, made by the same code of the "
            "references and metrics"
        )


def compare(paths) -> dict[str, pd.DataFrame]:
    """{category: table}: each card's methods with the category's primary median, interval,
    rank, win rate and ms, one row per (card, method), labelled by method, device and date."""
    paths = list(paths)
    if len(paths) < 2:
        raise ValueError("blurlab suite compare: give at least two cards")
    cards = [load_card(p) for p in paths]
    check_same_suite(cards)
    tables: dict[str, list] = {}
    for card in cards:
        try:
            rows = card_rows(card)
        except (KeyError, TypeError, IndexError) as error:  # a card edited by hand, or cut
            raise ValueError(
                f"blurlab suite: the card {card['path']} lacks a figure ({error!r}); "
                "write it again with blurlab suite run"
            ) from None
        if rows.empty:
            continue
        rows.insert(2, "device", card["device"]["renderer"])
        rows.insert(3, "date", card["date"])
        for category, group in rows.groupby("category", sort=False):
            tables.setdefault(category, []).append(group.drop(columns="category"))
    return {c: pd.concat(parts, ignore_index=True) for c, parts in tables.items()}


def compare_text(paths) -> str:
    """compare() as text: a heading and a table per category, after a note where the cards'
    built-in methods ran other code (their ranks and win rates are against other fields)."""
    tables = compare(paths)
    fields = {load_card(p).get("field_digest") for p in paths}
    chunks = []
    if len(fields) > 1:
        chunks.append(
            "note: the cards' built-in methods ran other code (field digests "
            f"{', '.join(sorted(str(f) for f in fields))}): ranks and win rates are against "
            "other fields\n"
        )
    for category, table in tables.items():
        text = table.to_string(index=False, float_format=lambda v: f"{v:.4g}")
        chunks.append(f"## {category}\n{text}\n")
    return "\n".join(chunks)
