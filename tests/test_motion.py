"""Motion as functions of time: linear, spin, keyframes with slerp, skeletons."""

from __future__ import annotations

import math

import numpy as np
import pytest

import blurlab as bl
from blurlab.scene import motion
from blurlab.scene.motion import quaternion_matrix, slerp


def test_linear_motion_and_spin():
    motion = bl.Motion.linear((1, 2, 3), (4, 0, 0), spin_axis=(0, 0, 1), spin_rate=math.pi)
    m = motion.transform(0.5)
    np.testing.assert_allclose(m[:3, 3], [3, 2, 3])
    np.testing.assert_allclose(m[:3, :3] @ [1, 0, 0], [0, 1, 0], atol=1e-12)  # 90 degrees


def test_keyframes_interpolate_and_hold():
    q = bl.quaternion((0, 1, 0), math.pi / 2)
    motion = bl.Motion.keyframes(
        [bl.Keyframe(0.0, (0, 0, 0)), bl.Keyframe(1.0, (2, 0, 0), q, scale=3.0)]
    )
    half = motion.transform(0.5)
    np.testing.assert_allclose(half[:3, 3], [1, 0, 0])
    np.testing.assert_allclose(np.linalg.norm(half[:3, 0]), 2.0)  # scale 1 -> 3 at half way
    angle = math.atan2(-half[2, 0], half[0, 0])
    assert angle == pytest.approx(math.pi / 4)
    np.testing.assert_allclose(motion.transform(-1.0), motion.transform(0.0))
    np.testing.assert_allclose(motion.transform(9.0), motion.transform(1.0))


def test_slerp_takes_the_short_way_at_constant_speed():
    a = bl.quaternion((0, 0, 1), 0.0)
    b = -bl.quaternion((0, 0, 1), 1.0)  # the same rotation, other hemisphere
    for s in (0.25, 0.5, 0.75):
        r = quaternion_matrix(slerp(a, b, s))
        assert math.atan2(r[1, 0], r[0, 0]) == pytest.approx(s)


def test_bad_keyframes_are_rejected():
    with pytest.raises(ValueError, match="at least one"):
        bl.Motion.keyframes([])
    with pytest.raises(ValueError, match="increasing"):
        bl.Motion.keyframes([bl.Keyframe(1.0), bl.Keyframe(0.5)])
    with pytest.raises(ValueError, match="finite"):
        bl.Motion.keyframes([bl.Keyframe(0.0, (0, math.inf, 0))])
    with pytest.raises(ValueError, match="axis"):
        bl.Motion.linear(spin_axis=(0, 0, 0), spin_rate=1.0)


def test_skeleton_rest_pose_is_identity_and_children_follow_parents():
    skeleton = bl.Skeleton(
        [
            bl.Bone(-1, np.eye(4), bl.Motion.linear(velocity=(1, 0, 0))),
            bl.Bone(
                0,
                motion.compose((1, 0, 0)),
                bl.Motion.linear(spin_axis=(0, 0, 1), spin_rate=1.0),
            ),
        ]
    )
    at_rest = skeleton.matrices(0.0)
    np.testing.assert_allclose(at_rest, np.broadcast_to(np.eye(4), (2, 4, 4)), atol=1e-12)
    later = skeleton.matrices(2.0)
    np.testing.assert_allclose(later[0][:3, 3], [2, 0, 0])
    # A point at the child's joint moves with the parent only.
    joint = later[1] @ [1, 0, 0, 1]
    np.testing.assert_allclose(joint[:3], [3, 0, 0], atol=1e-12)
    with pytest.raises(ValueError, match="parent"):
        bl.Skeleton([bl.Bone(0, np.eye(4))])


def test_compose_gives_the_bits_of_the_plain_numpy_formula():
    # compose and quaternion_matrix take shortcuts for speed (thousands of calls per
    # reference); they must give exactly what T · R(q / |q|) · S gives in NumPy float64.
    rng = np.random.default_rng(11)
    for _ in range(2000):
        q = rng.normal(size=4) * rng.choice([1e-3, 1.0, 1e3])
        position = rng.normal(size=3) * 10
        scale = rng.choice([1.0, float(rng.normal())]) if rng.random() < 0.5 else rng.normal(size=3)
        w, x, y, z = np.asarray(q) / np.linalg.norm(q)
        rotation = np.array(
            [
                [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
            ]
        )
        expected = np.eye(4)
        expected[:3, :3] = rotation * np.broadcast_to(np.asarray(scale, float), 3)
        expected[:3, 3] = position
        assert np.array_equal(motion.compose(position, q, scale), expected)
