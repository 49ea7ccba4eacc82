"""Error against a reference, docs/spec.md §6: PSNR (linear color clipped to [0, 1]), SSIM on
luminance, FLIP (the flip-evaluator package, on sRGB), per-pixel error maps, and flicker for
sequences. `gpu_mse`, `gpu_ssim`, `gpu_mse_ssim` (both from one pass) and `gpu_flip` reduce
the error on the GPU and read back a scalar, for sweeps.

The LDR metrics above clip to [0, 1] on purpose: they measure what an LDR display shows of
linear colour. HDR scenes (docs/hdr.md, docs/spec.md §6.2) are measured without that clip:
`hdr_flip`, `psnr_tm` and `ssim_tm` (after `tone_map` at the reference's `exposure`),
`log_luminance_error` and `energy_ratio`.
"""

from __future__ import annotations

import math

import numpy as np

from . import _core
from .io import linear_to_srgb
from .twins import flip as flip_twin

# Rec. 709 / sRGB luminance weights, for SSIM on luminance.
LUMINANCE = np.array([0.2126, 0.7152, 0.0722])


def _rgb(image, dtype=np.float64) -> np.ndarray:
    image = np.asarray(image, dtype)
    if image.ndim != 3 or image.shape[2] < 3:
        raise ValueError(f"blurlab.metrics: expected an (H, W, 3 or 4) image, not {image.shape}")
    return np.clip(image[..., :3], 0.0, 1.0)


def _pair(a, b, dtype=np.float64) -> tuple[np.ndarray, np.ndarray]:
    a, b = _rgb(a, dtype), _rgb(b, dtype)
    if a.shape != b.shape:
        raise ValueError(f"blurlab.metrics: images differ in shape: {a.shape} and {b.shape}")
    return a, b


def mse(a, b) -> float:
    """Mean squared error over pixels and RGB, colors clipped to [0, 1]."""
    a, b = _pair(a, b)
    return float(np.mean((a - b) ** 2))


def psnr_from_mse(value: float) -> float:
    """PSNR in dB for a peak of 1; identical images give +inf."""
    return math.inf if value <= 0 else 10.0 * math.log10(1.0 / value)


def psnr(a, b) -> float:
    """PSNR in dB of linear color clipped to [0, 1] (docs/spec.md §6)."""
    return psnr_from_mse(mse(a, b))


def _gaussian_blur(image: np.ndarray, sigma: float = 1.5, radius: int = 5) -> np.ndarray:
    # np.pad's reflect mirrors without repeating the edge, and repeats the mirror for images
    # smaller than the window (period 2(n - 1)); shaders/passes/ssim.comp does the same.
    x = np.arange(-radius, radius + 1)
    kernel = np.exp(-(x**2) / (2 * sigma**2))
    kernel /= kernel.sum()
    padded = np.pad(image, radius, mode="reflect")
    rows = sum(w * padded[:, i : i + image.shape[1]] for i, w in enumerate(kernel))
    return sum(w * rows[i : i + image.shape[0], :] for i, w in enumerate(kernel))


def ssim(a, b) -> float:
    """Mean SSIM (Wang et al. 2004) of the luminance, Gaussian window σ = 1.5, 11 taps,
    C1 = (0.01)², C2 = (0.03)² for a data range of 1."""
    a, b = _pair(a, b)
    x, y = a @ LUMINANCE, b @ LUMINANCE
    c1, c2 = 0.01**2, 0.03**2
    mx, my = _gaussian_blur(x), _gaussian_blur(y)
    sxx = _gaussian_blur(x * x) - mx * mx
    syy = _gaussian_blur(y * y) - my * my
    sxy = _gaussian_blur(x * y) - mx * my
    s = ((2 * mx * my + c1) * (2 * sxy + c2)) / ((mx * mx + my * my + c1) * (sxx + syy + c2))
    return float(np.mean(s))


def flip(reference, test) -> float:
    """Mean FLIP error (Andersson et al. 2020) of the sRGB-encoded images, 0 = identical."""
    import flip_evaluator

    ref, out = _pair(reference, test)
    srgb = lambda c: np.ascontiguousarray(linear_to_srgb(c), dtype=np.float32)  # noqa: E731
    _, mean, _ = flip_evaluator.evaluate(
        srgb(ref), srgb(out), "LDR", inputsRGB=True, applyMagma=False
    )
    return float(mean)


