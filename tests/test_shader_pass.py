"""_core.ShaderPass (src/passes/shader_pass.h): each post-process shader run from named textures
and uniforms gives the same bits as its dedicated pass class, on both backends, restricted to
tiles too; bad names and value counts are refused with the shader and the name."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import random_frame

import blurlab as bl
from blurlab import _core

W, H, K = 53, 37, 8  # sizes that are no multiple of any work-group size
GRID = (-(-H // K), -(-W // K))


def assert_same_bits(a: np.ndarray, b: np.ndarray) -> None:
    assert a.shape == b.shape and a.dtype == b.dtype == np.float32
    assert np.array_equal(a.view(np.uint32), b.view(np.uint32))


def nan_texture(ctx, shape):
    """A target whose texels are all NaN, so that a texel left unwritten shows."""
    return ctx.upload(np.full(shape, np.nan, np.float32))


def same_output(ctx, shape, run_dedicated, run_shader_pass, initial=None):
    """Runs both into targets of `shape` (starting as `initial`, else NaN), checks that every
    texel was written (unless `initial` is given) and that the bits agree."""
    targets = [ctx.upload(initial) if initial is not None else nan_texture(ctx, shape)]
    targets.append(ctx.upload(initial) if initial is not None else nan_texture(ctx, shape))
    run_dedicated(targets[0]._core)
    run_shader_pass(targets[1]._core)
    a, b = (t.download() for t in targets)
    if initial is None:
        assert not np.isnan(a).any()
    assert_same_bits(a, b)
    return a


@pytest.fixture(scope="module")
def frame():
    return random_frame(np.random.default_rng(7), W, H, k=K)


@pytest.fixture(scope="module")
def textures(ctx, frame):
    rng = np.random.default_rng(8)
    # NeighborMax-like grid: some tiles still (|v| <= 0.5), some longer than k.
    angle = rng.uniform(0, 2 * np.pi, GRID)
    length = rng.choice([0.2, 3.0, 1.4 * K], GRID) * rng.uniform(0.5, 1.0, GRID)
    grid = np.stack([np.cos(angle), np.sin(angle)], -1) * length[..., None]
    return {
        "color": ctx.upload(frame.color),
        "depth": ctx.upload(frame.depth),
        "motion": ctx.upload(frame.motion),
        "neighbor_max": ctx.upload(grid.astype(np.float32)),
        "jitter": ctx.upload(rng.random((64, 64), dtype=np.float32)),
    }


def cores(textures, *names):
    return {name: textures[name]._core for name in names}


def shader_pass(ctx, shader):
    return _core.ShaderPass(ctx._core, "passes/" + shader)


# --- gathers ------------------------------------------------------------------------------


@pytest.mark.parametrize("backend", ["compute", "fragment"])
@pytest.mark.parametrize("edge", ["clamp", "ignore"])
@pytest.mark.parametrize("centered", [False, True])
def test_gather_box(ctx, textures, backend, edge, centered):
    params = _core.GatherParams()
    params.taps, params.intensity, params.centered, params.edge = 7, 1.3, centered, edge
    dedicated, generic = _core.GatherBoxPass(ctx._core), shader_pass(ctx, "gather_box.glsl")
    uniforms = {
        "taps": 7,
        "intensity": 1.3,
        "centered": centered,
        "ignore_outside": edge == "ignore",
    }
    same_output(
        ctx,
        (H, W, 4),
        lambda out: dedicated.run(
            textures["color"]._core, textures["motion"]._core, out, params, backend
        ),
        lambda out: generic.run(
            cores(textures, "color", "motion"), {"result": out}, uniforms, backend
        ),
    )


@pytest.mark.parametrize("backend", ["compute", "fragment"])
@pytest.mark.parametrize("edge", ["clamp", "ignore"])
def test_gather_weighted(ctx, textures, backend, edge):
    params = _core.GatherParams()
    params.edge = edge
    dedicated = _core.GatherWeightedPass(ctx._core)
    generic = shader_pass(ctx, "gather_weighted.glsl")
    same_output(
        ctx,
        (H, W, 4),
        lambda out: dedicated.run(
            textures["color"]._core, textures["motion"]._core, out, params, backend
        ),
        lambda out: generic.run(
            cores(textures, "color", "motion"),
            {"result": out},
            {"ignore_outside": edge == "ignore"},
            backend,
        ),
    )


# --- reconstruction filters ---------------------------------------------------------------

DEFAULTS = {
    "k": K,
    "samples": 15,
    "soft_z": 0.05,
    "exposure": 1.0,
    "seed": 0,
    "jitter_tiles": 0,
    "adaptive_samples": 0,
    "early_exit": 0.0,
}
OPTIONS = {
    **DEFAULTS,
    "samples": 9,
    "exposure": 0.7,
    "seed": 4294967295,
    "jitter_tiles": 1,
    "adaptive_samples": 1,
    "early_exit": 2.5,
}


def filter_params(values: dict, params_type=_core.McGuire2012Params):
    p = params_type()
    for name, value in values.items():
        setattr(p, name, bool(value) if name in ("jitter_tiles", "adaptive_samples") else value)
    return p


FILTER_INPUTS = ("color", "depth", "motion", "neighbor_max")


@pytest.mark.parametrize("backend", ["compute", "fragment"])
@pytest.mark.parametrize("values", [DEFAULTS, OPTIONS], ids=["defaults", "options"])
def test_reconstruct_mcguire2012(ctx, textures, backend, values):
    dedicated = _core.ReconstructMcGuire2012Pass(ctx._core)
    generic = shader_pass(ctx, "reconstruct_mcguire2012.glsl")
    params = filter_params(values)
    same_output(
        ctx,
        (H, W, 4),
        lambda out: dedicated.run(
            *(textures[n]._core for n in FILTER_INPUTS), out, params, backend
        ),
        lambda out: generic.run(cores(textures, *FILTER_INPUTS), {"result": out}, values, backend),
    )


@pytest.mark.parametrize("backend", ["compute", "fragment"])
@pytest.mark.parametrize("values", [DEFAULTS, OPTIONS], ids=["defaults", "options"])
def test_reconstruct_guertin2014(ctx, textures, backend, values):
    values = {**values, "gamma": 1.25, "kappa": 33.0}
    dedicated = _core.ReconstructGuertin2014Pass(ctx._core)
    generic = shader_pass(ctx, "reconstruct_guertin2014.glsl")
    params = filter_params(values, _core.Guertin2014Params)
    same_output(
        ctx,
        (H, W, 4),
        lambda out: dedicated.run(
            *(textures[n]._core for n in FILTER_INPUTS), out, params, backend
        ),
        lambda out: generic.run(cores(textures, *FILTER_INPUTS), {"result": out}, values, backend),
    )


def test_reconstruct_urho3d(ctx, textures):
    # The pass sets no sampler state: the shader reads every input with texelFetch and blends
    # four texels itself, so the textures' own nearest / clamp state is all it needs.
    values = {"k": K, "samples": 12, "soft_z": 0.05, "exposure": 1.0, "far": 20.0}
    dedicated = _core.ReconstructUrho3dPass(ctx._core)
    generic = shader_pass(ctx, "reconstruct_urho3d.glsl")
    params = filter_params({n: values[n] for n in ("k", "samples", "soft_z", "exposure")})
    same_output(
        ctx,
        (H, W, 4),
        lambda out: dedicated.run(
            *(textures[n]._core for n in (*FILTER_INPUTS, "jitter")), out, params, values["far"]
        ),
        lambda out: generic.run(
            cores(textures, *FILTER_INPUTS, "jitter"), {"result": out}, values, "fragment"
        ),
    )


@pytest.mark.parametrize("backend", ["compute", "fragment"])
@pytest.mark.parametrize("diagonal_reach", [False, True])
def test_neighbor_max(ctx, textures, backend, diagonal_reach):
    dedicated = _core.NeighborMaxPass(ctx._core)
    generic = shader_pass(ctx, "neighbor_max.glsl")
    tile_max = textures["neighbor_max"]  # any tile grid will do
    same_output(
        ctx,
        (*GRID, 2),
        lambda out: dedicated.run(tile_max._core, out, backend, diagonal_reach),
        lambda out: generic.run(
            {"tile_max": tile_max._core},
            {"neighbor_max": out},
            {"diagonal_reach": diagonal_reach},
            backend,
        ),
    )


@pytest.mark.parametrize("backend", ["compute", "fragment"])
@pytest.mark.parametrize("k", [8, 40])
def test_tile_max(ctx, textures, backend, k):
    # TileMaxPass's choice: a work group per tile above 32 px on llvmpipe, 8 px on a GPU.
    group_per_tile = k > (32 if ctx._core.software else 8)
    values = {"k": k, "exposure": 0.8}
    uniforms = {**values, "group_per_tile": group_per_tile} if backend == "compute" else values
    dedicated, generic = _core.TileMaxPass(ctx._core), shader_pass(ctx, "tile_max.glsl")
    motion = textures["motion"]._core
    same_output(
        ctx,
        (-(-H // k), -(-W // k), 2),
        lambda out: dedicated.run(motion, out, filter_params(values), backend),
        lambda out: generic.run(
            {"motion": motion}, {"tile_max": out}, uniforms, backend, group_per_texel=group_per_tile
        ),
    )


# --- classification's passes, plain and restricted to tiles --------------------------------


def test_tile_copy(ctx, textures):
    dedicated, generic = _core.TileCopyPass(ctx._core), shader_pass(ctx, "tile_copy.glsl")
    same_output(
        ctx,
        (H, W, 4),
        lambda out: dedicated.run(textures["color"]._core, out),
        lambda out: generic.run({"color": textures["color"]._core}, {"result": out}, {}),
    )


def test_uniform_gather(ctx, textures):
    values = {"k": K, "samples": 11, "seed": 99}
    dedicated = _core.UniformGatherPass(ctx._core)
    generic = shader_pass(ctx, "uniform_gather.glsl")
    same_output(
        ctx,
        (H, W, 4),
        lambda out: dedicated.run(
            textures["color"]._core,
            textures["neighbor_max"]._core,
            out,
            filter_params(values),
        ),
        lambda out: generic.run(cores(textures, "color", "neighbor_max"), {"result": out}, values),
    )


@pytest.fixture(scope="module")
def tile_lists(ctx, frame):
    """A classification with every class present: still on the left, one motion in the middle,
    the frame's own motion at the bottom right."""
    motion = np.zeros((H, W, 2), np.float32)
    motion[:, 24:] = (5.0, 2.0)
    motion[24:, 40:] = frame.motion[24:, 40:]
    params = filter_params(DEFAULTS)
    tile_max = ctx.empty((*GRID, 2))
    bounds, neighbors, classes = ctx.empty((*GRID, 4)), ctx.empty((*GRID, 2)), ctx.empty(GRID)
    _core.TileMaxPass(ctx._core).run_with_bounds(
        ctx.upload(motion)._core, tile_max._core, bounds._core, params
    )
    _core.NeighborMaxPass(ctx._core).run(tile_max._core, neighbors._core, "compute")
    lists = _core.TileLists(ctx._core, GRID[1], GRID[0], K)
    _core.ClassifyTilesPass(ctx._core).run(
        bounds._core, neighbors._core, classes._core, lists, _core.ClassifyParams()
    )
    assert all(lists.counts()), lists.counts()
    return lists


