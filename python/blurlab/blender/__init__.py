"""A blurlab Scene rendered by Blender (Cycles or EEVEE), headless, for cross-checks
(docs/crosscheck.md).

The scene is exported here, without Blender: blurlab's own triangles, its transforms sampled
densely over the shutter, the camera's matrices, materials as emission plus a shadowless sun.
Blender (the ``bpy`` module of the optional extra ``blender``) then runs in a child process
(``child.py`` beside this file), so a Blender crash never takes the caller down; its log comes
back in the exception.
"""

from __future__ import annotations

import json
import math
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from numbers import Real
from pathlib import Path

import numpy as np

from ..core.render import check_shutter, check_size
from ..io import capture
from ..io import images as io
from ..scene.blur_scales import scaled_scene
from ..scene.model import Scene
from ..sizes import DEFAULT_SIZE
from . import environment

CHILD = Path(__file__).with_name("child.py")
ENGINES = {"CYCLES": "CYCLES", "EEVEE": "BLENDER_EEVEE"}
INSTALL = (
    "blurlab.blender needs Blender's Python module: run `blurlab blender install`, which puts "
    "bpy 5.0 (Python 3.11 only) in an environment of its own and leaves yours unchanged "
    "(docs/crosscheck.md)"
)
# blurlab is y-up, Blender z-up: Blender (x, y, z) = blurlab (x, -z, y).
Y_UP_TO_Z_UP = np.array([[1, 0, 0, 0], [0, 0, -1, 0], [0, 1, 0, 0], [0, 0, 0, 1.0]])
LOG_TAIL_LINES = 40
MAX_SIZE = 16384  # Blender's largest render resolution is larger; blurlab's textures are not
DEFAULT_SAMPLES = {"CYCLES": 128, "EEVEE": 64}  # EEVEE's is Blender's own default
DEFAULT_STEPS = {"CYCLES": 7, "EEVEE": 1}
# Cycles draws each path's time through a table of this many entries (its SHUTTER_TABLE_SIZE),
# which is why its shutter is a little shorter than the one it is given: cycles_shutter.
CYCLES_SHUTTER_TABLE = 256


class BlenderError(RuntimeError):
    """Blender failed, crashed or ran out of time; the message ends with its log's tail."""


@dataclass
class BlenderRender:
    """What Blender rendered: linear float32 (H, W, 4) color, the settings it used, the wall
    time of the whole child process (start, scene build, shader compile, render, write) and of
    the render call alone, and the device that rendered."""

    color: np.ndarray
    settings: dict
    wall_s: float
    render_s: float
    device: str
    log: str = field(default="", repr=False)


def available() -> bool:
    """Whether Blender can run: blurlab's private environment has bpy (`blurlab blender
    install`), or this Python can import it (bpy is not imported here)."""
    return environment.interpreter() is not None


def check_reproducible(scene: Scene) -> None:
    """Raises ValueError naming the first thing of `scene` that Blender cannot match.
    Textures are exported (linear, repeating, bilinear without mipmaps in Blender, whose
    samples per pixel do the filtering), so minified textures differ a little."""
    if not isinstance(scene, Scene):
        raise TypeError(f"blurlab.blender needs a blurlab Scene, not {type(scene).__name__}")
    for obj in scene.objects:
        m = obj.material
        what = None
        if m.hatch is not None:
            what = "a hatched material (tonal art maps have no Blender counterpart)"
        elif m.specular > 0:
            what = "Blinn-Phong specular (specular > 0): Blender's BSDFs have no Blinn-Phong lobe"
        if what:
            raise ValueError(
                f"blurlab.blender: object {obj.name!r} has {what}; Blender cannot render it as "
                "blurlab does. Allowed: Lambert materials (specular = 0, textured or not, rigid or "
                "skinned) without hatching, under the directional light and ambient term"
            )


