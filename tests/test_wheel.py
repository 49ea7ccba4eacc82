"""The binary wheel, as a user gets it: `make wheel` (packaging/build-wheel.sh: zig for glibc
2.28, auditwheel, under pip's build isolation) builds it into dist/, and these tests check that
wheel: installed into a fresh venv with --no-deps plus the runtime requirements its metadata
declares, and smoke-tested there in a subprocess with the source tree off the path
(tests/wheel_smoke.py). .ci/run runs `make wheel` before `make test` and sets
BLURLAB_WHEEL_REQUIRED=1, so there a missing or stale wheel fails; elsewhere it skips, saying
to run `make wheel`. Each step's seconds are written to build/wheel-test.json."""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
import time
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PLATFORM = "manylinux_2_28_x86_64"
# What manylinux_2_28 lets a wheel take from the system (PEP 600's glibc set). libEGL is not
# among them: the module opens it with dlopen, so it must not be a dependency at all.
SYSTEM_LIBRARIES = {"libc.so.6", "libm.so.6", "libpthread.so.0", "libdl.so.2", "librt.so.1"}
SIZE_LIMIT = 10 * 1024 * 1024

pytestmark = pytest.mark.wheel


def run(command, **kwargs) -> subprocess.CompletedProcess:
    result = subprocess.run(command, capture_output=True, text=True, **kwargs)
    assert result.returncode == 0, (
        f"{' '.join(map(str, command))} failed ({result.returncode}):\n"
        f"{result.stdout[-4000:]}\n{result.stderr[-4000:]}"
    )
    return result


def runtime_requirements(wheel: Path) -> list[str]:
    """Requires-Dist of the wheel's metadata, less the optional extras."""
    with zipfile.ZipFile(wheel) as archive:
        name = next(n for n in archive.namelist() if n.endswith(".dist-info/METADATA"))
        metadata = archive.read(name).decode()
    lines = re.findall(r"^Requires-Dist: (.+)$", metadata, flags=re.MULTILINE)
    return [line.strip() for line in lines if "extra ==" not in line]


def needed_libraries(wheel: Path, folder: Path) -> dict[str, list[str]]:
    """DT_NEEDED of every shared object in the wheel."""
    from elftools.elf.dynamic import DynamicSection
    from elftools.elf.elffile import ELFFile

    needed = {}
    with zipfile.ZipFile(wheel) as archive:
        for name in archive.namelist():
            if ".so" not in Path(name).name:
                continue
            path = Path(archive.extract(name, folder))
            with path.open("rb") as handle:
                for section in ELFFile(handle).iter_sections():
                    if isinstance(section, DynamicSection):
                        needed[name] = [
                            tag.needed
                            for tag in section.iter_tags()
                            if tag.entry.d_tag == "DT_NEEDED"
                        ]
    return needed


@pytest.fixture(scope="module")
def timings():
    seconds = {}
    yield seconds
    (ROOT / "build").mkdir(exist_ok=True)
    (ROOT / "build" / "wheel-test.json").write_text(json.dumps(seconds, indent=2) + "\n")


# What the wheel is built from: a wheel older than any of these does not show this tree.
SOURCES = ("CMakeLists.txt", "pyproject.toml", "src", "shaders", "python/blurlab")


def _newest_source() -> tuple[float, Path]:
    files = [ROOT / name for name in SOURCES if (ROOT / name).is_file()]
    files += [f for name in SOURCES if (ROOT / name).is_dir() for f in (ROOT / name).rglob("*")]
    return max(
        (f.stat().st_mtime, f) for f in files if f.is_file() and "__pycache__" not in f.parts
    )


@pytest.fixture(scope="module")
def wheel() -> Path:
    tag = f"cp{sys.version_info.major}{sys.version_info.minor}"
    wheels = sorted((ROOT / "dist").glob(f"blurlab-*-{tag}-{tag}-{PLATFORM}.whl"))
    problem = ""
    if len(wheels) != 1:
        problem = f"expected one {tag} {PLATFORM} wheel in dist/, found {wheels}"
    elif wheels[0].stat().st_mtime < _newest_source()[0]:
        problem = f"{wheels[0].name} is older than {_newest_source()[1].relative_to(ROOT)}"
    if problem and os.environ.get("BLURLAB_WHEEL_REQUIRED") == "1":
        pytest.fail(problem)
    if problem:
        pytest.skip(f"{problem}: run `make wheel` first (.ci/run does)")
    return wheels[0]


def test_sdist_is_built_beside_the_wheel(wheel):
    # build-wheel.sh builds the wheel from this sdist, so its existence here means it built.
    sdists = list((ROOT / "dist").glob("blurlab-*.tar.gz"))
    assert len(sdists) == 1
    assert sdists[0].stat().st_mtime <= wheel.stat().st_mtime


def test_wheel_is_manylinux_with_system_libraries_only(wheel, tmp_path, timings):
    shown = run([sys.executable, "-m", "auditwheel", "show", str(wheel)]).stdout
    flat = " ".join(shown.split())
    tag = re.search(r'consistent with the following platform tag: "manylinux_2_(\d+)_x86_64"', flat)
    assert tag and int(tag.group(1)) <= 28, shown
    assert "external shared libraries are required" not in flat, shown
    system = set(re.findall(r"(lib[\w+-]+\.so\.\d+) with versions", flat))
    assert system and system <= SYSTEM_LIBRARIES, shown
    needed = needed_libraries(wheel, tmp_path)
    assert any(name.startswith("blurlab/_core") for name in needed), needed
    for name, libraries in needed.items():
        outside = set(libraries) - SYSTEM_LIBRARIES - {"ld-linux-x86-64.so.2"}
        assert not outside, f"{name} needs {sorted(outside)} beyond the manylinux system set"
    timings["wheel_bytes"] = wheel.stat().st_size
    assert wheel.stat().st_size <= SIZE_LIMIT