# Per tile class: the shader and dedicated pass that handle it, their inputs, the uniforms the
# dedicated pass sets, and how it is run.
RESTRICTED = {
    0: ("tile_copy.glsl", _core.TileCopyPass, ("color",), (), lambda p, i, o, _: p.run(*i, o)),
    1: (
        "uniform_gather.glsl",
        _core.UniformGatherPass,
        ("color", "neighbor_max"),
        ("k", "samples", "seed"),
        lambda p, i, o, params: p.run(*i, o, params),
    ),
    2: (
        "reconstruct_mcguire2012.glsl",
        _core.ReconstructMcGuire2012Pass,
        FILTER_INPUTS,
        tuple(OPTIONS),
        lambda p, i, o, params: p.run(*i, o, params, "compute"),
    ),
}


@pytest.mark.parametrize("tile_class", sorted(RESTRICTED))
def test_restricted_to_tiles(ctx, textures, tile_lists, tile_class):
    # The still class's copy runs a work group per whole tile in TileCopyPass and one per
    # 8 x 8 block through ShaderPass: the same texels either way.
    shader, dedicated_type, names, uniforms, run = RESTRICTED[tile_class]
    dedicated, generic = dedicated_type(ctx._core), shader_pass(ctx, shader)
    for p in (dedicated, generic):
        p.restrict_to_tiles(tile_lists, tile_class)
    initial = np.random.default_rng(9).random((H, W, 4), dtype=np.float32)
    out = same_output(
        ctx,
        (H, W, 4),
        lambda out: run(dedicated, [textures[n]._core for n in names], out, filter_params(OPTIONS)),
        lambda out: generic.run(
            cores(textures, *names), {"result": out}, {n: OPTIONS[n] for n in uniforms}
        ),
        initial=initial,
    )
    assert (out != initial).any() and (out == initial).any()  # some tiles written, some not


