"""visualization_msgs markers from parts (messages/markers.py): the patched bytes of `MovingMarkers` equal what the
serializer (rosbags) makes of the same markers, and the parts' shapes map to RViz's marker conventions."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from usvsim.messages.markers import MovingMarkers, marker_array, part_marker
from usvsim.messages.ros import header, msg_class, point, quaternion, typestore
from usvsim.vessels.parts import Mesh, Part

PARTS = [Part("sphere", (0.3,), (0.0, 0.0, 0.2), rgba=(1.0, 0.0, 0.0, 1.0)),
         Part("box", (1.0, 0.5, 0.25), (0.1, -0.2, 0.3), (0.9238795, 0.0, 0.0, 0.3826834)),
         Part("cylinder", (0.2, 1.5)),
         Part("mesh", (), mesh=Mesh(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1.0]]),
                                    np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])))]  # fmt: skip


def test_shapes_follow_rviz_conventions():
    m = msg_class("visualization_msgs/msg/Marker")
    sphere, box, cylinder, mesh = (part_marker(p, 5, "world", "ns", k) for k, p in enumerate(PARTS))
    assert sphere.type == m.SPHERE and (sphere.scale.x, sphere.scale.y, sphere.scale.z) == (0.6, 0.6, 0.6)
    assert box.type == m.CUBE and (box.scale.x, box.scale.y, box.scale.z) == (2.0, 1.0, 0.5)  # full sides
    assert (box.pose.orientation.w, box.pose.orientation.z) == (0.9238795, 0.3826834)  # ROS (x, y, z, w) fields
    assert cylinder.type == m.CYLINDER and (cylinder.scale.x, cylinder.scale.y, cylinder.scale.z) == (0.4, 0.4, 3.0)
    assert mesh.type == m.TRIANGLE_LIST and len(mesh.points) == 12  # three points per face
    assert [(p.x, p.y, p.z) for p in mesh.points[3:6]] == [(0, 0, 0), (1, 0, 0), (0, 0, 1)]
    assert part_marker(Part("hfield", (1.0, 1.0)), 0, "world", "ns", 0) is None


@pytest.mark.parametrize("stamp_ns", [0, 1_500_000_001, 86_400 * 10**9 + 7])
def test_patched_bytes_equal_the_serializers(stamp_ns):
    markers = [part_marker(p, 0, "world", f"body/b{k}", k) for k, p in enumerate(PARTS)]
    moving = MovingMarkers(markers)
    rng = np.random.default_rng(stamp_ns)
    positions = rng.normal(0.0, 50.0, (len(PARTS), 3))
    quats = rng.normal(size=(len(PARTS), 4))
    quats /= np.linalg.norm(quats, axis=1, keepdims=True)
    pose = msg_class("geometry_msgs/msg/Pose")
    want = [dataclasses.replace(m, header=header(stamp_ns, "world"),
                                pose=pose(position=point(p), orientation=quaternion(q)))
            for m, p, q in zip(markers, positions, quats)]  # fmt: skip
    expected = bytes(typestore().serialize_cdr(marker_array(want), "visualization_msgs/msg/MarkerArray"))
    assert moving.cdr(stamp_ns, np.hstack([positions, quats[:, 1:], quats[:, :1]])) == expected
