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
