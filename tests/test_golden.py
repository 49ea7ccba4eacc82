"""Every method's output bits on fixed frames equal the golden file recorded before the methods
moved into blurlab.methods (tests/golden.py says what the cases are and when to record anew)."""

from __future__ import annotations

import json

import pytest
from golden import GOLDEN_FILE, compute

import blurlab as bl


def test_every_method_output_matches_the_golden_hashes():
    golden = json.loads(GOLDEN_FILE.read_text())
    ctx = bl.Context("software")
    if ctx.info()["renderer"] != golden["renderer"]:
        pytest.skip(
            f"golden hashes were recorded on {golden['renderer']}, this is "
            f"{ctx.info()['renderer']}: another JIT may round differently"
        )
    hashes = compute(ctx)
    assert set(hashes) == set(golden["hashes"]), "the set of cases changed"
    changed = sorted(case for case, digest in hashes.items() if golden["hashes"][case] != digest)
    assert not changed, f"{len(changed)} of {len(hashes)} outputs changed, e.g. {changed[:5]}"