def error_map(a, b) -> np.ndarray:
    """(H, W) float32 per-pixel mean absolute RGB error, colors clipped to [0, 1]. In float32:
    it is drawn and searched for its worst windows, never summed over an image, and float64
    took 4x as long on the study's 1080p pictures."""
    a, b = _pair(a, b, np.float32)
    a -= b
    np.abs(a, out=a)
    return a.sum(axis=-1) / np.float32(3.0)


def flicker(frames, still) -> float:
    """Mean |out_n - out_{n-1}| over RGB on the pixels where `still` is true (docs/spec.md §6)."""
    frames = np.asarray(frames, np.float64)
    if frames.ndim != 4 or len(frames) < 2:
        raise ValueError("blurlab.metrics.flicker: needs a (N >= 2, H, W, C) sequence")
    still = np.asarray(still, bool)
    if still.shape != frames.shape[1:3] or not still.any():
        raise ValueError("blurlab.metrics.flicker: `still` must be an (H, W) mask with pixels")
    steps = np.abs(np.diff(frames[..., :3], axis=0)).mean(axis=-1)
    return float(steps[:, still].mean())


def _same_size(a, b, name: str) -> None:
    if a.shape[:2] != b.shape[:2]:
        raise ValueError(
            f"blurlab.metrics.{name}: textures differ in shape: {a.shape} and {b.shape}"
        )


def gpu_mse(ctx, a, b) -> float:
    """`mse` of two (H, W, 4) float32 textures, reduced on the GPU: only partial sums (one
    float per 32 x 32 pixels) are read back. NaN reads as 0."""
    _same_size(a, b, "gpu_mse")
    return _mean_squared(_squared_error_pass(ctx).squared_error(a.native, b.native), a.shape)


def _squared_error_pass(ctx):
    return ctx.cached("squared_error", lambda: _core.ErrorReductionPass(ctx.native))


def _mean_squared(total: float, shape) -> float:
    """The MSE of a squared error summed over the pixels and RGB of an image of `shape`."""
    return total / (shape[0] * shape[1] * 3)


def _mse_ssim_of_totals(totals, shape) -> tuple[float, float]:
    """(MSE, mean SSIM) from the two sums of a fused pass: Σ SSIM, Σ squared error."""
    return _mean_squared(totals[1], shape), totals[0] / (shape[0] * shape[1])


# Work-group layouts of the SSIM pass, (tile columns, tile rows, output rows per invocation);
# every layout gives the same value up to float rounding, and benchmarks/speed_floor.py times
# them all. Tiles 32 pixels wide (shaders/passes/ssim.comp): "column4" computes four pixels down
# a column per invocation (the vertical blur reads each row's moments once for up to four
# outputs), "column2x32" two in 32 x 32 tiles; "pixel16" is the one-pixel-per-invocation layout
# measured in docs/benchmarks.md before it. Strips (shaders/passes/ssim_strip.comp),
# "stripWxH": W invocations, each walking its column down H rows with the vertical blur in
# registers, one barrier per 8 (W = 256: 4) rows, a subgroup sum where the driver has one, and
# a prepared reference that reads 8 bytes per border texel instead of 16.
SSIM_LAYOUTS = {
    "pixel16": (32, 16, 1),
    "column2": (32, 16, 2),
    "column2x32": (32, 32, 2),
    "column4": (32, 32, 4),
    "column8": (32, 32, 8),
    "strip64x16": (64, 16, 16),
    "strip64x32": (64, 32, 32),
    "strip128x16": (128, 16, 16),
    "strip128x32": (128, 32, 32),
    "strip256x16": (256, 16, 16),
    "strip256x32": (256, 32, 32),
}
# The defaults, from the H100 at 1080p (docs/benchmarks.md, 2026-11-24): a pair is fastest in
# strip128x32 (gpu_ssim 0.107 ms against column4's 0.137), a prepared reference in column2x32
# since the tiles sum their group with a subgroup add into a few shared slots: its pass 0.0524
# ms issued without a read-back (0.0492 back to back), column2's 0.0564, column4's 0.0566 (the
# strips re-read its moments, 0.145 ms).
SSIM_LAYOUT = "strip128x32"
PREPARED_SSIM_LAYOUT = "column2x32"


