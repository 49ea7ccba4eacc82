"""Captures from other renderers (docs/spec.md §16): EXR colour, depth and motion in each
documented convention become a bl.Frame that every post-process method accepts."""

from __future__ import annotations

import math
import subprocess
import sys
import textwrap

import numpy as np
import pytest
from method_picks import picks

import blurlab as bl
from blurlab.io import capture

SIZE = (160, 90)
# The tile filters that read what a capture holds (colour, depth, one motion: their twins'
# inputs) at the centre of the shutter, the instant of the frames below. (Gathers are not held
# to it: engine_unity, for one, differs by more than 1e-3 on about 1 % of the pixels here, from
# the capture's small differences in motion and depth.)
CAPTURE_METHODS = [
    name
    for name in picks(kind="filter", twin=True)
    if set(bl.method(name).twin_inputs) <= {"color", "depth", "motion"}
    and bl.method_instant(name) == "center"
]


@pytest.fixture(scope="module")
def rendered(ctx):
    return ctx.render(bl.scenes.get("teapot_pass"), SIZE)


def test_uv_capture_of_our_own_gbuffer_round_trips(ctx, rendered, tmp_path):
    """blurlab's G-buffer written as a Unity-style capture (UV per frame, half-frame shutter,
    hardware depth) and read back gives the same frame: motion within 1e-3 px, depth within
    1e-4 relative."""
    camera = bl.scenes.get("teapot_pass").camera
    uv = capture.motion_from_blurlab(rendered.motion, "uv", shutter_fraction=0.5)
    hardware = capture.depth_from_linear(rendered.depth, "hardware", camera.near, camera.far)
    layers = np.concatenate([rendered.color, hardware[..., None], uv], axis=2)
    names = ["R", "G", "B", "A", "depth.Z", "motion.R", "motion.G"]
    path = bl.io.write(tmp_path / "capture.exr", layers.astype(np.float32), channel_names=names)
    frame = bl.Frame.from_exr(
        path,
        convention="uv",
        shutter_fraction=0.5,
        depth_encoding="hardware",
        near=camera.near,
        far=camera.far,
    )
    assert np.abs(frame.motion - rendered.motion).max() <= 1e-3
    drawn = np.isfinite(rendered.depth)
    assert np.array_equal(np.isfinite(frame.depth), drawn)
    relative = np.abs(frame.depth[drawn] / rendered.depth[drawn] - 1)
    assert relative.max() <= 1e-4
    assert np.array_equal(frame.color, rendered.color)
    assert np.abs(rendered.motion).max() > 5  # pixels really move
    # Every such filter takes the imported frame and gives what the original gives.
    for name in CAPTURE_METHODS:
        a = bl.blur(ctx, frame, name).color
        b = bl.blur(ctx, rendered, name).color
        assert np.isfinite(a).all()
        assert np.mean(np.abs(a - b) <= 1e-3) >= 0.999, name


@pytest.mark.parametrize(
    "convention, stored, expected",
    [
        ("blurlab", [3.0, -2.0], [3.0, -2.0]),
        # Blender's vectors point back in time, y up: M = -(s/2)(a + c), +(s/2)(b + d).
        ("blender", [4.0, 2.0, 6.0, 2.0], [-2.5, 1.0]),
        ("uv", [0.1, 0.1], [0.5 * 0.1 * 40, -0.5 * 0.1 * 20]),
        ("ndc", [0.1, 0.1], [0.5 * 0.1 * 20, -0.5 * 0.1 * 10]),
        ("unity", [0.1, 0.1], [0.5 * 0.1 * 40, -0.5 * 0.1 * 20]),
        # Unreal: E = 0.2495 V + 0.5 per channel, V in NDC units per frame, +y up.
        ("unreal", [0.5 + 0.2495 * 0.1, 0.5 - 0.2495 * 0.2], [0.5 * 0.1 * 20, 0.5 * 0.2 * 10]),
    ],
)
def test_each_motion_convention_against_hand_values(convention, stored, expected):
    image = np.tile(np.asarray(stored, np.float32), (20, 40, 1))  # W = 40, H = 20
    m = capture.motion_to_blurlab(image, convention, shutter_fraction=0.5)
    scale = 1.0 if convention == "blurlab" else 1.0  # expected already holds s = 0.5 where due
    want = np.asarray(expected) * (0.5 if convention == "blurlab" else 1.0) * scale
    assert np.allclose(m[0, 0], want)
    back = capture.motion_from_blurlab(m, convention, shutter_fraction=0.5)
    assert np.allclose(capture.motion_to_blurlab(back, convention, 0.5), m)


