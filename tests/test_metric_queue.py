"""metrics.MetricQueue (docs/spec.md §6.3): GPU metrics issued now and read back together give the
bits of gpu_mse, gpu_mse_ssim and gpu_flip called one at a time, with one wait for the GPU."""

from __future__ import annotations

import pytest
from method_picks import EXAMPLE

import blurlab as bl
from blurlab import _core
from blurlab import metrics as m

SIZE = (160, 90)


@pytest.fixture(scope="module")
def scene_inputs(ctx):
    scene = bl.scenes.teapot_pass()
    frame = ctx.render(scene, SIZE)
    reference = ctx.reference(scene, SIZE, samples=8, progress=False)
    prepared = m.prepare_reference(ctx, reference.texture)
    yield frame, reference, prepared
    prepared.release()


def test_queued_metrics_equal_the_immediate_ones_with_one_wait(ctx, scene_inputs):
    frame, reference, prepared = scene_inputs
    queue = m.MetricQueue(ctx)
    expected, order = [], []
    for k in (4, 8, 16, 20, 40, 8):  # a repeat: the same value twice, from two slots
        result = bl.blur(ctx, frame, EXAMPLE, k=k, timed=False)
        color = result.textures["color"]
        expected += [
            m.gpu_mse_ssim(ctx, prepared, color),
            m.gpu_mse_ssim(ctx, reference.texture, color),
            m.gpu_mse(ctx, color, reference.texture),
            m.gpu_flip(ctx, reference.texture, color),
        ]
        order += [
            queue.mse_ssim(prepared, color),
            queue.mse_ssim(reference.texture, color),
            queue.mse(color, reference.texture),
            queue.flip(reference.texture, color),
        ]
        # Back to the pool before the read: the next blur writes into the same texture, after
        # the queued reductions read it.
        del result, color
    assert order == list(range(24)) and len(queue) == 24
    waits = ctx.waits()
    values = queue.read()
    # One wait for the reductions' sums, one per FLIP partials download.
    assert ctx.waits() - waits == 1 + 6
    assert values == expected
    assert len({v[1] for v in values[::4]}) == 5  # the SSIMs differ with k
    assert len(queue) == 0 and queue.read() == []


def test_an_empty_read_does_not_wait(ctx):
    queue = m.MetricQueue(ctx)
    waits = ctx.waits()
    assert queue.read() == [] and ctx.waits() == waits


def test_bad_queued_metrics_are_refused_and_leave_the_batch_whole(ctx, scene_inputs):
    frame, reference, prepared = scene_inputs
    queue = m.MetricQueue(ctx)
    queue.mse(frame.textures["color"], reference.texture)
    small = ctx.pooled((45, 80, 4))
    with pytest.raises(TypeError, match="PreparedReference"):
        queue.mse_ssim(reference.color, frame.textures["color"])
    with pytest.raises(ValueError, match="unknown SSIM layout"):
        queue.mse_ssim(reference.texture, frame.textures["color"], layout="column3")
    with pytest.raises(ValueError, match="differ in shape"):
        queue.mse(small, reference.texture)
    with pytest.raises(ValueError, match="differ in shape"):
        queue.mse_ssim(prepared, small)
    gone = m.prepare_reference(ctx, reference.texture)
    gone.release()
    with pytest.raises(ValueError, match="after release"):
        queue.mse_ssim(gone, frame.textures["color"])
    ctx.recycle(small)
    assert len(queue) == 1
    assert queue.read() == [m.gpu_mse(ctx, frame.textures["color"], reference.texture)]


def test_batches_read_one_behind_in_order(ctx, scene_inputs):
    # Batches of 2 over 5 evaluations: nothing is read until the second batch is issued, then
    # the first; flush() gives the rest. Every value equals the immediate call's, in order.
    frame, reference, prepared = scene_inputs
    batches = m.MetricBatches(ctx, 2)
    expected, got = [], []
    for i, k in enumerate((4, 8, 16, 20, 40)):
        result = bl.blur(ctx, frame, EXAMPLE, k=k, timed=False)
        color = result.textures["color"]
        expected.append(m.gpu_mse_ssim(ctx, prepared, color))
        ready = batches.add((i, batches.queue.mse_ssim(prepared, color)))
        assert [item[0] for item, _ in ready] == {0: [], 1: [], 2: [], 3: [0, 1], 4: []}[i]
        got += [values[index] for (_, index), values in ready]
        del result, color
    ready = batches.flush()
    assert [item[0] for item, _ in ready] == [2, 3, 4]
    got += [values[index] for (_, index), values in ready]
    assert got == expected
    assert batches.flush() == []
    with pytest.raises(ValueError, match="size must be an integer >= 1"):
        m.MetricBatches(ctx, 0)


def test_a_sealed_queue_takes_no_more_until_read(ctx, scene_inputs):
    frame, reference, prepared = scene_inputs
    queue = m.MetricQueue(ctx)
    queue.mse(frame.textures["color"], reference.texture)
    queue.seal()
    with pytest.raises(RuntimeError, match="read\\(\\) a sealed batch"):
        queue.mse_ssim(prepared, frame.textures["color"])
    assert len(queue.read()) == 1
    queue.mse(frame.textures["color"], reference.texture)  # open again
    assert len(queue.read()) == 1


def test_many_batches_hold_no_more_gl_objects(ctx, scene_inputs):
    # Buffers grow to the largest batch once; fences are deleted as batches are read.
    frame, reference, prepared = scene_inputs
    color = frame.textures["color"]
    batches = m.MetricBatches(ctx, 4)

    def some_batches():
        for _ in range(3):
            for _ in range(4):
                batches.add(batches.queue.mse_ssim(prepared, color))
        batches.flush()

    some_batches()
    before = ctx.live_objects()
    for _ in range(10):
        some_batches()
    assert ctx.live_objects() == before and ctx.gl_errors() == []


def test_a_reduction_no_pass_wrote_is_refused_as_stale(ctx, scene_inputs):
    # A range reserved and never dispatched holds no ticket: what a read-back of partial sums
    # that the passes did not write looks like (docs/spec.md §6.3).
    frame, reference, _ = scene_inputs
    core = _core.ReductionQueue(ctx.native)
    before = ctx.stale_readbacks()
    core.reserve(groups=4, components=1)
    with pytest.raises(bl.StaleReadback, match="ticket"):
        core.read()
    assert core.pending == 0 and ctx.stale_readbacks() == before + 1
    # The queue is whole afterwards, and a batch its passes wrote reads back as ever.
    queue = m.MetricQueue(ctx)
    queue.mse(frame.textures["color"], reference.texture)
    (value,) = queue.read()
    assert value == m.gpu_mse(ctx, frame.textures["color"], reference.texture)
    assert ctx.stale_readbacks() == before + 1


def test_reservations_are_checked(ctx):
    core = _core.ReductionQueue(ctx.native)
    with pytest.raises(ValueError, match="work group"):
        core.reserve(groups=0, components=1)
    with pytest.raises(ValueError, match="component"):
        core.reserve(groups=1, components=0)


def test_tickets_differ_between_reductions(ctx):
    core = _core.ReductionQueue(ctx.native)
    tickets = [core.reserve(groups=1, components=2)[1] for _ in range(5)]
    core.clear()
    assert len(set(tickets)) == 5 and all(t >= 1 and t == int(t) for t in tickets)
