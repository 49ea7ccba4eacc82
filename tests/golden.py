"""The golden record: every method's output on fixed frames, recorded once per renderer.

The cases come from the public API alone (bl.methods(), each method's parameters and default
sweep grid), so a refactor of the methods' layout runs the same script:

- frames: a random frame built from arrays, teapot_pass and the failure scene `occluder`, each
  at GOLDEN_SIZE; rendered frames at the instant each configuration expects;
- configurations: the defaults, every point of the method's default sweep grid, the other
  choices of every choice and bool parameter, the 0..1 option switches turned on, another
  seed, and `steps` = 2 for post-process methods;
- every backend of the method; a sequence method (trail) at its first frame and with a history.

tests/test_golden.py checks it two ways (docs/reliability.md):

- bits: tests/golden/*.json hold the SHA-256 of every output, one file per renderer (its
  `renderer` and GL `version` strings); on a renderer that has a file, every hash must match;
- images, on every renderer: tests/golden/llvmpipe_images.npz holds llvmpipe's outputs, and
  every output must match them within IMAGE_TOLERANCE (image_problems says exactly what).

Record anew only when a change is meant to change output, and say so in the commit:

    python tests/golden.py --record --out tests/golden            (this renderer's hashes)
    python tests/golden.py --record --images --out tests/golden   (on llvmpipe: the images too)

`--record --out DIR` writes DIR/<renderer>.json, replacing the file there that has the same
renderer and version; it runs on the default device (bl.Context()), so on a GPU machine it
records the GPU's hashes.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import re
import zipfile
from pathlib import Path

import numpy as np
from conftest import random_frame

import blurlab as bl

GOLDEN_SIZE = (96, 64)
GOLDEN_DIR = Path(__file__).parent / "golden"
IMAGES_FILE = GOLDEN_DIR / "llvmpipe_images.npz"
SCENES = ("teapot_pass", "occluder")
COLOR_OUTPUTS = ("color", "color_with_history")

# What another renderer may change (measured: NVIDIA H200 against llvmpipe, the worst output of
# 474 rendered-scene colors: largest difference 0.263, mean 0.00115, 0.58% of values beyond
# 0.05; the random frame's channel means within 0.0059). Rasterization and float rounding move
# edges by a pixel, so a few values differ much and the rest hardly at all. The images are
# stored as float16, which rounds a value by at most 2**-11 of its magnitude (2**-25 below
# 2**-14); the bound for an image's largest value is added to `largest` and `mean`.
IMAGE_TOLERANCE = {
    "largest": 0.5,  # every value of a rendered scene's color
    "mean": 0.004,  # mean absolute difference of a rendered scene's color
    "beyond": 0.05,  # a value differs "much" beyond this ...
    "share_beyond": 0.01,  # ... and at most this share of the values may
    "channel_mean": 0.015,  # the random frame's colors: each channel's mean
}


def golden_frame() -> bl.Frame:
    """The random frame built from arrays: the tests' builder with a fixed seed."""
    return random_frame(np.random.default_rng(20261123), *GOLDEN_SIZE, reach=30.0)


def _grid_points(grid) -> list[dict]:
    if isinstance(grid, dict):
        grid = [grid]
    points: list[dict] = []
    for part in grid:
        keys = sorted(part)
        combos = [{}]
        for key in keys:
            combos = [{**c, key: v} for c in combos for v in part[key]]
        points += [p for p in combos if p not in points]
    return points


def configurations(name: str) -> list[dict]:
    """The parameter sets of method `name` that the golden file covers."""
    m = bl.method(name)
    points: list[dict] = [{}]
    points += _grid_points(_default_grid(name))
    for key, param in m.params.items():
        kind = _kind(param)
        if isinstance(kind, tuple):
            points += [{key: choice} for choice in kind if choice != param.default]
        elif kind is bool:
            points.append({key: not param.default})
        elif kind is int and param.low == 0 and param.high == 1:
            points.append({key: 1 - param.default})
        elif key == "seed":
            points.append({key: 7})
    if m.kind in ("filter", "gather"):  # post-process methods of one frame take steps
        points.append({"steps": 2})
    unique: list[dict] = []
    for p in points:
        if p not in unique:
            unique.append(p)
    return unique


def _kind(param):
    return getattr(param, "kind", None) if hasattr(param, "kind") else param.type


def _default_grid(name: str):
    return bl.method(name).default_grid


