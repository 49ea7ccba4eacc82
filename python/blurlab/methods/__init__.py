"""Motion-blur methods by name: ``bl.methods()`` lists them, ``bl.blur(ctx, frame, name, ...)``
runs one. The core is ``core`` (blur, steps) with ``params``, ``registry`` and ``passes``; the
families' shared code (tile filters, tile lists, layers) is a module each. Every method is a
folder, ``<name>/`` here for the built-in ones (method.py, its shaders, twin.py, spec.md, its
tests), found by ``load_builtin_methods``; a user's folder is loaded by ``load_methods`` or an
entry point (folders.py, docs/spec.md §25, docs/adding_a_method.md).
"""

from .core import (
    KINDS,
    BlurResult,
    Method,
    Param,
    Pass,
    blur,
    blur_steps,
    check_param,
    check_steps,
    method,
    method_instant,
    methods,
    register,
    render_and_blur,
    render_steps,
)

# folders: method folders, loaded after the built-ins (and installed packages' on first use).
from .folders import (
    Declaration,
    MethodFolderError,
    load_builtin_methods,
    load_methods,
    unload_methods,
)
from .registry import example_method, translucent_layer_method

load_builtin_methods()

__all__ = [
    "KINDS",
    "BlurResult",
    "Declaration",
    "Method",
    "MethodFolderError",
    "Param",
    "Pass",
    "blur",
    "blur_steps",
    "check_param",
    "check_steps",
    "example_method",
    "load_methods",
    "method",
    "method_instant",
    "methods",
    "register",
    "render_and_blur",
    "render_steps",
    "translucent_layer_method",
    "unload_methods",
]
