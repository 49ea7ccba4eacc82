"""The contract every method meets (blurlab.methods.contract, `blurlab check-method`),
parametrised over the registry: a method added later is checked without a line of its own.
Its frames are small (48 x 27, and 1 x 1 and odd sizes), so every method's checks fit in CI."""

from __future__ import annotations

import pytest

import blurlab as bl
from blurlab.methods.contract import check_method, table


@pytest.mark.parametrize("name", bl.methods())
def test_every_method_meets_the_contract(ctx, name):
    checks = check_method(ctx, name)
    assert all(c.passed is not False for c in checks), table(name, checks)
    # Every built-in has a twin, except those whose output is no single frame's function.
    skipped = [c.name for c in checks if c.passed is None]
    assert bl.method(name).twin is None or not skipped, skipped
