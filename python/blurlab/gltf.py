"""glTF 2.0 files as blurlab scenes (docs/spec.md §15).

The file is parsed by pygltflib; everything it describes is then checked here before use,
because a file from outside is untrusted: indices and ranges are bounded, buffers come only
from the file itself, a data: URI or a file inside the file's own folder, and nothing is
downloaded. Scene time is the animation's time in seconds; the motion of every node is its
animation sampled at t, so any shutter, instant or reference works on it unchanged.
"""

from __future__ import annotations

import base64
import binascii
import io as bytes_io
import json
import math
import warnings
from dataclasses import dataclass
from pathlib import Path
from urllib.parse import unquote, urlsplit

import numpy as np

from .mesh import Mesh
from .motion import Motion, compose, slerp
from .scene import MAX_EMISSION_STRENGTH, Camera, Material, Scene

MAX_FILE_BYTES = 256 << 20  # a .gltf, .glb or external buffer larger than this is refused
MAX_JSON_VALUES = 100_000  # pygltflib builds an object per JSON value: this bounds its time
MAX_ACCESSOR_VALUES = 1 << 25  # numbers in one accessor (256 MiB as float64)
MAX_IMAGE_PIXELS = 1 << 26  # 8192 x 8192: larger base colour textures are refused
MAX_VERTICES = 1 << 24  # per primitive, after any de-indexing
MAX_NODES = 1 << 16
DEFAULT_SHUTTER_S = 1.0 / 60.0

_COMPONENTS = {  # componentType: (dtype, the divisor of a normalized value)
    5120: (np.int8, 127.0),
    5121: (np.uint8, 255.0),
    5122: (np.int16, 32767.0),
    5123: (np.uint16, 65535.0),
    5125: (np.uint32, None),
    5126: (np.float32, None),
}
_WIDTHS = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT2": 4, "MAT3": 9, "MAT4": 16}
_TRIANGLES, _STRIP, _FAN = 4, 5, 6
_MODES = {0: "POINTS", 1: "LINES", 2: "LINE_LOOP", 3: "LINE_STRIP"}
_TRS_PATHS = ("translation", "rotation", "scale")


class GltfError(ValueError):
    """A glTF file blurlab cannot use: the message names the file and what is wrong."""


def load(
    path,
    animation: int | None = 0,
    camera: int | Camera | None = None,
    size_hint=None,
    shutter=None,
) -> Scene:
    """A `bl.Scene` from a .gltf or .glb file (docs/spec.md §15).

    ``animation``: index of the animation that moves the scene, or None for the rest pose.
    ``camera``: None (the file's first camera, or one framing the scene's bounds when the file
    has none), the index of one of the file's cameras, or a `bl.Camera`.
    ``size_hint``: (W, H) the scene will mostly be rendered at; the framing camera fits the
    bounds into that aspect ratio. ``shutter``: (t0, t1) in animation seconds; by default
    1/60 s opening where the animation moves fastest (docs/spec.md §15).
    """
    path = Path(path)
    try:
        return _Loader(path).scene(animation, camera, size_hint, shutter)
    except GltfError:
        raise
    except (ValueError, TypeError, KeyError, IndexError, AttributeError, OverflowError) as error:
        # What slipped past the checks below still names the file and never escapes as a crash.
        raise GltfError(f"blurlab.gltf: {path.name}: malformed file ({error})") from None


@dataclass
class JointSkin:
    """A glTF skin: the skinning matrix of joint j at t is global_j(t) · inverseBind_j, applied
    to the mesh's bind-pose vertices (the skinned mesh node's own transform is ignored, as the
    glTF spec says)."""

    nodes: object  # _Nodes
    joints: list[int]
    inverse_bind: np.ndarray  # (J, 4, 4)

    @property
    def bones(self) -> list[int]:
        return self.joints

    def matrices(self, t: float) -> np.ndarray:
        globals_ = self.nodes.world(t)
        return np.stack(
            [globals_[j] @ m for j, m in zip(self.joints, self.inverse_bind, strict=True)]
        )


class NodeMotion(Motion):
    """The world transform of one node of the file's hierarchy, animated."""

    def __init__(self, nodes, index: int):
        self.nodes, self.index = nodes, index

    def transform(self, t: float) -> np.ndarray:
        return self.nodes.world(t)[self.index]


class CameraNodeMotion(NodeMotion):
    """A camera node's world transform with its scale removed (a camera has none)."""

    def transform(self, t: float) -> np.ndarray:
        m = super().transform(t).copy()
        m[:3, :3] /= np.linalg.norm(m[:3, :3], axis=0)
        return m


# --- Animation sampling -----------------------------------------------------------------------


