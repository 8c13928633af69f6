"""Macro variables over the native protocol: their records and their requests.

``cnc_rdmacro`` and ``cnc_wrmacro`` carry :class:`~.records.ScaledNumber` records (0x15,
0x16), ``cnc_rdmacror2`` and ``cnc_wrmacror2`` IEEE doubles (0xA7, 0xA8). "[V]" marks what
FANUC's library (libfwlib32 1.0.5) was seen to accept and read back.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, ClassVar, Final, Self

from focas_net.errors import EW

from .base import NativePayloadError, NativeRecord, check_multiple
from .records import ScaledNumber, ScaledValues
from .requests import EXTRA_LENGTH, NativeCommand, NativeRequest, _ArgSpec, _register

__all__ = [
    "MacroDouble",
    "MacroDoubleReadRequest",
    "MacroDoubleWriteRequest",
    "MacroDoubles",
    "MacroReadRequest",
    "MacroWriteRequest",
]


# --------------------------------------------------------------------------------------------
# Records


@dataclass(frozen=True, slots=True)
class MacroDouble(NativeRecord):
    """One IEEE double, big-endian (0xA7, 0xA8)."""

    FORMAT: ClassVar[str] = ">d"
    value: float


_DOUBLE: Final = MacroDouble.STRUCT
_NAN_BITS: Final = b"\x7f\xf8\x00\x00\x00\x00\x00\x00"


def _pack_double(value: float | None) -> bytes:
    if value is None:
        return _NAN_BITS
    if math.isnan(value):
        raise ValueError("NaN is reserved for a vacant variable; pass None")
    return _DOUBLE.pack(value)


def _unpack_double(data: bytes | memoryview, offset: int) -> float | None:
    (value,) = _DOUBLE.unpack_from(data, offset)
    return None if math.isnan(value) else float(value)


@dataclass(frozen=True, slots=True)
class MacroDoubles:
    """``cnc_rdmacror2`` (0xA7): one 8-byte IEEE double per variable [V]; None = vacant (sent
    as a quiet NaN, this project's choice)."""

    values: tuple[float | None, ...]

    def encode(self) -> bytes:
        return b"".join(_pack_double(v) for v in self.values)

    @classmethod
    def decode(cls, data: bytes) -> Self:
        check_multiple(data, _DOUBLE.size, "MacroDoubles")
        return cls(tuple(_unpack_double(data, i) for i in range(0, len(data), _DOUBLE.size)))


# --------------------------------------------------------------------------------------------
# Requests


@dataclass(frozen=True, slots=True)
class MacroReadRequest(NativeRequest):
    """0x15, args ``first, last`` (inclusive; ``cnc_rdmacro(n)`` sends ``(n, n)``) [V]:
    :class:`ScaledValues`, one record per variable."""

    COMMAND: ClassVar[int] = NativeCommand.RDMACRO
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = ("first", "last")
    ANSWER: ClassVar[Any] = ScaledValues
    first: int
    last: int


@dataclass(frozen=True, slots=True)
class MacroWriteRequest(NativeRequest):
    """0x16, args ``(number, number, 0, 0, 8)``, extra: one :class:`ScaledNumber`
    (``cnc_wrmacro``) [V]: base 2 at 16i class, base 10 at 30i class, see
    :meth:`ScaledNumber.from_macro`. No answer data."""

    COMMAND: ClassVar[int] = NativeCommand.WRMACRO
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = ("number", "number", 0, 0, EXTRA_LENGTH)
    WRITE: ClassVar[bool] = True
    number: int
    value: ScaledNumber

    def extra(self) -> bytes:
        return self.value.encode()

    @classmethod
    def _extra_fields(cls, extra: bytes) -> dict[str, Any]:
        if len(extra) != ScaledNumber.SIZE:
            raise NativePayloadError(
                f"macro write carries {len(extra)} data bytes, expected 8", EW.LENGTH
            )
        return {"value": ScaledNumber.decode(extra)}


@dataclass(frozen=True, slots=True)
class MacroDoubleReadRequest(NativeRequest):
    """0xA7, args ``first, count`` (a count, not a last number; ``cnc_rdmacror2``) [V]:
    :class:`MacroDoubles`."""

    COMMAND: ClassVar[int] = NativeCommand.RDMACRO_DOUBLE
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = ("first", "count")
    ANSWER: ClassVar[Any] = MacroDoubles
    first: int
    count: int


@dataclass(frozen=True, slots=True)
class MacroDoubleWriteRequest(NativeRequest):
    """0xA8, args ``(number, 0, 0, 0, 8)``, extra: the IEEE double (``cnc_wrmacror2``) [V].

    ``value`` None writes a vacant variable (sent as a quiet NaN, this project's choice).
    No answer data.
    """

    COMMAND: ClassVar[int] = NativeCommand.WRMACRO_DOUBLE
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = ("number", 0, 0, 0, EXTRA_LENGTH)
    WRITE: ClassVar[bool] = True
    number: int
    value: float | None

    def extra(self) -> bytes:
        return _pack_double(self.value)

    @classmethod
    def _extra_fields(cls, extra: bytes) -> dict[str, Any]:
        if len(extra) != MacroDouble.SIZE:
            raise NativePayloadError(
                f"macro double write carries {len(extra)} data bytes, expected 8", EW.LENGTH
            )
        return {"value": _unpack_double(extra, 0)}


_register(
    MacroReadRequest,
    MacroWriteRequest,
    MacroDoubleReadRequest,
    MacroDoubleWriteRequest,
)
