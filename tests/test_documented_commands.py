"""Every command the README and docs/ give a user runs as written.

Commands are the lines of fenced ```console blocks that start with the prompt `$ `, one command
a line. Each page's `blurlab ...` and `python -m blurlab ...`
commands run verbatim through bash, in order, in one empty folder per page, with this tree's
blurlab first on the path; each must exit 0 within COMMAND_TIMEOUT_S. `make ...` commands are
.ci/run's to run: a test checks that .ci/run runs each one the docs give.

A command that cannot run on every machine says what it needs in a trailing comment,
`$ blurlab study --peers eevee  # needs: bpy`; NEEDS lists the needs and when they are met.
Where one is not met the command is skipped, and the skip says which need was missing."""

from __future__ import annotations

import os
import re
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import pytest

import blurlab as bl

ROOT = Path(__file__).resolve().parents[1]
COMMAND_TIMEOUT_S = 120
DOCUMENTED = ("blurlab", "python -m blurlab", "python3 -m blurlab")
NEEDS = {
    "gpu": (
        lambda: any(d["kind"] != "software" for d in bl.Context.devices()),
        "no GPU EGL device here",
    ),
    "bpy": (bl.blender.available, "bpy is not set up (blurlab blender install)"),
    "scheduler": (lambda: False, "needs a running Dask scheduler at the address it names"),
}
FENCE = re.compile(r"^(\s*)(`{3,}|~{3,})\s*([\w+-]*)")
NEED = re.compile(r"#\s*needs:\s*([\w, ]+)\s*$")


@dataclass(frozen=True)
class Command:
    page: str
    line: int
    text: str
    needs: tuple[str, ...]


def console_commands(path: Path, root: Path = ROOT) -> list[Command]:
    """The `$ ` lines of the ```console blocks of markdown file `path`."""
    commands, fence, language = [], None, ""
    for number, line in enumerate(path.read_text().splitlines(), 1):
        opened = FENCE.match(line)
        if fence is None and opened:
            fence, language = opened.group(2), opened.group(3)
        elif fence is not None and line.strip().startswith(fence):
            fence = None
        elif fence is not None and language == "console" and line.lstrip().startswith("$ "):
            text = line.lstrip()[2:].strip()
            need = NEED.search(text)
            needs = tuple(n.strip() for n in need.group(1).split(",")) if need else ()
            commands.append(Command(str(path.relative_to(root)), number, text, needs))
    return commands


def documented_pages(root: Path = ROOT) -> list[Path]:
    return [root / "README.md", *sorted((root / "docs").rglob("*.md"))]


def _is_blurlab(command: Command) -> bool:
    return any(command.text == d or command.text.startswith(d + " ") for d in DOCUMENTED)


def _pages_with_commands() -> list[tuple[str, list[Command]]]:
    pages = []
    for path in documented_pages():
        commands = [c for c in console_commands(path) if _is_blurlab(c)]
        if commands:
            pages.append((commands[0].page, commands))
    return pages


def _shims(folder: Path) -> dict[str, str]:
    """An environment whose `blurlab`, `python` and `python3` are this interpreter with this
    tree's blurlab first on its path."""
    folder.mkdir()
    for name, run in (("blurlab", '-m blurlab "$@"'), ("python", '"$@"'), ("python3", '"$@"')):
        shim = folder / name
        shim.write_text(f'#!/bin/sh\nexec "{sys.executable}" {run}\n')
        shim.chmod(0o755)
    package_parent = str(Path(bl.__file__).resolve().parents[1])
    path = os.pathsep.join(filter(None, [package_parent, os.environ.get("PYTHONPATH")]))
    return dict(os.environ, PATH=f"{folder}{os.pathsep}{os.environ['PATH']}", PYTHONPATH=path)


