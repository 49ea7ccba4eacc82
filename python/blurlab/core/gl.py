"""The GL context and what lives in it: textures, compute programs, timers.

Every array that crosses to the GPU has shape (H, W) or (H, W, C), C in 1..4, row 0 at the top
of the image, dtype uint8, float16 or float32 (docs/architecture.md "Arrays"), or uint32 for
integer textures that passes update atomically (sampled as usampler2D, bound as r32ui images).
"""

from __future__ import annotations

import math
import weakref
from collections.abc import Mapping, Sequence
from contextlib import contextmanager
from numbers import Integral
from pathlib import Path

import numpy as np

from .. import _core
from .._paths import shader_dir as _default_shader_dir
from .timers import DeferredTimers, LazyTimers, Timing

TEXTURE_DTYPES = ("uint8", "float16", "float32", "uint32")
DEVICE_MODES = ("auto", "gpu", "software")


def _check_array(array, what: str = "array") -> np.ndarray:
    """Validates an image array and returns it C-contiguous; raises naming what is allowed."""
    if not isinstance(array, np.ndarray):
        raise TypeError(
            f"blurlab: {what} must be a numpy.ndarray of shape (H, W) or (H, W, C), "
            f"not {type(array).__name__}"
        )
    if array.dtype.name not in TEXTURE_DTYPES:
        raise TypeError(
            f"blurlab: {what} has dtype {array.dtype}; allowed dtypes are "
            + ", ".join(TEXTURE_DTYPES)
        )
    if array.ndim not in (2, 3) or (array.ndim == 3 and not 1 <= array.shape[2] <= 4):
        raise ValueError(
            f"blurlab: {what} has shape {array.shape}; allowed shapes are (H, W) and "
            "(H, W, C) with C in 1..4"
        )
    if array.size == 0:
        raise ValueError(f"blurlab: {what} of shape {array.shape} is empty")
    if not array.dtype.isnative:  # e.g. big-endian '>f4': GL reads native bytes
        array = array.astype(array.dtype.newbyteorder("="))
    return np.ascontiguousarray(array)


class Texture:
    """A 2D texture on the GPU. ``download()`` returns the array it was made from, bit for bit."""

    def __init__(self, context: GLContext, core: _core.Texture, shape: tuple[int, ...]):
        self.context = context
        self._core = core
        self.shape = shape
        self.dtype = np.dtype(core.dtype)
        self.dtype_name = self.dtype.name  # "float32": the pool's key, read on every recycle

    @property
    def native(self) -> _core.Texture:
        """The C++ texture, for blurlab's own passes (blurlab._core)."""
        return self._core

    @property
    def glo(self) -> int:
        """The GL texture name, for moderngl's ``external_texture`` and other GL code."""
        return self._core.glo

    @property
    def width(self) -> int:
        return self._core.width

    @property
    def height(self) -> int:
        return self._core.height

    @property
    def channels(self) -> int:
        return self._core.channels

    def upload(self, array: np.ndarray) -> None:
        """Replaces the contents with ``array``, which must have this texture's shape and dtype."""
        array = _check_array(array)
        if array.shape != self.shape or array.dtype != self.dtype:
            raise ValueError(
                f"blurlab: upload of {array.dtype}{array.shape} into a texture of "
                f"{self.dtype}{self.shape}; shapes and dtypes must match"
            )
        self._core.upload(array.reshape(self.height, self.width, self.channels))

    def download(self) -> np.ndarray:
        """The texture as a new array of shape ``self.shape``."""
        return self._core.download().reshape(self.shape)

    def download_async(self) -> PendingDownload:
        """Queues the download and returns at once; ``.result()`` waits for it."""
        return PendingDownload(self._core.download_async(), self.shape, self.dtype)

    def clear(self) -> None:
        self._core.clear()

    def __repr__(self) -> str:
        return f"<blurlab.Texture {self.dtype}{self.shape} glo={self.glo}>"


