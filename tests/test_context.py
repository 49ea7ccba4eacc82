"""The headless context: device choice, info, errors that say what to install."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import threading

import pytest
from method_picks import pick

import blurlab as bl


def test_info_names_vendor_renderer_version_and_device(ctx):
    info = ctx.info()
    for key in ("vendor", "renderer", "version", "device", "timer", "max_texture_size"):
        assert key in info
    assert info["device"] in ("gpu", "software")
    major, minor = (int(v) for v in info["version"].split()[0].split(".")[:2])
    assert (major, minor) >= (4, 5)
    assert info["timer"] == ("wall_glfinish" if info["device"] == "software" else "gl_time_elapsed")


def test_the_context_asks_to_be_told_of_a_gpu_reset(ctx):
    # Mesa's llvmpipe and NVIDIA's driver both grant it; without it, work after a reset would
    # silently do nothing and read-backs would return stale memory.
    assert ctx.info()["reset_notification"] == "lose_context"
    assert ctx.reset_status() == "none"
    assert ctx.gl_errors() == []
    assert issubclass(bl.ContextLost, bl.GLError)  # code that catches GLError catches it too


# A method whose passes run over tile lists (indirect dispatches), blurred in layers: the run
# whose syncs, waits and fences the variables below change (_synced_run sets its METHOD).
SYNCED_METHOD = pick(role="tile_lists")
SYNCED_RUN = """
import hashlib, json
import blurlab as bl
ctx = bl.Context()
frame = ctx.render(bl.scenes.get("moving_glass"), (48, 27))
before = ctx.waits()
out = bl.blur(ctx, frame, METHOD, translucency="layered", timed=False).color
print(json.dumps({"sync": ctx.info()["sync_passes"], "waits": ctx.waits() - before,
                  "notification": ctx.info()["reset_notification"],
                  "in_flight": ctx.info()["passes_in_flight"], "pacing": ctx.pacing_waits(),
                  "per_fence": ctx.info()["passes_per_fence"],
                  "sha": hashlib.sha256(out.tobytes()).hexdigest()}))
"""


def _in_process(script: str, **environment) -> subprocess.CompletedProcess:
    """`script` run by Python in a process of its own, `environment` added to this one's (the
    context reads these variables when it is made)."""
    return subprocess.run(
        [sys.executable, "-c", script],
        env={**os.environ, **environment},
        capture_output=True,
        text=True,
        timeout=300,
    )


def _synced_run(**environment) -> dict:
    """SYNCED_RUN's figures, run with `environment`."""
    done = _in_process(f"METHOD = {SYNCED_METHOD!r}\n" + SYNCED_RUN, **environment)
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout.splitlines()[-1])


def test_blurlab_sync_passes_waits_after_every_pass_and_changes_no_bit():
    runs = {flag: _synced_run(BLURLAB_SYNC_PASSES=flag) for flag in ("0", "1")}
    assert (runs["0"]["sync"], runs["1"]["sync"]) == ("off", "on")
    assert runs["1"]["sha"] == runs["0"]["sha"]
    # one wait per pass of the layered blur (the layer's split, both blurs, the over)
    assert runs["1"]["waits"] >= runs["0"]["waits"] + 5


def has_software_device() -> bool:
    return any(d["kind"] == "software" for d in bl.Context.devices())


def test_software_device_is_llvmpipe():
    try:
        info = bl.Context("software").info()
    except RuntimeError as error:
        if has_software_device():
            raise
        pytest.skip(f"no software rasterizer here: {error}")
    assert info["device"] == "software"
    assert "llvmpipe" in info["renderer"]
    assert info["timer"] == "wall_glfinish"


def test_devices_lists_kinds():
    devices = bl.Context.devices()
    assert all(d["kind"] in ("gpu", "software") for d in devices)
    assert [d["index"] for d in devices] == list(range(len(devices)))


def test_device_index_picks_that_device():
    devices = bl.Context.devices()
    if not devices:
        pytest.skip("EGL lists no devices here (surfaceless platform only)")
    info = bl.Context(devices[-1]["index"]).info()
    assert info["device_index"] == devices[-1]["index"]
    assert info["device"] == devices[-1]["kind"]


def test_gpu_without_one_says_what_to_install():
    if any(d["kind"] == "gpu" for d in bl.Context.devices()):
        pytest.skip("this machine has a GPU")
    with pytest.raises(RuntimeError, match="NVIDIA driver"):
        bl.Context("gpu")


@pytest.mark.parametrize(
    ("device", "error", "message"),
    [
        ("cuda", ValueError, "must be one of"),
        (1.5, TypeError, "must be one of"),
        (True, TypeError, "must be one of"),
        (999, ValueError, "EGL device 999 does not exist"),
        (-1, ValueError, "EGL device -1 does not exist"),
    ],
)
def test_bad_device_is_rejected(device, error, message):
    with pytest.raises(error, match=message):
        bl.Context(device)


def test_missing_shader_folder_is_reported(tmp_path):
    ctx = bl.Context(shader_dir=tmp_path)
    with pytest.raises(bl.ShaderError, match="not found"):
        ctx.program("util/test_pattern.comp")


def test_context_refuses_other_threads(ctx):
    errors = []

    def use():
        try:
            ctx.empty((4, 4, 4))
        except RuntimeError as e:
            errors.append(str(e))

    worker = threading.Thread(target=use)
    worker.start()
    worker.join()
    assert errors and "thread" in errors[0]
    # The owning thread still works afterwards.
    assert ctx.empty((2, 2)).download().shape == (2, 2)


def test_contexts_can_be_created_and_freed_repeatedly():
    for _ in range(20):
        context = bl.Context()
        texture = context.upload(__import__("numpy").ones((3, 3), "float32"))
        assert texture.download().sum() == 9
        del texture, context


def test_blurlab_reset_notification_0_makes_a_plain_context_with_the_same_images():
    runs = {flag: _synced_run(BLURLAB_RESET_NOTIFICATION=flag) for flag in ("1", "0")}
    assert runs["1"]["notification"] == "lose_context"
    assert runs["0"]["notification"] == "none"
    assert runs["0"]["sha"] == runs["1"]["sha"]


def test_the_passes_in_flight_are_bounded_by_default_and_the_bound_changes_no_bit():
    runs = {flag: _synced_run(BLURLAB_PASSES_IN_FLIGHT=flag) for flag in ("", "0", "1")}
    assert [runs[flag]["in_flight"] for flag in ("", "0", "1")] == ["32", "unbounded", "1"]
    # four fences over the bound's passes: a fence after every pass cost the H100 a quarter
    # of a short filter's time
    assert [runs[flag]["per_fence"] for flag in ("", "0", "1")] == ["8", "none", "1"]
    assert runs["0"]["pacing"] == 0  # no bound, no pacing
    assert runs["1"]["sha"] == runs["0"]["sha"] == runs[""]["sha"]
    # llvmpipe finishes each pass before the next is issued, so no bound waits there, and the
    # waits that read results are the same
    assert runs["1"]["waits"] == runs["0"]["waits"] == runs[""]["waits"]


@pytest.mark.parametrize("value", ["x", "-1", "2.5", "2000000"])
def test_a_bad_blurlab_passes_in_flight_is_refused_in_words(value):
    done = _in_process("import blurlab as bl; bl.Context()", BLURLAB_PASSES_IN_FLIGHT=value)
    assert done.returncode != 0
    allowed = "must be a whole number from 0 (no bound) to 1000000"
    assert f"BLURLAB_PASSES_IN_FLIGHT {allowed}, not '{value}'" in done.stderr
