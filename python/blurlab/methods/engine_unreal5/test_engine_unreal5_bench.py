"""engine_unreal5 in the engines benchmark (benchmarks/blurlab_bench/quality.py): its
reconstruct pass is timed by tile class, and the classes' tiles add up to the frame's tiles
(what every method's per-pass rows share: tests/test_bench.py)."""

from __future__ import annotations

import blurlab_bench as bench

METHOD = "engine_unreal5"


def test_the_reconstruct_pass_is_timed_by_tile_class(ctx):
    given = {"methods": METHOD, "film_filter": 0.0}
    record = bench.run_benchmark(ctx, "engines", "tiny", given=given)
    figures = {f["name"] for f in record["figures"]}
    assert f"{METHOD}: median ms, reconstruct[gather]" in figures
    # thin_bar at 64 x 36 has 4 x 3 tiles of 16 px
    table = next(t for t in record["tables"] if t["name"].startswith("each pass"))
    rows = [r for r in table["rows"] if r[1] == METHOD and r[2] == "reconstruct"]
    assert {r[3] for r in rows} >= {"skip", "uniform", "gather"}
    assert sum(r[4] for r in rows) == 12 and all(r[5] >= 0 for r in rows)
