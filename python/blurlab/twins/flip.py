"""LDR-FLIP (Andersson et al. 2020, "FLIP: A Difference Evaluator for Alternating Images",
Proc. ACM Comput. Graph. Interact. Tech. 3(2)), docs/spec.md §6.1, in float64: the twin of
shaders/passes/flip_*.comp (blurlab.metrics.gpu_flip), held to the flip-evaluator package by
tests/test_flip_gpu.py.

Two pipelines on the images in linear RGB clipped to [0, 1]:

- colour: to the opponent space YCxCz, filtered per channel by the contrast sensitivity of the
  eye (sums of Gaussians in degrees of visual angle), back to linear RGB clipped to [0, 1],
  to CIELAB with the Hunt effect (a*, b* scaled by L*/100); the HyAB distance to the power
  qc = 0.7, remapped to [0, 1] with the breakpoints pc = 0.4, pt = 0.95 of the largest
  distance (green against blue);
- features: edges and points (first and second derivatives of a Gaussian, σ = w/2 degrees,
  w = 0.082) of the normalized luminance; the larger difference of their magnitudes, scaled by
  1/√2 and raised to qf = 0.5.

The error is the colour error raised to 1 - the feature error. Every filter is separable, each
Gaussian term a product of two 1-D kernels; images are extended past their edges by repeating
the edge pixel.
"""

from __future__ import annotations

import math

import numpy as np

# The viewing condition FLIP's authors chose: a 0.7 m wide 3840-pixel monitor seen from 0.7 m.
DEFAULT_PPD = 0.7 * 3840 / 0.7 * math.pi / 180

# Linear sRGB to XYZ from the sRGB primaries and D65 (exact rationals), and its inverse.
RGB_TO_XYZ = np.array(
    [
        [10135552 / 24577794, 8788810 / 24577794, 4435075 / 24577794],
        [2613072 / 12288897, 8788810 / 12288897, 887015 / 12288897],
        [1425312 / 73733382, 8788810 / 73733382, 70074185 / 73733382],
    ]
)
XYZ_TO_RGB = np.linalg.inv(RGB_TO_XYZ)
# The reference white: XYZ of linear RGB (1, 1, 1).
WHITE = RGB_TO_XYZ.sum(axis=1)

# Contrast sensitivity of the achromatic, red-green and blue-yellow channels as sums of two
# Gaussians a·√(π/b)·exp(-π²x²/b), x in degrees: (a1, b1, a2, b2) per channel (paper, Table 1).
CSF = (
    (1.0, 0.0047, 0.0, 1e-5),
    (1.0, 0.0053, 0.0, 1e-5),
    (34.1, 0.04, 13.5, 0.025),
)
FEATURE_WIDTH = 0.082  # degrees between the peak and trough of the edge detector
QC, PC, PT, QF = 0.7, 0.4, 0.95, 0.5


def srgb_to_ycxcz(linear: np.ndarray) -> np.ndarray:
    """(H, W, 3) linear RGB to YCxCz (Y = 116·Y/Yn - 16, Cx = 500·(X/Xn - Y/Yn),
    Cz = 200·(Y/Yn - Z/Zn))."""
    xyz = (linear @ RGB_TO_XYZ.T) / WHITE
    x, y, z = xyz[..., 0], xyz[..., 1], xyz[..., 2]
    return np.stack([116 * y - 16, 500 * (x - y), 200 * (y - z)], axis=-1)


def ycxcz_to_linear(ycxcz: np.ndarray) -> np.ndarray:
    y = (ycxcz[..., 0] + 16) / 116
    xyz = np.stack([ycxcz[..., 1] / 500 + y, y, y - ycxcz[..., 2] / 200], axis=-1) * WHITE
    return xyz @ XYZ_TO_RGB.T


def linear_to_lab(linear: np.ndarray) -> np.ndarray:
    """CIELAB of linear RGB, white = `WHITE`."""
    t = (linear @ RGB_TO_XYZ.T) / WHITE
    delta = 6 / 29
    f = np.where(t > delta**3, np.cbrt(t), t / (3 * delta**2) + 4 / 29)
    return np.stack(
        [116 * f[..., 1] - 16, 500 * (f[..., 0] - f[..., 1]), 200 * (f[..., 1] - f[..., 2])],
        axis=-1,
    )


def hunt(lab: np.ndarray) -> np.ndarray:
    """The Hunt effect: chroma scaled by L*/100."""
    lightness = lab[..., 0]
    return np.stack([lightness, 0.01 * lightness * lab[..., 1], 0.01 * lightness * lab[..., 2]], -1)


