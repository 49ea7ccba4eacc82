"""Method folders (docs/adding_a_method.md): `blurlab new-method` writes one that passes
`blurlab check-method` and takes its place in a study, in GLSL and in HLSL; check-method names
the check a broken method fails; an installed package offers a method through its entry point;
bad folders are refused with an error naming the file."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pandas as pd
import pytest
from conftest import CLI_DEVICE

import blurlab as bl
from blurlab.methods import folders, hlsl
from blurlab.methods.contract import check_method
from blurlab.methods.template import write_template

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = Path(__file__).parent / "data" / "entry_point_package"
HLSL_TOOLS = shutil.which("glslangValidator") is not None and shutil.which("spirv-cross")
needs_hlsl_tools = pytest.mark.skipif(not HLSL_TOOLS, reason="glslang-tools/spirv-cross absent")


@pytest.fixture(autouse=True)
def registry_restored():
    """Whatever a test loads leaves the registry with it: other tests read bl.methods()."""
    before = set(bl.methods())
    yield
    bl.unload_methods([name for name in bl.methods() if name not in before])


def environment(**extra) -> dict:
    """This process's environment with blurlab importable from anywhere (the checkout's
    python/ first where the tests run from one)."""
    env = dict(os.environ, **extra)
    paths = [str(Path(bl.__file__).parents[1]), env.get("PYTHONPATH", "")]
    env["PYTHONPATH"] = os.pathsep.join(p for p in paths if p)
    return env


def blurlab(*args, cwd: Path, env: dict | None = None) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "blurlab", "--device", CLI_DEVICE, *args],
        capture_output=True,
        text=True,
        cwd=cwd,
        env=env or environment(),
        timeout=600,
    )


@pytest.mark.e2e
@pytest.mark.parametrize("language", ["glsl", pytest.param("hlsl", marks=needs_hlsl_tools)])
def test_a_new_method_passes_the_contract_and_joins_a_study(tmp_path, language):
    """As a new user would, from an empty folder outside the repository."""
    made = blurlab("new-method", "my_tent", "--language", language, "--out", "X", cwd=tmp_path)
    assert made.returncode == 0, made.stderr
    checked = blurlab("check-method", "X/my_tent", cwd=tmp_path)
    assert checked.returncode == 0, checked.stdout + checked.stderr
    assert "0 failed" in checked.stdout and "FAILED" not in checked.stdout
    study = blurlab(
        "study",
        "--methods-from",
        "X",
        "--scenes",
        "fan",
        "teapot_pass",
        "--size",
        "160x90",
        "--out",
        "out",
        cwd=tmp_path,
    )
    assert study.returncode == 0, study.stderr
    rows = pd.read_csv(tmp_path / "out" / "results.csv")
    mine = rows[rows["method"] == "my_tent"]
    assert set(mine["scene"]) == {"fan", "teapot_pass"} and mine["psnr"].notna().all()
    assert "my_tent" in (tmp_path / "out" / "report.html").read_text()


def tent(tmp_path: Path, language: str = "glsl", old: str = "", new: str = "") -> Path:
    """The template folder, its shader's `old` text replaced by `new`."""
    folder = write_template("my_tent", tmp_path, language)
    shader = folder / f"gather.{language}"
    text = shader.read_text()
    assert old in text
    shader.write_text(text.replace(old, new, 1))
    return folder


def failed(ctx, folder: Path) -> dict[str, str]:
    (name,) = bl.load_methods(folder)
    return {c.name: c.detail for c in check_method(ctx, name) if c.passed is False}


def test_a_shader_that_disagrees_with_its_twin_fails_the_twin_checks(ctx, tmp_path):
    folder = tent(tmp_path, old="1.0 - 2.0 * abs(s)", new="1.0")  # a box, not a tent
    checks = failed(ctx, folder)
    assert "twin_on_random_frames" in checks and "twin_on_a_rendered_frame" in checks
    assert "of pixels within 0.001 of the twin" in checks["twin_on_random_frames"]


def test_nan_for_finite_input_fails_by_name(ctx, tmp_path):
    folder = tent(
        tmp_path,
        old="return sum / total;",
        new="return x == ivec2(3, 2) ? vec4(uintBitsToFloat(0x7fc00000u)) : sum / total;",
    )
    checks = failed(ctx, folder)
    assert "finite_for_finite_input" in checks, checks
    assert "non-finite values for finite input" in checks["finite_for_finite_input"]


GL_ERROR_METHOD = """
import ctypes

from blurlab.methods.chain import chain_run

from .twin import my_tent

egl = ctypes.CDLL("libEGL.so.1")
egl.eglGetProcAddress.restype = ctypes.c_void_p
gl_enable = ctypes.CFUNCTYPE(None, ctypes.c_uint)(egl.eglGetProcAddress(b"glEnable"))


def run(ctx, frame, inputs, values, backend, passes):
    out = chain_run(tuple(passes.values()), PARAMS, "my_tent")(ctx, frame, inputs, values, backend)
    gl_enable(0xFFFF)  # not a capability: GL_INVALID_ENUM, left set
    return out


METHOD = dataclasses.replace(METHOD, run=run)
"""