@dataclass
class _Channel:
    path: str  # translation, rotation or scale
    times: np.ndarray  # (K,) increasing
    values: np.ndarray  # (K, n) or (K, 3, n) for CUBICSPLINE: in-tangent, value, out-tangent
    interpolation: str

    def sample(self, t: float) -> np.ndarray:
        times, values = self.times, self.values
        cubic = self.interpolation == "CUBICSPLINE"
        key = (lambda i: values[i, 1]) if cubic else (lambda i: values[i])
        if t <= times[0] or len(times) == 1:
            return self._unit(key(0))
        if t >= times[-1]:
            return self._unit(key(len(times) - 1))
        i = int(np.searchsorted(times, t, side="right")) - 1
        span = times[i + 1] - times[i]
        s = (t - times[i]) / span
        if self.interpolation == "STEP":
            return self._unit(values[i])
        if cubic:  # Hermite spline with tangents scaled by the key interval (glTF Appendix C)
            s2, s3 = s * s, s * s * s
            p0, m0 = values[i, 1], values[i, 2] * span
            p1, m1 = values[i + 1, 1], values[i + 1, 0] * span
            v = (
                (2 * s3 - 3 * s2 + 1) * p0
                + (s3 - 2 * s2 + s) * m0
                + (-2 * s3 + 3 * s2) * p1
                + (s3 - s2) * m1
            )
            return self._unit(v)
        if self.path == "rotation":
            return slerp(values[i], values[i + 1], s)  # slerp is blind to component order
        return (1 - s) * values[i] + s * values[i + 1]

    def _unit(self, v: np.ndarray) -> np.ndarray:
        if self.path != "rotation":
            return v
        norm = np.linalg.norm(v)
        return v / norm if norm > 0 else np.array([0.0, 0.0, 0.0, 1.0])


class _Nodes:
    """The node hierarchy: rest TRS or matrix per node, the animation's channels, and world
    matrices at any time (cached for the last few times asked, since every object of a scene
    asks for the same t)."""

    def __init__(self, rest: list, parents: list[int], order: list[int], channels: dict):
        self.rest, self.parents, self.order, self.channels = rest, parents, order, channels
        self._cache: dict[float, list[np.ndarray]] = {}

    def world(self, t: float) -> list[np.ndarray]:
        t = float(t)
        if t not in self._cache:
            if len(self._cache) > 16:
                self._cache.clear()
            out: list[np.ndarray] = [np.eye(4)] * len(self.rest)
            for i in self.order:
                local = self.local(i, t)
                p = self.parents[i]
                out[i] = local if p < 0 else out[p] @ local
            self._cache[t] = out
        return self._cache[t]

    def local(self, i: int, t: float) -> np.ndarray:
        rest = self.rest[i]
        if isinstance(rest, np.ndarray):  # a matrix node: the spec lets no channel target it
            return rest
        trs = dict(rest)
        for channel in self.channels.get(i, ()):
            trs[channel.path] = channel.sample(t)
        x, y, z, w = trs["rotation"]  # glTF stores (x, y, z, w); blurlab's are (w, x, y, z)
        return compose(trs["translation"], (w, x, y, z), trs["scale"])


# --- The loader -------------------------------------------------------------------------------


