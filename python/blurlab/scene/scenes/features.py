"""What a rendered frame holds, as numbers a study can split its results by (docs/spec.md §22.2):
how far it moves, how many surfaces overlap, how much of it is thin, how much of its motion is
the camera's, and whether it has HDR light or translucent surfaces.

Every feature is measured on the frame (its G-buffer, camera matrices and scene), so it applies
to built-in, random and loaded scenes alike, at the frame's size.
"""

from __future__ import annotations

import hashlib
import os
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pandas as pd

from ...io import images as io
from ...twins.gathers import camera_motion

# The feature columns `features` returns, in order, with what each is (docs/spec.md §22.2).
FEATURES = {
    "motion_p50": "median |M| over the pixels, px at the frame's size",
    "motion_p90": "90th percentile of |M|, px",
    "motion_p99": "99th percentile of |M|, px",
    "moving_share": "share of pixels with |M| >= 1 px",
    "depth_complexity": "mean over pixels of the objects whose shutter-long screen box covers it",
    "thin_share": "share of pixels in a run of one object id at most 3 % of the height long",
    "camera_motion_share": "the camera's share of the summed motion, 0 (objects) to 1 (camera)",
    "has_hdr": "whether some material emits more than 1 (bool)",
    "has_translucency": "whether some surface is blended or additive (bool)",
}
# A run of one object id no longer than this share of the image height (and at least 2 px) is
# thin: a thin bar, a post, a gap between blades.
THIN_SHARE_OF_HEIGHT = 0.03


def features(frame) -> dict:
    """The `FEATURES` of a rendered frame (a bl.Frame from ctx.render), as a dict of floats
    and bools."""
    if frame.camera is None or frame.scene is None or frame.object_id is None:
        raise ValueError(
            "blurlab: scene features need a frame rendered by ctx.render (its camera, scene and "
            "object ids); a frame built from arrays has none"
        )
    motion = np.asarray(frame.motion, np.float64)
    finite = np.isfinite(motion).all(axis=-1)
    speed = np.linalg.norm(np.where(finite[..., None], motion, 0.0), axis=-1)
    p50, p90, p99 = np.percentile(speed, [50, 90, 99])
    camera = camera_motion(frame.depth, frame.camera, frame.size)
    camera = np.where(finite[..., None] & np.isfinite(camera), camera, 0.0)
    camera_sum = float(np.linalg.norm(camera, axis=-1).sum())
    object_sum = float(
        np.linalg.norm(np.where(finite[..., None], motion, 0.0) - camera, axis=-1).sum()
    )
    total = camera_sum + object_sum
    return {
        "motion_p50": float(p50),
        "motion_p90": float(p90),
        "motion_p99": float(p99),
        "moving_share": float((speed >= 1.0).mean()),
        "depth_complexity": depth_complexity(frame),
        "thin_share": thin_share(frame.object_id),
        "camera_motion_share": camera_sum / total if total > 0 else 0.0,
        "has_hdr": bool(frame.scene.hdr),
        "has_translucency": bool(frame.scene.translucent),
    }


def thin_share(object_id: np.ndarray) -> float:
    """Share of pixels whose run of equal object ids along their row or their column is at
    most max(2, 0.03 · H) pixels long (background, id -1, included)."""
    ids = np.asarray(object_id)
    limit = max(2.0, THIN_SHARE_OF_HEIGHT * ids.shape[0])
    shortest = np.minimum(_run_lengths(ids), _run_lengths(ids.T).T)
    return float((shortest <= limit).mean())


def _run_lengths(ids: np.ndarray) -> np.ndarray:
    """Each pixel's run length of equal values along its row."""
    starts = np.ones(ids.shape, bool)
    starts[:, 1:] = ids[:, 1:] != ids[:, :-1]
    label = np.cumsum(starts.ravel()) - 1  # every row starts a run: runs never cross rows
    return np.bincount(label)[label].reshape(ids.shape)


def depth_complexity(frame) -> float:
    """Mean over pixels of how many objects' screen bounding boxes cover it, each box spanning
    the object's mesh (skinned where skinned, clipped at the near plane) at shutter open, the
    instant and close."""
    width, height = frame.size
    camera = frame.camera
    times = camera["times"]
    projections = [
        camera["view_projection"][0],
        camera["view_projection"][1],
        camera["projection"] @ camera["view"][2],
    ]
    count = np.zeros((height + 1, width + 1))
    for obj in frame.scene.objects:
        edges = obj.mesh.indices[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)
        points = []
        for t, projection in zip((times[0], times[1], times[2]), projections, strict=True):
            clip = _world_positions(obj, t) @ (projection @ obj.model(t)).T
            inside = _near_clipped(clip, edges, camera["near"])
            if len(inside):
                points.append((inside[:, :2] / inside[:, 3:] * 0.5 + 0.5) * [width, height])
        if not points:
            continue
        xy = np.concatenate(points)
        x0, y0 = np.clip(np.floor(xy.min(0)).astype(int), 0, [width, height])
        x1, y1 = np.clip(np.ceil(xy.max(0)).astype(int), 0, [width, height])
        if x1 > x0 and y1 > y0:  # a 2D difference array: +1 inside the box
            count[y0, x0] += 1
            count[y0, x1] -= 1
            count[y1, x0] -= 1
            count[y1, x1] += 1
    covered = count.cumsum(0).cumsum(1)[:height, :width]
    return float(covered.mean())


