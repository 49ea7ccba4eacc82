"""Method folders: a method declared in a folder of its own, outside the package or in an
installed package, loaded into the same registry as the built-in methods
(docs/adding_a_method.md).

A folder holds ``method.py``, whose ``METHOD`` is a `Declaration` (name, kind, instant, order,
parameters with their ranges, passes, optional NumPy twin), the passes' shaders (GLSL, or HLSL
compute shaders translated by blurlab.methods.hlsl), its spec text and its tests. Its shaders are
found beside method.py, and their ``#include "common/..."`` lines reach blurlab's shared
includes. ``load_methods(path)`` loads one folder or a folder of them; installed packages offer
theirs through the entry-point group ``blurlab.methods``, found the first time the registry is
read."""

from __future__ import annotations

import hashlib
import importlib
import importlib.metadata
import importlib.util
import re
import sys
import types
import warnings
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

from . import hlsl
from .chain import chain_run
from .params import Param, typed
from .passes import Pass, choice_defines
from .registry import (
    KINDS,
    Method,
    add_discoverer,
    describe_source,
    methods,
    register,
    twin_keywords,
    twin_positionals,
    unregister,
)
from .registry import method as registered

DECLARATION_FILE = "method.py"
# The folder `blurlab new-method` copies (blurlab.methods.template): a method folder, not a
# built-in method.
TEMPLATE_FOLDER = "template_files"
ENTRY_POINT_GROUP = "blurlab.methods"
GLSL_SUFFIXES = (".glsl", ".comp")
# A method folder's rows come after the built-in methods' (order 0) unless it says otherwise.
DEFAULT_ORDER = 1000
BACKENDS = ("compute", "fragment")
INSTANTS = ("center", "close")
# What a twin may take from the frame by name: its arrays, the two-sided motion (docs/spec.md
# §17.1) and the camera's matrices (None where the frame has none), as the engines' twins do.
FRAME_ARRAYS = ("color", "depth", "motion", "motion_prev", "motion_next", "camera")
NAME = re.compile(r"[a-z][a-z0-9_]{0,63}")
# Kinds a chain of passes can be: the others render or blend frames, which needs a run.
CHAIN_KINDS = ("filter", "gather")


class MethodFolderError(ValueError):
    """A method folder that cannot be loaded; the message names the file and what is wrong."""


@dataclass(frozen=True, kw_only=True)
class Declaration:
    """What a method folder's method.py declares as ``METHOD``.

    `passes` run in order (blurlab.methods.chain): each `Pass(name, shader, params)` names its
    timing, its shader file in the folder (.glsl or .comp: GLSL 4.50; .hlsl: an HLSL compute
    shader) and the parameters it takes as uniforms of the same names. A method whose passes
    need more wiring than a chain gives `run(ctx, frame, inputs, values, backend, passes)`, with
    `passes` the declared ones by name, their shaders resolved; such a method may declare no
    passes where it only renders or blends frames with blurlab's own."""

    name: str
    kind: str  # one of CHAIN_KINDS, or any of KINDS with a `run`
    params: dict[str, Param]
    passes: tuple[Pass, ...]
    doc: str
    instant: str | Callable[[dict], str] = "center"
    order: float = DEFAULT_ORDER
    backends: tuple[str, ...] = ("compute",)
    default_grid: dict | list = field(default_factory=dict)
    twin: Callable | None = None  # as Method.twin: optional for a method folder
    twin_inputs: tuple[str, ...] | None = None
    run: Callable | None = None
    # The roles studies and benchmarks choose methods by, as Method declares them: so that no
    # code outside a method's folder names it.
    study_curves: tuple[str, ...] = ()
    gallery: bool = False
    translucent_layer: bool = False
    example: bool = False
    renders_for: Callable[[int], dict] | None = None
    engine_peer: bool = False
    tile_lists: tuple[str, ...] = ()
    linked_params: tuple[tuple[str, str], ...] = ()