def _ssim_pass(ctx, layout: str | None):
    layout = SSIM_LAYOUT if layout is None else layout
    if layout not in SSIM_LAYOUTS:
        raise ValueError(
            f"blurlab.metrics: unknown SSIM layout {layout!r}; choose from {list(SSIM_LAYOUTS)}"
        )
    columns, tile_rows, rows = SSIM_LAYOUTS[layout]
    make = lambda: _core.SsimReductionPass(ctx.native, tile_rows, rows, columns)  # noqa: E731
    return ctx.cached(("ssim", layout), make)


def gpu_ssim(ctx, a, b, layout: str | None = None) -> float:
    """`ssim` of two (H, W, 4) float32 textures, computed on the GPU (docs/spec.md §6): only partial
    sums of the SSIM map (one float per work group's tile or strip) are read back.
    `layout`: a key of SSIM_LAYOUTS (default SSIM_LAYOUT), for benchmarks that compare them."""
    _same_size(a, b, "gpu_ssim")
    return _ssim_pass(ctx, layout).mean_ssim(a.native, b.native)


def gpu_mse_ssim(ctx, a, b, layout: str | None = None) -> tuple[float, float]:
    """(`mse`, `ssim`) of two (H, W, 4) float32 textures from one GPU dispatch and one read-back
    (docs/spec.md §6): the SSIM pass also sums the squared error of the texels it loads, so a
    sweep that wants PSNR and SSIM pays for one pass. Equal to (`gpu_mse`, `gpu_ssim`) up to
    float rounding (tests/test_ssim_gpu.py). `layout` as in `gpu_ssim`. `a` may be a
    `PreparedReference` (`prepare_reference`) of a reference compared many times: then only
    three moments of the pair are blurred, in the layout it was prepared with."""
    if isinstance(a, PreparedReference):
        return a.mse_ssim(b)
    _same_size(a, b, "gpu_mse_ssim")
    squared_error, mean_ssim = _ssim_pass(ctx, layout).mse_ssim(a.native, b.native)
    return _mean_squared(squared_error, a.shape), mean_ssim


class PreparedReference:
    """A reference prepared once for many `gpu_mse_ssim` calls against it (a sweep's scene): its
    clipped colour and luminance, and the Gaussian mean and variance of its luminance, computed
    once on the GPU, so each evaluation blurs three moments of the pair instead of five. Two
    textures hold them, packed as the layout's shader reads them (docs/spec.md §6: tiles keep
    colour + luminance and mean + variance, strips colour + mean and luminance + variance). It
    holds copies: later changes to the reference texture do not reach it. Make it with
    `prepare_reference`; its textures go back to the pool with `release()`."""

    def __init__(self, ctx, reference, layout: str | None = None):
        if reference.channels < 3:
            raise ValueError("blurlab.metrics.prepare_reference: the reference needs RGB channels")
        self.layout = PREPARED_SSIM_LAYOUT if layout is None else layout
        self.shape = reference.shape
        height, width = reference.shape[:2]
        self.colour_luminance = ctx.pooled((height, width, 4))
        self.moments = ctx.pooled((height, width, 2))
        native = (self.colour_luminance.native, self.moments.native)
        _ssim_pass(ctx, self.layout).prepare(reference.native, *native)
        self._ctx = ctx

    def mse_ssim(self, test) -> tuple[float, float]:
        """(`mse`, `ssim`) of the reference and `test`, as `gpu_mse_ssim` computes them."""
        squared_error, mean_ssim = self.pass_against(test, "gpu_mse_ssim").mse_ssim_prepared(
            *self.natives(test)
        )
        return _mean_squared(squared_error, test.shape), mean_ssim

    def pass_against(self, test, caller: str):
        """The SSIM pass of this reference's layout, once `test` is checked against it (the
        reference not released, the same size); `caller` names the call in errors."""
        if self.colour_luminance is None:
            raise ValueError("blurlab.metrics.PreparedReference: used after release()")
        _same_size(self.colour_luminance, test, caller)
        return _ssim_pass(self._ctx, self.layout)

    def natives(self, test) -> tuple:
        """The native textures a prepared pass reads: the reference's two and `test`."""
        return self.colour_luminance.native, self.moments.native, test.native

    def release(self) -> None:
        """Returns the textures to the context's pool; the object cannot be used after."""
        if self.colour_luminance is not None:
            self._ctx.recycle(self.colour_luminance, self.moments)
            self.colour_luminance = self.moments = None


