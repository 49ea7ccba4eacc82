"""The ``blurlab`` command and its subcommands (build_parser; ``blurlab --help`` names every
one). User errors (bad names, values, sizes, files) print one line ``blurlab: error: ...`` and
exit with status 2; ``--debug`` shows the traceback instead."""

from __future__ import annotations

import argparse
import functools
import importlib
import importlib.util
import json
import os
import signal
import sys
import time
from contextlib import contextmanager
from pathlib import Path

from . import metrics
from .blender import environment
from .cli_args import SIZE_HELP, parse_size
from .cli_methods import (
    add_method_commands,
    add_methods_from,
    check_method_command,
    load_methods_from,
    method_table,
    new_method_command,
)
from .cli_recommend import add_recommend_command, recommend_command
from .cli_suite import add_suite_command, suite_command
from .core.context import Context
from .errors import cause
from .io import images as io
from .methods import blur, example_method, method, methods
from .scene import scenes
from .sizes import DEFAULT_SIZE
from .studies import capture_study, plots
from .studies.cluster import account_table
from .studies.cluster_devices import local_cluster
from .studies.scheduler import CONNECT_TIMEOUT_S, scheduler_client
from .studies.sequence_study import run_sequence_study
from .studies.study import run_study
from .studies.sweep_config import run_sweep_config
from .twins.patterns import test_pattern

# The benchmarks are a development package of the checkout, which the wheel does not ship.
BENCH_PACKAGE = "blurlab_bench"
BENCH_FOLDER = Path(__file__).resolve().parents[2] / "benchmarks"  # python/blurlab -> root
NO_BENCHMARKS = (
    "the benchmarks are a development package in a checkout's benchmarks/ folder, which the "
    "wheel does not ship: run `blurlab bench` from a checkout's source (PYTHONPATH=python), or "
    "put the checkout's benchmarks/ folder on PYTHONPATH"
)


def parse_device(text: str) -> str | int:
    return int(text) if text.isdigit() else text


def _info(args) -> int:
    ctx = Context(args.device)
    print(json.dumps({"devices": Context.devices(), "context": ctx.info()}, indent=2))
    return 0


def _demo(args) -> int:
    import numpy as np

    ctx = Context(args.device)
    info = ctx.info()
    print(f"device: {info['device']} ({info['renderer']}, {info['version']})")
    width, height = args.size
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)

    pattern = ctx.empty((height, width, 4), "float32")
    ctx.program("util/test_pattern.comp").run(
        (width, height), images=[pattern], uniforms={"seed": args.seed}
    )
    image = pattern.download()
    error = float(np.abs(image - test_pattern(width, height, args.seed)).max())
    io.write(out / "test_pattern.png", image[..., :3])
    print(f"test pattern {width}x{height}: largest difference from NumPy {error:.1e}")

    print(f"\n{'scene':<14} {'G-buffer ms':>12} {'blur ms':>9} {'max |M| px':>11}")
    for name in scenes.names():
        frame = ctx.render(scenes.get(name), (width, height))
        result = blur(ctx, frame, args.method, seed=args.seed)
        speed = np.linalg.norm(frame.motion, axis=-1)
        io.write(out / f"{name}_sharp.png", frame.color)
        io.write(out / f"{name}_blurred.png", result.color)
        io.write(out / f"{name}_motion.png", plots.motion_picture(frame.motion))
        io.write(
            out / f"{name}_gbuffer.exr",
            np.concatenate([frame.color, frame.depth[..., None], frame.motion], axis=-1),
        )
        print(
            f"{name:<14} {frame.timings['gbuffer'].ms:>12.3f} {result.total_ms:>9.3f} "
            f"{speed.max():>11.1f}"
        )
    print(f"(times by {info['timer']})")
    # The blur's name and its tile filter's k and samples, as the last call resolved them.
    shown = [f"{key} = {result.params[key]}" for key in ("k", "samples") if key in result.params]
    print(
        f"\nwrote sharp, blurred ({', '.join([args.method, *shown])}) and motion pictures, "
        f"and G-buffer EXRs (R, G, B, A, Z, Mx, My) to {out}/"
    )
    return 0