class PendingDownload:
    """A download in flight (a pixel-pack buffer and a fence)."""

    def __init__(self, core: _core.PendingDownload, shape: tuple[int, ...], dtype: np.dtype):
        self._core = core
        self._shape = shape
        self._dtype = dtype

    def done(self) -> bool:
        """True once the GPU has finished the copy; never blocks."""
        return self._core.done()

    def result(self) -> np.ndarray:
        """Waits for the copy and returns the image as a new array (any number of times), read
        from the pixel-pack buffer through GL (glGetNamedBufferSubData). On the H100 the copy
        once differed from ``Texture.download()`` right after a long translucent reference
        (docs/foundation.md); where every byte counts, use ``download()``."""
        return self._core.result_bytes().view(self._dtype).reshape(self._shape)


class ComputeProgram:
    """A compute shader loaded from the shader folder (or an absolute path)."""

    def __init__(self, core: _core.Program):
        self._core = core

    @property
    def local_size(self) -> tuple[int, int, int]:
        return tuple(self._core.local_size)

    @property
    def uniforms(self) -> dict[str, int]:
        return dict(self._core.uniforms)

    def run(
        self,
        size: tuple[int, int],
        images: Sequence[Texture | tuple[Texture, str]] = (),
        textures: Sequence[Texture] = (),
        uniforms: Mapping[str, float | Sequence[float]] | None = None,
    ) -> None:
        """Dispatches enough work groups to cover ``size`` = (W, H) invocations.

        ``images`` are bound to image units 0, 1, ... (access ``read_write`` unless given as
        ``(texture, "read" | "write")``); ``textures`` to texture units 0, 1, ...
        """
        width, height = size
        for unit, item in enumerate(images):
            texture, access = item if isinstance(item, tuple) else (item, "read_write")
            self._core.bind_image(unit, texture._core, access)
        for unit, texture in enumerate(textures):
            self._core.bind_texture(unit, texture._core)
        for name, value in (uniforms or {}).items():
            values = [float(v) for v in np.asarray(value, dtype=np.float64).ravel()]
            self._core.set_uniform(name, values)
        lx, ly, _ = self.local_size
        self._core.dispatch(-(-width // lx), -(-height // ly), 1)


class ShaderPass:
    """A post-process pass known by its shader: its inputs, outputs and uniforms are the
    shader's own samplers, images and uniforms, bound by name (``reflect()`` lists them).
    Made once per context and shader by ``Context.shader_pass``; the values it gets are
    validated where they are declared (blurlab.methods), not again here."""

    def __init__(self, core: _core.ShaderPass):
        self._core = core

    @property
    def shader(self) -> str:
        return self._core.shader

    @property
    def native(self) -> _core.ShaderPass:
        """The C++ pass, for blurlab's own code (recorded dispatch plans)."""
        return self._core

    def run(
        self,
        inputs: Mapping[str, Texture],
        outputs: Mapping[str, Texture],
        uniforms: Mapping[str, object] | None = None,
        backend: str = "compute",
        group_per_texel: bool = False,
    ) -> None:
        """Runs the shader once per texel of the first output (``group_per_texel``: one work
        group per texel). Every sampler and image of the shader must be named, each with a
        texture of the kind it reads: uint32 for usampler2D and r32ui images, another dtype
        for the rest."""
        self._core.run(
            {name: texture._core for name, texture in inputs.items()},
            {name: texture._core for name, texture in outputs.items()},
            dict(uniforms or {}),
            backend,
            group_per_texel,
        )

    def reflect(self, backend: str = "compute") -> dict:
        """The shader's samplers, images, fragment outputs and uniforms on `backend`."""
        return self._core.reflect(backend)


class GLContext:
    """An OpenGL 4.5 core context with no display: textures, passes, timers and pools.
    ``blurlab.Context`` (core.context) is this with the render and reference shortcuts.

    ``device``: ``"auto"`` (a GPU if EGL finds one, else Mesa's llvmpipe), ``"gpu"`` (fails
    without one), ``"software"`` (llvmpipe), or an int that picks an EGL device by index
    (see ``Context.devices()``).
    """

    def __init__(self, device: str | int = "auto", shader_dir: str | Path | None = None):
        if isinstance(device, bool) or not isinstance(device, (str, int)):
            raise TypeError(
                f"blurlab: device must be one of {DEVICE_MODES} or an int, not {device!r}"
            )
        if isinstance(device, str) and device not in DEVICE_MODES:
            raise ValueError(
                f"blurlab: device must be one of {DEVICE_MODES} or an int, not {device!r}"
            )
        folder = Path(shader_dir) if shader_dir is not None else _default_shader_dir()
        mode, index = ("index", device) if isinstance(device, int) else (device, -1)
        self._core = _core.Context(mode, index, str(folder.resolve()))
        self._moderngl = None
        self._cache: dict = {}  # cached(): passes, tile lists, lookup textures
        self._pool: dict = {}  # (shape, dtype) -> free textures
        # GPU copies of scene data, dropped with the mesh or material they belong to.
        self._meshes: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()
        self._material_textures: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()

    @property
    def shader_dir(self) -> Path:
        """The folder this context reads its shaders from."""
        return Path(self._core.shader_dir)

    @staticmethod
    def devices() -> list[dict]:
        """The EGL devices of this machine: index, kind ("gpu" or "software") and name."""
        return [{"index": d.index, "kind": d.kind, "name": d.name} for d in _core.Context.devices()]

    def info(self) -> dict:
        """vendor, renderer, version, device ("gpu" or "software"), timer clock, and more."""
        info = dict(self._core.info())
        for key in ("device_index", "max_texture_size"):
            info[key] = int(info[key])
        return info

    @property
    def software(self) -> bool:
        return self._core.software

    @property
    def max_texture_size(self) -> int:
        return self._core.max_texture_size

    def upload(self, array: np.ndarray) -> Texture:
        """A new texture holding ``array`` ((H, W) or (H, W, C), uint8/float16/float32)."""
        array = _check_array(array)
        self._check_size(array.shape[1], array.shape[0])
        channels = array.shape[2] if array.ndim == 3 else 1
        core = self._new_texture(array.shape[1], array.shape[0], channels, array.dtype.name)
        texture = Texture(self, core, array.shape)
        core.upload(array.reshape(array.shape[0], array.shape[1], channels))
        return texture

    def empty(self, shape: tuple[int, ...], dtype: str = "float32") -> Texture:
        """A new zero-filled texture of ``shape`` (H, W) or (H, W, C) and ``dtype``."""
        if (
            not isinstance(shape, (tuple, list))
            or len(shape) not in (2, 3)
            or not all(isinstance(s, Integral) and not isinstance(s, bool) for s in shape)
            or (len(shape) == 3 and not 1 <= shape[2] <= 4)
        ):
            raise ValueError(
                f"blurlab: texture shape {shape!r} is not (H, W) or (H, W, C) of integers "
                "with C in 1..4"
            )
        shape = tuple(int(s) for s in shape)
        try:
            dtype_name = np.dtype(dtype).name
        except TypeError:
            dtype_name = repr(dtype)
        if dtype_name not in TEXTURE_DTYPES:
            raise TypeError(
                f"blurlab: texture dtype {dtype!r} is not one of " + ", ".join(TEXTURE_DTYPES)
            )
        self._check_size(shape[1], shape[0])
        channels = shape[2] if len(shape) == 3 else 1
        core = self._new_texture(shape[1], shape[0], channels, np.dtype(dtype).name)
        core.clear()
        return Texture(self, core, shape)

    def _new_texture(self, width: int, height: int, channels: int, dtype_name: str):
        """A texture from the core; where the driver is out of memory, a GLError that says
        what was asked for and what to do (the context stays usable)."""
        try:
            return self._core.texture(width, height, channels, dtype_name)
        except _core.GLError as error:
            if "OUT_OF_MEMORY" not in str(error):
                raise
            mib = width * height * channels * np.dtype(dtype_name).itemsize / 2**20
            raise _core.GLError(
                f"blurlab: a {width}x{height} texture of {channels} {dtype_name} channels "
                f"({mib:,.0f} MiB) does not fit in the device's memory (GL_OUT_OF_MEMORY; "
                "llvmpipe refuses any texture over 1 GiB). Use a smaller size, or free "
                "textures and references you no longer need; this context is still usable"
            ) from None

    def _check_size(self, width: int, height: int) -> None:
        limit = self.max_texture_size
        if not (1 <= width <= limit and 1 <= height <= limit):
            raise ValueError(
                f"blurlab: image size {width}x{height} is outside 1..{limit} per side "
                "(GL_MAX_TEXTURE_SIZE of this device)"
            )

    def program(
        self, path: str | Path, defines: Mapping[str, object] | None = None
    ) -> ComputeProgram:
        """Loads a compute shader: ``path`` relative to the shader folder, or absolute.

        ``defines`` are injected after ``#version`` as ``#define NAME value``. A compile error
        raises ``blurlab.ShaderError`` with file:line and the driver's log.
        """
        path = Path(path)
        resolved = str(path.resolve()) if path.is_absolute() or path.exists() else str(path)
        pairs = [(str(k), _glsl_literal(v)) for k, v in (defines or {}).items()]
        return ComputeProgram(_core.Program.compute(self._core, resolved, pairs))

    @contextmanager
    def timer(self):
        """Times the GPU work issued inside the ``with`` block: yields a Timing filled on exit.

        GL timer queries where valid; on llvmpipe glFinish and a wall clock (``timing.clock``
        says which).
        """
        core = _core.Timer(self._core)
        timing = Timing(clock=core.clock)
        core.start()
        try:
            yield timing
        finally:
            timing.ms = core.stop()

    @property
    def lazy_timers(self) -> LazyTimers:
        """Timers read when first asked for (a PendingTiming each), for work whose time a caller
        may never read."""
        return LazyTimers(self)

    @contextmanager
    def deferred_timers(self):
        """Yields a DeferredTimers: its ``timer()`` blocks time GPU work as ``timer()`` does,
        but no block waits for its result; every Timing is filled when this block ends, after
        one wait. For loops of many short timed passes (reference sub-frames), which would
        otherwise stop the CPU until the GPU catches up once per pass (a GPU clock; the wall
        clock of llvmpipe waits at each block regardless, glFinish being its measurement)."""
        timers = DeferredTimers(self)
        try:
            yield timers
        finally:
            timers.read()

    def finish(self) -> None:
        """Waits until the GPU has finished all work issued so far."""
        self._core.finish()

    def waits(self) -> int:
        """How many times blurlab has stopped the CPU until the GPU caught up on this context
        (glFinish, a timer result not yet there, a texture download, an asynchronous download's
        fence): a counter for checking that a loop issues no wait per step."""
        return self._core.waits

    def fence_timeouts(self) -> int:
        """How many of those waits, on a fence (a batch of metrics or an asynchronous
        download), the driver ended before the GPU had finished: each is waited again, so none
        reads memory the GPU is still writing. Nonzero on a busy GPU; a count for reports."""
        return self._core.fence_timeouts

    def pacing_waits(self) -> int:
        """How many times the CPU waited for the oldest of its issued passes because more than
        ``info()["passes_in_flight"]`` were unfinished (32, unless BLURLAB_PASSES_IN_FLIGHT
        sets another bound), checked at a fence every ``info()["passes_per_fence"]`` passes
        (docs/spec.md §6.3). Not among waits(): nothing is read."""
        return self._core.pacing_waits

    def stale_readbacks(self) -> int:
        """How many batches of GPU metrics came back lacking their passes' tickets, so not what
        the passes wrote (``blurlab.StaleReadback``, docs/spec.md §6.3), and were refused: a
        sweep evaluates each such batch again. A count for reports; 0 where all is well."""
        return self._core.stale_readbacks

    def live_objects(self) -> dict[str, int]:
        """Counts of live GL objects blurlab made, by kind (texture, buffer, program, query)."""
        return dict(self._core.live_objects())

    def gl_errors(self) -> list[str]:
        """Reads and clears GL's error flags: the names of the errors set ("GL_INVALID_VALUE",
        ...), or [] when none is. Every blurlab call checks and clears them itself, so a
        non-empty list means a bug (or GL calls of your own, e.g. through moderngl)."""
        return list(self._core.gl_errors())

    def reset_status(self) -> str:
        """Whether the GPU reset this context since it was made: "none", "guilty" (its own work
        caused it), "innocent" or "unknown". After a reset every texture and pass is lost and
        blurlab's calls raise ``blurlab.ContextLost``; make a new Context. Where the driver gives no
        notification (``info()["reset_notification"]`` is "none") this is always "none"."""
        return self._core.reset_status()

    def memory(self) -> dict[str, int]:
        """Video memory in KiB ("total", "available") where the driver reports it (NVIDIA's
        GL_NVX_gpu_memory_info); {} elsewhere, llvmpipe included."""
        return {k: int(v) for k, v in self._core.memory().items()}

    def moderngl(self):
        """A moderngl context on this very GL context, for users' own passes.

        Share textures without a copy: ``mgl.external_texture(tex.glo, (W, H), C, 0, "f4")``.
        """
        import moderngl

        self._core.make_current()
        if self._moderngl is None:
            # moderngl's default loader attaches to the EGL context current on this thread.
            moderngl.init_context()
            self._moderngl = moderngl.get_context()
            self._moderngl.clear_errors()
        return self._moderngl

    def make_current(self) -> None:
        self._core.make_current()

    @property
    def native(self) -> _core.Context:
        """The C++ context, for blurlab's own passes (blurlab._core)."""
        return self._core

    def cached(self, key, make):
        """The object stored under `key`, made by `make()` on first use and kept as long as the
        context: passes (their programs compile once), tile lists, lookup textures."""
        if key not in self._cache:
            self._cache[key] = make()
        return self._cache[key]

    def shader_pass(self, shader: str, defines: Mapping[str, object] | None = None) -> ShaderPass:
        """The pass of `shader` (a path under the shader folder) compiled with `defines`, made
        once per context (its programs compile on first use per backend)."""
        pairs = tuple((str(k), _glsl_literal(v)) for k, v in (defines or {}).items())
        return self.cached(
            ("shader_pass", shader, pairs),
            lambda: ShaderPass(_core.ShaderPass(self._core, shader, list(pairs))),
        )

    def pooled(self, shape, dtype: str = "float32") -> Texture:
        """A texture from the context's pool; its contents are undefined. Give it back with
        ``recycle``.

        Fresh allocations are expensive on first use (about 4 ms per 1080p RGBA32F target on
        the H100), so passes that run many times take their targets from here.
        """
        name = dtype if dtype in TEXTURE_DTYPES else np.dtype(dtype).name
        free = self._pool.get((tuple(shape), name))
        return free.pop() if free else self.empty(shape, dtype)

    def recycle(self, *textures: Texture) -> None:
        """Returns textures to the pool for later ``pooled`` calls; the caller must not use
        them afterwards."""
        for texture in textures:
            free = self._pool.setdefault((texture.shape, texture.dtype_name), [])
            if len(free) < 8:  # a few spares serve a pipeline; more would only hold memory
                free.append(texture)

    def gpu_mesh(self, mesh) -> _core.Mesh:
        """The mesh's vertex and index buffers on this context, uploaded once per mesh."""
        if mesh not in self._meshes:
            self._meshes[mesh] = _core.Mesh(
                self._core,
                mesh.positions,
                mesh.normals,
                mesh.uvs,
                mesh.indices,
                mesh.bone_indices,
                mesh.bone_weights,
            )
        return self._meshes[mesh]

    def gpu_material_texture(self, material) -> _core.Texture | None:
        """The material's texture, mip-mapped, on this context; uploaded once per material."""
        if material.texture is None:
            return None
        if material not in self._material_textures:
            rgba = material.texture_rgba()
            levels = int(np.log2(max(rgba.shape[:2]))) + 1
            core = self._core.texture(rgba.shape[1], rgba.shape[0], 4, "float16", levels)
            core.upload(rgba)
            core.generate_mipmaps()
            self._material_textures[material] = core
        return self._material_textures[material]

    def __repr__(self) -> str:
        info = self._core.info()
        return f"<blurlab.Context {info['device']}: {info['renderer']}>"


def _glsl_literal(value: object) -> str:
    if isinstance(value, bool):
        return "1" if value else "0"
    if isinstance(value, float):
        return repr(value) if math.isfinite(value) else _reject_define(value)
    return str(value)


def _reject_define(value: object) -> str:
    raise ValueError(f"blurlab: shader define value {value!r} is not finite")
