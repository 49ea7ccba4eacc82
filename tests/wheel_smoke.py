"""Smoke test of an installed blurlab, run from outside the source tree (tests/test_wheel.py
runs it in a fresh venv that holds only the wheel and its runtime requirements).

Usage: python -I tests/wheel_smoke.py SOURCE_TREE [DEVICE] -> one JSON object on stdout
(DEVICE: "software", the default, or "gpu" as benchmarks/gpu.sh runs it). It fails (an
AssertionError) when blurlab or anything on sys.path comes from SOURCE_TREE, when libepoxy is
loaded, or when libEGL comes from inside the Python environment rather than from the system.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

import blurlab as bl
from blurlab import _core
from blurlab.methods import example_method


def inside(path: Path, folder: Path) -> bool:
    return path == folder or folder in path.parents


def loaded_libraries() -> list[Path]:
    with open("/proc/self/maps") as maps:
        paths = {line.split()[-1] for line in maps if len(line.split()) >= 6}
    return sorted(Path(p) for p in paths if p.startswith("/") and ".so" in p)


def main() -> None:
    source = Path(sys.argv[1]).resolve()
    package = Path(bl.__file__).resolve().parent
    assert not inside(package, source), f"blurlab was imported from the source tree: {package}"
    on_path = [p for p in sys.path if p and inside(Path(p).resolve(), source)]
    assert not on_path, f"the source tree is on sys.path: {on_path}"

    ctx = bl.Context(sys.argv[2] if len(sys.argv) > 2 else "software")
    size = (160, 90)
    scene = bl.scenes.teapot_pass()
    frame = ctx.render(scene, size)
    blurred = bl.blur(ctx, frame, example_method())
    reference = ctx.reference(scene, size, samples=64, progress=False)
    result = {
        "blurlab": str(package),
        "core": str(Path(_core.__file__).resolve()),
        "renderer": ctx.info()["renderer"],
        "psnr_still": bl.metrics.psnr(reference.color, frame.color),
        "psnr_blurred": bl.metrics.psnr(reference.color, blurred.color),
        "ssim_blurred": bl.metrics.ssim(reference.color, blurred.color),
        "flip_blurred": bl.metrics.flip(reference.color, blurred.color),
    }
    for key in ("psnr_still", "psnr_blurred", "ssim_blurred", "flip_blurred"):
        assert np.isfinite(result[key]), f"{key} is not finite: {result[key]}"
    assert result["psnr_blurred"] > result["psnr_still"], f"the blur moved away: {result}"

    libraries = loaded_libraries()
    egl = [p for p in libraries if p.name.startswith("libEGL.so")]
    assert egl, "libEGL.so.1 is not loaded after creating a context"
    # Not from where blurlab was installed, nor from a venv's own folder (a system Python's
    # prefix, /usr, is where the system's libEGL lives).
    shipped = [package.parent] + ([Path(sys.prefix)] if sys.prefix != sys.base_prefix else [])
    from_python = [p for p in egl if any(inside(p.resolve(), r.resolve()) for r in shipped)]
    assert not from_python, f"libEGL comes with the Python install, not the system: {from_python}"
    epoxy = [p for p in libraries if "epoxy" in p.name]
    assert not epoxy, f"libepoxy is loaded: {epoxy}"
    result["libEGL"] = [str(p) for p in egl]
    json.dump(result, sys.stdout)


if __name__ == "__main__":
    main()
