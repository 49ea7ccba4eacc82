"""The suite's identity (docs/spec.md §24.2): its version, and one hash over everything that
defines it at a preset: the definition (categories, scenes, sizes, shutters, references,
metrics, statistic), every scene's digest (blurlab.studies.identity.scene_digest, as sweeps
key their rows), and the code of the references and the metrics: their Python modules and
the shader files those modules name, with the files those include.

The compiled core is left out on purpose: a wheel and a source build of the same code are
other bytes, and cards from both must compare. Each method's own code is named on the card
beside it (method_digest), not in the suite's hash: a new method, or a change to one, is a
new entry of the same suite.
"""

from __future__ import annotations

import functools
import hashlib
import json
import re
from pathlib import Path

from .._paths import shader_dir
from ..methods import method
from ..scene import scenes
from ..studies import identity
from . import definition as d

PACKAGE = Path(__file__).resolve().parents[1]
# The modules that compute the references (docs/spec.md §11, §21.1), the G-buffer and TAA the
# sequences run under, and the metrics (§6), relative to the package.
REFERENCE_CODE = (
    "core/references.py",
    "core/render.py",
    "temporal/sequences.py",
    "temporal/taa.py",
    "scene/shutters.py",
)
METRIC_CODE = ("metrics",)
SHADER_NAME = re.compile(r"[\"']((?:passes|common|util)/[\w/]+\.(?:comp|glsl|vert|frag))[\"']")
INCLUDE = re.compile(r"#include\s+\"([\w/]+\.glsl)\"")


def code_files(package: Path = PACKAGE, shaders: Path | None = None) -> list[tuple[str, Path]]:
    """(name, path) of every file the references and metrics run: their modules, and the
    shaders they name with every file those include, sorted by name."""
    shaders = shaders or shader_dir()
    modules: list[Path] = []
    for entry in REFERENCE_CODE + METRIC_CODE:
        path = package / entry
        modules += sorted(path.rglob("*.py")) if path.is_dir() else [path]
    files = {f"blurlab/{p.relative_to(package).as_posix()}": p for p in modules}
    pending = [n for p in modules for n in SHADER_NAME.findall(p.read_text())]
    while pending:
        name = pending.pop()
        key = f"shaders/{name}"
        path = shaders / name
        if key in files or not path.is_file():
            continue
        files[key] = path
        pending += INCLUDE.findall(path.read_text())
    return sorted(files.items())


def code_digest(package: Path = PACKAGE, shaders: Path | None = None) -> str:
    h = hashlib.sha256()
    for name, path in code_files(package, shaders):
        h.update(name.encode() + b"\0" + path.read_bytes() + b"\0")
    return h.hexdigest()[: identity.HASH_CHARS]


@functools.lru_cache(maxsize=4096)
def _builtin_scene_digest(name: str) -> str:
    return identity.scene_digest(scenes.get(name))


def scene_digests(preset: str) -> dict[str, dict[str, str]]:
    """{category: {scene: digest}}: built-in and random scenes by their content; the authored
    files by the digest the definition pins (the same on every machine, with or without them)."""
    out = {}
    for category in d.categories():
        names = category.at(preset).scenes
        if category.needs_assets:
            out[category.name] = {n: d.AUTHORED_FILES[n] for n in names}
        else:
            out[category.name] = {n: _builtin_scene_digest(n) for n in names}
    return out


def suite_identity(preset: str, captured: dict | None = None) -> dict:
    """{"version", "preset", "hash", "parts"}: the suite's hash at `preset` and the digest of
    each part it covers (the definition, the scenes, the code, and the captured frames where
    `captured` gives their digests: blurlab.suite.captured), so that two cards that differ
    say where."""
    definition = d.definition(preset)
    parts = {
        "definition": _json_digest(definition),
        "scenes": _json_digest(scene_digests(preset)),
        "code": code_digest(),
    }
    if captured:
        parts["captured"] = _json_digest(captured)
    return {
        "version": d.VERSION,
        "preset": preset,
        "hash": _json_digest(parts),
        "parts": parts,
    }


def method_digest(name: str) -> str:
    """The code a method runs: a method folder's files (its declaration, shaders and twin);
    for a built-in method, blurlab's own code (identity.code_digest: modules and shaders)."""
    source = method(name).source
    if source is None:
        return identity.code_digest(shader_dir())
    folder = Path(source)
    folder = folder if folder.is_dir() else folder.parent
    h = hashlib.sha256()
    for path in sorted(p for p in folder.rglob("*") if p.is_file()):
        if "__pycache__" not in path.parts:
            h.update(path.relative_to(folder).as_posix().encode() + b"\0" + path.read_bytes())
    return h.hexdigest()[: identity.HASH_CHARS]


def _json_digest(value) -> str:
    text = json.dumps(value, sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(text.encode()).hexdigest()[: identity.HASH_CHARS]