def outputs(ctx: bl.Context) -> dict[str, np.ndarray | str]:
    """{case: output array, or 'error: <type>' where the call refuses} for every case on `ctx`."""
    made: dict[str, np.ndarray | str] = {}
    frames = {"random": golden_frame()}
    scenes = {name: bl.scenes.get(name) for name in SCENES}
    for name in bl.methods():
        m = bl.method(name)
        for backend in m.backends:
            for point in configurations(name):
                params = {k: v for k, v in point.items() if k != "steps"}
                steps = point.get("steps", 1)
                case_params = json.dumps(point, sort_keys=True)
                for frame_name in ("random", *SCENES):
                    case = f"{name}|{backend}|{case_params}|{frame_name}"
                    try:
                        if frame_name == "random":
                            if steps > 1:
                                continue
                            arrays = _run(ctx, frames["random"], name, backend, params)
                        else:
                            _, result = bl.render_and_blur(
                                ctx,
                                scenes[frame_name],
                                name,
                                size=GOLDEN_SIZE,
                                backend=backend,
                                steps=steps,
                                **params,
                            )
                            arrays = _outputs(ctx, name, result, params, scenes[frame_name])
                    except (ValueError, TypeError) as error:  # e.g. a rendering method on arrays
                        made[case] = f"error: {type(error).__name__}"
                        continue
                    for output, array in arrays.items():
                        made[f"{case}|{output}"] = np.array(array)
    return made


def digest(value: np.ndarray | str) -> str:
    """The SHA-256 of an output's bits; a refusal's 'error: <type>' stands for itself."""
    if isinstance(value, str):
        return value
    return hashlib.sha256(np.ascontiguousarray(value).tobytes()).hexdigest()


def compute(ctx: bl.Context) -> dict[str, str]:
    """{case: sha256 or 'error: <type>'} for every case on `ctx`."""
    return {case: digest(value) for case, value in outputs(ctx).items()}


def _run(ctx, frame, name, backend, params) -> dict[str, np.ndarray]:
    result = bl.blur(ctx, frame, name, backend=backend, **params)
    return _outputs(ctx, name, result, params, None)


def _outputs(ctx, name, result, params, scene) -> dict[str, np.ndarray]:
    outputs = {"color": result.color}
    for key, array in sorted(result.buffers.items()):
        outputs[key] = array
    if bl.method(name).kind == "sequence":  # the second frame blends with the first's output
        frame = ctx.render(scene, GOLDEN_SIZE, instant="close") if scene else golden_frame()
        second = bl.blur(ctx, frame, name, history=result, **params)
        outputs["color_with_history"] = second.color
    return outputs


def layout(value: np.ndarray | str) -> str:
    """What every renderer must agree on for an output: dtype, shape and how many values are
    not finite; or the refusal."""
    if isinstance(value, str):
        return value
    finite = np.isfinite(value) if value.dtype.kind == "f" else np.ones(value.shape, bool)
    return f"{value.dtype.str} {'x'.join(map(str, value.shape))} nonfinite={int((~finite).sum())}"


def _frame_and_output(case: str) -> tuple[str, str]:
    parts = case.split("|")
    return parts[3], parts[4] if len(parts) > 4 else ""


def device_id(ctx: bl.Context) -> dict[str, str]:
    info = ctx.info()
    return {"renderer": info["renderer"], "version": info["version"]}


def hash_files() -> list[Path]:
    return sorted(GOLDEN_DIR.glob("*.json"))


def recorded_for(device: dict[str, str], folder: Path = GOLDEN_DIR) -> Path | None:
    """The hash file recorded on `device` (same renderer and GL version), if there is one."""
    for path in sorted(folder.glob("*.json")):
        record = json.loads(path.read_text())
        if all(record.get(key) == value for key, value in device.items()):
            return path
    return None


def hash_problems(recorded: dict[str, str], made: dict[str, np.ndarray | str]) -> list[str]:
    """Every recorded case is still made and has the recorded hash."""
    problems = [f"{case}: no longer made" for case in sorted(set(recorded) - set(made))]
    for case, expected in sorted(recorded.items()):
        if case in made and digest(made[case]) != expected:
            problems.append(f"{case}: bits changed")
    return problems


def _compared_as(case: str, value: np.ndarray | str) -> str:
    """'image' for a rendered scene's color, 'means' for the random frame's (whose random
    motion makes every pixel hinge on rounding), '' for the rest: refusals and the methods'
    intermediate buffers, some of them packed keys, which are compared by layout only."""
    frame, output = _frame_and_output(case)
    if isinstance(value, str) or output not in COLOR_OUTPUTS:
        return ""
    return "means" if frame == "random" else "image"


def record_images(made: dict[str, np.ndarray | str], device: dict[str, str], path: Path) -> None:
    """Writes what image_problems compares with: every output's layout, the rendered scenes'
    colors (float16, one copy of each distinct image) and the random frame's channel means."""
    cases = sorted(made)
    images: dict[str, np.ndarray] = {}
    image_of = np.full(len(cases), -1, np.int32)
    channel_means = np.full((len(cases), 4), np.nan)
    for i, case in enumerate(cases):
        value = made[case]
        compared = _compared_as(case, value)
        if compared == "image":
            key = digest(value)
            images.setdefault(key, value)
            image_of[i] = list(images).index(key)
        elif compared == "means":
            channel_means[i] = value.reshape(-1, value.shape[-1]).mean(0, dtype=np.float64)
    arrays = {
        "renderer": np.array(device["renderer"]),
        "version": np.array(device["version"]),
        "cases": np.array(cases),
        "layouts": np.array([layout(made[case]) for case in cases]),
        "image_of": image_of,
        "images": np.stack([image.astype(np.float16) for image in images.values()]),
        "channel_means": channel_means,
    }
    # An .npz that np.load reads, compressed with LZMA: a fifth of np.savez_compressed's size.
    with zipfile.ZipFile(path, "w", compression=zipfile.ZIP_LZMA) as archive:
        for name, array in arrays.items():
            with archive.open(f"{name}.npy", "w") as member:
                np.lib.format.write_array(member, array, allow_pickle=False)


