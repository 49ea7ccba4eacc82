"""Property-based tests of the public API (hypothesis): random parameters for every registered
method, random arrays for textures and frames, random sizes up to the device's limit + 1,
random render and reference arguments, random image and OBJ files.

Every call either returns finite output of the right shape or raises ValueError/TypeError
(OSError for files) whose message names the argument; none leaves a GL error set. The tests
read the registry (bl.methods(), bl.method(name).params, bl.scenes.names()), so methods added
later are fuzzed too. docs/reliability.md records what is fuzzed and how many examples run.
"""

from __future__ import annotations

import math
import re
import warnings

import numpy as np
import pytest
from conftest import count_example
from hypothesis import HealthCheck, assume, event, given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

import blurlab as bl
from blurlab.methods import method

SIZE = (16, 12)  # rendered frames: tiny, so a few thousand examples fit in CI


def fuzz(examples: int) -> settings:
    """The profile's settings (conftest.py) with `examples` examples and no deadline
    (llvmpipe compiles each new shader variant on first use)."""
    return settings(
        max_examples=examples,
        deadline=None,
        suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow],
    )


BAD_ARGUMENT = (ValueError, TypeError)


def assert_no_gl_error(ctx):
    errors = ctx.gl_errors()
    assert errors == [], f"GL errors left set: {errors}"


def assert_names(error: Exception, *names: str) -> None:
    text = str(error)
    assert any(re.search(rf"\b{re.escape(n)}\b", text) for n in names), (
        f"{type(error).__name__} names none of {names}: {text}"
    )


def assert_finite_image(color: np.ndarray, size) -> None:
    width, height = size
    assert color.shape == (height, width, 4)
    assert np.isfinite(color).all(), "non-finite output"


@pytest.fixture(scope="module")
def frames(ctx):
    """One rendered frame per instant, per scene kind (still cheap at 16 x 12)."""
    scene = bl.scenes.fan()
    return {instant: ctx.render(scene, SIZE, instant=instant) for instant in ("center", "close")}


# --- method parameters ---------------------------------------------------------------------

SPECIAL_NUMBERS = [
    0,
    -1,
    1,
    0.5,
    -0.0,
    math.nan,
    math.inf,
    -math.inf,
    1e-50,
    1e39,
    1e300,
    2**31,
    2**32,
    2**64,
    2**1100,
]
WRONG_TYPES = ["20", None, b"x", [1], (1, 2), {"a": 1}, 1 + 2j, True, np.array([1.0, 2.0])]


def valid_value(p) -> st.SearchStrategy:
    """Values the parameter's declaration allows (ints near the low end: their cost grows)."""
    if isinstance(p.kind, tuple):
        return st.sampled_from(p.kind)
    if p.kind is bool:
        return st.booleans()
    if p.kind is int:
        low = int(p.low) if p.low is not None else -(2**31)
        high = int(p.high) if p.high is not None else 2**31
        return st.integers(low, min(high, low + 16)) | st.sampled_from(
            [v for v in (low, high) if v - low <= 300]
        )
    low = p.low if p.low is not None else -1e6
    high = min(p.high, 1e6) if p.high is not None else 1e6
    if p.low_open:
        low = max(low, 1e-6)  # the float32 value must stay > low
    return st.floats(low, high, allow_nan=False, allow_infinity=False)


def invalid_value(p) -> st.SearchStrategy:
    """Values that break the declaration: wrong types, outside the range, not finite."""
    if isinstance(p.kind, tuple):
        return st.sampled_from(["", "nonsense", p.kind[0].upper(), 3, None, [p.kind[0]]])
    if p.kind is bool:
        return st.sampled_from([v for v in WRONG_TYPES if v is not True] + [0, 1, 0.5, "True"])
    out = list(WRONG_TYPES)
    if p.kind is int:
        out += [0.5, 2.0, math.nan, math.inf]
        out += [int(p.low) - 1] if p.low is not None else []
        out += [int(p.high) + 1, 2**1100] if p.high is not None else []
    else:
        out += [math.nan, math.inf, -math.inf, 2**1100, 1e39]
        out += [p.low - 1.0, p.low if p.low_open else p.low - 1e-3] if p.low is not None else []
        out += [p.high * 2 + 1] if p.high is not None else []
    return st.sampled_from(out)