def load_methods(path) -> list[str]:
    """Loads the method folder at `path` (a folder with a method.py), or every method folder
    directly inside it, into the registry; returns their names. A name already registered is
    refused, unless it came from the same method.py (loading a folder again replaces it)."""
    folder = Path(path).expanduser()
    if not folder.is_dir():
        raise MethodFolderError(
            f"blurlab: {folder} is not a folder (a method folder or a folder of them)"
        )
    if (folder / DECLARATION_FILE).is_file():
        files = [folder / DECLARATION_FILE]
    else:
        files = sorted(p for p in folder.glob(f"*/{DECLARATION_FILE}") if p.is_file())
    if not files:
        raise MethodFolderError(
            f"blurlab: {folder} has no {DECLARATION_FILE}, nor has any folder inside it: a method "
            f"folder declares its method there (METHOD = Declaration(...))"
        )
    loaded = [_method(file.resolve()) for file in files]
    names = [m.name for m in loaded]
    twice = {n for n in names if names.count(n) > 1}
    if twice:
        raise MethodFolderError(f"blurlab: {folder}: more than one folder declares {sorted(twice)}")
    for m in loaded:
        _check_new(m)
    for m in loaded:
        register(m, replace=True)
    return names


def unload_methods(names) -> None:
    """Removes the methods `names` that load_methods registered."""
    for name in names:
        if registered(name).source is None:
            raise ValueError(f"blurlab: {name} is built in; only loaded methods unload")
        unregister(name)


def _check_new(m: Method) -> None:
    if m.name not in methods():
        return
    old = registered(m.name)
    if old.source != m.source:
        what = "the built-in method" if old.source is None else f"the method {describe_source(old)}"
        raise MethodFolderError(
            f"blurlab: {m.source} declares {m.name!r}, the name of {what}; method names are "
            "unique, so give this one another"
        )


def _method(file: Path) -> Method:
    declaration = _declaration(file)
    return method_of(declaration, file.parent, str(file))


def load_builtin_methods() -> list[str]:
    """Registers blurlab's own methods: each folder of this package with a method.py, imported
    as a module of the package (blurlab.methods.<name>.method) and declared as a user's folder
    is. Methods are found, not listed: a new folder is a new method."""
    names = []
    for file in sorted(Path(__file__).parent.glob(f"*/{DECLARATION_FILE}")):
        if file.parent.name == TEMPLATE_FOLDER:
            continue
        module = importlib.import_module(f"{__package__}.{file.parent.name}.method")
        declaration = _declared(module, file)
        if declaration.name != file.parent.name:
            raise MethodFolderError(
                f"blurlab: {file} declares {declaration.name!r}; a built-in method's folder "
                "is named as the method"
            )
        register(method_of(declaration, file.parent, str(file), builtin=True))
        names.append(declaration.name)
    return names


def _declaration(file: Path) -> Declaration:
    """Runs method.py as a package of its folder (so that `from .twin import ...` works) and
    returns its METHOD."""
    package = "blurlab_method_" + hashlib.sha256(str(file).encode()).hexdigest()[:12]
    for loaded in [m for m in sys.modules if m == package or m.startswith(package + ".")]:
        del sys.modules[loaded]  # a folder loaded again is read again
    spec = importlib.util.spec_from_file_location(
        package, file, submodule_search_locations=[str(file.parent)]
    )
    module = importlib.util.module_from_spec(spec)
    sys.modules[package] = module
    try:
        spec.loader.exec_module(module)
    except Exception as error:
        del sys.modules[package]
        raise MethodFolderError(
            f"blurlab: {file} failed to run: {type(error).__name__}: {error}"
        ) from error
    return _declared(module, file)


def _declared(module, file: Path) -> Declaration:
    """The METHOD that `module`, run from `file`, declares."""
    declaration = getattr(module, "METHOD", None)
    if not isinstance(declaration, Declaration):
        raise MethodFolderError(
            f"blurlab: {file} must set METHOD = blurlab.methods.Declaration(...), "
            f"not {'nothing' if declaration is None else type(declaration).__name__}"
        )
    return declaration


