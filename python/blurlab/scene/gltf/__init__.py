"""glTF 2.0 files as blurlab scenes (docs/spec.md §15).

The file is parsed by pygltflib; everything it describes is then checked here before use,
because a file from outside is untrusted: indices and ranges are bounded, buffers come only
from the file itself, a data: URI or a file inside the file's own folder, and nothing is
downloaded. Scene time is the animation's time in seconds; the motion of every node is its
animation sampled at t, so any shutter, instant or reference works on it unchanged.

The package reads a file in layers: document (the container, URIs and the checks of untrusted
values), accessors, animation (nodes, channels, the default shutter), skins, meshes, materials,
and build, which assembles the Scene and its camera.
"""

from __future__ import annotations

from pathlib import Path

from ...errors import cause
from ..model import Camera, Scene
from .accessors import MAX_ACCESSOR_VALUES
from .animation import (
    ALL_ANIMATIONS,
    DEFAULT_SHUTTER_S,
    MAX_NODES,
    CameraNodeMotion,
    NodeMotion,
    check_animation_choice,
)
from .build import build_scene
from .document import MAX_FILE_BYTES, MAX_JSON_VALUES, GltfError, GltfFile
from .materials import MAX_IMAGE_PIXELS
from .meshes import MAX_VERTICES
from .skins import JointSkin

__all__ = [
    "ALL_ANIMATIONS",
    "DEFAULT_SHUTTER_S",
    "MAX_ACCESSOR_VALUES",
    "MAX_FILE_BYTES",
    "MAX_IMAGE_PIXELS",
    "MAX_JSON_VALUES",
    "MAX_NODES",
    "MAX_VERTICES",
    "CameraNodeMotion",
    "GltfError",
    "JointSkin",
    "NodeMotion",
    "load",
]


def load(
    path,
    animation: int | str | list | None = ALL_ANIMATIONS,
    camera: int | Camera | None = None,
    size_hint=None,
    shutter=None,
) -> Scene:
    """A `bl.Scene` from a .gltf or .glb file (docs/spec.md §15).

    ``animation``: which of the file's animations move the scene (docs/spec.md §15.1): "all"
    (every one; two that drive the same property of a node are refused, naming both), an index,
    a name, a list of indices and names, or None for the rest pose. A warning names the file's
    animations that are left out.
    ``camera``: None (the file's first camera, or one framing the scene's bounds when the file
    has none), the index of one of the file's cameras, or a `bl.Camera`.
    ``size_hint``: (W, H) the scene will mostly be rendered at; the framing camera fits the
    bounds into that aspect ratio. ``shutter``: (t0, t1) in animation seconds; by default
    1/60 s opening where the animation moves fastest (docs/spec.md §15).
    """
    path = Path(path)
    check_animation_choice(animation)
    try:
        return build_scene(GltfFile(path), animation, camera, size_hint, shutter)
    except GltfError:
        raise
    except (ValueError, TypeError, KeyError, IndexError, AttributeError, OverflowError) as error:
        # What slipped past the checks below still names the file and never escapes as a crash.
        raise GltfError(
            f"blurlab.scene.gltf: {path.name}: malformed file ({cause(error)})"
        ) from None
