"""blurlab: real-time motion-blur methods run headless on the GPU, measured from Python."""

from . import io, reference
from ._core import GLError, ShaderError
from .context import ComputeProgram, Context, PendingDownload, Texture, Timing

__version__ = "0.1.0"

__all__ = [
    "ComputeProgram",
    "Context",
    "GLError",
    "PendingDownload",
    "ShaderError",
    "Texture",
    "Timing",
    "io",
    "reference",
]
