"""Test helper for the rclpy peer: a raw-bytes subscription type for tf2_msgs/msg/TFMessage, and a decoder.

The PyPI ROS 2 wheels have no tf2_msgs package. rmw_fastrtps names a DDS type from the namespace and name
in its typesupport callbacks and, for raw (serialized) subscriptions, never calls the (de)serializers.
So `raw_message_type(...)` copies the Fast DDS typesupport of an unbounded message with the same wire
class (geometry_msgs/PoseArray), renames it `tf2_msgs::msg::dds_::TFMessage_`, and wraps it in a class
that rclpy accepts for `create_subscription(..., raw=True)`. Received bytes are decoded here, by hand,
independently of usvsim's serializer. Test-only; not for publishing.
"""

from __future__ import annotations

import ctypes
import importlib
import struct
import sys
from pathlib import Path

_keep: list = []  # ctypes objects referenced by the C structs must live as long as the process


def _lib(name: str) -> ctypes.CDLL:
    return ctypes.CDLL(str(Path(sys.prefix) / "lib" / name))


def raw_message_type(pkg: str, name: str, donor_pkg: str = "geometry_msgs", donor: str = "PoseArray"):
    """A class usable as `msg_type` for a raw rclpy subscription on a `pkg/msg/name` topic."""
    ts_lib = _lib(f"lib{donor_pkg}__rosidl_typesupport_fastrtps_c.so")
    getter = getattr(ts_lib, f"rosidl_typesupport_fastrtps_c__get_message_type_support_handle__"
                             f"{donor_pkg}__msg__{donor}")  # fmt: skip
    getter.restype = ctypes.POINTER(ctypes.c_void_p * 6)  # rosidl_message_type_support_t
    handle = getter().contents
    callbacks = (ctypes.c_void_p * 7).from_address(handle[1])  # message_type_support_callbacks_t
    namespace, type_name = ctypes.c_char_p(f"{pkg}::msg".encode()), ctypes.c_char_p(name.encode())
    new_callbacks = (ctypes.c_void_p * 7)(*callbacks)
    new_callbacks[0] = ctypes.cast(namespace, ctypes.c_void_p).value
    new_callbacks[1] = ctypes.cast(type_name, ctypes.c_void_p).value
    runtime = _lib("librosidl_runtime_c.so")
    dispatch = ctypes.cast(runtime.get_message_typesupport_handle_function, ctypes.c_void_p).value
    new_handle = (ctypes.c_void_p * 6)(handle[0], ctypes.addressof(new_callbacks), dispatch, *handle[3:6])
    _keep.extend([namespace, type_name, new_callbacks, new_handle])
    capsule_new = ctypes.pythonapi.PyCapsule_New
    capsule_new.restype, capsule_new.argtypes = (
        ctypes.py_object,
        [ctypes.c_void_p, ctypes.c_char_p, ctypes.c_void_p],
    )
    capsule = capsule_new(ctypes.addressof(new_handle), None, None)
    donor_cls = getattr(importlib.import_module(f"{donor_pkg}.msg"), donor)
    donor_cls.__class__.__import_type_support__()
    meta = type(f"Metaclass_{name}", (type,), {
        "_TYPE_SUPPORT": capsule,
        **{k: getattr(donor_cls.__class__, k) for k in
           ("_CREATE_ROS_MESSAGE", "_CONVERT_FROM_PY", "_CONVERT_TO_PY", "_DESTROY_ROS_MESSAGE")},
        "__import_type_support__": classmethod(lambda cls: None),
    })  # fmt: skip
    return meta(name, (), {})


# -- hand-written XCDR1 decoding of tf2_msgs/TFMessage ------------------------------------------------
class _Reader:
    def __init__(self, data: bytes):
        if data[:2] != b"\x00\x01":
            raise ValueError(f"not little-endian CDR: header {data[:4].hex()}")
        self.body, self.pos = memoryview(data)[4:], 0

    def take(self, fmt: str):
        size = struct.calcsize(fmt)
        align = min(size, 8) if fmt[-1] in "dqQ" else min(size, 4)
        self.pos += -self.pos % align
        value = struct.unpack_from("<" + fmt, self.body, self.pos)
        self.pos += size
        return value if len(value) > 1 else value[0]

    def string(self) -> str:
        n = self.take("I")
        text = bytes(self.body[self.pos : self.pos + n - 1]).decode()
        self.pos += n
        return text


def decode_tf(data: bytes) -> list[dict]:
    """TFMessage CDR → [{stamp_ns, frame_id, child_frame_id, translation, rotation}]."""
    r, out = _Reader(data), []
    for _ in range(r.take("I")):
        sec, nanosec = r.take("i"), r.take("I")
        frame, child = r.string(), r.string()
        translation = [r.take("d") for _ in range(3)]
        rotation = [r.take("d") for _ in range(4)]
        out.append({"stamp_ns": sec * 10**9 + nanosec, "frame_id": frame, "child_frame_id": child,
                    "translation": translation, "rotation": rotation})  # fmt: skip
    return out
