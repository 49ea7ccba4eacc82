"""Shared fixtures: one GL context for the whole session, as moderngl's own tests do."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest

import blurlab as bl

TEST_SHADERS = Path(__file__).parent / "tests" / "shaders"

try:
    from hypothesis import settings

    # CI: the same examples on every run (derandomized), no example database in the tree.
    # HYPOTHESIS_PROFILE=explore draws new examples each run.
    settings.register_profile("blurlab", derandomize=True, database=None, print_blob=True)
    settings.register_profile("explore", database=None, print_blob=True)
    settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "blurlab"))
except ImportError:  # hypothesis is in the test extra; only the fuzz tests need it
    pass

# What a user runs, end to end: every command and code block of the docs and the README, the
# notebooks, Blender's cross-checks, and a new method made and studied from an empty folder.
# Each takes seconds to minutes on llvmpipe, so `make test` leaves them to `make test-e2e`
# (pytest -m e2e); .ci/run runs both.
E2E_FILES = {
    "test_documented_commands.py",
    "test_notebooks.py",
    "test_blender.py",
    "test_blender_roundtrip.py",
    "test_translucency_blender.py",
    "test_study_peers.py",
}


def pytest_collection_modifyitems(items):
    for item in items:
        if item.path.name in E2E_FILES:
            item.add_marker(pytest.mark.e2e)


# Examples run by the property tests (tests/test_fuzz.py calls count_example() in each);
# the total is printed at the end of the run, and docs/reliability.md records it.
EXAMPLES = {"count": 0}


def count_example() -> None:
    EXAMPLES["count"] += 1


def pytest_sessionfinish(session):
    """Under pytest-xdist each worker counts its own examples and hands the count back."""
    if hasattr(session.config, "workeroutput"):
        session.config.workeroutput["hypothesis_examples"] = EXAMPLES["count"]


@pytest.hookimpl(optionalhook=True)
def pytest_testnodedown(node, error):
    EXAMPLES["count"] += getattr(node, "workeroutput", {}).get("hypothesis_examples", 0)


def pytest_terminal_summary(terminalreporter):
    if EXAMPLES["count"]:
        terminalreporter.write_line(f"hypothesis: {EXAMPLES['count']} examples run")


# The device CLI tests name: llvmpipe where there is one (CI, for stable output), else the GPU
# (the lent NVIDIA machine has no software EGL device).
CLI_DEVICE = "software" if any(d["kind"] == "software" for d in bl.Context.devices()) else "auto"


@pytest.fixture(scope="session")
def ctx() -> bl.Context:
    """The default context: the GPU where EGL finds one, llvmpipe otherwise (CI)."""
    return bl.Context()


@pytest.fixture(autouse=True)
def no_gl_error_left(request):
    """After every test that used the session context: no GL error is left set (every blurlab
    call checks and clears the ones it causes; docs/reliability.md)."""
    yield
    if "ctx" in request.fixturenames:
        context = request.getfixturevalue("ctx")
        assert context.gl_errors() == [], "a GL error was left set"


@pytest.fixture
def rng() -> np.random.Generator:
    return np.random.default_rng(20261122)


@pytest.fixture
def test_shader():
    """Absolute path of a shader in tests/shaders."""
    return lambda name: TEST_SHADERS / name


def random_frame(
    rng, width: int, height: int, k: int = 20, background: float = 0.2, reach: float | None = None
):
    """A Frame of random color, depth (a fraction `background` at +inf) and motion.

    Motion lengths lie in (1.1, 1.9·k) pixels, so every half-vector lies strictly inside the
    clamp range [0.5, k] of docs/spec.md §3.1: lengths are then distinct almost surely, and TileMax
    and NeighborMax have no ties. With `reach`, each motion component is uniform in [-reach,
    reach] px instead (tests/golden.py's frame).
    """
    color = rng.random((height, width, 4), dtype=np.float32)
    depth = rng.uniform(1.0, 10.0, (height, width)).astype(np.float32)
    depth[rng.random((height, width)) < background] = np.inf
    if reach is not None:
        motion = rng.uniform(-reach, reach, (height, width, 2)).astype(np.float32)
        return bl.Frame(color=color, depth=depth, motion=motion)
    angle = rng.uniform(0, 2 * np.pi, (height, width))
    length = rng.uniform(1.1, 1.9 * k, (height, width))
    motion = (np.stack([np.cos(angle), np.sin(angle)], -1) * length[..., None]).astype(np.float32)
    return bl.Frame(color=color, depth=depth, motion=motion)


def assert_inside_input_range(out: np.ndarray, color: np.ndarray, tolerance: float = 1e-6):
    """Every channel of `out` lies within [min, max] of the same channel of `color`: a blur
    takes convex combinations of its input colors."""
    for c in range(color.shape[-1]):
        lo, hi = color[..., c].min(), color[..., c].max()
        assert lo - tolerance <= out[..., c].min() and out[..., c].max() <= hi + tolerance, c


def assert_timings_name(ctx, rng, method: str, passes: list[str], **params):
    """bl.blur(method) reports a time for each of `passes`, in order, and a positive total;
    returns the result."""
    result = bl.blur(ctx, random_frame(rng, 64, 36), method, **params)
    assert list(result.timings) == passes
    assert result.total_ms > 0
    return result


def assert_matches_twin(result, frame, diagnose=None, expected=None) -> None:
    """The one comparison of the GPU against a NumPy twin: a blur's `result` against its
    method's twin on `frame` with the parameters the blur resolved (or against `expected`, where
    the twin is another function): >= 99.9 % of pixels within 1e-3 on every channel and a mean
    absolute error <= 1e-4. On a miss, diagnose(expected), where given, adds its text to the
    failure's message."""
    if expected is None:
        expected = bl.method(result.method).twin_output(frame, **result.params)
    error = np.abs(result.color - expected)
    within = (error.max(axis=-1) <= 1e-3).mean()
    if within < 0.999 or error.mean() > 1e-4:
        note = diagnose(expected) if diagnose else ""
        assert within >= 0.999, f"{within:.5f} of pixels within 1e-3{note}"
        assert error.mean() <= 1e-4, f"mean absolute error {error.mean():.2e}{note}"
