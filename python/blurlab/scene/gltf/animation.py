"""glTF animation: the node hierarchy, its channels sampled at any time (LINEAR, STEP and
CUBICSPLINE keys), the motion of a node, and where the default shutter opens (docs/spec.md §15).
Scene time is the animation's time in seconds; the motion of every node is its animation sampled
at t, so any shutter, instant or reference works on it unchanged."""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from ..motion import Motion, compose, slerp
from .accessors import accessor
from .document import GltfFile

MAX_NODES = 1 << 16
DEFAULT_SHUTTER_S = 1.0 / 60.0
_TRS_PATHS = ("translation", "rotation", "scale")


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


@dataclass
class Channel:
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


class Nodes:
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


def node_hierarchy(file: GltfFile, animation) -> tuple[Nodes, list[int]]:
    doc = file.doc
    count = len(doc.nodes or [])
    if count > MAX_NODES:
        file.fail(f"{count} nodes; at most {MAX_NODES} are read")
    scenes = doc.scenes or []
    if scenes:
        chosen = file.index(doc.scene if doc.scene is not None else 0, len(scenes), "scene")
        roots = [file.index(r, count, "scene root node") for r in scenes[chosen].nodes or []]
    else:
        roots = list(range(count))
    parents = [-1] * count
    for i, node in enumerate(doc.nodes or []):
        for child in node.children or []:
            c = file.index(child, count, f"node {i} child")
            if parents[c] != -1 or c == i:
                file.fail(f"node {c} has more than one parent")
            parents[c] = i
    order, seen, stack = [], set(), [r for r in reversed(roots) if parents[r] == -1]
    while stack:  # parents before children; a cycle never reaches a root and is left out
        i = stack.pop()
        if i in seen:
            file.fail(f"node {i} is reached twice (a cycle in the hierarchy)")
        seen.add(i)
        order.append(i)
        stack.extend(reversed([int(c) for c in doc.nodes[i].children or []]))
    rest = [_rest(file, i, node) for i, node in enumerate(doc.nodes or [])]
    return Nodes(rest, parents, order, animation_channels(file, animation, count, rest)), order


def _rest(file: GltfFile, i: int, node):
    if node.matrix is not None and list(node.matrix) != list(np.eye(4).ravel()):
        m = file.floats(node.matrix, f"node {i} matrix", 16)
        return m.reshape(4, 4).T  # glTF matrices are column-major
    return {
        "translation": file.floats(node.translation or (0, 0, 0), f"node {i} translation", 3),
        "rotation": file.floats(node.rotation or (0, 0, 0, 1), f"node {i} rotation", 4),
        "scale": file.floats(node.scale or (1, 1, 1), f"node {i} scale", 3),
    }


ALL_ANIMATIONS = "all"


def check_animation_choice(animation):
    """`animation` as load() takes it, checked before the file is read: None, "all", an index,
    a name, or a non-empty list of indices and names without repeats (docs/spec.md §15.1)."""
    allowed = 'None, "all", an index, a name, or a list of indices and names'
    items = list(animation) if isinstance(animation, (list, tuple)) else [animation]
    if isinstance(animation, (list, tuple)) and not items:
        raise ValueError(f"blurlab.scene.gltf: animation is an empty list; allowed: {allowed}")
    for item in items:
        if animation is None:
            continue
        if isinstance(item, bool) or not isinstance(item, (int, np.integer, str)):
            raise TypeError(
                f"blurlab.scene.gltf: animation {item!r} is not allowed; allowed: {allowed}"
            )
        if isinstance(item, (int, np.integer)) and item < 0:
            raise ValueError(f"blurlab.scene.gltf: animation index {item} is negative")
    if isinstance(animation, (list, tuple)) and ALL_ANIMATIONS in items:
        raise ValueError(f'blurlab.scene.gltf: animation list {items!r}: "all" stands alone')
    keys = [int(i) if isinstance(i, (int, np.integer)) else i for i in items]
    if len(set(keys)) != len(keys):
        raise ValueError(f"blurlab.scene.gltf: animation list {list(items)!r} names one twice")


def describe_animation(file: GltfFile, index: int) -> str:
    name = (file.doc.animations or [])[index].name
    return f"animation {index}" + (f" {name!r}" if isinstance(name, str) and name else "")


