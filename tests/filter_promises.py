"""The promises every motion-blur filter keeps, as checks the test files share: the
GPU matches the NumPy twin (docs/spec.md §13), a still frame comes back unchanged, the output
stays inside the input range, zero, tiny and huge motion give no NaN, and the same seed gives
the same bits (another seed, other noise)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
import pytest
from conftest import assert_inside_input_range, assert_matches_twin, random_frame

import blurlab as bl


def two_sided_frame(rng, width, height, reach=20.0, k=10):
    """A random frame whose halves differ (not constant velocity): each half its own random
    direction and length up to `reach` px (the colour and depth of random_frame(k=k))."""
    frame = random_frame(rng, width, height, k=k)
    halves = []
    for _ in range(2):
        angle = rng.uniform(0, 2 * np.pi, (height, width))
        length = rng.uniform(0, reach, (height, width))
        halves.append(np.stack([np.cos(angle), np.sin(angle)], -1) * length[..., None])
    return bl.Frame(
        frame.color,
        frame.depth,
        halves[0] + halves[1],
        motion_prev=halves[0],
        motion_next=halves[1],
    )


def share_within(a, b) -> float:
    return float((np.abs(a - b).max(axis=-1) <= 1e-3).mean())


def assert_blurs_a_rendered_scene_as_its_twin(ctx, method: str, scene: str, **params) -> None:
    """`method` on `scene` rendered at 160 x 90 matches its twin (assert_matches_twin) and
    really blurs: some pixel moves by more than 0.05."""
    frame = ctx.render(bl.scenes.get(scene), (160, 90))
    result = bl.blur(ctx, frame, method, **params)

    def diagnose(expected) -> str:
        # A miss seen on an H100 under 16 test processes (docs/reliability.md, "Determinism"):
        # tells a bad read-back (the texture now holds the twin's image) from a bad output (it
        # does not, and a second call does) from a context the GPU stopped serving (its reset
        # status; GPU timers that read 0; a new context in this process gets it right).
        texture = result.textures["color"].download()
        again = bl.blur(ctx, frame, method, **params).color
        index = int(ctx.info()["device_index"])  # -1: the surfaceless platform
        fresh_ctx = bl.Context(index if index >= 0 else "auto")
        fresh_frame = fresh_ctx.render(bl.scenes.get(scene), (160, 90))
        fresh = bl.blur(fresh_ctx, fresh_frame, method, **params)
        fresh_expected = bl.method(method).twin_output(fresh_frame, **fresh.params)
        timings = {name: t.ms for name, t in {**frame.timings, **result.timings}.items()}
        return (
            f"; the output texture read again: {share_within(texture, expected):.5f} within, "
            f"the first read: {share_within(result.color, expected):.5f}, "
            f"a second call: {share_within(again, expected):.5f}; "
            f"a new context: {share_within(fresh.color, fresh_expected):.5f} within, its frame "
            f"{share_within(fresh_frame.color, frame.color):.5f} like this one's; "
            f"reset status {ctx.reset_status()!r} ({ctx.info()['reset_notification']}), "
            f"GL errors {ctx.gl_errors()}, times (ms) {timings}"
        )

    assert_matches_twin(result, frame, diagnose)
    assert np.abs(result.color - frame.color).max() > 0.05


def assert_still_frame_unchanged(ctx, rng, method: str) -> None:
    frame = random_frame(rng, 64, 48)
    frame.motion[:] = 0
    assert bl.blur(ctx, frame, method).color.tobytes() == frame.color.tobytes()


def assert_inside_the_input_range(ctx, frame, method: str, **params) -> None:
    frame.color[..., :3] = frame.color[..., :3] * 0.5 + 0.25  # inputs in [0.25, 0.75]
    assert_inside_input_range(bl.blur(ctx, frame, method, **params).color, frame.color)


def assert_finite_for_motion_scale(ctx, rng, method: str, scale: float, **params) -> None:
    frame = random_frame(rng, 80, 60)
    frame.motion[:] = np.float32(scale) * np.sign(frame.motion)
    assert np.isfinite(bl.blur(ctx, frame, method, **params).color).all()


def assert_seeded(ctx, frame, method: str) -> None:
    a = bl.blur(ctx, frame, method, seed=3).color
    b = bl.blur(ctx, frame, method, seed=3).color
    c = bl.blur(ctx, frame, method, seed=4).color
    assert a.tobytes() == b.tobytes()
    assert a.tobytes() != c.tobytes()


@dataclass(frozen=True)
class Tried:
    """How a filter is tried: the frame maker (`make(rng, width, height, k=...)`; a method that
    reads two-sided motion wants two_sided_frame); the parameters that let its blur reach far
    enough for the input-range check (`inside`) and for huge motion (`huge`); the random frames
    ((size, params) each, on every backend of `backends`) and rendered scenes ((scene, params)
    each) on which it must match its twin."""

    make: Callable = random_frame
    inside: dict = field(default_factory=dict)
    huge: dict = field(default_factory=dict)
    backends: tuple[str, ...] = ("compute",)
    random: tuple = ()
    scenes: tuple = ()


def _finite(scale, huge=False):
    def check(ctx, rng, method, tried):
        params = tried.huge if huge else {}
        assert_finite_for_motion_scale(ctx, rng, method, scale, **params)

    return check


# Every promise, as `check(ctx, rng, method, tried)` (a Tried), for a test to parametrize over:
# still frame, input range, no NaN from zero to huge motion, same seed same bits.
PROMISES = {
    "still_frame_unchanged": lambda ctx, rng, method, tried: assert_still_frame_unchanged(
        ctx, rng, method
    ),
    "inside_the_input_range": lambda ctx, rng, method, tried: assert_inside_the_input_range(
        ctx, tried.make(rng, 120, 80), method, **tried.inside
    ),
    "finite_at_zero_motion": _finite(0.0),
    "finite_at_tiny_motion": _finite(1e-6),
    "finite_at_small_motion": _finite(1e-3),
    "finite_at_huge_motion": _finite(1e7, huge=True),
    "finite_at_enormous_motion": _finite(1e30, huge=True),
    "same_seed_same_bits": lambda ctx, rng, method, tried: assert_seeded(
        ctx, tried.make(rng, 80, 60), method
    ),
}


def promise_tests(method: str, tried: Tried):
    """The three tests of `method` tried as `tried` says, for a test module to bind at module
    level (pytest collects them there): its random frames and its rendered scenes match its
    twin, and it keeps every promise. A method's folder declares its Tried and binds them:
    ``test_random_frames, test_rendered_scenes, test_promises = promise_tests(METHOD, TRIED)``."""
    random_cases = [
        (backend, size, params) for backend in tried.backends for size, params in tried.random
    ]

    @pytest.mark.parametrize(("backend", "size", "params"), random_cases)
    def test_random_frames_match_the_twin(ctx, rng, backend, size, params):
        # Half-vectors shorter than k: no two tiles tie at the clamp (conftest.random_frame).
        frame = tried.make(rng, *size, k=min(10, params.get("k", 10)))
        result = bl.blur(ctx, frame, method, backend=backend, **params)
        assert params.items() <= result.params.items()
        assert_matches_twin(result, frame)

    @pytest.mark.parametrize(("scene", "params"), list(tried.scenes))
    def test_rendered_scenes_match_the_twin(ctx, scene, params):
        assert_blurs_a_rendered_scene_as_its_twin(ctx, method, scene, **params)

    @pytest.mark.parametrize("promise", list(PROMISES))
    def test_keeps_the_filter_promises(ctx, rng, promise):
        PROMISES[promise](ctx, rng, method, tried)

    return (
        test_random_frames_match_the_twin,
        test_rendered_scenes_match_the_twin,
        test_keeps_the_filter_promises,
    )