# --- read-modify-write: accumulation and stochastic ---------------------------------------


def test_accumulate(ctx, textures):
    dedicated, generic = _core.AccumulatePass(ctx._core), shader_pass(ctx, "accumulate.comp")
    initial = np.random.default_rng(10).random((H, W, 4), dtype=np.float32)
    out = same_output(
        ctx,
        (H, W, 4),
        lambda out: dedicated.run(textures["color"]._core, out, 0.37),
        lambda out: generic.run({"color": textures["color"]._core}, {"sum": out}, {"weight": 0.37}),
        initial=initial,
    )
    assert (out != initial).all()


@pytest.mark.parametrize(("slice_", "position"), [(0, 0), (2, 3)])
def test_stochastic(ctx, textures, slice_, position):
    dedicated, generic = _core.StochasticPass(ctx._core), shader_pass(ctx, "stochastic.comp")
    initial = np.random.default_rng(11).random((H, W, 4), dtype=np.float32)
    uniforms = {"slice": slice_, "position": position, "slices": 3, "seed": 77}
    out = same_output(
        ctx,
        (H, W, 4),
        lambda out: dedicated.run(textures["color"]._core, out, slice_, position, 3, 77),
        lambda out: generic.run({"color": textures["color"]._core}, {"sum": out}, uniforms),
        initial=initial,
    )
    assert (out != initial).any()


