"""A tiny protobuf reader for tests (the venv has no `protobuf` package): wire format → nested dicts by field name.

Field names and numbers come from the FileDescriptorSet that the Foxglove server advertises with the channel
(descriptor.proto numbering), so the test reads the messages the way any Foxglove client would.
"""

from __future__ import annotations

import base64
import struct

# descriptor.proto field numbers
FILE, PACKAGE, MESSAGE_TYPE = 1, 2, 4  # FileDescriptorSet.file; FileDescriptorProto.package / message_type
NAME, FIELD = 1, 2  # DescriptorProto.name / field
F_NAME, F_NUMBER, F_LABEL, F_TYPE, F_TYPE_NAME = 1, 3, 4, 5, 6  # FieldDescriptorProto
REPEATED, TYPE_DOUBLE, TYPE_MESSAGE, TYPE_STRING, TYPE_BYTES, TYPE_FIXED32 = 3, 1, 11, 9, 12, 7


def fields(data: bytes) -> list[tuple[int, int, object]]:
    """Raw (number, wire type, value) triples: varint → int, fixed64/32 → bytes, length-delimited → bytes."""
    out, i = [], 0
    while i < len(data):
        key, i = _varint(data, i)
        number, wire = key >> 3, key & 7
        if wire == 0:
            value, i = _varint(data, i)
        elif wire == 1:
            value, i = data[i : i + 8], i + 8
        elif wire == 2:
            size, i = _varint(data, i)
            value, i = data[i : i + size], i + size
        elif wire == 5:
            value, i = data[i : i + 4], i + 4
        else:
            raise ValueError(f"unsupported wire type {wire}")
        out.append((number, wire, value))
    return out


def _varint(data: bytes, i: int) -> tuple[int, int]:
    result = shift = 0
    while True:
        b = data[i]
        result |= (b & 0x7F) << shift
        i, shift = i + 1, shift + 7
        if not b & 0x80:
            return result, i


def _first(raw, number, default=None):
    return next((v for n, _, v in raw if n == number), default)


class Schema:
    """Message layouts of a FileDescriptorSet: full name → {field number: (name, type, type name, repeated)}."""

    def __init__(self, descriptor_set: bytes):
        self.messages: dict[str, dict[int, tuple[str, int, str, bool]]] = {}
        for _, _, file in (f for f in fields(descriptor_set) if f[0] == FILE):
            raw = fields(file)
            package = _first(raw, PACKAGE, b"").decode()
            for n, _, msg in raw:
                if n == MESSAGE_TYPE:
                    self._add(package, fields(msg))

    @classmethod
    def from_advertised(cls, channel: dict) -> Schema:
        return cls(base64.b64decode(channel["schema"]))

    def _add(self, package: str, raw) -> None:
        layout = {}
        for n, _, f in raw:
            if n == FIELD:
                fr = fields(f)
                layout[_first(fr, F_NUMBER)] = (_first(fr, F_NAME).decode(), _first(fr, F_TYPE),
                                               _first(fr, F_TYPE_NAME, b"").decode().lstrip("."),
                                               _first(fr, F_LABEL) == REPEATED)  # fmt: skip
        self.messages[f"{package}.{_first(raw, NAME).decode()}"] = layout

    def decode(self, type_name: str, data: bytes) -> dict:
        layout, out = self.messages[type_name], {}
        for number, wire, value in fields(data):
            if number not in layout:
                continue
            name, ftype, sub, repeated = layout[number]
            items = self._values(ftype, sub, wire, value)
            if repeated:
                out.setdefault(name, []).extend(items)
            else:
                out[name] = items[0]
        return out

    def _values(self, ftype: int, sub: str, wire: int, value) -> list:
        if ftype == TYPE_MESSAGE:
            return [self.decode(sub, value)]
        if ftype == TYPE_STRING:
            return [value.decode()]
        if ftype == TYPE_BYTES:
            return [value]
        if ftype == TYPE_DOUBLE:
            if wire == 2:  # packed
                return list(struct.unpack(f"<{len(value) // 8}d", value))
            return [struct.unpack("<d", value)[0]]
        if ftype == TYPE_FIXED32:
            return list(struct.unpack(f"<{len(value) // 4}I", value))
        if wire == 2:  # packed varints
            items, i = [], 0
            while i < len(value):
                v, i = _varint(value, i)
                items.append(v)
            return items
        return [value]