def prepare_reference(ctx, reference, layout: str | None = None) -> PreparedReference:
    """`reference` (an (H, W, 4) float32 texture) prepared for `gpu_mse_ssim(ctx, prepared,
    test)`: for a caller that compares many images with one fixed reference. `layout`: a key
    of SSIM_LAYOUTS (default PREPARED_SSIM_LAYOUT)."""
    return PreparedReference(ctx, reference, layout)


class MetricQueue:
    """GPU metrics issued now and read together later (docs/spec.md §6.3): `mse`, `mse_ssim`
    and `flip` dispatch their passes and return their place in the batch; `read()` waits for
    the GPU once and returns every value in the order issued, each equal bit for bit to what
    `gpu_mse` / `gpu_mse_ssim` / `gpu_flip` return for the same pair. Between the two the CPU
    goes on issuing work (the next evaluation's filter) while the GPU runs, instead of waiting
    for each scalar. `seal()` ends a batch without waiting (the copy of its sums to mapped
    memory and a fence are queued), so that with two queues in turn the GPU works through one
    batch while the CPU issues the next and reads the one before. The compared textures may go
    back to the pool once issued: GL runs the reduction before any later pass that reuses them."""

    def __init__(self, ctx):
        self._ctx = ctx
        self._core = _core.ReductionQueue(ctx.native)
        self._finish: list = []  # per reduction issued: totals -> the metric's value
        self._sealed = False

    def _issuing(self) -> None:
        if self._sealed:
            raise RuntimeError("blurlab.metrics.MetricQueue: read() a sealed batch before issuing")

    def seal(self) -> None:
        """Ends the batch: its read-back starts on the GPU; `read()` then waits only for it."""
        self._core.seal()
        self._sealed = bool(self._finish)

    def __len__(self) -> int:
        return len(self._finish)

    def mse(self, a, b) -> int:
        """Issues `gpu_mse(ctx, a, b)`; returns its index in `read()`'s list."""
        self._issuing()
        _same_size(a, b, "MetricQueue.mse")
        _squared_error_pass(self._ctx).issue_squared_error(a.native, b.native, self._core)
        shape = a.shape
        self._finish.append((True, lambda totals: _mean_squared(totals[0], shape)))
        return len(self._finish) - 1

    def mse_ssim(self, reference, test, layout: str | None = None) -> int:
        """Issues `gpu_mse_ssim(ctx, reference, test)`: `reference` a `PreparedReference`
        (prepare_reference; `layout` is then its own) or a texture (both images' moments
        blurred, in `layout` as `gpu_mse_ssim` says). Returns its index in `read()`'s list,
        where its value is the (mse, ssim) tuple."""
        self._issuing()
        if isinstance(reference, PreparedReference):
            reference.pass_against(test, "MetricQueue.mse_ssim").issue_mse_ssim_prepared(
                *reference.natives(test), self._core
            )
        else:
            if getattr(reference, "native", None) is None:
                raise TypeError(
                    "blurlab.metrics.MetricQueue.mse_ssim: compares with a PreparedReference "
                    f"(prepare_reference) or a texture, not {type(reference).__name__}"
                )
            _same_size(reference, test, "MetricQueue.mse_ssim")
            _ssim_pass(self._ctx, layout).issue_mse_ssim(reference.native, test.native, self._core)
        shape = test.shape
        self._finish.append((True, lambda totals: _mse_ssim_of_totals(totals, shape)))
        return len(self._finish) - 1

    def flip(self, reference, test, ppd: float = flip_twin.DEFAULT_PPD) -> int:
        """Issues `gpu_flip(ctx, reference, test, ppd)`; returns its index in `read()`'s list.
        Its partial sums stay in a small pooled texture until `read()` downloads them."""
        self._issuing()
        error, partials = _gpu_flip_textures(self._ctx, reference, test, ppd)
        self._ctx.recycle(error)
        shape = reference.shape
        self._finish.append((False, lambda: _flip_mean(self._ctx, partials, shape)))
        return len(self._finish) - 1

    def read(self) -> list:
        """The values of every metric issued since the last read, in order; empties the queue.
        One wait for the GPU (none when nothing is pending)."""
        finish, self._finish, self._sealed = self._finish, [], False
        totals = iter(self._core.read())
        return [f(next(totals)) if reads_totals else f() for reads_totals, f in finish]


