"""Per-object errors from the object-id buffer: the OGRE paper's Table 1 redone with accuracy.

`textured_spin` has four textures (low, medium and high contrast, rainbow), each on a sphere
turning slowly and on one turning fast. For each sphere, accumulation is compared with
stochastic blur at matched render counts (each method that renders its own sub-frames says, in
the registry, which parameters make it render n times: stochastic renders 4 jittered views per
time slice, so K slices cost 4K renders, as accumulation of 4K sub-frames does): the PSNR of
that sphere against the converged reference, and each method's time for the whole frame.
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from .. import metrics
from ..core.references import default_reference_samples
from ..methods import blur, method, methods
from ..scene import scenes
from ..sizes import DEFAULT_SIZE

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


def object_errors(
    ctx, size=DEFAULT_SIZE, renders=RENDERS, reference_samples=None, reference=None
) -> pd.DataFrame:
    """One row per sphere of textured_spin and render count: its texture and rotation, the
    PSNR of accumulation and of stochastic blur inside the sphere's box, and their times.
    `reference`: textured_spin's converged reference at `size` where the caller has rendered
    it already (the study's sweep has), else it is rendered here with `reference_samples`
    sub-frames (default: default_reference_samples)."""
    scene = scenes.get("textured_spin")
    frame = ctx.render(scene, size)
    if reference is None:
        n = reference_samples or default_reference_samples(frame)
        reference = ctx.reference(scene, size, samples=n, progress=False)
    elif reference.color.shape[:2] != frame.shape:
        raise ValueError(
            f"blurlab.studies.objects: the reference is {reference.color.shape[1]}x"
            f"{reference.color.shape[0]}, the study renders {size[0]}x{size[1]}"
        )
    n, reference = reference.samples, reference.color
    boxes = object_boxes(frame)
    # Every method that renders its own sub-frames, each at the same number of renders.
    compared = [name for name in methods() if method(name).renders_for is not None]
    rows = []
    for count in renders:
        results = {
            name: blur(ctx, frame, name, **method(name).renders_for(count)) for name in compared
        }
        for object_id, (y0, y1, x0, x1) in sorted(boxes.items()):
            name = scene.objects[object_id].name
            crop = np.s_[y0:y1, x0:x1]
            row = {
                "object": name,
                "texture": TEXTURES[int(name[len("sphere")])],
                "rotation": name.rsplit("_", 1)[1],
                "renders": count,
            }
            for compared_name, result in results.items():
                row[f"psnr_{compared_name}"] = metrics.psnr(reference[crop], result.color[crop])
            for compared_name, result in results.items():
                row[f"ms_{compared_name}"] = result.total_ms
            rows.append({**row, "reference_samples": n})
    return pd.DataFrame(rows)
