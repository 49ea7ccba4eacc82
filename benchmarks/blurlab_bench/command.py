"""`blurlab bench`: list, run, record and merge benchmarks, and write docs/benchmarks.md.
blurlab.cli declares the subcommand's options (add_arguments) and calls main."""

from __future__ import annotations

import json
import sys
import time
import traceback

from blurlab.core.context import Context

from .core import (
    RECORDS,
    Unavailable,
    benchmark,
    commit,
    merged,
    names,
    parse_value,
    read_records,
    run_benchmark,
    write_records,
)
from .report import markdown, record_markdown


def add_arguments(parser, parse_size) -> None:
    parser.add_argument("names", nargs="*", help="benchmarks to run, or all")
    parser.add_argument("--list", action="store_true", help="every benchmark, one line each")
    parser.add_argument(
        "--device",
        dest="bench_device",
        default=None,
        help="auto, gpu, software, or an EGL device index (default: blurlab's --device)",
    )
    parser.add_argument("--size", type=parse_size, default=None, help="WxH (default: preset's)")
    parser.add_argument(
        "--param",
        action="append",
        default=[],
        metavar="KEY=VALUE",
        help="a parameter of the benchmark(s) (repeatable; see --list and docs/benchmarks.md)",
    )
    parser.add_argument(
        "--tiny", action="store_true", help="the tiny preset CI runs (for a quick check)"
    )
    parser.add_argument("--json", action="store_true", help="print each record as JSON")
    parser.add_argument(
        "--record",
        nargs="?",
        const=str(RECORDS),
        default=None,
        metavar="FILE",
        help="write each record into FILE (default: benchmarks/records.jsonl), replacing the "
        "previous one of the same benchmark, device and image size",
    )
    parser.add_argument("--merge", metavar="FILE", help="merge FILE's records into --record's")
    parser.add_argument(
        "--markdown", action="store_true", help="print docs/benchmarks.md from the records"
    )


def _given(bench, items: list[str]) -> dict:
    given = {}
    for item in items:
        key, equals, text = item.partition("=")
        if not equals:
            raise ValueError(f"blurlab: --param {item!r}: give KEY=VALUE")
        given[key] = parse_value(bench, key, text)
    return given


def main(args, device) -> int:
    """Runs `blurlab bench` as `args` ask; `device`: blurlab's global --device."""
    if args.list:
        width = max(map(len, names()))
        for name in names():
            print(f"{name:<{width}}  {benchmark(name).doc}")
        return 0
    target = args.record or str(RECORDS)
    if args.merge:
        write_records(merged(read_records(target), read_records(args.merge)), target)
        print(f"merged {args.merge} into {target}")
        return 0
    if args.markdown:
        sys.stdout.write(markdown(read_records(target)))
        return 0
    if not args.names:
        raise ValueError("blurlab: bench: name a benchmark, or all (blurlab bench --list)")
    chosen = names() if args.names == ["all"] else args.names
    benches = [benchmark(name) for name in chosen]
    givens = [_given(b, args.param) for b in benches]  # every --param checked before a run
    commit()  # the code this process loaded, before anything runs
    requested = args.bench_device or device
    ctx = Context(int(requested) if str(requested).isdigit() else requested)
    records, failed = [], []
    for bench, given in zip(benches, givens, strict=True):
        start = time.perf_counter()
        preset = "tiny" if args.tiny else None
        try:
            record = run_benchmark(ctx, bench.name, preset, args.size, given)
        except Unavailable as why:
            print(f"bench {bench.name}: skipped: {why}", file=sys.stderr)
            continue
        except Exception:  # one broken benchmark must not cost the others' records
            if len(benches) == 1:
                raise
            failed.append(bench.name)
            print(f"bench {bench.name}: FAILED\n{traceback.format_exc()}", file=sys.stderr)
            continue
        records.append(record)
        if args.record:  # written as each finishes: a run cut short keeps what it made
            write_records(merged(read_records(args.record), [record]), args.record)
        print(json.dumps(record) if args.json else record_markdown(record), flush=True)
        print(f"bench {bench.name}: {time.perf_counter() - start:.1f} s", file=sys.stderr)
    if failed:
        print(f"bench: {len(failed)} failed: {', '.join(failed)}", file=sys.stderr)
        return 1
    return 0