def test_hardware_depth_against_hand_values():
    n, f = 1.0, 10.0
    d = 10 / 9 * (1 - 1 / 2)  # z = 2: d = f/(f-n) (1 - n/z)
    assert capture.depth_to_linear([d], "hardware", n, f)[0] == pytest.approx(2.0, rel=1e-6)
    assert capture.depth_to_linear([1 - d], "hardware", n, f, reversed_z=True)[0] == pytest.approx(
        2.0, rel=1e-6
    )
    assert capture.depth_to_linear([0.5], "hardware", n, math.inf)[0] == pytest.approx(2.0)
    assert capture.depth_to_linear([1.0], "hardware", n, f)[0] == math.inf  # the far plane: nothing
    assert capture.depth_to_linear([0.0], "hardware", n, f, reversed_z=True)[0] == math.inf
    assert capture.depth_to_linear([0.0, -1.0, np.nan, 3.0])[:3].tolist() == [math.inf] * 3
    z = np.array([0.5, 1.0, 7.0, 99.0])
    for far in (100.0, math.inf):
        for rev in (False, True):
            d = capture.depth_from_linear(z, "hardware", 0.5, far, rev)
            assert np.allclose(capture.depth_to_linear(d, "hardware", 0.5, far, rev), z, rtol=1e-4)


def test_blender_multilayer_names_are_found(tmp_path):
    h, w = 6, 8
    rng = np.random.default_rng(1)
    color = rng.random((h, w, 4), dtype=np.float32)
    depth = rng.uniform(1, 5, (h, w, 1)).astype(np.float32)
    vector = rng.normal(size=(h, w, 4)).astype(np.float32)
    names = [f"ViewLayer.Combined.{c}" for c in "RGBA"]
    names += ["ViewLayer.Depth.Z"] + [f"ViewLayer.Vector.{c}" for c in "XYZW"]
    path = bl.io.write(
        tmp_path / "render.exr", np.concatenate([color, depth, vector], axis=2), names
    )
    frame = bl.Frame.from_exr(path, convention="blender", shutter_fraction=1.0)
    assert np.array_equal(frame.color, color)
    assert np.array_equal(frame.depth, depth[..., 0])
    expected = 0.5 * (vector[..., :2] + vector[..., 2:]) * [-1, 1]
    assert np.allclose(frame.motion, expected, atol=1e-6)


def test_a_multi_part_exr_is_read_whole(tmp_path):
    """Blender 5 writes each pass of a multi-layer EXR as its own part: all parts of the first
    one's size are read, channels in file order."""
    import OpenImageIO as oiio  # noqa: PLC0415 (blurlab.io's reader, a dependency)

    h, w = 4, 6
    parts = {
        ("ViewLayer.Combined.R", "ViewLayer.Combined.G", "ViewLayer.Combined.B"): 3,
        ("ViewLayer.Depth.Z",): 1,
        ("ViewLayer.Vector.X", "ViewLayer.Vector.Y", "ViewLayer.Vector.Z", "ViewLayer.Vector.W"): 4,
    }
    rng = np.random.default_rng(2)
    specs, data = [], []
    for names, count in parts.items():
        spec = oiio.ImageSpec(w, h, count, oiio.FLOAT)
        spec.channelnames = names
        specs.append(spec)
        data.append(rng.random((h, w, count), dtype=np.float32))
    path = tmp_path / "parts.exr"
    out = oiio.ImageOutput.create(str(path))
    assert out.open(str(path), specs)
    for k, (spec, pixels) in enumerate(zip(specs, data, strict=True)):
        if k:
            assert out.open(str(path), spec, "AppendSubimage")
        assert out.write_image(pixels)
    out.close()
    names, pixels = bl.io.read_channels(path)
    assert names == [n for group in parts for n in group]
    assert np.array_equal(pixels, np.concatenate(data, axis=2))
    frame = bl.Frame.from_exr(path, convention="blender")
    assert np.array_equal(frame.depth, data[1][..., 0])


