"""engine_hdrp, docs/spec.md §17.4, in NumPy float64: the motion blur of Unity's High Definition
Render Pipeline as HDRP's public manual describes it. One function per pass; the GPU
passes (the shaders beside it) must match them.

Velocities travel polar, (length in px, turn), and depth as it is, in the unsigned small floats
of a B10G11R11 texture (twins.polar_small_float, twins.small_float). Tiles compare the length codes
themselves, exact floats, so the GPU and this twin choose the same tile among equal lengths.
"""

from __future__ import annotations

import math

import numpy as np

from ...twins.eevee import clamp_length
from ...twins.gathers import camera_motion, camera_rotation_motion
from ...twins.hashing import rand
from ...twins.inputs import sanitize_color, sanitize_depth, sanitize_motion
from ...twins.mcguire2012 import cone, cylinder, soft_depth_compare
from ...twins.polar_small_float import polar_codes, polar_decode
from ...twins.small_float import UF10_MANTISSA, quantize
from ...twins.tile_reach import reach_widening, segment_meets_box

EARLY_OUT, FAST, SLOW = 0, 1, 2
CLASS_NAMES = ("early_out", "fast", "slow")
GATHER_TILE, SCATTER_TILE = 32, 16  # px: the tile side without and with scattering
# The parameters of step 1, the velocity setup.
SETUP_PARAMS = (
    "intensity",
    "maximum_velocity",
    "camera_motion_blur",
    "camera_clamp_mode",
    "rotation_clamp",
    "translation_clamp",
    "motion_vector_clamp",
)
# Camera clamp modes whose clamp applies to the rotation, the translation, the whole camera.
ROTATION_CLAMPED = ("rotation", "separate")
TRANSLATION_CLAMPED = ("translation", "separate")


def tile_size(scatter: bool) -> int:
    return SCATTER_TILE if scatter else GATHER_TILE


def clamp_screen_fraction(v: np.ndarray, fraction: float, size) -> np.ndarray:
    """v with its length in screen units (v.x/W, v.y/H) clamped to `fraction`: HDRP's camera
    clamps, "a fraction of the screen's full resolution"."""
    width, height = size
    n = np.linalg.norm(v / [width, height], axis=-1, keepdims=True)
    with np.errstate(divide="ignore", invalid="ignore"):
        return v * np.where(n > fraction, fraction / n, 1.0)


def velocity(
    motion,
    depth,
    camera: dict | None,
    *,
    intensity: float,
    maximum_velocity: float,
    camera_motion_blur: bool,
    camera_clamp_mode: str,
    rotation_clamp: float,
    translation_clamp: float,
    motion_vector_clamp: float,
) -> np.ndarray:
    """§17.4 step 1, before packing: (H, W, 2) the velocity v in pixels. Without a camera (a
    frame made from arrays) the camera's own motion is taken as zero."""
    m = sanitize_motion(motion) * intensity
    h, w = m.shape[:2]
    split = camera is not None and (not camera_motion_blur or camera_clamp_mode != "none")
    if not split:
        return clamp_length(m, maximum_velocity)
    size = (w, h)
    whole = camera_motion(depth, camera, size) * intensity
    rotation = camera_rotation_motion(camera, size) * intensity
    if not camera_motion_blur:
        return clamp_length(m - whole, maximum_velocity)
    translation = whole - rotation
    if camera_clamp_mode == "full":
        return clamp_length(m - whole, maximum_velocity) + clamp_screen_fraction(
            whole, motion_vector_clamp, size
        )
    clamped = np.zeros_like(m)
    separated = np.zeros_like(m)
    if camera_clamp_mode in ROTATION_CLAMPED:
        clamped = clamped + clamp_screen_fraction(rotation, rotation_clamp, size)
        separated = separated + rotation
    if camera_clamp_mode in TRANSLATION_CLAMPED:
        clamped = clamped + clamp_screen_fraction(translation, translation_clamp, size)
        separated = separated + translation
    return clamp_length(m - separated, maximum_velocity) + clamped


def velocity_setup(depth, motion, camera=None, **params) -> np.ndarray:
    """§17.4 step 1: (H, W, 3) codes (length, turn, depth): the velocity polar in two unsigned
    11-bit floats and the linear depth Z in an unsigned 10-bit float (+inf stays +inf)."""
    v = velocity(motion, depth, camera, **params)
    z = quantize(sanitize_depth(depth).astype(np.float32), UF10_MANTISSA)
    return np.concatenate([polar_codes(v), z[..., None]], -1)


