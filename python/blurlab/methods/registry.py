"""The registry of methods: what a method is (`Method`: its parameters, instant, backends, kind,
default sweep grid and NumPy twin), the lookups by name every study and the CLI use, and the
resolution of a call's values from the given ones, the defaults and the "auto" rules."""

from __future__ import annotations

import inspect
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from ..core.frame import Frame
from .params import Param, auto_refused, check_known, is_auto, typed

# What a method is, for the studies that choose methods by what they do:
#   filter    - a tile-based reconstruction filter (k, samples, soft_z): failure-suite
#               sensitivity to k and soft_z applies;
#   gather    - a post-process gather along the motion;
#   render    - renders sub-frames itself (accumulation, stochastic): `steps` does not apply,
#               and its output is not a convex combination of one frame's colors;
#   sequence  - blends a sequence of frames (trail): not swept over a single shutter.
KINDS = ("filter", "gather", "render", "sequence")


@dataclass(frozen=True, kw_only=True)
class Method:
    """A registered method: everything the rest of blurlab needs to know about it."""

    name: str
    kind: str  # one of KINDS
    params: dict[str, Param]
    # (ctx, frame, inputs: dict[str, Texture], params, backend) -> (outputs, timings)
    run: Callable
    # "center" or "close": the G-buffer time the method expects, or a function of the params
    instant: str | Callable[[dict], str] = "center"
    backends: tuple[str, ...] = ("compute",)  # the first is the default
    doc: str = ""
    # The grid `blurlab study` and `bl.sweep` use by default: {param: [values]} or a list of
    # them (their union); {} is the defaults alone.
    default_grid: dict | list = field(default_factory=dict)
    # The NumPy twin: twin(*frame arrays named by twin_inputs, **params) -> (H, W, C) color,
    # keyword-only parameters named as in `params`, with no defaults of their own.
    twin: Callable | None = None
    # The frame arrays the twin takes positionally; None: its positional parameters' names.
    twin_inputs: tuple[str, ...] | None = None
    # Parameters whose time/error curves the study report draws (the thesis's tables 5.2/5.3).
    study_curves: tuple[str, ...] = ()
    # Shown in the failure suite's image gallery (one or two methods of each kind).
    gallery: bool = False
    # The method that blurs the translucent layer in the layered approach when its
    # layer_filter is "auto" (docs/spec.md §20.4); one method says so.
    translucent_layer: bool = False
    # For a "render" method: the parameters under which it makes n renders, so that studies
    # compare such methods at equal cost (the per-object table of blurlab.studies.objects).
    renders_for: Callable[[int], dict] | None = None
    # Reproduces a shipped engine's filter under a name other than engine_*: the engines
    # benchmark shows it beside them.
    engine_peer: bool = False
    # The method examples run when they need one (the CLI's first pictures, the docs' first
    # example, tests of what every method shares); one method says so.
    example: bool = False
    # The place of its rows in sweeps, studies and the failure suite: methods() sorts by order,
    # then by registration (the modules in this package are 0; a method folder's default is
    # later, blurlab.methods.folders).
    order: float = 0
    # The names of the timings its run reports, where it declares them (a method folder's
    # passes): check-method holds the run to them. () where undeclared.
    passes: tuple[str, ...] = ()
    # The names of its tile lists (docs/spec.md §9.3) in the order of the counts its run returns
    # as the output "tile_counts"; () for a method that dispatches every pass over every pixel.
    tile_lists: tuple[str, ...] = ()
    # Pairs of parameters whose allowed values depend on each other: each may be valid alone
    # and the pair refused, with an error that names both (the fuzz test holds it to that).
    linked_params: tuple[tuple[str, str], ...] = ()
    # Where it was declared: a method folder's method.py; None for the modules in this package.
    source: str | None = None

    def __post_init__(self):
        if self.kind not in KINDS:
            raise ValueError(f"blurlab: method kind {self.kind!r} is not one of {KINDS}")
        if self.twin_inputs is None and self.twin is not None:
            object.__setattr__(self, "twin_inputs", twin_positionals(self.twin))

    @property
    def renders(self) -> bool:
        """True for methods that render sub-frames themselves: `steps` does not apply."""
        return self.kind == "render"

    @property
    def sweepable(self) -> bool:
        """True for methods a single-shutter sweep can evaluate."""
        return self.kind != "sequence"

    def defaults(self, frame: Frame | None = None, **given) -> dict:
        """Every parameter's value for a call with `given` on `frame`, validated as blur
        validates them (defaults read from the frame need a frame)."""
        return resolve_params(self, frame, given)

    def twin_output(self, frame: Frame, **given) -> np.ndarray:
        """The NumPy twin's output for `frame` with `given` parameters (the rest at their
        defaults): what the GPU passes must match."""
        if self.twin is None:
            raise ValueError(f"blurlab: {self.name} has no NumPy twin of a single frame")
        values = resolve_params(self, frame, given)
        taken = twin_keywords(self.twin)
        arrays = [getattr(frame, name) for name in self.twin_inputs]
        return self.twin(
            *arrays, **{k: v for k, v in values.items() if taken is None or k in taken}
        )