def test_three_separate_files(tmp_path, rendered):
    color = bl.io.write(tmp_path / "color.exr", rendered.color)
    depth = bl.io.write(tmp_path / "depth.exr", capture.depth_from_linear(rendered.depth))
    motion = bl.io.write(tmp_path / "motion.exr", rendered.motion)
    frame = bl.Frame.from_exr(color=color, depth=depth, motion=motion)
    assert np.array_equal(frame.motion, rendered.motion)
    assert np.array_equal(frame.depth, rendered.depth)


def test_bad_captures_say_what_is_wrong(tmp_path, rendered):
    color = bl.io.write(tmp_path / "color.exr", rendered.color)
    small = bl.io.write(tmp_path / "small.exr", np.zeros((4, 4, 2), np.float32))
    with pytest.raises(ValueError, match="convention must be one of"):
        bl.Frame.from_exr(color=color, depth=color, motion=color, convention="maya")
    with pytest.raises(ValueError, match="shutter_fraction"):
        bl.Frame.from_exr(color=color, depth=color, motion=color, shutter_fraction=2)
    with pytest.raises(ValueError, match="differ in size"):
        bl.Frame.from_exr(color=color, depth=color, motion=small)
    with pytest.raises(ValueError, match="needs near and far"):
        bl.Frame.from_exr(color=color, depth=color, motion=color, depth_encoding="hardware")
    with pytest.raises(ValueError, match="no depth layer among .* 1 channel; its channels are"):
        bl.Frame.from_exr(color)
    with pytest.raises(ValueError, match="no motion layer named 'speed'"):
        bl.Frame.from_exr(color, depth="R", motion="speed")
    with pytest.raises(ValueError, match="three EXR paths"):
        bl.Frame.from_exr(color=color)
    with pytest.raises(FileNotFoundError):
        bl.Frame.from_exr(tmp_path / "absent.exr")
    broken = tmp_path / "broken.exr"
    broken.write_bytes(color.read_bytes()[:300])
    with pytest.raises(OSError, match="broken.exr"):
        bl.Frame.from_exr(broken)


def test_mutated_exr_files_never_crash(tmp_path, rendered):
    """1000 mutated EXRs through the reader in a child process (a crash of the image library
    would show as a signal, not take the test run down): each is read or refused with an
    OSError or ValueError; none takes over 5 s."""
    names = ["R", "G", "B", "A", "depth.Z", "motion.X", "motion.Y"]
    data = np.concatenate(
        [rendered.color[:24, :32], rendered.depth[:24, :32, None], rendered.motion[:24, :32]],
        axis=2,
    )
    base = bl.io.write(tmp_path / "base.exr", np.nan_to_num(data, posinf=0.0), names)
    script = textwrap.dedent(
        f"""
        import random, time, sys
        from pathlib import Path
        import blurlab as bl
        rng = random.Random(7)
        base = Path({str(base)!r}).read_bytes()
        counts = {{"read": 0, "refused": 0}}
        slowest = 0.0
        for k in range(1000):
            data = bytearray(base)
            if rng.random() < 0.2:
                data = data[: rng.randrange(len(data))]
            else:
                for _ in range(rng.randint(1, 8)):
                    data[rng.randrange(len(data))] = rng.randrange(256)
            path = Path({str(tmp_path)!r}) / "m.exr"
            path.write_bytes(bytes(data))
            start = time.perf_counter()
            try:
                bl.Frame.from_exr(path)
                counts["read"] += 1
            except (OSError, ValueError):
                counts["refused"] += 1
            slowest = max(slowest, time.perf_counter() - start)
        print(counts["read"], counts["refused"], round(slowest, 3))
        """
    )
    result = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, timeout=600
    )
    assert result.returncode == 0, result.stderr[-2000:]
    read, refused, slowest = result.stdout.split()
    print(f"exr fuzz: {read} read, {refused} refused, slowest {slowest} s")
    assert int(read) + int(refused) == 1000
    assert float(slowest) < 5.0


