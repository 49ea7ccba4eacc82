"""Sweeps: the table's columns and rows, resuming without duplicates, keeping rows when
interrupted, TOML configurations, and the study's report."""

from __future__ import annotations

import importlib
import json
import os
import re

import pandas as pd
import pytest
from method_picks import EXAMPLE, pick, picks

import blurlab as bl
from blurlab import cli

sw = importlib.import_module("blurlab.studies.sweep")  # the module; bl.sweep is the function
evaluation = importlib.import_module("blurlab.studies.evaluation")

# A tile filter with k and samples, and a gather with taps.
FILTER = EXAMPLE
GATHER = pick(kind="gather", params=("taps",))
GRID = {FILTER: {"k": [8, 16], "samples": [5, 9]}, GATHER: {"taps": [4]}}
SIZE = (64, 36)


def test_table_has_one_row_per_evaluation_and_every_column(ctx, tmp_path):
    table = sw.sweep(
        ctx,
        ["fan", "teapot_pass"],
        GRID,
        SIZE,
        reference_samples=16,
        out=tmp_path / "r.csv",
        progress=False,
    )
    assert len(table) == 2 * (4 + 1)
    for column in (
        "scene",
        "method",
        "backend",
        "param_k",
        "param_samples",
        "param_taps",
        "ms_tile_max",
        "ms_reconstruct",
        "total_ms",
        "clock",
        "psnr",
        "ssim",
        "flip",
        "device",
        "width",
        "height",
        "reference_samples",
    ):
        assert column in table.columns, column
    assert "ms_neighbor_max" in table.columns  # a pass of its own (docs/spec.md §3.6)
    frame = ctx.render(bl.scenes.fan(), SIZE, instant=bl.method_instant(GATHER, {"taps": 4}))
    for timing in bl.blur(ctx, frame, GATHER, taps=4).timings:  # the gather's passes
        assert f"ms_{timing}" in table.columns, timing
    assert (table["reference_samples"] == 16).all()
    assert table["psnr"].between(10, 80).all() and table["flip"].between(0, 1).all()
    assert len(pd.read_csv(tmp_path / "r.csv")) == len(table)


def test_resume_adds_no_duplicates(ctx, tmp_path):
    out = tmp_path / "r.csv"
    first = sw.sweep(
        ctx,
        ["fan"],
        {GATHER: {"taps": [4, 8]}},
        SIZE,
        reference_samples=8,
        metrics=("psnr",),
        out=out,
        progress=False,
    )
    table = sw.sweep(
        ctx, ["fan"], GRID, SIZE, reference_samples=8, metrics=("psnr",), out=out, progress=False
    )
    saved = pd.read_csv(out)
    assert len(saved) == 6 and not saved.duplicated(["scene", "method", "params"]).any()
    assert len(table) == 5  # what this sweep asked for, the earlier rows included
    # each call says how many of its rows it read from the file instead of evaluating
    assert first.attrs["resumed"] == 0 and table.attrs["resumed"] == 1


def test_on_scene_is_called_once_a_scene_is_evaluated_with_its_cache(ctx, tmp_path):
    # what the study begins its pictures from while the GPU goes on with the next scene
    out, seen = tmp_path / "s.csv", []

    def on_scene(scene, cache):
        rows = pd.read_csv(out)
        seen.append((scene.name, int((rows["scene"] == scene.name).sum()), "reference" in cache))

    arguments = dict(reference_samples=8, metrics=("psnr",), out=out, progress=False)
    grid = {GATHER: {"taps": [4, 8]}}
    sw.sweep(ctx, ["fan", "teapot_pass"], grid, SIZE, on_scene=on_scene, **arguments)
    # each scene's rows are written before it is announced, and its reference is in its cache
    assert seen == [("fan", 2, True), ("teapot_pass", 2, True)]
    seen.clear()
    sw.sweep(ctx, ["fan", "teapot_pass"], grid, SIZE, on_scene=on_scene, **arguments)
    assert seen == []  # nothing was evaluated: every row came from the file


