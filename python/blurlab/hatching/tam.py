"""Tonal art maps (docs/spec.md §5; Praun, Hoppe, Webb, Finkelstein 2001, "Real-Time Hatching").

A TAM is 6 tones of hatching strokes, lightest first, each a chain of mip levels (finest first,
every level half the size of the one before). Strokes nest: a stroke of a lighter tone is in
every darker tone, and a stroke of a coarser level is in every finer level, so blending tones or
levels never makes a stroke pop. Beside the six tone images a TAM holds, per level, the
threshold texture of Webb et al. 2002: each texel stores the darkness at which it turns to ink.

``generate`` builds one from a seed (the same seed gives the same bits); ``TAM(...)`` and
``TAM.from_images`` take the user's own, ``TAM.read``/``write`` keep one on disk through
OpenImageIO (one EXR per level: 6 tone channels and the threshold).

Ink is stored, not tone: 0 is paper, 1 is a fully covered texel.
"""

from __future__ import annotations

import math
import re
import weakref
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..io import images as io

TONES = 6
NEVER = 1.0  # threshold of texels no stroke covers: darkness never exceeds 1
# Hatching directions per tone, degrees from the u axis: single hatching in the light tones,
# cross-hatching from tone 4 on (Praun et al. 2001, Figure 2).
DIRECTIONS = (0.0, 0.0, 0.0, 90.0, 45.0, -45.0)


@dataclass(frozen=True)
class Stroke:
    """One stroke in texture units (the texture is [0, 1)² and repeats)."""

    x: float
    y: float
    angle: float  # radians from the u axis
    length: float  # texture units
    tone: int  # the tone (0..5) whose construction added it
    level: int  # the coarsest level (index, 0 = finest) that holds it


