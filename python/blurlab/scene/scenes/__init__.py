"""Built-in scenes. Each is a few lines; motion is in units per second, shutter 1/60 s.

``names()`` lists them, ``get(name)`` builds one; ``get`` and ``gltf`` also load scene files.
"""

from __future__ import annotations

import os
from pathlib import Path

from .. import gltf as gltf_files
from ..model import Scene
from .benchmark import fps_weapon, mostly_still, tracked_car
from .builtin import fan, skinned_arm, teapot_pass, textured_spin, vehicle
from .failures import (
    camera_yaw,
    crossed_motions,
    crossing,
    edge_exit,
    fast_fan,
    long_motion,
    moire,
    near_plane,
    occluder,
    racing_road,
    reverse_near_plane,
    subpixel,
    thin_bar,
)
from .features import FEATURES as FEATURES
from .features import features as features
from .features import frame_arrays as frame_arrays
from .features import gbuffer_digest as gbuffer_digest
from .features import with_features as with_features
from .hdr import neon_pan, night_street, sparks, spinning_ring
from .parts import checker as checker
from .parts import rainbow as rainbow
from .random import check_seed as check_seed
from .random import parse_name as parse_random_name
from .random import random as random
from .random import random_name as random_name
from .transparency import (
    car_behind_window,
    foliage_spin,
    moving_glass,
    smoke_pan,
    sparks_over_mover,
)
from .transparency import (
    leaves as leaves,
)
from .transparency import (
    streaked_glass as streaked_glass,
)

_SCENES = {f.__name__: f for f in (teapot_pass, fan, vehicle, textured_spin, skinned_arm)}
_BENCHMARKS = {f.__name__: f for f in (mostly_still, fps_weapon, tracked_car)}
_HDR = {f.__name__: f for f in (night_street, sparks, spinning_ring, neon_pan)}
_FAILURES = {
    f.__name__: f
    for f in (
        thin_bar,
        near_plane,
        crossing,
        crossed_motions,
        long_motion,
        edge_exit,
        subpixel,
        camera_yaw,
        occluder,
        moire,
        fast_fan,
        racing_road,
        reverse_near_plane,
        tracked_car,
    )
}


_TRANSPARENCY = {
    f.__name__: f
    for f in (car_behind_window, moving_glass, sparks_over_mover, smoke_pan, foliage_spin)
}


_TAGGED = {
    "failure": _FAILURES,
    "benchmark": _BENCHMARKS,
    "hdr": _HDR,
    "transparency": _TRANSPARENCY,
}
TAGS = tuple(_TAGGED)


def names(tag: str | None = None) -> list[str]:
    """The built-in scenes; `tag="failure"` lists the failure cases instead, `"benchmark"`
    the scenes built for one benchmark, `"hdr"` the scenes lit by emission far above 1,
    `"transparency"` the translucent, additive and masked failure cases (docs/transparency.md)."""
    if tag is None:
        return list(_SCENES)
    if tag not in _TAGGED:
        raise ValueError(f"blurlab: scene tag must be None or one of {TAGS}, not {tag!r}")
    return list(_TAGGED[tag])


def _builder(name: str):
    for registry in (_SCENES, *_TAGGED.values()):
        if name in registry:
            return registry[name]
    everything = names() + [n for tag in TAGS for n in names(tag)]
    raise ValueError(
        f"blurlab: no built-in scene {name!r}; there are {everything}, 'random:SEED', "
        "or give a .gltf/.glb path"
    )


def describe(name: str) -> str:
    """One sentence on what the built-in scene `name` shows (its docstring's first line)."""
    return " ".join(_builder(name).__doc__.split("\n\n")[0].split())


FILE_SUFFIXES = (".gltf", ".glb")


def gltf(
    path,
    animation: int | str | list | None = gltf_files.ALL_ANIMATIONS,
    camera=None,
    size_hint=None,
    shutter=None,
) -> Scene:
    """A scene from a glTF 2.0 file (.gltf or .glb), animated: `blurlab.scene.gltf.load`."""
    return gltf_files.load(path, animation, camera, size_hint, shutter)


def is_file(item) -> bool:
    """Whether `item` names a scene file rather than a built-in scene."""
    return isinstance(item, os.PathLike) or str(item).lower().endswith(FILE_SUFFIXES)


def label(item) -> str:
    """How tables and reports name a scene: a built-in name, or a file's name."""
    return Path(item).name if is_file(item) else str(item)


def get(name) -> Scene:
    """A built-in scene by name, a random scene with the default ranges by 'random:SEED'
    (docs/spec.md §22), or a scene file (.gltf, .glb) by path."""
    if is_file(name):
        return gltf(name)
    seed = parse_random_name(name)
    return _builder(name)() if seed is None else random(seed)
