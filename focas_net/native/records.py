"""The data records of the native protocol: what answer blocks (and write requests) carry.

This module holds the records every area uses (:class:`NoData`, the 8-byte
:class:`ScaledNumber` and its runs) and those of the CNC's identity, status, program numbers
and alarms; the records of parameters and diagnostics, macro variables, the PMC and the axes
are declared with their requests in :mod:`.items`, :mod:`.macros`, :mod:`.pmc` and
:mod:`.axes`.

Each fixed record is declared once on :class:`~focas_net.native.base.NativeRecord` (a
big-endian ``FORMAT`` and its fields give both ``encode`` and ``decode``); the variable answers
are runs of them (:class:`~focas_net.native.base.RecordArray`) or a head followed by a number
of value slots. The FOCAS function each one serves is named in its docstring; "[V]" marks what
FANUC's library (libfwlib32 1.0.5) was seen to accept and read back, "[I]" what is inferred.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from decimal import Decimal
from typing import ClassVar, Final, Self

from focas_net.errors import EW

from .base import NativePayloadError, NativeRecord, RecordArray, check_multiple
from .binfloat import binary_to_decimal, decimal_to_binary

__all__ = [
    "SCALED_SIZE",
    "VACANT",
    "AlarmHistoryRecord",
    "AlarmMessage",
    "AlarmMessageHead",
    "AlarmMessages",
    "AlarmStatus",
    "CncId",
    "ExecutingProgram",
    "HdckStatus",
    "NativeAlarmHistory",
    "NativeProgramNumbers",
    "NativeSysInfo",
    "NoData",
    "ScaledNumber",
    "ScaledValues",
    "SequenceNumber",
    "StatInfo",
    "TimerValue",
    "TmModeStatus",
]


@dataclass(frozen=True, slots=True)
class NoData(NativeRecord):
    """The empty answer of a write (``cnc_wrmacro``, ``cnc_wrparam``, ``pmc_wrpmcrng``...)."""


# --------------------------------------------------------------------------------------------
# Identity and status


@dataclass(frozen=True, slots=True)
class NativeSysInfo(NativeRecord):
    """``cnc_sysinfo`` (0x18): ODBSYS, 18 bytes; the texts are fixed-width ASCII (space padded).

    FANUC's library asks it once per path while connecting and answers ``cnc_sysinfo`` from
    what it stored (nothing goes on the wire then) [V]. A 0i-D answers ``" 0"``, ``" M"``,
    ``"D4G3"``, ``"28.0"``, ``"03"``.
    """

    FORMAT: ClassVar[str] = ">hh2s2s4s4s2s"
    TEXT: ClassVar[frozenset[str]] = frozenset({"cnc_type", "mt_type", "series", "version", "axes"})
    addinfo: int
    max_axis: int
    cnc_type: str
    mt_type: str
    series: str
    version: str
    axes: str


@dataclass(frozen=True, slots=True)
class StatInfo(NativeRecord):
    """``cnc_statinfo`` (0x19): 7 x i16 ``aut, run, motion, mstb, emergency, alarm, edit`` (the
    ODBST fields after ``hdck`` and ``tmmode``, which come from 0xE1 and 0x98) [V]."""

    FORMAT: ClassVar[str] = ">7h"
    aut: int
    run: int
    motion: int
    mstb: int
    emergency: int
    alarm: int
    edit: int


@dataclass(frozen=True, slots=True)
class HdckStatus(NativeRecord):
    """``cnc_statinfo`` (0xE1): i16, ODBST ``hdck`` (handle retrace status). If this block
    answers EW_FUNC the library still returns EW_OK with hdck = 0 [V]."""

    FORMAT: ClassVar[str] = ">h"
    hdck: int


@dataclass(frozen=True, slots=True)
class TmModeStatus(NativeRecord):
    """``cnc_statinfo`` (0x98): i16, ODBST ``tmmode`` (T/M mode); EW_FUNC gives 0 [V]."""

    FORMAT: ClassVar[str] = ">h"
    tmmode: int


@dataclass(frozen=True, slots=True)
class CncId(NativeRecord):
    """``cnc_rdcncid`` (0xE8): the CNC ID, 4 x u32 [V]."""

    FORMAT: ClassVar[str] = ">4I"
    id1: int
    id2: int
    id3: int
    id4: int


@dataclass(frozen=True, slots=True)
class TimerValue(NativeRecord):
    """``cnc_rdtimer`` (0x120): IODBTIME ``i32 minute, i32 msec`` [V]."""

    FORMAT: ClassVar[str] = ">ii"
    minute: int
    msec: int


# --------------------------------------------------------------------------------------------
# Programs and alarms


@dataclass(frozen=True, slots=True)
class NativeProgramNumbers(NativeRecord):
    """``cnc_rdprgnum`` / ``cnc_rdprgnumo8`` (0x1C): ``i32 running, i32 main`` [V]. ODBPRO has
    short fields, so ``cnc_rdprgnum`` keeps the low 16 bits; ODBPROO8 keeps all 32."""

    FORMAT: ClassVar[str] = ">ii"
    running: int
    main: int


@dataclass(frozen=True, slots=True)
class SequenceNumber(NativeRecord):
    """``cnc_rdseqnum`` and ``cnc_rddynamic2`` (0x1D): ``i32`` sequence number [V]."""

    FORMAT: ClassVar[str] = ">i"
    number: int


@dataclass(frozen=True, slots=True)
class ExecutingProgram(NativeRecord):
    """``cnc_exeprgname`` (0xCF): ``i32 o_num``, then the name in 36 NUL-padded bytes [V]
    (ODBEXEPRG holds them the other way round: name, then o_num at offset 36)."""

    FORMAT: ClassVar[str] = ">i36s"
    PADDED: ClassVar[frozenset[str]] = frozenset({"name"})
    o_num: int
    name: bytes


@dataclass(frozen=True, slots=True)
class AlarmStatus(NativeRecord):
    """``cnc_alarm`` / ``cnc_alarm2`` and ``cnc_rddynamic2`` (0x1A): ``i32`` alarm bits [V].
    ``cnc_alarm`` (ODBALM.data, a short) keeps the low 16 bits, ``cnc_alarm2`` all 32."""

    FORMAT: ClassVar[str] = ">i"
    alarm: int


@dataclass(frozen=True, slots=True)
class AlarmMessageHead(NativeRecord):
    """Head of one 0x23 entry: ``i32 number, i32 type, i32 axis, i32 message length``."""

    FORMAT: ClassVar[str] = ">iiii"
    number: int
    alarm_type: int
    axis: int
    length: int


@dataclass(frozen=True, slots=True)
class AlarmMessage:
    """One alarm entry of 0x23: number, type, axis and the message bytes (ASCII on this side)."""

    number: int
    alarm_type: int
    axis: int
    message: bytes


@dataclass(frozen=True, slots=True)
class AlarmMessages:
    """``cnc_rdalmmsg`` / ``cnc_rdalmmsg2`` (0x23): per entry an :class:`AlarmMessageHead`,
    then a text field of exactly ``text_length`` bytes (the request's 4th argument: 32 for
    ``cnc_rdalmmsg``, 64 for ``cnc_rdalmmsg2``), the message then zero padding [V]. No active
    alarm is zero bytes; the library counts the entries from the data length."""

    alarms: tuple[AlarmMessage, ...]

    def encode(self, text_length: int) -> bytes:
        if text_length < 0:
            raise ValueError(f"text_length must not be negative, got {text_length}")
        parts: list[bytes] = []
        for a in self.alarms:
            if len(a.message) > text_length:
                raise ValueError(f"message of {len(a.message)} bytes exceeds {text_length}")
            head = AlarmMessageHead(a.number, a.alarm_type, a.axis, len(a.message))
            parts.append(head.encode())
            parts.append(a.message.ljust(text_length, b"\x00"))
        return b"".join(parts)

    @classmethod
    def decode(cls, data: bytes, text_length: int) -> Self:
        if text_length < 0:
            raise ValueError(f"text_length must not be negative, got {text_length}")
        size = AlarmMessageHead.SIZE + text_length
        check_multiple(data, size, "AlarmMessages")
        alarms = []
        for pos in range(0, len(data), size):
            head = AlarmMessageHead.decode_from(data, pos)
            if not 0 <= head.length <= text_length:
                raise NativePayloadError(
                    f"AlarmMessages: message length {head.length} outside 0..{text_length}",
                    EW.LENGTH,
                )
            start = pos + AlarmMessageHead.SIZE
            message = bytes(data[start : start + head.length])
            alarms.append(AlarmMessage(head.number, head.alarm_type, head.axis, message))
        return cls(tuple(alarms))


@dataclass(frozen=True, slots=True)
class AlarmHistoryRecord(NativeRecord):
    """One 60-byte record of ``cnc_rdalmhistry`` (0x6C) [V]: ``i32 alarm_no, i32 group,
    i32 axis, u16 year, month, day, hour, minute, second, i32 length, char message[32]``.

    ODBAHIS gets alm_no, alm_grp, axis_no (a char), the year mod 100, the date and time, and
    len_msg from the low byte of ``length``, sign-extended.
    """

    FORMAT: ClassVar[str] = ">iiiHHHHHHi32s"
    PADDED: ClassVar[frozenset[str]] = frozenset({"text"})
    alarm_no: int
    group: int
    axis: int
    year: int
    month: int
    day: int
    hour: int
    minute: int
    second: int
    length: int
    text: bytes

    @property
    def message(self) -> bytes:
        """The message: the first ``length`` bytes of the text field."""
        return self.text[: max(self.length, 0)]


@dataclass(frozen=True, slots=True)
class NativeAlarmHistory(RecordArray[AlarmHistoryRecord]):
    """``cnc_rdalmhistry`` (0x6C): a run of :class:`AlarmHistoryRecord`; the library counts
    them from the data length (length / 60) and asks at most 23 per request [V]."""

    ITEM: ClassVar[type[NativeRecord]] = AlarmHistoryRecord
    records: tuple[AlarmHistoryRecord, ...]


# --------------------------------------------------------------------------------------------
# The 8-byte number record


@dataclass(frozen=True, slots=True)
class ScaledNumber(NativeRecord):
    """The 8-byte number record: ``i32 mantissa, i16 base, i16 decimals``.

    With base 10 the value is ``mantissa / 10**decimals``; FANUC's library also takes any other
    base as a **binary** record, value ``mantissa / 2**decimals`` (16i-class ``cnc_wrmacro``
    sends base 2), converted to decimal as :meth:`to_macro` does [V]. A vacant macro variable
    is ``decimals = -1`` (bytes 6..7 = FF FF) with mantissa 0 (base 10 or 0 both work) [V].
    It carries macros (0x15, 0x16), feed and speed (0x24, 0x25), positions (0x26), spindle
    load (0x40), servo meters (0x56) and the value slots of 30i parameters (0x8D, 0x8E) and
    diagnostics (0x93).
    """

    FORMAT: ClassVar[str] = ">ihh"
    WIRE: ClassVar[tuple[str, ...]] = ("mantissa", "base", "decimals")
    mantissa: int
    decimals: int
    base: int = 10

    @property
    def vacant(self) -> bool:
        return self.decimals == -1

    def to_float(self) -> float | None:
        """The value, or None when vacant."""
        if self.vacant:
            return None
        if self.base == 0:
            return float(self.mantissa)
        return float(self.mantissa / self.base**self.decimals)

    @property
    def binary(self) -> bool:
        """Whether FANUC's library reads this record as binary (any base but 10)."""
        return self.base != 10

    def to_decimal(self) -> Decimal | None:
        """The exact value (binary records included), or None when vacant."""
        if self.vacant:
            return None
        if self.binary:
            scale = Decimal(2) ** -self.decimals
            return Decimal(self.mantissa) * scale
        return Decimal(self.mantissa).scaleb(-self.decimals)

    def to_macro(self) -> tuple[int, int]:
        """``(mcr_val, dec_val)`` as ``cnc_rdmacro`` reports this record [V]: a base-10 record
        as it is (vacant: ``(0, -1)``), a binary one with nine significant digits
        (``62C28F5C 0002 001B`` -> ``(123450000, 7)``), see :mod:`.binfloat`."""
        if not self.binary:
            return (self.mantissa, self.decimals)
        return binary_to_decimal(self.mantissa, self.decimals)

    @classmethod
    def from_macro(cls, mcr_val: int, dec_val: int, *, binary: bool = False) -> Self:
        """The record ``cnc_wrmacro(mcr_val, dec_val)`` sends [V]: base 10 as given on a
        30i-class handle (``binary=False``); on a 16i-class handle (``binary=True``) a base-2
        record with the mantissa normalised to ``2**30 <= |m| < 2**31`` (12.345 ->
        ``62C28F5C 0002 001B``)."""
        if not binary:
            return cls(mcr_val, dec_val, 10)
        mantissa, exponent = decimal_to_binary(mcr_val, dec_val)
        return cls(mantissa, exponent, 2)

    @classmethod
    def from_float(cls, value: float, decimals: int) -> Self:
        """``value`` rounded to ``decimals`` places (0..9); ValueError if it does not fit."""
        if not 0 <= decimals <= 9:
            raise ValueError(f"decimals must be 0..9, got {decimals}")
        if not math.isfinite(value):
            raise ValueError(f"{value} cannot be sent as a scaled number")
        mantissa = round(value * 10**decimals)
        if not -(2**31) <= mantissa < 2**31:
            raise ValueError(f"{value} with {decimals} decimals does not fit 32 bits")
        return cls(mantissa, decimals)


