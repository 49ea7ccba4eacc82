"""Every filter refuses bad parameters before it runs, with an error that names the parameter,
the value and what is allowed (docs/reliability.md). The bad values come from each parameter's
declaration: below and above its range, not finite, not an integer, a choice it does not offer,
not True or False; and a parameter the method does not take."""

from __future__ import annotations

import re

import pytest
from conftest import random_frame
from method_picks import builtin, picks

import blurlab as bl
from blurlab.methods.params import FLOAT32_MAX


def bad_values(key, p) -> list[tuple[object, type, str]]:
    """The values parameter `key`, declared as `p`, refuses: (value, error, message regex)."""
    allowed = re.escape(p.allowed())
    if isinstance(p.kind, tuple):
        return [("no such choice", ValueError, rf"{key} must be {allowed}")]
    if p.kind is bool:
        return [(1, TypeError, rf"{key} must be True or False")]
    if p.kind not in (int, float):
        return []
    bad = []
    if p.low is not None:
        low = p.low if p.low_open else p.low - 1
        bad.append(p.kind(low))
    if p.high is not None and p.high < FLOAT32_MAX:
        bad.append(p.kind(p.high + 1))
    cases = [(v, ValueError, rf"{key} = {re.escape(repr(v))} .*{allowed}") for v in bad]
    if p.kind is int:
        return [*cases, (2.5, TypeError, rf"{key} must be an integer \({allowed}\)")]
    return [
        *cases,
        (float("nan"), ValueError, rf"{key} must be finite"),
        (float("inf"), ValueError, rf"{key} must be finite"),
    ]


def foreign(name) -> str:
    """A parameter another built-in method takes and `name` does not."""
    own = bl.method(name).params
    return next(k for other in builtin() for k in bl.method(other).params if k not in own)


def refusals(name):
    m = bl.method(name)
    first = next(iter(m.params))
    unknown = foreign(name)
    cases = [({unknown: 3}, TypeError, rf"no parameter.*{unknown}.*{first}")]
    for key, p in m.params.items():
        cases += [({key: value}, error, message) for value, error, message in bad_values(key, p)]
    return cases


CASES = [
    pytest.param(name, *case, id=f"{name}-{next(iter(case[0]))}={next(iter(case[0].values()))}")
    for name in picks(kind=("filter", "gather"))
    for case in refusals(name)
]


@pytest.mark.parametrize(("method", "params", "error", "message"), CASES)
def test_a_bad_parameter_is_refused_in_words(ctx, rng, method, params, error, message):
    with pytest.raises(error, match=message):
        bl.blur(ctx, random_frame(rng, 16, 16), method, **params)


def test_every_filter_has_bad_values_to_refuse():
    """Each filter and gather has a declared range or choice to be refused outside of."""
    for name in picks(kind=("filter", "gather")):
        assert len(refusals(name)) > 1, name