def twin_positionals(twin: Callable) -> tuple[str, ...]:
    """The names of a NumPy twin's positional parameters: the frame arrays it takes."""
    positional = (inspect.Parameter.POSITIONAL_ONLY, inspect.Parameter.POSITIONAL_OR_KEYWORD)
    parameters = inspect.signature(twin).parameters.values()
    return tuple(p.name for p in parameters if p.kind in positional)


def twin_keywords(twin: Callable) -> set[str] | None:
    """The method parameters a NumPy twin takes: its keyword-only parameters without a default
    (None where it takes **keywords, i.e. all of them). Keyword-only parameters with a default
    are extra inputs, such as a precomputed NeighborMax, not method parameters."""
    taken = set()
    for p in inspect.signature(twin).parameters.values():
        if p.kind is inspect.Parameter.VAR_KEYWORD:
            return None
        if p.kind is inspect.Parameter.KEYWORD_ONLY and p.default is inspect.Parameter.empty:
            taken.add(p.name)
    return taken


_REGISTRY: dict[str, Method] = {}
# Functions that register more methods the first time the registry is read: the methods of
# installed packages' entry points (blurlab.methods.folders), found once, when first asked for.
_DISCOVERERS: list[Callable[[], None]] = []


def register(method: Method, replace: bool = False) -> Method:
    """Adds `method` to the registry. Its name must be new; `replace=True` lets a method from
    the same source (a method folder loaded again) take its own name's place."""
    if not isinstance(method, Method):
        raise TypeError(f"blurlab: register takes a Method, not {type(method).__name__}")
    old = _REGISTRY.get(method.name)
    if old is not None and not (replace and old.source == method.source):
        raise ValueError(
            f"blurlab: a method named {method.name!r} is registered already "
            f"({describe_source(old)}); method names are unique"
            + (f", so {method.source} cannot register it too" if method.source else "")
        )
    _REGISTRY[method.name] = method
    # methods() lists by order, then by registration: a stable sort keeps the latter.
    ordered = sorted(_REGISTRY.values(), key=lambda m: m.order)
    _REGISTRY.clear()
    _REGISTRY.update((m.name, m) for m in ordered)
    return method


def unregister(name: str) -> Method:
    """Removes method `name` from the registry and returns it (a notebook or a test that
    loaded a method folder and is done with it)."""
    m = method(name)
    del _REGISTRY[name]
    return m


def describe_source(m: Method) -> str:
    """Where `m` was declared, in words."""
    return f"from {m.source}" if m.source else "built in"


def add_discoverer(discover: Callable[[], None]) -> None:
    """Runs `discover()` before the registry is next read; it may register methods."""
    _DISCOVERERS.append(discover)


def _discover() -> None:
    while _DISCOVERERS:
        _DISCOVERERS.pop(0)()


def methods() -> list[str]:
    """Names of the registered methods."""
    _discover()
    return list(_REGISTRY)


def method_instant(name: str, params: dict | None = None) -> str:
    """The G-buffer instant method `name` expects with `params` ("center" or "close")."""
    m = method(name)
    if callable(m.instant):
        return m.instant(resolve_params(m, None, params or {}, frame_free=True))
    return m.instant


