"""Every filter refuses bad parameters before it runs, with an error that names the parameter,
the value and what is allowed (docs/reliability.md): one table, a row per method."""

from __future__ import annotations

import pytest
from conftest import random_frame

import blurlab as bl

# method: the bad parameters each refuses, with the error and (a regex of) its message
REFUSALS = {
    "engine_eevee": [
        ({"tile_size": 2}, ValueError, r"tile_size = 2 is outside 4\.\.256"),
        ({"samples": 0}, ValueError, r"samples = 0 is outside 1\.\.64"),
        ({"depth_scale": 0.0}, ValueError, "depth_scale = 0.0 is outside"),
        ({"max_blur": -1.0}, ValueError, "max_blur = -1.0 is outside"),
        ({"k": 3}, TypeError, "no parameter.*k.*depth_scale"),
    ],
    "engine_godot": [
        ({"quality": "ultra"}, ValueError, "quality"),
        ({"object_multiplier": 1.5}, ValueError, "object_multiplier = 1.5 is outside"),
        ({"reference_fps": 0.0}, ValueError, "reference_fps"),
    ],
    "engine_hdrp": [
        ({"samples": 1}, ValueError, r"samples = 1 is outside 2\.\.64"),
        ({"maximum_velocity": -1.0}, ValueError, r"maximum_velocity = -1.0 is outside"),
        ({"depth_comparison_extent": 0.0}, ValueError, "depth_comparison_extent = 0.0 must be"),
        ({"camera_clamp_mode": "Rotation"}, ValueError, "must be one of 'none', 'rotation'"),
        ({"fast_ratio": 1.5}, ValueError, r"fast_ratio = 1.5 is outside \[0, 1\]"),
        ({"scatter": 1}, TypeError, "scatter must be True or False"),
        ({"k": 3}, TypeError, "no parameter.*k.*samples"),
    ],
    "engine_jimenez2014": [
        ({"k": 0}, ValueError, r"k = 0 is outside 1\.\.256"),
        ({"soft_z": 0.0}, ValueError, "soft_z = 0.0 must be"),
        ({"quality": 3}, TypeError, "no parameter.*quality.*samples"),
    ],
    "engine_unity": [
        ({"samples": 3}, ValueError, r"samples = 3 is outside 4\.\.32"),
        ({"max_radius": 0.0}, ValueError, "max_radius = 0.0 must be"),
        ({"depth_factor": -1.0}, ValueError, r"depth_factor = -1.0 is outside"),
        ({"k": 3}, TypeError, "no parameter.*k.*depth_factor"),
    ],
    "engine_unreal": [
        ({"quality": 0}, ValueError, r"quality = 0 is outside 1\.\.4"),
        ({"quality": 5}, ValueError, r"quality = 5 is outside 1\.\.4"),
        ({"max_blur": 0.0}, ValueError, "max_blur = 0.0 must be"),
        ({"max_blur": 101.0}, ValueError, "max_blur = 101.0"),
        ({"depth_extent": 0.0}, ValueError, "depth_extent = 0.0 must be"),
        ({"samples": 8}, TypeError, "no parameter.*samples.*quality"),
    ],
    "engine_unreal5": [
        ({"directions": 3}, ValueError, r"directions = 3 is outside 1\.\.2"),
        ({"half_res_gather": 2}, ValueError, r"half_res_gather = 2 is outside 0\.\.1"),
        ({"tile_dispatch": "all"}, ValueError, "tile_dispatch must be one of 'lists', 'one'"),
        ({"quality": 5}, ValueError, r"quality = 5 is outside 1\.\.4"),
        ({"samples": 8}, TypeError, "no parameter.*samples.*quality"),
    ],
    "gather_coverage": [
        ({"samples": 1}, ValueError, r"samples = 1 is outside 2\.\.32"),
        ({"max_blur": 0.0}, ValueError, "max_blur = 0.0 must be"),
        ({"tile_percent": 101.0}, ValueError, "tile_percent = 101.0"),
        ({"film_filter": 4.5}, ValueError, r"film_filter = 4\.5 is outside \[0, 4\]"),
        ({"film_filter": -0.5}, ValueError, "film_filter = -0.5"),
        ({"k": 3}, TypeError, "no parameter.*k.*tile_percent"),
        ({"tap_spacing": -1.0}, ValueError, "tap_spacing = -1.0"),
        ({"uniform_tolerance": float("nan")}, ValueError, "uniform_tolerance must be finite"),
    ],
    "gather_pixel": [
        ({"samples": 0}, ValueError, r"samples = 0 is outside 1\.\.32"),
        ({"spacing": 0.0}, ValueError, "spacing = 0.0 must be"),
        ({"depth_extent": -1.0}, ValueError, "depth_extent = -1.0"),
        ({"taps": 8}, TypeError, "no parameter.*taps.*samples"),
    ],
    "reconstruct_guertin2014": [
        ({"gamma": 0.0}, ValueError, "gamma .* must be finite and > 0"),
        ({"kappa": -1.0}, ValueError, "kappa .* must be finite and > 0"),
        ({"gamma": float("inf")}, ValueError, "gamma must be finite"),
        ({"k": 0}, ValueError, r"k = 0 is outside 1\.\.256"),
        ({"samples": 300}, ValueError, r"samples = 300 is outside 1\.\.256"),
        ({"taps": 3}, TypeError, "no parameter.*taps.*gamma"),
    ],
    "reconstruct_mcguire2012": [
        ({"k": 0}, ValueError, r"k = 0 is outside 1\.\.256"),
        ({"k": 2.5}, TypeError, "k must be an integer"),
        ({"samples": 0}, ValueError, r"samples = 0 is outside 1\.\.256"),
        ({"soft_z": 0.0}, ValueError, "soft_z .* must be finite and > 0"),
        ({"soft_z": -1.0}, ValueError, "soft_z"),
        ({"exposure": float("nan")}, ValueError, "exposure must be finite"),
        ({"exposure": float("inf")}, ValueError, "exposure must be finite"),
        ({"seed": -1}, ValueError, "seed"),
        ({"taps": 3}, TypeError, "no parameter.*taps.*samples"),
    ],
}
CASES = [(method, *case) for method, cases in REFUSALS.items() for case in cases]


@pytest.mark.parametrize(("method", "params", "error", "message"), CASES)
def test_a_bad_parameter_is_refused_in_words(ctx, rng, method, params, error, message):
    with pytest.raises(error, match=message):
        bl.blur(ctx, random_frame(rng, 16, 16), method, **params)
