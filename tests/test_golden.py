"""Every method's output bits on fixed frames equal the golden file recorded before the methods
moved into blurlab.methods (tests/golden.py says what the cases are and when to record anew)."""

from __future__ import annotations

import json

import pytest
from golden import GOLDEN_FILE, compute

import blurlab as bl


def test_every_method_output_matches_the_golden_hashes():
    golden = json.loads(GOLDEN_FILE.read_text())
    if not any(device["kind"] == "software" for device in bl.Context.devices()):
        pytest.skip("golden hashes are llvmpipe's, and this machine has no software EGL device")
    ctx = bl.Context("software")
    if ctx.info()["renderer"] != golden["renderer"]:
        pytest.skip(
            f"golden hashes were recorded on {golden['renderer']}, this is "
            f"{ctx.info()['renderer']}: another JIT may round differently"
        )
    hashes = compute(ctx)
    # Methods added since have cases of their own; every recorded case must still be made.
    missing = sorted(set(golden["hashes"]) - set(hashes))
    assert not missing, f"{len(missing)} recorded cases are no longer made, e.g. {missing[:3]}"
    changed = sorted(c for c, digest in golden["hashes"].items() if hashes[c] != digest)
    assert not changed, f"{len(changed)} of {len(golden['hashes'])} outputs changed: {changed[:5]}"