def test_finished_rows_keep_every_bit_when_the_file_gains_columns(ctx, tmp_path):
    # 27.001846454071572 is a value the default float parser of pandas before 3.1 reads one
    # unit in the last place off; a rewrite that parsed and formatted the old rows changed it
    out = tmp_path / "r.csv"
    options = {"reference_samples": 8, "metrics": ("psnr",), "out": out, "progress": False}
    sw.sweep(ctx, ["fan"], {GATHER: {"taps": [4]}}, SIZE, **options)
    header, row = out.read_text().splitlines()
    psnr = header.split(",").index("psnr")
    fields = row.split(",")
    fields[psnr] = "27.001846454071572"
    out.write_text(f"{header}\n{','.join(fields)}\n")
    table = sw.sweep(ctx, ["fan"], GRID, SIZE, **options)  # mcguire2012's rows add columns
    lines = out.read_text().splitlines()
    assert len(lines) == 6 and len(lines[0].split(",")) > len(header.split(","))
    assert lines[1].startswith(",".join(fields))  # the old row's text, unchanged
    box = table[table["method"] == GATHER]["psnr"]
    assert box.tolist() == [27.001846454071572]
    assert sw.read_row_file(out)["psnr"].tolist()[0] == 27.001846454071572


def test_interrupted_sweep_keeps_finished_rows(ctx, tmp_path, monkeypatch):
    out = tmp_path / "r.csv"
    calls = {"n": 0}
    real = evaluation.blur_steps

    def interrupt_after_three(*args, **kwargs):
        calls["n"] += 1
        # Per scene: the timing runs (2 warm-ups + 5 timed), then one run per row. Rows are
        # read back two at a time, a batch once the next is issued: after rows 3 and 4, rows 1
        # and 2 are finished and reach the file; the fifth run is interrupted.
        if calls["n"] > 11:
            raise KeyboardInterrupt
        return real(*args, **kwargs)

    def run(**options):
        return sw.sweep(
            ctx,
            ["fan"],
            GRID,
            SIZE,
            reference_samples=8,
            metrics=("psnr",),
            out=out,
            progress=False,
            repeats=1,
            **options,
        )

    monkeypatch.setattr(evaluation, "blur_steps", interrupt_after_three)
    with pytest.raises(KeyboardInterrupt):
        run(readback_batch=2)
    assert len(pd.read_csv(out)) == 2
    monkeypatch.undo()
    table = run()
    assert len(table) == 5 and len(pd.read_csv(out)) == 5


def test_psnr_and_ssim_come_from_one_gpu_pass_equal_to_numpy(ctx, monkeypatch):
    # With SSIM asked for, the sweep takes PSNR and SSIM from gpu_mse_ssim alone (one dispatch,
    # one read-back) against the scene's reference, prepared once; each value must equal
    # metrics.mse and metrics.ssim (NumPy) of the reference and the very image it compared
    # (downloaded here, not by the sweep).
    real, real_prepare = evaluation.m.gpu_mse_ssim, evaluation.m.prepare_reference
    compared, prepared = [], []

    def gpu_and_cpu(ctx_, reference, color):
        assert isinstance(reference, evaluation.m.PreparedReference)
        values = real(ctx_, reference, color)
        a, b = prepared[0], color.download()  # the reference as it was prepared
        compared.append((values, (evaluation.m.mse(a, b), evaluation.m.ssim(a, b))))
        return values

    def prepare(ctx_, reference):
        prepared.append(reference.download())
        return real_prepare(ctx_, reference)

    def separate(*args):
        raise AssertionError("the sweep ran a separate PSNR or SSIM pass")

    monkeypatch.setattr(evaluation.m, "gpu_mse_ssim", gpu_and_cpu)
    monkeypatch.setattr(evaluation.m, "prepare_reference", prepare)
    monkeypatch.setattr(evaluation.m, "gpu_mse", separate)
    monkeypatch.setattr(evaluation.m, "gpu_ssim", separate)
    # Read back per evaluation, through gpu_mse_ssim; test_deferred_readback_gives_the_same_table
    # shows that the batched read-back gives the same bits.
    args = dict(reference_samples=8, metrics=("psnr", "ssim"), progress=False, repeats=1)
    args["readback_batch"] = 1
    table = sw.sweep(ctx, ["fan"], GRID, SIZE, **args)
    assert len(compared) == len(table) == 5 and len(prepared) == 1
    assert list(table["ssim"]) == [gpu[1] for gpu, _ in compared]
    assert list(table["psnr"]) == [evaluation.m.psnr_from_mse(gpu[0]) for gpu, _ in compared]
    for (mse, ssim), (cpu_mse, cpu_ssim) in compared:
        assert mse == pytest.approx(cpu_mse, rel=1e-5)
        assert ssim == pytest.approx(cpu_ssim, abs=1e-5)
    assert table["ssim"].between(0, 1).all() and table["ssim"].nunique() > 1


