"""The benchmark registry (benchmarks/blurlab_bench): every benchmark runs on llvmpipe at its tiny
preset and gives a valid record with finite figures; records are validated on write and read, and
merged by (benchmark, device); `blurlab bench`'s options refuse bad input; docs/benchmarks.md
is the records file's Markdown."""

from __future__ import annotations

import json
import math
import re
import tomllib
import warnings
from pathlib import Path

import pandas as pd
import pytest
from conftest import CLI_DEVICE
from method_picks import pick

import blurlab as bl
import blurlab_bench as bench
from blurlab import cli
from blurlab.cli import main
from blurlab_bench import core, filters, report, timing

ROOT = Path(__file__).resolve().parents[1]
# The glTF models beside the checkout; a git worktree sits one folder deeper.
ASSETS = [p / "shared" / "assets" / "gltf" for p in ROOT.parents[:2]]


@pytest.mark.parametrize("name", bench.names())
def test_every_benchmark_runs_at_its_tiny_preset(ctx, name):
    given = {}
    if name == "content":
        given["assets"] = str(next((p for p in ASSETS if p.exists()), ASSETS[0]))
    try:
        record = bench.run_benchmark(ctx, name, "tiny", given=given)
    except bench.Unavailable as why:
        pytest.skip(str(why))
    bench.validate(json.loads(json.dumps(record)))  # survives the file's round trip
    # Filed under the device that ran it, with the clock it times by (llvmpipe on CI).
    assert record["device"] == core.device_name(ctx.info())
    assert record["clock"] == ctx.info()["timer"]
    assert all(math.isfinite(f["value"]) for f in record["figures"])
    assert set(bench.benchmark(name).params) <= set(record["params"])
    for table in record["tables"]:
        assert table["rows"], table["name"]
    if name == "auto_rules":  # the held-out split by HDR emitters covers every held-out seed
        split = next(t for t in record["tables"] if "HDR emitters" in t["name"])
        counts: dict = {}
        for method, configuration, _, count, *_ in split["rows"]:
            counts[method, configuration] = counts.get((method, configuration), 0) + count
        assert set(counts.values()) == {record["params"]["seeds"]}


def test_transfer_checks_every_async_download_against_the_upload(ctx):
    record = bench.run_benchmark(ctx, "transfer", "tiny", given={"runs": 4, "depth": 2})
    figures = {f["name"]: f["value"] for f in record["figures"]}
    assert figures["async downloads unlike the uploaded image"] == 0


def test_sweep_scaling_gives_the_same_rows_on_one_and_two_warm_workers(ctx):
    pytest.importorskip("distributed")
    given = {"workers": "1,2", "warm": True, "scenes": "fan,thin_bar"}
    record = bench.run_benchmark(ctx, "sweep_scaling", "tiny", given=given)
    figures = {f["name"]: f["value"] for f in record["figures"]}
    assert figures["2 worker(s): same rows as the first"] == 1


def test_auto_rules_resumed_from_its_results_says_so(ctx, tmp_path):
    given = {"results": str(tmp_path / "rows.csv")}
    first, again = (bench.run_benchmark(ctx, "auto_rules", "tiny", given=given) for _ in range(2))
    read = "sweep rows read from results (evaluated by an earlier run)"
    evaluated = "sweep rows evaluated in this run"
    figures = [{f["name"]: f["value"] for f in r["figures"]} for r in (first, again)]
    assert figures[0][read] == 0 and figures[0][evaluated] > 0
    assert figures[1][read] == figures[0][evaluated] and figures[1][evaluated] == 0
    assert first["tables"] == again["tables"]  # the same rows give the same rules