class _Loader:
    def __init__(self, path: Path):
        self.path = path
        self.folder = path.resolve().parent
        self.ignored: set[str] = set()
        self.doc, self.glb_blob = self._document()
        self._buffers: dict[int, bytes] = {}

    def fail(self, what: str):
        raise GltfError(f"blurlab.gltf: {self.path.name}: {what}")

    # The container and its buffers.

    def _document(self):
        import pygltflib

        if not self.path.is_file():
            raise FileNotFoundError(f"blurlab.gltf: no such file: {self.path}")
        size = self.path.stat().st_size
        if size > MAX_FILE_BYTES:
            self.fail(f"{size} bytes is more than the {MAX_FILE_BYTES} allowed")
        data = self.path.read_bytes()
        blob = None
        if data[:4] == b"glTF":
            self._check_json(self._check_glb(data))
            try:
                doc = pygltflib.GLTF2.load_from_bytes(data)
            except Exception as error:  # pygltflib reports a bad container in many ways
                self.fail(f"not a valid GLB container ({type(error).__name__}: {error})")
            if doc is None:
                self.fail("the GLB has no JSON chunk")
            blob = doc.binary_blob()
        else:
            try:
                text = data.decode("utf-8")
                self._check_json(text)
                doc = pygltflib.GLTF2.gltf_from_json(text)
            except (UnicodeDecodeError, ValueError) as error:
                self.fail(f"not a glTF JSON document or GLB ({error})")
            except Exception as error:
                self.fail(f"its JSON is not a glTF document ({type(error).__name__}: {error})")
        version = str(getattr(doc.asset, "version", "") or "")
        if not version.startswith("2."):
            self.fail(f"asset.version is {version!r}; only glTF 2.x is read")
        required = set(doc.extensionsRequired or [])
        if required:
            self.fail(f"it requires extensions blurlab does not implement: {sorted(required)}")
        return doc, blob

    def _check_glb(self, data: bytes) -> str:
        """The GLB header and chunk table, checked before pygltflib reads it; the JSON text."""
        if len(data) < 20:
            self.fail(f"a GLB needs at least 20 bytes, this one has {len(data)} (truncated?)")
        version, length = np.frombuffer(data[4:12], "<u4")
        if version != 2:
            self.fail(f"GLB container version {version}; only 2 is read")
        if length != len(data):
            self.fail(f"the GLB header says {length} bytes, the file has {len(data)} (truncated?)")
        offset, kinds = 12, []
        while offset < length:
            if offset + 8 > length:
                self.fail("a GLB chunk header is cut off")
            chunk_length, kind = np.frombuffer(data[offset : offset + 8], "<u4")
            if offset + 8 + int(chunk_length) > length:
                self.fail(f"a GLB chunk claims {chunk_length} bytes past the end of the file")
            kinds.append(int(kind))
            offset += 8 + int(chunk_length)
        if not kinds or kinds[0] != 0x4E4F534A:  # "JSON" must come first
            self.fail("the first GLB chunk is not JSON")
        json_length = int(np.frombuffer(data[12:16], "<u4")[0])
        try:
            return data[20 : 20 + json_length].decode("utf-8")
        except UnicodeDecodeError as error:
            self.fail(f"the GLB's JSON chunk is not UTF-8 ({error})")

    def _check_json(self, text: str):
        """Valid JSON (pygltflib accepts some broken JSON silently) of a bounded size."""
        try:
            document = json.loads(text)
        except ValueError as error:
            self.fail(f"not a glTF JSON document or GLB ({error})")
        count, stack = 0, [document]
        while stack:
            value = stack.pop()
            count += 1
            if count > MAX_JSON_VALUES:
                self.fail(f"its JSON holds more than {MAX_JSON_VALUES} values")
            if isinstance(value, dict):
                stack.extend(value.values())
            elif isinstance(value, list):
                stack.extend(value)
        if not isinstance(document, dict):
            self.fail("its JSON is not an object")

    def buffer(self, index: int) -> bytes:
        if index not in self._buffers:
            buffers = self.doc.buffers or []
            _index(self, index, len(buffers), "buffer")
            entry = buffers[index]
            uri = entry.uri
            if uri is None:
                if index != 0 or self.glb_blob is None:
                    self.fail(f"buffer {index} has no uri and there is no GLB binary chunk")
                data = bytes(self.glb_blob)
            else:
                data = self.external(str(uri), f"buffer {index}")
            declared = _int(self, entry.byteLength, f"buffer {index} byteLength", 1, MAX_FILE_BYTES)
            if len(data) < declared:
                self.fail(f"buffer {index} has {len(data)} bytes, byteLength says {declared}")
            self._buffers[index] = data[:declared]
        return self._buffers[index]

    def external(self, uri: str, what: str) -> bytes:
        """The bytes behind a URI: a base64 data: URI, or a relative path that stays inside the
        file's folder. Network locations, absolute paths and '..' escapes are refused."""
        if uri.startswith("data:"):
            header, _, payload = uri.partition(",")
            if not header.endswith(";base64"):
                self.fail(f"{what}: only base64 data: URIs are read")
            if len(payload) > MAX_FILE_BYTES * 4 // 3 + 4:
                self.fail(f"{what}: its data: URI is larger than {MAX_FILE_BYTES} bytes")
            try:
                return base64.b64decode(payload, validate=True)
            except (binascii.Error, ValueError) as error:
                self.fail(f"{what}: its data: URI is not valid base64 ({error})")
        parts = urlsplit(uri)
        if parts.scheme or parts.netloc:
            self.fail(
                f"{what}: URI {uri[:80]!r} is not a relative file path; blurlab never "
                "downloads and reads only files beside the glTF"
            )
        relative = unquote(parts.path)
        if not relative or Path(relative).is_absolute() or "\\" in relative or "\0" in relative:
            self.fail(f"{what}: URI {uri[:80]!r} must be a relative path inside the file's folder")
        target = (self.folder / relative).resolve()
        if not target.is_relative_to(self.folder):
            self.fail(f"{what}: URI {uri[:80]!r} leaves the file's folder; refused")
        if not target.is_file():
            self.fail(f"{what}: {relative!r} does not exist beside the file")
        if target.stat().st_size > MAX_FILE_BYTES:
            self.fail(f"{what}: {relative!r} is larger than {MAX_FILE_BYTES} bytes")
        return target.read_bytes()

    def accessor(self, index, what: str, types: tuple[str, ...], floats: bool = True):
        """Accessor `index` as a (count, n) array: float64 (normalized integers scaled to
        [-1, 1] or [0, 1]) when `floats`, else int64."""
        accessors = self.doc.accessors or []
        index = _index(self, index, len(accessors), f"{what} accessor")
        a = accessors[index]
        label = f"accessor {index} ({what})"
        if a.type not in types:
            self.fail(f"{label} has type {a.type!r}; expected one of {types}")
        if a.componentType not in _COMPONENTS:
            self.fail(f"{label} has componentType {a.componentType!r}")
        dtype, divisor = _COMPONENTS[a.componentType]
        width = _WIDTHS[a.type]
        count = _int(self, a.count, f"{label} count", 1, MAX_ACCESSOR_VALUES // width)
        if a.bufferView is None:
            values = np.zeros((count, width), dtype=dtype)
        else:
            values = self._view_elements(
                a.bufferView, a.byteOffset or 0, dtype, width, count, label
            )
        if a.sparse is not None:
            values = self._sparse(a.sparse, values, dtype, width, count, label)
        if floats:
            out = values.astype(np.float64)
            if a.normalized and divisor is not None:
                out = np.maximum(out / divisor, -1.0)
            if not np.isfinite(out).all():
                self.fail(f"{label} holds NaN or inf")
            return out
        return values.astype(np.int64)

    def _view_elements(self, view_index, offset, dtype, width, count, label) -> np.ndarray:
        views = self.doc.bufferViews or []
        view_index = _index(self, view_index, len(views), f"{label} bufferView")
        view = views[view_index]
        data = self.buffer(_int(self, view.buffer, f"bufferView {view_index} buffer", 0, 1 << 20))
        start = _int(
            self, view.byteOffset or 0, f"bufferView {view_index} byteOffset", 0, len(data)
        )
        length = _int(self, view.byteLength, f"bufferView {view_index} byteLength", 1, len(data))
        if start + length > len(data):
            self.fail(f"bufferView {view_index} runs past the end of buffer {view.buffer}")
        item = np.dtype(dtype).itemsize
        element = item * width
        stride = view.byteStride or element
        _int(self, stride, f"bufferView {view_index} byteStride", element, 252)
        offset = _int(self, offset, f"{label} byteOffset", 0, length)
        if offset % item or stride % item:
            self.fail(f"{label} is not aligned to its {item}-byte components")
        needed = offset + stride * (count - 1) + element
        if needed > length:
            self.fail(f"{label} needs {needed} bytes, its bufferView has {length}")
        first = start + offset
        byte_index = first + stride * np.arange(count)[:, None] + np.arange(element)
        rows = np.frombuffer(data, dtype=np.uint8)[byte_index]
        return rows.view(np.dtype(dtype).newbyteorder("<")).reshape(count, width)

    def _sparse(self, sparse, values, dtype, width, count, label) -> np.ndarray:
        n = _int(self, sparse.count, f"{label} sparse count", 1, count)
        idx = sparse.indices
        if idx.componentType not in (5121, 5123, 5125):
            self.fail(f"{label} sparse indices have componentType {idx.componentType!r}")
        where = self._view_elements(
            idx.bufferView, idx.byteOffset or 0, _COMPONENTS[idx.componentType][0], 1, n, label
        )[:, 0].astype(np.int64)
        if where.max() >= count or np.any(np.diff(where) <= 0):
            self.fail(f"{label} sparse indices must increase and stay below {count}")
        replaced = self._view_elements(
            sparse.values.bufferView, sparse.values.byteOffset or 0, dtype, width, n, label
        )
        values = values.copy()
        values[where] = replaced
        return values

    # Nodes and animation.

    def nodes(self, animation) -> tuple[_Nodes, list[int]]:
        doc = self.doc
        count = len(doc.nodes or [])
        if count > MAX_NODES:
            self.fail(f"{count} nodes; at most {MAX_NODES} are read")
        scenes = doc.scenes or []
        if scenes:
            chosen = _index(self, doc.scene if doc.scene is not None else 0, len(scenes), "scene")
            roots = [_index(self, r, count, "scene root node") for r in scenes[chosen].nodes or []]
        else:
            roots = list(range(count))
        parents = [-1] * count
        for i, node in enumerate(doc.nodes or []):
            for child in node.children or []:
                c = _index(self, child, count, f"node {i} child")
                if parents[c] != -1 or c == i:
                    self.fail(f"node {c} has more than one parent")
                parents[c] = i
        order, seen, stack = [], set(), [r for r in reversed(roots) if parents[r] == -1]
        while stack:  # parents before children; a cycle never reaches a root and is left out
            i = stack.pop()
            if i in seen:
                self.fail(f"node {i} is reached twice (a cycle in the hierarchy)")
            seen.add(i)
            order.append(i)
            stack.extend(reversed([int(c) for c in doc.nodes[i].children or []]))
        rest = [self._rest(i, node) for i, node in enumerate(doc.nodes or [])]
        return _Nodes(rest, parents, order, self.channels(animation, count, rest)), order

    def _rest(self, i: int, node):
        if node.matrix is not None and list(node.matrix) != list(np.eye(4).ravel()):
            m = _floats(self, node.matrix, f"node {i} matrix", 16)
            return m.reshape(4, 4).T  # glTF matrices are column-major
        return {
            "translation": _floats(self, node.translation or (0, 0, 0), f"node {i} translation", 3),
            "rotation": _floats(self, node.rotation or (0, 0, 0, 1), f"node {i} rotation", 4),
            "scale": _floats(self, node.scale or (1, 1, 1), f"node {i} scale", 3),
        }

    def channels(self, animation, node_count: int, rest) -> dict[int, list[_Channel]]:
        animations = self.doc.animations or []
        if animation is None or not animations:
            if animation not in (None, 0):
                self.fail(f"animation {animation} asked for; the file has none")
            return {}
        chosen = animations[_index(self, animation, len(animations), "animation")]
        samplers = chosen.samplers or []
        out: dict[int, list[_Channel]] = {}
        for c, channel in enumerate(chosen.channels or []):
            target = channel.target
            if target is None or target.node is None:
                continue  # a channel without a node may be ignored (glTF 2.0, 3.11)
            node = _index(self, target.node, node_count, f"animation channel {c} node")
            if target.path == "weights":
                self.fail("it animates morph target weights; morph targets are not supported")
            if target.path not in _TRS_PATHS:
                self.fail(f"animation channel {c} targets {target.path!r}")
            if isinstance(rest[node], np.ndarray):
                self.fail(f"node {node} has a matrix and is animated (glTF forbids that)")
            sampler = samplers[_index(self, channel.sampler, len(samplers), f"channel {c} sampler")]
            out.setdefault(node, []).append(self._channel(sampler, target.path, c))
        return out

    def _channel(self, sampler, path: str, c: int) -> _Channel:
        interpolation = sampler.interpolation or "LINEAR"
        if interpolation not in ("LINEAR", "STEP", "CUBICSPLINE"):
            self.fail(f"animation channel {c} has interpolation {interpolation!r}")
        times = self.accessor(sampler.input, f"channel {c} input", ("SCALAR",))[:, 0]
        if np.any(np.diff(times) <= 0):
            self.fail(f"animation channel {c} has key times that do not increase")
        width = 4 if path == "rotation" else 3
        values = self.accessor(sampler.output, f"channel {c} output", (f"VEC{width}",))
        per_key = 3 if interpolation == "CUBICSPLINE" else 1
        if len(values) != per_key * len(times):
            self.fail(f"animation channel {c} has {len(values)} values for {len(times)} keys")
        if per_key == 3:
            values = values.reshape(len(times), 3, width)
        return _Channel(path, times, values, interpolation)

    # Meshes, skins, materials.

    def scene(self, animation, camera, size_hint, shutter) -> Scene:
        doc = self.doc
        nodes, order = self.nodes(animation)
        if shutter is None:
            start = _busiest_time(nodes)
            shutter = (start, start + DEFAULT_SHUTTER_S)
        scene = Scene(name=self.path.name, shutter=tuple(float(s) for s in shutter))
        scene.source = self.path
        materials: dict = {}
        skins: dict[int, JointSkin] = {}
        for i in order:
            node = doc.nodes[i]
            if node.mesh is None:
                continue
            meshes = doc.meshes or []
            mesh_index = _index(self, node.mesh, len(meshes), f"node {i} mesh")
            skin = None
            if node.skin is not None:
                skin_index = _index(self, node.skin, len(doc.skins or []), f"node {i} skin")
                if skin_index not in skins:
                    skins[skin_index] = self.skin(skin_index, nodes)
                skin = skins[skin_index]
            for p, primitive in enumerate(meshes[mesh_index].primitives or []):
                label = f"mesh {mesh_index} primitive {p}"
                mesh = self.primitive(primitive, label, skin)
                material = self.material(primitive.material, materials)
                name = f"{node.name or f'node{i}'}/{meshes[mesh_index].name or label}/{p}"
                motion = None if skin else NodeMotion(nodes, i)
                scene.add(mesh, material, motion, skin, name)
        if not scene.objects:
            self.fail("its scene has no mesh to draw")
        if self.ignored:
            warnings.warn(
                f"blurlab.gltf: {self.path.name}: ignored {', '.join(sorted(self.ignored))}",
                stacklevel=3,
            )
        scene.camera = self.camera(camera, nodes, order, scene, size_hint)
        return scene

    def primitive(self, primitive, label: str, skin) -> Mesh:
        attributes = primitive.attributes
        mode = 4 if primitive.mode is None else primitive.mode
        if mode in _MODES:
            self.fail(f"{label} draws {_MODES[mode]}; only triangles are drawn")
        if mode not in (_TRIANGLES, _STRIP, _FAN):
            self.fail(f"{label} has primitive mode {mode!r}")
        if primitive.targets:
            self.fail(f"{label} has morph targets; morph targets are not supported")
        if getattr(attributes, "POSITION", None) is None:
            self.fail(f"{label} has no POSITION attribute")
        positions = self.accessor(attributes.POSITION, f"{label} POSITION", ("VEC3",))
        n = len(positions)
        if primitive.indices is not None:
            corners = self.accessor(primitive.indices, f"{label} indices", ("SCALAR",), False)[:, 0]
            if corners.size and (corners.min() < 0 or corners.max() >= n):
                self.fail(f"{label} has indices outside 0..{n - 1}")
        else:
            corners = np.arange(n)
        triangles = _triangles(corners, mode)
        if len(triangles) == 0:
            self.fail(f"{label} has no complete triangle")
        if 3 * len(triangles) > MAX_VERTICES:
            self.fail(f"{label} has {len(triangles)} triangles; at most {MAX_VERTICES // 3}")
        uvs = np.zeros((n, 2))
        texcoord = getattr(attributes, "TEXCOORD_0", None)
        if texcoord is not None:
            uvs = self.accessor(texcoord, f"{label} TEXCOORD_0", ("VEC2",))
        joints = weights = None
        if skin is not None:
            joints, weights = self.weights(attributes, label, n, len(skin.joints))
        elif getattr(attributes, "JOINTS_0", None) is not None:
            self.ignored.add("skin weights of a mesh whose node has no skin")
        for extra in ("COLOR_0", "TANGENT", "TEXCOORD_1"):
            if getattr(attributes, extra, None) is not None:
                self.ignored.add(extra)
        normal = getattr(attributes, "NORMAL", None)
        if normal is not None:
            normals = self.accessor(normal, f"{label} NORMAL", ("VEC3",))
            _check_count(self, normals, n, f"{label} NORMAL")
            for array, what in ((uvs, "TEXCOORD_0"),):
                _check_count(self, array, n, f"{label} {what}")
            length = np.linalg.norm(normals, axis=1, keepdims=True)
            normals = np.where(length > 0, normals / np.maximum(length, 1e-12), [0.0, 1.0, 0.0])
            return Mesh(positions, normals, uvs, triangles, joints, weights, label)
        # No normals: flat ones, as the glTF spec asks, so each triangle gets its own corners.
        _check_count(self, uvs, n, f"{label} TEXCOORD_0")
        flat = triangles.ravel()
        a, b, c = (positions[triangles[:, k]] for k in range(3))
        face = np.cross(b - a, c - a)
        length = np.linalg.norm(face, axis=1, keepdims=True)
        face = np.where(length > 0, face / np.maximum(length, 1e-300), [0.0, 1.0, 0.0])
        return Mesh(
            positions[flat],
            np.repeat(face, 3, axis=0),
            uvs[flat],
            np.arange(len(flat)).reshape(-1, 3),
            None if joints is None else joints[flat],
            None if weights is None else weights[flat],
            label,
        )

    def weights(self, attributes, label: str, n: int, joint_count: int):
        sets = []
        for k in range(2):
            j = getattr(attributes, f"JOINTS_{k}", None)
            w = getattr(attributes, f"WEIGHTS_{k}", None)
            if j is None and w is None:
                continue
            if j is None or w is None:
                self.fail(f"{label} has JOINTS_{k} or WEIGHTS_{k} without the other")
            jj = self.accessor(j, f"{label} JOINTS_{k}", ("VEC4",), False)
            ww = self.accessor(w, f"{label} WEIGHTS_{k}", ("VEC4",))
            _check_count(self, jj, n, f"{label} JOINTS_{k}")
            _check_count(self, ww, n, f"{label} WEIGHTS_{k}")
            sets.append((jj, ww))
        if not sets:
            self.fail(f"{label} belongs to a skinned node but has no JOINTS_0/WEIGHTS_0")
        joints = np.concatenate([s[0] for s in sets], axis=1)
        weights = np.concatenate([s[1] for s in sets], axis=1)
        if np.any(weights < 0):
            self.fail(f"{label} has negative skin weights")
        if joints.min() < 0 or joints[weights > 0].max(initial=0) >= joint_count:
            self.fail(f"{label} names a joint outside its skin's {joint_count}")
        joints = np.where(weights > 0, joints, 0)
        if joints.shape[1] > 4:
            # blurlab skins with four influences: keep the four largest, renormalised.
            top = np.argsort(-weights, axis=1, kind="stable")[:, :4]
            if np.any(np.take_along_axis(weights, np.argsort(-weights, axis=1)[:, 4:], 1) > 0):
                warnings.warn(
                    f"blurlab.gltf: {self.path.name}: {label} has more than four joint weights "
                    "per vertex; the four largest are kept and renormalised",
                    stacklevel=5,
                )
            joints = np.take_along_axis(joints, top, 1)
            weights = np.take_along_axis(weights, top, 1)
        total = weights.sum(axis=1, keepdims=True)
        if np.any(total <= 0):
            self.fail(f"{label} has a vertex whose skin weights are all zero")
        return joints.astype(np.uint32), weights / total

    def skin(self, index: int, nodes: _Nodes) -> JointSkin:
        skin = self.doc.skins[index]
        count = len(self.doc.nodes)
        joints = [_index(self, j, count, f"skin {index} joint") for j in skin.joints or []]
        if not joints:
            self.fail(f"skin {index} has no joints")
        if skin.inverseBindMatrices is None:
            inverse = np.tile(np.eye(4), (len(joints), 1, 1))
        else:
            flat = self.accessor(
                skin.inverseBindMatrices, f"skin {index} inverseBindMatrices", ("MAT4",)
            )
            if len(flat) != len(joints):
                self.fail(
                    f"skin {index} has {len(flat)} inverse bind matrices for {len(joints)} joints"
                )
            inverse = flat.reshape(-1, 4, 4).transpose(0, 2, 1)  # column-major
        return JointSkin(nodes, joints, inverse)

    def material(self, index, cache: dict) -> Material:
        if index is None:
            return Material(color=(1.0, 1.0, 1.0))
        materials = self.doc.materials or []
        index = _index(self, index, len(materials), "material")
        if index in cache:
            return cache[index]
        m = materials[index]
        pbr = m.pbrMetallicRoughness
        color = (1.0, 1.0, 1.0, 1.0)
        texture = None
        if pbr is not None:
            color = _floats(
                self, pbr.baseColorFactor or color, f"material {index} baseColorFactor", 4
            )
            if pbr.baseColorTexture is not None:
                texture = self.texture(pbr.baseColorTexture, index)
            if pbr.metallicRoughnessTexture is not None or (pbr.metallicFactor not in (None, 0)):
                self.ignored.add("metallic-roughness")
        for feature in ("normalTexture", "occlusionTexture", "emissiveTexture"):
            if getattr(m, feature, None) is not None:
                self.ignored.add(feature)
        emission = _floats(
            self, m.emissiveFactor or (0, 0, 0), f"material {index} emissiveFactor", 3
        )
        extensions = dict(m.extensions or {})
        # KHR_materials_emissive_strength scales the factor beyond 1: blurlab's HDR emission.
        strength_ext = extensions.pop("KHR_materials_emissive_strength", None) or {}
        strength = 1.0
        if isinstance(strength_ext, dict) and "emissiveStrength" in strength_ext:
            strength = _floats(self, [strength_ext["emissiveStrength"]], "emissiveStrength", 1)[0]
        if (
            np.any(emission < 0)
            or np.any(emission > 1)
            or not 0 <= strength <= MAX_EMISSION_STRENGTH
        ):
            self.fail(
                f"material {index}: emission {emission.tolist()} x {strength} is outside colour "
                f"[0, 1] x strength [0, {MAX_EMISSION_STRENGTH:g}]"
            )
        if m.alphaMode not in (None, "OPAQUE"):
            self.ignored.add(f"alphaMode {m.alphaMode}")
        if extensions:
            self.ignored.add("material extensions " + ", ".join(sorted(extensions)))
        lit = bool(np.any(emission > 0))
        cache[index] = Material(
            color=tuple(float(c) for c in color[:3]),
            texture=texture,
            emission=tuple(float(e) for e in emission),
            emission_strength=float(strength) if lit else 0.0,
        )
        return cache[index]

    def texture(self, info, material: int) -> np.ndarray:
        from PIL import Image, UnidentifiedImageError

        textures = self.doc.textures or []
        texture = textures[_index(self, info.index, len(textures), f"material {material} texture")]
        if (info.texCoord or 0) != 0:
            self.ignored.add("texture coordinate sets other than 0")
        images = self.doc.images or []
        if texture.source is None:
            self.fail(f"material {material}'s texture has no image")
        image_index = _index(self, texture.source, len(images), "texture source")
        image = images[image_index]
        what = f"image {image_index}"
        if image.uri is not None:
            data = self.external(str(image.uri), what)
        else:
            views = self.doc.bufferViews or []
            view = views[_index(self, image.bufferView, len(views), f"{what} bufferView")]
            buffer = self.buffer(_int(self, view.buffer, f"{what} buffer", 0, 1 << 20))
            start, length = view.byteOffset or 0, view.byteLength or 0
            if start < 0 or length <= 0 or start + length > len(buffer):
                self.fail(f"{what}'s bufferView runs past its buffer")
            data = buffer[start : start + length]
        try:
            with Image.open(bytes_io.BytesIO(data), formats=("PNG", "JPEG")) as picture:
                w, h = picture.size
                if w * h > MAX_IMAGE_PIXELS:
                    self.fail(f"{what} is {w}x{h}; at most {MAX_IMAGE_PIXELS} pixels are read")
                array = np.asarray(picture.convert("RGBA"))
        except (UnidentifiedImageError, OSError, ValueError, SyntaxError) as error:
            self.fail(f"{what} could not be decoded as PNG or JPEG ({error})")
        return array

    # The camera.

    def camera(self, camera, nodes: _Nodes, order: list[int], scene: Scene, size_hint) -> Camera:
        if isinstance(camera, Camera):
            return camera
        cameras = self.doc.cameras or []
        if camera is not None:
            _index(self, camera, len(cameras), "camera")
        wanted = camera if camera is not None else 0
        for i in order:
            if self.doc.nodes[i].camera is not None and self.doc.nodes[i].camera == wanted:
                return self._file_camera(cameras[wanted], wanted, nodes, i, scene)
        if camera is not None:
            self.fail(f"camera {camera} is used by no node of the scene")
        return _framing_camera(scene, size_hint)

    def _file_camera(self, entry, index: int, nodes: _Nodes, node: int, scene: Scene) -> Camera:
        if entry.type != "perspective" or entry.perspective is None:
            self.fail(f"camera {index} is {entry.type!r}; only perspective cameras are read")
        p = entry.perspective
        fov = math.degrees(_floats(self, [p.yfov], f"camera {index} yfov", 1)[0])
        near = _floats(self, [p.znear], f"camera {index} znear", 1)[0]
        far = None if p.zfar is None else _floats(self, [p.zfar], f"camera {index} zfar", 1)[0]
        if far is None:  # an infinite projection: far enough for the scene's bounds
            center, radius = _bounds(scene)
            eye = nodes.world(scene.shutter[0])[node][:3, 3]
            far = max(near * 1e4, 4.0 * (np.linalg.norm(eye - center) + radius))
        try:
            return Camera(
                position=(0, 0, 0),
                look_at=(0, 0, -1),
                fov_y=fov,
                near=near,
                far=far,
                motion=CameraNodeMotion(nodes, node),
            )
        except ValueError as error:
            self.fail(f"camera {index}: {error}")


def _busiest_time(nodes: _Nodes, samples: int = 64) -> float:
    """Where the default shutter opens: of `samples` times spread over the keyed range, the
    one at which the nodes' world matrices change fastest (docs/spec.md §15), so that a scene
    loaded without a shutter shows its motion; 0 for a still file."""
    keyed = [ch.times for chans in nodes.channels.values() for ch in chans]
    if not keyed:
        return 0.0
    start, end = min(float(k[0]) for k in keyed), max(float(k[-1]) for k in keyed)
    if end <= start:
        return start
    step = DEFAULT_SHUTTER_S
    times = start + (np.arange(samples) + 0.5) / samples * max(end - start - step, 0.0)
    change = [
        sum(np.abs(a - b).sum() for a, b in zip(nodes.world(t), nodes.world(t + step), strict=True))
        for t in times
    ]
    return float(times[int(np.argmax(change))])


def _framing_camera(scene: Scene, size_hint) -> Camera:
    """A camera on +z of the scene's bounds at the shutter's opening, looking at their centre,
    with the bounding sphere inside the view (docs/spec.md §15)."""
    center, radius = _bounds(scene)
    fov_y = 45.0
    aspect = 16 / 9 if size_hint is None else float(size_hint[0]) / float(size_hint[1])
    half = math.radians(fov_y) / 2
    half = min(half, math.atan(math.tan(half) * aspect))
    distance = 1.1 * radius / math.sin(half)
    return Camera(
        position=tuple(center + np.array([0.0, 0.0, distance])),
        look_at=tuple(center),
        fov_y=fov_y,
        near=max(distance - 2 * radius, distance * 1e-3),
        far=distance + 4 * radius,
    )


def _bounds(scene: Scene) -> tuple[np.ndarray, float]:
    t = scene.shutter[0]
    points = []
    for obj in scene.objects:
        p = np.c_[obj.mesh.positions.astype(np.float64), np.ones(len(obj.mesh.positions))]
        if obj.skeleton is not None:
            bones = obj.skeleton.matrices(t)
            skinning = np.einsum(
                "vk,vkij->vij", obj.mesh.bone_weights, bones[obj.mesh.bone_indices]
            )
            p = np.einsum("vij,vj->vi", skinning, p)
        points.append((p @ obj.model(t).T)[:, :3])
    points = np.concatenate(points)
    low, high = points.min(axis=0), points.max(axis=0)
    center = 0.5 * (low + high)
    radius = max(float(np.linalg.norm(high - low)) / 2, 1e-3)
    return center, radius


def _triangles(corners: np.ndarray, mode: int) -> np.ndarray:
    if mode == _TRIANGLES:
        return corners[: len(corners) // 3 * 3].reshape(-1, 3)
    if len(corners) < 3:
        return np.zeros((0, 3), np.int64)
    i = np.arange(len(corners) - 2)
    if mode == _FAN:
        return np.stack([np.full_like(i, corners[0]), corners[i + 1], corners[i + 2]], axis=1)
    odd = i % 2 == 1  # a strip flips every second triangle to keep the winding
    a = np.where(odd, corners[i + 1], corners[i])
    b = np.where(odd, corners[i], corners[i + 1])
    return np.stack([a, b, corners[i + 2]], axis=1)


def _index(loader: _Loader, value, count: int, what: str) -> int:
    return (
        _int(loader, value, what, 0, count - 1) if count > 0 else loader.fail(f"{what}: none exist")
    )


def _int(loader: _Loader, value, what: str, low: int, high: int) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        loader.fail(f"{what} must be an integer, not {value!r}"[:200])
    if not low <= int(value) <= high:
        loader.fail(f"{what} is {value}; allowed {low}..{high}")
    return int(value)


def _floats(loader: _Loader, value, what: str, size: int) -> np.ndarray:
    try:
        v = np.asarray(value, dtype=np.float64).ravel()
    except (TypeError, ValueError):
        loader.fail(f"{what} must be {size} numbers, not {value!r}"[:200])
    if v.shape != (size,) or not np.isfinite(v).all():
        loader.fail(f"{what} must be {size} finite numbers, not {value!r}"[:200])
    return v


def _check_count(loader: _Loader, array: np.ndarray, n: int, what: str):
    if len(array) != n:
        loader.fail(f"{what} has {len(array)} elements, POSITION has {n}")
