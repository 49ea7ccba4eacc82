"""Per-object errors from the object-id buffer: the OGRE paper's Table 1 redone with accuracy.

`textured_spin` has four textures (low, medium and high contrast, rainbow), each on a sphere
turning slowly and on one turning fast. For each sphere, accumulation is compared with
stochastic blur at matched render counts (stochastic renders 4 jittered views per time slice,
so K slices cost 4K renders, as accumulation of 4K sub-frames does): the PSNR of that sphere
against the converged reference, and each method's time for the whole frame.
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from .. import metrics, scenes
from ..converged import default_reference_samples
from ..methods import blur

TEXTURES = ("low contrast", "medium contrast", "high contrast", "rainbow")
RENDERS = (8, 16, 32)


def object_boxes(frame) -> dict[int, tuple[int, int, int, int]]:
    """(y0, y1, x0, x1) of each object seen in `frame`: its pixels at the G-buffer's instant,
    widened by half its longest motion (+1 px) so that its blur over the shutter is inside."""
    boxes = {}
    height, width = frame.object_id.shape
    for object_id in np.unique(frame.object_id[frame.object_id >= 0]):
        ys, xs = np.nonzero(frame.object_id == object_id)
        speed = np.linalg.norm(frame.motion[ys, xs], axis=-1)
        speed = speed[np.isfinite(speed)]
        margin = math.ceil(float(speed.max()) / 2 if speed.size else 0.0) + 1
        boxes[int(object_id)] = (
            max(0, int(ys.min()) - margin),
            min(height, int(ys.max()) + 1 + margin),
            max(0, int(xs.min()) - margin),
            min(width, int(xs.max()) + 1 + margin),
        )
    return boxes


def object_errors(ctx, size=(640, 360), renders=RENDERS, reference_samples=None) -> pd.DataFrame:
    """One row per sphere of textured_spin and render count: its texture and rotation, the
    PSNR of accumulation and of stochastic blur inside the sphere's box, and their times."""
    scene = scenes.get("textured_spin")
    frame = ctx.render(scene, size)
    n = reference_samples or default_reference_samples(frame)
    reference = ctx.reference(scene, size, samples=n, progress=False).color
    boxes = object_boxes(frame)
    rows = []
    for count in renders:
        accumulation = blur(ctx, frame, "accumulation", samples=count)
        stochastic = blur(ctx, frame, "stochastic", slices=max(1, count // 4))
        for object_id, (y0, y1, x0, x1) in sorted(boxes.items()):
            name = scene.objects[object_id].name
            crop = np.s_[y0:y1, x0:x1]
            rows.append(
                {
                    "object": name,
                    "texture": TEXTURES[int(name[len("sphere")])],
                    "rotation": name.rsplit("_", 1)[1],
                    "renders": count,
                    "psnr_accumulation": metrics.psnr(reference[crop], accumulation.color[crop]),
                    "psnr_stochastic": metrics.psnr(reference[crop], stochastic.color[crop]),
                    "ms_accumulation": accumulation.total_ms,
                    "ms_stochastic": stochastic.total_ms,
                    "reference_samples": n,
                }
            )
    return pd.DataFrame(rows)
