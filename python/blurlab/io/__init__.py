"""Files in and out: images (EXR, PNG; images.py, whose functions this package offers as
``bl.io.read``, ``bl.io.write``, ...), engine captures (capture.py) and video (video.py). Files
from outside are untrusted: bounded reads, no paths outside the one given."""

from .images import (
    EIGHT_BIT_FORMATS,
    FLOAT_FORMATS,
    MAX_READ_VALUES,
    linear_to_srgb,
    publish,
    read,
    read_channels,
    srgb8,
    srgb_to_linear,
    write,
    write_text,
)

__all__ = [
    "EIGHT_BIT_FORMATS",
    "FLOAT_FORMATS",
    "MAX_READ_VALUES",
    "linear_to_srgb",
    "publish",
    "read",
    "read_channels",
    "srgb8",
    "srgb_to_linear",
    "write",
    "write_text",
]