def translucent_layer_method() -> str:
    """The name of the method registered with translucent_layer=True: what blurs the
    translucent layer by default (docs/spec.md §20.4)."""
    return _the_one("translucent_layer")


def example_method() -> str:
    """The name of the method registered with example=True: the one an example runs when it
    needs a method (the CLI's first pictures, the docs' first example)."""
    return _the_one("example")


def _the_one(role: str) -> str:
    _discover()
    chosen = [name for name, m in _REGISTRY.items() if getattr(m, role)]
    if len(chosen) != 1:
        raise RuntimeError(f"blurlab: exactly one method is registered {role}=True, not {chosen}")
    return chosen[0]


def method(name: str) -> Method:
    _discover()
    if name not in _REGISTRY:
        raise ValueError(f"blurlab: no method {name!r}; registered methods: {methods()}")
    return _REGISTRY[name]


def check_param(name: str, key: str, value):
    """`value` as parameter `key` of method `name` takes it, or the error a blur would raise:
    for callers (sweeps) that check their values before running anything."""
    m = method(name)
    if key not in m.params:
        raise ValueError(f"blurlab: {name} has no parameter {key!r}")
    if is_auto(value) and m.params[key].auto is not None:
        return value  # chosen per frame when the method runs
    return typed(name, key, value, m.params[key])


# Validated values of the parameter sets already seen, per method: sweeps and benchmarks call
# blur with the same few sets thousands of times. The key holds the given values and the
# defaults read from the frame (soft_z), all of the plain types below ("auto" is never cached,
# it reads the frame's motion); the cache is bounded.
_RESOLVED: dict[int, tuple[Method, dict]] = {}
_RESOLVED_MAX = 4096
_CACHEABLE_TYPES = (int, float, bool, str)


def key_item(name: str, value) -> tuple | None:
    """(name, type, value) that tells 1, 1.0, True and -0.0 apart; None for other types."""
    kind = type(value)
    if kind not in _CACHEABLE_TYPES or is_auto(value):
        return None
    return (name, kind.__name__, value.hex() if kind is float else value)


def _resolved_key(m: Method, frame: Frame | None, given: dict) -> tuple | None:
    key = []
    for name, value in given.items():
        key.append(key_item(name, value))
    for name, p in m.params.items():
        if name not in given and callable(p.default):
            key.append(key_item(name, p.default(frame)))
    return None if None in key else tuple(sorted(key))


def resolve_params(m: Method, frame: Frame | None, given: dict, frame_free: bool = False) -> dict:
    """The validated values of every parameter of `m` from `given` and the defaults (reading
    `frame` where a default or an "auto" rule needs it)."""
    key = None if frame_free else _resolved_key(m, frame, given)
    if key is None:
        return _resolve_params(m, frame, given, frame_free)
    entry = _RESOLVED.get(id(m))
    if entry is None or entry[0] is not m:
        entry = _RESOLVED[id(m)] = (m, {})
    seen = entry[1]
    if key not in seen:
        values = _resolve_params(m, frame, given, frame_free)
        if len(seen) >= _RESOLVED_MAX:
            seen.clear()
        seen[key] = values
    return dict(seen[key])


def _resolve_params(m: Method, frame: Frame | None, given: dict, frame_free: bool) -> dict:
    check_known(m.name, m.params, given)
    values = {}
    automatic = [key for key, value in given.items() if is_auto(value)]
    for key, p in m.params.items():
        value = given.get(key, None)
        if key in automatic:
            if p.auto is None:
                raise ValueError(auto_refused(m.name, key, p))
            continue  # chosen below, once the other parameters are known
        if value is None and callable(p.default) and frame_free:
            continue  # defaults read from a frame are not needed to know the instant
        if value is None:
            value = p.default(frame) if callable(p.default) else p.default
        if value is None:  # an optional parameter, such as trail's history
            values[key] = None
            continue
        values[key] = typed(m.name, key, value, p)
    if frame_free:
        return values
    for key in [key for key in m.params if key in automatic]:  # in declaration order
        if frame is None:
            raise ValueError(f"blurlab: {m.name} parameter {key}='auto' reads a frame")
        values[key] = typed(m.name, key, m.params[key].auto(frame, values), m.params[key])
    return {key: values[key] for key in m.params if key in values}