@contextmanager
def _cluster(args):
    """The cluster that --scheduler or --workers asks for, or None (this process renders)."""
    tls = (args.tls_ca, args.tls_cert, args.tls_key)
    if (any(tls) or args.connect_timeout != CONNECT_TIMEOUT_S) and not args.scheduler:
        raise ValueError(
            "--tls-ca, --tls-cert, --tls-key and --connect-timeout go with --scheduler ADDRESS"
        )
    if args.scheduler:
        with scheduler_client(args.scheduler, *tls, args.connect_timeout) as client:
            yield client
    elif args.workers:
        if not isinstance(args.device, str):
            raise ValueError(
                "--workers gives each worker its own device; --device must be "
                "auto, gpu or software with it"
            )
        with local_cluster(args.workers, args.device) as cluster:
            yield cluster
    else:
        yield None


def _study(args) -> int:
    ctx = Context(args.device)
    if capture_study.capture_command(ctx, args):  # --capture; without it, refuses its options
        return 0
    info = ctx.info()
    print(f"device: {info['device']} ({info['renderer']}); {args.size[0]}x{args.size[1]}")
    if args.sequence:
        others = [args.metrics != "auto", args.peers, args.scheduler, args.workers]
        if any(others):
            raise ValueError(
                "study --sequence measures PSNR and temporal instability on this device; "
                "--metrics, --peers, --scheduler and --workers are for the single-frame study"
            )
        report = run_sequence_study(ctx, args.scenes, args.size, args.out, args.reference_samples)
        print(f"wrote {report} and {Path(args.out) / 'sequence.csv'}")
        return 0
    with _cluster(args) as cluster:
        report = run_study(
            ctx,
            _study_scenes(args),
            args.size,
            args.out,
            args.reference_samples,
            None if args.metrics == "auto" else tuple(args.metrics.split(",")),
            cluster=cluster,
            peer_names=tuple(args.peers.split(",")) if args.peers else (),
        )
    print(f"wrote {report}, {Path(args.out) / 'results.csv'} and {Path(args.out) / 'phases.json'}")
    return 0


def _study_scenes(args) -> list | None:
    """The study's scenes: --scenes, then the transparency scenes of --transparency and the
    random scenes of --random N --seed S."""
    if args.random is None and not args.transparency:
        return args.scenes
    added = scenes.names("transparency") if args.transparency else []
    if args.random is not None:
        added += [scenes.random_name(seed) for seed in range(args.seed, args.seed + args.random)]
    return list(args.scenes or []) + [name for name in added if name not in (args.scenes or [])]


def _sweep(args) -> int:
    with _cluster(args) as cluster:
        ctx = Context(args.device) if cluster is None else None
        start = time.perf_counter()
        table = run_sweep_config(ctx, args.config, cluster=cluster)
        wall = time.perf_counter() - start
    print(f"{len(table)} rows")
    if "workers" in table.attrs:  # where each worker's time went
        print(f"\nsweep wall {wall:.1f} s\n{account_table(table.attrs['workers'], wall)}")
    return 0


def _add_cluster_options(parser) -> None:
    group = parser.add_mutually_exclusive_group()
    group.add_argument(
        "--scheduler",
        metavar="ADDRESS",
        help="run the sweep on the Dask cluster at this scheduler address (tls://host:8786 "
        "with the --tls options; plain tcp:// is for a trusted network only); "
        "each worker renders on its own device (docs/distributed.md)",
    )
    group.add_argument(
        "--workers",
        type=_positive_int,
        metavar="N",
        help="run the sweep on N local Dask workers: one per GPU, or N llvmpipe workers",
    )
    for name, what in (
        ("ca", "the CA certificate"),
        ("cert", "this client's certificate"),
        ("key", "this client's private key"),
    ):
        parser.add_argument(
            f"--tls-{name}",
            metavar="PEM",
            help=f"with --scheduler tls://...: {what} (docs/distributed.md, 'Securing a cluster')",
        )
    parser.add_argument(
        "--connect-timeout",
        type=float,
        default=CONNECT_TIMEOUT_S,
        metavar="SECONDS",
        help=f"with --scheduler: how long to try to reach it (default {CONNECT_TIMEOUT_S:g})",
    )


def _blender(args) -> int:
    """blurlab blender install | status | uninstall (blurlab.blender.environment)."""
    if args.python and args.action != "install":
        raise ValueError("--python goes with blurlab blender install")
    if args.action == "install":
        environment.install(args.python)
    elif args.action == "uninstall":
        environment.uninstall()
    else:
        python = environment.interpreter()
        print(
            f"Blender runs with {python}"
            if python
            else "Blender is not set up: blurlab "
            "blender install makes an environment of its own for it"
        )
    return 0


