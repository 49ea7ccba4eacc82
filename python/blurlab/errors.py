"""What every error message shares: it starts with one owner ("blurlab.scene.gltf: ",
"blurlab: ") and
says its cause once. A message that quotes another error quotes its cause, not its owner."""

from __future__ import annotations

import re

_OWNER = re.compile(r"^blurlab[\w. ]*: ")


def cause(error: BaseException | str) -> str:
    """`error`'s message without the owner it starts with, to quote inside a message that names
    its own."""
    return _OWNER.sub("", str(error))


def bad_byte(error: UnicodeDecodeError) -> str:
    """Where a text is not UTF-8, in words that do not say "utf-8" again."""
    return f"byte 0x{error.object[error.start]:02x} at {error.start} ({error.reason})"
