"""docs/cli.md: every ``blurlab`` subcommand's usage and options, printed as Markdown from the
command's own argument parser, so the page restates nothing by hand.

    python -m blurlab.cli_reference > docs/cli.md

tests/test_docs.py fails when docs/cli.md differs from this output.
"""

from __future__ import annotations

import argparse
import os
import sys
from contextlib import contextmanager

from .cli import build_parser

HEADER = """# Command line

Generated from the `blurlab` command's argument parser by
`python -m blurlab.cli_reference > docs/cli.md`; `tests/test_docs.py` fails when it is out of
date. `blurlab COMMAND --help` prints the same. The global options go before the command
(`blurlab --device software study ...`).
"""

# Usage lines wrap at the terminal's width; the page is made at this one, whatever the terminal.
USAGE_COLUMNS = "100"


@contextmanager
def _fixed_width():
    before = os.environ.get("COLUMNS")
    os.environ["COLUMNS"] = USAGE_COLUMNS
    try:
        yield
    finally:
        if before is None:
            del os.environ["COLUMNS"]
        else:
            os.environ["COLUMNS"] = before


def _cell(text: str) -> str:
    return " ".join(str(text).split()).replace("|", "\\|")


def _default(action: argparse.Action) -> str:
    unset = action.default in (None, argparse.SUPPRESS, "") or action.default is False
    if action.required or unset:
        return ""
    if isinstance(action.default, tuple) and len(action.default) == 2:
        return f"`{action.default[0]}x{action.default[1]}`"  # a size, as --size takes it
    return f"`{action.default}`"


def _name(action: argparse.Action) -> str:
    if not action.option_strings:
        return f"`{action.metavar or action.dest}`"
    if action.nargs == 0:
        return ", ".join(f"`{s}`" for s in action.option_strings)
    value = action.metavar or action.dest.upper()
    return ", ".join(f"`{s} {value}`" for s in action.option_strings)


def arguments(parser: argparse.ArgumentParser) -> list[argparse.Action]:
    """A parser's own arguments: not --help, not the subcommands. (argparse has no public way
    to list them; ``_actions`` has been where they are since Python 3.2.)"""
    return [
        action
        for action in parser._actions
        if not isinstance(action, argparse._HelpAction | argparse._SubParsersAction)
    ]


def options_table(parser: argparse.ArgumentParser) -> str:
    """A parser's arguments as a Markdown table."""
    rows = ["| argument | default | meaning |", "|---|---|---|"]
    for action in arguments(parser):
        meaning = action.help or ""
        if action.choices is not None:
            meaning += (" " if meaning else "") + "(one of: " + ", ".join(action.choices) + ")"
        rows.append(f"| {_name(action)} | {_default(action)} | {_cell(meaning)} |")
    return "\n".join(rows) + "\n" if len(rows) > 2 else ""


def subcommands(parser: argparse.ArgumentParser) -> list[tuple[str, str, argparse.ArgumentParser]]:
    """(name, one-line help, parser) of each subcommand, in the order they were added."""
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            helps = {choice.dest: choice.help or "" for choice in action._choices_actions}
            return [(name, helps.get(name, ""), sub) for name, sub in action.choices.items()]
    return []


def markdown(parser: argparse.ArgumentParser | None = None) -> str:
    """docs/cli.md's text."""
    parser = parser or build_parser()
    with _fixed_width():
        parts = [HEADER, "```text\n" + parser.format_usage() + "```\n", options_table(parser)]
        parts += _sections(parser, parser.prog)
    return "\n".join(parts)


def _sections(parser: argparse.ArgumentParser, prefix: str) -> list[str]:
    """A section per subcommand, each followed by its own subcommands' (`blurlab suite run`)."""
    parts = []
    for name, help_line, sub in subcommands(parser):
        parts.append(f"## {prefix} {name}\n")
        if help_line:
            parts.append(help_line[0].upper() + help_line[1:] + ".\n")
        parts.append("```text\n" + sub.format_usage() + "```\n")
        table = options_table(sub)
        if table:
            parts.append(table)
        parts += _sections(sub, f"{prefix} {name}")
    return parts


def main() -> int:
    sys.stdout.write(markdown())
    return 0


if __name__ == "__main__":
    sys.exit(main())