# --- camera_motion: mat4 uniforms -----------------------------------------------------------


def test_camera_motion(ctx):
    frame = ctx.render(bl.scenes.get("camera_yaw"), (64, 48))
    camera = frame.camera
    # As the camera_only method hands them to CameraMotionPass.
    matrices = {
        "view_from_clip": np.linalg.inv(camera["projection"]).astype(np.float32),
        "world_from_view": np.linalg.inv(camera["view"][2]).astype(np.float32),
        "clip_from_world": camera["view_projection"][:2].astype(np.float32),
        "sky_from_clip": camera["sky_from_clip"].astype(np.float32),
        "sky_projection": camera["sky_projection"].astype(np.float32),
        "near": float(camera["near"]),
    }
    depth = frame.depth.copy()
    depth[:12] = np.inf  # sky, whose motion comes from sky_from_clip and sky_projection
    depth = ctx.upload(depth)
    dedicated = _core.CameraMotionPass(ctx._core)
    generic = shader_pass(ctx, "camera_motion.glsl")
    motion = same_output(
        ctx,
        (48, 64, 2),
        lambda out: dedicated.run(depth._core, out, matrices),
        lambda out: generic.run({"depth": depth._core}, {"motion": out}, matrices),
    )
    assert np.abs(motion).max() > 1.0  # the camera turns: the test sees real motion