def test_random_scenes_writes_every_scenes_scores_and_their_digests(ctx, tmp_path):
    from blurlab.studies.sweep import read_row_file
    from blurlab_bench.random_scenes import scores_digest

    path = tmp_path / "scores.csv"
    records = [
        bench.run_benchmark(ctx, "random_scenes", "tiny", given={"results": str(path)})
        for _ in range(2)
    ]
    scores = read_row_file(path)  # the exact float parser, as results are read
    table = next(t for t in records[0]["tables"] if t["name"].startswith("each method"))
    assert len(scores) == records[0]["params"]["scenes"] * len(table["rows"])
    for row in table["rows"]:  # the digest is of the rows written
        assert row[-1] == scores_digest(scores[scores["method"] == row[0]])
    # the same scenes on the same renderer score the same, scene by scene
    again = next(t for t in records[1]["tables"] if t["name"].startswith("each method"))
    assert [row[-1] for row in table["rows"]] == [row[-1] for row in again["rows"]]
    # one scene's score moved by 0.01 dB changes its method's digest
    moved = scores[scores["method"] == table["rows"][0][0]].copy()
    moved.loc[moved.index[0], "psnr"] += 0.01
    assert scores_digest(moved) != table["rows"][0][-1]
    with pytest.raises(ValueError, match="existing folder"):  # refused before any scene runs
        bench.run_benchmark(
            ctx, "random_scenes", "tiny", given={"results": str(tmp_path / "no" / "s.csv")}
        )
    # rows scored again one at a time give the sweep's scores (on llvmpipe, bit for bit)
    figures = {f["name"]: f["value"] for f in records[0]["figures"]}
    assert figures["rows scored again, one evaluation at a time"] == 3
    assert figures["largest psnr difference of a row scored again"] == 0.0
    assert figures["rows of the table whose GPU metrics were refused and scored again"] == 0
    assert (scores["stale_readbacks"] == 0).all()  # the results file keeps the column
    rescored = next(t for t in records[0]["tables"] if t["name"].startswith("rows of the sweep"))
    swept = set(zip(scores["scene"], scores["method"], strict=True))
    assert {(r[0], r[1]) for r in rescored["rows"]} <= swept
    for row in rescored["rows"]:  # the other metrics agree too, from references of the same N
        assert row[6] == 0.0
        sweep_n, again_n = row[7].split(" / ")
        assert sweep_n == again_n == str(records[0]["params"]["reference_samples"])


def test_rescore_picks_the_rows_that_stand_out_of_their_scene_then_draws():
    from blurlab_bench.rescore import rescore_picks

    table = pd.DataFrame(
        {
            "scene": ["a"] * 4 + ["b"] * 4,
            "method": list("wxyz") * 2,
            "psnr": [30.0, 31.0, 32.0, 70.0, 20.0, 21.0, 22.0, -40.0],
        }
    )
    picked = rescore_picks(table, 3, "psnr")
    assert len(picked) == 3 and picked.index.is_unique
    # b's -40 dB stands 61.5 dB (61.5 spreads) below b's median, a's 70 dB 38.5 (38.5) above
    assert list(picked.index[:2]) == [7, 3]


def test_rescore_picks_within_a_method_where_the_sweep_has_a_grid():
    from blurlab_bench.rescore import rescore_picks

    # Grids of k: one scene's method spans 20 dB from k to k, the other 1 dB. A read-back
    # wrong by NaN, and one by 5 dB in the tight method, stand out; the spread method's low k
    # does not.
    spread = [10.0, 15.0, 20.0, 25.0, 30.0]
    tight = [40.0, 40.2, 45.4, 40.6, 40.8]
    table = pd.DataFrame(
        {
            "scene": ["a"] * 10,
            "method": ["m"] * 5 + ["n"] * 5,
            "param_k": [4, 8, 12, 16, 20] * 2,
            "psnr": spread + tight,
        }
    )
    table.loc[1, "psnr"] = float("nan")
    picked = rescore_picks(table, 4, "psnr")
    assert list(picked.index[:2]) == [1, 7]


@pytest.mark.parametrize("name", ["rankings", "auto_rules"])
def test_sweeping_benchmarks_score_rows_again_and_get_the_same(ctx, name):
    record = bench.run_benchmark(ctx, name, "tiny")
    figures = {f["name"]: f["value"] for f in record["figures"]}
    assert figures["rows scored again, one evaluation at a time"] == 2
    assert figures["largest psnr difference of a row scored again"] == 0.0
    assert figures["rows of the table whose GPU metrics were refused and scored again"] == 0