def cycles_shutter(shutter) -> tuple[float, float]:
    """The part of `shutter` that Cycles' motion blur actually spans (docs/spec.md §16.4).

    Cycles maps a uniform number u to a time through the inverted CDF of its shutter curve,
    tabulated at CYCLES_SHUTTER_TABLE = n points. For the flat curve every blurlab scene is given,
    entry i holds (i + 1/2)(n - 1)/n^2 and the lookup interpolates linearly, so the time is
    ((n - 1)/n)^2 u + (n - 1)/(2 n^2), still uniform but over
    [0.00195, 0.99415] of the shutter: 0.78 % shorter, its middle 0.2 % early.
    ``ctx.reference(scene, size, cycles_shutter(scene.shutter), antialias=True)`` is therefore
    what Cycles converges to; ``scene.shutter`` is what blurlab's methods blur over."""
    t0, t1 = check_shutter(shutter)
    n = CYCLES_SHUTTER_TABLE
    start = 0.5 * (n - 1) / n**2
    end = start + ((n - 1) / n) ** 2
    return t0 + start * (t1 - t0), t0 + end * (t1 - t0)


def skinned_positions(obj, t: float) -> np.ndarray:
    """Object-space positions of a skinned mesh at time t: linear blend skinning with the
    G-buffer's weights and bone matrices (shaders/passes/gbuffer.vert)."""
    mesh = obj.mesh
    bones = obj.skeleton.matrices(t)[mesh.bone_indices]  # (V, 4, 4, 4)
    blend = np.einsum("vk,vkij->vij", mesh.bone_weights.astype(np.float64), bones)
    p = np.concatenate([mesh.positions, np.ones((len(mesh.positions), 1))], axis=1)
    return np.einsum("vij,vj->vi", blend, p)[:, :3].astype(np.float32)


def check_keyable(matrices: np.ndarray, name: str) -> None:
    """Blender keys location, rotation and scale: a sheared transform (scale along axes that
    are not the rotated ones) has no such keys."""
    linear = matrices[:, :3, :3]
    gram = np.einsum("kji,kjl->kil", linear, linear)  # A^T A: diagonal without shear
    off = gram - np.einsum("kii->ki", gram)[:, :, None] * np.eye(3)
    if np.abs(off).max() > 1e-6 * max(1.0, np.abs(gram).max()):
        raise ValueError(
            f"blurlab.blender: object {name!r} has a sheared transform (non-uniform scale under "
            "a rotation), which Blender's location/rotation/scale keys cannot hold"
        )


def export(scene: Scene, size, shutter, keys: int) -> tuple[dict, dict]:
    """The scene as (description, arrays) for child.py: geometry in object space, object and
    camera transforms in Blender's axes at `keys` + 1 evenly spaced times over the shutter."""
    check_reproducible(scene)
    t0, t1 = shutter
    times = t0 + (t1 - t0) * np.arange(keys + 1) / keys
    camera = scene.camera
    light = scene.light
    objects, arrays = [], {}
    for i, obj in enumerate(scene.objects):
        arrays[f"positions{i}"] = obj.mesh.positions
        if obj.skeleton is not None:  # baked: the skinned positions at every key time
            arrays[f"skinned{i}"] = np.stack([skinned_positions(obj, t) for t in times])
        arrays[f"normals{i}"] = obj.mesh.normals
        arrays[f"indices{i}"] = obj.mesh.indices.astype(np.int32)
        arrays[f"world{i}"] = np.stack([Y_UP_TO_Z_UP @ obj.model(t) for t in times])
        check_keyable(arrays[f"world{i}"], obj.name)
        albedo = np.asarray(obj.material.color[:3], dtype=np.float64)
        texture = obj.material.texture_rgba()  # linear, row 0 at v = 0 as blurlab uploads it
        if texture is not None:
            arrays[f"texture{i}"] = texture.astype(np.float32)
            arrays[f"uvs{i}"] = obj.mesh.uvs
        m = obj.material
        objects.append(
            {
                "name": f"{i:03d}_{obj.name}",
                "emission": (albedo * light.ambient).tolist(),
                "diffuse": albedo.tolist(),
                "textured": texture is not None,
                "skinned": obj.skeleton is not None,
                # docs/spec.md §20.1: alpha (× the texture's, in Blender's nodes), blend mode
                # and cutoff; the emitted radiance, added untextured as blurlab adds it.
                "radiance": m.radiance.tolist(),
                "alpha": float(m.alpha * m.color[3]),
                "blend": m.blend,
                "alpha_cutoff": float(m.alpha_cutoff),
            }
        )
    arrays["camera"] = np.stack([Y_UP_TO_Z_UP @ camera.world(t) for t in times])
    direction = light.direction / np.linalg.norm(light.direction)
    strength = float(np.max(light.color))
    description = {
        "size": [int(size[0]), int(size[1])],
        "shutter": [float(t0), float(t1)],
        "keys": int(keys),
        "objects": objects,
        "camera": {"fov_y": float(camera.fov_y), "near": camera.near, "far": camera.far},
        # Lambert: albedo · light · cos. Blender's diffuse BSDF is albedo/π, a sun's strength
        # is irradiance: strength π · max(light) with the colour normalised gives the same.
        "sun": None
        if strength <= 0
        else {
            "direction": (Y_UP_TO_Z_UP[:3, :3] @ direction).tolist(),
            "color": (light.color / strength).tolist(),
            "strength": math.pi * strength,
        },
        "background": [float(v) for v in scene.background[:3]],
        # Every translucent or masked surface a camera ray passes is one transparent bounce.
        "transparent_bounces": 0
        if all(obj.material.blend == "opaque" for obj in scene.objects)
        else 2 * scene.max_layers + 2,
    }
    return description, arrays


