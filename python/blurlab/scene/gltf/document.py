"""Reading a glTF file as untrusted input: the container (.gltf JSON or .glb), its buffers and
the URIs they name, and the checks every index, count and number of the file passes before use.
A file from outside is untrusted: indices and ranges are bounded, buffers come only from the
file itself, a data: URI or a file inside the file's own folder, and nothing is downloaded.
"""

from __future__ import annotations

import base64
import binascii
import json
from pathlib import Path
from urllib.parse import unquote, urlsplit

import numpy as np

from ...errors import bad_byte

MAX_FILE_BYTES = 256 << 20  # a .gltf, .glb or external buffer larger than this is refused
MAX_JSON_VALUES = 100_000  # pygltflib builds an object per JSON value: this bounds its time


class GltfError(ValueError):
    """A glTF file blurlab cannot use: the message names the file and what is wrong."""


class GltfFile:
    """An opened glTF document (`doc`, pygltflib's), its GLB binary chunk, its buffers as read,
    and the features met that blurlab ignores (warned about once the scene is built)."""

    def __init__(self, path: Path):
        self.path = path
        self.folder = path.resolve().parent
        self.ignored: set[str] = set()
        self.doc, self.glb_blob = self._document()
        self._buffers: dict[int, bytes] = {}

    def fail(self, what: str):
        raise GltfError(f"blurlab.scene.gltf: {self.path.name}: {what}")

    def _document(self):
        import pygltflib

        if not self.path.is_file():
            raise FileNotFoundError(f"blurlab.scene.gltf: no such file: {self.path}")
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
            except UnicodeDecodeError as error:
                self.fail(f"neither a GLB nor glTF JSON text: {bad_byte(error)}")
            self._check_json(text)  # fails with its own message
            try:
                doc = pygltflib.GLTF2.gltf_from_json(text)
            except ValueError as error:
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
            self.fail(f"the GLB's JSON chunk is not UTF-8: {bad_byte(error)}")

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
            self.index(index, len(buffers), "buffer")
            entry = buffers[index]
            uri = entry.uri
            if uri is None:
                if index != 0 or self.glb_blob is None:
                    self.fail(f"buffer {index} has no uri and there is no GLB binary chunk")
                data = bytes(self.glb_blob)
            else:
                data = self.external(str(uri), f"buffer {index}")
            declared = self.integer(
                entry.byteLength, f"buffer {index} byteLength", 1, MAX_FILE_BYTES
            )
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

    # Checks of the values the file holds: each failure names the file and the value.

    def index(self, value, count: int, what: str) -> int:
        """`value` as an index into `count` items of kind `what`."""
        if count <= 0:
            self.fail(f"{what}: none exist")
        return self.integer(value, what, 0, count - 1)

    def integer(self, value, what: str, low: int, high: int) -> int:
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
            self.fail(f"{what} must be an integer, not {value!r}"[:200])
        if not low <= int(value) <= high:
            self.fail(f"{what} is {value}; allowed {low}..{high}")
        return int(value)

    def floats(self, value, what: str, size: int) -> np.ndarray:
        try:
            v = np.asarray(value, dtype=np.float64).ravel()
        except (TypeError, ValueError):
            self.fail(f"{what} must be {size} numbers, not {value!r}"[:200])
        if v.shape != (size,) or not np.isfinite(v).all():
            self.fail(f"{what} must be {size} finite numbers, not {value!r}"[:200])
        return v

    def check_count(self, array: np.ndarray, n: int, what: str):
        if len(array) != n:
            self.fail(f"{what} has {len(array)} elements, POSITION has {n}")
