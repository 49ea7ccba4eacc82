"""Every command and every Python block the README and docs/ give a user runs as written.

Python blocks: see "Python blocks" below (one namespace per page, sizes at TEST_SIZE, and the
few fence options: needs, files, module, excerpt).

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
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest
from gltf_writer import moving_box

import blurlab as bl
from blurlab.metrics import perceptual

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
    "perceptual": (perceptual.available, "the optional extra blurlab[perceptual] is not installed"),
    # The user's own capture files (tests/test_capture_scoring.py runs the command on its own).
    "captures": (lambda: False, "reads the user's own capture files"),
}
FENCE = re.compile(r"^(\s*)(`{3,}|~{3,})\s*([\w+-]*)")
NEED = re.compile(r"#\s*needs:\s*([\w, ]+)\s*$")
OPTION = re.compile(r'(\w+)="([^"]*)"')


@dataclass(frozen=True)
class Located:
    """Where a documented thing is: its page and the line it starts on."""

    page: str
    line: int


@dataclass(frozen=True)
class Command(Located):
    text: str
    needs: tuple[str, ...]


def fenced_blocks(path: Path) -> list[tuple[str, dict[str, str], int, list[str]]]:
    """(language, options, first line number, lines) of each top-level fenced block of `path`.
    Options are the `key="value"` words after the language on the opening fence."""
    blocks, fence = [], None
    for number, line in enumerate(path.read_text().splitlines(), 1):
        opened = FENCE.match(line)
        if fence is None and opened:
            fence, indent = opened.group(2), len(opened.group(1))
            options = dict(OPTION.findall(line[opened.end() :]))
            blocks.append((opened.group(3), options, number + 1, []))
        elif fence is not None and line.strip().startswith(fence):
            fence = None
        elif fence is not None:
            blocks[-1][3].append(line[indent:])
    return blocks


def console_commands(path: Path, root: Path = ROOT) -> list[Command]:
    """The `$ ` lines of the ```console blocks of markdown file `path`."""
    commands = []
    for language, _options, first, lines in fenced_blocks(path):
        for number, line in enumerate(lines, first):
            if language == "console" and line.lstrip().startswith("$ "):
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
    tree's blurlab, and its benchmarks (a development package the wheel does not ship), first
    on its path."""
    folder.mkdir()
    for name, run in (("blurlab", '-m blurlab "$@"'), ("python", '"$@"'), ("python3", '"$@"')):
        shim = folder / name
        shim.write_text(f'#!/bin/sh\nexec "{sys.executable}" {run}\n')
        shim.chmod(0o755)
    package_parent = str(Path(bl.__file__).resolve().parents[1])
    benchmarks = str(ROOT / "benchmarks")
    path = os.pathsep.join(filter(None, [package_parent, benchmarks, os.environ.get("PYTHONPATH")]))
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


# Python blocks -------------------------------------------------------------------------------
#
# Every ```python block of a page runs, in page order, in one namespace per page that starts
# with `bl` (blurlab), `np` (NumPy) and `ctx` (the session's context), in an empty folder. Image
# sizes written as (W, H) with W:H = 16:9 run at TEST_SIZE, or at the size the block declares
# with `size="WxH"`, so that a page can show 1080p and CI still runs in seconds. A block may
# instead declare, on its opening fence:
#   needs="bpy"                    what it needs (NEEDS above); skipped, saying so, where unmet;
#   files="robot.glb shot.exr"     the user's files it reads: the test writes stand-ins first
#                                  (DOC_FILES: an animated glTF, a Blender-named EXR capture,
#                                  a PNG texture), chosen by suffix;
#   module="blurlab.metrics.x"     a new module: it runs as that module in a fresh interpreter;
#   excerpt="python/blurlab/x.py"  an excerpt of that file: each of its lines is in the file, in
#                                  order (a comment after two spaces at a line's end may differ).

TEST_SIZE = (160, 90)
SIZE_LITERAL = re.compile(r"\(\s*(\d{3,4})\s*,\s*(\d{2,4})\s*\)")


@dataclass(frozen=True)
class PythonBlock(Located):
    code: str
    options: dict


def python_blocks(path: Path, root: Path = ROOT) -> list[PythonBlock]:
    page = str(path.relative_to(root))
    return [
        PythonBlock(page, first, "\n".join(lines) + "\n", options)
        for language, options, first, lines in fenced_blocks(path)
        if language == "python"
    ]


