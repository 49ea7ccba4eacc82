"""Methods picked by what their declarations say, for the tests of what methods share: no test
outside a method's folder names a method (tests/test_house.py), so a test that needs "a tile
filter" or "a method with k" asks the registry for one. A method's own behaviour is tested in
its folder (python/blurlab/methods/<name>/test_*.py)."""

from __future__ import annotations

import blurlab as bl
from blurlab.methods import example_method


def builtin() -> list[str]:
    """The built-in methods, in the registry's order."""
    return [name for name in bl.methods() if bl.method(name).source is None]


def picks(*, kind=None, params=(), backends=(), role=None, twin=None, exclude=()) -> list[str]:
    """The built-in methods, in order, of `kind` (a kind or a tuple of kinds), that take every
    parameter in `params`, run on every backend in `backends`, are declared with the role
    `role` (a Method flag: "gallery", "engine_peer", ...), have a twin (twin=True) or not."""
    kinds = (kind,) if isinstance(kind, str) else kind
    chosen = []
    for name in builtin():
        m = bl.method(name)
        if name in exclude or (kinds is not None and m.kind not in kinds):
            continue
        if not set(params) <= set(m.params) or not set(backends) <= set(m.backends):
            continue
        if role is not None and not getattr(m, role):
            continue
        if twin is not None and (m.twin is not None) != twin:
            continue
        chosen.append(name)
    return chosen


def pick(**what) -> str:
    """The first built-in method that `picks(**what)` finds; an error where none is."""
    chosen = picks(**what)
    if not chosen:
        raise LookupError(f"no built-in method is {what}")
    return chosen[0]


# The method examples run (registered example=True): a tile filter with k and samples.
EXAMPLE = example_method()
