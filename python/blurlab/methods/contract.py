"""The contract every method meets, built in or loaded from a folder (`blurlab check-method`,
tests/test_method_contract.py): it runs; its NumPy twin agrees on random and rendered frames
(the tolerance of docs/spec.md §13); out-of-range parameters are refused by name; NaN and
infinity in the input and finite input give finite output; the same call gives the same bits;
1×1 and odd sizes work; its timings name every pass it declares; no GL error is left behind."""

from __future__ import annotations

import dataclasses
import math
import traceback
import warnings
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..core.context import Context
from ..core.frame import Frame
from ..scene import scenes
from .core import blur, method, method_instant
from .params import FLOAT32_MAX, Param
from .registry import Method

SIZE = (48, 27)  # the random and rendered frames: small, so a check of every method is fast
ODD_SIZES = ((1, 1), (7, 1), (1, 5), (13, 9))
SCENE = "teapot_pass"  # a rendered scene with motion of several directions and depths
# The twin tolerance of docs/spec.md §13: 99.9 % of pixels within 1e-3, a mean below 1e-4.
WITHIN, SHARE, MEAN = 1e-3, 0.999, 1e-4
SEED = 20261207


@dataclass
class Check:
    """One check's outcome: passed True or False, or None where it does not apply."""

    name: str
    passed: bool | None
    detail: str = ""


class _Failed(Exception):
    pass


def check_method(ctx: Context, name: str, size=SIZE) -> list[Check]:
    """Runs every check of the contract on registered method `name` and returns them in
    order; a method that does not run at all fails the first and skips the rest."""
    m = method(name)
    checker = _Checker(ctx, m, size)
    ctx.gl_errors()  # errors left by earlier work are not this method's
    checks = [checker.check("runs", checker.runs)]
    if not checks[0].passed:
        rest = [n for n, _ in checker.checks()]
        return checks + [Check(n, None, "not run: the method does not run") for n in rest]
    checks += [checker.check(n, fn) for n, fn in checker.checks()]
    return checks


def table(name: str, checks: list[Check]) -> str:
    """The checks as a text table, one line each."""
    width = max(len(c.name) for c in checks)
    lines = [f"check-method {name}"]
    for c in checks:
        mark = {True: "passed", False: "FAILED", None: "skipped"}[c.passed]
        detail = c.detail.replace("\n", "\n" + " " * (width + 12))
        lines.append(f"  {c.name:<{width}}  {mark:<7}  {detail}".rstrip())
    failed = sum(c.passed is False for c in checks)
    lines.append(
        f"{len(checks) - failed} of {len(checks)} checks passed or skipped, {failed} failed"
    )
    return "\n".join(lines)


