"""The rules of the house, checked on the tree itself: a method lives in one place,
each parameter is declared once, no module reaches into a Context's private members, no import
cycles, no import upward between the package's layers, no module over 600 lines."""

from __future__ import annotations

import ast
import functools
import inspect
import re
from pathlib import Path

import pytest

import blurlab as bl
from blurlab.cli_methods import method_table
from blurlab.methods.core import KINDS, check_param, twin_keywords
from blurlab.methods.params import Param

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "python" / "blurlab"


def python_files(*folders: Path) -> list[Path]:
    return sorted(p for folder in folders for p in folder.rglob("*.py"))


BUILTIN = [name for name in bl.methods() if bl.method(name).source is None]
# What may name a method outside its folder: prose (the docs, the notebooks, comments and
# docstrings), the benchmarks' records and the golden hashes, which are keyed by method.
ASIDE = ("docs/", "notebooks/", "tests/golden/", "benchmarks/records.jsonl")
CODE_SUFFIXES = {".py", ".glsl", ".comp", ".vert", ".frag", ".hlsl", ".toml", ".sh", ".txt"}


def code_files() -> list[Path]:
    """The repository's files of code and configuration, outside the prose set aside."""
    roots = ["python", "tests", "benchmarks", "tools", "shaders", "src", "packaging", ".ci"]
    top = ("conftest.py", "Makefile", "pyproject.toml", "CMakeLists.txt")
    files = [ROOT / name for name in top]
    for root in roots:
        files += [p for p in (ROOT / root).rglob("*") if p.is_file()]
    return sorted(
        p
        for p in files
        if (p.suffix in CODE_SUFFIXES or p.parent.name == ".ci" or p.name == "Makefile")
        and "__pycache__" not in p.parts
        and not str(p.relative_to(ROOT)).startswith(ASIDE)
    )


def docstrings(tree: ast.AST) -> set[int]:
    kinds = (ast.Module, ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)
    return {
        id(node.body[0].value)
        for node in ast.walk(tree)
        if isinstance(node, kinds)
        and node.body
        and isinstance(node.body[0], ast.Expr)
        and isinstance(node.body[0].value, ast.Constant)
    }


def python_names(path: Path) -> set[str]:
    """What a module's code says: its strings (not its docstrings), its identifiers and the
    modules it imports; its comments and docstrings are prose."""
    tree = ast.parse(path.read_text())
    prose = docstrings(tree)
    said = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Constant) and isinstance(node.value, str) and id(node) not in prose:
            said.add(node.value)
        elif isinstance(node, ast.Name):
            said.add(node.id)
        elif isinstance(node, ast.Attribute):
            said.add(node.attr)
        elif isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            said.add(node.name)
        elif isinstance(node, ast.ImportFrom):
            said.update((node.module or "").split("."))
            said.update(a.name for a in node.names)
        elif isinstance(node, ast.Import):
            said.update(part for a in node.names for part in a.name.split("."))
    return said


def other_code(path: Path) -> set[str]:
    """A shader's or a script's lines less its comments."""
    comment = re.compile(r"(//|#(?!include|define|version|if|else|endif|line|pragma)).*$")
    return {comment.sub("", line) for line in path.read_text(errors="replace").splitlines()}


@functools.lru_cache(maxsize=1)
def said_by_file() -> dict[Path, set[str]]:
    return {p: python_names(p) if p.suffix == ".py" else other_code(p) for p in code_files()}


@pytest.mark.parametrize("name", BUILTIN)
def test_a_method_is_named_only_in_its_folder(name):
    """A built-in method is its folder (docs/spec.md §25.2): no code or test elsewhere names it,
    so that a method is added, changed or removed in one place. Code that needs a method picks
    it by what its declaration says (its kind, its parameters, its roles)."""
    folder = PACKAGE / "methods" / name
    assert (folder / "method.py").is_file(), f"{name} has no folder of its own"
    word = re.compile(rf"(?<![A-Za-z0-9_]){name}(?![A-Za-z0-9_])")
    elsewhere = sorted(
        str(path.relative_to(ROOT))
        for path, said in said_by_file().items()
        if not path.is_relative_to(folder) and any(word.search(text) for text in said)
    )
    assert not elsewhere, f"{name} is named outside {folder.relative_to(ROOT)}: {elsewhere}"