def test_engines_scores_every_frame_blurring_method_at_its_own_instant(ctx):
    given = {"methods": "post", "film_filter": 0.5, "references": "temporal,antialiased"}
    with warnings.catch_warnings():
        warnings.filterwarnings("error", "blurlab: .* expects the G-buffer at")
        record = bench.run_benchmark(ctx, "engines", "tiny", given=given)
    figures = {f["name"] for f in record["figures"]}
    for name in timing.post_process_methods():
        assert {f"{name}: median PSNR", f"{name}: median PSNR, antialiased"} <= figures
    film = f"{timing.film_method()}, film_filter=0.5"
    assert timing.optioned_filters()
    for label in (timing.film_method(), film):
        for baseline in timing.optioned_filters():
            assert f"{label} / {baseline}, calls back to back (median)" in figures
    # each pass by tile class, with the tiles of its list (how many: each method's folder's
    # test_<name>_bench.py); a method without tile lists has no classes
    table = next(t for t in record["tables"] if t["name"].startswith("each pass"))
    listed = [n for n in timing.post_process_methods() if bl.method(n).tile_lists]
    assert listed and len(listed) < len(timing.post_process_methods())
    for name in timing.post_process_methods():
        rows = [r for r in table["rows"] if r[1] == name]
        classed = [r for r in rows if r[3]]
        assert rows and all(r[5] >= 0 for r in rows), name
        if name not in listed:
            assert all(r[3] == "" and r[4] is None for r in rows), name
            continue
        assert {r[3] for r in classed} <= set(bl.method(name).tile_lists), name
        assert len({r[3] for r in classed}) >= 2, name  # the frame has tiles of several kinds
        assert all(r[4] >= 0 and r[4] == int(r[4]) for r in classed), name  # tile counts
        for _, _, step, cls, _, _ in classed:
            assert f"{name}: median ms, {step}[{cls}]" in figures


def record(name="transfer", device="llvmpipe", value=1.0) -> dict:
    return {
        "benchmark": name,
        "params": {"runs": 1},
        "device": device,
        "driver": {"renderer": "r", "gl_version": "v"},
        "clock": "wall_glfinish",
        "commit": "abc",
        "date": "2026-01-01",
        "wall_s": 0.1,
        "figures": [{"name": "upload GB/s", "value": value, "unit": "GB/s"}],
        "tables": [{"name": "t", "columns": [{"name": "a", "unit": "ms"}], "rows": [[1.0]]}],
    }


@pytest.mark.parametrize(
    "broken, message",
    [
        (lambda r: r.pop("commit"), "keys must be"),
        (lambda r: r.update(clock="sundial"), "clock must be"),
        (lambda r: r["figures"][0].update(value=float("nan")), "finite number"),
        (lambda r: r["figures"][0].pop("unit"), "name, value and unit"),
        (lambda r: r["tables"][0]["rows"].append([1, 2]), "every row needs 1 cells"),
        (lambda r: r.update(figures=[]), "at least one figure"),
    ],
)
def test_a_broken_record_is_refused_on_write_and_the_file_is_left_alone(tmp_path, broken, message):
    path = tmp_path / "records.jsonl"
    bench.write_records([record()], path)
    before = path.read_text()
    bad = record()
    broken(bad)
    with pytest.raises(ValueError, match=message):
        bench.write_records([record("gbuffer"), bad], path)
    assert path.read_text() == before


def test_records_merge_by_benchmark_and_device(tmp_path):
    path = tmp_path / "records.jsonl"
    bench.write_records([record(), record(device="NVIDIA H100"), record("gbuffer")], path)
    new = tmp_path / "new.jsonl"
    bench.write_records([record(device="NVIDIA H100", value=2.0)], new)
    assert main(["bench", "--record", str(path), "--merge", str(new)]) == 0
    records = bench.read_records(path)
    assert [(r["benchmark"], r["device"]) for r in records] == [
        ("gbuffer", "llvmpipe"),
        ("transfer", "NVIDIA H100"),
        ("transfer", "llvmpipe"),
    ]
    assert records[1]["figures"][0]["value"] == 2.0
    assert len(path.read_text().splitlines()) == 3  # one compact line a record