def _methods(args) -> int:
    """Prints each method's kind, instant, backends and parameter table: the one declaration
    of every parameter, in Markdown."""
    for name in [args.name] if args.name else methods():
        print(method_table(method(name)))
    return 0


def _metrics(args) -> int:
    """Prints docs/metrics.md: every registered metric, from the registry."""
    print(metrics.reference_page(), end="")
    return 0


def _positive_int(text: str) -> int:
    if not text.isdigit() or int(text) < 1:
        raise argparse.ArgumentTypeError(f"must be an integer >= 1, not {text!r}")
    return int(text)


def _seed(text: str) -> int:
    if not text.isdigit():
        raise argparse.ArgumentTypeError(f"must be an integer >= 0, not {text!r}")
    try:
        return scenes.check_seed(int(text))
    except ValueError as error:
        raise argparse.ArgumentTypeError(str(error)) from None


class _Parser(argparse.ArgumentParser):
    """argparse, with its errors in the one-line form of every other CLI error."""

    def error(self, message: str):
        self.exit(2, f"blurlab: error: {message}\n")


# What a user can cause: bad values, names, files, sizes, a missing driver. Anything else is a
# bug and keeps its traceback.
# ImportError: an optional extra that is not installed (blurlab study --peers eevee without bpy).
USER_ERRORS = (ValueError, TypeError, LookupError, OSError, RuntimeError, ImportError)


@functools.cache
def bench_command():
    """`blurlab bench`'s module (blurlab_bench.command): the development package beside this
    source where it is a checkout's, else one on the path; None where there is neither."""
    if (BENCH_FOLDER / BENCH_PACKAGE / "__init__.py").is_file():
        if str(BENCH_FOLDER) not in sys.path:
            sys.path.insert(0, str(BENCH_FOLDER))
    elif importlib.util.find_spec(BENCH_PACKAGE) is None:
        return None
    return importlib.import_module(f"{BENCH_PACKAGE}.command")


