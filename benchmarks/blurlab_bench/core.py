"""The benchmarks' registry, record schema, records file and runner.

A benchmark is registered once (``Benchmark``: name, one line of doc, its parameters declared
with ``blurlab.methods.params.Param``, its sizes and presets, and ``run``), and everything else
reads it from here: ``blurlab bench``, benchmarks/gpu.sh, the CI test that runs each at a tiny
size, and docs/benchmarks.md, which is generated from benchmarks/records.jsonl.

A run writes figures (name, value, unit) and tables (columns with units, rows) into a
``Measured``; ``run_benchmark`` wraps them in a record that says what measured them: device,
driver (renderer and GL version), clock, commit and date. Records are validated when they are
made, written and read.
"""

from __future__ import annotations

import datetime
import functools
import json
import math
import os
import subprocess
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from numbers import Real
from pathlib import Path

from blurlab.blender import available as blender_available
from blurlab.core.context import Context
from blurlab.methods.params import Param, check_known, typed
from blurlab.version import __version__

PRESETS = ("tiny", "software", "gpu")  # CI's size, llvmpipe's records, the GPU's records
CLOCKS = ("gl_time_elapsed", "wall_glfinish")
RECORD_KEYS = (
    "benchmark",
    "params",
    "device",
    "driver",
    "clock",
    "commit",
    "date",
    "wall_s",
    "figures",
    "tables",
)
SIGNIFICANT = 5  # digits a figure keeps in a record: more is noise, and makes the file long
# The benchmarks are a development package of the checkout (benchmarks/blurlab_bench), never
# in the wheel, so the records file beside them is always there.
PACKAGE_PARENT = Path(__file__).resolve().parents[1]
ROOT = PACKAGE_PARENT.parent
RECORDS = PACKAGE_PARENT / "records.jsonl"


def child_environment(extra: dict[str, str]) -> dict[str, str]:
    """This process's environment with `extra` and this package's folder first on PYTHONPATH,
    so that a child Python imports these benchmarks however this process found them."""
    path = os.pathsep.join(p for p in (str(PACKAGE_PARENT), os.environ.get("PYTHONPATH")) if p)
    return {**os.environ, **extra, "PYTHONPATH": path}


class Unavailable(RuntimeError):
    """A benchmark that cannot run here (an optional extra or data missing), and why."""


@dataclass
class Measured:
    """What a run measured: figures (one number each, with its unit) and tables."""

    figures: list[dict] = field(default_factory=list)
    tables: list[dict] = field(default_factory=list)

    def figure(self, name: str, value: float, unit: str) -> None:
        self.figures.append({"name": name, "value": _rounded(value), "unit": unit})

    def table(self, name: str, columns: list[tuple[str, str]], rows: list[list]) -> None:
        """`columns`: (name, unit) each, unit "" for a label; `rows`: one list a row."""
        self.tables.append(
            {
                "name": name,
                "columns": [{"name": c, "unit": u} for c, u in columns],
                "rows": [[_rounded(v) for v in row] for row in rows],
            }
        )


def _rounded(value):
    if isinstance(value, bool) or not isinstance(value, Real):
        return value
    value = float(value)
    return float(f"{value:.{SIGNIFICANT}g}") if math.isfinite(value) else value


@dataclass(frozen=True)
class Benchmark:
    """A registered benchmark.

    `run(ctx, size, values, out)`: measures on Context `ctx` at `size` ((width, height), or None
    where the benchmark has no image size) with `values` (every parameter, checked) and writes
    into `out` (a Measured). `sizes`: the size of each preset (PRESETS); `presets`: parameter
    values of each preset that differ from the defaults. `needs`: modules it imports that are
    optional extras; without them it is Unavailable.
    """

    name: str
    doc: str
    params: dict[str, Param]
    run: Callable
    sizes: dict[str, tuple[int, int]] | None = None
    presets: dict[str, dict] = field(default_factory=dict)
    needs: tuple[str, ...] = ()
    # parameters that say which variant a record measures: each value keeps a record of its own
    variants: tuple[str, ...] = ()

    def __post_init__(self):
        unknown = [v for v in self.variants if v not in self.params]
        if unknown:
            raise ValueError(
                f"blurlab: benchmark {self.name}: variants {unknown} are not parameters"
            )
        for preset, values in self.presets.items():
            if preset not in PRESETS:
                raise ValueError(f"blurlab: benchmark {self.name}: no preset {preset!r}")
            for key, value in values.items():
                check_value(self, key, value)
        if self.sizes is not None and set(self.sizes) != set(PRESETS):
            raise ValueError(f"blurlab: benchmark {self.name} needs a size for each of {PRESETS}")

    def values(self, preset: str, given: dict | None = None) -> dict:
        """Every parameter: the default, the preset's value, then `given`, each checked."""
        values = {key: p.default for key, p in self.params.items()}
        values |= self.presets.get(preset, {})
        for key, value in (given or {}).items():
            values[key] = check_value(self, key, value)
        return values


