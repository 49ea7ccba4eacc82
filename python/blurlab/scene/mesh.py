"""Triangle meshes built in NumPy: primitives, the Utah teapot, a fan, a skinned tube, OBJ files.

World space is right-handed with y up. Texture coordinates (u, v) have v growing down the
image: (0, 0) is the image's top-left texel (textures are stored top row first).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import bad_byte, cause

_DATA = Path(__file__).resolve().parents[1] / "data"  # blurlab/data


@dataclass(eq=False)
class Mesh:
    """Vertices (positions, normals, uvs), triangles, and optional skinning weights."""

    positions: np.ndarray  # (N, 3) float32
    normals: np.ndarray  # (N, 3) float32
    uvs: np.ndarray  # (N, 2) float32
    indices: np.ndarray  # (M, 3) uint32
    bone_indices: np.ndarray | None = None  # (N, 4) uint32
    bone_weights: np.ndarray | None = None  # (N, 4) float32, rows sum to 1
    name: str = "mesh"
    _gpu: dict = field(default_factory=dict, repr=False)  # per-context GPU copies

    def __post_init__(self):
        self.positions = _as(self.positions, np.float32, 3, "positions")
        count = len(self.positions)
        self.normals = _as(self.normals, np.float32, 3, "normals", count)
        self.uvs = _as(self.uvs, np.float32, 2, "uvs", count)
        self.indices = np.ascontiguousarray(np.asarray(self.indices).reshape(-1, 3))
        if len(self.indices) == 0 or count == 0:
            raise ValueError(f"blurlab: mesh {self.name!r} has no triangles or no vertices")
        if self.indices.min() < 0 or self.indices.max() >= count:
            raise ValueError(f"blurlab: mesh {self.name!r} has indices outside 0..{count - 1}")
        self.indices = self.indices.astype(np.uint32)
        if (self.bone_indices is None) != (self.bone_weights is None):
            raise ValueError("blurlab: bone_indices and bone_weights come together")
        if self.bone_indices is not None:
            self.bone_indices = np.ascontiguousarray(self.bone_indices, dtype=np.uint32)
            self.bone_weights = _as(self.bone_weights, np.float32, 4, "bone_weights", count)
            if self.bone_indices.shape != (count, 4):
                raise ValueError(f"blurlab: bone_indices must be ({count}, 4)")
            if np.any(self.bone_weights < 0) or not np.allclose(self.bone_weights.sum(1), 1, 1e-4):
                raise ValueError("blurlab: bone weights must be >= 0 and sum to 1 per vertex")

    @property
    def skinned(self) -> bool:
        return self.bone_indices is not None

    def transformed(self, matrix: np.ndarray) -> Mesh:
        """A copy with positions and normals transformed by a 4x4 matrix."""
        m = np.asarray(matrix, dtype=np.float64)
        p = self.positions @ m[:3, :3].T + m[:3, 3]
        n = self.normals @ np.linalg.inv(m[:3, :3])
        n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-12)
        return Mesh(p, n, self.uvs, self.indices, self.bone_indices, self.bone_weights, self.name)

    @staticmethod
    def merge(parts: list[Mesh], name: str = "merged") -> Mesh:
        """One mesh holding every part (unskinned parts only)."""
        offsets = np.cumsum([0] + [len(p.positions) for p in parts[:-1]])
        return Mesh(
            np.concatenate([p.positions for p in parts]),
            np.concatenate([p.normals for p in parts]),
            np.concatenate([p.uvs for p in parts]),
            np.concatenate([p.indices + o for p, o in zip(parts, offsets, strict=True)]),
            name=name,
        )


def _as(array, dtype, columns, what, count=None) -> np.ndarray:
    a = np.ascontiguousarray(np.asarray(array, dtype=dtype).reshape(-1, columns))
    if count is not None and len(a) != count:
        raise ValueError(f"blurlab: mesh {what} has {len(a)} rows, expected {count}")
    if not np.isfinite(a).all():
        raise ValueError(f"blurlab: mesh {what} contain NaN or inf")
    return a


def _grid(nu: int, nv: int) -> np.ndarray:
    """Triangles of an (nu+1) x (nv+1) vertex grid, row-major in v then u."""
    u, v = np.meshgrid(np.arange(nu), np.arange(nv))
    a = (v * (nu + 1) + u).ravel()
    b, c, d = a + 1, a + nu + 1, a + nu + 2
    return np.stack([np.stack([a, c, b], 1), np.stack([b, c, d], 1)], 1).reshape(-1, 3)


def _surface(points: np.ndarray, normals: np.ndarray, nu: int, nv: int, name: str) -> Mesh:
    u, v = np.meshgrid(np.linspace(0, 1, nu + 1), np.linspace(0, 1, nv + 1))
    uvs = np.stack([u.ravel(), v.ravel()], 1)
    return Mesh(points.reshape(-1, 3), normals.reshape(-1, 3), uvs, _grid(nu, nv), name=name)


def plane(width: float = 1.0, depth: float = 1.0, uv_repeat: float = 1.0) -> Mesh:
    """A rectangle in the XZ plane, facing +y, centered at the origin."""
    x = np.array([-0.5, 0.5]) * width
    z = np.array([-0.5, 0.5]) * depth
    xx, zz = np.meshgrid(x, z)
    p = np.stack([xx, np.zeros_like(xx), zz], -1)
    n = np.broadcast_to([0.0, 1.0, 0.0], p.shape)
    mesh = _surface(p, n, 1, 1, "plane")
    mesh.uvs *= uv_repeat
    return mesh


def box(size=(1.0, 1.0, 1.0)) -> Mesh:
    """An axis-aligned box centered at the origin, flat-shaded (24 vertices)."""
    half = np.asarray(size, dtype=np.float64) / 2
    faces = []
    for axis in range(3):
        for sign in (-1.0, 1.0):
            n = np.zeros(3)
            n[axis] = sign
            a, b = [(axis + 1) % 3, (axis + 2) % 3][:: int(sign)]
            corners = []
            for du, dv in ((-1, -1), (1, -1), (-1, 1), (1, 1)):
                c = n.copy()
                c[a], c[b] = du, dv
                corners.append(c * half)
            faces.append(
                Mesh(
                    np.array(corners),
                    np.tile(n, (4, 1)),
                    [[0, 0], [1, 0], [0, 1], [1, 1]],
                    [[0, 1, 2], [1, 3, 2]],
                )
            )
    return Mesh.merge(faces, "box")


def sphere(radius: float = 0.5, segments: int = 48, rings: int = 24) -> Mesh:
    theta, phi = np.meshgrid(
        np.linspace(0, 2 * math.pi, segments + 1), np.linspace(0, math.pi, rings + 1)
    )
    n = np.stack([np.sin(phi) * np.cos(theta), np.cos(phi), -np.sin(phi) * np.sin(theta)], -1)
    return _surface(n * radius, n, segments, rings, "sphere")


def cylinder(radius: float = 0.5, height: float = 1.0, segments: int = 48) -> Mesh:
    """A capped cylinder along y, centered at the origin."""
    theta, h = np.meshgrid(np.linspace(0, 2 * math.pi, segments + 1), [0.5, -0.5])
    n = np.stack([np.cos(theta), np.zeros_like(theta), -np.sin(theta)], -1)
    side = _surface(n * radius + np.stack([0 * h, h * height, 0 * h], -1), n, segments, 1, "side")
    caps = []
    for y, sign in ((0.5, 1.0), (-0.5, -1.0)):
        ring = np.stack([np.cos(theta[0]), np.zeros(segments + 1), -np.sin(theta[0])], -1)
        p = np.concatenate([[[0.0, y * height, 0.0]], ring * radius + [0, y * height, 0]])
        fan = [[0, i + 1, i + 2] if sign > 0 else [0, i + 2, i + 1] for i in range(segments)]
        uv = np.concatenate([[[0.5, 0.5]], ring[:, [0, 2]] * 0.5 + 0.5])
        caps.append(Mesh(p, np.tile([0.0, sign, 0.0], (len(p), 1)), uv, fan))
    return Mesh.merge([side, *caps], "cylinder")


def torus(major: float = 0.5, minor: float = 0.2, segments: int = 64, sides: int = 32) -> Mesh:
    """A torus around the y axis."""
    u, v = np.meshgrid(
        np.linspace(0, 2 * math.pi, segments + 1), np.linspace(0, 2 * math.pi, sides + 1)
    )
    ring = np.stack([np.cos(u), np.zeros_like(u), -np.sin(u)], -1)
    n = ring * np.cos(v)[..., None] + np.array([0.0, 1.0, 0.0]) * np.sin(v)[..., None]
    return _surface(ring * major + n * minor, n, segments, sides, "torus")


def torus_knot(
    p: int = 2,
    q: int = 3,
    radius: float = 0.4,
    tube: float = 0.1,
    segments: int = 256,
    sides: int = 16,
) -> Mesh:
    """A (p, q) torus knot: a tube around the curve that winds p times around the axis."""
    t = np.linspace(0, 2 * math.pi, segments + 1)

    def curve(t):
        r = radius * (2 + np.cos(q * t)) / 3
        return np.stack([r * np.cos(p * t), radius * np.sin(q * t) / 3, r * np.sin(p * t)], -1)

    center = curve(t)
    tangent = curve(t + 1e-4) - curve(t - 1e-4)
    tangent /= np.linalg.norm(tangent, axis=1, keepdims=True)
    normal = np.cross(tangent, center)  # any vector across the tangent, stable along this knot
    normal /= np.linalg.norm(normal, axis=1, keepdims=True)
    binormal = np.cross(tangent, normal)
    a = np.linspace(0, 2 * math.pi, sides + 1)[:, None, None]
    n = np.cos(a) * normal[None] + np.sin(a) * binormal[None]
    return _surface(center[None] + tube * n, n, segments, sides, "torus_knot")


def _teapot_data() -> tuple[np.ndarray, np.ndarray]:
    lines = [ln for ln in (_DATA / "teapot.txt").read_text().splitlines() if not ln.startswith("#")]
    count = int(lines[0].split()[1])
    patches = np.array([[int(x) for x in ln.split()] for ln in lines[1 : 1 + count]])
    points = np.array([[float(x) for x in ln.split()] for ln in lines[2 + count :]])
    return patches, points


def teapot(segments: int = 10) -> Mesh:
    """The Utah teapot from Newell's 32 Bezier patches, standing on y = 0, 1 unit tall."""
    patches, points = _teapot_data()
    s = np.linspace(0, 1, segments + 1)
    basis = np.stack([(1 - s) ** 3, 3 * s * (1 - s) ** 2, 3 * s**2 * (1 - s), s**3], 1)
    dbasis = np.stack(
        [
            -3 * (1 - s) ** 2,
            3 * (1 - s) ** 2 - 6 * s * (1 - s),
            6 * s * (1 - s) - 3 * s**2,
            3 * s**2,
        ],
        1,
    )
    # z-up data to y-up, scaled to unit height (the lid knob tops out at 3.15).
    control = points[patches][..., [0, 2, 1]] * np.array([1.0, 1.0, -1.0]) / 3.15
    control = control.reshape(-1, 4, 4, 3)
    p = np.einsum("ui,vj,kijc->kuvc", basis, basis, control)
    du = np.einsum("ui,vj,kijc->kuvc", dbasis, basis, control)
    dv = np.einsum("ui,vj,kijc->kuvc", basis, dbasis, control)
    n = np.cross(dv, du)
    # At the lid's knob and the bottom's center a patch edge collapses to a point; its normal is
    # the axis, pointing away from the body.
    length = np.linalg.norm(n, axis=-1, keepdims=True)
    axis = np.array([0.0, 1.0, 0.0]) * np.sign(p[..., 1:2] - 0.5)
    n = np.where(length > 1e-9, n / np.maximum(length, 1e-12), axis)
    parts = [_surface(p[k], n[k], segments, segments, "patch") for k in range(len(control))]
    return Mesh.merge(parts, "teapot")


