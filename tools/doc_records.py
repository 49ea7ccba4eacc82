"""The docs' figures, filled in from benchmarks/records.jsonl, and the methods' specifications,
filled in from their folders.

A hand-written page holds no measured number of its own. Where it shows one, it marks a region
that names the record, and the region's body is generated from it:

    <!-- record benchmark="engines" device="llvmpipe" size="160x90" figures="name; name" -->
    ...generated: the record's source line and a table...
    <!-- end record -->

Values are HTML-escaped where they hold a quote (`&quot;`). `figures=` picks figures by
name; `table=` picks a table by name instead, with optional `columns=` (names, "; "-separated)
and `rows=` (the first n). A record is found by its benchmark, device and image size, and by
the values of the benchmark's variant parameters (the study's mode): the key under which
`blurlab bench --record` keeps the latest one. `where="mode=--sequence"` ("; "-separated
name=value pairs) picks a variant; without it, each variant parameter has its default.

A method's specification lives in its folder (python/blurlab/methods/<name>/spec.md); the
docs' spec shows it in a region that names the method, generated from that file:

    <!-- method spec="gather_pixel" -->
    ...generated: the folder's spec.md...
    <!-- end method -->

The same function fills the regions three ways: `python tools/doc_records.py` rewrites the
pages in place (so the Markdown read raw is current), MkDocs runs it as a hook on every page at
build time (mkdocs.yml `hooks:`), and tests/test_doc_records.py fails where a committed page
differs from what the records give.
"""

from __future__ import annotations

import html
import json
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
RECORDS = ROOT / "benchmarks" / "records.jsonl"
sys.path.insert(0, str(ROOT / "benchmarks"))  # the checkout's development package
from blurlab_bench.core import benchmark as registered  # noqa: E402
from blurlab_bench.core import names as registered_names  # noqa: E402
from blurlab_bench.core import variant_values  # noqa: E402
from blurlab_bench.report import cell, heading  # noqa: E402 (cells as docs/benchmarks.md writes them)

REGION = re.compile(
    r"(?P<open><!-- record (?P<options>[^>]*?) -->\n)(?P<body>.*?)(?P<close><!-- end record -->)",
    re.DOTALL,
)
METHOD_REGION = re.compile(
    r'(?P<open><!-- method spec="(?P<name>[a-z0-9_]+)" -->\n)'
    r"(?P<body>.*?)(?P<close><!-- end method -->)",
    re.DOTALL,
)
METHODS = ROOT / "python" / "blurlab" / "methods"
OPTION = re.compile(r'(\w+)="([^"]*)"')
KNOWN = {"benchmark", "device", "size", "figures", "table", "columns", "rows", "where"}


def read_records(path: Path = RECORDS) -> list[dict]:
    return [json.loads(line) for line in path.read_text().splitlines() if line.strip()]


def find_record(
    records: list[dict], benchmark: str, device: str, size: str, where: str = ""
) -> dict:
    # a benchmark no longer registered keeps its records, without variants
    variants = registered(benchmark).variants if benchmark in registered_names() else ()
    wanted = {v: registered(benchmark).params[v].default for v in variants}
    for pair in _names(where):
        name, _, value = pair.partition("=")
        if name.strip() not in wanted:
            raise ValueError(
                f"where={where!r}: {benchmark} has the variant parameters {sorted(wanted)}"
            )
        wanted[name.strip()] = value.strip()
    variant = tuple(str(v) for v in wanted.values())
    found = [
        r
        for r in records
        if r["benchmark"] == benchmark
        and r["device"] == device
        and str(r["params"].get("size", "")) == size
        and tuple(str(v) for v in variant_values(r)) == variant
    ]
    if not found:
        held = sorted(
            f"{r['device']} {r['params'].get('size', '')}"
            for r in records
            if r["benchmark"] == benchmark
        )
        raise ValueError(f"no {benchmark} record for {device} at {size!r}; held: {held}")
    return found[-1]


def _names(text: str) -> list[str]:
    return [name.strip() for name in text.split(";") if name.strip()]


def _pick(items: list[dict], names: list[str], what: str) -> list[dict]:
    by_name = {item["name"]: item for item in items}
    missing = [n for n in names if n not in by_name]
    if missing:
        raise ValueError(f"the record has no {what} {missing}; it has {sorted(by_name)}")
    return [by_name[n] for n in names]


def region_markdown(options: dict, records: list[dict]) -> str:
    """The body of one region: where the numbers come from, then the figures or the table."""
    unknown = set(options) - KNOWN
    if unknown or not {"benchmark", "device", "size"} <= set(options):
        raise ValueError(
            f"a record region takes {sorted(KNOWN)}, of which benchmark, device and size are "
            f"required; not {sorted(options)}"
        )
    record = find_record(
        records, options["benchmark"], options["device"], options["size"], options.get("where", "")
    )
    source = (
        f"*The `{record['benchmark']}` record: {record['device']}, "
        + (f"{options['size']}, " if options["size"] else "")
        + f"commit `{record['commit']}`, {record['date']}.*"
    )
    if "table" in options:
        (table,) = _pick(record["tables"], [options["table"]], "table")
        columns = table["columns"]
        picked = (
            _pick(columns, _names(options["columns"]), "column")
            if "columns" in options
            else columns
        )
        indices = [columns.index(c) for c in picked]
        rows = table["rows"][: int(options["rows"])] if "rows" in options else table["rows"]
        lines = [
            "| " + " | ".join(heading(c) for c in picked) + " |",
            "|" + "---|" * len(picked),
            *("| " + " | ".join(cell(row[i]) for i in indices) + " |" for row in rows),
        ]
    else:
        figures = _pick(record["figures"], _names(options.get("figures", "")), "figure")
        lines = ["| figure | value | unit |", "|---|---|---|"]
        lines += [f"| {f['name']} | {cell(f['value'])} | {f['unit']} |" for f in figures]
    return "\n".join([source, "", *lines]) + "\n"


def fill(markdown: str, records: list[dict], page: str = "page") -> str:
    """`markdown` with every record region's body generated from `records`."""

    def filled(match: re.Match) -> str:
        options = {k: html.unescape(v) for k, v in OPTION.findall(match.group("options"))}
        try:
            body = region_markdown(options, records)
        except ValueError as error:
            line = markdown.count("\n", 0, match.start()) + 1
            raise ValueError(f"{page}:{line}: {error}") from None
        return match.group("open") + body + match.group("close")

    return fill_specs(REGION.sub(filled, markdown), page)


def fill_specs(markdown: str, page: str = "page", methods: Path = METHODS) -> str:
    """`markdown` with every method region's body the spec.md of that method's folder."""

    def filled(match: re.Match) -> str:
        spec = methods / match.group("name") / "spec.md"
        if not spec.is_file():
            line = markdown.count("\n", 0, match.start()) + 1
            raise ValueError(f"{page}:{line}: no method folder holds {spec}")
        body = spec.read_text()
        return (
            match.group("open")
            + body
            + ("" if body.endswith("\n") else "\n")
            + match.group("close")
        )

    return METHOD_REGION.sub(filled, markdown)


def on_page_markdown(markdown, page, config, files):
    """The MkDocs hook: every page's regions from the records, at build time."""
    return fill(markdown, read_records(), page.file.src_path)


def pages(root: Path = ROOT) -> list[Path]:
    return [root / "README.md", *sorted((root / "docs").rglob("*.md"))]


def main() -> int:
    records = read_records()
    for path in pages():
        text = path.read_text()
        new = fill(text, records, str(path.relative_to(ROOT)))
        if new != text:
            path.write_text(new)
            print(f"updated {path.relative_to(ROOT)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