class _Checker:
    def __init__(self, ctx: Context, m: Method, size):
        self.ctx, self.m = ctx, m
        self.size = tuple(size)
        self.rng = np.random.default_rng(SEED)
        # Methods that render or blend frames, or read the camera, get rendered frames only.
        self.rendered_only = m.renders or m.kind == "sequence"
        self.left: list[str] = []  # GL errors found set after a call of the method

    def checks(self) -> list[tuple[str, Callable[[], str]]]:
        return [
            ("twin_on_random_frames", self.twin_random),
            ("twin_on_a_rendered_frame", self.twin_rendered),
            ("ranges_refused_by_name", self.ranges),
            ("finite_for_finite_input", self.finite),
            ("finite_for_nan_and_inf_input", self.nonfinite),
            ("same_call_same_bits", self.determinism),
            ("sizes_1x1_and_odd", self.sizes),
            ("timings_name_every_pass", self.timings),
            ("no_gl_error_left", self.gl_errors),
        ]

    def check(self, name: str, fn: Callable[[], str | None]) -> Check:
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")  # a frame at another instant warns; not a failure
                detail = fn()
        except _Failed as failure:
            return Check(name, False, str(failure))
        except Exception as error:  # any error of the method's is this check's failure
            text = str(error).strip() or traceback.format_exc(limit=2)
            return Check(name, False, f"{type(error).__name__}: {text}")
        if detail is not None and detail.startswith("skipped"):
            return Check(name, None, detail.removeprefix("skipped: "))
        return Check(name, True, detail or "")

    # Frames ---------------------------------------------------------------------------------

    def frame(self, width: int, height: int, params: dict | None = None) -> Frame:
        """A frame for the method: random arrays, or (a method that renders) a rendered one."""
        if self.rendered_only:
            return self.rendered(width, height, params)
        rng = self.rng
        color = rng.random((height, width, 4), dtype=np.float32)
        depth = rng.uniform(1.0, 10.0, (height, width)).astype(np.float32)
        depth[rng.random((height, width)) < 0.2] = np.inf
        angle = rng.uniform(0, 2 * np.pi, (height, width))
        length = rng.uniform(1.1, 20.0, (height, width))
        motion = np.stack([np.cos(angle), np.sin(angle)], -1) * length[..., None]
        return Frame(color=color, depth=depth, motion=motion.astype(np.float32))

    def rendered(self, width: int, height: int, params: dict | None = None) -> Frame:
        instant = self.instant(params)
        return self.ctx.render(scenes.get(SCENE), (width, height), instant=instant)

    def instant(self, params: dict | None) -> str:
        return method_instant(self.m.name, params)

    def blur(self, frame: Frame, **params):
        """The method's result; GL errors it left set are read (and so cleared) at once, before
        a download would report them as its own, and kept for no_gl_error_left."""
        try:
            return blur(self.ctx, frame, self.m.name, **params)
        finally:
            self.left += self.ctx.gl_errors()

    def points(self) -> list[dict]:
        """The defaults and the first and last points of the default grid."""
        grid = self.m.default_grid
        parts = [grid] if isinstance(grid, dict) else list(grid)
        points = [{}]
        for part in parts[:2]:
            if part:
                points.append({key: values[0] for key, values in part.items()})
                points.append({key: values[-1] for key, values in part.items()})
        unique = []
        for point in points:
            if point not in unique:
                unique.append(point)
        return unique

    # Checks ---------------------------------------------------------------------------------

    def runs(self) -> str:
        try:
            result = self.blur(self.frame(*self.size))
        except ValueError:
            # A frame of arrays may be refused (camera_only reads the camera): rendered ones
            # must do.
            if self.rendered_only:
                raise
            self.rendered_only = True
            result = self.blur(self.frame(*self.size))
        _expect(result.color.shape == (self.size[1], self.size[0], 4), "the output's shape")
        frames = "rendered frames" if self.rendered_only else "frames of random arrays"
        return f"{self.size[0]}x{self.size[1]} at its defaults, on {frames}"

    def agree(self, frame: Frame, params: dict, what: str) -> None:
        result = self.blur(frame, **params)
        expected = self.m.twin_output(frame, **result.params)
        error = np.abs(np.asarray(result.color, np.float64) - expected)
        error = np.where(np.isnan(error), np.inf, error)
        share = float((error.max(axis=-1) <= WITHIN).mean())
        mean = float(error.mean())
        _expect(
            share >= SHARE and mean <= MEAN,
            f"{what} with {params or 'the defaults'}: {share:.4f} of pixels within {WITHIN:g} "
            f"of the twin (needs {SHARE}), mean error {mean:.2e} (needs <= {MEAN:g})",
        )

    def twin_random(self) -> str:
        if self.m.twin is None:
            return "skipped: no NumPy twin"
        sizes = [self.size, (max(1, self.size[0] - 9) | 1, max(1, self.size[1] - 4) | 1)]
        points = self.points()
        for index, point in enumerate(points):
            width, height = sizes[index % 2]
            self.agree(self.frame(width, height, point), point, f"a random {width}x{height} frame")
        return f"{len(points)} parameter sets"

    def twin_rendered(self) -> str:
        if self.m.twin is None:
            return "skipped: no NumPy twin"
        frame = self.rendered(*self.size)
        self.agree(frame, {}, f"{SCENE} at {self.size[0]}x{self.size[1]}")
        return SCENE

    def ranges(self) -> str:
        """Each parameter refuses a value outside its declaration, of the error's type, in a
        message that names it and what is allowed; an unknown one is refused listing them."""
        frame = self.frame(8, 6)
        refused = 0
        for key, p in self.m.params.items():
            for value, error_type in _outside(p):
                try:
                    self.blur(frame, **{key: value})
                except (TypeError, ValueError) as error:
                    text = str(error)
                    _expect(
                        isinstance(error, error_type) and key in text and p.allowed() in text,
                        f"{key}={value!r} was refused as {type(error).__name__}: {text!r}; "
                        f"expected a {error_type.__name__} naming {key} and {p.allowed()!r}",
                    )
                    refused += 1
                    continue
                raise _Failed(f"{key}={value!r} is outside {p.allowed()} and was accepted")
        try:
            self.blur(frame, no_such_parameter=1)
        except TypeError as error:
            unnamed = [key for key in self.m.params if key not in str(error)]
            _expect(not unnamed, f"an unknown parameter's error leaves out {unnamed}: {error}")
            refused += 1
        else:
            raise _Failed("an unknown parameter was accepted")
        return f"{refused} bad values refused"

    def finite(self) -> str:
        for point in self.points():
            out = self.blur(self.frame(*self.size, point), **point).color
            bad = int(np.count_nonzero(~np.isfinite(out)))
            _expect(
                bad == 0, f"{bad} non-finite values for finite input with {point or 'defaults'}"
            )
        return ""

    def nonfinite(self) -> str:
        frame = self.frame(*self.size)
        color, depth, motion = frame.color.copy(), frame.depth.copy(), frame.motion.copy()
        for array, values in (
            (color, [np.nan, np.inf, -np.inf, 3e38]),
            (depth, [np.nan, -np.inf, 0.0, -2.0]),
            (motion, [np.nan, np.inf, -np.inf, 3e38]),
        ):
            mask = self.rng.random(array.shape) < 0.1
            array[mask] = self.rng.choice(values, int(mask.sum()))
        poisoned = dataclasses.replace(frame, color=color, depth=depth, motion=motion, textures={})
        out = self.blur(poisoned).color
        bad = int(np.count_nonzero(~np.isfinite(out)))
        _expect(bad == 0, f"{bad} non-finite output values from NaN and inf in the input")
        return ""

    def determinism(self) -> str:
        frame = self.frame(*self.size)
        again = dataclasses.replace(frame, textures={})
        first = self.blur(frame).color
        second = self.blur(frame).color
        third = self.blur(again).color
        _expect(first.tobytes() == second.tobytes(), "two calls on one frame differ")
        _expect(first.tobytes() == third.tobytes(), "the same arrays uploaded again differ")
        return ""

    def sizes(self) -> str:
        for width, height in ODD_SIZES:
            frame = self.frame(width, height)
            result = self.blur(frame)
            _expect(
                result.color.shape == (height, width, 4),
                f"{width}x{height}: shape {result.color.shape}",
            )
            _expect(np.isfinite(result.color).all(), f"{width}x{height}: non-finite output")
            if self.m.twin is not None:
                self.agree(frame, {}, f"a {width}x{height} frame")
        return ", ".join(f"{w}x{h}" for w, h in ODD_SIZES)

    def timings(self) -> str:
        result = self.blur(self.frame(*self.size))
        named = list(result.timings)
        _expect(named, "no timings")
        for key, timing in result.timings.items():
            _expect(bool(timing.clock), f"timing {key} has no clock")
            _expect(timing.ms >= 0 and math.isfinite(timing.ms), f"timing {key} = {timing.ms} ms")
        # A pass run once per tile class is timed as name[class] (methods.tiles.run_over_list).
        passes = {key.split("[", 1)[0] for key in named}
        missing = [p for p in self.m.passes if p not in passes]
        _expect(not missing, f"no timing for the declared passes {missing} (timings: {named})")
        return ", ".join(named)

    def gl_errors(self) -> str:
        errors = self.left + self.ctx.gl_errors()
        _expect(not errors, f"GL errors left set after its calls: {sorted(set(errors))}")
        return "after each call"


def _expect(condition: bool, message: str) -> None:
    if not condition:
        raise _Failed(message)


def _outside(p: Param) -> list[tuple[object, type]]:
    """Values `p` refuses, each with the error it raises: just below and above its range, a
    value of the wrong type, NaN."""
    if isinstance(p.kind, tuple):
        return [("no_such_choice", ValueError), (1, ValueError)]
    if p.kind is bool:
        return [(2, TypeError)]
    if p.kind not in (int, float):
        return []
    values: list[tuple[object, type]] = []
    if p.kind is int:
        if p.low is not None:
            values.append((int(p.low) - 1, ValueError))
        if p.high is not None:
            values.append((int(p.high) + 1, ValueError))
        return values + [((p.low or 0) + 0.5, TypeError)]
    if p.low is not None:
        values.append((float(p.low) if p.low_open else p.low - max(1.0, abs(p.low)), ValueError))
    if p.high is not None:
        above = math.inf if p.high >= FLOAT32_MAX else p.high + max(1.0, abs(p.high))
        values.append((float(above), ValueError))
    return values + [(math.nan, ValueError)]
