"""Motion-blur methods by name: ``bl.methods()`` lists them, ``bl.blur(ctx, frame, name, ...)``
runs one. The core is ``core`` (blur, steps) with ``params``, ``registry`` and ``passes``; each
method or family is a module of its own that registers itself on import, below. A new method
is a new module here, its shader, its NumPy twin and its test; a method from outside is a
method folder, loaded by ``load_methods`` or an entry point (folders.py,
docs/adding_a_method.md).
"""

# Each module registers its methods on import; the order here is the registry's, which is the
# order of rows in sweeps, studies and the failure suite.
# isort: off
from . import mcguire2012, guertin2014, urho3d, gathers, camera_only, trail  # noqa: F401
from . import accumulation, stochastic  # noqa: F401
from . import gather_gaussian  # noqa: F401
from . import eevee, unity, hdrp, jimenez2014  # noqa: F401

# isort: on
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
