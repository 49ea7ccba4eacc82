"""GPU-first data (docs/spec.md §1.1): images cross to the host only when a caller reads them.
Every texture transfer is counted by wrapping the calls that make one (Texture.upload,
Texture.download, Texture.download_async, Context.upload); an image transfer is one of a
texture of the frame's size. Reductions read back a few numbers per tile, not an image."""

from __future__ import annotations

import warnings
from collections import Counter
from contextlib import contextmanager

import pytest
from method_picks import pick

import blurlab as bl
from blurlab.core.context import Context
from blurlab.core.gl import Texture
from blurlab.temporal.sequences import ORDERS

SIZE = (64, 36)
# A tile filter with k, and a one-pass gather with samples on both backends.
FILTER = pick(kind="filter", params=("k",))
GATHER = pick(kind="gather", params=("samples",), backends=("compute", "fragment"))


@contextmanager
def counted(monkeypatch, size=SIZE):
    """Counts transfers: Counter of "download"/"upload" for image-sized textures (H, W as
    `size`), "small_download" for the rest."""
    counts: Counter = Counter()
    image = (size[1], size[0])

    def kind(shape, what: str) -> str:
        return what if tuple(shape[:2]) == image else f"small_{what}"

    def wrap(cls, name: str, what: str, shape_of):
        original = getattr(cls, name)

        def wrapped(self, *args, **kwargs):
            counts[kind(shape_of(self, args), what)] += 1
            return original(self, *args, **kwargs)

        monkeypatch.setattr(cls, name, wrapped)

    wrap(Texture, "download", "download", lambda self, args: self.shape)
    wrap(Texture, "download_async", "download", lambda self, args: self.shape)
    wrap(Texture, "upload", "upload", lambda self, args: args[0].shape)
    wrap(Context, "upload", "upload", lambda self, args: args[0].shape)
    yield counts


def test_render_downloads_nothing_until_a_field_is_read(ctx, monkeypatch):
    scene = bl.scenes.teapot_pass()
    with counted(monkeypatch) as counts:
        frame = ctx.render(scene, SIZE)
        assert frame.on_host == ()
        assert sum(counts.values()) == 0
        _ = frame.depth_range  # a GPU reduction: a few numbers per tile
        _ = frame.longest_motion
        assert counts["download"] == 0 and counts["upload"] == 0
        color = frame.color
        assert counts["download"] == 1 and frame.on_host == ("color",)
        assert frame.color is color and counts["download"] == 1  # read once, kept


def from_arrays(rendered: bl.Frame) -> bl.Frame:
    """A frame built from the rendered frame's arrays (its layers too): no textures, no camera."""
    return bl.Frame(
        rendered.color,
        rendered.depth,
        rendered.motion,
        rendered.object_id,
        shutter=rendered.shutter,
        time=rendered.time,
        opaque_color=rendered.opaque_color,
        translucent=rendered.translucent,
        translucent_motion=rendered.translucent_motion,
        translucent_depth=rendered.translucent_depth,
    )


def test_translucent_render_downloads_nothing_until_read(ctx, monkeypatch):
    with counted(monkeypatch) as counts:
        frame = ctx.render(bl.scenes.get("moving_glass"), SIZE)
        assert frame.layered
        for translucency in ("composite_motion", "layered", "unblurred"):
            bl.blur(ctx, frame, FILTER, translucency=translucency)
        assert counts["download"] == 0 and counts["upload"] == 0
        _ = frame.translucent_depth  # one texture holds the layer motion and depth
        assert counts["download"] == 1 and frame.translucent_motion.shape == SIZE[::-1] + (2,)
        assert counts["download"] == 1


def test_gpu_statistics_match_numpy(ctx):
    """depth_range, longest_motion and layer_moves from the GPU equal the NumPy ones."""
    for name in ("teapot_pass", "fan", "moving_glass"):
        rendered = ctx.render(bl.scenes.get(name), (67, 37))  # odd: partial tiles
        on_gpu = (rendered.depth_range, rendered.longest_motion, rendered.layer_moves)
        arrays = from_arrays(rendered)
        assert on_gpu == (arrays.depth_range, arrays.longest_motion, arrays.layer_moves), name


