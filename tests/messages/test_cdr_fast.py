"""The direct Image / PointCloud2 encoders give exactly rosbags' CDR bytes, for awkward string lengths too."""

from __future__ import annotations

import numpy as np
import pytest

from usvsim.messages import ros
from usvsim.messages.cdr_fast import image_cdr, pointcloud2_cdr
from usvsim.messages.envelope import Envelope


def rosbags_cdr(msg) -> bytes:
    return bytes(ros.typestore().serialize_cdr(msg, msg.__msgtype__))


@pytest.mark.parametrize("frame", ["", "a", "cam_optical", "wamv/front_camera_optical"])
@pytest.mark.parametrize(("encoding", "shape", "dtype"), [("rgb8", (5, 7, 3), np.uint8), ("32FC1", (3, 4), np.float32),
                                                          ("16UC1", (2, 3), np.uint16), ("mono8", (1, 1), np.uint8)])  # fmt: skip
def test_image_matches_rosbags(frame, encoding, shape, dtype):
    array = (np.arange(np.prod(shape)) % 251).astype(dtype).reshape(shape)
    msg = ros.image_msg(1_234_567_890_123, frame, array, encoding)
    assert image_cdr(msg) == rosbags_cdr(msg)
    assert Envelope("/cam/image_raw", 0, msg).cdr == rosbags_cdr(msg)


@pytest.mark.parametrize("names", [("x", "y", "z"), ("x", "y", "z", "intensity", "ring", "time"), ()])
@pytest.mark.parametrize("frame", ["", "wamv/lidar"])
def test_pointcloud2_matches_rosbags(names, frame):
    field = ros.msg_class("sensor_msgs/msg/PointField")
    fields = [field(name=n, offset=4 * i, datatype=7, count=1) for i, n in enumerate(names)]
    step = 4 * len(names)
    data = np.arange(step * 6, dtype=np.uint8)
    msg = ros.msg_class("sensor_msgs/msg/PointCloud2")(
        header=ros.header(-5, frame), height=2, width=3, fields=fields, is_bigendian=False, point_step=step,
        row_step=3 * step, data=data, is_dense=False)  # fmt: skip
    assert pointcloud2_cdr(msg) == rosbags_cdr(msg)


@pytest.mark.parametrize("frame", ["", "wamv/radar", "ab"])
@pytest.mark.parametrize("spokes", [0, 1, 3])
def test_radar_sector_matches_rosbags(frame, spokes):
    from usvsim.messages.cdr_fast import radar_sector_cdr

    duration = ros.msg_class("builtin_interfaces/msg/Duration")
    echo = ros.msg_class("marine_sensor_msgs/msg/RadarEcho")
    msg = ros.msg_class("marine_sensor_msgs/msg/RadarSector")(
        header=ros.header(5_000_000_123, frame), angle_start=-0.25, angle_increment=-0.006,
        time_increment=duration(sec=0, nanosec=2_441_406), scan_time=duration(sec=2, nanosec=500_000_000),
        range_min=0.0, range_max=1500.0,
        intensities=[echo(echoes=np.linspace(0, 1, 5 + k, dtype=np.float32)) for k in range(spokes)])  # fmt: skip
    assert radar_sector_cdr(msg) == rosbags_cdr(msg)
