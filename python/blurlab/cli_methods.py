"""The ``blurlab`` subcommands of methods from outside the package (docs/adding_a_method.md):
``check-method``, ``new-method``, ``--methods-from``, and a method's parameter table."""

from __future__ import annotations

from pathlib import Path

from .core.context import Context
from .methods import load_methods, method
from .methods.contract import SIZE as CHECK_SIZE
from .methods.contract import Check, check_method
from .methods.contract import table as check_table
from .methods.folders import MethodFolderError
from .methods.template import LANGUAGES, write_template


def method_table(m) -> str:
    """A method's parameters as a Markdown table, from their declarations."""
    instant = "depends on the parameters" if callable(m.instant) else m.instant
    lines = [
        f"## {m.name}",
        "",
        f"{m.doc}",
        "",
        f"kind: {m.kind}; G-buffer instant: {instant}; backends: {', '.join(m.backends)}",
        f"declared in {m.source}" if m.source else f"its folder: blurlab/methods/{m.name}/",
        "",
        "| parameter | default | allowed | meaning |",
        "|---|---|---|---|",
    ]
    for key, p in m.params.items():
        default = "from the frame" if callable(p.default) else repr(p.default)
        lines.append(f"| `{key}` | {default} | {p.allowed()} | {p.doc} |")
    return "\n".join(lines) + "\n"


def check_method_command(args) -> int:
    """Runs the contract on a method folder's methods or a registered method: a table of
    checks each, status 1 when any failed."""
    target = Path(args.method)
    if target.is_dir():
        try:
            names = load_methods(target)
        except MethodFolderError as error:  # it does not load: the first check failed
            print(check_table(str(target), [Check("loads", False, str(error))]))
            return 1
    else:
        names = [method(args.method).name]  # an unknown name is a user error
    ctx = Context(args.device)
    failed = False
    for name in names:
        checks = check_method(ctx, name, args.size)
        print(check_table(name, checks))
        failed = failed or any(c.passed is False for c in checks)
    return 1 if failed else 0


def new_method_command(args) -> int:
    folder = write_template(args.name, args.out, args.language)
    print(f"wrote {folder}; check it with: blurlab check-method {folder}")
    return 0


def load_methods_from(args) -> None:
    """--methods-from: loads each folder into this process's registry before the command."""
    paths = getattr(args, "methods_from", None) or []
    if paths and (getattr(args, "workers", None) or getattr(args, "scheduler", None)):
        raise ValueError(
            "--methods-from loads methods into this process; the workers of --workers or "
            "--scheduler would not have them (install them as a package with a blurlab.methods "
            "entry point instead)"
        )
    for path in paths:
        load_methods(path)


def add_methods_from(parser) -> None:
    parser.add_argument(
        "--methods-from",
        action="append",
        metavar="PATH",
        help="load the method folder at PATH, or every method folder in it, beside the "
        "built-in methods (repeatable; docs/adding_a_method.md)",
    )


def add_method_commands(sub, parse_size) -> None:
    """The subcommands check-method and new-method."""
    checking = sub.add_parser(
        "check-method",
        help="run the contract every method meets on a method folder or a registered method; "
        "a table of checks, status 1 when one fails",
    )
    checking.add_argument("method", metavar="PATH|NAME", help="a method folder, or a method's name")
    checking.add_argument(
        "--size",
        type=parse_size,
        default=CHECK_SIZE,
        help="WxH of the checks' frames (default {}x{})".format(*CHECK_SIZE),
    )
    add_methods_from(checking)
    new = sub.add_parser(
        "new-method",
        help="write a method folder to start from (a gather along the motion with its twin) "
        "that passes check-method",
    )
    new.add_argument("name", help="the method's name: lower case letters, digits and _")
    new.add_argument("--language", choices=LANGUAGES, default="glsl", help="the shader's language")
    new.add_argument("--out", default=".", help="the folder to write NAME/ in (default: .)")
