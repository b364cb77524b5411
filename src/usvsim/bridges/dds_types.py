"""ROS 2 message types for Cyclone DDS, and the one place that touches cyclonedds-python internals.

Types: `idl_type("sensor_msgs/msg/Image")` builds (once) a final (XCDR1) cyclonedds `IdlStruct` named
`sensor_msgs::msg::dds_::Image_` from the rosbags typestore's field definitions, nested types with their
own mangled names (ros2-interop.md §2.1). The classes exist so that topics carry the right type name and
final extensibility and XTypes type information (cyclonedds-python 11 requires it); samples are never
built from them: the bridge writes and takes CDR bytes. Fast DDS 3.x (ROS 2 Kilted) announces type objects that Cyclone 11
rejects for messages with arrays; `dds_config` tells Cyclone to match Fast DDS endpoints by type name instead,
as Jazzy/Humble RMWs (which announce no type objects) are matched anyway.

Raw I/O: cyclonedds-python has no public API to write or take serialized samples; `DataWriter.write`
serializes sequence[uint8] element by element (~50 ms for a VGA image). `write_cdr` hands the bytes to
libddsc's `dds_write` in the container cyclonedds-python's serdata reads (through ctypes, so the GIL is
free while Cyclone copies and sends: the simulation thread keeps running); `take_cdr` calls the C-layer
function `DataReader.take` uses. Both only on the versions checked below (`check_raw_api`).
"""

from __future__ import annotations

import ctypes
import functools
import os
from pathlib import Path
from typing import Any

from usvsim.messages.ros import typestore

TESTED_CYCLONEDDS = ("11.0",)  # major.minor versions whose C layer matches write_cdr / take_cdr
_ANY_STATE = 0x7F  # SampleState.Any | ViewState.Any | InstanceState.Any, as cyclonedds-python passes


def dds_type_name(msgtype: str) -> str:
    """`pkg/msg/Type` → `pkg::msg::dds_::Type_` (the DDS type name ROS 2 RMWs use)."""
    pkg, kind, name = msgtype.split("/")
    return f"{pkg}::{kind}::dds_::{name}_"


def dds_topic_name(topic: str) -> str:
    """ROS topic `/a/b` → DDS topic `rt/a/b`."""
    return "rt/" + topic.lstrip("/")


@functools.cache
def check_raw_api() -> str:
    """The cyclonedds version, after checking that its raw write/take path is one we know."""
    from importlib.metadata import version

    ver = version("cyclonedds")
    if not ver.startswith(TESTED_CYCLONEDDS):
        raise RuntimeError(
            f"usvsim's DDS bridge writes pre-serialized CDR through cyclonedds-python's C layer, which was "
            f"checked on cyclonedds {', '.join(TESTED_CYCLONEDDS)}.x; found {ver}. Install a tested version "
            f"(pip install 'cyclonedds~=11.0') or extend usvsim/bridges/dds_types.py after checking it."
        )
    from cyclonedds import _clayer  # pyright: ignore[reportAttributeAccessIssue] (a C extension without stubs)

    for name in ("ddspy_write", "ddspy_take"):
        if not hasattr(_clayer, name):
            raise RuntimeError(f"cyclonedds {ver} lacks _clayer.{name}; the DDS bridge cannot write raw CDR")
    return ver


class _SampleContainer(ctypes.Structure):
    """What cyclonedds-python's serdata reads a sample from (its `ddspy_sample_container_t`, 11.0.x)."""

    _fields_ = [("usample", ctypes.c_void_p), ("usample_size", ctypes.c_size_t)]


@functools.cache
def _dds_write() -> Any:
    """libddsc's `dds_write`, from the copy cyclonedds-python already loaded, called through ctypes so that
    the GIL is released while Cyclone copies and sends the sample (its own binding holds the GIL); None
    where that library cannot be found (the C-layer path is used then)."""
    import cyclonedds

    libs = Path(cyclonedds.__file__).parent.parent / "cyclonedds.libs"
    found = sorted(libs.glob("libddsc-*.so*")) if libs.is_dir() else []
    if not found:
        return None
    try:
        fn = ctypes.CDLL(str(found[0]), mode=os.RTLD_NOLOAD | os.RTLD_GLOBAL).dds_write
    except (OSError, AttributeError):
        return None
    fn.argtypes, fn.restype = [ctypes.c_int32, ctypes.POINTER(_SampleContainer)], ctypes.c_int32
    return fn


def write_cdr(writer: Any, cdr: bytes) -> int:
    """Write one CDR sample (encapsulation header included) as is; returns the DDS return code (<0 = error)."""
    if len(cdr) % 4:  # the C layer expects whole 4-byte units, as DataWriter.write pads them
        cdr = cdr + b"\0" * (4 - len(cdr) % 4)
    dds_write = _dds_write()
    if dds_write is None:
        from cyclonedds._clayer import ddspy_write

        return ddspy_write(writer._ref, cdr)
    container = _SampleContainer(ctypes.cast(ctypes.c_char_p(cdr), ctypes.c_void_p), len(cdr))  # no copy
    return dds_write(writer._ref, ctypes.byref(container))


def take_cdr(reader: Any, limit: int = 64) -> list[bytes]:
    """Take up to `limit` samples as CDR bytes (encapsulation header included); invalid samples skipped."""
    from cyclonedds._clayer import ddspy_take

    ret = ddspy_take(reader._ref, _ANY_STATE, limit)
    if isinstance(ret, int):
        raise RuntimeError(f"DDS take failed with return code {ret}")
    return [bytes(data) for data, info in ret if info.valid_data]


# -- types ---------------------------------------------------------------------------------------
def _base_types() -> dict[str, Any]:
    from cyclonedds.idl import types as t

    return {
        "bool": bool, "byte": t.uint8, "char": t.uint8, "octet": t.uint8,
        "int8": t.int8, "uint8": t.uint8, "int16": t.int16, "uint16": t.uint16,
        "int32": t.int32, "uint32": t.uint32, "int64": t.int64, "uint64": t.uint64,
        "float32": t.float32, "float64": t.float64, "string": str,
    }  # fmt: skip


def _field_type(node: tuple, base: dict[str, Any]) -> Any:
    """cyclonedds annotation for one rosbags field node (Nodetype, args)."""
    from cyclonedds.idl import types as t

    kind, args = node
    kind = int(kind)
    if kind == 1:  # BASE: (name, string bound)
        name, bound = args
        if name == "string" and bound:
            return t.bounded_str[bound]
        if name not in base:
            raise TypeError(f"ROS base type {name!r} is not supported by the DDS bridge")
        return base[name]
    if kind == 2:  # NAME: a nested message
        return idl_type(args)
    sub, size = args
    if kind == 3:  # ARRAY: fixed length
        return t.array[_field_type(sub, base), size]
    return t.sequence[_field_type(sub, base), size] if size else t.sequence[_field_type(sub, base)]


@functools.cache
def idl_type(msgtype: str) -> type:
    """The final cyclonedds IdlStruct for ROS type `msgtype` (cached per process)."""
    from cyclonedds.idl import annotations as annotate
    from cyclonedds.idl import make_idl_struct

    base = _base_types()
    fields = {name: _field_type(node, base) for name, node in typestore().fielddefs[msgtype][1]}
    cls = annotate.final(make_idl_struct(msgtype.rsplit("/", 1)[1] + "_", dds_type_name(msgtype), fields))
    return cls


def delete_entity(entity: Any) -> None:
    """Delete a cyclonedds entity (and its children) now rather than at garbage collection."""
    entity.__del__()  # what cyclonedds-python does at collection; idempotent
