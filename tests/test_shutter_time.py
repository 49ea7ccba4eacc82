"""Engine frame timing (docs/spec.md §15.2): `bl.shutter` from a frame rate, a shutter angle and
a frame number, and the time Blender's glTF exporter gives a frame (frame / fps), checked
against Blender itself where bpy is installed."""

from __future__ import annotations

import json
import math
import subprocess
import warnings
from pathlib import Path

import numpy as np
import pytest

import blurlab as bl

EXPORTER = Path(__file__).with_name("blender_export.py")
needs_bpy = pytest.mark.skipif(not bl.blender.available(), reason="bpy is not installed")


def test_the_shutter_of_a_frame():
    assert bl.shutter(fps=60, angle=180, frame=12) == pytest.approx((11.75 / 60, 12.25 / 60))
    assert bl.shutter(24, 360, 0) == pytest.approx((-1 / 48, 1 / 48))
    assert bl.shutter(24, 90, 10, position="start") == pytest.approx((10 / 24, 10.25 / 24))
    assert bl.shutter(24, 90, 10, position="end") == pytest.approx((9.75 / 24, 10 / 24))
    assert bl.shutter(30, 0, 3) == (0.1, 0.1)  # a closed shutter: the sharp instant
    assert bl.shutter(30000 / 1001, 180, 2.5)[1] == pytest.approx(2.75 * 1001 / 30000)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"fps": 0}, "fps must be > 0"),
        ({"fps": -24}, "fps must be > 0"),
        ({"fps": math.inf}, "fps must be a finite number"),
        ({"fps": "24"}, "fps must be a finite number"),
        ({"angle": 400}, r"angle must be in \[0, 360\] degrees"),
        ({"angle": -1}, r"angle must be in \[0, 360\] degrees"),
        ({"angle": True}, "angle must be a finite number"),
        ({"frame": math.nan}, "frame must be a finite number"),
        ({"frame": None}, "frame must be a finite number"),
        ({"position": "middle"}, "position must be one of"),
    ],
)
def test_bad_shutter_arguments_say_what_is_allowed(kwargs, message):
    with pytest.raises(ValueError, match=message):
        bl.shutter(**kwargs)


def blender_export(scene: str, folder: Path, size=None, samples=0) -> tuple[Path, dict]:
    """Blender's own export of `scene` (tests/blender_export.py) and Blender's evaluation; with
    a size, Cycles' still and motion-blurred renders beside it (OUT.still.exr, OUT.blur.exr)."""
    out = folder / f"{scene}.glb"
    rendering = [] if size is None else [*map(str, size), str(samples)]
    result = subprocess.run(
        # The Python that has bpy: blurlab's private environment for it (blurlab blender install).
        [bl.blender.environment.interpreter(), str(EXPORTER), scene, str(out), *rendering],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert result.returncode == 0 and out.is_file(), result.stdout[-2000:] + result.stderr[-2000:]
    return out, json.loads(Path(str(out) + ".json").read_text())


# Blender is z-up, glTF y-up: the exporter writes Blender (x, y, z) as glTF (x, z, -y).
Z_UP_TO_Y_UP = np.array([[1, 0, 0, 0], [0, 0, 1, 0], [0, -1, 0, 0], [0, 0, 0, 1.0]])


@needs_bpy
def test_blender_exports_frame_f_at_time_f_over_fps(tmp_path):
    path, blender = blender_export("timing", tmp_path)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # one animation per object: all play, nothing warned
        scene = bl.scenes.gltf(path)
    fps = blender["fps"]
    assert len(scene.objects) == 2
    for frame, matrices in blender["frames"].items():
        t = int(frame) / fps
        for obj, name in zip(scene.objects, ("Slider", "Spinner"), strict=True):
            assert obj.name.startswith(name)
            expected = Z_UP_TO_Y_UP @ np.array(matrices[name]) @ Z_UP_TO_Y_UP.T
            assert np.allclose(obj.model(t), expected, atol=1e-5), (frame, name)
    # The shutter of frame 22 at 180° spans Blender's frames 21.75..22.25.
    t0, t1 = bl.shutter(fps, 180, 22)
    x = [scene.objects[0].model(t)[0, 3] for t in (t0, t1)]
    slider = [np.array(blender["frames"][str(f)]["Slider"])[0, 3] for f in (21, 22, 23)]
    assert slider[0] < x[0] < slider[1] < x[1] < slider[2]