def test_every_method_says_what_it_is():
    for name in bl.methods():
        m = bl.method(name)
        assert m.kind in KINDS and m.doc, name
        for part in [m.default_grid] if isinstance(m.default_grid, dict) else m.default_grid:
            for key, values in part.items():
                for value in values:
                    if key != "steps":
                        check_param(name, key, value)  # raises for an unknown or bad value


def test_a_shared_parameter_is_one_declaration():
    """Two methods whose parameter of one name has the same default and range share the one
    declaration object; a second declaration of the same parameter would be a copy."""
    seen: dict[tuple, object] = {}
    for name in bl.methods():
        for key, param in bl.method(name).params.items():
            signature = (key, repr(param.default), repr(param.kind), param.low, param.high)
            first = seen.setdefault(signature, param)
            assert first is param, f"{name}.{key} is declared again with the same default/range"


def test_a_params_flags_are_keyword_only():
    """`Param(1.5, float, "...", 0, 100, True)` would not say what True is."""
    with pytest.raises(TypeError):
        Param(1.5, float, "tile side", 0, 100, True)
    assert (
        Param(1.5, float, "tile side", 0, 100, low_open=True).allowed()
        == "finite and > 0 and <= 100"
    )


def test_no_param_declaration_states_its_range_in_its_doc():
    """Ranges are derived from low/high (Param.allowed); a range in the doc line would be a
    second declaration that can drift."""
    for name in bl.methods():
        for key, param in bl.method(name).params.items():
            assert not re.search(r"\(\s*[<>]?=?\s*-?\d[\d.^]*\s*(\.\.|,)", param.doc), (
                f"{name}.{key}: {param.doc!r} states a range"
            )


@pytest.mark.parametrize("name", [n for n in bl.methods() if bl.method(n).twin is not None])
def test_twins_take_the_method_parameters_by_name_without_defaults(name):
    m = bl.method(name)
    taken = twin_keywords(m.twin)
    if taken is not None:
        assert taken <= set(m.params), f"{name}'s twin takes {taken - set(m.params)}"
    for p in inspect.signature(m.twin).parameters.values():
        if p.name in m.params:
            assert p.kind is inspect.Parameter.KEYWORD_ONLY, f"{name} twin: {p.name} positional"
            assert p.default is inspect.Parameter.empty, f"{name} twin: {p.name} has a default"


def test_shaders_declare_no_parameter_defaults():
    """A uniform with an initializer would be a second default beside the Python declaration."""
    pattern = re.compile(r"^\s*uniform\s+\w+\s+\w+\s*=", re.M)
    offenders = [
        str(p.relative_to(ROOT))
        for p in sorted([*(ROOT / "shaders").rglob("*"), *(PACKAGE / "methods").rglob("*.glsl")])
        if p.is_file() and pattern.search(p.read_text())
    ]
    assert not offenders


CONTEXT_MODULES = (PACKAGE / "core" / "gl.py", PACKAGE / "core" / "context.py")


def context_private_members() -> set[str]:
    """Names of the context's and Texture's private attributes and methods."""
    names = set()
    for node in (n for path in CONTEXT_MODULES for n in ast.walk(ast.parse(path.read_text()))):
        if isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name):
            if node.value.id == "self" and node.attr.startswith("_"):
                names.add(node.attr)
        if isinstance(node, ast.FunctionDef) and node.name.startswith("_"):
            if not node.name.startswith("__"):
                names.add(node.name)
    return names


def test_no_module_uses_a_context_private_member():
    private = context_private_members()
    assert "_core" in private and "_pool" in private  # the scan sees them
    offenders = []
    for path in python_files(PACKAGE, ROOT / "tests", ROOT / "benchmarks"):
        if path in CONTEXT_MODULES:
            continue
        tree = ast.parse(path.read_text())
        for node in ast.walk(tree):
            if (
                isinstance(node, ast.Attribute)
                and node.attr in private
                and not (isinstance(node.value, ast.Name) and node.value.id in ("self", "cls"))
            ):
                offenders.append(f"{path.relative_to(ROOT)}:{node.lineno} .{node.attr}")
    assert not offenders, offenders[:10]