def test_a_gl_error_left_behind_fails_by_name(ctx, tmp_path):
    folder = write_template("my_tent", tmp_path)
    declaration = folder / "method.py"
    text = "import dataclasses\n" + declaration.read_text() + GL_ERROR_METHOD
    declaration.write_text(text)
    checks = failed(ctx, folder)
    assert "no_gl_error_left" in checks, checks
    assert "GL_INVALID_ENUM" in checks["no_gl_error_left"]
    assert ctx.gl_errors() == []  # the check read and cleared it


def test_a_glsl_compile_error_fails_with_file_and_line(tmp_path):
    folder = tent(tmp_path, old="float total = 0.0;", new="float total = 0.0")
    result = blurlab("check-method", str(folder), cwd=tmp_path)
    assert result.returncode == 1
    line = next(
        n
        for n, t in enumerate((folder / "gather.glsl").read_text().splitlines(), 1)
        if "float total" in t
    )
    runs = next(r for r in result.stdout.splitlines() if r.strip().startswith("runs"))
    assert "FAILED" in runs and "failed to compile" in runs
    assert f"{folder / 'gather.glsl'}:" in result.stdout
    assert any(f"gather.glsl:{n}" in result.stdout for n in (line, line + 1)), result.stdout


@needs_hlsl_tools
def test_an_hlsl_compile_error_fails_with_file_and_line(tmp_path):
    folder = tent(tmp_path, "hlsl", old="float total = 0.0;", new="float total = undeclared;")
    result = blurlab("check-method", str(folder), cwd=tmp_path)
    assert result.returncode == 1
    loads = next(r for r in result.stdout.splitlines() if r.strip().startswith("loads"))
    assert "FAILED" in loads
    line = next(
        n
        for n, t in enumerate((folder / "gather.hlsl").read_text().splitlines(), 1)
        if "undeclared" in t
    )
    assert f"gather.hlsl:{line}:" in result.stdout and "undeclared" in result.stdout


def test_an_installed_package_offers_a_method_through_its_entry_point(tmp_path):
    """tests/data/entry_point_package with the template's folder as its module
    blurlab_example.example_tent, installed with pip offline into a folder on the path."""
    package = shutil.copytree(PACKAGE, tmp_path / "package")
    module = write_template("example_tent", package / "src" / "blurlab_example")
    (module / "test_example_tent.py").unlink()
    (module / "__init__.py").write_text('"""The method folder example_tent."""\n')
    target = tmp_path / "site"
    install = subprocess.run(
        [sys.executable, "-m", "pip", "install", "--no-deps", "--no-build-isolation",
         "--no-index", "--quiet", "--target", str(target), str(package)],
        capture_output=True, text=True, timeout=300, cwd=package,
    )  # fmt: skip
    assert install.returncode == 0, install.stderr
    env = environment()
    env["PYTHONPATH"] = os.pathsep.join([str(target), env["PYTHONPATH"]])
    listing = blurlab("methods", cwd=tmp_path, env=env)
    assert listing.returncode == 0, listing.stderr
    assert "## example_tent" in listing.stdout
    blurred = subprocess.run(
        [sys.executable, "-c", BLUR_EXAMPLE, CLI_DEVICE],
        capture_output=True, text=True, cwd=tmp_path, env=env, timeout=300,
    )  # fmt: skip
    assert blurred.returncode == 0, blurred.stderr
    assert blurred.stdout.split() == ["gather", "site", "blurred"]


BLUR_EXAMPLE = """
import sys
import numpy as np
import blurlab as bl
ctx = bl.Context(sys.argv[1])
frame = ctx.render(bl.scenes.fan(), (64, 36))
result = bl.blur(ctx, frame, "example_tent", taps=5)
expected = bl.method("example_tent").twin_output(frame, **result.params)
assert (np.abs(result.color - expected).max(axis=-1) <= 1e-3).mean() >= 0.999
print(*result.timings, bl.method("example_tent").source.split("/")[-4],
      "blurred" if np.abs(result.color - frame.color).max() > 0.05 else "unchanged")
"""


def test_a_folder_without_a_declaration_is_refused_by_name(tmp_path):
    (tmp_path / "empty" / "inner").mkdir(parents=True)
    with pytest.raises(folders.MethodFolderError, match=r"empty has no method\.py"):
        bl.load_methods(tmp_path / "empty")


def test_a_parameter_without_a_range_is_refused_naming_the_file(tmp_path):
    folder = write_template("my_tent", tmp_path)
    declaration = folder / "method.py"
    declaration.write_text(declaration.read_text().replace(", low=0.0, high=4.0", ""))
    with pytest.raises(folders.MethodFolderError, match="parameter scale has no range") as error:
        bl.load_methods(folder)
    assert str(declaration) in str(error.value)