def test_gpu_flip_column_equals_the_cpu_metric_on_the_same_images(ctx, monkeypatch):
    # The sweep reduces FLIP on the GPU; each value must equal metrics.flip (flip-evaluator) of
    # the very images it compared (downloaded here, not by the sweep), as the CPU column did.
    real = evaluation.m.gpu_flip
    compared = []

    def gpu_and_cpu(ctx_, reference, color):
        value = real(ctx_, reference, color)
        compared.append((value, evaluation.m.flip(reference.download(), color.download())))
        return value

    monkeypatch.setattr(evaluation.m, "gpu_flip", gpu_and_cpu)
    args = dict(reference_samples=8, metrics=("psnr", "flip"), progress=False, repeats=1)
    args["readback_batch"] = 1  # through gpu_flip, as above
    table = sw.sweep(ctx, ["fan"], GRID, SIZE, **args)
    assert len(compared) == len(table) == 5
    assert list(table["flip"]) == [gpu for gpu, _ in compared]
    for gpu, cpu in compared:
        assert gpu == pytest.approx(cpu, abs=1e-4)
    assert table["flip"].between(0, 1).all() and table["flip"].nunique() > 1


def test_no_metric_downloads_the_images(ctx, monkeypatch):
    downloads = []
    real = bl.Texture.download
    monkeypatch.setattr(bl.Texture, "download", lambda t: downloads.append(t.shape) or real(t))
    ctx.render(bl.scenes.fan(), SIZE)
    render = len(downloads)  # the G-buffer's arrays, which every sweep makes once per scene
    args = dict(reference_samples=8, progress=False, repeats=1)
    downloads.clear()
    ldr = ("psnr", "ssim", "flip")  # the HDR metrics run on the CPU: they read images back
    sw.sweep(ctx, ["fan"], {GATHER: {"taps": [4]}}, SIZE, metrics=ldr, **args)
    # FLIP reads back its partial sums, one per 16 x 16 pixels, and nothing else.
    assert downloads[render:] == [(-(-SIZE[1] // 16), -(-SIZE[0] // 16))]


def test_deferred_readback_gives_the_same_table(ctx, monkeypatch):
    # The GPU metrics of 3 evaluations read back together (a last batch of 2), and of each one
    # alone: every column but the timings holds the same bits, in the same order; PSNR, SSIM,
    # FLIP and psnr_aa all come from the queue when batched.
    calls = []
    for name in ("gpu_mse", "gpu_mse_ssim", "gpu_flip"):
        real = getattr(evaluation.m, name)
        spy = lambda *a, real=real, name=name: calls.append(name) or real(*a)  # noqa: E731
        monkeypatch.setattr(evaluation.m, name, spy)
    args = dict(reference_samples=8, metrics=("psnr", "ssim", "flip", "psnr_aa"), repeats=1)
    tables = {}
    for batch in (1, 3):
        calls.clear()
        tables[batch] = sw.sweep(
            ctx, ["fan"], GRID, SIZE, progress=False, readback_batch=batch, **args
        )
        assert len(calls) == (15 if batch == 1 else 0)
    timing = [c for c in tables[1] if c.startswith("ms_") or c in ("total_ms", "clock")]
    one, three = (tables[b].drop(columns=timing) for b in (1, 3))
    assert list(one.columns) == list(three.columns) and len(one) == 5
    assert one.equals(three)
    assert one["psnr"].nunique() == 5 and one["flip"].nunique() > 1


def test_an_untimed_sweep_scores_the_same_without_running_twice(ctx, monkeypatch):
    # repeats=0: each configuration runs once, for its scores (no warm-up, no timed runs), and
    # every score is the same bits as a timed sweep's.
    runs = []
    real = evaluation.blur_steps
    monkeypatch.setattr(
        evaluation, "blur_steps", lambda *a, **k: runs.append(a[2]) or real(*a, **k)
    )
    args = dict(reference_samples=8, metrics=("psnr", "ssim", "flip"), progress=False)
    caches: dict = {}
    untimed = sw.sweep(ctx, ["fan"], GRID, SIZE, repeats=0, caches=caches, **args)
    assert len(runs) == len(untimed) == 5
    assert caches["fan"]["clock"].seconds.get("warm_up", 0.0) == 0.0
    assert untimed["total_ms"].isna().all() and not any(c.startswith("ms_") for c in untimed)
    assert (untimed["repeats"] == 0).all() and untimed["clock"].isna().all()
    runs.clear()
    timed = sw.sweep(ctx, ["fan"], GRID, SIZE, repeats=1, **args)
    assert len(runs) == 2 + 5 + 5  # a warm-up run per method, then each timed once and scored
    for metric in args["metrics"]:
        assert list(untimed[metric]) == list(timed[metric]), metric


def test_bad_sweeps_are_rejected(ctx, tmp_path):
    with pytest.raises(ValueError, match="no parameter 'kk'"):
        sw.sweep(ctx, ["fan"], {FILTER: {"kk": [1]}}, SIZE, progress=False)
    sequence = pick(kind="sequence")
    with pytest.raises(ValueError, match=f"{sequence} needs a frame sequence"):
        sw.sweep(ctx, ["fan"], [sequence], SIZE, progress=False)
    with pytest.raises(ValueError, match=".csv"):
        sw.sweep(ctx, ["fan"], [GATHER], SIZE, out=tmp_path / "r.parquet", progress=False)
    with pytest.raises(ValueError, match="repeats must be an integer >= 1, or 0"):
        sw.sweep(ctx, ["fan"], [GATHER], SIZE, repeats=-1, progress=False)
    with pytest.raises(ValueError, match="readback_batch must be an integer >= 1"):
        sw.sweep(ctx, ["fan"], [GATHER], SIZE, readback_batch=0, progress=False)
    with pytest.raises(ValueError, match=r"k = 0 is outside 1\.\.256"):
        out = tmp_path / "never.csv"
        sw.sweep(ctx, ["fan"], {FILTER: {"k": [8, 0]}}, SIZE, out=out)
    assert not out.exists()  # refused before anything ran
    with pytest.raises(TypeError, match="taps must be an integer"):
        sw.sweep(ctx, ["fan"], {GATHER: {"taps": [4, "8"]}}, SIZE, progress=False)
    with pytest.raises(ValueError, match="unknown metrics"):
        sw.sweep(ctx, ["fan"], [GATHER], SIZE, metrics=("mse",), progress=False)


def test_sweep_from_a_toml_file(tmp_path, capsys):
    config = tmp_path / "sweep.toml"
    config.write_text(
        'scenes = ["fan"]\nsize = [48, 32]\nreference_samples = 8\n'
        f'out = "{(tmp_path / "out.csv").as_posix()}"\n'
        f"[methods.{GATHER}]\ntaps = [3, 6]\n"
    )
    assert cli.main(["sweep", str(config)]) == 0
    assert len(pd.read_csv(tmp_path / "out.csv")) == 2
    bad = tmp_path / "bad.toml"
    bad.write_text("scenes = ['fan']\nsamples = 3\n")
    with pytest.raises(ValueError, match="unknown keys"):
        cli.main(["--debug", "sweep", str(bad)])
    with pytest.raises(SystemExit) as exit_:
        cli.main(["sweep", str(bad)])
    assert exit_.value.code == 2 and "unknown keys" in capsys.readouterr().err


def test_study_writes_the_report(tmp_path, capsys):
    previous = os.umask(0o022)
    try:
        assert cli.main(["study", "--size", "160x90", "--out", str(tmp_path)]) == 0
    finally:
        os.umask(previous)
    report = (tmp_path / "report.html").read_text()
    # Readable by others under a 022 umask, like any file the process makes.
    for written in ("report.html", "results.csv", "teapot_pass_reference.png"):
        assert (tmp_path / written).stat().st_mode & 0o777 == 0o644, written
    # A budget nothing fits says so and names the fastest, instead of printing nan.
    assert not re.search(r"<td>\s*nan\s*</td>", report, re.IGNORECASE)
    if (pd.read_csv(tmp_path / "results.csv")["total_ms"] > 0.1).all():
        assert "nothing within budget (fastest: " in report
    for name in bl.scenes.names():
        assert f"{name}_pareto.png" in report
        assert (tmp_path / f"{name}_pareto.png").stat().st_size > 1000
        assert (tmp_path / f"{name}_images.png").exists()
    table = pd.read_csv(tmp_path / "results.csv")
    assert set(table["scene"]) == set(bl.scenes.names())
    assert set(table["method"]) == set(sw.default_grids())
    assert "best method within it" in report and (tmp_path / "curve_k.png").exists()
    # The images at full size with their error maps and crops, and the per-object table.
    for method_name in sw.default_grids():
        assert (tmp_path / f"teapot_pass_{method_name}_error.png").exists()
        assert f"href='teapot_pass_{method_name}.png'" in report
    assert (tmp_path / "teapot_pass_crops.png").exists()
    per_object = pd.read_csv(tmp_path / "per_object.csv")
    compared = [f"psnr_{name}" for name in picks(role="renders_for")]
    assert len(compared) >= 2  # the methods that render their own sub-frames, at equal cost
    assert len(per_object) == 8 * 3 and per_object[compared].gt(10).all(axis=None)
    assert "OGRE paper's Table 1" in report
    # Each phase timed, in phases.json, the report and the console; they add up to
    # the whole run, less the HTML and JSON writes.
    timing = json.loads((tmp_path / "phases.json").read_text())
    phases = timing["phases_s"]
    assert {"references", "g_buffers", "evaluations", "images", "charts", "per_object"} <= set(
        phases
    )
    assert all(seconds > 0 for seconds in phases.values())
    # in their listed order, though a scene's images begin during the sweep
    assert list(phases) == [phase for phase in bl.studies.study.PHASES if phase in phases]
    assert 0.9 * timing["total_s"] <= sum(phases.values()) <= timing["total_s"]
    assert timing["evaluations"] == len(table) and timing["size"] == [160, 90]
    assert "Where the time went" in report and "phases.json" in report
    printed = capsys.readouterr().out
    assert "study: " in printed and all(phase in printed for phase in phases)
    assert (tmp_path / "teapot_pass_error_scale.png").exists()


def test_pareto_front_and_chart(ctx):
    import pandas as pd

    table = pd.DataFrame(
        {
            "scene": "s",
            "method": ["a", "b", "c", "d"],
            "total_ms": [1.0, 2.0, 3.0, 4.0],
            "psnr": [20.0, 30.0, 25.0, 40.0],
            "clock": "c",
            "renderer": "r",
            "width": 8,
            "height": 8,
        }
    )
    front = bl.plots.pareto_front(table)
    assert list(front["method"]) == ["a", "b", "d"]  # c is slower and worse than b
    with pytest.raises(ValueError, match="no rows for scene 'x'"):
        bl.plots.pareto(table, "x")


SWEEP_SCRIPT = """
import importlib
import os
import re
import signal
# Ctrl-C interrupts, as in a terminal: a process started in the background by a shell without
# job control (as CI may start the tests) inherits SIGINT ignored, and Python keeps that.
signal.signal(signal.SIGINT, signal.default_int_handler)
import blurlab as bl
sw = importlib.import_module("blurlab.studies.sweep")
sw.sweep(bl.Context(), ["fan"], {{{gather!r}: {{"taps": list(range(2, 200))}}}}, (48, 32),
         reference_samples=4, metrics=("psnr", "ssim"), out={out!r}, progress=False, repeats=1)
"""


def test_sigint_mid_sweep_keeps_every_finished_row(ctx, tmp_path):
    """A real interrupt: Ctrl-C (SIGINT) to a sweep running in another process, once rows
    are being written; every row on disk is whole, and a rerun finishes the rest."""
    import signal
    import subprocess
    import sys
    import time

    out = tmp_path / "r.csv"
    proc = subprocess.Popen(
        [sys.executable, "-c", SWEEP_SCRIPT.format(out=str(out), gather=GATHER)],
        stderr=subprocess.PIPE,
        text=True,
    )
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and proc.poll() is None:
        if out.exists() and out.read_text().count("\n") >= 4:  # header + 3 rows
            break
        time.sleep(0.02)
    # Python drops a KeyboardInterrupt raised inside a weakref finalizer (the pooled textures'
    # recycling) with "Exception ignored", so, like a user, press Ctrl-C again until it stops.
    for _ in range(120):
        proc.send_signal(signal.SIGINT)
        try:
            proc.wait(timeout=0.5)
            break
        except subprocess.TimeoutExpired:
            continue
    _, stderr = proc.communicate(timeout=60)
    assert proc.returncode != 0 and "KeyboardInterrupt" in stderr, stderr[-500:]
    text = out.read_text()
    assert text.endswith("\n")  # no row cut in half
    saved = pd.read_csv(out)
    assert 3 <= len(saved) < 198, "the interrupt did not land mid-sweep"
    assert saved[["scene", "params", "psnr", "ssim", "total_ms"]].notna().all().all()
    table = sw.sweep(
        ctx,
        ["fan"],
        {GATHER: {"taps": list(range(2, 200))}},
        (48, 32),
        reference_samples=4,
        metrics=("psnr", "ssim"),
        out=out,
        progress=False,
        repeats=1,
    )
    final = pd.read_csv(out)
    assert len(table) == 198 and len(final) == 198
    assert not final.duplicated(["scene", "method", "params"]).any()
    kept = final.set_index("params").loc[saved["params"], "psnr"].to_numpy()
    assert (kept == saved["psnr"].to_numpy()).all()  # finished rows were kept, not redone


def test_row_cut_short_by_a_crash_is_evaluated_again(ctx, tmp_path):
    out = tmp_path / "r.csv"
    grid = {GATHER: {"taps": [3, 4, 5]}}
    args = dict(reference_samples=4, metrics=("psnr",), out=out, progress=False, repeats=1)
    sw.sweep(ctx, ["fan"], grid, (32, 24), **args)
    text = out.read_text()
    out.write_text(text[: len(text) - 25])  # the last row loses its end, and its newline
    table = sw.sweep(ctx, ["fan"], grid, (32, 24), **args)
    final = pd.read_csv(out)
    assert len(table) == 3 and len(final) == 3 and final["psnr"].notna().all()


def test_a_list_of_grids_sweeps_their_union(ctx, tmp_path):
    grid = [
        {"k": [8], "samples": [5, 9]},
        {"k": [8], "samples": [9], "jitter_tiles": [1]},
        {"k": [8], "samples": [5]},  # already in the first: run once
    ]
    points = sw.grid_points(grid)
    assert points == [
        {"k": 8, "samples": 5},
        {"k": 8, "samples": 9},
        {"jitter_tiles": 1, "k": 8, "samples": 9},
    ]
    assert sw.grid_keys(grid) == {"k", "samples", "jitter_tiles"}
    assert sw.middle_point(grid) == {"k": 8, "samples": 9}
    table = sw.sweep(
        ctx,
        ["fan"],
        {pick(params=("k", "samples", "jitter_tiles")): grid},
        SIZE,
        reference_samples=8,
        metrics=("psnr",),
        progress=False,
    )
    assert len(table) == 3
    assert table["param_jitter_tiles"].fillna(0).tolist() == [0, 0, 1]
    without = next(n for n in picks(params=("k",)) if "gamma" not in bl.method(n).params)
    with pytest.raises(ValueError, match="no parameter 'gamma'"):
        sw.sweep(ctx, ["fan"], {without: [{"gamma": [1.0]}]}, SIZE)


def test_default_grids_show_each_filter_option_on_both_filters():
    options = ("jitter_tiles", "adaptive_samples", "early_exit")
    filters = picks(kind="filter", params=("k", "samples", *options))
    assert len(filters) >= 2  # the tile filters that take every option
    for name in filters:
        points = sw.grid_points(sw.default_grids()[name])
        for option, on in (("jitter_tiles", 1), ("adaptive_samples", 1), ("early_exit", 2.0)):
            assert {"k": 20, "samples": 15, option: on} in points, (name, option)
        assert {"k": 20, "samples": 15} in points


def test_psnr_aa_is_against_the_antialiased_reference(ctx):
    table = sw.sweep(
        ctx,
        ["fan"],
        {GATHER: {"taps": [4]}},
        SIZE,
        reference_samples=8,
        metrics=("psnr", "psnr_aa"),
        progress=False,
        repeats=1,
    )
    scene = bl.scenes.fan()
    frame = ctx.render(scene, SIZE, instant=bl.method_instant(GATHER, {"taps": 4}))
    out = bl.blur(ctx, frame, GATHER, taps=4).color
    antialiased = ctx.reference(scene, SIZE, samples=8, antialias=True).color
    temporal = ctx.reference(scene, SIZE, samples=8).color
    row = table.iloc[0]
    assert abs(row["psnr_aa"] - bl.metrics.psnr(antialiased, out)) < 0.01
    assert abs(row["psnr"] - bl.metrics.psnr(temporal, out)) < 0.01
    assert abs(row["psnr_aa"] - row["psnr"]) > 0.1  # two references, two numbers