def imports_of(path: Path) -> set[str]:
    """The blurlab modules a module imports at its top level or anywhere inside it."""
    module = ".".join(path.relative_to(PACKAGE.parent).with_suffix("").parts)
    package = module if path.name == "__init__.py" else module.rsplit(".", 1)[0]
    found = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[: len(base) - node.level + 1]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            if target.startswith("blurlab"):
                found.add(target)
                found.update(f"{target}.{a.name}" for a in node.names)
        elif isinstance(node, ast.Import):
            found.update(a.name for a in node.names if a.name.startswith("blurlab"))
    return found


def module_graph() -> dict[str, set[str]]:
    modules = {}
    for path in python_files(PACKAGE):
        name = ".".join(path.relative_to(PACKAGE.parent).with_suffix("").parts)
        modules[name.removesuffix(".__init__")] = path
    graph = {}
    for name, path in modules.items():
        graph[name] = {m for m in imports_of(path) if m in modules and m != name}
    return graph


def test_no_import_cycles_between_blurlab_modules():
    """Package __init__ files only gather their children, so edges into a package's own
    __init__ from its children are left out."""
    graph = module_graph()
    for name in graph:
        graph[name] = {m for m in graph[name] if not name.startswith(m + ".")}
    cycles = []
    state: dict[str, int] = {}

    def visit(node, stack):
        state[node] = 1
        stack.append(node)
        for nxt in sorted(graph[node]):
            if state.get(nxt) == 1:
                cycles.append(stack[stack.index(nxt) :] + [nxt])
            elif nxt not in state:
                visit(nxt, stack)
        stack.pop()
        state[node] = 2

    for node in sorted(graph):
        if node not in state:
            visit(node, [])
    assert not cycles, cycles[:3]


# The package's layers, lowest first: a module or package by its dotted name under blurlab (the
# longest listed prefix wins). A module imports its own layer and those below it, never one above.
LAYERS = {
    "base": {"version", "_paths", "sizes", "errors", "docs_link"},
    "twins": {"twins"},  # the spec in NumPy: depends on nothing of blurlab
    "io": {"io"},
    "gl": {"core.gl", "core.timers", "core.graph"},  # knows nothing of scenes or rendering
    "hatching": {"hatching"},  # tonal art maps, which a scene's materials carry
    "scene": {"scene"},
    "gpu core": {"core.frame", "core.render", "core.references", "core.context", "core"},
    "passes": {"methods", "metrics"},
    "temporal": {"temporal"},
    "lab": {"studies", "blender", "suite"},
    # "": the package's own __init__
    "front": {
        "cli",
        "cli_args",
        "cli_methods",
        "cli_recommend",
        "cli_reference",
        "cli_suite",
        "__main__",
        "",
    },
}


def layer_of(module: str) -> int:
    name = module.removeprefix("blurlab").removeprefix(".")
    listed = {member: rank for rank, members in enumerate(LAYERS.values()) for member in members}
    for prefix in sorted(listed, key=len, reverse=True):
        if name == prefix or name.startswith(prefix + ".") or (prefix == "" and name == ""):
            return listed[prefix]
    raise AssertionError(f"{module} is in no layer of tests/test_house.py LAYERS: give it one")


def upward_imports() -> set[tuple[str, str]]:
    graph = module_graph()
    return {
        (module, target)
        for module, targets in graph.items()
        for target in targets
        if not module.startswith(target + ".") and layer_of(target) > layer_of(module)
    }


def test_no_module_imports_a_layer_above_its_own():
    names = list(LAYERS)
    upward = sorted(
        f"{a} ({names[layer_of(a)]}) imports {b} ({names[layer_of(b)]})"
        for a, b in upward_imports()
    )
    assert not upward, upward


def test_no_function_local_import_of_a_blurlab_module():
    """Local imports hid cycles; optional third-party imports (moderngl, Dask, tqdm, ...) may
    stay local."""
    offenders = []
    for path in python_files(PACKAGE):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                for inner in ast.walk(node):
                    if isinstance(inner, ast.ImportFrom) and (
                        inner.level or (inner.module or "").startswith("blurlab")
                    ):
                        offenders.append(f"{path.relative_to(ROOT)}:{inner.lineno}")
    assert not offenders, offenders