def build_parser(bench_arguments: bool = True) -> argparse.ArgumentParser:
    """The `blurlab` command line; docs/cli.md is printed from it (blurlab.cli_reference).
    `bench_arguments` False leaves the bench command's own arguments out, and so does not import
    the benchmarks (a development package of every benchmark), for a command that is not it."""
    parser = _Parser(prog="blurlab", description=__doc__)
    parser.add_argument(
        "--debug", action="store_true", help="show the Python traceback of an error"
    )
    parser.add_argument(
        "--device",
        type=parse_device,
        default="auto",
        help="auto, gpu, software, or an EGL device index (default: auto)",
    )
    sub = parser.add_subparsers(dest="command", required=True)
    sub.add_parser("info", help="print the EGL devices and the context's info as JSON")
    demo = sub.add_parser(
        "demo", help="render the built-in scenes, blur them, write pictures and G-buffers"
    )
    demo.add_argument("--out", default="out/demo", help="output folder (default: out/demo)")
    demo.add_argument("--size", type=parse_size, default=DEFAULT_SIZE, help=SIZE_HELP)
    demo.add_argument("--seed", type=int, default=0)
    demo.add_argument(
        "--method",
        choices=methods(),
        default=example_method(),
        help=f"the method that blurs each scene (default: {example_method()})",
    )
    listing = sub.add_parser(
        "methods", help="list the registered methods and their parameters (defaults, ranges)"
    )
    listing.add_argument("name", nargs="?", help="one method (default: all)")
    add_methods_from(listing)
    sub.add_parser(
        "metrics", help="print every registered metric: direction, range, definition (Markdown)"
    )
    study = sub.add_parser(
        "study", help="the main job: every scene x method x grid, report.html + results.csv"
    )
    study.add_argument(
        "--scenes",
        nargs="+",
        default=None,
        help="built-in scenes and .gltf/.glb files (default: every built-in scene)",
    )
    study.add_argument(
        "--random",
        type=_positive_int,
        default=None,
        metavar="N",
        help="add N random scenes, seeds S..S+N-1 (bl.scenes.random); then every row of "
        "results.csv has its scene's features",
    )
    study.add_argument(
        "--seed", type=_seed, default=0, metavar="S", help="the first random seed (default: 0)"
    )
    study.add_argument(
        "--transparency",
        action="store_true",
        help="add the transparency scenes; each gets the four ways to blur translucency",
    )
    study.add_argument("--size", type=parse_size, default=DEFAULT_SIZE, help=SIZE_HELP)
    study.add_argument("--out", default="out/study", help="output folder (default: out/study)")
    study.add_argument(
        "--reference-samples",
        type=int,
        default=None,
        help="N of each reference (default: max(64, 2 x longest motion))",
    )
    study.add_argument(
        "--metrics",
        default="auto",
        help="comma-separated names (blurlab metrics lists them); auto (default): "
        f"{','.join(metrics.default_names(False))} and, on HDR scenes, "
        f"{','.join(n for n in metrics.default_names(True) if metrics.get(n).hdr)}",
    )
    study.add_argument(
        "--peers",
        default="",
        help="comma-separated peers rendered by Blender and scored alike: eevee "
        "(needs blurlab blender install)",
    )
    study.add_argument(
        "--sequence",
        action="store_true",
        help="sequences instead: every method before TAA, after it and in its history, "
        "sequence.html + sequence.csv (docs/temporal.md)",
    )
    capture_study.add_capture_options(study)
    _add_cluster_options(study)
    add_methods_from(study)
    add_recommend_command(sub)
    sweep = sub.add_parser("sweep", help="run the sweep a TOML configuration describes")
    sweep.add_argument("config", help="TOML file: scenes, methods, size, shutter, ...")
    _add_cluster_options(sweep)
    add_methods_from(sweep)
    add_method_commands(sub, parse_size)
    add_suite_command(sub, _add_cluster_options)
    benchmarks = bench_command() if bench_arguments else None
    bench = sub.add_parser(
        "bench",
        help="run, list and record the registered benchmarks (from a checkout)",
        add_help=benchmarks is not None or not bench_arguments,
    )
    if benchmarks is not None:
        benchmarks.add_arguments(bench, parse_size)
    blender = sub.add_parser(
        "blender",
        help="set up Blender's bpy for the cross-checks in an environment of its own",
    )
    blender.add_argument(
        "action",
        choices=("install", "status", "uninstall"),
        help="install: make the private environment with bpy (your own stays unchanged); "
        "status: where Blender runs from; uninstall: remove the environment",
    )
    blender.add_argument(
        "--python", metavar="PATH", help="with install: the Python 3.11 to make it with"
    )
    # The summary is made from the subcommands, so that none can be left out of it.
    parser.description = (
        f"The blurlab command: {', '.join(sub.choices)}. User errors (bad names, values, "
        "sizes, files) print one line 'blurlab: error: ...' and exit with status 2; --debug "
        "shows the traceback instead."
    )
    return parser


def _reader_gone() -> int:
    """stdout's reader went away (`blurlab methods | head -1`): stop quietly, as Unix tools do,
    with the status a shell shows for SIGPIPE. What is left in stdout's buffer goes to
    /dev/null, so that the interpreter's last flush raises nothing either."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
    except (OSError, ValueError, AttributeError):  # a stdout with no file descriptor
        pass
    return 128 + signal.SIGPIPE


def main(argv: list[str] | None = None) -> int:
    words = sys.argv[1:] if argv is None else argv
    parser = build_parser(bench_arguments="bench" in words)
    args, unknown = parser.parse_known_args(argv)
    if args.command == "bench" and bench_command() is None:
        parser.error(NO_BENCHMARKS)
    if unknown:
        parser.error(f"unrecognized arguments: {' '.join(unknown)}")
    commands = {
        "info": _info,
        "demo": _demo,
        "methods": _methods,
        "metrics": _metrics,
        "recommend": recommend_command,
        "study": _study,
        "sweep": _sweep,
        "bench": lambda args: bench_command().main(args, args.device),
        "check-method": check_method_command,
        "new-method": new_method_command,
        "suite": lambda args: suite_command(args, _cluster),
        "blender": _blender,
    }
    try:
        load_methods_from(args)
        status = commands[args.command](args)
        sys.stdout.flush()  # a reader gone away shows here, not in the interpreter's last flush
        return status
    except BrokenPipeError:
        return _reader_gone()
    except USER_ERRORS as error:
        if args.debug:
            raise
        # One line: a multi-line message (the EGL driver's remedy, say) is joined, not cut.
        lines = [line.strip() for line in str(error).splitlines() if line.strip()]
        message = cause(" ".join(lines)) or type(error).__name__
        parser.exit(2, f"blurlab: error: {message}\n")


if __name__ == "__main__":
    sys.exit(main())
