"""``blurlab recommend``: the cheapest method reaching a PSNR, or the most accurate within a
time budget, for one scene or a set (docs/recommend.md)."""

from __future__ import annotations

from .cli_args import SIZE_HELP, parse_animation, parse_size
from .cli_methods import add_methods_from
from .core.context import Context
from .scene import scenes
from .sizes import DEFAULT_SIZE
from .studies.recommend import AGGREGATES, expand, ranking_metrics, recommend, recommend_set
from .temporal.sequences import frame_scenes


def add_recommend_command(sub) -> None:
    """The subcommand recommend."""
    advice = sub.add_parser(
        "recommend",
        help="the cheapest method reaching a PSNR, or the most accurate within a time budget; "
        "for one scene or a set",
    )
    advice.add_argument(
        "scene",
        nargs="+",
        help="built-in scenes (bl.scenes.names()), random:SEED or random:A-B (seeds A to B), "
        "or .gltf/.glb files; several give one configuration for the set",
    )
    advice.add_argument("--size", type=parse_size, default=DEFAULT_SIZE, help=SIZE_HELP)
    advice.add_argument("--budget-ms", type=float, default=None, help="GPU ms per frame at most")
    advice.add_argument("--target-psnr", type=float, default=None, help="PSNR in dB at least")
    advice.add_argument("--metric", choices=ranking_metrics(), default="psnr")
    advice.add_argument(
        "--all",
        action="store_true",
        help="print every configuration measured, not only the Pareto front",
    )
    advice.add_argument(
        "--aggregate",
        default=None,
        help=f"over a set of scenes, rank by {', '.join(AGGREGATES)} (pNN: the NN-th percentile "
        "from the bad end), optionally ':METRIC', e.g. p10:psnr (default with several scenes: "
        "median of --metric)",
    )
    advice.add_argument(
        "--frames",
        type=int,
        default=None,
        help="measure each scene as FRAMES consecutive frames of a sequence at --fps (180° "
        "shutters), one configuration for them all (with --aggregate, e.g. p10:psnr: its worst "
        "frames)",
    )
    advice.add_argument(
        "--fps", type=float, default=60.0, help="with --frames: the frame rate (default 60)"
    )
    advice.add_argument(
        "--animation",
        type=parse_animation,
        default="all",
        help="a file's animations to play: all (default; refused where two drive one property),"
        " none, or indices and names separated by commas",
    )
    add_methods_from(advice)


def recommend_command(args) -> int:
    """One line with the answer, then the table it was chosen from (fastest first); for
    several scenes or an --aggregate, one configuration for the set, then its per-scene rows."""
    if args.budget_ms is None and args.target_psnr is None:
        raise ValueError("recommend needs --budget-ms, --target-psnr or both")
    # Built-in names or .gltf/.glb files: fail before the GPU.
    if args.animation != "all" and not all(scenes.is_file(s) for s in args.scene):
        raise ValueError("--animation is for .gltf/.glb files, not built-in scenes")
    items = [
        scenes.gltf(s, animation=args.animation) if scenes.is_file(s) else scenes.get(s)
        for s in expand(args.scene)
    ]
    if args.frames is not None:  # each scene as the frames of a sequence (docs/recommend.md)
        items = [frame for item in items for frame in frame_scenes(item, args.fps, args.frames)]
    if len(items) > 1 or args.aggregate is not None:
        return recommend_set_command(args, items)
    ctx = Context(args.device)
    answer = recommend(
        ctx, items[0], args.size, args.budget_ms, args.target_psnr, args.metric, progress=True
    )
    print(f"recommend: {answer}")
    for line in answer.details():
        print(f"  {line}")
    columns = ["chosen", "method", "params", "total_ms", "ms_low", "ms_high", "psnr", "ssim"]
    columns += [c for c in answer.table if c.startswith("auto_")]
    if args.all:
        rows, title = answer.table.sort_values("total_ms"), "every configuration, fastest first"
    else:
        rows, title = (
            answer.front(),
            "the Pareto front (none faster and more accurate; --all: every row)",
        )
    print(f"\n{title}:")
    print(rows[columns].to_string(index=False, float_format=lambda v: f"{v:.4g}", na_rep=""))
    print_clock(ctx)
    return 0


def recommend_set_command(args, items) -> int:
    aggregate = args.aggregate or f"median:{args.metric}"
    if args.target_psnr is not None and not aggregate.endswith(":psnr"):
        raise ValueError("--target-psnr goes with an aggregate of PSNR (e.g. p10:psnr)")
    ctx = Context(args.device)
    answer = recommend_set(
        ctx, items, args.size, args.budget_ms, args.target_psnr, aggregate, progress=True
    )
    print(f"recommend: {answer}")
    number = {"float_format": lambda v: f"{v:.4g}", "index": False}
    if answer.method is not None:
        columns = ["scene", "total_ms", *dict.fromkeys(["psnr", "ssim", answer.aggregate.metric])]
        columns += [c for c in answer.per_scene if c.startswith("auto_")]
        print(answer.per_scene[columns].to_string(**number))
    print(f"\nevery configuration, by {answer.aggregate} over {len(items)} scenes:")
    ranked = answer.table.sort_values("time_ms")
    print(ranked.rename(columns={"value": str(answer.aggregate)}).to_string(**number))
    print_clock(ctx)
    return 0


def print_clock(ctx) -> None:
    info = ctx.info()
    print(f"(times: the methods' GPU passes by {info['timer']} on {info['renderer']})")
