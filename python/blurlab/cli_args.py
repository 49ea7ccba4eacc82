"""Argument types the blurlab subcommands share: sizes and a glTF file's animations."""

from __future__ import annotations

import argparse

from .sizes import DEFAULT_SIZE

DEFAULT_SIZE_TEXT = "{}x{}".format(*DEFAULT_SIZE)
SIZE_HELP = f"WxH (default {DEFAULT_SIZE_TEXT})"


def parse_size(text: str) -> tuple[int, int]:
    """'WxH' -> (W, H)."""
    try:
        width, height = (int(part) for part in text.lower().split("x"))
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"size must look like {DEFAULT_SIZE_TEXT}, not {text!r}"
        ) from None
    if width < 1 or height < 1:
        raise argparse.ArgumentTypeError(f"size must be positive, not {text!r}")
    return width, height


def parse_animation(text: str):
    """--animation: "all", "none" (the rest pose), or indices and names separated by commas
    (blurlab.scene.gltf.load's `animation`)."""
    if text in ("all", "none"):
        return None if text == "none" else text
    items = [int(part) if part.strip().isdigit() else part.strip() for part in text.split(",")]
    return items[0] if len(items) == 1 else items