# --- reflect() and errors -------------------------------------------------------------------


def test_reflect_lists_what_a_pass_takes(ctx):
    p = shader_pass(ctx, "reconstruct_mcguire2012.glsl")
    compute = p.reflect("compute")
    assert compute["samplers"] == {
        name: {"type": "sampler2D", "unit": unit} for unit, name in enumerate(FILTER_INPUTS)
    }
    assert compute["images"] == {"result": {"type": "image2D", "unit": 0, "format": "rgba32f"}}
    assert compute["fragment_outputs"] == {}
    assert set(compute["uniforms"]) == set(DEFAULTS)
    assert compute["uniforms"]["seed"] == {"type": "uint", "count": 1}
    fragment = p.reflect("fragment")
    assert fragment["images"] == {}
    assert fragment["fragment_outputs"] == {"result": {"type": "vec4", "location": 0}}
    camera = shader_pass(ctx, "camera_motion.glsl").reflect()
    assert camera["uniforms"]["clip_from_world"] == {"type": "mat4", "count": 32}
    assert camera["images"]["motion"]["format"] == "rg32f"
    # The tile-list uniform is the pass's own business.
    p.restrict_to_tiles(_core.TileLists(ctx._core, GRID[1], GRID[0], K), 2)
    assert "tile_list_k" not in p.reflect()["uniforms"]


def test_errors_name_the_shader_and_the_name(ctx, textures):
    p = shader_pass(ctx, "gather_box.glsl")
    out = ctx.empty((H, W, 4))._core
    inputs = cores(textures, "color", "motion")
    uniforms = {"taps": 5, "intensity": 1.0, "centered": False, "ignore_outside": False}
    with pytest.raises(ValueError, match=r"gather_box.glsl has no sampler 'colour'.*color, motion"):
        p.run({"colour": inputs["color"], "motion": inputs["motion"]}, {"result": out}, uniforms)
    with pytest.raises(
        ValueError, match=r"gather_box.glsl: no texture given for its sampler\(s\) motion"
    ):
        p.run({"color": inputs["color"]}, {"result": out}, uniforms)
    with pytest.raises(ValueError, match=r"gather_box.glsl has no image 'out'.*result"):
        p.run(inputs, {"out": out}, uniforms)
    with pytest.raises(ValueError, match=r"gather_box.glsl has no uniform 'tap'.*taps"):
        p.run(inputs, {"result": out}, {**uniforms, "tap": 5})
    with pytest.raises(ValueError, match=r"gather_box.glsl: uniform 'taps' takes 1 value.*got 2"):
        p.run(inputs, {"result": out}, {**uniforms, "taps": [5, 6]})
    with pytest.raises(ValueError, match=r"gather_box.glsl: uniform 'taps' takes numbers"):
        p.run(inputs, {"result": out}, {**uniforms, "taps": "5"})
    with pytest.raises(ValueError, match=r"gather_box.glsl: input 'color' must be a _core.Texture"):
        p.run({**inputs, "color": textures["color"]}, {"result": out}, uniforms)
    with pytest.raises(ValueError, match=r"gather_box.glsl draws one output.*result"):
        p.run(inputs, {"result": out, "more": out}, uniforms, "fragment")
    assert ctx.gl_errors() == []
