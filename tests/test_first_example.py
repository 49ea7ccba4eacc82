"""The first example (README's "Ten lines", docs/quickstart.md) is the code the first_example
benchmark runs, and its llvmpipe record keeps within the goal. The benchmark's tiny run
(tests/test_bench.py) runs the example and checks the columns its comment names."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

import blurlab_bench as bench
from blurlab_bench.first_example import EXAMPLE, GOAL_S, documented_columns

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.parametrize("page", ["README.md", "docs/quickstart.md"])
def test_the_pages_show_the_benchmarked_example(page):
    blocks = re.findall(r"```python\n(.*?)```", (ROOT / page).read_text(), re.S)
    assert EXAMPLE in blocks, f"{page}'s first example is not first_example.EXAMPLE"


def test_the_comment_names_sweep_columns():
    assert documented_columns() == ["method", "params", "total_ms", "psnr"]


def test_the_llvmpipe_record_is_within_the_goal():
    records = bench.read_records(ROOT / "benchmarks" / "records.jsonl")
    (record,) = [r for r in records if r["benchmark"] == "first_example" and
                 r["device"] == "llvmpipe"]  # fmt: skip
    figures = {f["name"]: f["value"] for f in record["figures"]}
    assert figures["wall time, median of the runs"] <= GOAL_S
    assert figures["CPU cores"] == 2