def test_wheel_carries_the_shaders_and_data_files(wheel):
    with zipfile.ZipFile(wheel) as archive:
        names = {n for n in archive.namelist() if not n.endswith("/")}
    shaders = {
        "blurlab/shaders/" + p.relative_to(ROOT / "shaders").as_posix()
        for p in (ROOT / "shaders").rglob("*")
        if p.is_file()
    }
    package = ROOT / "python" / "blurlab"
    data = {
        "blurlab/" + p.relative_to(package).as_posix()
        for p in package.rglob("*")
        if p.is_file() and p.suffix not in (".py", ".pyc") and "__pycache__" not in p.parts
    }
    assert data, "the package's data files were not found in the tree"
    assert shaders <= names, sorted(shaders - names)
    assert data <= names, sorted(data - names)
    in_wheel = {n for n in names if n.startswith("blurlab/shaders/")}
    assert in_wheel == shaders, sorted(in_wheel ^ shaders)


def test_wheel_holds_the_library_and_no_benchmark(wheel):
    """The wheel holds what a user imports: the modules of python/blurlab less the built-in
    method folders' tests (the template's stays: new-method writes it), and none of the
    benchmarks' development package (benchmarks/blurlab_bench)."""
    with zipfile.ZipFile(wheel) as archive:
        modules = {n for n in archive.namelist() if n.endswith(".py")}
    package = ROOT / "python" / "blurlab"
    tests = {
        p for p in (package / "methods").glob("*/test_*.py") if p.parent.name != "template_files"
    }
    assert tests, "the method folders' tests were not found in the tree"
    library = {
        "blurlab/" + p.relative_to(package).as_posix()
        for p in package.rglob("*.py")
        if p not in tests
    }
    assert modules == library, sorted(modules ^ library)
    benchmarks = [n for n in modules if "bench" in Path(n).parent.as_posix()]
    assert not benchmarks, benchmarks


def test_installed_wheel_runs_outside_the_source_tree(wheel, tmp_path, timings):
    venv = tmp_path / "venv"
    start = time.perf_counter()
    run([sys.executable, "-m", "venv", str(venv)])
    python = venv / "bin" / "python"
    timings["venv_s"] = round(time.perf_counter() - start, 1)
    start = time.perf_counter()
    run([python, "-m", "pip", "install", "-q", "--no-deps", str(wheel)])
    timings["pip_install_wheel_s"] = round(time.perf_counter() - start, 1)
    start = time.perf_counter()
    run([python, "-m", "pip", "install", "-q", *runtime_requirements(wheel)])
    timings["pip_install_requirements_s"] = round(time.perf_counter() - start, 1)

    # -I: no PYTHONPATH, no user site, not even the script's folder on sys.path.
    env = {k: v for k, v in os.environ.items() if not k.startswith("BLURLAB_")}
    start = time.perf_counter()
    smoke = run(
        [python, "-I", str(ROOT / "tests" / "wheel_smoke.py"), str(ROOT)], cwd=tmp_path, env=env
    )
    timings["smoke_s"] = round(time.perf_counter() - start, 1)
    result = json.loads(smoke.stdout)
    assert Path(result["blurlab"]).is_relative_to(venv)
    assert "llvmpipe" in result["renderer"]
    assert result["psnr_blurred"] > result["psnr_still"], result
    assert all(not Path(p).is_relative_to(venv) for p in result["libEGL"]), result
    # The dynamic linker's view: libEGL is opened at run time, so it is no dependency at all.
    ldd = run(["ldd", result["core"]]).stdout
    (ROOT / "build" / "wheel-ldd.txt").write_text(ldd)
    assert "not found" not in ldd and "epoxy" not in ldd and "libEGL" not in ldd, ldd
    assert "libstdc++" not in ldd, ldd

    info = run([venv / "bin" / "blurlab", "--device", "software", "info"], cwd=tmp_path, env=env)
    assert json.loads(info.stdout)["context"]["device"] == "software"
    # The benchmarks are not in the wheel, and its `blurlab bench` says where they are.
    bench = subprocess.run(
        [venv / "bin" / "blurlab", "bench", "--list"], cwd=tmp_path, env=env, capture_output=True
    )
    assert bench.returncode == 2 and b"development package" in bench.stderr, bench


@pytest.mark.parametrize(
    ("headers", "tag", "match"),
    [
        ("empty", "cp312", "needs Python.h and the real pyconfig.h"),
        ("wrapper", "cp312", "needs Python.h and the real pyconfig.h"),
        ("real", "py3", "PYTHON_TAG must be a CPython tag"),
    ],
)
def test_a_wheel_for_another_python_refuses_unusable_headers(tmp_path, headers, tag, match):
    """PYTHON_HEADERS + PYTHON_TAG (a wheel for another CPython) checks its inputs before any
    build: Debian's multiarch pyconfig.h wrapper would compile against the wrong Python."""
    folder = tmp_path / "include"
    folder.mkdir()
    if headers != "empty":
        (folder / "Python.h").write_text("")
        wrapper = "#  include <x86_64-linux-gnu/python3.12/pyconfig.h>\n"
        (folder / "pyconfig.h").write_text(wrapper if headers == "wrapper" else "#define X 1\n")
    result = subprocess.run(
        ["bash", str(ROOT / "packaging/build-wheel.sh")],
        capture_output=True,
        text=True,
        env={**os.environ, "PYTHON_HEADERS": str(folder), "PYTHON_TAG": tag},
        timeout=60,
    )
    assert result.returncode == 2 and match in result.stderr, result.stderr
    assert not list(tmp_path.glob("*.whl"))
