"""glTF mesh primitives as blurlab meshes: triangles, strips and fans, indexed or not, with
normals (flat ones where the file has none), texture coordinates and skin weights."""

from __future__ import annotations

import numpy as np

from ..mesh import Mesh
from .accessors import accessor
from .document import GltfFile
from .skins import skin_weights

MAX_VERTICES = 1 << 24  # per primitive, after any de-indexing
_TRIANGLES, _STRIP, _FAN = 4, 5, 6
_MODES = {0: "POINTS", 1: "LINES", 2: "LINE_LOOP", 3: "LINE_STRIP"}


def primitive_mesh(file: GltfFile, primitive, label: str, skin) -> Mesh:
    attributes = primitive.attributes
    mode = 4 if primitive.mode is None else primitive.mode
    if mode in _MODES:
        file.fail(f"{label} draws {_MODES[mode]}; only triangles are drawn")
    if mode not in (_TRIANGLES, _STRIP, _FAN):
        file.fail(f"{label} has primitive mode {mode!r}")
    if primitive.targets:
        file.fail(f"{label} has morph targets; morph targets are not supported")
    if getattr(attributes, "POSITION", None) is None:
        file.fail(f"{label} has no POSITION attribute")
    positions = accessor(file, attributes.POSITION, f"{label} POSITION", ("VEC3",))
    n = len(positions)
    if primitive.indices is not None:
        corners = accessor(file, primitive.indices, f"{label} indices", ("SCALAR",), False)[:, 0]
        if corners.size and (corners.min() < 0 or corners.max() >= n):
            file.fail(f"{label} has indices outside 0..{n - 1}")
    else:
        corners = np.arange(n)
    triangles = _triangles(corners, mode)
    if len(triangles) == 0:
        file.fail(f"{label} has no complete triangle")
    if 3 * len(triangles) > MAX_VERTICES:
        file.fail(f"{label} has {len(triangles)} triangles; at most {MAX_VERTICES // 3}")
    uvs = np.zeros((n, 2))
    texcoord = getattr(attributes, "TEXCOORD_0", None)
    if texcoord is not None:
        uvs = accessor(file, texcoord, f"{label} TEXCOORD_0", ("VEC2",))
    joints = weights = None
    if skin is not None:
        joints, weights = skin_weights(file, attributes, label, n, len(skin.joints))
    elif getattr(attributes, "JOINTS_0", None) is not None:
        file.ignored.add("skin weights of a mesh whose node has no skin")
    for extra in ("COLOR_0", "TANGENT", "TEXCOORD_1"):
        if getattr(attributes, extra, None) is not None:
            file.ignored.add(extra)
    normal = getattr(attributes, "NORMAL", None)
    if normal is not None:
        normals = accessor(file, normal, f"{label} NORMAL", ("VEC3",))
        file.check_count(normals, n, f"{label} NORMAL")
        for array, what in ((uvs, "TEXCOORD_0"),):
            file.check_count(array, n, f"{label} {what}")
        length = np.linalg.norm(normals, axis=1, keepdims=True)
        normals = np.where(length > 0, normals / np.maximum(length, 1e-12), [0.0, 1.0, 0.0])
        return Mesh(positions, normals, uvs, triangles, joints, weights, label)
    # No normals: flat ones, as the glTF spec asks, so each triangle gets its own corners.
    file.check_count(uvs, n, f"{label} TEXCOORD_0")
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