_REGISTRY: dict[str, Benchmark] = {}


def register(benchmark: Benchmark) -> Benchmark:
    if benchmark.name in _REGISTRY or benchmark.name == "all":
        raise ValueError(f"blurlab: benchmark {benchmark.name!r} is registered twice")
    _REGISTRY[benchmark.name] = benchmark
    return benchmark


def names() -> list[str]:
    """Names of the registered benchmarks."""
    return list(_REGISTRY)


def benchmark(name: str) -> Benchmark:
    if name not in _REGISTRY:
        raise ValueError(f"blurlab: no benchmark {name!r}; registered: {', '.join(names())}")
    return _REGISTRY[name]


def check_value(bench: Benchmark, key: str, value):
    """`value` as parameter `key` of `bench` takes it, or a ValueError/TypeError that names the
    benchmark, the parameter, the value and what is allowed (the methods' own check)."""
    owner = f"benchmark {bench.name}"
    check_known(owner, bench.params, [key])
    return typed(owner, key, value, bench.params[key])


def parse_value(bench: Benchmark, key: str, text: str):
    """`--param key=text`'s value, converted to the parameter's type and checked."""
    kind = bench.params[key].kind if key in bench.params else str
    value: object = text
    if kind is bool:
        if text not in ("true", "false"):
            raise ValueError(f"blurlab: benchmark {bench.name} parameter {key}: true or false")
        value = text == "true"
    elif kind in (int, float):
        try:
            value = kind(text)
        except ValueError:
            what = "an integer" if kind is int else "a number"
            raise ValueError(
                f"blurlab: benchmark {bench.name} parameter {key} must be {what}, not {text!r}"
            ) from None
    return check_value(bench, key, value)


@functools.cache
def commit() -> str:
    """The tree's `git describe` (with -dirty where the code differs from it), or the package
    version where there is no checkout or no git; taken once a process, so that a long run's
    records name the code it loaded, not a commit made while it ran. ``BLURLAB_COMMIT``, where
    set, names it instead: a copy of a tree without its git folder (the lent GPU machine gets
    one) is told which commit it is by whoever copied it."""
    given = os.environ.get("BLURLAB_COMMIT", "").strip()
    if given:
        return given
    try:
        described = subprocess.run(
            ["git", "describe", "--always", "--tags"],
            cwd=ROOT,
            capture_output=True,
            text=True,
            timeout=10,
        )
        if described.returncode != 0 or not described.stdout.strip():
            return __version__
        clean = subprocess.run(
            ["git", "diff", "--quiet", "HEAD", "--", "python", "src", "shaders"],
            cwd=ROOT,
            timeout=10,
        )
        return described.stdout.strip() + ("" if clean.returncode == 0 else "-dirty")
    except (OSError, subprocess.SubprocessError):
        return __version__


def device_name(info: dict) -> str:
    """The device a record is filed under: llvmpipe, or the GPU's renderer name."""
    if info["device"] == "software":
        return "llvmpipe"
    return info["renderer"].split("/")[0].strip()


def preset_of(ctx: Context) -> str:
    return "software" if ctx.info()["device"] == "software" else "gpu"


def _usable(module: str) -> bool:
    """Whether a benchmark's `needs` entry can be used: bpy runs in Blender's child process,
    from blurlab's own environment for it (blurlab.blender.available); any other module is
    imported here."""
    if module == "bpy":
        return blender_available()
    try:
        __import__(module)
    except ImportError:
        return False
    return True


