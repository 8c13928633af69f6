"""VersaMax Read Configuration datagrams of the packed protocol (0x0201, ``docs/protocol.md``
section 5).

A slot's configuration record (its format is :mod:`focas_net.versamax`) is read by offset, at
most :data:`MAX_CONFIG_CHUNK` bytes per request; a longer record is reassembled by the client.
"""

from __future__ import annotations

import struct
from dataclasses import dataclass
from typing import Final, Self

from ..errors import PayloadError
from ._base import field_error

__all__ = ["MAX_CONFIG_CHUNK", "VersaMaxReply", "VersaMaxRequest"]

#: Most record bytes one Read Configuration reply carries.
MAX_CONFIG_CHUNK: Final = 128

_REQUEST: Final = struct.Struct("<BHBH")


@dataclass(frozen=True, slots=True)
class VersaMaxRequest:
    """Read Configuration datagram (subfunction 02): 6 bytes ``<B H B H``."""

    rack: int
    length: int
    slot: int
    offset: int

    def encode(self) -> bytes:
        try:
            return _REQUEST.pack(self.rack, self.length, self.slot, self.offset)
        except struct.error as exc:
            fields: tuple[tuple[str, object, str], ...] = (
                ("rack", self.rack, "B"),
                ("length", self.length, "H"),
                ("slot", self.slot, "B"),
                ("offset", self.offset, "H"),
            )
            raise ValueError(field_error(fields, exc)) from None

    @classmethod
    def decode(cls, data: bytes) -> Self:
        if len(data) != _REQUEST.size:
            raise PayloadError(f"VersaMaxRequest: {len(data)} bytes, expected {_REQUEST.size}")
        return cls(*_REQUEST.unpack(data))


@dataclass(frozen=True, slots=True)
class VersaMaxReply:
    """Read Configuration Reply (subfunction 03): the datagram header, then record bytes.

    The header's ``length`` field is the whole datagram (6 + ``len(data)``) and is derived.
    """

    rack: int
    slot: int
    offset: int
    data: bytes

    def encode(self) -> bytes:
        try:
            return (
                _REQUEST.pack(self.rack, _REQUEST.size + len(self.data), self.slot, self.offset)
                + self.data
            )
        except struct.error as exc:
            fields: tuple[tuple[str, object, str], ...] = (
                ("rack", self.rack, "B"),
                ("length", _REQUEST.size + len(self.data), "H"),
                ("slot", self.slot, "B"),
                ("offset", self.offset, "H"),
            )
            raise ValueError(field_error(fields, exc)) from None

    @classmethod
    def decode(cls, data: bytes) -> Self:
        if len(data) < _REQUEST.size:
            raise PayloadError(f"VersaMaxReply: {len(data)} bytes is shorter than its header")
        rack, length, slot, offset = _REQUEST.unpack_from(data, 0)
        if length != len(data):
            raise PayloadError(f"VersaMaxReply: length field {length}, datagram {len(data)}")
        return cls(rack, slot, offset, data[_REQUEST.size :])
