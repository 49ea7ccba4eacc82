"""blurlab: real-time motion-blur methods run headless on the GPU, measured from Python."""

from . import blender, hatching, io, metrics, twins
from ._core import ContextLost, GLError, ShaderError, StaleReadback
from .core.context import Context
from .core.frame import MOTION_FORMATS, Frame
from .core.gl import ComputeProgram, PendingDownload, Texture, Timing
from .core.references import Reference, reference_samples_needed
from .hatching import tam
from .io import capture
from .methods import (
    BlurResult,
    blur,
    blur_steps,
    load_methods,
    method,
    method_instant,
    methods,
    render_and_blur,
    render_steps,
    unload_methods,
)
from .scene import gltf, mesh, scenes
from .scene.blur_scales import CameraHeld
from .scene.mesh import Mesh
from .scene.model import Camera, DirectionalLight, Material, Scene
from .scene.motion import Bone, Keyframe, Motion, Skeleton, quaternion
from .scene.particles import Particle, particles
from .scene.shutters import shutter
from .sizes import DEFAULT_SIZE

# The studies sit above the core (the core never imports them); the package offers the most
# used ones by name.
from .studies import failures, plots  # noqa: E402
from .studies.cluster_devices import local_cluster  # noqa: E402
from .studies.recommend import recommend, recommend_set  # noqa: E402
from .studies.scheduler import scheduler  # noqa: E402
from .studies.sweep import sweep  # noqa: E402
from .temporal import taa
from .temporal.sequences import Sequence, SequenceRun, frame_scenes, sequence
from .version import __version__ as __version__  # noqa: E402

__all__ = [
    "DEFAULT_SIZE",
    "MOTION_FORMATS",
    "BlurResult",
    "Bone",
    "Camera",
    "CameraHeld",
    "ComputeProgram",
    "Context",
    "DirectionalLight",
    "Frame",
    "ContextLost",
    "GLError",
    "Keyframe",
    "Material",
    "Mesh",
    "Motion",
    "Particle",
    "PendingDownload",
    "Reference",
    "Scene",
    "Sequence",
    "SequenceRun",
    "ShaderError",
    "StaleReadback",
    "Skeleton",
    "Texture",
    "Timing",
    "blur",
    "blender",
    "blur_steps",
    "capture",
    "gltf",
    "hatching",
    "io",
    "local_cluster",
    "mesh",
    "method",
    "method_instant",
    "load_methods",
    "unload_methods",
    "particles",
    "methods",
    "quaternion",
    "recommend",
    "recommend_set",
    "reference_samples_needed",
    "render_and_blur",
    "scheduler",
    "render_steps",
    "shutter",
    "metrics",
    "failures",
    "plots",
    "scenes",
    "sequence",
    "frame_scenes",
    "sweep",
    "taa",
    "tam",
    "twins",
]