def test_a_variant_parameter_keeps_a_record_of_its_own(tmp_path):
    """The study's mode is a variant: a record of `--sequence` sits beside the default's, and a
    newer record of the same mode replaces the older; a plain parameter does not split them."""
    study = lambda mode, value: {**record("study", value=value), "params": {"mode": mode}}  # noqa: E731
    assert bench.benchmark("study").variants == ("mode", "scenes")
    kept = bench.merged([study("", 1.0), study("--sequence", 2.0)], [study("--sequence", 3.0)])
    assert sorted((r["params"]["mode"], r["figures"][0]["value"]) for r in kept) == [
        ("", 1.0),
        ("--sequence", 3.0),
    ]
    # a record older than the variant has the parameter's default
    older = {**record("study"), "params": {}}
    assert core.record_key(older) == core.record_key(study("", 1.0))
    other_runs = {**record(value=2.0), "params": {"runs": 9}}
    assert len(bench.merged([record(value=1.0)], [other_runs])) == 1
    with pytest.raises(ValueError, match=r"variants \['speed'\] are not parameters"):
        bench.Benchmark("x", "doc", {}, lambda *a: None, variants=("speed",))


def test_parameters_are_checked_against_their_declaration():
    transfer = bench.benchmark("transfer")
    assert core.parse_value(transfer, "runs", "3") == 3
    with pytest.raises(ValueError, match="runs = 0 is outside 1..10000"):
        core.parse_value(transfer, "runs", "0")
    with pytest.raises(ValueError, match="must be an integer"):
        core.parse_value(transfer, "runs", "many")
    with pytest.raises(TypeError, match=r"no parameter\(s\) \['speed'\]; its parameters are runs"):
        core.parse_value(transfer, "speed", "1")
    with pytest.raises(ValueError, match="must be one of '', 'eevee'"):
        core.check_value(bench.benchmark("engines"), "peers", "cycles")
    with pytest.raises(TypeError, match="parameter scenes must be text"):
        core.check_value(bench.benchmark("engines"), "scenes", 3)


@pytest.mark.parametrize(
    "argv, message",
    [
        (["bench", "nothing"], "no benchmark 'nothing'"),
        (["bench", "transfer", "--param", "runs"], "give KEY=VALUE"),
        (["bench", "transfer", "--param", "runs=-1"], "runs = -1 is outside 1..10000"),
        (["bench"], "name a benchmark, or all"),
        (["bench", "motion_formats", "--size", "8x8"], "has no image size"),
    ],
)
def test_the_command_refuses_bad_input_in_one_line(capsys, argv, message):
    with pytest.raises(SystemExit) as exit:
        main(["--device", CLI_DEVICE, *argv])
    assert exit.value.code == 2
    assert message in capsys.readouterr().err