def test_a_built_in_name_is_refused_naming_the_file(tmp_path):
    built_in = bl.methods()[0]
    folder = write_template("my_tent", tmp_path)
    declaration = folder / "method.py"
    declaration.write_text(declaration.read_text().replace('name="my_tent"', f'name="{built_in}"'))
    with pytest.raises(folders.MethodFolderError, match="the name of the built-in method") as error:
        bl.load_methods(folder)
    assert str(declaration) in str(error.value) and built_in in str(error.value)
    assert bl.method(built_in).source is None  # the built-in is untouched


def test_two_folders_of_one_name_are_refused(tmp_path):
    write_template("my_tent", tmp_path / "a")
    write_template("my_tent", tmp_path / "b")
    bl.load_methods(tmp_path / "a" / "my_tent")
    bl.load_methods(tmp_path / "a" / "my_tent")  # the same folder again replaces itself
    with pytest.raises(folders.MethodFolderError, match="from .*a/my_tent/method.py"):
        bl.load_methods(tmp_path / "b")


def test_absent_hlsl_tools_are_named_with_their_packages(tmp_path, monkeypatch):
    folder = write_template("my_tent", tmp_path, "hlsl")
    monkeypatch.setattr(hlsl.shutil, "which", lambda name: None)
    with pytest.raises(folders.MethodFolderError) as error:
        bl.load_methods(folder)
    text = str(error.value)
    assert str(folder / "method.py") in text and "glslang-tools" in text and "spirv-cross" in text


def test_a_shader_outside_the_folder_is_refused(tmp_path):
    folder = write_template("my_tent", tmp_path)
    declaration = folder / "method.py"
    declaration.write_text(declaration.read_text().replace('"gather.glsl"', '"../gather.glsl"'))
    shutil.copy(folder / "gather.glsl", tmp_path)
    with pytest.raises(folders.MethodFolderError, match="outside the method's folder"):
        bl.load_methods(folder)


def test_order_places_a_method_among_the_others(tmp_path):
    folder = write_template("my_tent", tmp_path)
    declaration = folder / "method.py"
    declaration.write_text(
        declaration.read_text().replace('kind="gather",', 'kind="gather", order=-1,')
    )
    bl.load_methods(folder)
    assert bl.methods()[0] == "my_tent"


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        ('name="my_tent"', 'name="My Tent"', "name 'My Tent' must be lower case"),
        ('kind="gather"', 'kind="render"', "a render method needs a run of its own"),
        ("tuple(PARAMS)", '("taps", "spread")', r"takes \['spread'\], which are not declared"),
        ('{"taps": [5, 9, 17]}', '{"taps": [1]}', r"default_grid: .*taps = 1 is outside 2\.\.64"),
        ('"gather.glsl"', '"gather.txt"', "must end in .glsl, .comp or .hlsl"),
        ("METHOD = Declaration(", "raise RuntimeError('broken')\nMETHOD = Declaration(",
         "failed to run: RuntimeError: broken"),
    ],
)  # fmt: skip
def test_a_bad_declaration_is_refused_naming_the_file(tmp_path, old, new, message):
    folder = write_template("my_tent", tmp_path)
    declaration = folder / "method.py"
    shutil.copy(folder / "gather.glsl", folder / "gather.txt")
    text = declaration.read_text()
    assert old in text
    declaration.write_text(text.replace(old, new, 1))
    with pytest.raises(folders.MethodFolderError, match=message) as error:
        bl.load_methods(folder)
    assert str(declaration) in str(error.value)


def test_a_broken_entry_point_is_skipped_with_a_warning(monkeypatch):
    class Broken:
        name, value = "broken", "no_such_package.methods"

        def load(self):
            raise ImportError("No module named 'no_such_package'")

    monkeypatch.setattr(folders.importlib.metadata, "entry_points", lambda group: [Broken()])
    with pytest.warns(UserWarning, match="skipped the methods of entry point broken"):
        assert folders.load_entry_points() == []


def test_methods_from_goes_with_this_process_only(tmp_path):
    write_template("my_tent", tmp_path)
    result = blurlab(
        "study", "--methods-from", str(tmp_path), "--workers", "2", "--out", "o", cwd=tmp_path
    )
    assert result.returncode == 2 and "--methods-from loads methods into this process" in (
        result.stderr
    )


def test_methods_lists_a_loaded_method_with_its_folder(tmp_path):
    folder = write_template("my_tent", tmp_path)
    result = blurlab("methods", "my_tent", "--methods-from", str(tmp_path), cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert "## my_tent" in result.stdout and f"declared in {folder / 'method.py'}" in result.stdout
    assert "| `scale` | 1.0 | [0, 4] |" in result.stdout