#: The record of a vacant variable.
VACANT: Final = ScaledNumber(0, -1)
SCALED_SIZE: Final = ScaledNumber.SIZE
_SCALED: Final = ScaledNumber.STRUCT


@dataclass(frozen=True, slots=True)
class ScaledValues:
    """Consecutive 8-byte :class:`ScaledNumber` records: ``cnc_rdmacro`` (0x15, one per
    variable), ``cnc_actf`` / ``cnc_acts`` (0x24 / 0x25, one), the positions of
    ``cnc_absolute`` / ``cnc_machine`` / ``cnc_relative`` / ``cnc_distance`` /
    ``cnc_rdposition`` / ``cnc_rddynamic2`` (0x26, one per axis; FANUC's library counts them
    from the data length), ``cnc_rdspload`` (0x40, one per spindle) and ``cnc_rdsvmeter``
    (0x56, one per axis) [V]."""

    values: tuple[ScaledNumber, ...]

    def encode(self) -> bytes:
        return ScaledNumber.encode_many(self.values)

    @classmethod
    def decode(cls, data: bytes) -> Self:
        check_multiple(data, SCALED_SIZE, "ScaledValues")
        return cls(ScaledNumber.decode_many(data))

    @staticmethod
    def mantissas(data: bytes, count: int) -> tuple[int, ...]:
        """The mantissas of the first ``count`` records of ``data`` (all of them when it holds
        fewer), the records not made: the positions of a path's axes in an answer sized for
        the CNC's most axes, read at every poll."""
        check_multiple(data, SCALED_SIZE, "ScaledValues")
        return tuple(v[0] for v in ScaledNumber.STRUCT.iter_unpack(data[: count * SCALED_SIZE]))