def test_list_names_every_benchmark_with_its_doc(capsys):
    assert main(["bench", "--list"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert [line.split()[0] for line in lines] == bench.names()
    assert all(bench.benchmark(line.split()[0]).doc in line for line in lines)


def test_the_benchmarks_are_outside_the_package_the_wheel_ships():
    """The wheel ships python/blurlab alone (pyproject's wheel.packages); the benchmarks are a
    development package beside it, which nothing in the library imports."""
    config = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["scikit-build"]
    shipped = [ROOT / folder for folder in config["wheel"]["packages"]]
    assert shipped == [ROOT / "python" / "blurlab"]
    here = Path(bench.__file__).resolve()
    assert here.parent == ROOT / "benchmarks" / "blurlab_bench"
    assert not any(here.is_relative_to(folder) for folder in shipped)
    # A built-in method folder's tests stay in the repository (pyproject's wheel.exclude).
    importing = [
        str(path.relative_to(ROOT))
        for folder in shipped
        for path in folder.rglob("*.py")
        if not (path.match("methods/*/test_*.py") and path.parent.name != "template_files")
        and re.search(r"^\s*(from|import) blurlab_bench\b", path.read_text(), re.M)
    ]
    assert not importing, importing


def test_without_a_checkout_the_command_says_the_benchmarks_need_one(capsys, monkeypatch):
    monkeypatch.setattr(cli, "bench_command", lambda: None)
    for argv in (["bench", "--list"], ["bench", "transfer", "--tiny"], ["bench", "--help"]):
        with pytest.raises(SystemExit) as exit:
            main(argv)
        assert exit.value.code == 2
        assert "development package in a checkout's benchmarks/" in capsys.readouterr().err


def test_config_rows_carry_their_parameters_and_bad_ones_are_refused():
    film = timing.film_method()  # its film filter's row comes first, then the configs
    config = timing.method_config(f"{film}:samples=16,film_filter=0.5,seed=3")
    assert config == (film, {"samples": 16, "film_filter": 0.5, "seed": 3})
    assert timing.method_config(f"{film}:packed_inputs=true")[1] == {"packed_inputs": True}
    # a choice parameter's value is a word, one of its choices ("one"), not a number
    listed = pick(params=("tile_dispatch",), exclude=(film,))
    one = timing.method_config(f"{listed}:tile_dispatch=one")
    assert one == (listed, {"tile_dispatch": "one"})
    other = pick(kind="gather", exclude=(film,))
    runs = timing.method_runs(["a"], 0.5, f"{film}:samples=4;{other}:seed=1")
    assert runs[1] == (f"{film}, film_filter=0.5", film, {"film_filter": 0.5})
    assert runs[2] == (f"{film}, samples=4", film, {"samples": 4})
    assert runs[3] == (f"{other}, seed=1", other, {"seed": 1})
    assert len(runs) == 4
    bad_ones = (f"{film}:samples", ":samples=4", f"{film}:samples=many")
    for bad in (*bad_ones, f"{listed}:tile_dispatch=all", "no_such_method:tile_dispatch=one"):
        with pytest.raises(ValueError, match="METHOD:KEY=VALUE"):
            timing.method_config(bad)


def test_benchmarks_md_is_generated_from_the_records():
    text = (ROOT / "docs" / "benchmarks.md").read_text()
    expected = report.markdown(bench.read_records(ROOT / "benchmarks" / "records.jsonl"))
    if text != expected:  # not `assert ==`: pytest's diff of two long pages takes a minute
        pytest.fail(
            "docs/benchmarks.md is out of date: regenerate it with "
            "`blurlab bench --markdown > docs/benchmarks.md`"
        )


def test_every_record_in_the_tree_is_of_a_registered_benchmark():
    records = bench.read_records(ROOT / "benchmarks" / "records.jsonl")
    assert {r["benchmark"] for r in records} <= set(bench.names())


def test_every_pass_layout_gives_the_default_layouts_image(ctx):
    """The layouts benchmark times every variant of every pass with alternatives; each gives the
    default layout's image, bit for bit (the film filter's to float rounding)."""
    record = bench.run_benchmark(ctx, "layouts", "tiny")
    (table,) = record["tables"]
    names = [c["name"] for c in table["columns"]]
    rows = [dict(zip(names, row, strict=True)) for row in table["rows"]]
    expected = {(layout.what, v) for layout, _, _ in filters.layout_runs() for v in layout.variants}
    assert {(r["pass"], r["layout"]) for r in rows} == expected
    for row in rows:
        bound = 1e-5 if row["pass"] == "film filter" else 0.0
        assert row["largest difference from the default"] <= bound, row


class _GpuClockedContext:
    """A context that reports GPU timer queries and counts its waits: spin_up's loop as it runs
    on a GPU, without one."""

    def __init__(self):
        self.waits = 0

    def info(self):
        return {"timer": "gl_time_elapsed"}

    def finish(self):
        self.waits += 1


def test_spin_up_waits_for_each_untimed_call_on_a_gpu_clock():
    # Unwaited, a slow method's spin-up queued seconds of GPU work past SPIN_UP_S.
    ctx, calls = _GpuClockedContext(), []
    timing.spin_up(ctx, lambda: calls.append(ctx.waits))
    assert len(calls) > 1
    # every call after the first finds the one before it finished
    assert calls == list(range(len(calls)))


RENDERS = pick(kind="render")


@pytest.mark.parametrize(
    "given, message",
    [
        ({"settings": "bounded,fast"}, "queue_depth settings 'bounded,fast': from bounded"),
        # a method that renders its own sub-frames blurs no frame
        ({"method": RENDERS}, f"queue_depth method '{RENDERS}': one of"),
        ({"scenes": "nowhere"}, "queue_depth scenes 'nowhere': built-in, failure or"),
        ({"reference_scenes": "x"}, "queue_depth reference_scenes 'x': built-in, failure or"),
        ({"cost_scenes": "x"}, "queue_depth cost_scenes 'x': built-in, failure or"),
        (
            {"scenes": "", "reference_scenes": "", "cost_scenes": ""},
            "queue_depth needs scenes, reference_scenes or cost_scenes",
        ),
    ],
)
def test_queue_depth_refuses_what_it_cannot_run_in_words(ctx, given, message):
    with pytest.raises(ValueError, match=re.escape(message)):
        core.run_benchmark(ctx, "queue_depth", "tiny", None, given)
