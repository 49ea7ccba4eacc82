"""Every filter against its NumPy twin and on its promises (tests/filter_promises.py), one table
for all of them: random frames and rendered scenes match the twin; a still frame comes back
unchanged, the output stays inside the input range, zero, tiny and huge motion give no NaN, the
same seed gives the same bits. Each row says how its method is tried: the frame (engine_eevee
and gather_coverage read two-sided motion), the parameters that let its blur reach far enough to
be tested, and the frames and scenes it must match its twin on."""

from __future__ import annotations

import pytest
from conftest import assert_matches_twin
from filter_promises import (
    PROMISES,
    Tried,
    assert_blurs_a_rendered_scene_as_its_twin,
    two_sided_frame,
)

import blurlab as bl

BOTH = ("compute", "fragment")
SCENES = ("teapot_pass", "fan", "skinned_arm", "crossing")
TRIED = {
    "engine_eevee": Tried(
        two_sided_frame,
        {"tile_size": 16},
        {"max_blur": 1e6, "tile_size": 16},
        random=(
            ((160, 90), {}),
            ((97, 61), {"tile_size": 8, "samples": 5, "max_blur": 40.0, "depth_scale": 2.0}),
            ((130, 70), {"tile_size": 16, "samples": 1, "exposure": 2.5, "seed": 9}),
            ((40, 30), {"tile_size": 4, "samples": 12, "max_blur": 6.0, "depth_scale": 0.5}),
        ),
        scenes=tuple((scene, {"tile_size": 16}) for scene in SCENES),
    ),
    "engine_unity": Tried(
        inside={"max_radius": 15.0},
        huge={"max_radius": 50.0},
        random=(
            ((160, 90), {}),
            ((97, 61), {"samples": 4, "max_radius": 12.0, "depth_factor": 3.0}),
            ((130, 70), {"samples": 32, "max_radius": 40.0, "exposure": 2.5, "seed": 9}),
            ((40, 30), {"samples": 7, "max_radius": 1.0, "far": 4.0}),
        ),
        scenes=tuple((scene, {}) for scene in SCENES),
    ),
    "engine_hdrp": Tried(
        inside={"fast_ratio": 0.2},
        huge={"maximum_velocity": 65024.0},
        random=(
            ((160, 90), {}),
            ((97, 61), {"samples": 4, "maximum_velocity": 12.0, "depth_comparison_extent": 0.3}),
            ((130, 70), {"samples": 12, "intensity": 2.5, "seed": 9, "fast_ratio": 0.05}),
            ((150, 80), {"scatter": True, "minimum_velocity": 6.0}),
            ((40, 30), {"samples": 64, "minimum_velocity": 0.0, "fast_ratio": 1.0}),
        ),
        scenes=(
            ("teapot_pass", {}),
            ("fan", {}),
            ("crossing", {}),
            ("fan", {"scatter": True}),
            ("camera_yaw", {"camera_clamp_mode": "rotation"}),
            ("vehicle", {"camera_clamp_mode": "separate", "translation_clamp": 0.01}),
            ("vehicle", {"camera_clamp_mode": "full", "scatter": True}),
            ("vehicle", {"camera_motion_blur": False}),
        ),
    ),
    "engine_unreal": Tried(
        inside={"max_blur": 15.0},
        huge={"max_blur": 100.0},
        random=(
            ((160, 90), {}),
            ((97, 61), {"quality": 1, "max_blur": 12.0, "depth_extent": 0.05}),
            ((130, 70), {"quality": 4, "max_blur": 30.0, "exposure": 2.5, "seed": 9}),
            ((40, 30), {"quality": 2, "max_blur": 1.0}),
        ),
        scenes=(("teapot_pass", {}), ("fan", {}), ("crossing", {})),
    ),
    # engine_godot's twin checks are in tests/test_engine_godot.py; its promises are here.
    "engine_godot": Tried(inside={"k": 15}, huge={"k": 256}),
    "engine_unreal5": Tried(
        random=(
            ((160, 90), {}),
            ((160, 90), {"directions": 2}),
            ((97, 61), {"quality": 1, "max_blur": 12.0, "depth_extent": 0.05, "directions": 2}),
            ((130, 70), {"quality": 4, "max_blur": 30.0, "exposure": 2.5, "seed": 9}),
            ((40, 30), {"quality": 2, "max_blur": 1.0, "half_res_gather": 0, "directions": 2}),
        ),
        scenes=tuple(
            (scene, {"directions": directions})
            for scene in ("teapot_pass", "fan", "crossed_motions")
            for directions in (1, 2)
        ),
    ),
    "engine_jimenez2014": Tried(
        backends=BOTH,
        random=(
            ((160, 90), {}),
            ((97, 61), {"k": 8, "samples": 3, "soft_z": 0.05}),
            ((130, 70), {"k": 32, "samples": 24, "exposure": 2.5, "seed": 9}),
        ),
        scenes=(("teapot_pass", {}), ("crossing", {})),
    ),
    "gather_coverage": Tried(
        two_sided_frame,
        inside={"max_blur": 40.0},
        huge={"max_blur": 50.0},
        random=(
            ((160, 90), {}),
            ((97, 61), {"tile_percent": 20.0, "samples": 5, "max_blur": 60.0, "soft_z": 2.0}),
            ((130, 70), {"samples": 2, "exposure": 2.5, "seed": 9}),
            ((40, 30), {"tile_percent": 1.0, "samples": 16, "max_blur": 10.0, "soft_z": 0.01}),
            ((160, 90), {"film_filter": 0.5}),
            ((64, 48), {"film_filter": 1.3, "samples": 6}),
            ((160, 90), {"film_filter": 0.5, "film_through_taps": True}),
            ((61, 37), {"film_filter": 0.7, "film_through_taps": True, "samples": 5, "seed": 4}),
            ((160, 90), {"tap_spacing": 3.0}),
            ((97, 61), {"tap_spacing": 1.5, "samples": 15, "early_exit": 6.0}),
            ((130, 70), {"uniform_tolerance": 8.0, "samples": 7, "seed": 2}),
            ((97, 61), {"half_res_above": 6.0, "tap_spacing": 2.0}),
        ),
        scenes=tuple((scene, {}) for scene in (*SCENES, "occluder", "moire")),
    ),
    "gather_pixel": Tried(
        backends=BOTH,
        random=(
            ((160, 90), {}),
            ((97, 61), {"samples": 1, "spacing": 0.5, "depth_extent": 0.05}),
            ((130, 70), {"samples": 16, "spacing": 1.0, "exposure": 2.5, "seed": 9}),
        ),
        scenes=(("teapot_pass", {}), ("crossing", {})),
    ),
}
RANDOM = [
    (method, backend, size, params)
    for method, tried in TRIED.items()
    for backend in tried.backends
    for size, params in tried.random
]
RENDERED = [
    (method, scene, params) for method, tried in TRIED.items() for scene, params in tried.scenes
]


@pytest.mark.parametrize(("method", "backend", "size", "params"), RANDOM)
def test_random_frames_match_the_twin(ctx, rng, method, backend, size, params):
    # Half-vectors shorter than k: no two tiles tie at the clamp (conftest.random_frame).
    frame = TRIED[method].make(rng, *size, k=min(10, params.get("k", 10)))
    result = bl.blur(ctx, frame, method, backend=backend, **params)
    assert params.items() <= result.params.items()
    assert_matches_twin(result, frame)


@pytest.mark.parametrize(("method", "scene", "params"), RENDERED)
def test_rendered_scenes_match_the_twin(ctx, method, scene, params):
    assert_blurs_a_rendered_scene_as_its_twin(ctx, method, scene, **params)


@pytest.mark.parametrize("promise", list(PROMISES))
@pytest.mark.parametrize("method", list(TRIED))
def test_every_filter_keeps_its_promises(ctx, rng, method, promise):
    PROMISES[promise](ctx, rng, method, TRIED[method])
