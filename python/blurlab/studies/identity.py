"""A sweep row's identity: everything that determines the numbers in it (docs/reliability.md,
"Resuming a sweep").

A row is named by a hash of its scene's name and content, its method, backend, parameters,
size and shutter, its reference's definition (N, antialias, seed, guard), the device and
renderer, the metric set, blurlab's version and a digest of the code that ran (its Python
modules, compiled core and shaders). A sweep skips a row of its out-file only where
the identity is the same; `bl.recommend` caches by the same components.
"""

from __future__ import annotations

import dataclasses
import functools
import hashlib
import json
import types
from pathlib import Path

import numpy as np

from ..scene.model import Material, Scene
from ..version import __version__

# The row columns that spell the identity out, beside the hash in IDENTITY.
IDENTITY = "identity"
SCENE_DIGEST = "scene_digest"
REFERENCE = "reference"
METRIC_SET = "metric_set"
VERSION = "blurlab_version"
CODE = "code_digest"
HASH_CHARS = 16  # 64 bits of SHA-256: a collision among a file's rows is not a practical risk


def scene_digest(scene: Scene) -> str:
    """A hash of what `scene` draws: its camera, light, background, shutter, every object's
    mesh, material (texture bytes included) and motion, and, for a scene loaded from a file,
    that file's bytes and the bytes of every file beside it that it refers to (buffers,
    images). Two scenes with the same name but other content have other digests."""
    h = hashlib.sha256()
    _feed(h, scene, set())
    if scene.source is not None:
        for path in scene_files(Path(scene.source)):
            h.update(path.name.encode() + b"\0" + path.read_bytes())
    return h.hexdigest()[:HASH_CHARS]


def scene_files(path: Path) -> list[Path]:
    """A glTF file and the external files its buffers and images name (data: URIs are inside
    it already); for a .glb, the file alone unless its JSON chunk names external files."""
    files = [path]
    try:
        document = _gltf_json(path)
    except (OSError, ValueError):
        return files  # the loader has already said what is wrong with it
    for entry in document.get("buffers", []) + document.get("images", []):
        uri = entry.get("uri") if isinstance(entry, dict) else None
        if isinstance(uri, str) and not uri.startswith("data:"):
            from urllib.parse import unquote

            candidate = path.parent / unquote(uri)
            if candidate.is_file():
                files.append(candidate)
    return files


def _gltf_json(path: Path) -> dict:
    data = path.read_bytes()
    if data[:4] == b"glTF":  # GLB: 12-byte header, then the JSON chunk (length, type, bytes)
        length = int.from_bytes(data[12:16], "little")
        data = data[20 : 20 + length]
    document = json.loads(data.decode("utf-8"))
    return document if isinstance(document, dict) else {}


def _feed(h, value, seen: set) -> None:
    """Feeds `value` to the hash in a canonical form: its type, then its content."""
    if value is None or isinstance(value, (bool, int, float, str, complex)):
        h.update(f"{type(value).__name__}:{value!r};".encode())
    elif isinstance(value, bytes):
        h.update(b"bytes:%d:" % len(value) + value)
    elif isinstance(value, np.ndarray):
        array = np.ascontiguousarray(value)
        h.update(f"ndarray:{array.dtype.str}:{array.shape};".encode())
        h.update(array.tobytes() if array.dtype != object else repr(array.tolist()).encode())
    elif isinstance(value, np.generic):
        _feed(h, value.item(), seen)
    elif isinstance(value, Path):  # a texture file: its bytes
        h.update(b"file:" + (value.read_bytes() if value.is_file() else str(value).encode()))
    elif isinstance(value, (list, tuple)):
        h.update(f"{type(value).__name__}:{len(value)}[".encode())
        for item in value:
            _feed(h, item, seen)
        h.update(b"]")
    elif isinstance(value, dict):
        h.update(f"dict:{len(value)}{{".encode())
        for key in sorted(value, key=repr):
            _feed(h, key, seen)
            _feed(h, value[key], seen)
        h.update(b"}")
    elif isinstance(value, (types.FunctionType, types.MethodType)):
        _feed_function(h, value, seen)
    else:
        if id(value) in seen:  # a shared or cyclic object, fed once
            h.update(b"seen;")
            return
        seen.add(id(value))
        kind = type(value)
        h.update(f"{kind.__module__}.{kind.__qualname__}(".encode())
        if dataclasses.is_dataclass(value):
            fields = {f.name: getattr(value, f.name) for f in dataclasses.fields(value)}
        else:
            fields = dict(getattr(value, "__dict__", {}))
        if isinstance(value, Scene):
            fields.pop("source", None)  # where it was loaded from is not what it draws
        if isinstance(value, Material) and isinstance(fields.get("texture"), str):
            fields["texture"] = Path(fields["texture"])  # a texture named by path: its bytes
        _feed(h, fields, seen)
        h.update(b")")


def _feed_function(h, fn, seen: set) -> None:
    """A function by its code and the values it closes over (a motion given as a lambda)."""
    if isinstance(fn, types.MethodType):
        _feed(h, fn.__self__, seen)
        fn = fn.__func__
    code = fn.__code__
    h.update(f"function:{fn.__module__}.{fn.__qualname__}:".encode() + code.co_code)
    _feed(h, [c for c in code.co_consts if not isinstance(c, types.CodeType)], seen)
    _feed(h, [cell.cell_contents for cell in fn.__closure__ or ()], seen)


def row_identity(components: dict) -> str:
    """The hash of a row's identity components (a JSON-able dict)."""
    text = json.dumps(components, sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(text.encode()).hexdigest()[:HASH_CHARS]


def device_identity(ctx) -> dict:
    """The device part of a row's identity: the context's kind and renderer, and the digest of
    the code it runs (code_digest: blurlab's modules, core and the context's shaders)."""
    info = ctx.info()
    return {
        "device": info["device"],
        "renderer": info["renderer"],
        CODE: code_digest(ctx.shader_dir),
    }


def code_digest(shader_dir) -> str:
    """A hash of the code that computes a row: blurlab's Python modules, its compiled core and
    the shaders of `shader_dir` (the folder a context reads them from), each by its path inside
    the package or folder and its bytes. An edit, a rebuild or another shader folder gives
    another digest, so that a resumed sweep never returns a row that other code computed; the
    version alone stays the same between releases."""
    return _code_digest(str(Path(shader_dir).resolve()))


@functools.lru_cache(maxsize=8)
def _code_digest(shader_dir: str) -> str:
    h = hashlib.sha256(_package_digest().encode())
    _feed_files(h, Path(shader_dir), "*")
    return h.hexdigest()[:HASH_CHARS]


@functools.lru_cache(maxsize=1)
def _package_digest() -> str:
    """blurlab's modules and core, hashed once a process: the code it imported."""
    h = hashlib.sha256()
    package = Path(__file__).resolve().parents[1]
    _feed_files(h, package, "*.py")
    for suffix in ("glsl", "comp", "hlsl"):  # the method folders' shaders
        _feed_files(h, package, f"*.{suffix}")
    _feed_files(h, package, "_core*")
    return h.hexdigest()


def _feed_files(h, root: Path, pattern: str) -> None:
    for path in sorted(p for p in root.rglob(pattern) if p.is_file()):
        if "__pycache__" not in path.parts:
            h.update(path.relative_to(root).as_posix().encode() + b"\0" + path.read_bytes())


def version() -> str:
    """blurlab's version, part of every identity: a release may change what a method returns."""
    return __version__
