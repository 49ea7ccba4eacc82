"""The TAM generator (docs/spec.md §5): nesting across tones and levels, determinism, calibrated
thresholds, files, users' own images, and argument checks."""

from __future__ import annotations

import numpy as np
import pytest

from blurlab.hatching import tam as tams


@pytest.fixture(scope="module")
def tam():
    return tams.generate(64, 3, seed=3)


def test_tones_nest_every_ink_texel_of_a_tone_is_ink_in_the_next(tam):
    for level in tam.tones:
        assert (np.diff(level, axis=0) >= 0).all()
        binary = level >= 0.5
        assert not (binary[:-1] & ~binary[1:]).any()


def test_levels_nest_every_coarse_stroke_is_in_every_finer_level(tam):
    for coarse in range(1, len(tam.sizes)):
        kept = [s for s in tam.strokes if s.level >= coarse]
        assert kept
        for finer in range(coarse):
            drawn = tams.render_strokes(kept, tam.sizes[finer])
            assert (tam.tones[finer][-1] >= drawn - 1e-6).all()


def test_tones_get_darker_and_reach_their_targets(tam):
    darkness = tam.darkness()
    assert (np.diff(darkness, axis=1) > 0).all()
    # The five lighter tones stop at their target k/6 (within one stroke); the darkest stops
    # where new strokes only cover old ones.
    assert np.allclose(darkness[:, :5], np.arange(1, 6) / 6, atol=0.04)
    assert (darkness[:, 5] > 0.85).all()


def test_thresholds_cover_the_darkness_at_every_level(tam):
    for thr, tones in zip(tam.thresholds, tam.tones, strict=True):
        for d in (0.1, 0.3, 0.5, 0.7, 0.85):
            assert abs((thr < d).mean() - d) < 0.03
        # exactly the texels some stroke covers at least half turn to ink, at some darkness
        assert ((thr < tams.NEVER) == (tones[-1] >= 0.5)).all()


def test_same_seed_same_bits_other_seed_other_strokes():
    a, b = tams.generate(32, 2, seed=7), tams.generate(32, 2, seed=7)
    c = tams.generate(32, 2, seed=8)
    for x, y in zip(a.tones + a.thresholds, b.tones + b.thresholds, strict=True):
        assert x.tobytes() == y.tobytes()
    assert a.tones[0].tobytes() != c.tones[0].tobytes()


def test_write_and_read_back_through_openimageio(tam, tmp_path):
    paths = tam.write(tmp_path)
    assert sorted(p.name for p in paths) == ["tam_16.exr", "tam_32.exr", "tam_64.exr"]
    back = tams.TAM.read(tmp_path)
    assert back.sizes == tam.sizes
    for x, y in zip(tam.tones + tam.thresholds, back.tones + back.thresholds, strict=True):
        np.testing.assert_array_equal(x, y)


def test_users_images_make_a_tam_with_derived_thresholds(tam):
    pictures = [(255 * (1 - tam.tones[0][k])).round().astype(np.uint8) for k in range(6)]
    own = tams.TAM.from_images(pictures, levels=3)
    assert own.sizes == [64, 32, 16]
    assert np.abs(own.tones[0] - tam.tones[0]).max() <= 0.5 / 255 + 1e-6
    thr = own.thresholds[0]
    assert ((thr < tams.NEVER) == (own.tones[0][-1] >= 0.5)).all()
    assert thr.min() > 0


def test_a_stroke_image_draws_the_strokes():
    stroke = np.ones((5, 40))
    stroke[1:4, 2:38] = 0.0  # a dark bar on white
    own = tams.generate(32, 2, seed=1, stroke=stroke, stroke_width=2.0)
    assert (np.diff(own.tones[0], axis=0) >= 0).all()
    assert own.darkness()[0, 2] == pytest.approx(0.5, abs=0.05)


@pytest.mark.parametrize(
    "kwargs, name",
    [
        ({"size": 100}, "size"),
        ({"size": 4}, "size"),
        ({"levels": 0}, "levels"),
        ({"size": 32, "levels": 4}, "levels"),
        ({"seed": -1}, "seed"),
        ({"stroke_width": 0.0}, "stroke_width"),
        ({"stroke_length": (0.5, 0.2)}, "stroke_length"),
        ({"darkness": [0.1, 0.2, 0.3]}, "darkness"),
        ({"darkness": [0.6, 0.5, 0.7, 0.8, 0.9, 1.0]}, "darkness"),
        ({"candidates": 0}, "candidates"),
        ({"stroke": np.zeros((3, 4, 5, 6))}, "stroke"),
    ],
)
def test_bad_generator_arguments_name_the_argument(kwargs, name):
    with pytest.raises(ValueError, match=name):
        tams.generate(**kwargs)


def test_bad_user_tams_are_refused(tmp_path):
    with pytest.raises(ValueError, match="tones"):
        tams.TAM(np.zeros((5, 8, 8), np.float32))
    with pytest.raises(ValueError, match="tones"):
        tams.TAM(np.full((6, 8, 8), 2.0, np.float32))
    with pytest.raises(ValueError, match="level 1"):
        tams.TAM([np.zeros((6, 8, 8), np.float32), np.zeros((6, 8, 8), np.float32)])
    with pytest.raises(ValueError, match="thresholds"):
        tams.TAM(np.zeros((6, 8, 8), np.float32), [np.zeros((8, 8), np.float32)])
    with pytest.raises(FileNotFoundError):
        tams.TAM.read(tmp_path)
