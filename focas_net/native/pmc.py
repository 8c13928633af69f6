"""The PMC over the native protocol: its areas, its data and the range requests.

``pmc_rdpmcrng`` and ``pmc_wrpmcrng`` go to the PMC device (0x8001, 0x8002); the data is the
range's bytes, words and longs big-endian. "[V]" marks what FANUC's library (libfwlib32 1.0.5)
was seen to accept and read back.
"""

from __future__ import annotations

import enum
import struct
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, ClassVar, Final, Self

from focas_net.errors import EW

from .base import NativePayloadError
from .blocks import Device
from .requests import EXTRA_LENGTH, NativeCommand, NativeRequest, _ArgSpec, _register

__all__ = [
    "NativePmcArea",
    "NativePmcData",
    "PmcDataType",
    "PmcReadRequest",
    "PmcWriteRequest",
]


# --------------------------------------------------------------------------------------------
# Records


class PmcDataType(enum.IntEnum):
    """PMC data types and their width in bytes (``1 << value``)."""

    BYTE = 0
    WORD = 1
    LONG = 2

    @property
    def width(self) -> int:
        return 1 << self.value


_PMC_FORMATS: Final = {1: "B", 2: "H", 4: "I"}


def _pmc_type(data_type: int) -> PmcDataType:
    try:
        return PmcDataType(data_type)
    except ValueError:
        raise NativePayloadError(f"PMC data type {data_type} unknown", EW.ATTRIB) from None


@dataclass(frozen=True, slots=True)
class NativePmcData:
    """``pmc_rdpmcrng`` answer (0x8001) and ``pmc_wrpmcrng`` extra (0x8002): the bytes of the
    range; words and longs big-endian (the library swaps them to host order) [V]."""

    raw: bytes

    def encode(self) -> bytes:
        return self.raw

    @classmethod
    def decode(cls, data: bytes) -> Self:
        return cls(bytes(data))

    def values(self, data_type: int) -> tuple[int, ...]:
        """The unsigned values of ``data_type`` (0 byte, 1 word, 2 long)."""
        kind = _pmc_type(data_type)
        if len(self.raw) % kind.width:
            raise NativePayloadError(
                f"NativePmcData: {len(self.raw)} bytes is not a multiple of {kind.width}", EW.LENGTH
            )
        fmt = _PMC_FORMATS[kind.width]
        return struct.unpack(f">{len(self.raw) // kind.width}{fmt}", self.raw)

    @classmethod
    def from_values(cls, data_type: int, values: Sequence[int]) -> Self:
        """The data carrying unsigned ``values`` of ``data_type``."""
        kind = _pmc_type(data_type)
        fmt = _PMC_FORMATS[kind.width]
        try:
            return cls(struct.pack(f">{len(values)}{fmt}", *values))
        except struct.error as exc:
            raise ValueError(f"NativePmcData: {exc}") from None


# --------------------------------------------------------------------------------------------
# Requests


class NativePmcArea(enum.IntEnum):
    """PMC address letters and their FOCAS ``adr_type`` numbers."""

    G = 0
    F = 1
    Y = 2
    X = 3
    A = 4
    R = 5
    T = 6
    K = 7
    C = 8
    D = 9
    M = 10
    N = 11
    E = 12
    Z = 13


@dataclass(frozen=True, slots=True)
class PmcReadRequest(NativeRequest):
    """Device PMC, 0x8001, args ``first, last, area, data_type`` (``pmc_rdpmcrng(a, t, s, e)``
    sends ``(s, e, a, t)``) [V].

    ``first`` and ``last`` are inclusive byte addresses (``last = first + width * count - 1``);
    ``data_type`` 0 byte, 1 word, 2 long (:class:`PmcDataType`). Answered with
    :class:`NativePmcData`.
    """

    DEVICE: ClassVar[int] = Device.PMC
    COMMAND: ClassVar[int] = NativeCommand.PMC_RDPMCRNG
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = ("first", "last", "area", "data_type")
    ANSWER: ClassVar[Any] = NativePmcData
    first: int
    last: int
    area: int
    data_type: int


@dataclass(frozen=True, slots=True)
class PmcWriteRequest(NativeRequest):
    """Device PMC, 0x8002, args ``first, last, area, data_type, nbytes``, extra: the data,
    words and longs big-endian (``pmc_wrpmcrng``) [V]. No answer data."""

    DEVICE: ClassVar[int] = Device.PMC
    COMMAND: ClassVar[int] = NativeCommand.PMC_WRPMCRNG
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = ("first", "last", "area", "data_type", EXTRA_LENGTH)
    WRITE: ClassVar[bool] = True
    first: int
    last: int
    area: int
    data_type: int
    data: NativePmcData

    def extra(self) -> bytes:
        return self.data.raw

    @classmethod
    def _extra_fields(cls, extra: bytes) -> dict[str, Any]:
        return {"data": NativePmcData(bytes(extra))}

    def values(self) -> tuple[int, ...]:
        """The unsigned values written."""
        return self.data.values(self.data_type)


_register(
    PmcReadRequest,
    PmcWriteRequest,
)
