"""Message builders and the envelope: values, ROS field order, CDR round trip, serialize-once."""

from __future__ import annotations

import numpy as np
import pytest

from usvsim.messages import ros
from usvsim.messages.envelope import TF_STATIC_QOS, Envelope, QosProfile, qos_for_topic


def roundtrip(msg):
    store = ros.typestore()
    return store.deserialize_cdr(store.serialize_cdr(msg, msg.__msgtype__), msg.__msgtype__)


def test_time_split_for_large_stamps():
    stamp = 1_700_000_000 * 10**9 + 123_456_789  # a wall-clock-sized stamp
    t = ros.time_msg(stamp)
    assert (t.sec, t.nanosec) == (1_700_000_000, 123_456_789)
    assert ros.time_to_ns(t) == stamp
    assert (ros.time_msg(999_999_999).sec, ros.time_msg(999_999_999).nanosec) == (0, 999_999_999)
    assert (ros.time_msg(10**9).sec, ros.time_msg(10**9).nanosec) == (1, 0)
    with pytest.raises(ValueError, match="int32"):
        ros.time_msg(2**31 * 10**9)


def test_header_and_clock():
    h = ros.header(2_500_000_000, "wamv/base_link")
    assert (h.stamp.sec, h.stamp.nanosec, h.frame_id) == (2, 500_000_000, "wamv/base_link")
    c = roundtrip(ros.clock_msg(42))
    assert (c.clock.sec, c.clock.nanosec) == (0, 42)


def test_odometry_fields_quaternion_order_and_default_covariance():
    q_wxyz = np.array([0.9, 0.1, 0.2, 0.3]) / np.linalg.norm([0.9, 0.1, 0.2, 0.3])
    msg = ros.odometry_msg(
        5,
        "wamv/odom",
        "wamv/base_link",
        np.array([1.0, 2.0, 3.0]),
        q_wxyz,
        np.array([0.5, 0.0, 0.0]),
        np.array([0.0, 0.0, 0.1]),
    )
    back = roundtrip(msg)
    assert back.header.frame_id == "wamv/odom" and back.child_frame_id == "wamv/base_link"
    o = back.pose.pose.orientation
    assert np.allclose([o.x, o.y, o.z, o.w], q_wxyz[[1, 2, 3, 0]])
    p = back.pose.pose.position
    assert (p.x, p.y, p.z) == (1.0, 2.0, 3.0)
    assert back.twist.twist.linear.x == 0.5 and back.twist.twist.angular.z == 0.1
    # ground truth: exact, so zero covariance (not the "unknown" -1 marker of Imu.msg)
    assert back.pose.covariance.shape == (36,) and not back.pose.covariance.any()
    assert not back.twist.covariance.any()


def test_odometry_covariance_is_row_major_6x6():
    cov = np.arange(36.0).reshape(6, 6)
    msg = ros.odometry_msg(
        0, "a", "b", np.zeros(3), np.array([1.0, 0, 0, 0]), np.zeros(3), np.zeros(3), pose_cov=cov
    )
    assert np.array_equal(roundtrip(msg).pose.covariance, np.arange(36.0))
    with pytest.raises(ValueError, match="36"):
        ros.odometry_msg(
            0, "a", "b", np.zeros(3), np.array([1.0, 0, 0, 0]), np.zeros(3), np.zeros(3), twist_cov=np.eye(3)
        )


def test_tf_message():
    t1 = ros.transform_stamped(7, "world", "wamv/odom", np.array([1.0, 0, 0]), np.array([0.0, 0, 0, 1]))
    t2 = ros.transform_stamped(7, "wamv/odom", "wamv/base_link", np.zeros(3), np.array([1.0, 0, 0, 0]))
    back = roundtrip(ros.tf_message([t1, t2]))
    assert [t.child_frame_id for t in back.transforms] == ["wamv/odom", "wamv/base_link"]
    r = back.transforms[0].transform.rotation
    assert (r.x, r.y, r.z, r.w) == (0.0, 0.0, 1.0, 0.0)  # wxyz (0,0,0,1) = 180 deg about z
    assert back.transforms[0].header.frame_id == "world"


def test_image_from_numpy_without_copy_of_layout():
    rgb = np.arange(4 * 5 * 3, dtype=np.uint8).reshape(4, 5, 3)
    back = roundtrip(ros.image_msg(1, "cam_optical", rgb))
    assert (back.height, back.width, back.step, back.encoding, back.is_bigendian) == (4, 5, 15, "rgb8", 0)
    assert np.array_equal(back.data.reshape(4, 5, 3), rgb)
    depth = np.full((2, 3), 1.5, dtype=np.float32)
    d = roundtrip(ros.image_msg(1, "cam_optical", depth, "32FC1"))
    assert d.step == 12 and np.array_equal(d.data.view("<f4").reshape(2, 3), depth)
    with pytest.raises(ValueError, match="shape"):
        ros.image_msg(1, "cam", depth, "rgb8")


def test_envelope_serializes_once(monkeypatch):
    store = ros.typestore()
    calls = []
    real = store.serialize_cdr
    monkeypatch.setattr(store, "serialize_cdr", lambda *a, **k: calls.append(1) or real(*a, **k))
    env = Envelope("/clock", 3, ros.clock_msg(3))
    assert env.msgtype == "rosgraph_msgs/msg/Clock"
    first, second = env.cdr, env.cdr
    assert first is second and len(calls) == 1
    assert first[:4] == b"\x00\x01\x00\x00"  # XCDR1 little-endian encapsulation


def test_envelope_from_bytes_and_qos():
    cdr = Envelope("/clock", 3, ros.clock_msg(3)).cdr
    env = Envelope("/clock", 3, msgtype="rosgraph_msgs/msg/Clock", cdr=cdr)
    assert env.decoded().clock.nanosec == 3
    with pytest.raises(ValueError):
        Envelope("/clock", 3, cdr=cdr)
    assert qos_for_topic("/tf_static") == TF_STATIC_QOS == QosProfile("reliable", "transient_local", 1)
    assert qos_for_topic("/wamv/ground_truth/odometry").durability == "volatile"
    assert Envelope("/tf_static", 0, ros.tf_message([])).qos.durability == "transient_local"