def fan(
    blades: int = 4,
    radius: float = 1.0,
    hub: float = 0.15,
    width: float = 0.28,
    thickness: float = 0.04,
) -> Mesh:
    """A fan in the XY plane facing +z: a hub and `blades` flat blades."""
    parts = [cylinder(hub, thickness * 2, 32).transformed(rotation_x(math.pi / 2))]
    blade = box((radius - hub * 0.5, width, thickness))
    for i in range(blades):
        place = _rotation_z(2 * math.pi * i / blades) @ _translation(
            ((radius + hub * 0.5) / 2, 0, 0)
        )
        parts.append(blade.transformed(place))
    return Mesh.merge(parts, "fan")


def tube(
    length: float = 2.0,
    radius: float = 0.15,
    segments: int = 64,
    sides: int = 24,
    blend: float = 0.3,
) -> Mesh:
    """A tube along +x from 0 to `length`, skinned to two bones that meet at its middle.

    Bone 0 owns x < length/2 - blend/2, bone 1 owns x > length/2 + blend/2; between them the
    weights blend linearly.
    """
    x, a = np.meshgrid(np.linspace(0, length, segments + 1), np.linspace(0, 2 * math.pi, sides + 1))
    n = np.stack([np.zeros_like(a), np.cos(a), np.sin(a)], -1)
    p = n * radius + np.stack([x, 0 * x, 0 * x], -1)
    mesh = _surface(p, n, segments, sides, "tube")
    w1 = np.clip((mesh.positions[:, 0] - (length - blend) / 2) / blend, 0, 1)
    weights = np.stack([1 - w1, w1, 0 * w1, 0 * w1], 1)
    indices = np.tile(np.array([0, 1, 0, 0], np.uint32), (len(w1), 1))
    return Mesh(mesh.positions, mesh.normals, mesh.uvs, mesh.indices, indices, weights, "tube")