@st.composite
def method_call(draw):
    """(method name, params, names of the invalid ones)."""
    name = draw(st.sampled_from(bl.methods()))
    params, invalid = {}, set()
    for key, p in method(name).params.items():
        if p.kind is object:  # e.g. trail's history: None is the declared default
            if draw(st.booleans()):
                params[key] = None
            continue
        choice = draw(st.sampled_from(["default"] * 4 + ["valid"] * 4 + ["invalid", "special"]))
        if choice == "valid":
            params[key] = draw(valid_value(p))
        elif choice == "invalid":
            params[key] = draw(invalid_value(p))
            invalid.add(key)
        elif choice == "special":
            params[key] = draw(st.sampled_from(SPECIAL_NUMBERS + WRONG_TYPES))
            invalid.add(key)  # may be valid after all: then the call must succeed
    if draw(st.integers(0, 9)) == 0:
        params["no_such_parameter"] = 1
        invalid.add("no_such_parameter")
    return name, params, invalid


@fuzz(800)
@given(call=method_call(), backend=st.sampled_from([None] * 4 + ["compute", "fragment", "cuda"]))
def test_every_method_takes_any_parameters(ctx, frames, call, backend):
    name, params, invalid = call
    count_example()
    m = method(name)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # instant mismatches are warned about, not errors
        instant = bl.method_instant(name, {}) if not callable(m.instant) else "center"
        try:
            result = bl.blur(ctx, frames[instant], name, backend, **params)
        except BAD_ARGUMENT as error:
            event(f"{name}: {type(error).__name__}")
            assert_no_gl_error(ctx)
            if backend not in (None, *m.backends):
                assert_names(error, "backends")
                return
            # Parameters whose allowed values depend on each other's (Method.linked_params:
            # e.g. gather_coverage's 3-tap film through the taps holds film_filter up to
            # 0.71 px, docs/spec.md §17.6): each valid alone, the pair refused, both named.
            linked = [pair for pair in m.linked_params if set(pair) <= set(params)]
            if not invalid and linked:  # each valid alone, refused together: named together
                assert any(all(key in str(error) for key in pair) for pair in linked), error
                return
            assert invalid, f"{name}({params}) raised for valid parameters: {error}"
            assert_names(error, *invalid)
            return
    event(f"{name}: ran")
    assert_no_gl_error(ctx)
    assert backend in (None, *m.backends)
    assert_finite_image(result.color, SIZE)
    assert_no_gl_error(ctx)


# --- frames built from arrays --------------------------------------------------------------

NUMERIC = ["uint8", "int16", "int64", "float16", "float32", "float64", ">f4"]
ODD = ["bool", "complex64", "U3", "object"]
POISON = [np.nan, np.inf, -np.inf, 0.0, -1.0, 3e38, -3e38, 1e-45]


@st.composite
def image(draw, height, width, channels, poison=True):
    odd = draw(st.integers(0, 9)) == 0
    dtype = draw(st.sampled_from(NUMERIC + ODD if odd else NUMERIC))
    shape = (height, width) if channels is None else (height, width, channels)
    if dtype in ODD:
        return np.zeros(shape, dtype=dtype)
    values = draw(
        hnp.arrays(
            np.float64,
            shape,
            elements=st.floats(-1e3, 1e3, allow_nan=False, width=32),
        )
    )
    if poison and dtype[-1] in "24" and draw(st.booleans()):
        mask = draw(hnp.arrays(np.bool_, shape))
        values = np.where(mask, draw(st.sampled_from(POISON)), values)
    with np.errstate(invalid="ignore", over="ignore"):
        return values.astype(dtype)


