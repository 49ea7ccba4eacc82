"""blurlab: real-time motion-blur methods run headless on the GPU, measured from Python."""

from . import hatching, io, mesh, metrics, plots, reference, scenes, tam
from ._core import GLError, ShaderError
from .accumulation import Reference, reference_samples_needed
from .cluster import local_cluster
from .context import ComputeProgram, Context, PendingDownload, Texture, Timing
from .frame import MOTION_FORMATS, Frame
from .mesh import Mesh
from .methods import (
    BlurResult,
    blur,
    blur_steps,
    method,
    methods,
    render_and_blur,
    render_steps,
)
from .methods import method_instant as methods_instant
from .motion import Bone, Keyframe, Motion, Skeleton, quaternion
from .scene import Camera, DirectionalLight, Material, Scene
from .sweep import sweep  # the function; the module stays importable as blurlab.sweep

__version__ = "0.1.0"

__all__ = [
    "MOTION_FORMATS",
    "BlurResult",
    "Bone",
    "Camera",
    "ComputeProgram",
    "Context",
    "DirectionalLight",
    "Frame",
    "GLError",
    "Keyframe",
    "Material",
    "Mesh",
    "Motion",
    "PendingDownload",
    "Reference",
    "Scene",
    "ShaderError",
    "Skeleton",
    "Texture",
    "Timing",
    "blur",
    "blur_steps",
    "hatching",
    "io",
    "local_cluster",
    "mesh",
    "method",
    "methods",
    "methods_instant",
    "quaternion",
    "reference",
    "reference_samples_needed",
    "render_and_blur",
    "render_steps",
    "metrics",
    "plots",
    "scenes",
    "sweep",
    "tam",
]