def at_test_size(block: PythonBlock) -> str:
    """The block's code with its 16:9 (W, H) literals at its declared size or TEST_SIZE."""
    size = TEST_SIZE
    if "size" in block.options:
        width, height = block.options["size"].split("x")
        size = (int(width), int(height))

    def scaled(match: re.Match) -> str:
        width, height = int(match.group(1)), int(match.group(2))
        return f"({size[0]}, {size[1]})" if width * 9 == height * 16 else match.group(0)

    return SIZE_LITERAL.sub(scaled, block.code)


def _code_line(line: str) -> str:
    return " ".join(re.sub(r"\s{2,}#.*$", "", line).split())


def check_excerpt(block: PythonBlock, root: Path = ROOT) -> None:
    source = [
        _code_line(line) for line in (root / block.options["excerpt"]).read_text().split("\n")
    ]
    at = 0
    for number, line in enumerate(block.code.splitlines(), block.line):
        wanted = _code_line(line)
        if not wanted:
            continue
        assert wanted in source[at:], (
            f"{block.page}:{number}: `{line.strip()}` is not in {block.options['excerpt']} "
            "(after the block's previous lines)"
        )
        at = source.index(wanted, at) + 1


def run_as_module(block: PythonBlock, folder: Path) -> None:
    """Runs the block as module `module` of its package, in a fresh interpreter."""
    name = block.options["module"]
    program = (
        "import importlib, sys, types\n"
        f"name = {name!r}\n"
        "module = types.ModuleType(name)\n"
        "module.__package__ = name.rpartition('.')[0]\n"
        "importlib.import_module(module.__package__)\n"
        "sys.modules[name] = module\n"
        f"exec(compile({block.code!r}, {block.page!r}, 'exec'), module.__dict__)\n"
    )
    result = subprocess.run(
        [sys.executable, "-c", program],
        cwd=folder,
        env=_shims(folder / ".bin"),
        capture_output=True,
        text=True,
        timeout=COMMAND_TIMEOUT_S,
    )
    assert result.returncode == 0, f"{block.page}:{block.line}:\n{result.stderr[-3000:]}"


def _exr_capture(path: Path) -> None:
    """Colour, a depth that reads as linear or as hardware depth, and a small motion, under
    Blender's multi-layer names (every convention finds its channels among them)."""
    height, width = TEST_SIZE[1], TEST_SIZE[0]
    color = np.random.default_rng(0).random((height, width, 4))
    depth_and_vector = np.full((height, width, 5), 0.5)
    names = [f"ViewLayer.Combined.{c}" for c in "RGBA"] + ["ViewLayer.Depth.Z"]
    names += [f"ViewLayer.Vector.{c}" for c in "XYZW"]
    pixels = np.concatenate([color, depth_and_vector], axis=2).astype(np.float32)
    bl.io.write(path, pixels, channel_names=names)


