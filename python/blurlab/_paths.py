"""Where blurlab finds its GLSL files, and where it keeps what it can make again."""

from __future__ import annotations

import os
from pathlib import Path

_PACKAGE = Path(__file__).resolve().parent


def shader_dir() -> Path:
    """The folder of blurlab's shaders.

    In order: the ``BLURLAB_SHADER_DIR`` variable; ``shaders/`` inside the installed package;
    the repository's ``shaders/`` when running from a source checkout (editable installs), so
    that edits to a shader take effect without reinstalling.
    """
    override = os.environ.get("BLURLAB_SHADER_DIR")
    candidates = [Path(override)] if override else []
    candidates += [_PACKAGE / "shaders", _PACKAGE.parents[1] / "shaders"]
    for folder in candidates:
        if (folder / "common").is_dir():
            return folder
    raise FileNotFoundError(
        "blurlab: no shader folder found; looked in "
        + ", ".join(str(c) for c in candidates)
        + ". Reinstall blurlab (pip install .) or set BLURLAB_SHADER_DIR."
    )


def cache_root() -> Path:
    """The folder where blurlab keeps what it can make again (recommend's sweeps, the private
    environment of Blender's bpy): ``BLURLAB_CACHE_DIR``, else ``$XDG_CACHE_HOME/blurlab``,
    else ``~/.cache/blurlab``."""
    override = os.environ.get("BLURLAB_CACHE_DIR")
    if override:
        return Path(override)
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "blurlab"