def load_images(path: Path = IMAGES_FILE) -> dict:
    with np.load(path) as stored:
        return {key: stored[key] for key in stored.files}


def color_problems(made: np.ndarray, stored: np.ndarray) -> list[str]:
    """How a rendered scene's color `made` breaks IMAGE_TOLERANCE against its float16 copy."""
    difference = np.abs(made.astype(np.float64) - stored.astype(np.float64))
    rounding = float(np.abs(stored).max()) * 2.0**-11 + 2.0**-25  # float16's, at most
    problems = []
    largest = IMAGE_TOLERANCE["largest"] + rounding
    if difference.max() > largest:
        where = tuple(int(i) for i in np.unravel_index(difference.argmax(), difference.shape))
        problems.append(f"differs by {difference.max():.4g} > {largest:.4g} at (y, x, c) {where}")
    mean = IMAGE_TOLERANCE["mean"] + rounding
    if difference.mean() > mean:
        problems.append(f"mean difference {difference.mean():.4g} > {mean:.4g}")
    share = (difference > IMAGE_TOLERANCE["beyond"]).mean()
    if share > IMAGE_TOLERANCE["share_beyond"]:
        problems.append(
            f"{share:.2%} of values differ by more than {IMAGE_TOLERANCE['beyond']}, more than "
            f"{IMAGE_TOLERANCE['share_beyond']:.0%}"
        )
    return problems


def image_problems(stored: dict, made: dict[str, np.ndarray | str]) -> list[str]:
    """Every stored case is still made, with the same layout (refusal, dtype, shape, count of
    non-finite values), and its color within IMAGE_TOLERANCE of the stored one."""
    problems = []
    for i, case in enumerate(stored["cases"]):
        case = str(case)
        if case not in made:
            problems.append(f"{case}: no longer made")
            continue
        value = made[case]
        if layout(value) != stored["layouts"][i]:
            problems.append(f"{case}: {layout(value)}, recorded {stored['layouts'][i]}")
            continue
        if stored["image_of"][i] >= 0:
            found = color_problems(value, stored["images"][stored["image_of"][i]])
            problems += [f"{case}: {problem}" for problem in found]
        elif np.isfinite(stored["channel_means"][i]).all():
            means = value.reshape(-1, value.shape[-1]).mean(0, dtype=np.float64)
            off = np.abs(means - stored["channel_means"][i]).max()
            if off > IMAGE_TOLERANCE["channel_mean"]:
                problems.append(
                    f"{case}: a channel's mean differs by {off:.4g} > "
                    f"{IMAGE_TOLERANCE['channel_mean']}"
                )
    return problems


def _file_name(device: dict[str, str]) -> str:
    words = re.findall(r"[a-z0-9]+", f"{device['renderer']} {device['version']}".lower())
    return "-".join(words) + ".json"


def record_hashes(made: dict[str, np.ndarray | str], device: dict[str, str], folder: Path) -> Path:
    """Writes folder/<renderer and version>.json, or over the file there recorded on `device`."""
    folder.mkdir(parents=True, exist_ok=True)
    path = recorded_for(device, folder) or folder / _file_name(device)
    hashes = {case: digest(value) for case, value in made.items()}
    payload = {**device, "size": GOLDEN_SIZE, "hashes": hashes}
    path.write_text(json.dumps(payload, indent=1, sort_keys=True) + "\n")
    return path


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--record", action="store_true", help="write this renderer's hashes")
    parser.add_argument("--images", action="store_true", help="and the images (llvmpipe only)")
    parser.add_argument("--out", type=Path, default=GOLDEN_DIR, help="folder to write into")
    args = parser.parse_args()
    ctx = bl.Context()
    device = device_id(ctx)
    made = outputs(ctx)
    print(f"{len(made)} cases on {device['renderer']} ({device['version']})")
    if args.record:
        print(f"recorded {len(made)} hashes in {record_hashes(made, device, args.out)}")
    if args.images:
        if not device["renderer"].startswith("llvmpipe"):
            parser.error("the stored images are llvmpipe's; record them on llvmpipe")
        path = args.out / IMAGES_FILE.name
        record_images(made, device, path)
        print(f"recorded the images in {path} ({path.stat().st_size} bytes)")


if __name__ == "__main__":
    main()
