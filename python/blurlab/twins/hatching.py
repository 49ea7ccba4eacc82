"""Tonal-art-map hatching, docs/spec.md §5, in NumPy float64 (GPU twin:
shaders/common/hatching.glsl, used by the G-buffer pass). Tones are numbered 0 (white paper) to
6 (the darkest TAM tone); darkness = 1 − intensity."""

from __future__ import annotations

import numpy as np

LUMINANCE = np.array([0.2126, 0.7152, 0.0722])


def intensity(normal, view, light, light_color, ambient, specular=0.0, shininess=32.0):
    """The tone source: the luminance of Lambert (specular = 0) or Blinn–Phong light on a white
    surface, clamped to [0, 1]. Unit vectors, (..., 3); `normal` is turned toward the viewer."""
    n, v, s = (np.asarray(a, np.float64) for a in (normal, view, light))
    n = np.where((n * v).sum(-1, keepdims=True) < 0, -n, n)
    diffuse = np.maximum((n * s).sum(-1), 0.0)
    h = s + v
    h = h / np.linalg.norm(h, axis=-1, keepdims=True)
    highlight = np.where(
        (diffuse > 0) & (specular > 0),
        specular * np.maximum((n * h).sum(-1), 0.0) ** shininess,
        0.0,
    )
    light_lum = float(np.dot(light_color, LUMINANCE))
    ambient_lum = float(np.dot(ambient, LUMINANCE))
    return np.clip(ambient_lum + light_lum * (diffuse + highlight), 0.0, 1.0)


def six_way_weights(intensity) -> np.ndarray:
    """(..., 7): the weights of tones 0..6 for `intensity` (any shape). Tone t = 6·(1 − I); the
    two nearest tones i = ⌊t⌋ and i + 1 get 1 − (t − i) and t − i, every other tone 0."""
    t = 6.0 * (1.0 - np.clip(np.asarray(intensity, np.float64), 0.0, 1.0))
    i = np.minimum(np.floor(t), 5.0).astype(np.int64)
    f = t - i
    weights = np.zeros(t.shape + (7,))
    np.put_along_axis(weights, i[..., None], (1.0 - f)[..., None], axis=-1)
    np.put_along_axis(weights, (i + 1)[..., None], f[..., None], axis=-1)
    return weights


def six_way_ink(weights, tones) -> np.ndarray:
    """Σ w_k · stroke_k: `weights` (..., 7) from six_way_weights, `tones` (6, ...) the ink of
    tones 1..6 at the same points (tone 0, paper, has none)."""
    weights = np.asarray(weights, np.float64)
    tones = np.moveaxis(np.asarray(tones, np.float64), 0, -1)
    return (weights[..., 1:] * tones).sum(-1)


def threshold_ink(thresholds, uv, darkness) -> np.ndarray:
    """The threshold rule at one mip level. A texel is ink where its threshold < darkness; the 4
    texels around uv (texture units, the map repeats) are blended with weights smoothstep(fract)
    in x and y: a smooth step one texel wide across every stroke edge.

    `thresholds` (S, S); `uv` (..., 2); `darkness` broadcast against uv[..., 0].
    """
    thr = np.asarray(thresholds, np.float64)
    size = np.array(thr.shape[::-1], np.float64)  # (width, height)
    p = np.asarray(uv, np.float64) * size - 0.5
    corner = np.floor(p).astype(np.int64)
    f = p - corner
    f = f * f * (3.0 - 2.0 * f)
    darkness = np.asarray(darkness, np.float64)

    def ink(dx, dy):
        x = (corner[..., 0] + dx) % thr.shape[1]
        y = (corner[..., 1] + dy) % thr.shape[0]
        return (thr[y, x] < darkness).astype(np.float64)

    top = ink(0, 0) * (1 - f[..., 0]) + ink(1, 0) * f[..., 0]
    bottom = ink(0, 1) * (1 - f[..., 0]) + ink(1, 1) * f[..., 0]
    return top * (1 - f[..., 1]) + bottom * f[..., 1]


def patch_ink(tam, scheme: str, darkness, level: int = 0) -> np.ndarray:
    """Mean ink of a flat-lit patch that shows a whole number of TAM tiles at `level`, for each
    value of `darkness`: what a hatched patch should measure (docs/spec.md §5, tone
    reproduction)."""
    darkness = np.atleast_1d(np.asarray(darkness, np.float64))
    if scheme == "six_way":
        means = tam.tones[level].reshape(6, -1).mean(1).astype(np.float64)
        return six_way_weights(1.0 - darkness)[..., 1:] @ means
    thr = tam.thresholds[level].astype(np.float64).ravel()
    return (thr[None, :] < darkness[:, None]).mean(1)