class MetricBatches:
    """Batches of `size` evaluations whose metrics are read back one batch behind: two
    MetricQueues in turn, so that the CPU reads batch n only once batch n + 1 is issued and the
    GPU never waits for the CPU's read (docs/spec.md §6.3). Issue an evaluation's metrics into
    `queue`, then `add(item)` it; `add` and `flush` return (item, values) for each evaluation
    whose batch has been read, in order, `values` being its batch's `MetricQueue.read()`."""

    def __init__(self, ctx, size: int):
        if isinstance(size, bool) or not isinstance(size, int) or size < 1:
            raise ValueError(
                f"blurlab.metrics.MetricBatches: size must be an integer >= 1, not {size!r}"
            )
        self.size = size
        self._queues = [MetricQueue(ctx), MetricQueue(ctx)]
        self._items: list = []  # of the batch being issued
        self._sealed: list = []  # the batch before, sealed and not read yet

    @property
    def queue(self) -> MetricQueue:
        """The queue that the current evaluation's metrics go to."""
        return self._queues[0]

    def add(self, item) -> list[tuple[object, list]]:
        self._items.append(item)
        if len(self._items) < self.size:
            return []
        self.queue.seal()
        ready = self._read_sealed()
        self._sealed, self._items = self._items, []
        self._queues.reverse()
        return ready

    def flush(self) -> list[tuple[object, list]]:
        """Every evaluation not read yet."""
        ready = self._read_sealed()
        values = self.queue.read()
        ready += [(item, values) for item in self._items]
        self._items = []
        return ready

    def _read_sealed(self) -> list[tuple[object, list]]:
        values = self._queues[1].read()
        ready = [(item, values) for item in self._sealed]
        self._sealed = []
        return ready


def _glsl_floats(values) -> str:
    return f"float[{len(values)}](" + ", ".join(f"{float(v):.9e}" for v in values) + ")"


def _flip_defines(ppd: float) -> dict:
    """The kernels and constants of LDR-FLIP at `ppd` pixels per degree, computed in double
    (blurlab.twins.flip) and compiled into the shaders (about 1 ms of NumPy: made once per
    context and ppd, with the passes, in _flip_passes)."""
    csf = flip_twin.csf_kernels(ppd)
    g, d, dd = flip_twin.feature_kernels(ppd)
    inverse = flip_twin.XYZ_TO_RGB * flip_twin.WHITE  # undoes RGB_TO_XYZ / white
    return {
        "CSF_RADIUS": csf.shape[-1] // 2,
        "CSF_Y": _glsl_floats(csf[0, 0]),
        "CSF_CX": _glsl_floats(csf[1, 0]),
        "CSF_CZ1": _glsl_floats(csf[2, 0]),
        "CSF_CZ2": _glsl_floats(csf[2, 1]),
        "FEATURE_RADIUS": len(g) // 2,
        "FEATURE_G": _glsl_floats(g),
        "FEATURE_D": _glsl_floats(d),
        "FEATURE_DD": _glsl_floats(dd),
        # mat3 takes columns.
        "XYZ_TO_RGB_NORMALIZED": "mat3(" + ", ".join(f"{v:.9e}" for v in inverse.T.ravel()) + ")",
        "CMAX": f"{flip_twin.max_color_distance():.9e}",
    }


def _check_ppd(ppd) -> float:
    if isinstance(ppd, bool) or not isinstance(ppd, (int, float)) or not 1.0 <= ppd <= 1000.0:
        raise ValueError(
            f"blurlab.metrics.gpu_flip: ppd (pixels per degree) must be a number in "
            f"[1, 1000], not {ppd!r}"
        )
    return float(ppd)


def _flip_passes(ctx, ppd: float):
    """LDR-FLIP's two passes at `ppd`, compiled once per context and ppd."""

    def make():
        defines = _flip_defines(ppd)
        return (
            ctx.shader_pass("passes/flip_horizontal.comp", defines),
            ctx.shader_pass("passes/flip_error.comp", defines),
        )

    return ctx.cached(("gpu_flip", ppd), make)


