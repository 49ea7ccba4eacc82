"""Translucent and masked surfaces and particles (docs/spec.md §20): materials, the fragment
lists' resolve against its NumPy twin, the order-independent reference, overflow, particles."""

import random

import numpy as np
import pytest
from method_picks import EXAMPLE, pick, picks

import blurlab as bl
from blurlab.methods.layers import TRANSLUCENCY
from blurlab.scene import translucency as fragment_lists
from blurlab.scene.particles import Particle, particles
from blurlab.scene.translucency import resolve_fragments
from blurlab.twins import translucency as twin

SIZE = (48, 32)
# What blurs the translucent layer when layer_filter is "auto" (registered translucent_layer).
LAYER = pick(role="translucent_layer")
# A gather whose frame is rendered at the shutter's close, where the layer's motion is not.
CLOSE_GATHER = next(
    n for n in picks(kind="gather", exclude=(LAYER,)) if bl.method_instant(n) == "close"
)


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"alpha": 1.5}, r"alpha must be in \[0, 1\]"),
        ({"alpha": float("nan")}, r"alpha must be in \[0, 1\]"),
        ({"alpha_cutoff": -0.1}, r"alpha_cutoff must be in \[0, 1\]"),
        ({"blend": "alpha"}, r"one of \('opaque', 'mask', 'blend', 'additive'\)"),
        ({"blend": None}, "blend must be one of"),
    ],
)
def test_material_alpha_is_checked(kwargs, message):
    with pytest.raises(ValueError, match=message):
        bl.Material(**kwargs)


def test_material_alpha_must_be_a_number():
    with pytest.raises(TypeError, match="alpha must be a number"):
        bl.Material(alpha="0.5")


def quad_scene(material, background=(0.1, 0.2, 0.3)):
    scene = bl.Scene(background=background, name="quad")
    scene.add(bl.mesh.box((1.2, 1.2, 0.01)), material, bl.Motion.static((0, 0, 2)))
    return scene