def tile_min_max(codes: np.ndarray, tile: int) -> np.ndarray:
    """§17.4 step 2: (ceil(H/s), ceil(W/s), 3) per s x s tile: the codes (length, turn) of its
    longest velocity, the first in row-major order among equal lengths, and its shortest length.
    """
    h, w = codes.shape[:2]
    th, tw = -(-h // tile), -(-w // tile)
    padded = np.full((th * tile, tw * tile, 3), np.nan)
    padded[:h, :w, :2] = codes[..., :2]
    blocks = padded.reshape(th, tile, tw, tile, 3).transpose(0, 2, 1, 3, 4)
    blocks = blocks.reshape(th, tw, tile * tile, 3)  # pixels in row-major order
    lengths = blocks[..., 0]
    longest = np.argmax(np.where(np.isnan(lengths), -1.0, lengths), axis=-1)
    best = np.take_along_axis(blocks[..., :2], longest[..., None, None], axis=2)[:, :, 0]
    shortest = np.nanmin(lengths, axis=-1)
    return np.concatenate([best, shortest[..., None]], -1)


def _shifted(tiles: np.ndarray, dy: int, dx: int):
    """tiles[T + (dy, dx)] for every T, and whether that tile lies in the grid."""
    th, tw = tiles.shape[:2]
    ys, xs = np.arange(th) + dy, np.arange(tw) + dx
    inside = ((ys >= 0) & (ys < th))[:, None] & ((xs >= 0) & (xs < tw))[None, :]
    return tiles[np.clip(ys, 0, th - 1)][:, np.clip(xs, 0, tw - 1)], inside


def neighborhood(tiles: np.ndarray) -> np.ndarray:
    """§17.4 step 3: (th, tw, 3): the longest of the 3 x 3 tiles around each tile (scanned row by
    row, a candidate wins only if strictly longer) and the shortest of their shortest lengths."""
    best = np.zeros(tiles.shape[:2] + (2,))
    best_length = np.full(tiles.shape[:2], -1.0)
    shortest = np.full(tiles.shape[:2], np.inf)
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            c, inside = _shifted(tiles, dy, dx)
            better = inside & (c[..., 0] > best_length)
            best_length = np.where(better, c[..., 0], best_length)
            best = np.where(better[..., None], c[..., :2], best)
            shortest = np.where(inside, np.minimum(shortest, c[..., 2]), shortest)
    return np.concatenate([best, shortest[..., None]], -1)


def scatter_radius(tile: int, reach_px: float, grid) -> int:
    """How many tiles away a tile's velocity can reach: ceil(reach/2/s) + 1 (its blur spans half
    its length on each side), at most the grid's longer side."""
    return min(math.ceil(reach_px / 2 / tile) + 1, max(grid))


def scatter_neighborhood(tiles: np.ndarray, tile: int, reach_px: float) -> np.ndarray:
    """§17.4 step 3 with scattering: for each tile D, the longest velocity among the tiles S whose
    blur reaches D, the segment from S's center ± v/2 (tile units) meeting D's square widened by
    h + REACH_MARGIN, h = 1/2 - 1/(2s) (first in row-major order among equal lengths); the
    shortest length still over the 3 x 3 tiles around D."""
    th, tw = tiles.shape[:2]
    radius = scatter_radius(tile, reach_px, (th, tw))
    widen = reach_widening(tile)
    best = np.zeros((th, tw, 2))
    best_length = np.full((th, tw), -1.0)
    for oy in range(-radius, radius + 1):
        for ox in range(-radius, radius + 1):
            c, inside = _shifted(tiles, oy, ox)
            v = polar_decode(c[..., :2]) / tile
            center = np.stack([np.full((th, tw), ox + 0.5), np.full((th, tw), oy + 0.5)], -1)
            reach = segment_meets_box(center - v / 2, v, -widen, 1 + widen)
            better = inside & reach & (c[..., 0] > best_length)
            best_length = np.where(better, c[..., 0], best_length)
            best = np.where(better[..., None], c[..., :2], best)
    return np.concatenate([best, neighborhood(tiles)[..., 2:]], -1)


def classify(neighbors: np.ndarray, minimum_velocity: float, fast_ratio: float) -> np.ndarray:
    """§17.4 step 4: (th, tw) EARLY_OUT where the neighbourhood's longest velocity is shorter
    than minimum_velocity; else FAST where its shortest is at least fast_ratio times its longest;
    else SLOW."""
    longest, shortest = neighbors[..., 0], neighbors[..., 2]
    classes = np.where(shortest >= fast_ratio * longest, FAST, SLOW)
    return np.where(longest < minimum_velocity, EARLY_OUT, classes)


def reach_px(size, params: dict) -> float:
    """The longest velocity the setup can make, in pixels: maximum_velocity plus the camera
    clamps that the mode adds (each at most fraction x the longer image side)."""
    mode, longer = params["camera_clamp_mode"], max(size)
    extra = 0.0
    if mode in ROTATION_CLAMPED:
        extra += params["rotation_clamp"]
    if mode in TRANSLATION_CLAMPED:
        extra += params["translation_clamp"]
    if mode == "full":
        extra += params["motion_vector_clamp"]
    return params["maximum_velocity"] + extra * longer


def tap_count(longest: np.ndarray, samples: int) -> np.ndarray:
    """n = clamp(floor(L), 1, samples): taps along the velocity's whole length L stay at least a
    pixel apart ("no two samples are less than a pixel apart", HDRP's manual)."""
    return np.clip(np.floor(longest), 1, samples).astype(np.int64)


def engine_hdrp(
    color,
    depth,
    motion,
    camera,
    *,
    samples: int,
    intensity: float,
    maximum_velocity: float,
    minimum_velocity: float,
    depth_comparison_extent: float,
    camera_motion_blur: bool,
    camera_clamp_mode: str,
    rotation_clamp: float,
    translation_clamp: float,
    motion_vector_clamp: float,
    scatter: bool,
    fast_ratio: float,
    seed: int,
) -> np.ndarray:
    """§17.4 step 5: (H, W, C) float64 blurred color."""
    color = sanitize_color(color)
    h, w = color.shape[:2]
    setup = {
        "intensity": intensity,
        "maximum_velocity": maximum_velocity,
        "camera_motion_blur": camera_motion_blur,
        "camera_clamp_mode": camera_clamp_mode,
        "rotation_clamp": rotation_clamp,
        "translation_clamp": translation_clamp,
        "motion_vector_clamp": motion_vector_clamp,
    }
    codes = velocity_setup(depth, motion, camera, **setup)
    s = tile_size(scatter)
    tiles = tile_min_max(codes, s)
    if scatter:
        neighbors = scatter_neighborhood(tiles, s, reach_px((w, h), setup))
    else:
        neighbors = neighborhood(tiles)
    classes = classify(neighbors, minimum_velocity, fast_ratio)

    y, x = np.mgrid[0:h, 0:w]
    cls = classes[y // s, x // s]
    vmax = polar_decode(neighbors[y // s, x // s, :2])
    n = tap_count(neighbors[y // s, x // s, 0], samples)
    j = rand(x, y, seed)
    center = np.stack([x, y], -1) + 0.5
    own = np.stack([codes[..., 0] / 2, np.zeros((h, w))], -1)  # radius: half the length
    z = codes[..., 2]
    fast_sum = color.copy()
    slow_weight = 1 / np.maximum(own[..., 0], 0.5)
    slow_sum = color * slow_weight[..., None]
    for i in range(samples):
        active = i < n
        t = (i + j) / n - 0.5
        p = np.floor(center + vmax * t[..., None]).astype(np.int64)
        py, px = np.clip(p[..., 1], 0, h - 1), np.clip(p[..., 0], 0, w - 1)
        tap = color[py, px]
        fast_sum = fast_sum + np.where(active[..., None], tap, 0.0)
        dist = np.hypot(px - x, py - y)
        other = own[py, px]
        front = soft_depth_compare(z, z[py, px], depth_comparison_extent)
        back = soft_depth_compare(z[py, px], z, depth_comparison_extent)
        a = front * cone(dist, other) + back * cone(dist, own)
        a = a + 2 * cylinder(dist, other) * cylinder(dist, own)
        a = np.where(active, a, 0.0)
        slow_weight = slow_weight + a
        slow_sum = slow_sum + a[..., None] * tap
    fast = fast_sum / (n + 1)[..., None]
    slow = slow_sum / slow_weight[..., None]
    picked = np.where((cls == FAST)[..., None], fast, slow)
    return np.where((cls == EARLY_OUT)[..., None], color, picked)