# Engine captures (docs/spec.md §16.5): each test writes a file the way the engine's published
# convention says it stores motion, from a motion field known in blurlab's terms (pixels per
# frame, +y down), and checks that the loaded motion is that field within the file's precision.
ENGINE_SIZE = (64, 36)  # W, H


def _known_motion_per_frame(w: int, h: int) -> np.ndarray:
    """(H, W, 2) pixel motion from the previous frame to this one, +y down: a disc turning
    0.2 rad per frame about the image centre, on a background translating (-5, +3) px (down
    the screen), both with motion along y."""
    y, x = np.mgrid[0:h, 0:w] + 0.5
    cx, cy = w / 2, h / 2
    angle = 0.2
    # Where each point was a frame ago: turned back by the angle about the centre.
    px = cx + np.cos(angle) * (x - cx) + np.sin(angle) * (y - cy)
    py = cy - np.sin(angle) * (x - cx) + np.cos(angle) * (y - cy)
    turning = np.stack([x - px, y - py], axis=-1)
    disc = (x - cx) ** 2 + (y - cy) ** 2 < (0.4 * h) ** 2
    return np.where(disc[..., None], turning, [-5.0, 3.0])


def _half_ulp_below_one(values: np.ndarray) -> np.ndarray:
    """Half of float16's spacing at each |value| < 1 (2^-11 relative; the subnormal floor
    2^-24): the most a round to float16 moves it."""
    exponent = np.floor(np.log2(np.maximum(np.abs(values), 2.0**-14)))
    return 0.5 * 2.0 ** (exponent - 10)


def _engine_capture(tmp_path, name, motion_channels, motion_names):
    """A multi-layer EXR of colour, linear depth and the engine's motion channels, all
    float16 (what the engines' RGHalf and RGBA16F targets hold)."""
    h, w = motion_channels.shape[:2]
    rng = np.random.default_rng(5)
    color = rng.random((h, w, 4))
    depth = rng.uniform(1, 50, (h, w, 1))
    layers = np.concatenate([color, depth, motion_channels], axis=2).astype(np.float16)
    names = [f"rgba.{c}" for c in "RGBA"] + ["depth.Z"] + motion_names
    return bl.io.write(tmp_path / name, layers, channel_names=names)


def test_unity_motion_vectors(tmp_path):
    """Unity's motion-vector texture: RGHalf, current - previous screen UV per frame, +v up
    (UV (0, 0) is the bottom-left). Read from a layer named MotionVectors, with a half-frame
    shutter: the motion is the known field times 0.5, within float16 rounding."""
    w, h = ENGINE_SIZE
    per_frame = _known_motion_per_frame(w, h)
    uv_delta = per_frame / [w, h] * [1.0, -1.0]  # v grows upwards in Unity's UV
    stored = uv_delta.astype(np.float16)
    assert (stored[0, 0] < 0).all()  # the background moves left and down: both UV deltas < 0
    path = _engine_capture(tmp_path, "unity.exr", stored, ["MotionVectors.R", "MotionVectors.G"])
    frame = bl.Frame.from_exr(path, convention="unity", shutter_fraction=0.5)
    bound = 0.5 * _half_ulp_below_one(uv_delta) * [w, h] + 1e-6
    assert (np.abs(frame.motion - 0.5 * per_frame) <= bound).all()
    assert np.abs(frame.motion - 0.5 * per_frame).max() > 0  # the file really is float16
    assert frame.motion[0, 0, 1] == pytest.approx(1.5, abs=1e-3)  # down the screen: +y
    assert frame.motion[0, 0, 0] == pytest.approx(-2.5, abs=1e-3)


