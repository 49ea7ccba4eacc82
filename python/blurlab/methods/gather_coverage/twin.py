"""gather_coverage, docs/spec.md §17.6, in NumPy float64: on each half-shutter of the two-sided
motion (§17.1), the share of the half-shutter during which moving pixels cover X (their trails
gathered along the dilated tile motion and along X's own motion), the rest filled by what lies
behind X. Its parts (tile lines, tap plan, trail weights) are blurlab.twins.coverage; tiles are
engine_eevee's flatten and dilation (blurlab.twins.eevee). GPU twin: gather.glsl beside it.
"""

from __future__ import annotations

import numpy as np

from ...twins.coverage import (
    MOVING,
    MOVING_DEPTH,
    TapPlan,
    family_overlap,
    hot,
    quad_corner,
    tap_layout,
    tap_offset,
    tap_offset_along,
    tap_plan,
    trail_weights,
)
from ...twins.film import film_filter as apply_film_filter
from ...twins.film import film_spread, own_color, tap_color
from ...twins.hashing import rand
from ...twins.inputs import sanitize_color, sanitize_depth
from ...twins.mcguire2012 import soft_depth_compare


def uniform_gather(x_color, depth, plan: TapPlan, j, tolerance: float, samples: int, read):
    """§17.6.1, the uniform-motion path: per side the mean of X and of the taps along the tile's
    line, but those in front of X whose own trail lies further than `tolerance` px from the
    line (what does not move with X stands over it only where it is; what lies behind showed
    where X's object was not); the mean of the two sides. `read(px, py, k)` is the colour of
    tap k = side·samples + i."""
    h, w = x_color.shape[:2]
    y, x = np.mgrid[0:h, 0:w]
    center = np.stack([x, y], -1) + 0.5
    out = np.zeros_like(x_color)
    for side, (line, trails) in enumerate(zip(plan.lines, (plan.prev, -plan.next_), strict=True)):
        total, kept = x_color.copy(), np.ones((h, w))
        count = np.maximum(plan.taps, 1)
        for i in range(int(plan.taps.max(initial=0))):
            t = (i + tap_offset(j, 0, side)) / count
            p = np.floor(center + line * t[..., None]).astype(np.int64)
            py, px = np.clip(p[..., 1], 0, h - 1), np.clip(p[..., 0], 0, w - 1)
            agrees = np.linalg.norm(trails[py, px] - line, axis=-1) <= tolerance
            use = (i < plan.taps) & (agrees | (depth[py, px] >= depth))
            total = total + use[..., None] * read(px, py, side * samples + i)
            kept = kept + use
        out = out + 0.5 * total / kept[..., None]
    return out