def run_benchmark(
    ctx: Context,
    name: str,
    preset: str | None = None,
    size: tuple[int, int] | None = None,
    given: dict | None = None,
) -> dict:
    """Runs benchmark `name` on `ctx` with the parameters of `preset` (default: the context's,
    "software" on llvmpipe, else "gpu") updated by `given`, at `size` (default: the preset's);
    returns its record, validated."""
    bench = benchmark(name)
    for module in bench.needs:
        if not _usable(module):
            raise Unavailable(f"benchmark {name} needs the module {module!r}")
    preset = preset or preset_of(ctx)
    if preset not in PRESETS:
        raise ValueError(f"blurlab: preset {preset!r}: one of {', '.join(PRESETS)}")
    values = bench.values(preset, given)
    if bench.sizes is not None:
        size = size or bench.sizes[preset]
    elif size is not None:
        raise ValueError(f"blurlab: benchmark {name} has no image size")
    out = Measured()
    start = time.perf_counter()
    bench.run(ctx, size, values, out)
    wall = time.perf_counter() - start
    info = ctx.info()
    params = {**values, **({"size": f"{size[0]}x{size[1]}"} if size else {})}
    record = {
        "benchmark": name,
        "params": params,
        "device": device_name(info),
        "driver": {"renderer": info["renderer"], "gl_version": info["version"]},
        "clock": info["timer"],
        "commit": commit(),
        "date": datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d"),
        "wall_s": round(wall, 1),
        "figures": out.figures,
        "tables": out.tables,
    }
    validate(record)
    return record


def validate(record: dict) -> dict:
    """`record` if it follows the schema (RECORD_KEYS; figures with a finite value and a unit;
    tables whose rows have a cell per column), else a ValueError saying what is wrong."""

    def fail(what: str):
        raise ValueError(f"blurlab: record of {record.get('benchmark', '?')!r}: {what}")

    if not isinstance(record, dict) or list(record) != list(RECORD_KEYS):
        fail(f"keys must be {', '.join(RECORD_KEYS)} in that order")
    for key in ("benchmark", "device", "commit", "date"):
        if not isinstance(record[key], str) or not record[key]:
            fail(f"{key} must be non-empty text")
    if record["clock"] not in CLOCKS:
        fail(f"clock must be one of {', '.join(CLOCKS)}")
    driver = record["driver"]
    if not isinstance(driver, dict) or sorted(driver) != ["gl_version", "renderer"]:
        fail("driver must hold renderer and gl_version")
    if not isinstance(record["params"], dict):
        fail("params must be a dict")
    if not isinstance(record["figures"], list) or not record["figures"]:
        fail("a record needs at least one figure")
    for figure in record["figures"]:
        if not isinstance(figure, dict) or sorted(figure) != ["name", "unit", "value"]:
            fail(f"a figure holds name, value and unit: {figure!r}")
        value = figure["value"]
        if isinstance(value, bool) or not isinstance(value, Real) or not math.isfinite(value):
            fail(f"figure {figure['name']!r} must be a finite number, not {value!r}")
        if not isinstance(figure["unit"], str):
            fail(f"figure {figure['name']!r} needs a unit")
    for table in record["tables"]:
        if not isinstance(table, dict) or sorted(table) != ["columns", "name", "rows"]:
            fail("a table holds name, columns and rows")
        width = len(table["columns"])
        if any(sorted(c) != ["name", "unit"] for c in table["columns"]):
            fail(f"table {table['name']!r}: each column holds name and unit")
        if any(not isinstance(row, list) or len(row) != width for row in table["rows"]):
            fail(f"table {table['name']!r}: every row needs {width} cells")
    return record


def read_records(path: Path | str = RECORDS) -> list[dict]:
    """The records of a records file (one JSON object a line), each validated."""
    path = Path(path)
    if not path.exists():
        return []
    lines = path.read_text().splitlines()
    return [validate(json.loads(line)) for line in lines if line.strip()]


def record_key(record: dict) -> tuple:
    """What a record stands for, one record each in the records file: its benchmark, its
    device, its image size (a benchmark measured at two sizes on one device keeps both) and
    the values of the benchmark's `variants` (the study's mode keeps a record of each mode)."""
    return (
        record["benchmark"],
        record["device"],
        str(record["params"].get("size", "")),
        *(str(v) for v in variant_values(record)),
    )


def variant_values(record: dict) -> tuple:
    """The values of the record's benchmark's `variants` (a parameter the record lacks has its
    default: records older than the variant measured it)."""
    bench = _REGISTRY.get(record["benchmark"])
    if bench is None:
        return ()
    return tuple(record["params"].get(v, bench.params[v].default) for v in bench.variants)


def write_records(records: list[dict], path: Path | str = RECORDS) -> None:
    """Writes `records` into the records file, each validated, sorted by record_key; the file
    is written whole only after every record passed."""
    ordered = sorted((validate(r) for r in records), key=record_key)
    text = "".join(json.dumps(r, ensure_ascii=False, separators=(",", ":")) + "\n" for r in ordered)
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    Path(path).write_text(text)


def merged(old: list[dict], new: list[dict]) -> list[dict]:
    """`old` with each record of `new` in place of the one of the same record_key."""
    keyed = {record_key(r): r for r in old}
    keyed |= {record_key(r): r for r in new}
    return list(keyed.values())
