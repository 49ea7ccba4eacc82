"""Determinism (docs/spec.md §13): every method, the converged reference and every NumPy twin
give the same bits for the same inputs and seed, twice in one process and in two fresh
processes. Methods are read from the registry, so new ones are covered."""

from __future__ import annotations

import hashlib
import json
import subprocess
import sys
import warnings

import numpy as np
import pytest
from method_picks import pick

import blurlab as bl

SIZE = (24, 16)
SEED = 7
# A tile filter whose seed reaches its jitter.
SEEDED = pick(kind="filter", params=("k", "seed"))


def digest(array: np.ndarray) -> str:
    return hashlib.sha256(np.ascontiguousarray(array).tobytes()).hexdigest()


def fingerprints(ctx) -> dict[str, str]:
    """sha256 of every method's output, the GPU reference and the NumPy references."""
    scene = bl.scenes.fan()
    out = {}
    for name in bl.methods():
        params = {"seed": SEED} if "seed" in bl.method(name).params else {}
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            frame = ctx.render(scene, SIZE, instant=bl.method_instant(name, params))
            out[name] = digest(bl.blur(ctx, frame, name, **params).color)
    reference = ctx.reference(scene, SIZE, samples=8, stratified=True, seed=SEED, progress=False)
    out["ctx.reference"] = digest(reference.color)
    rng = np.random.default_rng(SEED)
    color = rng.random((SIZE[1], SIZE[0], 4))
    depth = rng.uniform(1, 5, SIZE[::-1])
    motion = rng.normal(0, 6, (SIZE[1], SIZE[0], 2))
    arrays = bl.Frame(color, depth, motion)
    for name in bl.methods():  # every NumPy twin, at its defaults and the seed
        m = bl.method(name)
        if m.twin is not None:
            params = {"seed": SEED} if "seed" in m.params else {}
            out[f"twin.{name}"] = digest(m.twin_output(arrays, **params))
    return out


SCRIPT = """
import json, sys
sys.path.insert(0, {tests!r})
import blurlab as bl
from test_determinism import fingerprints
print(json.dumps(fingerprints(bl.Context())))
"""


@pytest.fixture(scope="module")
def here(ctx):
    return fingerprints(ctx)


def test_two_runs_in_one_process_agree(ctx, here):
    again = fingerprints(ctx)
    assert set(here) >= set(bl.methods()) | {"ctx.reference"}
    assert again == here


def test_two_fresh_processes_agree_with_this_one(here):
    from pathlib import Path

    script = SCRIPT.format(tests=str(Path(__file__).parent))
    runs = [
        json.loads(
            subprocess.run(
                [sys.executable, "-c", script], capture_output=True, text=True, check=True
            )
            .stdout.strip()
            .splitlines()[-1]
        )
        for _ in range(2)
    ]
    assert set(runs[0]) == set(here) and runs[0] == runs[1], "two fresh processes disagree"
    differ = sorted(k for k in here if runs[0].get(k) != here[k])
    assert not differ, f"fresh processes differ from this one in {differ}"


def test_another_seed_gives_other_bits(ctx):
    frame = bl.Frame(
        color=np.random.default_rng(1).random((16, 24, 4)),
        depth=np.ones((16, 24)),
        motion=np.full((16, 24, 2), 9.0),
    )
    a = bl.blur(ctx, frame, SEEDED, k=8, seed=1).color
    b = bl.blur(ctx, frame, SEEDED, k=8, seed=2).color
    assert digest(a) != digest(b)  # the seed reaches the jitter: the test above can fail
