"""Metrics over time (docs/spec.md §21.3): a method's frames against the sequence reference's.
Per-frame error is any single-frame metric taken frame by frame (`per_frame`); temporal
instability, registered here, compares how the two change from one frame to the next."""

from __future__ import annotations

import numpy as np

from .registry import REFERENCES, Metric, check_names, cpu_scores, register


def check_sequence(frames, what: str) -> np.ndarray:
    """`frames` as an (N >= 2, H, W, 3|4) array, or a ValueError saying what was expected."""
    frames = np.asarray(frames)
    if frames.ndim != 4 or frames.shape[0] < 2 or frames.shape[3] not in (3, 4):
        raise ValueError(
            f"blurlab.metrics: {what} must be an (N >= 2, H, W, 3 or 4) sequence, not "
            f"{frames.shape}"
        )
    return frames


def clipped(frame) -> np.ndarray:
    """A frame's RGB clipped to [0, 1] (what an LDR display shows), in float32: the frames'
    own precision, in which differences of values in [0, 1] are exact where they are close."""
    return np.clip(np.asarray(frame[..., :3], np.float32), 0.0, 1.0)


def temporal_instability(reference, test) -> float:
    """Mean over frames 1 … N−1, pixels and RGB of |(O_i − O_{i−1}) − (R_i − R_{i−1})|,
    linear colour clipped to [0, 1] (docs/spec.md §21.3). 0: the output changes exactly as the
    reference does; the flicker of random taps and the lag of a history both add to it."""
    reference, test = check_sequence(reference, "reference"), check_sequence(test, "test")
    if reference.shape[:3] != test.shape[:3]:
        raise ValueError(
            f"blurlab.metrics: sequences differ in shape: {reference.shape} and {test.shape}"
        )
    # Frame pair by frame pair: a whole 1080p sequence in float64 would take gigabytes.
    total, r_prev, o_prev = 0.0, clipped(reference[0]), clipped(test[0])
    for r_frame, o_frame in zip(reference[1:], test[1:], strict=True):
        r_next, o_next = clipped(r_frame), clipped(o_frame)
        total += np.abs((o_next - o_prev) - (r_next - r_prev)).mean(dtype=np.float64)
        r_prev, o_prev = r_next, o_next
    return float(total / (len(test) - 1))


def gpu_pair_instability(ctx, output_now, output_before, reference_now, reference_before) -> float:
    """One frame pair's share of `temporal_instability`, from four (H, W, 4) float32 textures:
    the mean over pixels and RGB of |(O_i − O_{i−1}) − (R_i − R_{i−1})|, summed per 16 x 16
    tile on the GPU (passes/temporal_difference.comp) and over the tiles here in float64."""
    height, width = output_now.shape[:2]
    tiles = ctx.pooled((-(-height // 16), -(-width // 16)))
    try:
        ctx.shader_pass("passes/temporal_difference.comp").run(
            {
                "output_now": output_now,
                "output_before": output_before,
                "reference_now": reference_now,
                "reference_before": reference_before,
            },
            {"tile_sums": tiles},
        )
        total = tiles.download().sum(dtype=np.float64)
    finally:
        ctx.recycle(tiles)
    return float(total / (3 * height * width))


def per_frame(names, references, outputs) -> dict[str, np.ndarray]:
    """{metric: (N,) values}: each single-frame metric of `names` on each frame of `outputs`
    against the same frame of `references` (both (N, H, W, C)), with its NumPy definition. The
    sequence's reference stands for both kinds of reference (docs/spec.md §21.1)."""
    names = check_names(names, "blurlab.metrics.per_frame")
    scores = [
        cpu_scores(names, dict.fromkeys(REFERENCES, reference), output)
        for reference, output in zip(references, outputs, strict=True)
    ]
    return {name: np.array([s[name] for s in scores]) for name in names}


register(
    Metric(
        name="temporal_instability",
        doc="Mean over frames, pixels and RGB of the difference between the output's change "
        "from the previous frame and the reference's: flicker and lag that a single frame's "
        "error does not show.",
        spec="§21.3",
        higher_is_better=False,
        range=(0.0, 2.0),
        reference="antialiased",
        numpy=temporal_instability,
        label="temporal instability",
        sequence=True,
    )
)