def method_of(d: Declaration, folder: Path, source: str, builtin: bool = False) -> Method:
    """The registry's Method of declaration `d` of the folder `folder` (`source`: its
    method.py, named in every error; a `builtin` method's source is None)."""

    def fail(message: str):
        raise MethodFolderError(f"blurlab: {source}: {message}")

    if not isinstance(d.name, str) or not NAME.fullmatch(d.name):
        fail(f"name {d.name!r} must be lower case letters, digits and _, starting with a letter")
    if d.kind not in KINDS:
        fail(f"kind {d.kind!r} is not one of {KINDS}")
    if d.run is None and d.kind not in CHAIN_KINDS:
        fail(f"a {d.kind} method needs a run of its own; a chain of passes is {CHAIN_KINDS}")
    if not isinstance(d.doc, str) or not d.doc.strip():
        fail("doc must say in a line what the method does")
    _check_params(d.params, fail, d.kind)
    if not callable(d.instant) and d.instant not in INSTANTS:
        fail(f"instant {d.instant!r} must be one of {INSTANTS} or a function of the parameters")
    backends = tuple(d.backends)
    if not backends or any(b not in BACKENDS for b in backends):
        fail(f"backends {d.backends!r} must be one or both of {BACKENDS}")
    if isinstance(d.order, bool) or not isinstance(d.order, (int, float)):
        fail(f"order {d.order!r} must be a number")
    passes = _resolved_passes(d, folder, backends, fail)
    _check_twin(d, fail)
    _check_grid(d, fail)
    by_name = {p.name: p for p in passes}
    if d.run is None:
        run = chain_run(passes, d.params, source)
    else:

        def run(ctx, frame, inputs, values, backend):
            return d.run(ctx, frame, inputs, values, backend, by_name)

    return Method(
        name=d.name,
        kind=d.kind,
        params=dict(d.params),
        run=run,
        instant=d.instant,
        backends=backends,
        doc=d.doc.strip(),
        default_grid=d.default_grid,
        twin=d.twin,
        twin_inputs=d.twin_inputs,
        order=d.order,
        passes=tuple(by_name),
        study_curves=tuple(d.study_curves),
        gallery=d.gallery,
        translucent_layer=d.translucent_layer,
        example=d.example,
        renders_for=d.renders_for,
        engine_peer=d.engine_peer,
        tile_lists=tuple(d.tile_lists),
        linked_params=_linked_params(d, fail),
        source=None if builtin else source,
    )


def _check_params(params, fail, kind: str) -> None:
    if not isinstance(params, dict):
        fail(f"params must be a dict of name: Param, not {type(params).__name__}")
    for key, p in params.items():
        if not isinstance(key, str) or not key.isidentifier():
            fail(f"parameter name {key!r} is not an identifier (it is the shader's uniform)")
        if not isinstance(p, Param):
            fail(f"parameter {key} must be a Param, not {type(p).__name__}")
        if p.kind is object and kind == "sequence" and p.default is None:
            continue  # what a sequence method is handed from the frame before: not swept
        if p.kind in (int, float) and (p.low is None or p.high is None):
            fail(f"parameter {key} has no range: declare Param(..., low=..., high=...)")
        if p.kind is object or not (p.kind in (int, float, bool) or isinstance(p.kind, tuple)):
            fail(f"parameter {key} must be an int, float, bool or a tuple of choices")
        if callable(p.default) or p.default is None:
            continue  # read from the frame, or optional: checked when a call resolves it
        try:
            typed("method folder", key, p.default, p)
        except (TypeError, ValueError) as error:
            fail(f"parameter {key}'s default is not allowed: {error}")