@pytest.mark.parametrize("order", ORDERS)
@pytest.mark.parametrize("method", [None, FILTER])
def test_sequence_frames_stay_on_the_gpu(ctx, monkeypatch, order, method):
    if method is None and order in ("taa_then_blur", "blur_in_history"):
        pytest.skip("these orders need a method")
    seq = bl.sequence(ctx, bl.scenes.fan(), SIZE, frames=4, reference_samples=8)
    with counted(monkeypatch) as counts:
        run = seq.run(method, order, metrics=("psnr", "ssim", "temporal_instability"))
    assert counts["download"] == 0 and counts["upload"] == 0, counts
    assert len(run.scores["psnr"]) == 4
    with counted(monkeypatch) as counts:
        _ = run.color  # read when asked for: one download per frame
    assert counts["download"] == 4


def test_sweep_evaluations_transfer_no_image(ctx, monkeypatch):
    """After each scene's render and reference, a sweep's evaluations move no image."""
    counts = []
    for k in ([4], [4, 8, 12]):
        with counted(monkeypatch) as each:
            grid = {FILTER: {"k": k}, GATHER: {"samples": k}}
            bl.sweep(ctx, ["fan"], grid, size=SIZE, progress=False, repeats=1)
        counts.append(each)
    one, three = counts
    assert three["download"] == one["download"] and three["upload"] == one["upload"], (one, three)


def test_setting_an_array_replaces_the_frames_data(ctx):
    """A rendered frame given a new array reads its others first and drops its textures and
    plans, so the next blur uploads what was set."""
    frame = ctx.render(bl.scenes.fan(), SIZE)
    before = bl.blur(ctx, frame, GATHER).color
    frame.motion = frame.motion * 0.0
    assert frame.textures == {} and set(frame.on_host) >= {"color", "depth", "motion"}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        still = bl.blur(ctx, frame, GATHER).color
    assert (still != before).any()
    assert (still[..., :3] == frame.color[..., :3]).all()  # no motion: the frame as it is


def test_the_statistics_reduce_once_per_frame(ctx, monkeypatch):
    """depth_range and longest_motion share one GPU reduction: one small read-back pair."""
    frame = ctx.render(bl.scenes.fan(), SIZE)
    with counted(monkeypatch) as counts:
        _ = frame.depth_range, frame.longest_motion
    assert counts["small_download"] == 2 and counts["download"] == 0


@pytest.mark.parametrize("translucency", ["composite_motion", "layered", "unblurred"])
def test_a_translucent_frame_from_arrays_blurs_as_the_rendered_one(ctx, translucency):
    """The layer frames take the frame's textures, uploaded once where it was built from arrays:
    the same bits as the rendered frame's."""
    rendered = ctx.render(bl.scenes.get("moving_glass"), SIZE)
    arrays = from_arrays(rendered)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # a frame from arrays has no camera to check instants by
        expected = bl.blur(ctx, rendered, FILTER, translucency=translucency)
        got = bl.blur(ctx, arrays, FILTER, translucency=translucency)
    assert (got.color == expected.color).all()


def test_transparency_evaluations_download_only_the_pictured_images(ctx, monkeypatch):
    """The four-approach table scores every (method, approach) on the GPU: the only images
    read back are the pictured method's, one per approach, and the reference for the picture;
    a reference made before is reused."""
    from blurlab.studies import transparency

    methods = [FILTER, GATHER]
    reference = ctx.reference(bl.scenes.get("moving_glass"), SIZE, samples=8, antialias=True)
    shown: dict = {}
    monkeypatch.setattr(Context, "reference", lambda *a, **k: pytest.fail("made it again"))
    with counted(monkeypatch) as counts:
        table = transparency.evaluate(
            ctx, ["moving_glass"], methods, SIZE, 8, shown, {"moving_glass": reference}
        )
    assert len(table) == len(methods) * len(transparency.APPROACHES)
    assert counts["download"] == len(transparency.APPROACHES) + 1, counts
    assert counts["upload"] == 0, counts
    assert table["psnr"].between(5, 80).all() and table["flip"].between(0, 1).all()
    pictured, _, images = shown["moving_glass"]
    row = table[(table["method"] == pictured) & (table["translucency"] == "layered")]
    assert row["psnr"].iloc[0] == pytest.approx(
        bl.metrics.psnr(images["layered"], reference.color), abs=1e-4
    )
