"""Validated parameter sets are cached per method (methods.core.resolve_params): a repeat call
must see exactly what a first call sees, and the cache must not blur types or signs together."""

from __future__ import annotations

import importlib
import math

import pytest
from method_picks import pick

import blurlab as bl

core = importlib.import_module("blurlab.methods.core")
# A method with a frame-read default (soft_z) and a float that may be -0.0 (early_exit).
METHOD = pick(params=("k", "samples", "soft_z", "early_exit"))


def test_a_repeat_call_gets_equal_values_it_may_change_freely():
    m = bl.method(METHOD)
    given = {"k": 20, "samples": 15, "soft_z": 0.5}
    first = core.resolve_params(m, None, given)
    first["k"] = 999  # the caller's copy, not the cache's
    again = core.resolve_params(m, None, given)
    assert again["k"] == 20 and again == core.resolve_params(m, None, given, frame_free=True)


def test_types_and_signs_stay_apart():
    m = bl.method(METHOD)
    assert core.resolve_params(m, None, {"k": 20, "soft_z": 1})["soft_z"] == 1.0
    for not_an_int in (20.0, True):  # equal to a cached k = 20 or 1 as dict keys
        with pytest.raises(TypeError, match="k must be an integer"):
            core.resolve_params(m, None, {"k": not_an_int, "soft_z": 1})
    given = [{"soft_z": 1.0, "early_exit": z} for z in (-0.0, 0.0, -0.0)]
    signs = [core.resolve_params(m, None, g)["early_exit"] for g in given]
    assert [math.copysign(1.0, z) for z in signs] == [-1.0, 1.0, -1.0]


def test_defaults_read_from_the_frame_are_part_of_the_key(ctx):
    m = bl.method(METHOD)
    near = ctx.render(bl.scenes.fan(), (32, 18))
    far = ctx.render(bl.scenes.vehicle(), (32, 18))
    values = [core.resolve_params(m, f, {"k": 8})["soft_z"] for f in (near, far, near)]
    assert values[0] == values[2] != values[1]
    assert values[1] == m.params["soft_z"].default(far)


def test_bad_values_raise_every_time():
    m = bl.method(METHOD)
    for _ in range(2):
        with pytest.raises(ValueError, match=r"k = 0 is outside"):
            core.resolve_params(m, None, {"k": 0, "soft_z": 1.0})
