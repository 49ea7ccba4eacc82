"""Shared fixtures: one GL context for the whole session, as moderngl's own tests do."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import blurlab as bl

TEST_SHADERS = Path(__file__).parent / "shaders"


@pytest.fixture(scope="session")
def ctx() -> bl.Context:
    """The default context: the GPU where EGL finds one, llvmpipe otherwise (CI)."""
    return bl.Context()


@pytest.fixture
def rng() -> np.random.Generator:
    return np.random.default_rng(20261122)


@pytest.fixture
def test_shader():
    """Absolute path of a shader in tests/shaders."""
    return lambda name: TEST_SHADERS / name


def random_frame(rng, width: int, height: int, k: int = 20, background: float = 0.2):
    """A Frame of random color, depth (a fraction `background` at +inf) and motion.

    Motion lengths lie in (1.1, 1.9·k) pixels, so every half-vector lies strictly inside the
    clamp range [0.5, k] of SPEC.md §3.1: lengths are then distinct almost surely, and TileMax
    and NeighborMax have no ties.
    """
    import blurlab as bl

    color = rng.random((height, width, 4), dtype=np.float32)
    depth = rng.uniform(1.0, 10.0, (height, width)).astype(np.float32)
    depth[rng.random((height, width)) < background] = np.inf
    angle = rng.uniform(0, 2 * np.pi, (height, width))
    length = rng.uniform(1.1, 1.9 * k, (height, width))
    motion = (np.stack([np.cos(angle), np.sin(angle)], -1) * length[..., None]).astype(np.float32)
    return bl.Frame(color=color, depth=depth, motion=motion)
