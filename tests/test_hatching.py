"""Hatched materials (docs/spec.md §5) against the NumPy reference: six_way weights, the threshold
rule, tone reproduction of a flat-lit patch, and hatched objects in the G-buffer."""

from __future__ import annotations

import math

import numpy as np
import pytest
from method_picks import EXAMPLE

import blurlab as bl
from blurlab.studies import hatching
from blurlab.twins import hatching as ref


@pytest.fixture(scope="module")
def tam():
    return bl.tam.generate(64, 3, seed=3)


def test_weights_are_non_negative_and_sum_to_one_for_any_intensity(rng):
    intensity = np.concatenate(
        [rng.uniform(-0.5, 1.5, 10000), np.arange(7) / 6, [0.0, 1.0, -np.inf, np.inf]]
    )
    weights = ref.six_way_weights(intensity)
    assert (weights >= 0).all()
    np.testing.assert_allclose(weights.sum(-1), 1.0, atol=1e-12)
    assert ((weights > 0).sum(-1) <= 2).all()
    # the two nearest tones of t = 6 (1 - I), and only those
    t = 6 * (1 - np.clip(intensity, 0, 1))
    nearest = np.abs(np.arange(7)[None, :] - t[:, None])
    assert (weights[nearest >= 1] == 0).all()


def quads_scene(intensities, tam) -> bl.Scene:
    """Quads side by side across the patch view, each with a constant normal whose Lambert
    intensity under a light along +z is the given one."""
    n = len(intensities)
    parts = []
    for j, value in enumerate(intensities):
        x0, x1 = -0.5 + j / n, -0.5 + (j + 1) / n
        theta = math.acos(value)
        normal = (math.sin(theta), 0.0, math.cos(theta))
        positions = [(x0, -0.5, 0), (x1, -0.5, 0), (x0, 0.5, 0), (x1, 0.5, 0)]
        uv = [(0, 1), (1, 1), (0, 0), (1, 0)]
        parts.append(bl.Mesh(positions, [normal] * 4, uv, [[0, 1, 2], [1, 3, 2]]))
    light = bl.DirectionalLight(direction=(0, 0, 1), ambient=(0, 0, 0))
    camera = bl.Camera(position=(0, 0, 0.5 / math.tan(math.radians(15))), fov_y=30.0)
    scene = bl.Scene(camera, light, background=(1, 1, 1))
    scene.add(bl.Mesh.merge(parts), bl.Material.hatching("six_way", tam))
    return scene


