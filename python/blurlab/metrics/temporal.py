"""Metrics over time (docs/spec.md §21.3): a method's frames against the sequence reference's.
Per-frame error is any single-frame metric taken frame by frame (`per_frame`); temporal
instability, registered here, compares how the two change from one frame to the next."""

from __future__ import annotations

import numpy as np

from .registry import REFERENCES, Metric, check_names, cpu_scores, register


def frames_rgb(frames, what: str) -> np.ndarray:
    """The RGB of an (N, H, W, 3|4) sequence of N >= 2 frames, float64, clipped to [0, 1]."""
    frames = np.asarray(frames, np.float64)
    if frames.ndim != 4 or frames.shape[0] < 2 or frames.shape[3] < 3:
        raise ValueError(
            f"blurlab.metrics: {what} must be an (N >= 2, H, W, 3 or 4) sequence, not "
            f"{frames.shape}"
        )
    return np.clip(frames[..., :3], 0.0, 1.0)


def temporal_instability(reference, test) -> float:
    """Mean over frames 1 … N−1, pixels and RGB of |(O_i − O_{i−1}) − (R_i − R_{i−1})|,
    linear colour clipped to [0, 1] (docs/spec.md §21.3). 0: the output changes exactly as the
    reference does; the flicker of random taps and the lag of a history both add to it."""
    r, o = frames_rgb(reference, "reference"), frames_rgb(test, "test")
    if r.shape != o.shape:
        raise ValueError(f"blurlab.metrics: sequences differ in shape: {r.shape} and {o.shape}")
    return float(np.abs(np.diff(o, axis=0) - np.diff(r, axis=0)).mean())


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