def load(path: str | Path) -> Mesh:
    """Reads a Wavefront OBJ file: v, vt, vn and f (polygons are fanned into triangles).

    Missing normals are computed (area-weighted); missing texture coordinates are zero.
    Raises FileNotFoundError, or OSError naming the line of a malformed file.
    """
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"blurlab.scene.mesh.load: no such file: {path}")
    try:
        text = path.read_text()
    except UnicodeDecodeError as error:
        raise OSError(
            f"blurlab.scene.mesh.load: {path} is not a text OBJ file: {bad_byte(error)}"
        ) from None
    v, vt, vn, corners = [], [], [], []
    for number, line in enumerate(text.splitlines(), 1):
        words = line.split("#", 1)[0].split()
        if not words:
            continue
        try:
            if words[0] == "v":
                v.append([float(w) for w in words[1:4]])
            elif words[0] == "vt":
                vt.append([float(words[1]), 1.0 - float(words[2]) if len(words) > 2 else 0.0])
            elif words[0] == "vn":
                vn.append([float(w) for w in words[1:4]])
            elif words[0] == "f":
                face = [_obj_corner(w, len(v), len(vt), len(vn)) for w in words[1:]]
                if len(face) < 3:
                    raise ValueError("a face needs at least 3 corners")
                corners += [
                    c for i in range(1, len(face) - 1) for c in (face[0], face[i], face[i + 1])
                ]
        except (ValueError, IndexError) as error:
            raise OSError(
                f"blurlab.scene.mesh.load: {path}:{number}: {error}: {line.strip()!r}"
            ) from None
    if any(len(p) != 3 for p in v):
        raise OSError(f"blurlab.scene.mesh.load: {path}: a vertex has fewer than 3 coordinates")
    if not corners:
        raise OSError(f"blurlab.scene.mesh.load: {path} has no faces")
    unique, inverse = np.unique(np.array(corners), axis=0, return_inverse=True)
    positions = np.array(v, dtype=np.float64)[unique[:, 0]]
    uvs = (
        np.array(vt)[unique[:, 1]]
        if vt and (unique[:, 1] >= 0).all()
        else np.zeros((len(unique), 2))
    )
    indices = inverse.reshape(-1, 3)
    if vn and (unique[:, 2] >= 0).all():
        normals = np.array(vn, dtype=np.float64)[unique[:, 2]]
    else:
        normals = _smooth_normals(positions, indices)
    norm = np.linalg.norm(normals, axis=1, keepdims=True)
    normals = np.where(norm > 0, normals / np.maximum(norm, 1e-12), [0.0, 1.0, 0.0])
    try:
        return Mesh(positions, normals, uvs, indices, name=path.stem)
    except ValueError as error:  # e.g. "nan" or "1e999" coordinates
        raise OSError(f"blurlab.scene.mesh.load: {path}: {cause(error)}") from None