def hyab(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    d = a - b
    return np.abs(d[..., 0]) + np.hypot(d[..., 1], d[..., 2])


def max_color_distance() -> float:
    """cmax: the HyAB distance, to the power qc, between Hunt-adjusted green and blue."""
    green, blue = hunt(linear_to_lab(np.eye(3)[1])), hunt(linear_to_lab(np.eye(3)[2]))
    return float(hyab(green, blue) ** QC)


def csf_radius(ppd: float) -> int:
    """Half-width in pixels of the colour filters: three standard deviations of the widest
    Gaussian (b = 0.04 has σ = √(b / 2π²) degrees)."""
    widest = max(max(c[1], c[3]) for c in CSF)
    return math.ceil(3 * math.sqrt(widest / (2 * math.pi**2)) * ppd)


def csf_kernels(ppd: float) -> np.ndarray:
    """(3 channels, 2 terms, 2r + 1) 1-D kernels: the 2-D filter of channel c is
    sum_t k[c, t] ⊗ k[c, t], normalized so that its 2-D weights sum to 1."""
    r = csf_radius(ppd)
    x = np.arange(-r, r + 1) / ppd
    kernels = np.zeros((3, 2, 2 * r + 1))
    for c, (a1, b1, a2, b2) in enumerate(CSF):
        # a·√(π/b)·exp(-π²(x² + y²)/b) = (√(a·√(π/b))·e(x))·(√(a·√(π/b))·e(y))
        for t, (a, b) in enumerate(((a1, b1), (a2, b2))):
            kernels[c, t] = math.sqrt(a * math.sqrt(math.pi / b)) * np.exp(-(math.pi**2) * x**2 / b)
        total = sum(kernels[c, t].sum() ** 2 for t in range(2))
        kernels[c] /= math.sqrt(total)
    return kernels


def feature_kernels(ppd: float) -> np.ndarray:
    """(3, 2r + 1): the Gaussian g (sums to 1), its first derivative d (positive and negative
    weights each sum to ±1) and its second derivative dd (likewise). The 2-D edge filters are
    d ⊗ g and g ⊗ d, the point filters dd ⊗ g and g ⊗ dd."""
    sigma = 0.5 * FEATURE_WIDTH * ppd
    r = math.ceil(3 * sigma)
    x = np.arange(-r, r + 1, dtype=np.float64)
    g = np.exp(-(x**2) / (2 * sigma**2))
    d = -x * g
    dd = (x**2 / sigma**2 - 1) * g

    def balanced(k):
        return np.where(k > 0, k / k[k > 0].sum(), k / -k[k < 0].sum())

    return np.stack([g / g.sum(), balanced(d), balanced(dd)])


def convolve(image: np.ndarray, kernel: np.ndarray, axis: int) -> np.ndarray:
    """Correlation of (H, W) `image` with a 1-D `kernel` along `axis`, the edge pixel repeated."""
    r = len(kernel) // 2
    pad = [(0, 0), (0, 0)]
    pad[axis] = (r, r)
    padded = np.pad(image, pad, mode="edge")
    n = image.shape[axis]
    return sum(w * np.take(padded, np.arange(i, i + n), axis=axis) for i, w in enumerate(kernel))


def separable(image: np.ndarray, across: np.ndarray, down: np.ndarray) -> np.ndarray:
    return convolve(convolve(image, across, axis=1), down, axis=0)


def filtered_lab(ycxcz: np.ndarray, ppd: float) -> np.ndarray:
    kernels = csf_kernels(ppd)
    channels = [
        sum(separable(ycxcz[..., c], kernels[c, t], kernels[c, t]) for t in range(2))
        for c in range(3)
    ]
    linear = np.clip(ycxcz_to_linear(np.stack(channels, axis=-1)), 0.0, 1.0)
    return hunt(linear_to_lab(linear))


def features(ycxcz: np.ndarray, ppd: float) -> tuple[np.ndarray, np.ndarray]:
    """Edge and point magnitudes of the normalized luminance (Y + 16) / 116."""
    g, d, dd = feature_kernels(ppd)
    y = (ycxcz[..., 0] + 16) / 116
    edge = np.hypot(separable(y, d, g), separable(y, g, d))
    point = np.hypot(separable(y, dd, g), separable(y, g, dd))
    return edge, point


def color_error(distance: np.ndarray) -> np.ndarray:
    """HyAB distance to the power qc, remapped to [0, 1] (pc·cmax maps to pt)."""
    cmax = max_color_distance()
    e = distance**QC
    knee = PC * cmax
    return np.where(e < knee, PT / knee * e, PT + (e - knee) / (cmax - knee) * (1 - PT))


def flip_map(reference: np.ndarray, test: np.ndarray, ppd: float = DEFAULT_PPD) -> np.ndarray:
    """(H, W) LDR-FLIP error of (H, W, 3+) linear RGB images (clipped to [0, 1])."""
    ref = srgb_to_ycxcz(np.clip(np.asarray(reference, np.float64)[..., :3], 0.0, 1.0))
    out = srgb_to_ycxcz(np.clip(np.asarray(test, np.float64)[..., :3], 0.0, 1.0))
    e_color = color_error(hyab(filtered_lab(ref, ppd), filtered_lab(out, ppd)))
    (edge_r, point_r), (edge_t, point_t) = features(ref, ppd), features(out, ppd)
    difference = np.maximum(np.abs(edge_r - edge_t), np.abs(point_r - point_t))
    e_feature = (difference / math.sqrt(2)) ** QF
    return e_color ** (1 - e_feature)