def run_commands(commands: list[Command], folder: Path) -> None:
    """Runs `commands` in order in `folder` (made if missing); skips at the first unmet need."""
    folder.mkdir(parents=True, exist_ok=True)
    env = _shims(folder / ".bin")
    for command in commands:
        unknown = set(command.needs) - set(NEEDS)
        assert not unknown, f"{command.page}:{command.line}: unknown need {unknown}; {list(NEEDS)}"
        unmet = [NEEDS[n][1] for n in command.needs if not NEEDS[n][0]()]
        if unmet:
            pytest.skip(f"{command.page}:{command.line} `{command.text}`: {'; '.join(unmet)}")
        try:
            result = subprocess.run(
                ["bash", "-c", command.text],
                cwd=folder,
                env=env,
                capture_output=True,
                text=True,
                timeout=COMMAND_TIMEOUT_S,
            )
        except subprocess.TimeoutExpired:
            pytest.fail(
                f"{command.page}:{command.line} `{command.text}` ran over {COMMAND_TIMEOUT_S} s"
            )
        assert result.returncode == 0, (
            f"{command.page}:{command.line} `{command.text}` exited {result.returncode}:\n"
            f"{result.stdout[-2000:]}\n{result.stderr[-2000:]}"
        )


PAGES = _pages_with_commands()


@pytest.mark.parametrize(
    "page, commands",
    PAGES or [pytest.param("", [], marks=pytest.mark.skip(reason="no ```console commands yet"))],
    ids=[page for page, _ in PAGES] or ["none"],
)
def test_documented_commands_run_as_written(page, commands, tmp_path):
    run_commands(commands, tmp_path)


def test_ci_runs_every_documented_make_command():
    ci = (ROOT / ".ci" / "run").read_text().splitlines()
    run_by_ci = {line.strip() for line in ci if line.strip().startswith("make ")}
    documented = {
        re.sub(r"\s+#.*$", "", c.text)
        for path in documented_pages()
        for c in console_commands(path)
        if c.text.startswith("make ")
    }
    assert documented <= run_by_ci, f".ci/run does not run {sorted(documented - run_by_ci)}"


FIXTURE_PAGE = """\
# A page

```console
$ blurlab methods
$ python -m blurlab info   # the devices
$ make test
$ blurlab study --peers eevee  # needs: bpy, gpu
output lines are not commands
```

```
$ blurlab not-a-console-block
```

````markdown
```console
$ blurlab inside-another-fence
```
````

```console
$ pip install blurlab
```
"""


def test_console_commands_are_the_prompt_lines_of_console_blocks(tmp_path):
    page = tmp_path / "page.md"
    page.write_text(FIXTURE_PAGE)
    commands = console_commands(page, tmp_path)
    assert [(c.line, c.text, c.needs) for c in commands] == [
        (4, "blurlab methods", ()),
        (5, "python -m blurlab info   # the devices", ()),
        (6, "make test", ()),
        (7, "blurlab study --peers eevee  # needs: bpy, gpu", ("bpy", "gpu")),
        (22, "pip install blurlab", ()),
    ]
    assert [c.text for c in commands if _is_blurlab(c)] == [c.text for c in commands[:2]] + [
        commands[3].text
    ]


def test_commands_run_verbatim_in_order_with_this_trees_blurlab(tmp_path):
    page = tmp_path / "page.md"
    page.write_text(
        "```console\n"
        "$ blurlab demo --size 32x18 --out demo_out\n"
        "$ python -m blurlab info > info.json\n"
        "$ blurlab no-such-command  # needs: scheduler\n"
        "```\n"
    )
    commands = console_commands(page, tmp_path)
    work = tmp_path / "work"
    work.mkdir()
    run_commands(commands[:2], work)
    assert any((work / "demo_out").iterdir())
    assert '"context"' in (work / "info.json").read_text()
    with pytest.raises(pytest.skip.Exception, match="needs a running Dask scheduler"):
        run_commands(commands[2:], tmp_path / "again")


def test_a_failing_command_fails_the_test(tmp_path):
    failing = Command("page.md", 1, "blurlab methods no_such_method", ())
    with pytest.raises(
        AssertionError, match=r"page.md:1 `blurlab methods no_such_method` exited 2"
    ):
        run_commands([failing], tmp_path)
