"""Compute programs: GPU against NumPy, #include/#define handling, errors as file:line."""

from __future__ import annotations

import numpy as np
import pytest

import blurlab as bl
from blurlab import twins


def test_add_one_agrees_with_numpy(ctx, rng, test_shader):
    image = rng.standard_normal((45, 80, 4)).astype(np.float32)
    src, dst = ctx.upload(image), ctx.empty(image.shape)
    program = ctx.program(test_shader("add_scalar.comp"))
    assert program.local_size == (8, 8, 1)
    program.run((80, 45), images=[(src, "read"), (dst, "write")], uniforms={"value": 1.0})
    np.testing.assert_array_equal(dst.download(), image + np.float32(1.0))


def test_mat4_and_float_arrays_are_set_row_by_row(ctx, rng, test_shader):
    # Small integers: every product and sum is exact in float32, whatever the GPU's order.
    image = rng.integers(-8, 8, (6, 10, 4)).astype(np.float32)
    matrices = rng.integers(-4, 4, (2, 4, 4)).astype(np.float64)
    offsets = [0.5, -2.0]
    src, dst = ctx.upload(image), ctx.empty(image.shape)
    program = ctx.program(test_shader("matrix_array.comp"))
    assert {"matrices", "offsets"} <= set(program.uniforms)  # arrays go by name, no "[0]"
    uniforms = {"matrices": matrices, "offsets": offsets}
    program.run((10, 6), images=[(src, "read"), (dst, "write")], uniforms=uniforms)
    column = np.arange(10) % 2
    expected = (
        np.einsum("xij,yxj->yxi", matrices[column], image) + np.take(offsets, column)[:, None]
    )
    np.testing.assert_array_equal(dst.download(), expected.astype(np.float32))
    with pytest.raises(ValueError, match="matrix_array.comp: uniform 'matrices' takes 32 value"):
        program.run(
            (10, 6), images=[(src, "read"), (dst, "write")], uniforms={"matrices": matrices[0]}
        )


def test_test_pattern_matches_its_reference(ctx):
    width, height, seed = 97, 61, 7
    out = ctx.empty((height, width, 4))
    ctx.program("util/test_pattern.comp").run(
        (width, height), images=[out], uniforms={"seed": seed}
    )
    gpu = out.download().astype(np.float64)
    ref = twins.test_pattern(width, height, seed)
    np.testing.assert_allclose(gpu[..., :2], ref[..., :2], atol=1e-7)
    np.testing.assert_array_equal(gpu[..., 2], ref[..., 2])
    # docs/spec.md §1 hash: the GPU keeps 24 bits of it, so the two differ by less than 2^-24.
    assert np.max(np.abs(gpu[..., 3] - ref[..., 3])) < 2.0**-24
    assert np.all(gpu[..., 3] < 1.0)


def test_pcg_matches_spec_formula():
    v = np.array([0, 1, 2, 12345, 2**32 - 1], dtype=np.uint32)
    expected = []
    for x in v.tolist():
        s = (x * 747796405 + 2891336453) % 2**32
        w = (((s >> ((s >> 28) + 4)) ^ s) * 277803737) % 2**32
        expected.append((w >> 22) ^ w)
    np.testing.assert_array_equal(twins.pcg(v), np.array(expected, dtype=np.uint32))


def test_define_is_injected(ctx):
    out = ctx.empty((8, 8, 4))
    ctx.program("util/test_pattern.comp", defines={"CHECKER": 2}).run((8, 8), images=[out])
    np.testing.assert_array_equal(
        out.download()[..., 2], twins.test_pattern(8, 8, checker=2)[..., 2]
    )


def write(path, text):
    path.write_text(text)
    return path


def test_compile_error_names_file_and_line(ctx, tmp_path):
    shader = write(
        tmp_path / "broken.comp",
        "#version 450\n"
        '#include "common/pixel.glsl"\n'
        "layout(local_size_x = 1) in;\n"
        "void main() {\n"
        "    float x = undefined_name;\n"  # line 5
        "}\n",
    )
    with pytest.raises(bl.ShaderError) as error:
        ctx.program(shader)
    message = str(error.value)
    assert f"{shader}:5:" in message
    assert "undefined_name" in message


def test_error_inside_an_include_names_the_included_file(ctx, tmp_path):
    write(tmp_path / "helper.glsl", "float helper() {\n    return oops;\n}\n")  # line 2
    shader = write(
        tmp_path / "main.comp",
        '#version 450\n#include "helper.glsl"\nlayout(local_size_x = 1) in;\nvoid main() {}\n',
    )
    with pytest.raises(bl.ShaderError) as error:
        ctx.program(shader, defines={"UNUSED": 1})
    assert f"{tmp_path / 'helper.glsl'}:2:" in str(error.value)


def test_missing_include_is_reported(ctx, tmp_path):
    shader = write(tmp_path / "main.comp", '#version 450\n#include "nowhere.glsl"\n')
    with pytest.raises(bl.ShaderError, match=r"main.comp:2: #include \"nowhere.glsl\" not found"):
        ctx.program(shader)


def test_missing_version_is_reported(ctx, tmp_path):
    shader = write(tmp_path / "main.comp", "void main() {}\n")
    with pytest.raises(bl.ShaderError, match="#version"):
        ctx.program(shader)


def test_bad_define_name_is_rejected(ctx):
    with pytest.raises(ValueError, match="not a GLSL identifier"):
        ctx.program("util/test_pattern.comp", defines={"2BAD": 1})


def test_unknown_uniform_lists_the_real_ones(ctx, test_shader):
    program = ctx.program(test_shader("add_scalar.comp"))
    image = ctx.empty((4, 4, 4))
    with pytest.raises(ValueError, match="no uniform 'valu'.*value"):
        program.run((4, 4), images=[image, image], uniforms={"valu": 1.0})
    with pytest.raises(ValueError, match="takes 1 value"):
        program.run((4, 4), images=[image, image], uniforms={"value": [1.0, 2.0]})


def test_three_channel_texture_cannot_be_an_image(ctx, test_shader):
    program = ctx.program(test_shader("add_scalar.comp"))
    with pytest.raises(ValueError, match="3-channel"):
        program.run((4, 4), images=[ctx.empty((4, 4, 3)), ctx.empty((4, 4, 4))])


def test_bad_image_access_is_rejected(ctx, test_shader):
    program = ctx.program(test_shader("add_scalar.comp"))
    with pytest.raises(ValueError, match="'read', 'write' or 'read_write'"):
        program.run((4, 4), images=[(ctx.empty((4, 4, 4)), "readonly")])


def test_timer_reports_its_clock(ctx, test_shader):
    program = ctx.program(test_shader("add_scalar.comp"))
    src, dst = ctx.empty((90, 160, 4)), ctx.empty((90, 160, 4))
    with ctx.timer() as timing:
        program.run((160, 90), images=[src, dst], uniforms={"value": 1.0})
    assert timing.clock == ctx.info()["timer"]
    assert 0.0 < timing.ms < 10_000.0