@st.composite
def frame_arrays(draw, limit):
    wide = draw(st.integers(0, 19)) == 0  # now and then a row at the device's limit (+ 1)
    if wide:
        height, width = 1, draw(st.sampled_from([limit - 1, limit, limit + 1]))
    else:
        height, width = draw(st.integers(1, 9)), draw(st.integers(1, 9))
    c_shape = draw(st.sampled_from([4, 4, 4, 3, 2, 5]))
    m_shape = draw(st.sampled_from([2, 2, 2, 1, 3]))
    mismatch = draw(st.integers(0, 9)) == 0
    return (
        draw(image(height, width, c_shape, poison=not wide)),
        draw(image(height, width + mismatch, None, poison=not wide)),
        draw(image(height, width, m_shape, poison=not wide)),
    )


@fuzz(500)
@given(data=st.data())
def test_frames_from_any_arrays(ctx, data):
    limit = ctx.max_texture_size
    color, depth, motion = data.draw(frame_arrays(limit))
    name = data.draw(st.sampled_from(bl.methods()))
    count_example()
    try:
        frame = bl.Frame(color=color, depth=depth, motion=motion)
    except BAD_ARGUMENT as error:
        assert_names(error, "color", "depth", "motion")
        return
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            result = bl.blur(ctx, frame, name)
    except BAD_ARGUMENT as error:
        assert_no_gl_error(ctx)
        assert_names(error, "frame", "size")  # a frame that needs ctx.render, or too wide
        if "size" in str(error):
            assert frame.size[0] > limit
        return
    event("ran")
    assert frame.size[0] <= limit
    assert_finite_image(result.color, frame.size)
    assert_no_gl_error(ctx)


# --- textures ------------------------------------------------------------------------------

TEXTURE_DTYPES = ["uint8", "float16", "float32", "uint32", ">f4", "<f2", "int8", "int32", "uint16"]
TEXTURE_DTYPES += ["float64", "bool", "complex64"]


@fuzz(400)
@given(
    array=hnp.arrays(
        st.sampled_from(TEXTURE_DTYPES).map(np.dtype),
        hnp.array_shapes(min_dims=0, max_dims=4, min_side=0, max_side=6),
    ),
    transpose=st.booleans(),
)
def test_upload_any_array(ctx, array, transpose):
    count_example()
    if transpose and array.ndim >= 2:
        array = array.swapaxes(0, 1)  # not C-contiguous
    try:
        texture = ctx.upload(array)
    except BAD_ARGUMENT as error:
        assert_no_gl_error(ctx)
        assert_names(error, "array")
        ok_dtype = array.dtype.name in ("uint8", "float16", "float32", "uint32")
        ok_shape = array.ndim in (2, 3) and array.size > 0
        ok_shape = ok_shape and (array.ndim == 2 or 1 <= array.shape[2] <= 4)
        assert not (ok_dtype and ok_shape), f"valid array refused: {error}"
        return
    back = texture.download()
    assert back.shape == array.shape and back.dtype == array.dtype.newbyteorder("=")
    np.testing.assert_array_equal(
        back.view(f"u{back.itemsize}"), array.astype(back.dtype).view(f"u{back.itemsize}")
    )
    assert_no_gl_error(ctx)


def side(limit):
    return st.integers(-2, 9) | st.sampled_from(
        [limit - 1, limit, limit + 1, 2**31, 2**63, -(2**31)]
    )