def render(
    scene: Scene,
    size=DEFAULT_SIZE,
    shutter=None,
    engine: str = "CYCLES",
    samples: int | None = None,
    steps: int | None = None,
    seed: int = 0,
    instant: float | None = None,
    keys: int = 64,
    timeout: float = 1800.0,
    python: str | os.PathLike | None = None,
    passes: str | os.PathLike | None = None,
) -> BlenderRender:
    """Renders `scene` with Blender's `engine` ("CYCLES" or "EEVEE") in a child process.

    One Blender frame is the shutter: motion blur from the frame's start over the whole frame,
    transforms keyed at `keys` + 1 times (linear, extrapolated linearly). `samples`: Cycles'
    samples per pixel (default 128) or EEVEE's render samples (default 64, Blender's).
    `steps`: Cycles' per-object motion steps (2^(steps - 1) transform samples, default 7,
    the most) or EEVEE's motion-blur steps (default 1, Blender's). `instant` = a time in the
    shutter renders that instant without motion blur. `python`: the interpreter that has bpy
    (default: this one). Cycles runs on the CPU with a one-pixel box filter, no bounces, no
    adaptive sampling or denoising; both write a linear 32-bit EXR (view transform Standard).

    `passes` = a file path: Cycles renders the G-buffer of `instant` (default: the shutter's
    centre) with motion blur off, one sample and a 0.01 px pixel filter, so every pass is
    sampled at the pixel centres, and writes Blender's Combined, Depth and Vector passes there
    as one multi-layer EXR. ``bl.Frame.from_exr(passes, convention="blender")`` reads it back:
    the Vector pass spans one frame = the shutter (docs/spec.md §16.1).
    """
    engine_name = engine.upper() if isinstance(engine, str) else engine
    if engine_name not in ENGINES:
        raise ValueError(f"blurlab.blender: engine must be 'CYCLES' or 'EEVEE', not {engine!r}")
    if passes is not None:
        if engine_name != "CYCLES":
            raise ValueError("blurlab.blender: passes= are rendered by Cycles only")
        if not isinstance(passes, (str, os.PathLike)) or not Path(passes).parent.is_dir():
            raise ValueError(
                f"blurlab.blender: passes must be a file path in an existing folder, not {passes!r}"
            )
        samples = 1 if samples is None else samples
    samples = DEFAULT_SAMPLES[engine_name] if samples is None else samples
    steps = DEFAULT_STEPS[engine_name] if steps is None else steps
    top_steps = 7 if engine_name == "CYCLES" else 4096  # EEVEE's: a practical bound
    for name, value, low, high in (
        ("samples", samples, 1, 1 << 24),
        ("steps", steps, 1, top_steps),
        ("keys", keys, 1, 4096),
        ("seed", seed, 0, 2**31 - 1),
    ):
        if isinstance(value, bool) or not isinstance(value, int) or not low <= value <= high:
            raise ValueError(
                f"blurlab.blender: {name} must be an integer in {low}..{high}, not {value!r}"
            )
    if not (isinstance(timeout, Real) and timeout > 0):
        raise ValueError(f"blurlab.blender: timeout must be > 0 seconds, not {timeout!r}")
    width, height = check_size(size, MAX_SIZE)
    if not isinstance(scene, Scene):
        raise TypeError(f"blurlab.blender needs a blurlab Scene, not {type(scene).__name__}")
    shutter = check_shutter(scene.shutter if shutter is None else shutter)
    if shutter[1] <= shutter[0]:
        raise ValueError("blurlab.blender: the shutter must be longer than 0 (one frame is it)")
    if passes is not None and instant is None:
        instant = 0.5 * (shutter[0] + shutter[1])
    if instant is not None and not (
        isinstance(instant, Real) and shutter[0] <= instant <= shutter[1]
    ):
        raise ValueError(f"blurlab.blender: instant {instant!r} is outside the shutter {shutter}")
    scene = scaled_scene(scene, shutter)  # the blur scales, keyed as blurlab evaluates them
    # What Blender cannot reproduce is refused first: that needs no bpy.
    description, arrays = export(scene, (width, height), shutter, keys)
    if python is None:
        if not available():
            raise ImportError(INSTALL)
        python = environment.interpreter()
    description.update(
        engine=ENGINES[engine_name],
        samples=samples,
        steps=steps,
        seed=seed,
        instant=None if instant is None else float(instant),
        passes=passes is not None,
    )

    def read(image: Path) -> np.ndarray:
        if passes is None:
            return io.read(image).astype(np.float32)
        # The caller's file is whole or absent: copied only once Blender has finished.
        partial = Path(passes).with_name(Path(passes).name + ".partial")
        shutil.copyfile(image, partial)
        os.replace(partial, passes)
        return capture.read_exr(passes, convention="blender")["color"]

    color, result, wall, log = run_job(Path(python), description, arrays, timeout, read)
    if color.shape != (height, width, 4):
        raise BlenderError(f"blurlab.blender: Blender wrote a {color.shape} image.\n{tail(log)}")
    settings = result["settings"]
    if engine_name == "CYCLES" and instant is None:
        settings["shutter_spanned"] = cycles_shutter(shutter)  # what the image integrates
    return BlenderRender(color, settings, wall, result["render_s"], result["device"], log)


