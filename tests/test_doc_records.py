"""The docs' figures come from benchmarks/records.jsonl (tools/doc_records.py): every record
region of a page is what the records give, and a hand-written line holds no commit id or date
(those belong to the records and to git history)."""

from __future__ import annotations

import importlib.util
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
_spec = importlib.util.spec_from_file_location("doc_records", ROOT / "tools" / "doc_records.py")
doc_records = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(doc_records)

# Pages generated whole by a command, each with its own test that it is current.
GENERATED = {"docs/benchmarks.md", "docs/cli.md", "docs/parameters.md", "docs/metrics.md"}
COMMIT = re.compile(r"\b(?=[0-9a-f]*[a-f])(?=[0-9a-f]*[0-9])[0-9a-f]{7,40}\b")
MONTHS = "January|February|March|April|May|June|July|August|September|October|November|December"
DATE = re.compile(rf"\b(?:20\d\d-[01]\d(?:-[0-3]\d)?|(?:{MONTHS}) 20\d\d)\b")


def _page_name(path: Path) -> str:
    return str(path.relative_to(ROOT))


def hand_written_lines(path: Path, root: Path = ROOT):
    """(line number, text) of `path` outside record regions."""
    text = path.read_text()
    spans = [(m.start(), m.end()) for m in doc_records.REGION.finditer(text)]
    offset = 0
    for number, line in enumerate(text.split("\n"), 1):
        if not any(start <= offset < end for start, end in spans):
            yield number, line
        offset += len(line) + 1


@pytest.mark.parametrize("path", doc_records.pages(), ids=_page_name)
def test_record_regions_are_the_records(path):
    text = path.read_text()
    filled = doc_records.fill(text, doc_records.read_records(), _page_name(path))
    assert filled == text, (
        f"{_page_name(path)} shows figures its records no longer hold: run "
        "`python tools/doc_records.py`"
    )


def test_hand_written_lines_hold_no_commit_or_date():
    found = [
        f"{_page_name(path)}:{number}: {line.strip()[:120]}"
        for path in doc_records.pages()
        if _page_name(path) not in GENERATED
        for number, line in hand_written_lines(path)
        if COMMIT.search(line) or DATE.search(line)
    ]
    assert not found, (
        "a commit id or a date in a hand-written line: cite a record region instead "
        "(tools/doc_records.py), or leave the history to git\n" + "\n".join(found)
    )


RECORD = {
    "benchmark": "demo",
    "device": "llvmpipe",
    "params": {"size": "160x90"},
    "commit": "abc1234",
    "date": "2026-11-27",
    "figures": [{"name": "speed", "value": 1.23456, "unit": "ms"}],
    "tables": [
        {
            "name": "rows",
            "columns": [{"name": "scene", "unit": ""}, {"name": "PSNR", "unit": "dB"}],
            "rows": [["fan", 30.0], ["vehicle", 35.5]],
        }
    ],
}
PAGE = """\
Text with no figure.

<!-- record benchmark="demo" device="llvmpipe" size="160x90" figures="speed" -->
{figures}<!-- end record -->

<!-- record benchmark="demo" device="llvmpipe" size="160x90" table="rows" rows="1" -->
{table}<!-- end record -->
"""
FIGURES = (
    "*The `demo` record: llvmpipe, 160x90, commit `abc1234`, 2026-11-27.*\n\n"
    "| figure | value | unit |\n|---|---|---|\n| speed | 1.235 | ms |\n"
)
TABLE = (
    "*The `demo` record: llvmpipe, 160x90, commit `abc1234`, 2026-11-27.*\n\n"
    "| scene | PSNR (dB) |\n|---|---|\n| fan | 30 |\n"
)


def test_a_region_is_filled_from_its_record():
    empty = PAGE.format(figures="", table="")
    assert doc_records.fill(empty, [RECORD]) == PAGE.format(figures=FIGURES, table=TABLE)


def test_a_region_picks_a_variant_with_where():
    """A study record of a mode is found only by a region that names it (`where=`); a region
    without `where` finds the default mode's record."""
    study = lambda mode, value: {  # noqa: E731
        **RECORD,
        "benchmark": "study",
        "params": {"size": "160x90", "mode": mode},
        "figures": [{"name": "speed", "value": value, "unit": "s"}],
    }
    records = [study("", 1.0), study("--sequence", 2.0)]
    region = '<!-- record benchmark="study" device="llvmpipe" size="160x90" figures="speed"{} -->'
    page = (region + "\n<!-- end record -->\n").format
    assert "| speed | 1 | s |" in doc_records.fill(page(""), records)
    assert "| speed | 2 | s |" in doc_records.fill(page(' where="mode=--sequence"'), records)
    with pytest.raises(ValueError, match="no study record"):
        doc_records.fill(page(' where="mode=--random 5"'), records)
    with pytest.raises(ValueError, match=r"has the variant parameters \['mode', 'scenes'\]"):
        doc_records.fill(page(' where="size=1x1"'), records)


def test_a_figure_that_differs_from_its_record_is_found(tmp_path):
    stale = PAGE.format(figures=FIGURES.replace("1.235", "1.2"), table=TABLE)
    assert doc_records.fill(stale, [RECORD]) != stale
    page = tmp_path / "page.md"
    page.write_text("Measured at commit abc1234 on 2026-11-27: 1.2 ms.\n" + stale)
    lines = [n for n, line in hand_written_lines(page) if COMMIT.search(line) or DATE.search(line)]
    assert lines == [1]  # the region's own source line is generated, not hand-written


def test_a_region_naming_what_no_record_holds_says_so():
    with pytest.raises(ValueError, match=r"page.md:3: no demo record for llvmpipe at '320x180'"):
        doc_records.fill(PAGE.replace("160x90", "320x180", 1), [RECORD], "page.md")
    with pytest.raises(ValueError, match=r"no figure \['slow'\]"):
        doc_records.fill(PAGE.replace('figures="speed"', 'figures="slow"'), [RECORD])


def test_a_method_region_is_its_folders_spec(tmp_path):
    """docs/spec.md shows each method's specification from the method's folder (spec.md), so
    the spec is written once, where the method is."""
    (tmp_path / "tent").mkdir()
    (tmp_path / "tent" / "spec.md").write_text("Taps along M, tent-weighted.\n")
    page = '# Spec\n\n<!-- method spec="tent" -->\nan old text\n<!-- end method -->\n'
    filled = doc_records.fill_specs(page, "spec.md", tmp_path)
    assert filled == page.replace("an old text", "Taps along M, tent-weighted.")
    with pytest.raises(ValueError, match=r"spec.md:3: no method folder holds .*blur/spec.md"):
        doc_records.fill_specs(page.replace('"tent"', '"blur"'), "spec.md", tmp_path)
