"""The LDR metrics reduced on the GPU (docs/spec.md §6 "On the GPU"): `gpu_mse`, `gpu_ssim`
and `gpu_mse_ssim` (both from one pass) of two textures, reading back partial sums only, and
`PreparedReference`, a reference whose share of SSIM is computed once for many comparisons.
"""

from __future__ import annotations

from .. import _core


def check_same_size(a, b, name: str) -> None:
    if a.shape[:2] != b.shape[:2]:
        raise ValueError(
            f"blurlab.metrics.{name}: textures differ in shape: {a.shape} and {b.shape}"
        )


def gpu_mse(ctx, a, b) -> float:
    """`mse` of two (H, W, 4) float32 textures, reduced on the GPU: only partial sums (one
    float per 32 x 32 pixels) are read back. NaN reads as 0."""
    check_same_size(a, b, "gpu_mse")
    return mean_squared(squared_error_pass(ctx).squared_error(a.native, b.native), a.shape)


def squared_error_pass(ctx):
    return ctx.cached("squared_error", lambda: _core.ErrorReductionPass(ctx.native))


def mean_squared(total: float, shape) -> float:
    """The MSE of a squared error summed over the pixels and RGB of an image of `shape`."""
    return total / (shape[0] * shape[1] * 3)


def mse_ssim_of_totals(totals, shape) -> tuple[float, float]:
    """(MSE, mean SSIM) from the two sums of a fused pass: Σ SSIM, Σ squared error."""
    return mean_squared(totals[1], shape), totals[0] / (shape[0] * shape[1])


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


def ssim_pass(ctx, layout: str | None):
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
    check_same_size(a, b, "gpu_ssim")
    return ssim_pass(ctx, layout).mean_ssim(a.native, b.native)


def gpu_mse_ssim(ctx, a, b, layout: str | None = None) -> tuple[float, float]:
    """(`mse`, `ssim`) of two (H, W, 4) float32 textures from one GPU dispatch and one read-back
    (docs/spec.md §6): the SSIM pass also sums the squared error of the texels it loads, so a
    sweep that wants PSNR and SSIM pays for one pass. Equal to (`gpu_mse`, `gpu_ssim`) up to
    float rounding (tests/test_ssim_gpu.py). `layout` as in `gpu_ssim`. `a` may be a
    `PreparedReference` (`prepare_reference`) of a reference compared many times: then only
    three moments of the pair are blurred, in the layout it was prepared with."""
    if isinstance(a, PreparedReference):
        return a.mse_ssim(b)
    check_same_size(a, b, "gpu_mse_ssim")
    squared_error, mean_ssim = ssim_pass(ctx, layout).mse_ssim(a.native, b.native)
    return mean_squared(squared_error, a.shape), mean_ssim


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
        ssim_pass(ctx, self.layout).prepare(reference.native, *native)
        self._ctx = ctx

    def mse_ssim(self, test) -> tuple[float, float]:
        """(`mse`, `ssim`) of the reference and `test`, as `gpu_mse_ssim` computes them."""
        squared_error, mean_ssim = self.pass_against(test, "gpu_mse_ssim").mse_ssim_prepared(
            *self.natives(test)
        )
        return mean_squared(squared_error, test.shape), mean_ssim

    def pass_against(self, test, caller: str):
        """The SSIM pass of this reference's layout, once `test` is checked against it (the
        reference not released, the same size); `caller` names the call in errors."""
        if self.colour_luminance is None:
            raise ValueError("blurlab.metrics.PreparedReference: used after release()")
        check_same_size(self.colour_luminance, test, caller)
        return ssim_pass(self._ctx, self.layout)

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