@fuzz(250)
@given(data=st.data())
def test_empty_any_shape_up_to_the_limit(ctx, data):
    limit = ctx.max_texture_size
    h, w = data.draw(side(limit)), data.draw(side(limit))
    shape = data.draw(
        st.sampled_from([(h, w), (h, w, 1), (h, w, 4), (h, w, 3), (h, w, 0), (h, w, 5), (h,)])
        | st.sampled_from([(h, 2.5), ("4", 4), (True, 3), None])
    )
    dtype = data.draw(st.sampled_from(["float32", "uint8", "float16", "float64", "nonsense", None]))
    fits = isinstance(h, int) and isinstance(w, int) and 1 <= h <= limit and 1 <= w <= limit
    # Never allocate gigabytes: a valid shape must be small (w = limit means h = 1, ...).
    assume(not fits or h * w <= 1 << 16)
    count_example()
    try:
        texture = ctx.empty(shape, dtype)
    except BAD_ARGUMENT as error:
        assert_no_gl_error(ctx)
        assert_names(error, "shape", "dtype", "size")
        return
    assert fits and texture.shape == tuple(shape)
    assert not texture.download().any()
    assert_no_gl_error(ctx)


def test_limit_plus_one_is_refused_before_allocating(ctx):
    limit = ctx.max_texture_size
    before = ctx.live_objects().get("texture", 0)
    for shape in [(limit + 1, 1), (1, limit + 1), (limit + 1, limit + 1, 4), (2**31, 2**31)]:
        with pytest.raises(ValueError, match=rf"outside 1\.\.{limit}"):
            ctx.empty(shape)
    with pytest.raises(ValueError, match=rf"outside 1\.\.{limit}"):
        ctx.upload(np.zeros((1, limit + 1), np.uint8))
    with pytest.raises(ValueError, match=rf"1\.\.{limit}"):
        ctx.render(bl.scenes.fan(), (limit + 1, 1))
    with pytest.raises(ValueError, match=rf"1\.\.{limit}"):
        ctx.reference(bl.scenes.fan(), (1, limit + 1), samples=1)
    assert ctx.live_objects().get("texture", 0) == before
    edge = ctx.empty((1, limit, 4))  # exactly the limit works
    assert edge.width == limit
    assert_no_gl_error(ctx)


# --- render and reference arguments --------------------------------------------------------


@fuzz(150)
@given(data=st.data())
def test_render_any_arguments(ctx, data):
    limit = ctx.max_texture_size
    scene_name = data.draw(st.sampled_from(bl.scenes.names()))
    w = data.draw(st.integers(1, 12) | st.sampled_from([0, -1, limit + 1, 2.5, math.inf, "8"]))
    h = data.draw(st.integers(1, 8) | st.sampled_from([0, limit + 1, math.nan, None]))
    shutter = data.draw(
        st.none()
        | st.tuples(st.floats(-1, 1), st.floats(-1, 1))
        | st.sampled_from([(0, math.inf), (math.nan, 1), (1, 0), "ab", (0,)])
    )
    instant = data.draw(
        st.sampled_from(["center", "close", "open", "middle", None, 0.0]) | st.floats()
    )
    motion_format = data.draw(st.sampled_from([*bl.MOTION_FORMATS, "rgb9e5", 3]))
    maxlen = data.draw(st.none() | st.sampled_from([1.0, 0.0, -1.0, math.nan, math.inf, "x"]))
    count_example()
    args = dict(shutter=shutter, instant=instant, motion_format=motion_format, maxlen=maxlen)
    try:
        frame = ctx.render(bl.scenes.get(scene_name), (w, h), **args)
    except BAD_ARGUMENT as error:
        assert_no_gl_error(ctx)
        assert_names(error, "size", "shutter", "instant", "motion_format", "maxlen")
        return
    assert frame.color.shape == (h, w, 4) and np.isfinite(frame.color).all()
    assert np.isfinite(frame.motion).all()
    assert_no_gl_error(ctx)


@fuzz(60)
@given(
    samples=st.integers(1, 6) | st.sampled_from([0, -3, 2.0, None, True, 2**70]),
    seed=st.integers(0, 2**32 - 1) | st.sampled_from([-1, 2**32, 1.5, "0"]),
    stratified=st.booleans(),
)
def test_reference_any_arguments(ctx, samples, seed, stratified):
    count_example()
    try:
        reference = ctx.reference(
            bl.scenes.fan(), (8, 6), samples=samples, seed=seed, stratified=stratified
        )
    except BAD_ARGUMENT as error:
        assert_no_gl_error(ctx)
        assert_names(error, "samples", "seed")
        return
    assert np.isfinite(reference.color).all() and reference.color.shape == (6, 8, 4)
    assert_no_gl_error(ctx)


