"""The perceptual_agreement benchmark (docs/temporal.md, "Do the metrics agree with a model of
vision?"): how closely PSNR, FLIP and temporal instability rank the per-frame methods under TAA
as a model of vision does (ColorVideoVDP or FovVideoVDP: the `model` parameter, a record for
each), Kendall's τ per sequence with a bootstrap interval over the sequences
(blurlab.studies.perceptual_agreement). Needs the optional extra blurlab[perceptual]."""

from __future__ import annotations

from blurlab.methods.params import Param
from blurlab.studies import perceptual_agreement, temporal

from .core import Benchmark, Unavailable, register
from .temporal import SEQUENCE_PARAMS, sequence_scenes
from .timing import gallery_methods, split


def _perceptual_agreement(ctx, size, p, out) -> None:
    try:
        model = perceptual_agreement.require(p["model"])
    except ImportError as why:
        raise Unavailable(str(why)) from None
    names = sequence_scenes(p["scenes"])
    methods = split(p["methods"]) or temporal.sequence_methods()
    table = perceptual_agreement.scores(
        ctx,
        names,
        size,
        methods,
        p["frames"],
        p["warmup"],
        p["reference_samples"],
        p["fps"],
        model.name,
    )
    result = perceptual_agreement.agreement(table, model=model.name)
    out.figure("sequences", len(names), "")
    out.figure("methods ranked on each", len(methods), "")
    for row in result.itertuples():
        out.figure(f"{row.metric}: Kendall τ with {model.label}, mean", row.tau_mean, "")
    out.table(
        f"each metric's ranking of the methods under TAA against {model.label}'s: Kendall τ over "
        f"{len(names)} sequences (mean, 95 % bootstrap interval, median, lowest) and the share "
        "of sequences where both name the same best method",
        [
            ("metric", ""),
            ("sequences", ""),
            ("τ, mean", ""),
            ("interval low", ""),
            ("interval high", ""),
            ("τ, median", ""),
            ("τ, lowest", ""),
            ("same best method", "%"),
        ],
        [
            [
                r.metric,
                r.sequences,
                r.tau_mean,
                r.tau_low,
                r.tau_high,
                r.tau_median,
                r.tau_min,
                100 * r.same_best,
            ]
            for r in result.itertuples()
        ],
    )
    per_scene = perceptual_agreement.taus(table, model=model.name)
    out.table(
        f"Kendall τ with {model.label} per sequence",
        [("scene", ""), *[(m, "") for m in per_scene.columns]],
        [[scene, *row.tolist()] for scene, row in per_scene.iterrows()],
    )


register(
    Benchmark(
        "perceptual_agreement",
        "how closely PSNR, FLIP and temporal instability rank the methods under TAA as a model "
        "of human vision (ColorVideoVDP or FovVideoVDP) does: Kendall τ per sequence, with a "
        "bootstrap interval over the built-in and failure scenes' sequences",
        {
            "model": perceptual_agreement.MODEL,
            **SEQUENCE_PARAMS,
            "scenes": Param("", str, "comma-separated scenes (empty: built-in and failure)"),
            "fps": Param(60.0, float, "frame rate; the shutter is 180°", 1.0, 1000.0),
        },
        _perceptual_agreement,
        {"tiny": (32, 18), "software": (128, 72), "gpu": (1280, 720)},
        {
            # FovVideoVDP takes about 5 s of CPU for 8 frames of 160 x 90 on the 2-core
            # development machine, for each of 18 methods on 19 sequences: a smaller size and
            # fewer frames keep the run within half an hour there.
            "software": {"frames": 4, "warmup": 2, "reference_samples": 32},
            "tiny": {
                "scenes": "fan,vehicle",
                # a tile filter and the gathers the gallery shows
                "methods": ",".join(gallery_methods("filter")[:1] + gallery_methods("gather")),
                "frames": 2,
                "warmup": 1,
                "reference_samples": 4,
            },
            "gpu": {"frames": 16, "warmup": 8, "reference_samples": 256},
        },
        variants=("model",),
    )
)
