"""The Pareto chart keeps 20 and more methods apart, each series by its own colour and marker,
and its front's labels do not overlap; `blurlab --help` names every command."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pandas as pd
import pytest

from blurlab import cli
from blurlab.studies import plots

METHODS = 24


def many_methods_table() -> pd.DataFrame:
    """METHODS methods of three configurations each, crowded near one another, and the front
    climbing in small steps so that its labels would pile up unmoved."""
    rng = np.random.default_rng(7)
    rows = []
    for m in range(METHODS):
        for k in (4, 8, 16):
            rows.append(
                {"scene": "s", "method": f"method_{m:02d}", "param_k": float(k),
                 "total_ms": 1.0 + 0.02 * m + 0.001 * k + rng.random() * 1e-3,
                 "psnr": 30.0 + 0.05 * m + 0.01 * k, "clock": "wall_glfinish",
                 "renderer": "llvmpipe", "width": 160, "height": 90}
            )  # fmt: skip
    return pd.DataFrame(rows)


def test_every_series_has_its_own_colour_and_marker_and_no_labels_overlap():
    fig = plots.pareto(many_methods_table(), "s")
    ax = fig.axes[0]
    styles = set()
    for collection in ax.collections:
        colour = tuple(np.round(collection.get_facecolor()[0][:3], 3))
        marker = tuple(map(tuple, np.round(collection.get_paths()[0].vertices, 3)))
        styles.add((colour, marker))
    assert len(ax.collections) == METHODS and len(styles) == METHODS
    colours = {c for c, _ in styles}
    markers = {m for _, m in styles}
    assert len(colours) >= 10 and len(markers) >= 3  # apart by both, not by one alone
    renderer = fig.canvas.get_renderer()
    boxes = [t.get_window_extent(renderer) for t in ax.texts]
    assert len(boxes) >= 20  # the front's labels, most of them crowded
    overlapping = [
        (i, j) for i in range(len(boxes)) for j in range(i) if boxes[i].overlaps(boxes[j])
    ]
    assert not overlapping, [
        (ax.texts[i].get_text(), ax.texts[j].get_text()) for i, j in overlapping
    ]
    plots._pyplot().close(fig)


def test_series_styles_are_distinct_up_to_the_limit():
    limit = len(plots.COLOURS) * len(plots.MARKERS)
    assert len({plots.series_style(i) for i in range(limit)}) == limit
    with pytest.raises(ValueError, match="at most"):
        plots.series_style(limit)


def test_help_names_every_command():
    commands = list(cli.build_parser()._subparsers._group_actions[0].choices)
    assert "recommend" in commands
    result = subprocess.run(
        [sys.executable, "-m", "blurlab", "--help"], capture_output=True, text=True
    )
    assert result.returncode == 0
    summary = " ".join(result.stdout.split("positional arguments:")[0].split())
    for command in commands:
        assert f" {command}," in summary or f" {command}." in summary, command