def _resolved_passes(d: Declaration, folder: Path, backends, fail) -> tuple[Pass, ...]:
    """The declared passes with each shader as a path blurlab compiles: the folder's GLSL file,
    or the GLSL translated from its HLSL one."""
    if d.run is not None and isinstance(d.passes, (tuple, list)) and not d.passes:
        return ()  # a run that renders or blends frames with blurlab's own passes
    if not isinstance(d.passes, (tuple, list)) or not d.passes:
        fail("passes must be a non-empty tuple of Pass(name, shader, params)")
    resolved = []
    seen = set()
    for step in d.passes:
        if not isinstance(step, Pass):
            fail(f"passes must hold Pass(...) declarations, not {type(step).__name__}")
        if step.name in seen:
            fail(f"two passes are named {step.name!r}; each names a timing")
        seen.add(step.name)
        unknown = [key for key in step.params if key not in d.params]
        if unknown:
            fail(f"pass {step.name} takes {unknown}, which are not declared in params")
        shader = (folder / step.shader).resolve()
        if not shader.is_relative_to(folder.resolve()):
            fail(f"pass {step.name}'s shader {step.shader} is outside the method's folder")
        if not shader.is_file():
            fail(f"pass {step.name}'s shader {step.shader} is not in {folder}")
        if shader.suffix in hlsl.SUFFIXES:
            if backends != ("compute",):
                fail(f"pass {step.name} is HLSL, a compute shader: backends must be ('compute',)")
            try:
                path = hlsl.translate(shader, choice_defines(d.params, step.params))
            except hlsl.HLSLError as error:
                fail(str(error))
        elif shader.suffix in GLSL_SUFFIXES:
            path = shader
        else:
            fail(f"pass {step.name}'s shader {step.shader} must end in .glsl, .comp or .hlsl")
        resolved.append(Pass(step.name, str(path), tuple(step.params)))
    return tuple(resolved)


def _linked_params(d: Declaration, fail) -> tuple[tuple[str, str], ...]:
    pairs = tuple(tuple(pair) for pair in d.linked_params)
    for pair in pairs:
        if len(pair) != 2 or not set(pair) <= set(d.params):
            fail(f"linked_params {pair!r} must be a pair of the method's parameters")
    return pairs


def _check_twin(d: Declaration, fail) -> None:
    if d.twin is None:
        return
    if not callable(d.twin):
        fail("twin must be a function of the frame's arrays and the parameters")
    inputs = d.twin_inputs if d.twin_inputs is not None else twin_positionals(d.twin)
    if not inputs or any(name not in FRAME_ARRAYS for name in inputs):
        fail(f"the twin takes the frame arrays {inputs}; they must be among {FRAME_ARRAYS}")
    taken = twin_keywords(d.twin)
    if taken is not None and not taken <= set(d.params):
        fail(f"the twin takes {sorted(taken - set(d.params))}, which are not parameters")


def _check_grid(d: Declaration, fail) -> None:
    for part in [d.default_grid] if isinstance(d.default_grid, dict) else d.default_grid:
        for key, values in part.items():
            if key not in d.params:
                fail(f"default_grid sweeps {key!r}, which is not a parameter")
            for value in values:
                try:
                    typed(d.name, key, value, d.params[key])
                except (TypeError, ValueError) as error:
                    fail(f"default_grid: {error}")


def load_entry_points() -> list[str]:
    """Loads the method folders that installed packages offer in the entry-point group
    blurlab.methods: each entry point names a module (its folder is loaded) or a path. One that
    fails to load is skipped with a warning naming it, so that one broken package does not stop
    blurlab."""
    names = []
    for entry in importlib.metadata.entry_points(group=ENTRY_POINT_GROUP):
        try:
            target = entry.load()
            if isinstance(target, types.ModuleType):
                target = Path(target.__file__).parent
            names += load_methods(target)
        except Exception as error:  # a plugin's failure of any kind is reported, not raised
            warnings.warn(
                f"blurlab: skipped the methods of entry point {entry.name} = {entry.value} "
                f"({ENTRY_POINT_GROUP}): {error}",
                stacklevel=2,
            )
    return names


add_discoverer(load_entry_points)