def chosen_animations(file: GltfFile, animation) -> list[int]:
    """The indices of the file's animations that `animation` picks, in the order asked for
    (docs/spec.md §15.1)."""
    animations = file.doc.animations or []
    if animation is None:
        chosen = []
    elif animation == ALL_ANIMATIONS:
        chosen = list(range(len(animations)))
    else:
        items = animation if isinstance(animation, (list, tuple)) else [animation]
        chosen = [_animation_index(file, item) for item in items]
        if len(set(chosen)) != len(chosen):
            file.fail(f"animation {list(items)!r} picks one animation twice")
    return chosen


def _animation_index(file: GltfFile, item) -> int:
    animations = file.doc.animations or []
    if not isinstance(item, str):
        if not animations:
            file.fail(f"animation {item} asked for; the file has none")
        return file.index(int(item), len(animations), "animation")
    matches = [i for i, entry in enumerate(animations) if entry.name == item]
    if len(matches) != 1:
        names = [entry.name for entry in animations]
        how = "no animation" if not matches else f"{len(matches)} animations"
        file.fail(f"{how} named {item!r}; the file's animations are {names}")
    return matches[0]


def animation_channels(
    file: GltfFile, animation, node_count: int, rest
) -> dict[int, list[Channel]]:
    """The channels of every chosen animation by node. Two of them driving the same (node,
    property) is refused, naming both: which one plays is the caller's choice."""
    out: dict[int, list[Channel]] = {}
    driven_by: dict[tuple[int, str], int] = {}
    chosen_ones = chosen_animations(file, animation)
    for a in chosen_ones:
        chosen = file.doc.animations[a]
        samplers = chosen.samplers or []
        for c, channel in enumerate(chosen.channels or []):
            target = channel.target
            if target is None or target.node is None:
                continue  # a channel without a node may be ignored (glTF 2.0, 3.11)
            node = file.index(target.node, node_count, f"animation channel {c} node")
            if target.path == "weights":
                file.fail("it animates morph target weights; morph targets are not supported")
            if target.path not in _TRS_PATHS:
                file.fail(f"animation channel {c} targets {target.path!r}")
            if isinstance(rest[node], np.ndarray):
                file.fail(f"node {node} has a matrix and is animated (glTF forbids that)")
            other = driven_by.setdefault((node, target.path), a)
            if other == a and any(ch.path == target.path for ch in out.get(node, ())):
                file.fail(f"{describe_animation(file, a)} drives node {node} {target.path} twice")
            if other != a:
                file.fail(
                    f"{describe_animation(file, other)} and {describe_animation(file, a)} both "
                    f"drive the {target.path} of node {node} ({file.doc.nodes[node].name!r}); "
                    "choose which to play with animation= (an index, a name or a list)"
                )
            sampler = samplers[file.index(channel.sampler, len(samplers), f"channel {c} sampler")]
            out.setdefault(node, []).append(_channel(file, sampler, target.path, c))
    _warn_of_those_left_out(file, chosen_ones)
    return out


def _warn_of_those_left_out(file: GltfFile, chosen: list[int]):
    count = len(file.doc.animations or [])
    left_out = [describe_animation(file, i) for i in range(count) if i not in chosen]
    if left_out:
        played = ", ".join(describe_animation(file, i) for i in chosen) or "none (the rest pose)"
        warnings.warn(
            f"blurlab.scene.gltf: {file.path.name}: plays {played}; left out {', '.join(left_out)}",
            stacklevel=6,  # the caller of blurlab.scene.gltf.load
        )


def _channel(file: GltfFile, sampler, path: str, c: int) -> Channel:
    interpolation = sampler.interpolation or "LINEAR"
    if interpolation not in ("LINEAR", "STEP", "CUBICSPLINE"):
        file.fail(f"animation channel {c} has interpolation {interpolation!r}")
    times = accessor(file, sampler.input, f"channel {c} input", ("SCALAR",))[:, 0]
    if np.any(np.diff(times) <= 0):
        file.fail(f"animation channel {c} has key times that do not increase")
    width = 4 if path == "rotation" else 3
    values = accessor(file, sampler.output, f"channel {c} output", (f"VEC{width}",))
    per_key = 3 if interpolation == "CUBICSPLINE" else 1
    if len(values) != per_key * len(times):
        file.fail(f"animation channel {c} has {len(values)} values for {len(times)} keys")
    if per_key == 3:
        values = values.reshape(len(times), 3, width)
    return Channel(path, times, values, interpolation)


# Meshes, skins, materials.


def busiest_time(nodes: Nodes, samples: int = 64) -> float:
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
