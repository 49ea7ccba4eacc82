"""`blurlab sweep CONFIG`: a sweep described by a TOML file (docs/study.md)."""

from __future__ import annotations

import tomllib
from pathlib import Path

import pandas as pd

from ..core.context import Context
from ..scene import scenes
from ..sizes import DEFAULT_SIZE
from .sweep import sweep


def load_config(path: str | Path) -> dict:
    """A sweep configuration (TOML): scenes, methods = {name = {param = [values]}}, size, shutter,
    reference_samples, metrics, out."""
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"blurlab sweep: no such configuration file: {path}")
    try:
        config = tomllib.loads(path.read_text())
    except tomllib.TOMLDecodeError as error:
        raise ValueError(f"blurlab sweep: {path} is not valid TOML: {error}") from None
    allowed = {"scenes", "methods", "size", "shutter", "reference_samples", "metrics", "out"}
    unknown = set(config) - allowed
    if unknown:
        raise ValueError(
            f"blurlab sweep: unknown keys {sorted(unknown)}; allowed: {sorted(allowed)}"
        )
    return config


def run_sweep_config(
    ctx: Context | None, path: str | Path, progress: bool = True, cluster=None
) -> pd.DataFrame:
    """Runs the sweep of a TOML file, on `ctx` or (ctx=None) on a Dask `cluster`."""
    config = load_config(path)
    out = config.get("out", str(Path(path).with_suffix(".csv")))
    return sweep(
        ctx,
        config.get("scenes", scenes.names()),
        config.get("methods"),
        tuple(config.get("size", DEFAULT_SIZE)),
        config.get("shutter"),
        config.get("reference_samples"),
        tuple(config.get("metrics", ("psnr",))),
        out=out,
        progress=progress,
        cluster=cluster,
    )


__all__ = ["load_config", "run_sweep_config"]