def _gpu_flip_textures(ctx, reference, test, ppd):
    """Runs LDR-FLIP's two passes; returns the (H, W) error map and the per-group partial sums
    as pooled textures (the caller recycles them)."""
    _same_size(reference, test, "gpu_flip")
    if reference.channels < 3 or test.channels < 3:
        raise ValueError("blurlab.metrics.gpu_flip: the images need RGB channels")
    horizontal, vertical = _flip_passes(ctx, _check_ppd(ppd))
    height, width = reference.shape[:2]
    rows = [ctx.pooled((height, width, 4)) for _ in range(4)]
    names = ("reference_color", "reference_features", "test_color", "test_features")
    horizontal.run({"reference": reference, "test": test}, dict(zip(names, rows, strict=True)))
    error = ctx.pooled((height, width))
    partials = ctx.pooled((-(-height // 16), -(-width // 16)))
    vertical.run(dict(zip(names, rows, strict=True)), {"error": error, "partials": partials})
    ctx.recycle(*rows)
    return error, partials


def gpu_flip(ctx, reference, test, ppd: float = flip_twin.DEFAULT_PPD) -> float:
    """Mean LDR-FLIP error (Andersson et al. 2020; docs/spec.md §6.1) of two (H, W, 4) float32
    textures of linear colour, computed on the GPU: the `flip` of the images, as flip-evaluator
    computes it (tests/test_flip_gpu.py), with only one partial sum per 16 x 16 pixels read
    back. `ppd`: pixels per degree of visual angle (flip-evaluator's default: 67.02). NaN
    colour reads as 0 and infinities clip to [0, 1], as every pass reads colour."""
    error, partials = _gpu_flip_textures(ctx, reference, test, ppd)
    ctx.recycle(error)
    return _flip_mean(ctx, partials, reference.shape)


def _flip_mean(ctx, partials, shape) -> float:
    """The mean FLIP error from its per-group partial sums, which go back to the pool."""
    total = float(np.sum(partials.download(), dtype=np.float64))
    ctx.recycle(partials)
    return total / (shape[0] * shape[1])


def gpu_flip_map(ctx, reference, test, ppd: float = flip_twin.DEFAULT_PPD) -> np.ndarray:
    """The (H, W) per-pixel LDR-FLIP error of `gpu_flip`, in [0, 1]."""
    error, partials = _gpu_flip_textures(ctx, reference, test, ppd)
    image = error.download()
    ctx.recycle(error, partials)
    return image


def tile_border_error(reference, test, k: int, band: int = 1) -> dict:
    """Blockiness of a tiled filter (the Urho3D thesis saw it at k = 32), two ways:

    - level: the mean per-pixel error (`error_map`) on pixels within `band` pixels of a k x k
      tile border ("border") and on the pixels inside the tiles ("interior");
    - seams: the mean jump of the signed error (test - reference, mean over RGB) between
      neighboring pixels on either side of a tile border ("border_step") and between the other
      neighboring pixels ("interior_step").

    "ratio" and "step_ratio" are border / interior (> 1: errors line up with the tile grid).
    Borders are the lines x = i·k and y = i·k between tiles; the image edges are not borders."""
    if isinstance(k, bool) or not isinstance(k, int) or k < 2:
        raise ValueError(f"blurlab.metrics.tile_border_error: k must be an integer >= 2, not {k!r}")
    if isinstance(band, bool) or not isinstance(band, int) or not 1 <= band <= k // 2:
        raise ValueError(
            f"blurlab.metrics.tile_border_error: band must be an integer in 1..k/2, not {band!r}"
        )
    a, b = _pair(reference, test)
    errors = np.mean(np.abs(a - b), axis=-1)
    signed = np.mean(b - a, axis=-1)
    h, w = errors.shape
    if h <= k and w <= k:
        raise ValueError(
            f"blurlab.metrics.tile_border_error: a {w}x{h} image has no tile border at k = {k}"
        )

    def near_border(n: int) -> np.ndarray:
        near = np.zeros(n, bool)
        for border in range(k, n, k):  # the border between pixels border - 1 and border
            near[border - band : border + band] = True
        return near

    border = near_border(h)[:, None] | near_border(w)[None, :]
    # Jumps between horizontal neighbors (x, x + 1) and vertical ones (y, y + 1).
    steps_x = np.abs(np.diff(signed, axis=1))
    steps_y = np.abs(np.diff(signed, axis=0))
    across_x = np.broadcast_to((np.arange(1, w) % k == 0)[None, :], steps_x.shape)
    across_y = np.broadcast_to((np.arange(1, h) % k == 0)[:, None], steps_y.shape)
    on_steps = np.concatenate([steps_x[across_x], steps_y[across_y]])
    off_steps = np.concatenate([steps_x[~across_x], steps_y[~across_y]])

    def ratio(on: float, off: float) -> float:
        return on / off if off > 0 else (math.inf if on > 0 else 1.0)

    level_on, level_off = float(errors[border].mean()), float(errors[~border].mean())
    step_on, step_off = float(on_steps.mean()), float(off_steps.mean())
    return {
        "border": level_on,
        "interior": level_off,
        "ratio": ratio(level_on, level_off),
        "border_step": step_on,
        "interior_step": step_off,
        "step_ratio": ratio(step_on, step_off),
        "border_pixels": int(border.sum()),
    }


# --- HDR metrics (docs/spec.md §6.2): nothing is clipped above 1 --------------------------------

# Reinhard et al. 2002, eq. 1: the log-average luminance uses δ against log(0), and the key
# 0.18 maps it to middle grey.
KEY = 0.18
LOG_DELTA = 1e-4
# The ACES fit (Narkowicz 2016) that HDR-FLIP assumes, with FLIP's pre-exposure 0.6 folded
# into the coefficients: t(x) = (a x² + b x) / (c x² + d x + e).
ACES = (0.6 * 0.6 * 2.51, 0.6 * 0.03, 0.6 * 0.6 * 2.43, 0.6 * 0.59, 0.14)
FLIP_TARGET = 0.85  # HDR-FLIP's exposure range brings Y_max, then the median Y, to t = 0.85


def _hdr_rgb(image, what: str = "image") -> np.ndarray:
    """RGB of an (H, W, 3|4) linear image as float64, unclipped; refuses NaN and inf."""
    image = np.asarray(image, np.float64)
    if image.ndim != 3 or image.shape[2] < 3:
        raise ValueError(f"blurlab.metrics: expected an (H, W, 3 or 4) image, not {image.shape}")
    rgb = image[..., :3]
    if not np.isfinite(rgb).all():
        raise ValueError(
            f"blurlab.metrics: the {what} has NaN or inf values; HDR metrics need finite colour"
        )
    return rgb


def _hdr_pair(reference, test) -> tuple[np.ndarray, np.ndarray]:
    a, b = _hdr_rgb(reference, "reference"), _hdr_rgb(test, "test image")
    if a.shape != b.shape:
        raise ValueError(f"blurlab.metrics: images differ in shape: {a.shape} and {b.shape}")
    return a, b


def luminance(image) -> np.ndarray:
    """(H, W) Rec. 709 luminance of linear RGB, unclipped."""
    return _hdr_rgb(image) @ LUMINANCE


def exposure(reference) -> float:
    """The exposure that maps the reference's log-average luminance to middle grey
    (Reinhard et al. 2002): KEY / exp(mean(log(δ + max(Y, 0)))); the one exposure of
    `tone_map`, `psnr_tm`, `ssim_tm` and the report's pictures."""
    y = np.maximum(luminance(reference), 0.0)
    return float(KEY / np.exp(np.mean(np.log(LOG_DELTA + y))))


def _check_exposure(value) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise TypeError(f"blurlab.metrics: exposure must be a number, not {value!r}")
    if not (math.isfinite(value) and value > 0):
        raise ValueError(f"blurlab.metrics: exposure must be finite and > 0, not {value}")
    return float(value)


def tone_map(image, exposure: float) -> np.ndarray:
    """(H, W, 3) display values in [0, 1]: Reinhard's x / (1 + x) per channel on
    x = exposure · max(rgb, 0), then the sRGB transfer function (docs/spec.md §6.2). Never
    clips a highlight to a constant: a brighter input always maps to a brighter output."""
    x = _check_exposure(exposure) * np.maximum(_hdr_rgb(image), 0.0)
    return linear_to_srgb(x / (1.0 + x))


def _tone_mapped_pair(reference, test, exposure_value):
    a, b = _hdr_pair(reference, test)
    e = exposure(a) if exposure_value is None else exposure_value
    return tone_map(a, e), tone_map(b, e)


def psnr_tm(reference, test, exposure: float | None = None) -> float:
    """PSNR (dB, peak 1) of the two images tone-mapped alike (`tone_map`, the reference's
    exposure unless one is given)."""
    return psnr(*_tone_mapped_pair(reference, test, exposure))


def ssim_tm(reference, test, exposure: float | None = None) -> float:
    """`ssim` of the luma (Rec. 709 weights on the sRGB-encoded values) of the two images
    tone-mapped alike (`tone_map`, the reference's exposure unless one is given)."""
    return ssim(*_tone_mapped_pair(reference, test, exposure))


def log_luminance_error(reference, test) -> float:
    """Mean |log2((δ + Y_test) / (δ + Y_ref))| over pixels: the error in stops, negative
    luminance taken as 0, δ = LOG_DELTA."""
    a, b = _hdr_pair(reference, test)
    ya, yb = np.maximum(a @ LUMINANCE, 0.0), np.maximum(b @ LUMINANCE, 0.0)
    return float(np.mean(np.abs(np.log2((LOG_DELTA + yb) / (LOG_DELTA + ya)))))


def energy_ratio(reference, test) -> float:
    """Σ test / Σ reference over pixels and RGB: 1 when the output keeps the reference's total
    radiance, < 1 when it loses light, > 1 when it adds some (+inf if the reference is black
    and the output is not)."""
    a, b = _hdr_pair(reference, test)
    total_a, total_b = float(a.sum()), float(b.sum())
    if total_a <= 0:
        return 1.0 if total_b == total_a else math.inf
    return total_b / total_a


def flip_exposure_range(reference) -> tuple[float, float]:
    """HDR-FLIP's exposure range (Andersson et al. 2021) from the reference, in stops: the
    start exposure brings the largest luminance, the stop exposure the median luminance (of
    the pixels with Y > 0, so that a mostly black image has a range), to FLIP_TARGET under
    the ACES curve."""
    y = np.maximum(luminance(reference), 0.0)
    lit = y[y > 0]
    if lit.size == 0:
        return 0.0, 0.0
    a, b, c, d, e = ACES
    t = FLIP_TARGET  # solve t(x) = t: (a - t c) x² + (b - t d) x - t e = 0, the positive root
    qa, qb, qc = a - t * c, b - t * d, -t * e
    x = (-qb + math.sqrt(qb * qb - 4 * qa * qc)) / (2 * qa)
    start, stop = math.log2(x / float(lit.max())), math.log2(x / float(np.median(lit)))
    return start, stop


def hdr_flip(reference, test) -> float:
    """Mean HDR-FLIP error (flip-evaluator's "HDR" mode, ACES tone mapper), 0 = identical;
    its exposure range is `flip_exposure_range(reference)`. Negative values count as 0."""
    import flip_evaluator

    a, b = _hdr_pair(reference, test)
    start, stop = flip_exposure_range(a)
    linear = lambda c: np.ascontiguousarray(np.maximum(c, 0.0), dtype=np.float32)  # noqa: E731
    _, mean, _ = flip_evaluator.evaluate(
        linear(a),
        linear(b),
        "HDR",
        inputsRGB=False,
        applyMagma=False,
        parameters={"startExposure": start, "stopExposure": stop, "tonemapper": "ACES"},
    )
    return float(mean)


# The HDR metrics by the names sweeps, the study and benchmarks use; each f(reference, test).
HDR_METRICS = {
    "hdr_flip": hdr_flip,
    "psnr_tm": psnr_tm,
    "ssim_tm": ssim_tm,
    "log_lum_error": log_luminance_error,
    "energy_ratio": energy_ratio,
}


def hdr_scores(reference, test, names=tuple(HDR_METRICS)) -> dict[str, float]:
    """{name: value} of the HDR metrics `names` (keys of HDR_METRICS) of `test` against
    `reference`, and "exposure", the one `psnr_tm` and `ssim_tm` used."""
    unknown = set(names) - set(HDR_METRICS)
    if unknown:
        raise ValueError(
            f"blurlab.metrics: unknown HDR metrics {sorted(unknown)}; choose from "
            f"{list(HDR_METRICS)}"
        )
    a, b = _hdr_pair(reference, test)
    return {**{name: HDR_METRICS[name](a, b) for name in names}, "exposure": exposure(a)}