# --- files ---------------------------------------------------------------------------------


@fuzz(200)
@given(
    array=hnp.arrays(
        st.sampled_from(["uint8", "float16", "float32", "float64", "int32", "bool"]).map(np.dtype),
        hnp.array_shapes(min_dims=0, max_dims=4, min_side=0, max_side=5),
        elements={"allow_nan": True} if False else None,
    ),
    suffix=st.sampled_from([".exr", ".png", ".EXR", ".jpg", ""]),
)
def test_write_any_array_leaves_a_file_or_nothing(tmp_path_factory, array, suffix):
    count_example()
    folder = tmp_path_factory.mktemp("w")
    path = folder / f"image{suffix}"
    try:
        bl.io.write(path, array)
    except BAD_ARGUMENT as error:
        assert_names(error, "array", "dtype", "extensions", "PNG", "NaN")
        assert list(folder.iterdir()) == []
        return
    assert [p.name for p in folder.iterdir()] == [path.name]
    back = bl.io.read(path)
    assert back.shape[:2] == array.shape[:2]


OBJ_LINES = st.sampled_from(
    [
        "v 0 0 0",
        "v 1 0 0",
        "v 0 1 0",
        "v 1 1",
        "v nan 0 0",
        "v 1e999 0 0",
        "v a b c",
        "vt 0.5 0.5",
        "vt",
        "vn 0 0 1",
        "vn 0 0 0",
        "f 1 2 3",
        "f 1/1/1 2/1/1 3/1/1",
        "f -1 -2 -3",
        "f 1 2",
        "f 1 2 99",
        "f 0 1 2",
        "f 1//1 2//1 3//1",
        "f x y z",
        "# comment",
        "",
        "g group",
        "\x00\xff",
    ]
)


@fuzz(250)
@given(lines=st.lists(OBJ_LINES, max_size=12), cut=st.integers(0, 200))
def test_load_any_obj(tmp_path_factory, lines, cut):
    count_example()
    path = tmp_path_factory.mktemp("obj") / "mesh.obj"
    text = "\n".join(lines)
    path.write_bytes(text.encode("utf-8", "surrogateescape")[: cut or None])
    try:
        mesh = bl.mesh.load(path)
    except (OSError, ValueError) as error:
        assert "mesh.obj" in str(error) or "mesh" in str(error)
        return
    assert np.isfinite(mesh.positions).all() and len(mesh.indices) > 0


# --- compute programs ----------------------------------------------------------------------


@fuzz(150)
@given(
    size=st.tuples(st.integers(-1, 40), st.integers(-1, 40)),
    seed=st.integers(0, 2**32 - 1)
    | st.sampled_from([-1, 2**32, 0.5, math.nan, math.inf, 1e20, [1, 2], "7"]),
    define=st.sampled_from(
        [{}, {"CHECKER": 4}, {"CHECKER": 1.5}, {"not valid": 1}, {"X": math.nan}]
    ),
)
def test_program_run_any_arguments(ctx, size, seed, define):
    count_example()
    width, height = size
    try:
        program = ctx.program("util/test_pattern.comp", defines=define)
        target = ctx.empty((max(height, 1), max(width, 1), 4))
        program.run(size, images=[target], uniforms={"seed": seed})
    except (*BAD_ARGUMENT, bl.ShaderError) as error:
        assert_no_gl_error(ctx)
        if isinstance(error, bl.ShaderError):
            assert define.get("CHECKER") == 1.5  # a float where GLSL needs an int
        else:
            assert_names(error, "seed", "work-group", "not a GLSL identifier", "finite", "define")
        return
    assert width >= 1 and height >= 1
    assert np.isfinite(target.download()).all()
    assert_no_gl_error(ctx)
