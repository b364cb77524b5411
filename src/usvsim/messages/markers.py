"""`visualization_msgs/MarkerArray` from drawable parts (`vessels.parts.Part`): what RViz and Foxglove draw of
the scene from ROS 2 topics and recordings.

A part becomes one marker: CUBE (scale = the box's full size), CYLINDER (scale = diameter, diameter, length;
z the axis), SPHERE (scale = diameter) or TRIANGLE_LIST (a mesh: three points per face, outward winding, in
the part's frame; scale 1), its pose in the marker's frame (the part's pose, or the part placed by a body pose),
its colour the part's RGBA. `ns` groups a body's markers, `id` counts its parts; `frame_locked` markers follow
their frame as TF moves it (a vessel's `<v>/base_link`). Lifetime 0: a marker stays until it is replaced.
"""

from __future__ import annotations

import dataclasses
import struct
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from usvsim.messages.ros import header, msg_class, point, quaternion, typestore, vector3

if TYPE_CHECKING:
    from usvsim.vessels.parts import Part

MARKER = "visualization_msgs/msg/Marker"


def part_marker(part: Part, stamp_ns: int, frame_id: str, ns: str, marker_id: int, frame_locked: bool = False,
                base_pos=None, base_quat=None) -> Any | None:  # fmt: skip
    """The marker of `part` (body frame) in `frame_id`, placed by the body pose `base_pos` (m), `base_quat`
    (w, x, y, z) when given; None for a part with nothing to draw (a height field, a mesh-less mesh part)."""
    m = msg_class(MARKER)
    pos, quat = part.placed(base_pos, base_quat)
    size, points = np.asarray(part.size, float), []
    if part.kind == "box":
        kind, scale = m.CUBE, 2.0 * size[:3]
    elif part.kind == "cylinder":
        kind, scale = m.CYLINDER, (2.0 * size[0], 2.0 * size[0], 2.0 * size[1])
    elif part.kind == "sphere":
        kind, scale = m.SPHERE, (2.0 * size[0],) * 3
    elif part.kind == "mesh" and part.mesh is not None:
        kind, scale = m.TRIANGLE_LIST, (1.0, 1.0, 1.0)
        points = [point(p) for p in part.mesh.vertices[part.mesh.faces.reshape(-1)]]
    else:
        return None
    r, g, b, a = (float(c) for c in part.rgba)
    return m(header=header(stamp_ns, frame_id), ns=ns, id=marker_id, type=kind, action=m.ADD,
             pose=msg_class("geometry_msgs/msg/Pose")(position=point(pos), orientation=quaternion(quat)),
             scale=vector3(scale), color=msg_class("std_msgs/msg/ColorRGBA")(r=r, g=g, b=b, a=a),
             lifetime=msg_class("builtin_interfaces/msg/Duration")(sec=0, nanosec=0), frame_locked=frame_locked,
             points=points, colors=[], texture_resource="", texture=_no_texture(), uv_coordinates=[], text="",
             mesh_resource="", mesh_file=msg_class("visualization_msgs/msg/MeshFile")(filename="", data=_EMPTY),
             mesh_use_embedded_materials=False)  # fmt: skip


def marker_array(markers: Sequence[Any]) -> Any:
    return msg_class("visualization_msgs/msg/MarkerArray")(markers=list(markers))


_EMPTY = np.zeros(0, dtype=np.uint8)


def _no_texture() -> Any:
    return msg_class("sensor_msgs/msg/CompressedImage")(header=header(0, ""), format="", data=_EMPTY)


class MovingMarkers:
    """The CDR bytes of a MarkerArray whose markers change only their header stamps and poses (bodies moving in
    `world`): the array is serialized once, and `cdr` writes new stamps and poses into a copy of those bytes, the
    bytes the serializer makes for the same message (tests/messages/test_markers.py), at a few µs a call where
    building and serializing the message objects cost ~0.3 ms for nine buoys.

    Where the fields lie is found once by serializing the markers with a distinct sentinel value in each changing
    field and finding its bytes (each must occur exactly once)."""

    _SEC, _NSEC, _POSE = 0x5EC00000, 0x0AC00000, 9.87654321e12  # sentinels: + the marker's index (+ field)

    def __init__(self, markers: Sequence[Any]):
        n = len(markers)
        time, pose = msg_class("builtin_interfaces/msg/Time"), msg_class("geometry_msgs/msg/Pose")
        marked = []
        for k, m in enumerate(markers):
            values = self._POSE + 8.0 * k + np.arange(7.0)
            h = msg_class("std_msgs/msg/Header")(stamp=time(sec=self._SEC + k, nanosec=self._NSEC + k),
                                                 frame_id=m.header.frame_id)  # fmt: skip
            marked.append(dataclasses.replace(m, header=h, pose=pose(position=point(values[:3]),
                                                                     orientation=_xyzw(values[3:]))))  # fmt: skip
        data = bytes(typestore().serialize_cdr(marker_array(marked), "visualization_msgs/msg/MarkerArray"))
        stamps = np.array([_find(data, struct.pack("<iI", self._SEC + k, self._NSEC + k)) for k in range(n)]) - 4
        poses = np.array([[_find(data, struct.pack("<d", self._POSE + 8.0 * k + j)) for j in range(7)]
                          for k in range(n)]) - 4  # fmt: skip
        if np.any(stamps % 4) or np.any(poses % 8):  # CDR aligns from the byte after the 4-byte header
            raise RuntimeError("MovingMarkers: a stamp or pose field is not aligned as CDR aligns it")
        self._sec_at = (stamps // 4).astype(np.intp)  # in 32-bit words after the header; nanosec: the next word
        self._pose_at = (poses // 8).reshape(-1).astype(np.intp)  # in doubles after the header
        self._template, self.n = data, n
        self._words, self._doubles = (len(data) - 4) // 4, (len(data) - 4) // 8

    def cdr(self, stamp_ns: int, poses: np.ndarray) -> bytes:
        """The array's bytes with every marker stamped `stamp_ns` and posed at `poses` (n, 7): x, y, z (m) and the
        quaternion x, y, z, w (ROS order)."""
        buf = bytearray(self._template)
        sec, nanosec = divmod(int(stamp_ns), 1_000_000_000)
        words = np.frombuffer(buf, dtype="<u4", offset=4, count=self._words)
        words[self._sec_at] = sec & 0xFFFFFFFF  # int32 seconds, two's complement
        words[self._sec_at + 1] = nanosec
        np.frombuffer(buf, dtype="<f8", offset=4, count=self._doubles)[self._pose_at] = np.ravel(poses)
        return bytes(buf)


def _find(data: bytes, pattern: bytes) -> int:
    at = data.find(pattern)
    if at < 0 or data.find(pattern, at + 1) >= 0:
        raise RuntimeError("MovingMarkers: a sentinel's bytes are missing or repeated in the serialized array")
    return at


def _xyzw(q) -> Any:  # sentinel values in x, y, z, w order
    return msg_class("geometry_msgs/msg/Quaternion")(x=float(q[0]), y=float(q[1]), z=float(q[2]), w=float(q[3]))