def test_blend_over_the_background_is_premultiplied_over():
    # Unlit: no light, all ambient, so the surface's colour is its albedo times the ambient.
    material = bl.Material(color=(0.9, 0.5, 0.1), alpha=0.25, blend="blend")
    scene = quad_scene(material)
    scene.light = bl.DirectionalLight(color=(0, 0, 0), ambient=(1, 1, 1))
    frame = bl.Context().render(scene, size=SIZE)
    assert frame.layered
    center = frame.color[SIZE[1] // 2, SIZE[0] // 2, :3]
    # Two fragments (the thin box's front and back faces) over the background.
    one = np.array([0.9, 0.5, 0.1])
    expected = 0.25 * one + 0.75 * (0.25 * one + 0.75 * np.array([0.1, 0.2, 0.3]))
    np.testing.assert_allclose(center, expected, atol=1e-6)
    assert frame.translucent[SIZE[1] // 2, SIZE[0] // 2, 3] == pytest.approx(1 - 0.75**2)
    np.testing.assert_array_equal(frame.opaque_color[0, 0], frame.color[0, 0])  # uncovered
    assert np.isinf(frame.translucent_depth[0, 0]) and np.isfinite(frame.translucent_depth).any()


def test_mask_drops_the_surface_below_the_cutoff():
    texture = np.ones((8, 8, 4), np.float32)
    texture[:, :4, 3] = 0.2  # half the texture is below the cutoff
    drawn = {}
    for blend in ("opaque", "mask"):
        material = bl.Material(texture=texture, blend=blend, alpha_cutoff=0.5)
        scene = bl.Scene(name="mask")
        facing = bl.quaternion((1, 0, 0), np.pi / 2)  # the plane's +y normal turned to +z
        scene.add(bl.mesh.plane(1.2, 1.2), material, bl.Motion.static((0, 0, 2), facing))
        frame = bl.Context().render(scene, size=SIZE)
        assert not frame.layered  # a mask is opaque where it is kept
        drawn[blend] = int((frame.object_id >= 0).sum())
    assert 0.3 * drawn["opaque"] < drawn["mask"] < 0.7 * drawn["opaque"]


def random_lists(rng, capacity, shape=(6, 5)):
    h, w = shape
    counts = rng.integers(0, capacity + 3, size=shape).astype(np.uint32)
    surface = np.zeros((capacity, h, w, 4), np.float32)
    surface[..., 3] = rng.choice([0.0, 0.3, 0.5, 1.0], size=(capacity, h, w))
    surface[..., :3] = rng.choice([0.1, 0.4], size=(capacity, h, w, 3)) * surface[..., 3:]
    motion = np.zeros((capacity, h, w, 4), np.float32)
    motion[..., 0] = rng.choice([1.0, 2.0, 2.5], size=(capacity, h, w))  # ties on purpose
    motion[..., 1:3] = rng.normal(size=(capacity, h, w, 2)).astype(np.float32)
    motion[..., 3] = rng.choice([2.0, 3.0], size=(capacity, h, w))
    surface[..., 3] = np.where(motion[..., 3] == 3.0, 0.0, surface[..., 3])
    opaque = rng.random((h, w, 4)).astype(np.float32)
    return opaque, counts, surface, motion


def gpu_resolve(ctx, opaque, counts, surface, motion):
    capacity, h, w, _ = surface.shape
    outputs = {name: ctx.empty((h, w, 4)) for name in twin.RESOLVED}
    outputs["most_fragments"] = ctx.empty((1, 1), "uint32")
    lists = {
        "opaque_color": ctx.upload(opaque),
        "fragment_counts": ctx.upload(counts),
        "fragment_surface": ctx.upload(np.ascontiguousarray(surface.reshape(capacity * h, w, 4))),
        "fragment_motion": ctx.upload(np.ascontiguousarray(motion.reshape(capacity * h, w, 4))),
    }
    resolve_fragments(ctx, lists, outputs)
    return {name: texture.download() for name, texture in outputs.items()}


@pytest.mark.parametrize("seed", [0, 1])
def test_resolve_matches_its_numpy_twin(seed):
    rng = np.random.default_rng(seed)
    ctx = bl.Context()
    opaque, counts, surface, motion = random_lists(rng, capacity=4)
    gpu = gpu_resolve(ctx, opaque, counts, surface, motion)
    expected = twin.resolve(opaque, counts, surface, motion)
    for name in twin.RESOLVED:
        np.testing.assert_allclose(gpu[name], expected[name], atol=1e-6, err_msg=name)
    assert gpu["most_fragments"][0, 0] == counts.max()


def test_resolve_does_not_depend_on_the_order_fragments_arrive():
    rng = np.random.default_rng(7)
    ctx = bl.Context()
    opaque, counts, surface, motion = random_lists(rng, capacity=5)
    counts = np.minimum(counts, 5).astype(np.uint32)
    first = gpu_resolve(ctx, opaque, counts, surface, motion)
    # The same lists, each pixel's fragments in another order.
    listed = np.arange(5)[:, None, None] < counts[None]
    keys = np.where(listed, rng.random(surface.shape[:3]), 2.0 + np.arange(5)[:, None, None])
    order = np.argsort(keys, axis=0)
    shuffled = [np.take_along_axis(a, order[..., None], axis=0) for a in (surface, motion)]
    second = gpu_resolve(ctx, opaque, counts, *shuffled)
    for name in twin.RESOLVED:
        np.testing.assert_array_equal(first[name], second[name], err_msg=name)


def glass_and_sparks(seed=None):
    scene = bl.Scene(name="glass and sparks")
    scene.add(bl.mesh.box((3, 3, 0.2)), bl.Material(color=(0.2, 0.6, 0.2)), bl.Motion.static())
    glass = bl.Material(color=(0.9, 0.2, 0.2), alpha=0.5, blend="blend")
    scene.add(bl.mesh.box((1, 1, 0.05)), glass, bl.Motion.linear((-1, 0, 1), (90, 0, 0)))
    tint = bl.Material(color=(0.2, 0.2, 0.9), alpha=0.6, blend="blend")
    scene.add(bl.mesh.box((1, 0.5, 0.05)), tint, bl.Motion.static((0, 0, 1.5)))
    for i in range(6):  # blended and additive in turn
        blend = "additive" if i % 2 else "blend"
        spark = Particle((0.3 * i - 0.8, 0.0, 2.0), (0, 40, 0), 0.4, (1.0, 0.8, 0.3), 0.7, blend)
        particles(scene, [spark], f"spark {i}")
    if seed is not None:
        random.Random(seed).shuffle(scene.objects)
    return scene


def test_reference_does_not_depend_on_the_object_order():
    ctx = bl.Context()
    first = ctx.reference(glass_and_sparks(), size=SIZE, samples=8).color
    for seed in (1, 2):
        shuffled = ctx.reference(glass_and_sparks(seed), size=SIZE, samples=8).color
        np.testing.assert_allclose(shuffled, first, atol=1e-6)
    assert first.std() > 0.05


def test_too_many_fragments_raise():
    scene = glass_and_sparks()
    scene.max_layers = 1
    with pytest.raises(OverflowError, match="max_layers"):
        bl.Context().reference(scene, size=SIZE, samples=2)
    with pytest.raises(OverflowError, match="max_layers"):
        bl.Context().render(scene, size=SIZE)


def test_max_layers_is_checked():
    with pytest.raises(ValueError, match="max_layers"):
        bl.Scene(max_layers=0)


def test_particles_face_the_camera_and_move():
    # A camera turning about its own axis: the quad stays square on screen at every instant.
    scene = bl.Scene(camera=bl.Camera(position=(0, 0, 5), look_at=(0, 0, 0)), name="particle")
    scene.camera.motion = bl.Motion.linear(spin_axis=(0, 0, 1), spin_rate=20.0)
    (obj,) = particles(scene, [Particle((0, 0, 0), velocity=(60, 0, 0), size=1.0, alpha=0.5)])
    for t in (0.0, 1 / 120, 1 / 60):
        model, view = obj.model(t), scene.camera.view(t)
        axes = (view @ model)[:3, :3]
        np.testing.assert_allclose(axes, np.eye(3), atol=1e-12)  # aligned with view space
    frame = bl.Context().render(scene, size=SIZE)
    covered = frame.translucent[..., 3] > 0
    assert covered.any()
    # 60 units/s over 1/60 s = 1 unit across the screen, to the right (+x) in pixels.
    moving = frame.translucent_motion[covered]
    assert (moving[:, 0] > 1.0).all()


def test_particles_outside_their_lifetime_are_not_drawn():
    scene = bl.Scene(name="dead particle")
    particles(scene, [Particle((0, 0, 0), size=1.0, lifetime=(1.0, 2.0))])
    frame = bl.Context().render(scene, size=SIZE, shutter=(0.0, 0.5))
    assert not (frame.translucent[..., 3] > 0).any()


@pytest.mark.parametrize(
    "kwargs, error",
    [
        ({"size": 0.0}, ValueError),
        ({"size": True}, TypeError),
        ({"lifetime": (2.0, 1.0)}, ValueError),
        ({"velocity": (1, 2)}, ValueError),
        ({"blend": "screen"}, ValueError),
    ],
)
def test_particle_arguments_are_checked(kwargs, error):
    with pytest.raises(error):
        particles(bl.Scene(), [Particle((0, 0, 0), **kwargs)])


APPROACHES = TRANSLUCENCY.kind


@pytest.mark.parametrize("translucency", APPROACHES)
def test_every_approach_leaves_opaque_frames_as_they_are(translucency):
    ctx = bl.Context()
    frame = ctx.render(bl.scenes.teapot_pass(), size=SIZE)
    plain = bl.blur(ctx, frame, EXAMPLE).color
    chosen = bl.blur(ctx, frame, EXAMPLE, translucency=translucency).color
    np.testing.assert_array_equal(chosen, plain)


def test_the_options_are_checked():
    ctx = bl.Context()
    frame = ctx.render(glass_and_sparks(), size=SIZE)
    with pytest.raises(ValueError, match="translucency must be one of 'composite'"):
        bl.blur(ctx, frame, EXAMPLE, translucency="sorted")
    with pytest.raises(ValueError, match=r"motion_coverage = 2.0 is outside \[0, 1\]"):
        bl.blur(ctx, frame, EXAMPLE, translucency="composite_motion", motion_coverage=2.0)


def test_composite_is_the_plain_blur_of_the_engine_image():
    ctx = bl.Context()
    frame = ctx.render(glass_and_sparks(), size=SIZE, instant="close")
    plain = bl.Frame(frame.color, frame.depth, frame.motion, frame.object_id, frame.shutter)
    plain.time = frame.time
    ours = bl.blur(ctx, frame, CLOSE_GATHER, translucency="composite").color
    np.testing.assert_array_equal(ours, bl.blur(ctx, plain, CLOSE_GATHER).color)


@pytest.mark.parametrize("coverage", [0.3, 0.9])
def test_composite_motion_matches_its_numpy_twin(coverage):
    ctx = bl.Context()
    frame = ctx.render(glass_and_sparks(), size=SIZE, instant="close")
    result = bl.blur(
        ctx, frame, CLOSE_GATHER, translucency="composite_motion", motion_coverage=coverage
    )
    motion, depth = twin.chosen_motion(
        frame.translucent,
        frame.translucent_motion,
        frame.translucent_depth,
        frame.motion,
        frame.depth,
        coverage,
    )
    np.testing.assert_array_equal(result.buffers["chosen_motion"], motion)
    np.testing.assert_array_equal(result.buffers["chosen_depth"], depth)
    # At 0.3 the panes cover enough to write their own motion, which differs from what lies
    # behind them; whether anything reaches 0.9 depends on how the sparks overlap as rasterized.
    reaches = (frame.translucent[..., 3] >= coverage) & np.isfinite(frame.translucent_depth)
    own = np.any(frame.translucent_motion != frame.motion, axis=-1) & reaches
    assert own.any() == (not np.array_equal(motion, frame.motion))
    assert coverage > 0.5 or own.any()


@pytest.mark.parametrize("translucency", ["unblurred", "layered"])
def test_over_matches_its_numpy_twin(translucency):
    ctx = bl.Context()
    frame = ctx.render(glass_and_sparks(), size=SIZE)
    result = bl.blur(ctx, frame, EXAMPLE, translucency=translucency)
    opaque = result.buffers["opaque_blurred"]
    opaque_alone = bl.Frame(frame.opaque_color, frame.depth, frame.motion, frame.object_id)
    opaque_alone.shutter, opaque_alone.time = frame.shutter, frame.time
    np.testing.assert_array_equal(opaque, bl.blur(ctx, opaque_alone, EXAMPLE).color)
    layer = frame.translucent
    if translucency == "layered":
        alone = bl.Frame(
            frame.translucent, frame.translucent_depth, frame.translucent_motion, frame.object_id
        )
        alone.shutter, alone.time = frame.shutter, frame.time
        # At the centre instant the coverage gather blurs the layer (layer_filter="auto").
        assert result.params["layer_filter"] == LAYER
        layer = bl.blur(ctx, alone, LAYER).color
    np.testing.assert_allclose(result.color, twin.over(layer, opaque), atol=1e-6)


@pytest.mark.parametrize("layer_filter", ["same", LAYER])
def test_layer_filter_chooses_what_blurs_the_translucent_layer(layer_filter):
    ctx = bl.Context()
    frame = ctx.render(glass_and_sparks(), size=SIZE)
    name = EXAMPLE
    result = bl.blur(ctx, frame, name, translucency="layered", layer_filter=layer_filter, k=8)
    expected = name if layer_filter == "same" else LAYER
    assert result.params["layer_filter"] == expected
    assert result.params["k"] == 8
    assert any(key.startswith("translucent_") for key in result.timings)


def test_render_and_blur_takes_the_option():
    ctx = bl.Context()
    _, result = bl.render_and_blur(
        ctx, glass_and_sparks(), CLOSE_GATHER, size=SIZE, translucency="layered"
    )
    assert "translucency_over" in result.timings and "translucent_gather[moving]" in result.timings
    assert result.params["translucency"] == "layered"


def test_the_coverage_gather_blurs_the_layer_at_any_instant(recwarn):
    """A gather's frame rendered at the shutter's close: the layer's two-sided motion is made
    for that instant, so the coverage gather blurs it there without a warning, and better than
    the gather itself on a pane that slides over a still wall."""
    ctx = bl.Context()
    scene = bl.scenes.moving_glass()
    frame = ctx.render(scene, size=SIZE, instant=bl.method_instant(CLOSE_GATHER))
    reference = ctx.reference(scene, size=SIZE, samples=32, antialias=True, progress=False)
    auto = bl.blur(ctx, frame, CLOSE_GATHER, translucency="layered")
    same = bl.blur(ctx, frame, CLOSE_GATHER, translucency="layered", layer_filter="same")
    assert auto.params["layer_filter"] == LAYER
    assert not [w for w in recwarn if "expects the G-buffer" in str(w.message)]
    psnr = lambda out: bl.metrics.psnr(out.color, reference.color)  # noqa: E731
    assert psnr(auto) > psnr(same) + 2


def test_five_transparency_scenes_are_tagged():
    names = bl.scenes.names("transparency")
    assert len(names) >= 5 and not set(names) & set(bl.scenes.names("failure"))
    for name in names:
        assert bl.scenes.describe(name)


@pytest.mark.parametrize("name", bl.scenes.names("transparency"))
def test_transparency_references_do_not_depend_on_the_object_order(ctx, name):
    first = ctx.reference(bl.scenes.get(name), size=SIZE, samples=4, progress=False).color
    for seed in (3, 4):
        scene = bl.scenes.get(name)
        random.Random(seed).shuffle(scene.objects)
        shuffled = ctx.reference(scene, size=SIZE, samples=4, progress=False).color
        np.testing.assert_allclose(shuffled, first, atol=1e-6)


@pytest.mark.parametrize("name", bl.scenes.names("transparency"))
def test_transparency_scenes_show_their_surfaces(ctx, name):
    scene = bl.scenes.get(name)
    frame = ctx.render(scene, size=SIZE)
    translucent = any(obj.material.translucent for obj in scene.objects)
    assert frame.layered == translucent
    if translucent:
        assert (frame.translucent[..., 3] > 0.1).mean() > 0.01 or frame.translucent.max() > 0.1
    else:  # the masked leaves cut holes: some of their quad shows the wall behind
        assert any(obj.material.blend == "mask" for obj in scene.objects)
    for translucency in APPROACHES:
        out = bl.blur(ctx, frame, EXAMPLE, translucency=translucency).color
        assert np.isfinite(out).all()


def test_the_transparency_study_measures_every_approach(ctx):
    from blurlab.studies import transparency

    names, methods = ["moving_glass", "foliage_spin"], [LAYER]
    table = transparency.evaluate(ctx, names, methods, (32, 18), reference_samples=8)
    assert len(table) == len(names) * len(methods) * len(APPROACHES)
    assert np.isfinite(table[["psnr", "flip"]].to_numpy()).all()
    summary = transparency.summary(table)
    assert list(summary["median_per_approach"].index) == list(APPROACHES)
    gains = summary["median_gain_per_scene"]["psnr"]
    assert gains["foliage_spin"] == 0.0  # masked, no translucent layer: every approach alike
    assert gains["moving_glass"] > 0.5  # the pane's own motion, which only layered follows
    from blurlab_bench.transparency import layer_cost

    cost = layer_cost(ctx, "moving_glass", LAYER, (32, 18), runs=2)
    assert cost["layered_ms"] > 0 and cost["ratio"] == cost["layered_ms"] / cost["composite_ms"]


def test_drawn_opaque_scenes_give_their_translucent_surfaces_motion(ctx):
    from blurlab.studies import transparency

    scene = transparency.drawn_opaque_scene("moving_glass")
    assert not scene.translucent
    assert len(scene.objects) == len(bl.scenes.get("moving_glass").objects)
    assert bl.scenes.get("moving_glass").translucent  # the built-in scene is left as it was
    # the still wall moves nowhere (a GPU leaves rounding, 2e-6 px on an H100); drawn opaque,
    # the pane brings its own motion
    moving = np.abs(ctx.render(bl.scenes.get("moving_glass"), SIZE).motion).max()
    drawn = np.abs(ctx.render(scene, SIZE).motion).max()
    assert moving < 1e-3 and drawn > 1.0


def test_the_transparency_benchmark_times_every_cost_scene(ctx):
    import blurlab_bench as bench

    record = bench.run_benchmark(ctx, "transparency", "tiny")
    scenes = record["params"]["cost_scenes"].split(",")
    assert len(scenes) == 2
    times = next(t for t in record["tables"] if t["name"].startswith("time of the method"))
    methods = record["params"]["methods"].split(",")
    assert sorted((row[0], row[1]) for row in times["rows"]) == sorted(
        (scene, method) for scene in scenes for method in methods
    )
    figures = {f["name"]: f["value"] for f in record["figures"]}
    for scene in scenes:
        ratios = [row[4] for row in times["rows"] if row[0] == scene]
        median = figures[f"{scene}: layered / composite time, median over the methods"]
        assert median == pytest.approx(float(np.median(ratios)), rel=1e-4)  # 5 digits kept
        fewest = figures[f"{scene}: layered / composite time, fewest over the methods"]
        assert fewest == pytest.approx(min(ratios), rel=1e-4)
    gbuffers = next(t for t in record["tables"] if t["name"].startswith("the G-buffer with"))
    assert [row[0] for row in gbuffers["rows"]] == scenes
    for _, with_ms, without_ms, layer_ms, drawn_opaque_ms in gbuffers["rows"]:
        assert layer_ms == pytest.approx(with_ms - without_ms, rel=1e-3, abs=1e-3)
        assert drawn_opaque_ms > 0
    # a frame adds its G-buffer to each blur: layered's with the translucent layer and split
    frames = next(t for t in record["tables"] if t["name"].startswith("a frame, G-buffer"))
    gbuffer = {row[0]: row for row in gbuffers["rows"]}
    blurs = {(row[0], row[1]): row for row in times["rows"]}
    assert len(frames["rows"]) == len(times["rows"])
    for scene, method, layered, composite, drawn_opaque, *ratios in frames["rows"]:
        assert composite == pytest.approx(gbuffer[scene][1] + blurs[scene, method][2], rel=1e-3)
        split = blurs[scene, method][8]
        assert layered == pytest.approx(gbuffer[scene][1] + split + blurs[scene, method][3], 1e-3)
        assert drawn_opaque > gbuffer[scene][4]
        assert ratios == pytest.approx([layered / composite, layered / drawn_opaque], rel=1e-3)
    # an unknown cost scene is refused before anything is scored
    with pytest.raises(ValueError, match="no built-in scene 'nowhere'"):
        bench.run_benchmark(ctx, "transparency", "tiny", given={"cost_scenes": "nowhere"})


@pytest.mark.parametrize("name", picks(kind="render"))
def test_rendering_methods_composite_every_sub_frame_themselves(ctx, name):
    frame = ctx.render(glass_and_sparks(), size=SIZE)
    plain = bl.blur(ctx, frame, name).color
    for translucency in APPROACHES:
        np.testing.assert_array_equal(
            bl.blur(ctx, frame, name, translucency=translucency).color, plain
        )


def test_fragment_layout_folds_into_columns_where_one_column_is_too_tall():
    assert fragment_lists.fragment_layout(16, 1080, 1920, 32768) == (16, 1)
    assert fragment_lists.fragment_layout(32, 1080, 1920, 32768) == (16, 2)  # 34560 rows: folded
    assert fragment_lists.fragment_layout(5, 90, 160, 400) == (3, 2)
    with pytest.raises(ValueError, match="do not fit a texture of at most 256"):
        fragment_lists.fragment_layout(64, 90, 160, 256)


def test_a_folded_fragment_layout_gives_the_same_frame(ctx, monkeypatch):
    """Fragments stored in two columns of blocks (as 1080p with 32 fragments a pixel needs)
    give the same G-buffer bits as one column."""
    scene = bl.scenes.smoke_pan()
    size = (64, 36)
    one = ctx.render(scene, size)
    monkeypatch.setattr(fragment_lists, "fragment_layout", lambda k, h, w, most: (-(-k // 2), 2))
    two = ctx.render(scene, size)
    for name in ("color", "opaque_color", "translucent", "translucent_motion", "translucent_depth"):
        np.testing.assert_array_equal(getattr(one, name), getattr(two, name), err_msg=name)


@pytest.mark.filterwarnings("ignore:blurlab. .* expects the G-buffer")
def test_a_still_layer_is_composited_as_the_coverage_gather_leaves_it(ctx):
    """car_behind_window's glass is still: layered skips the layer's blur, which would keep
    every pixel (its early exit), and gives the same bits as blurring it would."""
    from blurlab.methods import layers

    for instant in ("center", "close"):
        frame = ctx.render(bl.scenes.car_behind_window(), size=SIZE, instant=instant)
        assert layers.layer_still(frame)
        layered = bl.blur(ctx, frame, EXAMPLE, translucency="layered")
        assert not any(key.startswith("translucent_") for key in layered.timings)
        gathered = bl.blur(ctx, layers.translucent_frame(ctx, frame), LAYER)
        np.testing.assert_array_equal(gathered.color, frame.translucent)
        unblurred = bl.blur(ctx, frame, EXAMPLE, translucency="unblurred")
        np.testing.assert_array_equal(layered.color, unblurred.color)
    moving = ctx.render(bl.scenes.moving_glass(), size=SIZE)
    assert not layers.layer_still(moving)