def _near_clipped(clip: np.ndarray, edges: np.ndarray, near: float) -> np.ndarray:
    """The clip-space vertices in front of the near plane (w > near) and the points where
    triangle edges cross it: their screen box is the clipped mesh's."""
    front = clip[:, 3] > near
    a, b = clip[edges[:, 0]], clip[edges[:, 1]]
    crossing = front[edges[:, 0]] != front[edges[:, 1]]
    a, b = a[crossing], b[crossing]
    s = (near - a[:, 3:]) / (b[:, 3:] - a[:, 3:])
    return np.concatenate([clip[front], a + s * (b - a)])


def _world_positions(obj, t: float) -> np.ndarray:
    """(N, 4) homogeneous mesh positions in the object's space at t: skinned where the object
    has a skeleton."""
    positions = np.concatenate([obj.mesh.positions, np.ones((len(obj.mesh.positions), 1))], 1)
    if obj.skeleton is None:
        return positions
    bones = obj.skeleton.matrices(t)
    blend = np.einsum("nk,nkij->nij", obj.mesh.bone_weights, bones[obj.mesh.bone_indices])
    return np.einsum("nij,nj->ni", blend, positions)


def with_features(
    ctx, table: pd.DataFrame, scenes, size, out=None, measured: dict | None = None
) -> pd.DataFrame:
    """`table` (rows with a "scene" column) with the `FEATURES` of `scenes` (bl.Scenes, each
    rendered by `ctx` at `size` at the shutter's centre) joined on the scene's name; feature
    columns the table had are replaced. `measured`: {scene name: its features} already
    measured on the same frame (a study measures them from its sweep's frames); the others are
    rendered and measured here. With `out`, a folder, it is also written to out/results.csv
    (atomically, replacing the file)."""
    scenes = list(scenes)
    measured = dict(measured or {})
    missing = [scene for scene in scenes if scene.name not in measured]
    for scene, row in zip(missing, features_of(ctx, missing, size), strict=True):
        measured[scene.name] = row
    rows = [{"scene": scene.name, **measured[scene.name]} for scene in scenes]
    measured = pd.DataFrame(rows, columns=["scene", *FEATURES]).drop_duplicates("scene")
    kept = table.drop(columns=[c for c in FEATURES if c in table])
    joined = kept.merge(measured, on="scene", how="left")
    joined.attrs = table.attrs
    if out is not None:
        io.write_text(Path(out) / "results.csv", joined.to_csv(index=False))
    return joined


def features_of(ctx, scenes, size, instant: str = "center", measure=features) -> list[dict]:
    """measure() (default: features()) of each of `scenes`, rendered by `ctx` at `size` at
    `instant`, in order. The renders run here, one after another (a GL context is this
    thread's); the measures, NumPy on the frame's arrays (features(): about a second at
    1080p, most of it in calls that release the GIL), run on threads meanwhile, a few frames at
    a time. A measure reads the frame's motion, depth, object_id, camera, scene and size."""
    threads = max(1, min(8, (os.cpu_count() or 1) - 1))
    results = []
    with ThreadPoolExecutor(threads) as pool:
        pending = []
        for scene in scenes:
            arrays = frame_arrays(ctx.render(scene, size, instant=instant))
            # the frame's GPU targets go back to the pool before the next render
            pending.append(pool.submit(measure, arrays))
            while len(pending) > 2 * threads:  # bounded memory: a 1080p frame is ~40 MB
                results.append(pending.pop(0).result())
        results += [job.result() for job in pending]
    return results


def frame_arrays(frame) -> SimpleNamespace:
    """What `features` reads of a rendered frame, downloaded here, for a thread to measure:
    the frame itself (and its GPU targets) stays on the GL context's thread."""
    return SimpleNamespace(
        motion=frame.motion,
        depth=frame.depth,
        object_id=frame.object_id,
        camera=frame.camera,
        scene=frame.scene,
        size=frame.size,
    )


def gbuffer_digest(frame) -> str:
    """SHA-256 of a frame's colour, depth, motion and object ids (their bytes): what must be
    the same for the same scene on the same renderer (docs/spec.md §22.1)."""
    h = hashlib.sha256()
    for array in (frame.color, frame.depth, frame.motion, frame.object_id):
        h.update(np.ascontiguousarray(array).tobytes())
    return h.hexdigest()