def test_gpu_six_way_weights_match_the_reference(ctx):
    intensities = np.linspace(0.0, 1.0, 16)
    size = 128
    columns = ((np.arange(16) + 0.5) * size / 16).astype(int)
    measured = np.zeros((16, 7))
    for tone in range(6):
        basis = np.zeros((6, 16, 16), np.float32)
        basis[tone] = 1.0  # constant ink 1 in this tone only: the pixel's ink is its weight
        frame = ctx.render(quads_scene(intensities, basis), (size, size), shutter=(0, 0))
        measured[:, tone + 1] = hatching.ink_of(frame)[size // 2, columns]
    expected = ref.six_way_weights(intensities)
    np.testing.assert_allclose(measured[:, 1:], expected[:, 1:], atol=2e-3)


def test_gpu_threshold_rule_matches_the_reference_pixel_for_pixel(ctx, tam):
    size = 128  # two pixels a texel of the 64-texel level: the smooth step lands between texels
    material = bl.Material.hatching("threshold", tam)
    y, x = np.mgrid[0:size, 0:size] + 0.5
    uv = np.stack([0.5 + x / size, 0.5 + y / size], -1)  # the patch shows uv 0.5 .. 1.5
    for darkness in (0.0, 0.2, 0.55, 0.9, 1.0):
        frame = ctx.render(hatching.patch_scene(darkness, material), (size, size), shutter=(0, 0))
        expected = ref.threshold_ink(tam.thresholds[0], uv, darkness)
        np.testing.assert_allclose(hatching.ink_of(frame), expected, atol=5e-3)


def test_small_images_read_the_tams_own_coarsest_level(ctx, tam):
    # 64 texels over 8 pixels: the level of detail (3) lies past the last level (2), which GL
    # then reads alone; each pixel center falls between 2 × 2 texels of that level.
    size, level = 8, len(tam.sizes) - 1
    y, x = np.mgrid[0:size, 0:size]
    uv = np.stack([0.5 + (x + 0.5) / size, 0.5 + (y + 0.5) / size], -1)
    s = tam.sizes[level]
    p = uv * s - 0.5
    x0, y0 = np.floor(p[..., 0]).astype(int) % s, np.floor(p[..., 1]).astype(int) % s
    x1, y1 = (x0 + 1) % s, (y0 + 1) % s
    tones = tam.tones[level].astype(np.float16).astype(np.float64)
    mean = (tones[:, y0, x0] + tones[:, y0, x1] + tones[:, y1, x0] + tones[:, y1, x1]) / 4
    for darkness in (0.3, 0.75):
        threshold = bl.Material.hatching("threshold", tam)
        frame = ctx.render(hatching.patch_scene(darkness, threshold), (size, size), (0, 0))
        expected = ref.threshold_ink(tam.thresholds[level], uv, darkness)
        np.testing.assert_allclose(hatching.ink_of(frame), expected, atol=5e-3)
        six_way = bl.Material.hatching("six_way", tam)
        frame = ctx.render(hatching.patch_scene(darkness, six_way), (size, size), (0, 0))
        expected = ref.six_way_ink(ref.six_way_weights(1.0 - darkness), mean)
        np.testing.assert_allclose(hatching.ink_of(frame), expected, atol=5e-3)


def test_blinn_phong_tone_source_matches_the_reference_per_pixel(ctx, tam):
    size = 128
    material = bl.Material.hatching("threshold", tam, specular=0.6, shininess=8.0)
    scene = hatching.patch_scene(0.0, material)
    scene.light = bl.DirectionalLight((0.5, 0.3, 0.8), color=(0.5, 0.5, 0.5), ambient=(0.02,) * 3)
    frame = ctx.render(scene, (size, size), shutter=(0, 0))
    y, x = np.mgrid[0:size, 0:size] + 0.5
    points = np.stack([x / size - 0.5, 0.5 - y / size, 0 * x], -1)  # the view is 1 unit across
    eye = scene.camera.position
    view = eye - points
    view /= np.linalg.norm(view, axis=-1, keepdims=True)
    light = np.array(scene.light.direction) / np.linalg.norm(scene.light.direction)
    intensity = ref.intensity(
        [0, 0, 1], view, light, scene.light.color, scene.light.ambient, 0.6, 8
    )
    assert intensity.max() - intensity.min() > 0.05  # the highlight makes a gradient
    uv = np.stack([0.5 + x / size, 0.5 + y / size], -1)
    expected = ref.threshold_ink(tam.thresholds[0], uv, 1.0 - intensity)
    differ = np.abs(hatching.ink_of(frame) - expected) > 0.01
    assert differ.mean() < 0.005  # only where a threshold equals the darkness to float precision


@pytest.mark.parametrize("scheme", bl.hatching.SCHEMES)
def test_darker_targets_give_more_ink_as_the_tam_predicts(ctx, tam, scheme):
    result = hatching.tone_reproduction(ctx, scheme, tam, steps=12, size=64)
    measured = result["measured"]
    assert measured[0] < 1e-4  # white at darkness 0 (to float precision of the light)
    assert (np.diff(measured) > 0).all()
    np.testing.assert_allclose(measured, result["expected"], atol=0.01)
    # the darkest tone of a stroke TAM is not black: six_way's error is largest there
    assert result["mean_abs_error"] < (0.03 if scheme == "threshold" else 0.05)


def test_hatched_objects_keep_depth_and_motion_and_blur(ctx, tam):
    def scene(material):
        s = bl.Scene(bl.Camera(position=(0, 0.8, 3), look_at=(0, 0.4, 0)), background=(1, 1, 1))
        motion = bl.Motion.linear(velocity=(30, 0, 0), spin_axis=(0, 1, 0), spin_rate=3)
        s.add(bl.mesh.teapot(6), material, motion)
        return s

    plain = ctx.render(scene(bl.Material()), (96, 64))
    for scheme in bl.hatching.SCHEMES:
        hatched = ctx.render(scene(bl.Material.hatching(scheme, tam, scale=2)), (96, 64))
        np.testing.assert_array_equal(hatched.depth, plain.depth)
        np.testing.assert_array_equal(hatched.motion, plain.motion)
        np.testing.assert_array_equal(hatched.object_id, plain.object_id)
        ink = hatching.ink_of(hatched)[hatched.object_id >= 0]
        assert 0.05 < ink.mean() < 0.95 and (ink > 0.5).any()
        out = bl.blur(ctx, hatched, EXAMPLE, k=8, samples=9)
        assert np.isfinite(out.color).all()
        assert np.abs(out.color - hatched.color).max() > 0.1  # the hatching was blurred


def test_a_tam_folder_is_a_tam(ctx, tam, tmp_path):
    tam.write(tmp_path)
    material = bl.Material.hatching("six_way", str(tmp_path))
    assert material.hatch.tam.sizes == tam.sizes
    frame = ctx.render(hatching.patch_scene(0.5, material), (64, 64), shutter=(0, 0))
    assert hatching.ink_of(frame).mean() == pytest.approx(0.5, abs=0.02)


def test_no_motion_and_no_light_change_means_no_popping(ctx, tam):
    result = hatching.temporal_coherence(
        ctx, "threshold", tam, frames=3, size=(96, 72), moving_light=False, spin_per_frame=0.0
    )
    assert result["pop_fraction"].tolist() == [0.0, 0.0]
    assert result["reprojected_pop_fraction"].tolist() == [0.0, 0.0]
    assert result["ink_change"].tolist() == [0.0, 0.0]


def test_turning_the_light_with_the_object_is_the_same_tone(ctx, tam):
    # spin only, still light: the same-pose measure compares frame n with frame n's light
    # turned back and forth; with a still light the turn is all there is
    result = hatching.temporal_coherence(ctx, "six_way", tam, frames=3, size=(96, 72))
    assert (result["pop_fraction"] < 0.5).all()
    assert (result["ink_change"] > 0).all()


@pytest.mark.parametrize(
    "kwargs, name",
    [
        ({"scheme": "sixway"}, "scheme"),
        ({"tam": np.zeros((5, 16, 16), np.float32)}, "tam"),
        ({"tam": np.zeros((6, 16, 8), np.float32)}, "tam"),
        ({"tam": np.zeros((6, 16, 16), np.int32)}, "tam"),
        ({"tam": np.full((6, 16, 16), 1.5, np.float32)}, "tam"),
        ({"tam": "strokes.png"}, "tam"),
        ({"scale": 0.0}, "scale"),
        ({"scale": -1.0}, "scale"),
        ({"scale": math.nan}, "scale"),
        ({"scale": "2"}, "scale"),
        ({"specular": -1.0}, "specular"),
        ({"tam": bl.tam}, "tam"),
    ],
)
def test_bad_arguments_name_the_argument(kwargs, name, tam):
    kwargs.setdefault("tam", tam)
    with pytest.raises(ValueError, match=name):
        bl.Material.hatching(**kwargs)


def test_a_hatch_that_is_not_a_hatching_is_refused():
    with pytest.raises(ValueError, match="hatch"):
        bl.Material(hatch="six_way")


def test_an_obj_with_texture_coordinates_is_hatched(ctx, tam, tmp_path):
    path = tmp_path / "quad.obj"
    path.write_text(
        "v -0.5 -0.5 0\nv 0.5 -0.5 0\nv 0.5 0.5 0\nv -0.5 0.5 0\n"
        "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\nf 1/1/1 2/2/1 3/3/1 4/4/1\n"
    )
    quad = bl.mesh.load(path)
    assert np.ptp(quad.uvs, axis=0).tolist() == [1.0, 1.0]
    scene = hatching.patch_scene(0.5, bl.Material.hatching("threshold", tam))
    scene.objects.clear()
    scene.add(quad, bl.Material.hatching("threshold", tam))
    ink = hatching.ink_of(ctx.render(scene, (64, 64), shutter=(0, 0)))
    assert ink.mean() == pytest.approx(0.5, abs=0.03)  # one whole tile at darkness 0.5
    assert (ink > 0.99).mean() > 0.3 and (ink < 0.01).mean() > 0.3  # strokes, not grey


def test_one_pass_draws_each_scheme_with_its_own_program(ctx, tam):
    """Plain, six_way and threshold objects in one G-buffer pass (one program per scheme, each
    given the frame's uniforms when first used): every object's pixels equal those of a pass
    in which all three objects share its scheme."""

    def scene(schemes):
        s = bl.Scene(bl.Camera(position=(0, 0.5, 4), look_at=(0, 0.3, 0)), background=(1, 1, 1))
        for x, scheme in zip((-1.2, 0.0, 1.2), schemes, strict=True):
            material = bl.Material() if scheme is None else bl.Material.hatching(scheme, tam)
            motion = bl.Motion.linear(start=(x, 0, 0), velocity=(4, 0, 0), spin_axis=(0, 1, 0))
            s.add(bl.mesh.teapot(6), material, motion)
        return s

    schemes = (None, *bl.hatching.SCHEMES)
    mixed = ctx.render(scene(schemes), (120, 48))
    shared = {scheme: ctx.render(scene((scheme,) * 3), (120, 48)) for scheme in schemes}
    for index, scheme in enumerate(schemes):
        alone = shared[scheme]
        np.testing.assert_array_equal(alone.object_id, mixed.object_id)
        drawn = mixed.object_id == index
        assert drawn.sum() > 100
        np.testing.assert_array_equal(mixed.color[drawn], alone.color[drawn])
        np.testing.assert_array_equal(mixed.motion[drawn], alone.motion[drawn])
        for other in schemes:  # the schemes do differ there, so the check above has teeth
            if other != scheme:
                assert np.abs(shared[other].color[drawn] - alone.color[drawn]).max() > 0.1
