"""Scenes: a camera, a directional light, and meshes with materials and motion.

World space is right-handed, y up; the camera looks down its own -z. Everything that moves is
a function of time (``blurlab.scene.motion``); the renderer evaluates it at shutter open, close and
the G-buffer's instant.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..hatching.patterns import Hatching, hatch
from ..io import images as io
from .blur_scales import check_blur_scale
from .mesh import Mesh
from .motion import Motion, Skeleton


def _finite(value, what: str, size: int) -> np.ndarray:
    v = np.asarray(value, dtype=np.float64)
    if v.shape != (size,) or not np.isfinite(v).all():
        raise ValueError(f"blurlab: {what} must be {size} finite numbers, not {value!r}")
    return v


@dataclass
class Camera:
    """A pinhole camera. ``fov_y`` in degrees, in (0, 180); 0 < near < far."""

    position: tuple = (0.0, 0.0, 5.0)
    look_at: tuple = (0.0, 0.0, 0.0)
    up: tuple = (0.0, 1.0, 0.0)
    fov_y: float = 60.0
    near: float = 0.1
    far: float = 100.0
    motion: Motion | None = None  # moves the whole camera rig: world(t) = motion(t) · base

    def __post_init__(self):
        self.position = _finite(self.position, "camera position", 3)
        self.look_at = _finite(self.look_at, "camera look_at", 3)
        self.up = _finite(self.up, "camera up", 3)
        if not (math.isfinite(self.fov_y) and 0.0 < self.fov_y < 180.0):
            raise ValueError(f"blurlab: fov_y must be in (0, 180) degrees, not {self.fov_y}")
        if not (math.isfinite(self.near) and math.isfinite(self.far) and 0 < self.near < self.far):
            raise ValueError(
                f"blurlab: camera needs 0 < near < far, got near={self.near}, far={self.far}"
            )
        forward = self.look_at - self.position
        if np.linalg.norm(forward) == 0:
            raise ValueError("blurlab: camera position and look_at are the same point")
        if np.linalg.norm(np.cross(forward, self.up)) < 1e-9 * np.linalg.norm(forward):
            raise ValueError("blurlab: camera up is parallel to the viewing direction")

    def base(self) -> np.ndarray:
        """Camera-to-world transform without motion: columns right, up, back, position."""
        # Kept with the values it was made from: a reference asks for it three times a
        # sub-frame, and once more for every camera-facing particle (docs/spec.md §20).
        key = (self.position.tobytes(), self.look_at.tobytes(), self.up.tobytes())
        cached = self.__dict__.get("_base")
        if cached is None or cached[0] != key:
            f = self.look_at - self.position
            f /= np.linalg.norm(f)
            r = _cross(f, self.up)
            r /= np.linalg.norm(r)
            u = _cross(r, f)
            m = np.eye(4)
            m[:3, 0], m[:3, 1], m[:3, 2], m[:3, 3] = r, u, -f, self.position
            cached = self.__dict__["_base"] = (key, m)
        return cached[1].copy()

    def world(self, t: float) -> np.ndarray:
        """Camera-to-world transform at time t."""
        base = self.base()
        return base if self.motion is None else _checked(self.motion.transform(t), "camera") @ base

    def view(self, t: float) -> np.ndarray:
        return np.linalg.inv(self.world(t))

    def projection(self, aspect: float) -> np.ndarray:
        """OpenGL perspective projection with y flipped, so that framebuffer row 0 is the top
        of the image (the one place blurlab meets GL's bottom-left origin)."""
        f = 1.0 / math.tan(math.radians(self.fov_y) / 2)
        n, far = self.near, self.far
        return np.array(
            [
                [f / aspect, 0, 0, 0],
                [0, -f, 0, 0],
                [0, 0, (far + n) / (n - far), 2 * far * n / (n - far)],
                [0, 0, -1, 0],
            ]
        )


@dataclass
class DirectionalLight:
    """Light from `direction` (pointing toward the light) plus an ambient term."""

    direction: tuple = (0.4, 1.0, 0.6)
    color: tuple = (1.0, 1.0, 1.0)
    ambient: tuple = (0.15, 0.15, 0.17)

    def __post_init__(self):
        self.direction = _finite(self.direction, "light direction", 3)
        if np.linalg.norm(self.direction) == 0:
            raise ValueError("blurlab: light direction must not be zero")
        self.color = _finite(self.color, "light color", 3)
        self.ambient = _finite(self.ambient, "ambient", 3)


# How a material's alpha is used (docs/spec.md §20).
BLEND_MODES = ("opaque", "mask", "blend", "additive")
TRANSLUCENT_MODES = ("blend", "additive")


def _unit_interval(value, what: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise TypeError(f"blurlab: {what} must be a number in [0, 1], not {value!r}")
    if not (math.isfinite(value) and 0.0 <= value <= 1.0):
        raise ValueError(f"blurlab: {what} must be in [0, 1], not {value}")
    return float(value)


# Translucent fragments a pixel holds (Scene.max_layers): the default, and the most a
# sort in one compute invocation is given (docs/spec.md §20).
DEFAULT_LAYERS = 16
MAX_LAYERS = 64


# The brightest emission a material may have: 10^4 × a white surface, what the HDR scenes need
# (headlights, sparks) with room to spare, and far inside float32.
MAX_EMISSION_STRENGTH = 1.0e4


@dataclass(eq=False)
class Material:
    """Lambert (specular = 0) or Blinn–Phong; `texture` (a path read through OpenImageIO, or an
    array) multiplies `color`. 8-bit textures are taken as sRGB, float ones as linear.
    ``Material.hatching(...)`` makes a hatched one (`hatch`, docs/spec.md §5).

    Emissive surfaces add the radiance `emission` × `emission_strength` (colour in [0, 1] per
    channel, strength in [0, 10^4]) to their shading, unclamped (docs/spec.md §12): headlights,
    neon and sparks in HDR scenes.

    Alpha (docs/spec.md §20) is ``alpha`` × the colour's fourth component × the texture's alpha
    channel. ``blend``: "opaque" ignores it; "mask" keeps the surface where alpha ≥
    ``alpha_cutoff`` and drops it elsewhere; "blend" composites it over what lies behind
    (premultiplied over); "additive" adds alpha × its colour to what lies behind."""

    color: tuple = (0.8, 0.8, 0.8)
    texture: str | Path | np.ndarray | None = None
    specular: float = 0.0
    shininess: float = 32.0
    hatch: object = None  # a blurlab.hatching.Hatching, made by Material.hatching
    emission: tuple = (0.0, 0.0, 0.0)
    emission_strength: float = 0.0
    alpha: float = 1.0
    blend: str = "opaque"
    alpha_cutoff: float = 0.5

    @property
    def translucent(self) -> bool:
        """Whether the surface is drawn into the translucent layer (blend or additive)."""
        return self.blend in TRANSLUCENT_MODES

    @classmethod
    def hatching(
        cls,
        scheme: str = "threshold",
        tam=None,
        scale: float = 1.0,
        color=(1.0, 1.0, 1.0),
        texture=None,
        specular: float = 0.0,
        shininess: float = 32.0,
    ) -> Material:
        """Hatching with a tonal art map instead of shading (docs/spec.md §5): color · (1 − ink).

        ``scheme``: "six_way" (per-vertex weights of the two nearest of 6 tones, Praun et al.
        2001) or "threshold" (a per-pixel threshold test, Webb et al. 2002). ``tam``: a
        ``bl.tam.TAM``, a (6, S, S) ink array, a folder written by ``TAM.write``, or None
        for ``blurlab.hatching.tam.default_tam()``.
        ``scale``: TAM repeats per unit of texture coordinate, > 0. The tone comes from the
        scene's light: Lambert, or Blinn–Phong when ``specular`` > 0.
        """
        return cls(color, texture, specular, shininess, hatch(scheme, tam, scale))

    def __post_init__(self):
        c = np.asarray(self.color, dtype=np.float64)
        if c.shape == (3,):
            c = np.append(c, 1.0)
        self.color = _finite(c, "material color", 4)
        if not (math.isfinite(self.specular) and self.specular >= 0):
            raise ValueError(f"blurlab: specular must be >= 0, not {self.specular}")
        if not (math.isfinite(self.shininess) and self.shininess > 0):
            raise ValueError(f"blurlab: shininess must be > 0, not {self.shininess}")
        if isinstance(self.texture, (str, Path)) and not Path(self.texture).is_file():
            raise FileNotFoundError(f"blurlab: material texture not found: {self.texture}")
        self.emission = _finite(self.emission, "material emission", 3)
        if not ((self.emission >= 0) & (self.emission <= 1)).all():
            raise ValueError(
                f"blurlab: emission is a colour in [0, 1] per channel, not {self.emission}; "
                "set the brightness with emission_strength"
            )
        strength = self.emission_strength
        if isinstance(strength, bool) or not isinstance(strength, (int, float)):
            raise TypeError(f"blurlab: emission_strength must be a number, not {strength!r}")
        if not (math.isfinite(strength) and 0 <= strength <= MAX_EMISSION_STRENGTH):
            raise ValueError(
                f"blurlab: emission_strength must be in [0, {MAX_EMISSION_STRENGTH:g}], "
                f"not {strength}"
            )
        self.alpha = _unit_interval(self.alpha, "material alpha")
        self.alpha_cutoff = _unit_interval(self.alpha_cutoff, "material alpha_cutoff")
        if not isinstance(self.blend, str) or self.blend not in BLEND_MODES:
            raise ValueError(
                f"blurlab: material blend must be one of {BLEND_MODES}, not {self.blend!r}"
            )
        if self.hatch is not None:
            if not isinstance(self.hatch, Hatching):
                raise ValueError(
                    "blurlab: material hatch must come from Material.hatching(...), not "
                    f"{type(self.hatch).__name__}"
                )

    @property
    def radiance(self) -> np.ndarray:
        """The emitted linear RGB radiance, emission × emission_strength."""
        return self.emission * float(self.emission_strength)

    def texture_rgba(self) -> np.ndarray | None:
        """The texture as (H, W, 4) linear float16, or None."""
        if self.texture is None:
            return None
        image = io.read(self.texture) if isinstance(self.texture, (str, Path)) else self.texture
        image = np.asarray(image)
        if image.ndim == 2:
            image = image[..., None]
        if image.ndim != 3 or image.shape[2] not in (1, 3, 4) or image.size == 0:
            raise ValueError(f"blurlab: texture of shape {image.shape} is not (H, W, 1|3|4)")
        linear = io.srgb_to_linear(image / 255.0) if image.dtype == np.uint8 else image
        if image.dtype == np.uint8 and image.shape[2] == 4:
            linear[..., 3] = image[..., 3] / 255.0  # alpha is not sRGB-encoded
        rgba = np.ones(image.shape[:2] + (4,))
        rgba[..., :3] = linear[..., :3] if image.shape[2] >= 3 else linear[..., :1]
        if image.shape[2] == 4:
            rgba[..., 3] = linear[..., 3]
        if not np.isfinite(rgba).all():
            raise ValueError("blurlab: texture has NaN or inf values")
        return rgba.astype(np.float16)


@dataclass(eq=False)
class SceneObject:
    mesh: Mesh
    material: Material
    motion: Motion | None
    skeleton: Skeleton | None
    name: str
    # How much of its motion the shutter blurs, in [0, 1]: 0 renders sharp (docs/spec.md §12.1).
    motion_blur: float = 1.0

    def model(self, t: float) -> np.ndarray:
        return np.eye(4) if self.motion is None else _checked(self.motion.transform(t), self.name)


@dataclass
class Scene:
    """What the renderer draws. `shutter` is the default shutter interval in seconds."""

    camera: Camera = field(default_factory=Camera)
    light: DirectionalLight = field(default_factory=DirectionalLight)
    background: tuple = (0.05, 0.05, 0.07, 1.0)
    shutter: tuple = (0.0, 1.0 / 60.0)
    name: str = "scene"
    objects: list[SceneObject] = field(default_factory=list)
    source: Path | None = None  # the file a scene was loaded from (blurlab.scene.gltf), for reports
    # How much of the camera's motion the shutter blurs, in [0, 1] (docs/spec.md §12.1).
    camera_motion_blur: float = 1.0
    # Translucent fragments kept per pixel in front of the opaque surface (docs/spec.md §20);
    # more raise OverflowError, never drop silently.
    max_layers: int = DEFAULT_LAYERS

    @property
    def hdr(self) -> bool:
        """Whether some material emits more than 1 in a channel: then the image holds values
        that clipping to [0, 1] would lose, and sweeps add the HDR metrics (docs/hdr.md)."""
        return any(float(obj.material.radiance.max()) > 1.0 for obj in self.objects)

    @property
    def translucent(self) -> bool:
        """Whether some object is drawn into the translucent layer (docs/spec.md §20)."""
        return any(obj.material.translucent for obj in self.objects)

    def __post_init__(self):
        check_blur_scale(self.camera_motion_blur, "camera_motion_blur")
        layers = self.max_layers
        if isinstance(layers, bool) or not isinstance(layers, int) or not 1 <= layers <= MAX_LAYERS:
            raise ValueError(
                f"blurlab: scene max_layers must be an integer in 1..{MAX_LAYERS}, not {layers!r}"
            )
        b = np.asarray(self.background, dtype=np.float64)
        self.background = _finite(np.append(b, 1.0) if b.shape == (3,) else b, "background", 4)

    def add(
        self,
        mesh: Mesh,
        material: Material | None = None,
        motion: Motion | None = None,
        skeleton: Skeleton | None = None,
        name: str | None = None,
        motion_blur: float = 1.0,
    ) -> SceneObject:
        """Adds an object; its object id in the G-buffer is its index in `objects`.
        ``motion_blur`` in [0, 1] scales how much of its motion is blurred (docs/spec.md
        §12.1): 0 draws it sharp at the shutter's centre, as engines draw a first-person
        weapon."""
        if not isinstance(mesh, Mesh):
            raise TypeError(f"blurlab: scene.add needs a blurlab Mesh, not {type(mesh).__name__}")
        if mesh.skinned != (skeleton is not None):
            raise ValueError("blurlab: a skinned mesh needs a skeleton, and only a skinned one")
        if skeleton is not None and int(mesh.bone_indices.max()) >= len(skeleton.bones):
            raise ValueError(
                f"blurlab: mesh uses bone {int(mesh.bone_indices.max())}, "
                f"the skeleton has {len(skeleton.bones)}"
            )
        name = name or mesh.name
        obj = SceneObject(mesh, material or Material(), motion, skeleton, name, motion_blur)
        check_blur_scale(motion_blur, f"motion_blur of {name}")
        self.objects.append(obj)
        return obj


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """np.cross of two 3-vectors, in the same IEEE operations (each product rounded, then the
    difference) at about a twentieth of its cost (0.7 against 17 µs on a 2-core machine)."""
    a0, a1, a2 = a.tolist()
    b0, b1, b2 = b.tolist()
    return np.array([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0])


def _checked(matrix: np.ndarray, what: str) -> np.ndarray:
    m = np.asarray(matrix, dtype=np.float64)
    if m.shape != (4, 4) or not np.isfinite(m).all():
        raise ValueError(f"blurlab: the motion of {what} gave a non-finite transform")
    return m
