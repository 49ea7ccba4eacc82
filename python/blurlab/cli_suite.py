"""``blurlab suite run | compare | show``: the suite's command (docs/suite.md, docs/spec.md
§24). The cluster options and their context manager are the study's, passed in by cli.py."""

from __future__ import annotations

import json
from pathlib import Path

from .cli_methods import add_methods_from
from .core.context import Context
from .studies.capture_study import add_capture_file_options
from .suite import PRESETS, compare_text, run_suite, suite_identity
from .suite.captured import captures_of
from .suite.definition import definition
from .suite.run import card_rows


def default_preset(ctx: Context) -> str:
    """software on llvmpipe, gpu on a GPU."""
    return "software" if ctx.info()["device"] == "software" else "gpu"


def suite_command(args, cluster_of) -> int:
    """Runs `blurlab suite ACTION`; `cluster_of(args)` is cli's context manager that gives the
    Dask cluster --scheduler or --workers asks for, or None."""
    if args.action == "compare":
        print(compare_text(args.cards), end="")
        return 0
    if args.action == "show":
        preset = args.preset or default_preset(Context(args.device))
        print(json.dumps({**suite_identity(preset), **definition(preset)}, indent=1))
        return 0
    ctx = Context(args.device)
    preset = args.preset or default_preset(ctx)
    with cluster_of(args) as cluster:
        card = run_suite(
            ctx,
            args.out,
            args.methods,
            preset,
            assets=args.assets,
            cluster=cluster,
            progress=False,
            captures=captures_of(
                args.capture, args.reference, args.convention, args.shutter_fraction
            ),
            field_from=args.field_from,
        )
    table = card_rows(card)
    if not table.empty:
        print(table.to_string(index=False, float_format=lambda v: f"{v:.4g}"))
    skipped = [n for n, c in card["categories"].items() if c["status"] != "measured"]
    for name in skipped:
        print(f"{name}: skipped, {card['categories'][name]['reason']}")
    out = Path(args.out)
    print(
        f"suite v{card['suite']['version']} {preset} hash {card['suite']['hash']}: wrote "
        f"{out / 'card.json'} and {out / 'card.html'}"
    )
    return 0


def add_suite_command(sub, add_cluster_options) -> None:
    """The subcommand `suite` and its actions run, compare and show."""
    suite = sub.add_parser(
        "suite",
        help="the versioned benchmark: run it for methods into a card (card.json, card.html), "
        "compare cards, show its definition and hash",
    )
    actions = suite.add_subparsers(dest="action", required=True)
    run = actions.add_parser(
        "run",
        help="every category of the suite for the methods and the built-ins they are ranked "
        "against; resumes from OUT's rows",
    )
    run.add_argument(
        "--methods",
        nargs="+",
        default=None,
        metavar="NAME",
        help="the methods the card is for (default: every single-frame method registered)",
    )
    run.add_argument(
        "--preset",
        choices=PRESETS,
        default=None,
        help="the preset (default: software on llvmpipe, gpu on a GPU)",
    )
    run.add_argument(
        "--assets",
        metavar="DIR",
        default=None,
        help="the folder of the authored category's glTF files (the Khronos sample models); "
        "without it that category is skipped",
    )
    run.add_argument("--out", required=True, help="the card's folder (rows are kept there)")
    run.add_argument(
        "--field-from",
        metavar="CARD",
        default=None,
        help="the folder of an earlier card on this device: its rows are taken where their keys "
        "match, so a card for a new method evaluates that method's rows only",
    )
    add_capture_file_options(
        run.add_argument_group(
            "captured frames (docs/suite.md)",
            "an engine's captures, scored as the suite's captured category where given",
        ),
        repeated=True,
    )
    add_cluster_options(run)
    add_methods_from(run)
    compare = actions.add_parser(
        "compare", help="cards of the same suite side by side, one table per category"
    )
    compare.add_argument("cards", nargs="+", metavar="CARD", help="card.json files or folders")
    show = actions.add_parser("show", help="print the suite's definition and hash as JSON")
    show.add_argument(
        "--preset", choices=PRESETS, default=None, help="the preset (default: as run)"
    )