def _unreal_encode(per_frame, w, h, encoding):
    """What an Unreal velocity target holds for `per_frame` pixel motion (+y down): V in NDC
    units (+y up), optionally sqrt-compressed, scaled and biased into [0, 1], rounded to the
    target's 16-bit unorm, then written to the EXR as float16. Also the largest error that
    rounding can put on V."""
    v = per_frame * [2 / w, -2 / h]
    d = np.sign(v) * np.sqrt(2 * np.abs(v)) if encoding.sqrt else v
    unorm = np.round((d * encoding.scale + encoding.bias) * 65535) / 65535
    stored = unorm.astype(np.float16)
    error_d = (0.5 / 65535 + _half_ulp_below_one(unorm)) / encoding.scale
    # V = D |D| / 2 under sqrt compression moves by at most (|D| + dD) dD when D moves by dD.
    error_v = (np.abs(d) + error_d) * error_d if encoding.sqrt else error_d
    return stored, error_v


@pytest.mark.parametrize("sqrt", [False, True], ids=["linear", "sqrt"])
def test_unreal_velocity_buffer(tmp_path, sqrt):
    """Unreal's velocity G-buffer: V = current - previous NDC position per frame (+y up),
    E = 0.2495 D + 0.5 in a 16-bit unorm target (D = V, or sign(V) sqrt(2|V|) compressed),
    written to the EXR as float16; pixels the engine wrote no velocity for hold (0, 0)
    (here a band of static background). Read with a half-frame shutter, the moving pixels
    have the known motion times 0.5 within the rounding; the marked ones get 0 with a warning
    that counts them, or `camera_motion` where given."""
    w, h = ENGINE_SIZE
    encoding = capture.UnrealVelocity(sqrt=sqrt)
    per_frame = _known_motion_per_frame(w, h)
    stored, error_v = _unreal_encode(per_frame, w, h, encoding)
    static = np.zeros((h, w), bool)
    static[:, -8:] = True  # the engine clears its target to 0 and writes only what moves
    stored[static] = 0
    # The zero mark never collides with a velocity in range: V = -2 is stored above 0.
    assert -2.0 * encoding.scale + encoding.bias > 0
    path = _engine_capture(tmp_path, "unreal.exr", stored, ["Velocity.R", "Velocity.G"])
    read = dict(convention="unreal", shutter_fraction=0.5, velocity_encoding=encoding)
    with pytest.warns(UserWarning, match=f"{static.sum()} pixels .* are \\(0, 0\\)"):
        frame = bl.Frame.from_exr(path, **read)
    bound = 0.5 * error_v * [w / 2, h / 2] + 1e-6
    moving = ~static
    error = np.abs(frame.motion - 0.5 * per_frame)
    assert (error[moving] <= bound[moving]).all()
    assert error[moving].max() > 0  # the rounding is really there
    assert (frame.motion[static] == 0).all()
    assert frame.motion[0, 0, 1] == pytest.approx(1.5, abs=0.01)  # down the screen: +y
    camera = np.broadcast_to(np.float32([0.25, -0.75]), (h, w, 2))
    with_camera = bl.Frame.from_exr(path, camera_motion=camera, **read)
    assert np.array_equal(with_camera.motion[static], camera[static])
    assert np.array_equal(with_camera.motion[moving], frame.motion[moving])
    # bl.capture writes the same encoding (before the target's rounding).
    encoded = capture.motion_from_blurlab(
        0.5 * per_frame, "unreal", 0.5, velocity_encoding=encoding
    )
    back = capture.motion_to_blurlab(encoded, "unreal", 0.5, velocity_encoding=encoding)
    assert np.abs(back - 0.5 * per_frame).max() <= 1e-4


