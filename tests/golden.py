"""Golden output hashes: the SHA-256 of every method's output bits on fixed frames.

Recorded on llvmpipe before the methods moved into the blurlab.methods package (issue 15) and
checked by tests/test_golden.py after every change since: a refactor that claims to keep
behaviour keeps every hash. The cases come from the public API alone (bl.methods(), each
method's parameters and default sweep grid), so the same script runs on the old and the new
layout:

- frames: a random frame built from arrays, teapot_pass and the failure scene `occluder`, each
  at GOLDEN_SIZE; rendered frames at the instant each configuration expects;
- configurations: the defaults, every point of the method's default sweep grid, the other
  choices of every choice and bool parameter, the 0..1 option switches turned on, another
  seed, and `steps` = 2 for post-process methods;
- every backend of the method; trail at its first frame and with a history.

Record anew with `python tests/golden.py --record` only when a change is meant to change
output, and say so in the commit.
"""

from __future__ import annotations

import hashlib
import json
import sys
from pathlib import Path

import numpy as np

import blurlab as bl

GOLDEN_SIZE = (96, 64)
GOLDEN_FILE = Path(__file__).parent / "golden" / "llvmpipe_hashes.json"
SCENES = ("teapot_pass", "occluder")


def random_frame() -> bl.Frame:
    rng = np.random.default_rng(20261123)
    width, height = GOLDEN_SIZE
    color = rng.random((height, width, 4), dtype=np.float32)
    depth = rng.uniform(1.0, 10.0, (height, width)).astype(np.float32)
    depth[rng.random((height, width)) < 0.2] = np.inf
    motion = rng.uniform(-30, 30, (height, width, 2)).astype(np.float32)
    return bl.Frame(color=color, depth=depth, motion=motion)


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
    if not m.renders and name != "trail":
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


def _digest(array: np.ndarray) -> str:
    return hashlib.sha256(np.ascontiguousarray(array).tobytes()).hexdigest()


def compute(ctx: bl.Context) -> dict[str, str]:
    """{case: sha256 or 'error: <type>'} for every case on `ctx`."""
    hashes: dict[str, str] = {}
    frames = {"random": random_frame()}
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
                            outputs = _run(ctx, frames["random"], name, backend, params)
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
                            outputs = _outputs(ctx, name, result, params, scenes[frame_name])
                    except (ValueError, TypeError) as error:  # e.g. a rendering method on arrays
                        hashes[case] = f"error: {type(error).__name__}"
                        continue
                    for output, array in outputs.items():
                        hashes[f"{case}|{output}"] = _digest(array)
    return hashes


def _run(ctx, frame, name, backend, params) -> dict[str, np.ndarray]:
    result = bl.blur(ctx, frame, name, backend=backend, **params)
    return _outputs(ctx, name, result, params, None)


def _outputs(ctx, name, result, params, scene) -> dict[str, np.ndarray]:
    outputs = {"color": result.color}
    for key, array in sorted(result.buffers.items()):
        outputs[key] = array
    if name == "trail":  # the second frame blends with the first one's output
        frame = ctx.render(scene, GOLDEN_SIZE, instant="close") if scene else random_frame()
        second = bl.blur(ctx, frame, name, history=result, **params)
        outputs["color_with_history"] = second.color
    return outputs


def main() -> None:
    ctx = bl.Context("software")
    hashes = compute(ctx)
    if "--record" in sys.argv:
        GOLDEN_FILE.parent.mkdir(parents=True, exist_ok=True)
        payload = {"renderer": ctx.info()["renderer"], "size": GOLDEN_SIZE, "hashes": hashes}
        GOLDEN_FILE.write_text(json.dumps(payload, indent=1, sort_keys=True) + "\n")
        print(f"recorded {len(hashes)} hashes in {GOLDEN_FILE}")
    else:
        print(f"{len(hashes)} cases")


if __name__ == "__main__":
    main()