class TAM:
    """Six tones × mip levels of stroke ink, and the threshold texture of every level.

    ``tones``: one (6, S, S) array per level, finest first, S halving from level to level, ink
    in [0, 1]. ``thresholds``: one (S, S) array per level (darkness in (0, 1] at which the texel
    turns to ink; 1 = never), or None to derive them from the tones.
    """

    def __init__(self, tones, thresholds=None, strokes: tuple[Stroke, ...] = (), seed=None):
        if isinstance(tones, np.ndarray):
            tones = [tones]
        if not isinstance(tones, (list, tuple)) or not tones:
            raise ValueError("blurlab: tam tones must be a list of (6, S, S) arrays, finest first")
        levels = []
        for index, level in enumerate(tones):
            levels.append(_ink_array(level, f"tam tones level {index}"))
        size = levels[0].shape[1]
        for index, level in enumerate(levels):
            expected = (TONES, size >> index, size >> index)
            if level.shape != expected or (size >> index) << index != size:
                raise ValueError(
                    f"blurlab: tam tones level {index} has shape {level.shape}, expected "
                    f"{expected} (each level half the size of the one before)"
                )
        self.tones = levels
        if thresholds is None:
            thresholds = [derived_thresholds(level) for level in levels]
        if not isinstance(thresholds, (list, tuple)) or len(thresholds) != len(levels):
            raise ValueError(
                f"blurlab: tam thresholds must be a list of {len(levels)} (S, S) arrays, one per "
                "level"
            )
        self.thresholds = []
        for index, (thr, level) in enumerate(zip(thresholds, levels, strict=True)):
            thr = np.asarray(thr)
            if thr.shape != level.shape[1:] or thr.dtype.kind != "f":
                raise ValueError(
                    f"blurlab: tam thresholds level {index} must be a float array of shape "
                    f"{level.shape[1:]}, not {thr.dtype}{thr.shape}"
                )
            if not (np.isfinite(thr).all() and thr.min() > 0 and thr.max() <= NEVER):
                raise ValueError(f"blurlab: tam thresholds level {index} must lie in (0, 1]")
            self.thresholds.append(np.ascontiguousarray(thr, dtype=np.float32))
        self.strokes = tuple(strokes)
        self.seed = seed
        self._gpu: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()

    @property
    def sizes(self) -> list[int]:
        return [level.shape[1] for level in self.tones]

    def darkness(self) -> np.ndarray:
        """(levels, 6): the mean ink of each tone at each level."""
        return np.array([level.reshape(TONES, -1).mean(1) for level in self.tones])

    def __repr__(self) -> str:
        return f"<blurlab.TAM {TONES} tones, levels {self.sizes}, seed={self.seed}>"

    # --- files -------------------------------------------------------------------------------

    def write(self, folder: str | Path) -> list[Path]:
        """Writes one EXR per level, ``tam_<S>.exr``: 7 float channels, the 6 tones' ink then the
        threshold. Each file is written atomically (blurlab.io.write)."""
        folder = Path(folder)
        if not folder.is_dir():
            raise FileNotFoundError(f"blurlab: tam folder {str(folder)!r} does not exist")
        paths = []
        for tones, thr in zip(self.tones, self.thresholds, strict=True):
            image = np.concatenate([tones.transpose(1, 2, 0), thr[..., None]], axis=2)
            paths.append(io.write(folder / f"tam_{tones.shape[1]}.exr", image.astype(np.float32)))
        return paths

    @classmethod
    def read(cls, folder: str | Path) -> TAM:
        """Reads the files ``write`` made (every ``tam_<S>.exr`` in the folder)."""
        folder = Path(folder)
        found = {}
        for path in folder.glob("tam_*.exr") if folder.is_dir() else ():
            match = re.fullmatch(r"tam_(\d+)\.exr", path.name)
            if match:
                found[int(match.group(1))] = path
        if not found:
            raise FileNotFoundError(f"blurlab: no tam_<size>.exr files in {str(folder)!r}")
        tones, thresholds = [], []
        for size in sorted(found, reverse=True):
            image = io.read(found[size])
            if image.shape != (size, size, TONES + 1):
                raise ValueError(
                    f"blurlab: {found[size].name} has shape {image.shape}, expected "
                    f"({size}, {size}, {TONES + 1})"
                )
            tones.append(np.ascontiguousarray(image[..., :TONES].transpose(2, 0, 1)))
            thresholds.append(image[..., TONES])
        return cls(tones, thresholds)

    @classmethod
    def from_images(cls, images, levels: int | None = None) -> TAM:
        """A TAM from six pictures of hatching, lightest first: dark strokes on white paper.

        Each item is an array or a path read through OpenImageIO (8-bit values are taken as
        coverage: ink = 1 − value/255; channels are averaged), or a list of such images, one per
        level, finest first. Single images get ``levels`` levels (default: down to 16 texels) by
        2×2 averaging.
        """
        if not isinstance(images, (list, tuple)) or len(images) != TONES:
            raise ValueError(f"blurlab: tam images must be {TONES} images (or lists of levels)")
        per_tone = []
        for tone, item in enumerate(images):
            chain = list(item) if isinstance(item, (list, tuple)) else [item]
            chain = [_picture_ink(image, f"tam image of tone {tone + 1}") for image in chain]
            if len(chain) == 1:
                count = levels or max(1, int(math.log2(max(chain[0].shape[0] // 16, 1))) + 1)
                while len(chain) < count:
                    previous = chain[-1]
                    if previous.shape[0] % 2:
                        raise ValueError(
                            f"blurlab: tam image of tone {tone + 1} cannot be halved to "
                            f"{count} levels"
                        )
                    chain.append(previous.reshape(previous.shape[0] // 2, 2, -1, 2).mean((1, 3)))
            per_tone.append(chain)
        if len({len(chain) for chain in per_tone}) != 1:
            raise ValueError("blurlab: every tone of a tam needs the same number of levels")
        tones = []
        for level in range(len(per_tone[0])):
            shapes = {chain[level].shape for chain in per_tone}
            if len(shapes) != 1:
                raise ValueError(f"blurlab: tam images differ in size at level {level}: {shapes}")
            tones.append(np.stack([chain[level] for chain in per_tone]).astype(np.float32))
        return cls(tones)

    # --- GPU ---------------------------------------------------------------------------------

    def textures(self, ctx):
        """(tones 1–3 as RGB, tones 4–6 as RGB, thresholds) on ``ctx``: mip chains uploaded level
        by level, trilinear and repeating; made once per context."""
        if ctx not in self._gpu:
            count = len(self.tones)
            size = self.sizes[0]
            low = ctx.native.texture(size, size, 3, "float16", count)
            high = ctx.native.texture(size, size, 3, "float16", count)
            thresholds = ctx.native.texture(size, size, 1, "float32", count)
            for level, (tones, thr) in enumerate(zip(self.tones, self.thresholds, strict=True)):
                rgb = tones.transpose(1, 2, 0).astype(np.float16)
                low.upload_level(level, np.ascontiguousarray(rgb[..., :3]))
                high.upload_level(level, np.ascontiguousarray(rgb[..., 3:]))
                thresholds.upload_level(level, np.ascontiguousarray(thr[..., None]))
            for texture in (low, high, thresholds):
                texture.use_mipmaps()
            self._gpu[ctx] = (low, high, thresholds)
        return self._gpu[ctx]


def derived_thresholds(tones: np.ndarray) -> np.ndarray:
    """Thresholds of a TAM given only as tone images: a texel turns to ink at the tone where
    its ink first reaches 0.5, at the darkness halfway between that tone's mean ink and the
    previous one's (so that the threshold scheme's coverage follows the tones)."""
    darkness = tones.reshape(TONES, -1).mean(1).astype(np.float64)
    steps = (np.concatenate([[0.0], darkness[:-1]]) + darkness) / 2
    steps = np.clip(steps, 1e-4, NEVER)
    thr = np.full(tones.shape[1:], NEVER, np.float32)
    for tone in reversed(range(TONES)):
        thr[tones[tone] >= 0.5] = steps[tone]
    return thr


def generate(
    size: int = 256,
    levels: int = 5,
    seed: int = 0,
    stroke=None,
    stroke_width: float = 1.25,
    stroke_length: tuple[float, float] = (0.3, 0.6),
    darkness=None,
    candidates: int = 6,
) -> TAM:
    """Builds a TAM as Praun et al. 2001 do: tone by tone, lightest first, and within a tone
    level by level, coarsest first, strokes are added to a level until its mean ink reaches the
    tone's darkness; each stroke goes into that level, every finer level, and every darker tone.
    Of `candidates` random strokes the one that adds the most new ink is kept (even spacing).

    ``size``: the finest level, a power of two; ``levels``: how many (each half the last,
    the coarsest at least 8 texels). ``stroke``: None (a tapered line) or an image of one stroke
    lying along x, dark on white (an array or a path), stretched to the stroke's length and
    ``stroke_width``. ``stroke_width`` in texels at every level; ``stroke_length`` (min, max) in
    texture units. ``darkness``: the 6 target mean inks, increasing (default k/6, the tone
    six_way assumes). Same arguments and seed → the same bits.
    """
    if isinstance(size, bool) or not isinstance(size, int) or size < 8 or size & (size - 1):
        raise ValueError(f"blurlab: tam size must be a power of two >= 8, not {size!r}")
    if isinstance(levels, bool) or not isinstance(levels, int) or levels < 1:
        raise ValueError(f"blurlab: tam levels must be an integer >= 1, not {levels!r}")
    if size >> (levels - 1) < 8:
        raise ValueError(
            f"blurlab: tam levels={levels} makes the coarsest level {size >> (levels - 1)} "
            "texels; it must be at least 8"
        )
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        raise ValueError(f"blurlab: tam seed must be an integer >= 0, not {seed!r}")
    if not (isinstance(stroke_width, (int, float)) and 0.5 <= stroke_width <= 4.0):
        raise ValueError(f"blurlab: stroke_width must be in [0.5, 4] texels, not {stroke_width!r}")
    try:
        low, high = (float(v) for v in stroke_length)
    except (TypeError, ValueError):
        raise ValueError(
            f"blurlab: stroke_length must be (min, max), not {stroke_length!r}"
        ) from None
    if not 0.05 <= low <= high <= 1.0:
        raise ValueError(
            f"blurlab: stroke_length must satisfy 0.05 <= min <= max <= 1, not {stroke_length!r}"
        )
    if darkness is None:
        darkness = np.arange(1, TONES + 1) / TONES
    darkness = np.asarray(darkness, dtype=np.float64)
    if (
        darkness.shape != (TONES,)
        or not np.isfinite(darkness).all()
        or darkness[0] <= 0
        or darkness[-1] > 1
        or np.any(np.diff(darkness) <= 0)
    ):
        raise ValueError(
            f"blurlab: darkness must be {TONES} increasing values in (0, 1], not {darkness!r}"
        )
    if isinstance(candidates, bool) or not isinstance(candidates, int) or candidates < 1:
        raise ValueError(f"blurlab: candidates must be an integer >= 1, not {candidates!r}")
    profile = None if stroke is None else _picture_ink(stroke, "stroke")

    rng = np.random.default_rng(seed)
    sizes = [size >> i for i in range(levels)]  # finest first
    ink = [np.zeros((s, s), np.float64) for s in sizes]
    thresholds = [np.full((s, s), NEVER, np.float32) for s in sizes]
    tones = [np.zeros((TONES, s, s), np.float32) for s in sizes]
    strokes: list[Stroke] = []
    total = [0.0] * levels  # running sums of ink, one per level
    covered = [0] * levels  # texels with ink >= 0.5 (a threshold), one count per level
    for tone in range(TONES):
        base = math.radians(DIRECTIONS[tone])
        for level in reversed(range(levels)):  # coarsest first
            s = sizes[level]
            area = s * s
            target = darkness[tone] * area
            # A stroke's ink when it overlaps nothing: stopping when the best candidate adds less
            # than 5 % of that ends the darkest tone where strokes only cover each other.
            full = low * s * stroke_width
            while total[level] < target:
                best, best_gain = None, -1.0
                for _ in range(candidates):
                    x, y = rng.random(2)
                    angle = base + rng.normal(0.0, math.radians(4.0))
                    length = rng.uniform(low, high)
                    stamp = _stamp(x, y, angle, length, s, stroke_width, profile)
                    gain = np.maximum(stamp[2] - ink[level][stamp[0], stamp[1]], 0.0).sum()
                    if gain > best_gain:
                        best, best_gain = (x, y, angle, length), gain
                if best_gain < 0.05 * full:
                    break
                strokes.append(Stroke(*best, tone=tone, level=level))
                for finer in range(level, -1, -1):
                    rows, cols, value = _stamp(*best, sizes[finer], stroke_width, profile)
                    old = ink[finer][rows, cols]
                    new = np.maximum(old, value)
                    total[finer] += (new - old).sum()
                    ink[finer][rows, cols] = new
                    # Webb et al. 2002: each texel turns to ink at the darkness its level has once
                    # its stroke is in. The tag is this level's covered fraction halfway through
                    # adding the stroke, so that at every level the texels with threshold < d
                    # cover about d: the threshold scheme's tone is calibrated per level.
                    r, c = rows[value >= 0.5], cols[value >= 0.5]
                    fresh = thresholds[finer][r, c] == NEVER
                    count = int(fresh.sum())
                    tag = (covered[finer] + count / 2) / sizes[finer] ** 2
                    thresholds[finer][r[fresh], c[fresh]] = max(tag, 1e-4)
                    covered[finer] += count
        for level in range(levels):
            tones[level][tone] = ink[level]
    return TAM(tones, thresholds, tuple(strokes), seed=seed)


def render_strokes(strokes, size: int, stroke_width: float = 1.25, stroke=None) -> np.ndarray:
    """(size, size) ink of the given strokes at one level (as ``generate`` draws them)."""
    profile = None if stroke is None else _picture_ink(stroke, "stroke")
    out = np.zeros((size, size), np.float64)
    for st in strokes:
        rows, cols, value = _stamp(st.x, st.y, st.angle, st.length, size, stroke_width, profile)
        out[rows, cols] = np.maximum(out[rows, cols], value)
    return out


def _stamp(x, y, angle, length, size, width, profile):
    """The texels a stroke touches at a level of `size` texels: rows, cols (wrapped) and ink.

    The default stroke is a line of `width` texels tapering to 40 % at its ends, with round
    caps, antialiased by its distance to the texel center (a one-texel ramp).
    """
    direction = np.array([math.cos(angle), math.sin(angle)])
    half = length * size / 2
    center = np.array([x, y]) * size
    p0, p1 = center - direction * half, center + direction * half
    margin = width / 2 + 1.5
    lo = np.floor(np.minimum(p0, p1) - margin).astype(int)
    hi = np.ceil(np.maximum(p0, p1) + margin).astype(int)
    cols, rows = np.meshgrid(np.arange(lo[0], hi[0]), np.arange(lo[1], hi[1]))
    q = np.stack([cols + 0.5, rows + 0.5], -1) - p0
    along = np.clip(q @ direction / (2 * half), 0.0, 1.0)
    if profile is None:
        across = np.linalg.norm(q - along[..., None] * direction * 2 * half, axis=-1)
        taper = 0.4 + 0.6 * np.minimum(1.0, np.minimum(along, 1.0 - along) * 6.0)
        value = np.clip(width / 2 * taper + 0.5 - across, 0.0, 1.0)
    else:
        normal = np.array([-direction[1], direction[0]])
        raw_along = q @ direction / (2 * half)
        across = (q @ normal) / width + 0.5
        value = _bilinear(profile, raw_along, across)
    keep = value > 0
    rows, cols, value = rows[keep] % size, cols[keep] % size, value[keep]
    if hi[0] - lo[0] > size or hi[1] - lo[1] > size:  # wraps onto itself: one value per texel
        canvas = np.zeros((size, size))
        np.maximum.at(canvas, (rows, cols), value)
        rows, cols = np.nonzero(canvas)
        value = canvas[rows, cols]
    return rows, cols, value


def _bilinear(image, u, v):
    """Samples `image` at (u, v) in [0, 1]² (u along columns), zero outside."""
    h, w = image.shape
    px, py = u * w - 0.5, v * h - 0.5
    x0, y0 = np.floor(px).astype(int), np.floor(py).astype(int)
    fx, fy = px - x0, py - y0
    padded = np.pad(image, 1)

    def at(yy, xx):
        return padded[np.clip(yy + 1, 0, h + 1), np.clip(xx + 1, 0, w + 1)]

    top = at(y0, x0) * (1 - fx) + at(y0, x0 + 1) * fx
    bottom = at(y0 + 1, x0) * (1 - fx) + at(y0 + 1, x0 + 1) * fx
    inside = (u >= 0) & (u <= 1) & (v >= 0) & (v <= 1)
    return np.where(inside, top * (1 - fy) + bottom * fy, 0.0)


def _picture_ink(image, what: str) -> np.ndarray:
    """A picture of strokes (dark on white; array or path) as (H, W) float64 ink in [0, 1]."""
    if isinstance(image, (str, Path)):
        image = io.read(image)
    if not isinstance(image, np.ndarray):
        raise ValueError(f"blurlab: {what} must be an array or an image path, not {type(image)}")
    if image.ndim == 3 and image.shape[2] in (1, 2, 3, 4):
        image = (
            image[..., : min(3, image.shape[2])].mean(axis=2)
            if image.shape[2] != 2
            else image[..., 0]
        )
    if image.ndim != 2 or image.size == 0:
        raise ValueError(f"blurlab: {what} of shape {image.shape} is not an (H, W[, C]) image")
    if image.dtype == np.uint8:
        value = image / 255.0
    elif image.dtype.kind == "f":
        value = image.astype(np.float64)
    else:
        raise ValueError(f"blurlab: {what} has dtype {image.dtype}; use uint8 or float")
    if not np.isfinite(value).all() or value.min() < 0 or value.max() > 1:
        raise ValueError(f"blurlab: {what} values must be finite and in [0, 1]")
    return 1.0 - value


def _ink_array(level, what: str) -> np.ndarray:
    array = np.asarray(level)
    if array.dtype == np.uint8:
        array = array / 255.0
    if array.dtype.kind != "f":
        raise ValueError(
            f"blurlab: {what} has dtype {array.dtype}; use float ink in [0, 1] or uint8"
        )
    if array.ndim != 3 or array.shape[0] != TONES or array.shape[1] != array.shape[2]:
        raise ValueError(f"blurlab: {what} has shape {array.shape}, expected (6, S, S)")
    if array.shape[1] < 1 or array.shape[1] & (array.shape[1] - 1):
        raise ValueError(f"blurlab: {what} size {array.shape[1]} is not a power of two")
    if not np.isfinite(array).all() or array.min() < 0 or array.max() > 1:
        raise ValueError(f"blurlab: {what} must hold finite ink in [0, 1]")
    return np.ascontiguousarray(array, dtype=np.float32)


_DEFAULT: dict = {}


def default_tam() -> TAM:
    """The TAM hatched materials use when given none: ``generate()`` with its defaults, made
    once per process."""
    if "tam" not in _DEFAULT:
        _DEFAULT["tam"] = generate()
    return _DEFAULT["tam"]
