"""Parameters: the declaration (`Param`) and the one check every value passes (`typed`), for
methods, TAA, the layers and the benchmarks alike. Each parameter is declared once, in the module
of what takes it."""

from __future__ import annotations

import math
import struct
from collections.abc import Callable
from dataclasses import KW_ONLY, dataclass
from numbers import Integral, Real

import numpy as np


@dataclass(frozen=True)
class WithdrawnAuto:
    """An "auto" rule withdrawn because it lost to the parameter's default on scenes no fit
    had read (docs/spec.md §14). The parameter refuses "auto" with an error naming `instead`;
    the rule stays so that the auto_holds benchmark shows, on every run, why it went."""

    rule: Callable  # rule(frame, values) -> a value, as Param.auto
    instead: str  # what to pass instead, in words


@dataclass(frozen=True)
class Param:
    """One parameter: its default, its type and, for numbers, its allowed range.

    Every value passes through ``typed`` before it is used, so a method (or TAA, a layer, a
    benchmark) never sees a value of the wrong type or outside [low, high]: the error names the
    owner, the parameter, the value and what is allowed. The flags are keyword-only.
    """

    default: object  # a value, or a callable(frame) -> value
    kind: object  # int, float, bool, str (any text), a tuple of allowed strings, or object
    doc: str
    low: float | None = None  # inclusive bounds for int and float parameters
    high: float | None = None
    _: KW_ONLY
    low_open: bool = False  # True: the value must be > low (e.g. soft_z > 0)
    # The rule that `"auto"` stands for: auto(frame, values) -> a value, where `values` holds
    # the call's other parameters (so a rule may read, say, the exposure); None: no "auto".
    auto: Callable | None = None
    # A rule withdrawn for failing the bar on held-out scenes: "auto" is refused, naming what
    # to pass instead.
    withdrawn_auto: WithdrawnAuto | None = None

    def allowed(self) -> str:
        """What values are allowed, in words (for error messages and docs)."""
        values = self._allowed_values()
        return values + ', or "auto"' if self.auto is not None else values

    def _allowed_values(self) -> str:
        if isinstance(self.kind, tuple):
            return "one of " + ", ".join(repr(k) for k in self.kind)
        if self.kind is bool:
            return "True or False"
        if self.kind is str:
            return "text"
        if self.kind is object:
            return "any value"
        if self.low is not None and self.high is not None and not self.low_open:
            if self.kind is int:
                return f"{_num(self.low)}..{_num(self.high)}"
            return f"[{_num(self.low)}, {_num(self.high)}]"
        bounds = []
        if self.low is not None:
            bounds.append(f"{'>' if self.low_open else '>='} {_num(self.low)}")
        if self.high is not None:
            bounds.append(f"<= {_num(self.high)}")
        return "finite" + "".join(" and " + b for b in bounds) if bounds else "finite"


SEED_MAX = 2**32 - 1
FLOAT32_MAX = float(np.finfo(np.float32).max)  # float parameters go to the GPU as float32
# Exposure and intensity scale motion, which the passes read as at most 2^20 px per component
# (shaders/common/inputs.glsl, docs/reliability.md); up to 1000 x that, tap positions stay
# below 2^31 px, where GLSL's float-to-int conversion is defined.
PARAM_SCALE_MAX = 1000.0
# Every method with random choices (jitter, stochastic times) takes this one seed parameter.
SEED = Param(0, int, "seed of the method's random choices", 0, SEED_MAX)


def _num(x: float) -> str:
    if float(x).is_integer() and abs(x) >= 2**16:
        exponent = math.log2(abs(x) + (1 if x < 0 else 0))
        if exponent.is_integer():
            return f"2^{int(exponent)}" if x > 0 else f"-2^{int(exponent)}"
        if math.log2(x + 1).is_integer():
            return f"2^{int(math.log2(x + 1))}-1"
    return f"{x:g}"


def is_auto(value) -> bool:
    return isinstance(value, str) and value == "auto"


def auto_refused(owner: str, key: str, p: Param) -> str:
    """The error for `"auto"` given to parameter `key` of `owner`, which has no live rule."""
    if p.withdrawn_auto is None:
        return f"blurlab: {owner} parameter {key} has no 'auto' rule"
    return (
        f'blurlab: {owner} parameter {key}="auto" was withdrawn: its rule lost to the default '
        f"on held-out scenes (docs/recommend.md). {p.withdrawn_auto.instead}"
    )


def check_known(owner: str, params: dict[str, Param], given) -> None:
    """A TypeError naming `owner`'s parameters (and defaults) if `given` names any other."""
    unknown = set(given) - set(params)
    if unknown:
        raise TypeError(
            f"blurlab: {owner} has no parameter(s) {sorted(unknown)}; its parameters are "
            + ", ".join(f"{k} (default {describe(p.default)})" for k, p in params.items())
        )


def describe(default) -> str:
    return "from the frame" if callable(default) else repr(default)


def typed(owner: str, key: str, value, p: Param):
    """`value` as parameter `key` of `owner` (a method, "taa", "benchmark NAME") takes it: the
    one place where every parameter is type- and range-checked. Every error names the owner,
    the parameter, the value and what is allowed."""
    where = f"blurlab: {owner} parameter {key}"
    if p.withdrawn_auto is not None and is_auto(value):
        raise ValueError(auto_refused(owner, key, p))
    kind = p.kind
    if kind is object:
        return value
    if kind is str:
        if not isinstance(value, str):
            raise TypeError(f"{where} must be text ({p.doc}), not {_show(value)}")
        return value
    if kind is bool:
        if not isinstance(value, (bool, np.bool_)):
            raise TypeError(f"{where} must be True or False, not {_show(value)}")
        return bool(value)
    if isinstance(kind, tuple):
        # Compare strings only: `value in kind` on an array or other odd object may itself raise.
        if not isinstance(value, str) or value not in kind:
            raise ValueError(f"{where} must be {p.allowed()}, not {_show(value)}")
        return value
    if kind is int:
        if isinstance(value, bool) or not isinstance(value, Integral):
            raise TypeError(f"{where} must be an integer ({p.allowed()}), not {_show(value)}")
        value = int(value)
    else:
        if isinstance(value, bool) or not isinstance(value, Real):
            raise TypeError(f"{where} must be a number ({p.allowed()}), not {_show(value)}")
        try:
            value = float(value)
        except OverflowError:  # an int beyond float's range
            value = math.inf
        if not math.isfinite(value):
            raise ValueError(f"{where} must be finite ({p.allowed()}), not {_show(value)}")
    # The GPU gets float32: check the value it will see (1e-50 is 0 there, 1e39 is inf).
    seen = as_float32(value) if kind is float else value
    if kind is float and not math.isfinite(seen):
        raise ValueError(f"{where} = {_show(value)} overflows float32 ({p.allowed()})")
    too_low = p.low is not None and (seen <= p.low if p.low_open else seen < p.low)
    too_high = p.high is not None and seen > p.high
    if too_low or too_high:
        closed = p.low is not None and p.high is not None and not p.low_open
        verb = "is outside" if closed else "must be"
        raise ValueError(f"{where} = {_show(value)} {verb} {p.allowed()}")
    return value


_FLOAT32 = struct.Struct("f")


def as_float32(value: float) -> float:
    """`value` rounded to float32 as the GPU receives it; ±inf where it overflows."""
    try:
        return _FLOAT32.unpack(_FLOAT32.pack(value))[0]
    except OverflowError:
        return math.copysign(math.inf, value)


def _show(value) -> str:
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."
