"""Blender's Python module in an environment of its own, so that the user's never changes.

bpy 5.0 from PyPI exists for Python 3.11 only and pins NumPy 1.26, which would downgrade the
NumPy 2 (and pandas) of the environment blurlab runs in. blurlab never imports bpy itself: it
runs Blender in a child process (blurlab.blender.child), which needs bpy and NumPy only. So
``blurlab blender install`` makes a virtual environment under blurlab's cache folder with bpy
and what bpy pins, and blurlab.blender runs its child with that environment's Python.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

from .._paths import cache_root

BPY_REQUIREMENT = "bpy>=5.0,<5.1"
BPY_PYTHON = (3, 11)  # the only Python that bpy 5.0's wheels are built for
ENVIRONMENT = "bpy-5.0-py3.11"  # the environment's folder under environments()
INSTALL_TIMEOUT_S = 3600  # bpy's wheel is 374 MB


def environments() -> Path:
    """The folder of blurlab's private environments (under cache_root())."""
    return cache_root() / "environments"


def environment() -> Path:
    """The folder of the private environment that holds bpy."""
    return environments() / ENVIRONMENT


def environment_python() -> Path:
    return environment() / "bin" / "python"


def installed() -> bool:
    """Whether the private environment is complete: its Python exists and has bpy (read
    from its files, without starting it). `install` writes the marker file last."""
    return environment_python().is_file() and (environment() / "blurlab-complete").is_file()


def interpreter() -> str | None:
    """The Python that runs Blender's child: the private environment's where it is installed,
    else this Python where bpy can be imported here (an environment of the user's own making),
    else None."""
    import importlib.util

    if installed():
        return str(environment_python())
    if importlib.util.find_spec("bpy") is not None:
        return sys.executable
    return None


def find_python311(python: str | os.PathLike | None = None) -> str:
    """A Python 3.11 to make the environment with: `python` if given, else this one if it is
    3.11, else python3.11 on PATH; a RuntimeError saying what to give otherwise."""
    candidates = [str(python)] if python else []
    if not python:
        if sys.version_info[:2] == BPY_PYTHON:
            candidates.append(sys.executable)
        found = shutil.which("python3.11")
        if found:
            candidates.append(found)
    for candidate in candidates:
        try:
            version = subprocess.run(
                [candidate, "-c", "import sys; print(*sys.version_info[:2])"],
                capture_output=True,
                text=True,
                timeout=60,
            ).stdout.split()
        except OSError:
            continue
        if tuple(map(int, version)) == BPY_PYTHON:
            return candidate
    raise RuntimeError(
        "blurlab blender install: bpy 5.0 needs Python 3.11, and "
        + (f"{python} is not one" if python else "neither this Python nor python3.11 on PATH is")
        + "; give one with --python PATH (python=)"
    )


def install(python: str | os.PathLike | None = None, echo=print) -> Path:
    """Makes the private environment (a venv of a Python 3.11, see find_python311) and
    installs bpy into it with pip, with what bpy pins; returns its Python. Nothing is
    installed into this Python's environment. Where it is already complete, does nothing.
    A failed install leaves no environment that `installed` would take for complete."""
    if installed():
        echo(f"Blender's bpy is installed in {environment()}")
        return environment_python()
    base = find_python311(python)
    folder = environment()
    if folder.exists():  # an earlier install that did not finish
        shutil.rmtree(folder)
    folder.parent.mkdir(parents=True, exist_ok=True)
    echo(f"making {folder} with {base} and installing {BPY_REQUIREMENT} (a 374 MB download)")
    steps = [
        [base, "-m", "venv", str(folder)],
        [str(folder / "bin" / "python"), "-m", "pip", "install", "-q", BPY_REQUIREMENT],
    ]
    for command in steps:
        result = subprocess.run(command, capture_output=True, text=True, timeout=INSTALL_TIMEOUT_S)
        if result.returncode != 0:
            shutil.rmtree(folder, ignore_errors=True)
            raise RuntimeError(
                f"blurlab blender install: {' '.join(command)} failed:\n{result.stderr[-3000:]}"
            )
    (folder / "blurlab-complete").write_text(BPY_REQUIREMENT + "\n")
    echo(f"Blender's bpy is installed in {folder}; blurlab.blender runs Blender with its Python")
    return environment_python()


def uninstall(echo=print) -> None:
    """Removes the private environment."""
    if environment().exists():
        shutil.rmtree(environment())
        echo(f"removed {environment()}")
    else:
        echo(f"nothing to remove: {environment()} does not exist")
