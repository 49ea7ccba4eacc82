"""Helpers shared by the benchmark scripts: device description and result records."""

from __future__ import annotations

import datetime
import json
import platform
import statistics
from pathlib import Path


def open_context(device: str):
    """The blurlab Context a benchmark's --device names: auto, gpu, software or an EGL index."""
    import blurlab as bl

    return bl.Context(int(device) if device.isdigit() else device)


def describe(ctx) -> dict:
    """Which device measured: renderer, GL version, timer clock, host."""
    info = ctx.info()
    return {
        "date": datetime.date.today().isoformat(),
        "device": info["device"],
        "renderer": info["renderer"],
        "gl_version": info["version"],
        "timer": info["timer"],
        "host_cpu": platform.processor() or platform.machine(),
    }


def summarize(samples_ms: list[float]) -> dict:
    return {
        "median_ms": statistics.median(samples_ms),
        "min_ms": min(samples_ms),
        "runs": len(samples_ms),
    }


def save(path: str | None, record: dict) -> None:
    if path:
        Path(path).parent.mkdir(parents=True, exist_ok=True)
        Path(path).write_text(json.dumps(record, indent=2))