def run_job(python: Path, description: dict, arrays: dict, timeout: float, read):
    """Writes the job into a temporary folder, runs child.py on it and returns (read(the
    rendered EXR's path), child.py's result, wall seconds, its log)."""
    with tempfile.TemporaryDirectory(prefix="blurlab blender ") as folder:
        folder = Path(folder)
        (folder / "job.json").write_text(json.dumps(description))
        np.savez(folder / "arrays.npz", **arrays)
        started = time.perf_counter()
        log = run_child(python, folder, timeout)
        wall = time.perf_counter() - started
        result_file, image = folder / "result.json", folder / "render.exr"
        if not (result_file.is_file() and image.is_file()):
            raise BlenderError(f"blurlab.blender: Blender wrote no image.\n{tail(log)}")
        return read(image), json.loads(result_file.read_text()), wall, log


def render_gltf(
    path: str | os.PathLike,
    size=DEFAULT_SIZE,
    samples: int = 128,
    seed: int = 0,
    background=(0.0, 0.0, 0.0),
    timeout: float = 1800.0,
    python: str | os.PathLike | None = None,
) -> BlenderRender:
    """A glTF file as Blender imports it (its own glTF importer: materials, alpha modes,
    cameras), rendered still by Cycles through the file's first camera with the same settings
    as `render` (box filter, no bounces beyond the transparent ones). `background`: linear RGB
    seen by camera rays only. The cross-check of docs/spec.md §15 and §20.1."""
    width, height = check_size(size, MAX_SIZE)
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"blurlab.blender: no glTF file {str(path)!r}")
    if isinstance(samples, bool) or not isinstance(samples, int) or not 1 <= samples <= 1 << 20:
        raise ValueError(f"blurlab.blender: samples must be an integer in 1..2^20, not {samples!r}")
    if python is None:
        if not available():
            raise ImportError(INSTALL)
        python = environment.interpreter()
    description = {
        "gltf": str(path.resolve()),
        "size": [width, height],
        "shutter": [0.0, 1.0],
        "keys": 1,
        "objects": [],
        "sun": None,
        "background": [float(v) for v in background][:3],
        "transparent_bounces": 64,
        "engine": "CYCLES",
        "samples": samples,
        "steps": 1,
        "seed": seed,
        "instant": 0.0,
        "passes": False,
    }
    read = lambda image: io.read(image).astype(np.float32)  # noqa: E731
    color, result, wall, log = run_job(Path(python), description, {}, timeout, read)
    if color.shape != (height, width, 4):
        raise BlenderError(f"blurlab.blender: Blender wrote a {color.shape} image.\n{tail(log)}")
    return BlenderRender(color, result["settings"], wall, result["render_s"], result["device"], log)