def test_unreal_encodings_against_hand_values():
    one = np.ones((20, 40, 2))  # W = 40, H = 20
    # D = 0.4 under sqrt compression is V = 0.4^2 / 2 = 0.08 NDC units: 1.6 px of 40.
    e = 0.5 + 0.2495 * 0.4
    m = capture.motion_to_blurlab(
        one * e, "unreal", velocity_encoding=capture.UnrealVelocity(sqrt=True)
    )
    assert np.allclose(m[0, 0], [0.08 * 20, -0.08 * 10], atol=1e-5)
    # scale and bias are parameters: the 16-bit code just below 0.5 as a still pixel's E.
    still = capture.UnrealVelocity(bias=32767 / 65535)
    m = capture.motion_to_blurlab(one * (32767 / 65535), "unreal", velocity_encoding=still)
    assert (m == 0).all()
    assert capture.motion_to_blurlab(one * 0.5, "unreal")[0, 0] == pytest.approx([0.0, 0.0])
    with pytest.warns(UserWarning, match="800 pixels"):
        assert (capture.motion_to_blurlab(one * 0, "unreal") == 0).all()


def test_bad_engine_captures_say_what_is_wrong(tmp_path):
    w, h = ENGINE_SIZE
    half = np.full((h, w, 2), 0.5, np.float16)
    path = _engine_capture(tmp_path, "ok.exr", half, ["Velocity.R", "Velocity.G"])
    with pytest.raises(ValueError, match="go with convention='unreal', not 'unity'"):
        bl.Frame.from_exr(path, convention="unity", velocity_encoding=capture.UnrealVelocity())
    with pytest.raises(ValueError, match="go with convention='unreal'"):
        bl.Frame.from_exr(path, convention="uv", camera_motion=np.zeros((h, w, 2)))
    with pytest.raises(ValueError, match=r"camera_motion must have shape \(36, 64, 2\)"):
        bl.Frame.from_exr(path, convention="unreal", camera_motion=np.zeros((h, w)))
    with pytest.raises(ValueError, match="must be a blurlab.io.capture.UnrealVelocity"):
        bl.Frame.from_exr(path, convention="unreal", velocity_encoding={"sqrt": True})
    with pytest.raises(ValueError, match=r"scale must be in \(0, 0.5\]"):
        capture.UnrealVelocity(scale=0.0)
    with pytest.raises(ValueError, match=r"bias must be in \(0, 1\)"):
        capture.UnrealVelocity(bias=1.0)
    with pytest.raises(ValueError, match="sqrt must be True or False"):
        capture.UnrealVelocity(sqrt="yes")
    with pytest.raises(ValueError, match="convention must be one of .*'unity', 'unreal'"):
        bl.Frame.from_exr(path, convention="unreal5")
    # Motion channels under no layer name the reader knows, or not two of them in the layer.
    odd = _engine_capture(tmp_path, "odd.exr", half, ["speed.R", "speed.G"])
    with pytest.raises(ValueError, match="no motion layer among .*'Velocity'.*; its channels"):
        bl.Frame.from_exr(odd, convention="unreal")
    three = np.full((h, w, 3), 0.5, np.float16)
    names = ["Velocity.P", "Velocity.Q", "Velocity.S"]
    odd = _engine_capture(tmp_path, "three.exr", three, names)
    with pytest.raises(ValueError, match="no motion layer named 'Velocity' with 2 channels"):
        bl.Frame.from_exr(odd, convention="unreal", motion="Velocity")
    one = bl.io.write(tmp_path / "one.exr", np.zeros((h, w, 1), np.float16))
    with pytest.raises(ValueError, match="one.exr has 1 channels; motion needs 2"):
        bl.Frame.from_exr(color=path, depth=path, motion=one, convention="unity")
