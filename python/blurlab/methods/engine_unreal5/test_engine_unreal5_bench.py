"""engine_unreal5's reconstruct pass timed by tile class, as the engines benchmark shows it
(benchmarks/blurlab_bench/quality.py's pass_rows; what every method's per-pass rows share:
tests/test_bench.py): its classes' tiles add up to the frame's tiles."""

from __future__ import annotations

import blurlab as bl

METHOD = "engine_unreal5"


def test_the_reconstruct_pass_is_timed_by_tile_class(ctx):
    frame = ctx.render(bl.scenes.get("thin_bar"), (64, 36))  # the benchmark's tiny scene
    result = bl.blur(ctx, frame, METHOD)
    row = result.textures["tile_counts"].download()[0, :, 0]
    counts = dict(zip(bl.method(METHOD).tile_lists, row[::4].tolist(), strict=True))
    classes = [
        key.partition("[")[2].rstrip("]")
        for key in result.timings
        if key.startswith("reconstruct[")
    ]
    assert set(classes) >= {"skip", "uniform", "gather"}
    # thin_bar at 64 x 36 has 4 x 3 tiles of 16 px
    assert sum(counts[cls] for cls in classes) == 12
    assert all(result.timings[f"reconstruct[{cls}]"].ms >= 0 for cls in classes)