def run_child(python: Path, folder: Path, timeout: float) -> str:
    """Runs child.py on the job in `folder` in its own process group; returns its log.
    Raises BlenderError when it fails, dies or outlives `timeout` (then the group is killed)."""
    log_path = folder / "blender.log"
    with open(log_path, "wb") as log_file:
        process = subprocess.Popen(
            [str(python), str(CHILD), str(folder)],
            stdin=subprocess.DEVNULL,
            stdout=log_file,
            stderr=subprocess.STDOUT,
            start_new_session=True,  # its own group, so a kill takes its helpers too
            preexec_fn=die_with_parent,
        )
        try:
            code = process.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            os.killpg(process.pid, signal.SIGKILL)
            process.wait()
            log = log_path.read_text(errors="replace")
            raise BlenderError(
                f"blurlab.blender: Blender did not finish within {timeout:g} s and was "
                f"killed.\n{tail(log)}"
            ) from None
        except BaseException:  # KeyboardInterrupt too: leave no Blender running
            os.killpg(process.pid, signal.SIGKILL)
            process.wait()
            raise
    log = log_path.read_text(errors="replace")
    if code < 0:
        try:
            name = signal.Signals(-code).name
        except ValueError:
            name = str(-code)
        raise BlenderError(f"blurlab.blender: Blender crashed (signal {name}).\n{tail(log)}")
    if code != 0:
        if "No module named 'bpy'" in log:
            raise ImportError(f"{INSTALL}; {python} has no bpy.\n{tail(log)}")
        raise BlenderError(f"blurlab.blender: Blender failed (exit code {code}).\n{tail(log)}")
    return log


def die_with_parent() -> None:
    """In the child, before Blender starts: Linux kills it if the caller dies first (even by
    SIGKILL), so no Blender outlives the process that wanted its image."""
    if sys.platform.startswith("linux"):
        import ctypes  # noqa: PLC0415 (only in the forked child)

        ctypes.CDLL(None, use_errno=True).prctl(1, signal.SIGKILL)  # PR_SET_PDEATHSIG


def tail(log: str) -> str:
    lines = log.rstrip().splitlines()[-LOG_TAIL_LINES:]
    return "Blender's log, last lines:\n" + "\n".join(lines) if lines else "Blender's log is empty."


__all__ = ["BlenderError", "BlenderRender", "available", "check_reproducible", "export", "render"]