def test_cpp_layers_have_no_include_cycle():
    """Headers include no cycle, and no X.cpp includes a header that itself (through headers)
    includes X.h: X's implementation would depend on something built on X."""
    include = re.compile(r'#include "([^"]+)"')
    src = ROOT / "src"
    includes = {
        str(p.relative_to(src)): set(include.findall(p.read_text()))
        for p in src.rglob("*")
        if p.suffix in (".h", ".cpp")
    }

    def reached(header: str) -> set[str]:
        seen, todo = set(), [header]
        while todo:
            for nxt in includes.get(todo.pop(), ()):
                if nxt not in seen:
                    seen.add(nxt)
                    todo.append(nxt)
        return seen

    offenders = [h for h in includes if h.endswith(".h") and h in reached(h)]
    for source, deps in includes.items():
        if source.endswith(".cpp"):
            own = source[:-4] + ".h"
            offenders += [f"{source} -> {d}" for d in deps if d != own and own in reached(d)]
    assert not offenders, offenders


def test_the_parameter_docs_are_generated_from_the_declarations():
    """docs/parameters.md below its header is `blurlab methods`' output: the docs restate no
    default or range by hand."""
    text = (ROOT / "docs" / "parameters.md").read_text()
    generated = "".join(method_table(bl.method(name)) + "\n" for name in bl.methods())
    assert text[text.index("## ") :] == generated, (
        "docs/parameters.md is out of date: regenerate it with `blurlab methods` (see its header)"
    )


def test_no_cpp_parameter_struct_restates_defaults():
    """Parameters reach C++ as plain values (uniforms by name); a *Params struct with member
    defaults would be a second declaration."""
    offenders = [
        str(p.relative_to(ROOT))
        for p in sorted((ROOT / "src").rglob("*.h"))
        if re.search(r"struct \w*Params\b", p.read_text())
    ]
    assert not offenders


MAX_MODULE_LINES = 600


def test_no_module_is_over_600_lines():
    """A module that outgrows this is split by concern (as gltf/, metrics/ and scenes/ were):
    the package's and the benchmarks'."""
    long = {
        str(path.relative_to(ROOT)): n
        for path in python_files(PACKAGE, ROOT / "benchmarks")
        if (n := len(path.read_text().splitlines())) > MAX_MODULE_LINES
    }
    assert not long, f"modules over {MAX_MODULE_LINES} lines: {long}"


def test_the_default_size_is_declared_once():
    """Every default size reads blurlab.DEFAULT_SIZE; its numbers appear only where it is set."""
    written = [
        str(path.relative_to(ROOT))
        for path in python_files(PACKAGE)
        if re.search(r"640, ?360|640x360", path.read_text())
    ]
    assert written == ["python/blurlab/sizes.py"], written


def test_the_files_the_spec_and_code_name_exist():
    """A path in the spec, the architecture page, the README, a method's spec.md or a comment
    of the package or its shaders names a file that is there: moving a file moves its
    mentions."""
    path = re.compile(
        r"(?<![\w/])((?:shaders/(?:passes|common|util)|tests|python/blurlab|benchmarks/blurlab_bench)"
        r"/[\w/.-]+\.(?:glsl|comp|py|md))"
    )
    twin = re.compile(r"\bblurlab\.twins\.([a-z_0-9]+)\b")
    texts = [ROOT / "README.md", ROOT / "docs" / "spec.md", ROOT / "docs" / "architecture.md"]
    texts += [p for p in sorted(PACKAGE.rglob("*")) if p.suffix in {".py", ".md", ".glsl", ".comp"}]
    texts += [p for p in sorted((ROOT / "shaders").rglob("*")) if p.is_file()]
    missing = []
    for text_file in texts:
        if "__pycache__" in text_file.parts:
            continue
        text = text_file.read_text()
        missing += [
            f"{text_file.relative_to(ROOT)}: {m}"
            for m in path.findall(text)
            if not (ROOT / m).exists()
        ]
        missing += [
            f"{text_file.relative_to(ROOT)}: blurlab.twins.{m}"
            for m in twin.findall(text)
            if not (PACKAGE / "twins" / f"{m}.py").exists()
        ]
    assert not missing, missing
