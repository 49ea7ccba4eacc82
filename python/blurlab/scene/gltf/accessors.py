"""glTF accessors: typed views into the file's buffers (strided, normalized, sparse), read into
NumPy arrays after every offset, stride and count is checked against the bytes there are."""

from __future__ import annotations

import numpy as np

from .document import GltfFile

MAX_ACCESSOR_VALUES = 1 << 25  # numbers in one accessor (256 MiB as float64)

_COMPONENTS = {  # componentType: (dtype, the divisor of a normalized value)
    5120: (np.int8, 127.0),
    5121: (np.uint8, 255.0),
    5122: (np.int16, 32767.0),
    5123: (np.uint16, 65535.0),
    5125: (np.uint32, None),
    5126: (np.float32, None),
}
_WIDTHS = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT2": 4, "MAT3": 9, "MAT4": 16}


def accessor(file: GltfFile, index, what: str, types: tuple[str, ...], floats: bool = True):
    """Accessor `index` as a (count, n) array: float64 (normalized integers scaled to
    [-1, 1] or [0, 1]) when `floats`, else int64."""
    accessors = file.doc.accessors or []
    index = file.index(index, len(accessors), f"{what} accessor")
    a = accessors[index]
    label = f"accessor {index} ({what})"
    if a.type not in types:
        file.fail(f"{label} has type {a.type!r}; expected one of {types}")
    if a.componentType not in _COMPONENTS:
        file.fail(f"{label} has componentType {a.componentType!r}")
    dtype, divisor = _COMPONENTS[a.componentType]
    width = _WIDTHS[a.type]
    count = file.integer(a.count, f"{label} count", 1, MAX_ACCESSOR_VALUES // width)
    if a.bufferView is None:
        values = np.zeros((count, width), dtype=dtype)
    else:
        values = _view_elements(file, a.bufferView, a.byteOffset or 0, dtype, width, count, label)
    if a.sparse is not None:
        values = _sparse(file, a.sparse, values, dtype, width, count, label)
    if floats:
        out = values.astype(np.float64)
        if a.normalized and divisor is not None:
            out = np.maximum(out / divisor, -1.0)
        if not np.isfinite(out).all():
            file.fail(f"{label} holds NaN or inf")
        return out
    return values.astype(np.int64)


def _view_elements(file: GltfFile, view_index, offset, dtype, width, count, label) -> np.ndarray:
    views = file.doc.bufferViews or []
    view_index = file.index(view_index, len(views), f"{label} bufferView")
    view = views[view_index]
    data = file.buffer(file.integer(view.buffer, f"bufferView {view_index} buffer", 0, 1 << 20))
    start = file.integer(view.byteOffset or 0, f"bufferView {view_index} byteOffset", 0, len(data))
    length = file.integer(view.byteLength, f"bufferView {view_index} byteLength", 1, len(data))
    if start + length > len(data):
        file.fail(f"bufferView {view_index} runs past the end of buffer {view.buffer}")
    item = np.dtype(dtype).itemsize
    element = item * width
    stride = view.byteStride or element
    file.integer(stride, f"bufferView {view_index} byteStride", element, 252)
    offset = file.integer(offset, f"{label} byteOffset", 0, length)
    if offset % item or stride % item:
        file.fail(f"{label} is not aligned to its {item}-byte components")
    needed = offset + stride * (count - 1) + element
    if needed > length:
        file.fail(f"{label} needs {needed} bytes, its bufferView has {length}")
    first = start + offset
    byte_index = first + stride * np.arange(count)[:, None] + np.arange(element)
    rows = np.frombuffer(data, dtype=np.uint8)[byte_index]
    return rows.view(np.dtype(dtype).newbyteorder("<")).reshape(count, width)


def _sparse(file: GltfFile, sparse, values, dtype, width, count, label) -> np.ndarray:
    n = file.integer(sparse.count, f"{label} sparse count", 1, count)
    idx = sparse.indices
    if idx.componentType not in (5121, 5123, 5125):
        file.fail(f"{label} sparse indices have componentType {idx.componentType!r}")
    where = _view_elements(
        file, idx.bufferView, idx.byteOffset or 0, _COMPONENTS[idx.componentType][0], 1, n, label
    )[:, 0].astype(np.int64)
    if where.max() >= count or np.any(np.diff(where) <= 0):
        file.fail(f"{label} sparse indices must increase and stay below {count}")
    replaced = _view_elements(
        file, sparse.values.bufferView, sparse.values.byteOffset or 0, dtype, width, n, label
    )
    values = values.copy()
    values[where] = replaced
    return values


# Nodes and animation.