def _png_texture(path: Path) -> None:
    checker = (np.indices((64, 64)).sum(axis=0) // 8 % 2).astype(np.float32)
    bl.io.write(path, np.repeat(checker[..., None], 3, axis=2))


DOC_FILES = {".glb": moving_box, ".exr": _exr_capture, ".png": _png_texture}
BLOCK_OPTIONS = {"size", "needs", "files", "module", "excerpt"}


def run_python_blocks(blocks: list[PythonBlock], folder: Path, ctx) -> dict:
    """Runs a page's blocks in order in `folder`, which is the working directory; gives their
    namespace. Skips at the first unmet need."""
    namespace = {"__name__": "__main__", "bl": bl, "np": np, "ctx": ctx}
    for block in blocks:
        where = f"{block.page}:{block.line}"
        unknown = set(block.options) - BLOCK_OPTIONS
        assert not unknown, f"{where}: unknown fence option {unknown}; {sorted(BLOCK_OPTIONS)}"
        needs = [n.strip() for n in block.options.get("needs", "").split(",") if n.strip()]
        assert set(needs) <= set(NEEDS), f"{where}: unknown need in {needs}; {list(NEEDS)}"
        files = block.options.get("files", "").split()
        strange = [f for f in files if Path(f).suffix not in DOC_FILES or Path(f).name != f]
        assert not strange, f"{where}: no stand-in for {strange}; suffixes {list(DOC_FILES)}"
        unmet = [NEEDS[n][1] for n in needs if not NEEDS[n][0]()]
        if unmet:
            pytest.skip(f"{where}: {'; '.join(unmet)}")
        for name in files:
            DOC_FILES[Path(name).suffix](folder / name)
        if "excerpt" in block.options:
            check_excerpt(block)
        elif "module" in block.options:
            run_as_module(block, folder)
        else:
            code = compile("\n" * (block.line - 1) + at_test_size(block), block.page, "exec")
            with warnings.catch_warnings():
                # A block that makes blurlab warn teaches a misuse (a frame at the wrong
                # instant, say): it fails like an error.
                warnings.filterwarnings("error", message="blurlab", category=UserWarning)
                exec(code, namespace)
    return namespace


def _pages_with_python() -> list[tuple[str, list[PythonBlock]]]:
    """Each page's blocks, once: a page whose blocks repeat an earlier page's (the README's ten
    lines are also docs/quickstart.md's) runs as that page."""
    pages, seen = [], set()
    for path in documented_pages():
        blocks = python_blocks(path)
        key = tuple((b.code, tuple(sorted(b.options.items()))) for b in blocks)
        if blocks and key not in seen:
            seen.add(key)
            pages.append((str(path.relative_to(ROOT)), blocks))
    return pages


PYTHON_PAGES = _pages_with_python()


@pytest.mark.parametrize("page, blocks", PYTHON_PAGES, ids=[page for page, _ in PYTHON_PAGES])
def test_documented_python_runs_as_written(page, blocks, ctx, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    run_python_blocks(blocks, tmp_path, ctx)


PYTHON_FIXTURE = """\
```python
frame = ctx.render(bl.scenes.fan(), (1920, 1080))
shape = frame.color.shape
```

```python size="32x18"
small = ctx.render(bl.scenes.fan(), (640, 360)).color.shape
```

```python excerpt="page.md"
shape = frame.color.shape  # a comment of the excerpt's own
```
"""


def test_python_blocks_run_in_order_at_the_test_size(ctx, tmp_path, monkeypatch):
    page = tmp_path / "page.md"
    page.write_text(PYTHON_FIXTURE)
    blocks = python_blocks(page, tmp_path)
    assert [(b.line, b.options) for b in blocks] == [
        (2, {}),
        (7, {"size": "32x18"}),
        (11, {"excerpt": "page.md"}),
    ]
    monkeypatch.chdir(tmp_path)
    namespace = run_python_blocks(blocks[:2], tmp_path, ctx)
    assert namespace["shape"] == (TEST_SIZE[1], TEST_SIZE[0], 4)
    assert namespace["small"] == (18, 32, 4)
    check_excerpt(blocks[2], tmp_path)


def test_a_broken_python_block_fails_and_names_its_line(ctx, tmp_path, monkeypatch):
    page = tmp_path / "page.md"
    page.write_text("Text.\n\n```python\nx = 1\nleaves = bl.Material(texture=rgba_leaves)\n```\n")
    monkeypatch.chdir(tmp_path)
    with pytest.raises(NameError, match="rgba_leaves") as raised:
        run_python_blocks(python_blocks(page, tmp_path), tmp_path, ctx)
    assert raised.traceback[-1].lineno + 1 == 5  # the page's own line
    stale = PythonBlock("page.md", 3, "x = 2\n", {"excerpt": "page.md"})
    with pytest.raises(AssertionError, match=r"page.md:3: `x = 2` is not in page.md"):
        check_excerpt(stale, tmp_path)


def test_a_python_block_with_an_unmet_need_is_skipped_saying_why(ctx, tmp_path):
    block = PythonBlock("page.md", 3, "raise SystemExit\n", {"needs": "scheduler"})
    with pytest.raises(pytest.skip.Exception, match="page.md:3: needs a running Dask scheduler"):
        run_python_blocks([block], tmp_path, ctx)


@pytest.mark.parametrize(
    "options, error",
    [
        ({"need": "bpy"}, "unknown fence option"),
        ({"needs": "a_gpu"}, "unknown need"),
        ({"files": "scene.usd"}, "no stand-in for"),
        ({"files": "../outside.glb"}, "no stand-in for"),
    ],
)
def test_a_python_block_with_a_mistyped_option_fails(ctx, tmp_path, options, error):
    block = PythonBlock("page.md", 3, "x = 1\n", options)
    with pytest.raises(AssertionError, match=f"page.md:3: {error}"):
        run_python_blocks([block], tmp_path, ctx)
