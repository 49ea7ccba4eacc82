"""Resources: long loops of render + blur + readback and of context creation leave GL object
counts and memory flat; a context refuses threads that do not own it."""

from __future__ import annotations

import gc
import os
import threading
import warnings

import numpy as np
import pytest
from method_picks import EXAMPLE, pick

import blurlab as bl

SIZE = (16, 12)
# A plain gather, for the calls from another thread.
GATHER = pick(kind="gather", params=("taps",))


def rss_mib() -> float:
    """Resident memory of this process (Linux), MiB: llvmpipe's GL memory is process memory."""
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE") / 2**20


def footprint(ctx) -> dict:
    gc.collect()
    return {"objects": ctx.live_objects(), "rss": rss_mib(), "vram": ctx.memory()}


def test_thousand_render_blur_readback_cycles_stay_flat(ctx):
    scene = bl.scenes.fan()
    names = [n for n in bl.methods() if bl.method(n).kind != "render"]  # arrays only

    def cycle(i):
        name = names[i % len(names)]
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            frame = ctx.render(scene, SIZE, instant=bl.method_instant(name, {}))
            out = bl.blur(ctx, frame, name)
        color = out.color
        assert color.shape == (SIZE[1], SIZE[0], 4)
        pending = out.textures["color"].download_async()
        assert pending.result().shape == color.shape

    for i in range(100):  # warm-up: pools, programs, driver caches fill once
        cycle(i)
    before = footprint(ctx)
    for i in range(1000):
        cycle(i)
    after = footprint(ctx)
    print(
        f"\n1000 cycles: live objects {before['objects']} -> {after['objects']}, "
        f"RSS {before['rss']:.1f} -> {after['rss']:.1f} MiB, VRAM {before['vram']} -> "
        f"{after['vram']}"
    )
    assert after["objects"] == before["objects"]
    assert after["rss"] - before["rss"] < 8.0
    # Free video memory is the whole GPU's: other processes on it (pytest-xdist's workers, a
    # soak beside the tests) move it, so it is checked only where this process runs alone.
    if before["vram"] and not os.environ.get("PYTEST_XDIST_WORKER"):
        assert before["vram"]["available"] - after["vram"]["available"] < 8 * 1024
    assert ctx.gl_errors() == []


def test_hundred_contexts_come_and_go(ctx):
    def one():
        context = bl.Context()
        texture = context.upload(np.ones((4, 4, 4), np.float32))
        frame = bl.Frame(
            color=np.ones((8, 8, 4)), depth=np.ones((8, 8)), motion=np.full((8, 8, 2), 3.0)
        )
        out = bl.blur(context, frame, EXAMPLE, k=4, samples=5)
        assert np.isfinite(out.color).all() and texture.download().sum() == 64
        assert context.gl_errors() == []
        live = context.live_objects()
        del out, texture, frame
        gc.collect()
        return context, live

    for _ in range(10):
        one()
    gc.collect()
    before = rss_mib()
    for _ in range(100):
        context, live = one()
        assert sum(live.values()) > 0
        del context
    gc.collect()
    after = rss_mib()
    print(f"\n100 contexts: RSS {before:.1f} -> {after:.1f} MiB")
    assert after - before < 16.0
    assert ctx.gl_errors() == []  # the session's context is untouched


def test_freed_objects_return_the_live_count(ctx):
    before = ctx.live_objects()
    textures = [ctx.empty((4, 4, 4)) for _ in range(10)]
    assert ctx.live_objects()["texture"] == before.get("texture", 0) + 10
    del textures
    gc.collect()
    assert ctx.live_objects() == before


def test_objects_freed_on_another_thread_are_released_by_the_owner(ctx):
    """Python may drop the last reference on any thread: the GL object is then released at the
    owner's next call instead of leaking (or taking the context from its thread)."""
    gc.collect()
    before = ctx.live_objects()
    box = [ctx.empty((4, 4, 4)) for _ in range(3)]
    assert ctx.live_objects()["texture"] == before.get("texture", 0) + 3

    def drop():
        box.clear()
        gc.collect()

    thread = threading.Thread(target=drop)
    thread.start()
    thread.join()
    assert not box
    ctx.finish()  # the owner's next call releases them
    assert ctx.live_objects() == before
    assert ctx.gl_errors() == []


@pytest.mark.parametrize(
    "call",
    [
        "upload",
        "empty",
        "download",
        "render",
        "blur",
        "reference",
        "program",
        "timer",
        "finish",
        "gl_errors",
        "moderngl",
    ],
)
def test_other_threads_get_a_clear_error(ctx, test_shader, call):
    texture = ctx.upload(np.ones((4, 4), np.float32))
    frame = bl.Frame(color=np.ones((8, 8, 4)), depth=np.ones((8, 8)), motion=np.ones((8, 8, 2)))
    calls = {
        "upload": lambda: ctx.upload(np.ones((4, 4), np.float32)),
        "empty": lambda: ctx.empty((4, 4)),
        "download": texture.download,
        "render": lambda: ctx.render(bl.scenes.fan(), (8, 8)),
        "blur": lambda: bl.blur(ctx, frame, GATHER),
        "reference": lambda: ctx.reference(bl.scenes.fan(), (8, 8), samples=2),
        "program": lambda: ctx.program("util/test_pattern.comp"),
        "timer": lambda: ctx.timer().__enter__(),
        "finish": ctx.finish,
        "gl_errors": ctx.gl_errors,
        "moderngl": ctx.moderngl,
    }
    gc.collect()  # garbage of earlier tests must not be counted as freed by this one
    before = ctx.live_objects()
    errors = []

    def worker():
        try:
            calls[call]()
        except RuntimeError as error:
            errors.append(str(error))

    thread = threading.Thread(target=worker)
    thread.start()
    thread.join()
    assert errors and "thread" in errors[0], errors
    # The owner's state is intact: no GL error, nothing leaked (a spare texture the call took
    # from the context's pool may have been freed), and it still works.
    gc.collect()
    assert ctx.gl_errors() == []
    after = ctx.live_objects()
    assert all(after.get(kind, 0) <= count for kind, count in before.items()), (before, after)
    assert set(after) <= set(before)
    assert texture.download().sum() == 16
    assert np.isfinite(bl.blur(ctx, frame, GATHER).color).all()