def gather_coverage(
    color,
    depth,
    motion_prev,
    motion_next,
    *,
    tile_percent: float,
    samples: int,
    max_blur: float,
    soft_z: float,
    exposure: float,
    seed: int,
    film_filter: float,
    film_through_taps: bool,
    tap_spacing: float,
    early_exit: float,
    uniform_tolerance: float,
    half_res_above: float,
    dilated: np.ndarray | None = None,
) -> np.ndarray:
    """§17.6: (H, W, C) float64 blurred color. `max_blur` is a percentage of the height;
    `film_filter` the σ (px) of the Gaussian film filter on the result, 0 for none; with
    `film_through_taps`, the filter is read through the taps' colours instead (tap k through
    film.tap_color, X through film.own_color, at d = film_spread(σ)), not applied after;
    `tap_spacing`, `early_exit`, `uniform_tolerance` and `half_res_above` choose each pixel's
    taps and path (tap_plan); `dilated` is the dilated tile grid if already computed."""
    color = sanitize_color(color)
    through_taps = film_through_taps and film_filter > 0
    spread = film_spread(film_filter) if through_taps else 0.0
    x_color = own_color(color, spread) if through_taps else color
    depth = sanitize_depth(depth)
    h, w = depth.shape
    plan = tap_plan(
        motion_prev,
        motion_next,
        tile_percent=tile_percent,
        samples=samples,
        max_blur=max_blur,
        exposure=exposure,
        seed=seed,
        tap_spacing=tap_spacing,
        early_exit=early_exit,
        uniform_tolerance=uniform_tolerance,
        half_res_above=half_res_above,
        dilated=dilated,
    )
    prev, next_, lines = plan.prev, plan.next_, plan.lines
    y, x = np.mgrid[0:h, 0:w]

    def read(px, py, k):
        return tap_color(color, px, py, k, spread) if through_taps else color[py, px]

    x_moves = np.maximum(np.linalg.norm(prev, axis=-1), np.linalg.norm(next_, axis=-1)) >= MOVING
    # Where X moves, a tap counts as in front within MOVING_DEPTH times X's depth (in effect at
    # any depth): the surface of X's own object turns and tilts; where X is still, §3's soft_z.
    finite = np.isfinite(depth)
    front_extent = np.where(
        x_moves & finite, np.maximum(soft_z, MOVING_DEPTH * np.where(finite, depth, 0)), soft_z
    )
    j = rand(x, y, seed)
    center = np.stack([x, y], -1) + 0.5
    behind_sum, behind_weight = np.zeros_like(color), np.zeros((h, w))
    bend = (next_ - prev) / 2
    sides = []
    # Each family's taps on this pixel: the side's taps split as tap_layout splits `samples`.
    counts = (np.maximum((plan.taps + 1) // 2, 1), np.maximum(plan.taps // 2, 1))
    # Prev side: the pixels whose way back to t0 crosses X lie at +τ·prev; next side: those
    # whose way on to t1 crosses X at -τ·next. Each is read as a trail towards X.
    for side, trails in enumerate((prev, -next_)):
        line, own = lines[side], trails
        first_tap = side * samples  # tap k = side·samples + i turns the film's offsets
        own_moves = np.linalg.norm(own, axis=-1) >= MOVING
        share = 1 / (1 + family_overlap(line, own))
        cover_sum, cover = np.zeros_like(color), np.zeros((h, w))
        spaced, seen = np.zeros((h, w)), np.zeros((h, w))
        for tap, (family, i, _) in enumerate(tap_layout(samples)):
            count = counts[family]
            along = np.where((family & own_moves)[..., None], own, line)
            # taps beyond the pixel's count weigh nothing
            spacing = (tap < plan.taps) * np.linalg.norm(along, axis=-1) / count * share
            t = (i + tap_offset(j, family, side)) / count
            bent = np.where((family & own_moves)[..., None], bend, 0.0)
            p = np.floor(center + tap_offset_along(along, bent, t)).astype(np.int64)
            py, px = np.clip(p[..., 1], 0, h - 1), np.clip(p[..., 0], 0, w - 1)
            cy = read(px, py, first_tap + tap)
            d = np.stack([px - x, py - y], -1).astype(np.float64)
            speed = np.linalg.norm(trails[py, px], axis=-1)
            moving = np.clip(speed - 0.5, 0, 1)
            zy = depth[py, px]
            reaches, on_pixel = trail_weights(d, trails[py, px], bend[py, px])
            in_front = soft_depth_compare(depth, zy, front_extent)
            # the share of the half-shutter the tap's trail spends on X, where it reaches X
            share_on_x = in_front * moving * spacing / np.maximum(speed, 1)
            a, a_hot = share_on_x * reaches, share_on_x * on_pixel
            cover = cover + a
            # Colour past display white counts only where the tap's own pixel crosses X.
            cover_sum = cover_sum + a[..., None] * cy - (a - a_hot)[..., None] * hot(cy)
            # A still tap in front of a moving X hides the part of X's line behind it: the
            # coverage is estimated from the part that is seen.
            nearer = 1 - soft_depth_compare(zy, depth, soft_z)
            spaced = spaced + spacing
            seen = seen + spacing * (1 - x_moves * nearer * (1 - moving))
            b = (1 - nearer) * (1 - soft_depth_compare(depth, zy, soft_z)) * (1 - reaches)
            b = b * (tap < plan.taps)
            behind_weight = behind_weight + b
            behind_sum = behind_sum + b[..., None] * cy
        sides.append(
            (cover_sum, cover, np.where(seen > 0, spaced / np.where(seen > 0, seen, 1), 1))
        )
    known = (behind_weight > 0) & x_moves
    background = np.where(
        known[..., None], behind_sum / np.where(known, behind_weight, 1.0)[..., None], x_color
    )
    out = np.zeros_like(color)
    for cover_sum, cover, scale in sides:
        alpha = np.minimum(cover * scale, 1.0)[..., None]
        covering = cover_sum / np.maximum(cover, 1e-12)[..., None]
        out = out + 0.5 * (alpha * covering + (1 - alpha) * background)
    if plan.fast.any():
        fast = uniform_gather(x_color, depth, plan, j, uniform_tolerance, samples, read)
        out = np.where(plan.fast[..., None], fast, out)
    out = np.where((plan.taps > 0)[..., None], out, x_color)
    # A long quad's four pixels take its top-left pixel's result.
    out = np.where(plan.half[..., None], out[quad_corner(y), quad_corner(x)], out)
    return out if through_taps else apply_film_filter(out, film_filter)
