"""Direct CDR encoding of the bulk message types: sensor_msgs/Image, sensor_msgs/PointCloud2 and
marine_sensor_msgs/RadarSector.

The general serializer (rosbags) walks every field; for these types almost all bytes are one `uint8[]` blob,
so they are written here as a few small packed fields around a single copy of the blob (about 5x faster
for a VGA image). The bytes are identical to rosbags' (XCDR1, little endian, the 4-byte encapsulation
header `00 01 00 00`, alignment counted from the byte after it): tests/messages/test_cdr_fast.py checks it.
"""

from __future__ import annotations

import struct
from typing import Any

import numpy as np

HEADER = b"\x00\x01\x00\x00"


class _Writer:
    """Appends CDR fields to a list of byte chunks, tracking the body offset for alignment."""

    def __init__(self) -> None:
        self.chunks: list[bytes | memoryview] = [HEADER]
        self.pos = 0

    def _align(self, n: int) -> None:
        pad = -self.pos % n
        if pad:
            self.chunks.append(b"\0" * pad)
            self.pos += pad

    def u32(self, *values: int) -> None:
        self._align(4)
        self.chunks.append(struct.pack(f"<{len(values)}I", *values))
        self.pos += 4 * len(values)

    def time(self, stamp: Any) -> None:
        self._align(4)
        self.chunks.append(struct.pack("<iI", stamp.sec, stamp.nanosec))
        self.pos += 8

    def f32(self, *values: float) -> None:
        self._align(4)
        self.chunks.append(struct.pack(f"<{len(values)}f", *values))
        self.pos += 4 * len(values)

    def f32_array(self, data: Any) -> None:
        """sequence<float32>: length, then the values."""
        view = np.ascontiguousarray(data, dtype="<f4").data.cast("B")
        self.u32(view.nbytes // 4)
        self.chunks.append(view)
        self.pos += view.nbytes

    def u8(self, value: int) -> None:
        self.chunks.append(bytes((value & 0xFF,)))
        self.pos += 1

    def string(self, text: str) -> None:
        raw = text.encode() + b"\0"
        self.u32(len(raw))
        self.chunks.append(raw)
        self.pos += len(raw)

    def blob(self, data: Any) -> None:
        view = np.ascontiguousarray(data, dtype=np.uint8).data.cast("B")
        self.u32(view.nbytes)
        self.chunks.append(view)
        self.pos += view.nbytes

    def header(self, header: Any) -> None:
        self.time(header.stamp)
        self.string(header.frame_id)

    def bytes(self) -> bytes:
        return b"".join(self.chunks)


def image_cdr(msg: Any) -> bytes:
    w = _Writer()
    w.header(msg.header)
    w.u32(msg.height, msg.width)
    w.string(msg.encoding)
    w.u8(msg.is_bigendian)
    w.u32(msg.step)
    w.blob(msg.data)
    return w.bytes()


def pointcloud2_cdr(msg: Any) -> bytes:
    w = _Writer()
    w.header(msg.header)
    w.u32(msg.height, msg.width, len(msg.fields))
    for field in msg.fields:
        w.string(field.name)
        w.u32(field.offset)
        w.u8(field.datatype)
        w.u32(field.count)
    w.u8(msg.is_bigendian)
    w.u32(msg.point_step, msg.row_step)
    w.blob(msg.data)
    w.u8(msg.is_dense)
    return w.bytes()


def radar_sector_cdr(msg: Any) -> bytes:
    """marine_sensor_msgs/RadarSector: hundreds of `float32[]` spokes per message."""
    w = _Writer()
    w.header(msg.header)
    w.f32(msg.angle_start, msg.angle_increment)
    w.time(msg.time_increment)  # builtin_interfaces/Duration: int32 sec, uint32 nanosec, like Time
    w.time(msg.scan_time)
    w.f32(msg.range_min, msg.range_max)
    w.u32(len(msg.intensities))
    for echo in msg.intensities:
        w.f32_array(echo.echoes)
    return w.bytes()


FAST = {"sensor_msgs/msg/Image": image_cdr, "sensor_msgs/msg/PointCloud2": pointcloud2_cdr,
        "marine_sensor_msgs/msg/RadarSector": radar_sector_cdr}  # fmt: skip