def _obj_corner(word: str, nv: int, nvt: int, nvn: int) -> tuple[int, int, int]:
    parts = (word.split("/") + ["", ""])[:3]
    out = []
    for part, count in zip(parts, (nv, nvt, nvn), strict=True):
        if part == "":
            out.append(-1)
            continue
        i = int(part)
        i = i - 1 if i > 0 else count + i
        if not 0 <= i < count:
            raise ValueError(f"index {part} refers to no element (there are {count})")
        out.append(i)
    if out[0] < 0:
        raise ValueError("a face corner needs a vertex index")
    return tuple(out)


def _smooth_normals(positions: np.ndarray, indices: np.ndarray) -> np.ndarray:
    a, b, c = (positions[indices[:, i]] for i in range(3))
    face = np.cross(b - a, c - a)  # length = twice the area: area weighting for free
    normals = np.zeros_like(positions)
    for i in range(3):
        np.add.at(normals, indices[:, i], face)
    return normals


def _translation(t) -> np.ndarray:
    m = np.eye(4)
    m[:3, 3] = t
    return m


def rotation_x(angle: float) -> np.ndarray:
    """The 4 x 4 rotation by `angle` radians about the x axis (for Mesh.transformed)."""
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[1, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1.0]])


def _rotation_z(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1.0]])
