"""The data records of the native protocol: what answer blocks (and write requests) carry.

Each fixed record is declared once on :class:`~focas_net.native.base.NativeRecord` (a
big-endian ``FORMAT`` and its fields give both ``encode`` and ``decode``); the variable answers
are runs of them (:class:`~focas_net.native.base.RecordArray`) or a head followed by a number
of value slots. The FOCAS function each one serves is named in its docstring; "[V]" marks what
FANUC's library (libfwlib32 1.0.5) was seen to accept and read back, "[I]" what is inferred.
"""

from __future__ import annotations

import enum
import math
import struct
from collections.abc import Sequence
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
    "AxisCount",
    "AxisDisplay",
    "AxisDisplays",
    "AxisName",
    "AxisNames",
    "AxisUnit",
    "AxisUnits",
    "CncId",
    "DiagType",
    "ExecutingProgram",
    "HdckStatus",
    "ItemHead",
    "ItemRecord",
    "ItemValues",
    "MacroDouble",
    "MacroDoubles",
    "NativeAlarmHistory",
    "NativePmcData",
    "NativeProgramNumbers",
    "NativeSysInfo",
    "NoData",
    "ParamInfo",
    "ParamInfo3",
    "ParamInfoEntry",
    "ParamType",
    "PmcDataType",
    "PositionAxisName",
    "PositionAxisNames",
    "ScaledItemRecord",
    "ScaledItemValues",
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


@dataclass(frozen=True, slots=True)
class AxisCount(NativeRecord):
    """0xA4, 30i class (answer version >= 3): ``u16`` count of the path's controlled axes
    (argument 0, ``cnc_rdposition``), spindles (1, ``cnc_rdspload``) or servo axes (2,
    ``cnc_rdsvmeter``). Two bytes are enough for FANUC's library [V]; a spindle count of 0 makes
    ``cnc_rdspload`` return EW_NOOPT [I]."""

    FORMAT: ClassVar[str] = ">H"
    count: int


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
# The 8-byte number record and macro variables


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
# Parameters and diagnostics


class ParamType(enum.IntEnum):
    """The ``type`` word of parameter records (0x0E, 0x0F, 0x8D, 0x8E) and of the 0x10
    attribute word, as FANUC's library reads them [V]: it copies 1 byte per slot for BIT and
    BYTE, 2 for WORD, 4 for TWO_WORD, and a value/decimals pair for REAL; any other type (5...)
    copies nothing. At 16i class ``cnc_wrparam`` refuses every length with EW_LENGTH when 0x10
    answers REAL, so REAL parameters are written only at 30i class (0xA0 type 4)."""

    BIT = 0
    BYTE = 1
    WORD = 2
    TWO_WORD = 3
    REAL = 4

    @classmethod
    def for_width(cls, width: int) -> ParamType:
        """The type of an integer value of ``width`` bytes (1, 2 or 4)."""
        return _PARAM_BY_WIDTH[width]


_PARAM_BY_WIDTH: Final = {1: ParamType.BYTE, 2: ParamType.WORD, 4: ParamType.TWO_WORD}


class DiagType(enum.IntEnum):
    """The ``type`` word of diagnostic records (0x30, 0x93) [V]: 0 byte, 1 word, 2 two-word,
    5 real (a value/decimals pair). FANUC's library reads 3 and 4 as a byte, on both
    commands."""

    BYTE = 0
    WORD = 1
    TWO_WORD = 2
    REAL = 5

    @classmethod
    def for_width(cls, width: int) -> DiagType:
        """The type of an integer value of ``width`` bytes (1, 2 or 4)."""
        return _DIAG_BY_WIDTH[width]


_DIAG_BY_WIDTH: Final = {1: DiagType.BYTE, 2: DiagType.WORD, 4: DiagType.TWO_WORD}


@dataclass(frozen=True, slots=True)
class ItemHead(NativeRecord):
    """The 8-byte head of a parameter/diagnostic record: ``i32 number, i16 axis, i16 type``.

    FANUC's library puts the low 16 bits of ``number`` in ``datano`` and the ``axis`` word in
    the struct's ``type`` field (0 non-axis, n one axis, -1 all) [V].
    """

    FORMAT: ClassVar[str] = ">ihh"
    number: int
    axis: int
    type: int


_ITEM_HEAD: Final = ItemHead.STRUCT
_I32: Final = struct.Struct(">i")


@dataclass(frozen=True, slots=True)
class ItemRecord:
    """One parameter/diagnostic record with 4-byte slots, 16i class (0x0E, 0x30, 0x0F).

    :class:`ItemHead`, then ``i32`` slots: one per axis up to the CNC's max axes (a byte or word
    value sign-extended; FANUC's library copies 1, 2 or 4 bytes of each slot by the type, slot
    0 for a single axis, slots 0..axes-1 for all axes) [V]. A REAL value takes **two** slots,
    a :class:`ScaledNumber` split in two i32 (value, then base and decimals; the base is
    ignored) [V]: see :meth:`real` and :meth:`reals`.
    """

    number: int
    axis: int
    type: int
    values: tuple[int, ...]

    @classmethod
    def real(
        cls, number: int, axis: int, values: Sequence[ScaledNumber], slots: int, type: int = 4
    ) -> Self:
        """A REAL record: each value in two slots, zero slots up to ``slots``."""
        flat: list[int] = []
        for v in values:
            flat.append(v.mantissa)
            flat.append(_I32.unpack(struct.pack(">hh", v.base, v.decimals))[0])
        if len(flat) > slots:
            raise ValueError(f"{len(values)} real values need {len(flat)} slots, not {slots}")
        return cls(number, axis, type, tuple(flat + [0] * (slots - len(flat))))

    def reals(self) -> tuple[ScaledNumber, ...]:
        """The slots read as REAL pairs."""
        out = []
        for i in range(0, len(self.values) - 1, 2):
            base, decimals = struct.unpack(">hh", _I32.pack(self.values[i + 1]))
            out.append(ScaledNumber(self.values[i], decimals, base))
        return tuple(out)

    def encode(self) -> bytes:
        """Head and slots (the extra of a 0x0F write)."""
        try:
            return _ITEM_HEAD.pack(self.number, self.axis, self.type) + struct.pack(
                f">{len(self.values)}i", *self.values
            )
        except struct.error as exc:
            raise ValueError(f"ItemRecord: {exc}") from None

    @classmethod
    def decode(cls, data: bytes) -> Self:
        """One record; its slot count is taken from the length."""
        if len(data) < ItemHead.SIZE:
            raise NativePayloadError(f"ItemRecord: {len(data)} bytes", EW.LENGTH)
        check_multiple(data[ItemHead.SIZE :], 4, "ItemRecord slots")
        head = ItemHead.decode_from(data)
        count = (len(data) - ItemHead.SIZE) // 4
        values = struct.unpack_from(f">{count}i", data, ItemHead.SIZE)
        return cls(head.number, head.axis, head.type, values)


@dataclass(frozen=True, slots=True)
class ItemValues:
    """``cnc_rdparam`` (0x0E) and ``cnc_diagnoss`` (0x30), 16i class: ``records``, each
    ``8 + 4 * slots`` bytes (slots = the CNC's max axes)."""

    records: tuple[ItemRecord, ...]

    def encode(self, max_axis: int | None = None) -> bytes:
        """The records, each with ``max_axis`` slots (default: as many as the first has)."""
        parts: list[bytes] = []
        if max_axis is None and self.records:
            max_axis = len(self.records[0].values)
        for r in self.records:
            if len(r.values) != max_axis:
                raise ValueError(f"record {r.number} has {len(r.values)} slots, not {max_axis}")
            parts.append(r.encode())
        return b"".join(parts)

    @classmethod
    def decode(cls, data: bytes, max_axis: int) -> Self:
        if max_axis < 1:
            raise ValueError(f"max_axis must be positive, got {max_axis}")
        size = ItemHead.SIZE + 4 * max_axis
        check_multiple(data, size, "ItemValues")
        slots = struct.Struct(f">{max_axis}i")
        records = []
        for pos in range(0, len(data), size):
            number, axis, kind = _ITEM_HEAD.unpack_from(data, pos)
            values = slots.unpack_from(data, pos + ItemHead.SIZE)
            records.append(ItemRecord(number, axis, kind, values))
        return cls(tuple(records))


@dataclass(frozen=True, slots=True)
class ScaledItemRecord:
    """One parameter/diagnostic record with 8-byte slots, 30i class (0x8D, 0x93, 0x8E): the
    :class:`ItemHead`, then one :class:`ScaledNumber` per axis up to max axes [V].

    FANUC's library takes the mantissa of each slot (and the decimals for REAL). In a 0x8E
    write it sends ``(value, 0, -1)`` for integer types and ``(value, 10, decimals)`` for REAL.
    """

    number: int
    axis: int
    type: int
    values: tuple[ScaledNumber, ...]

    def encode(self) -> bytes:
        """Head and slots (the extra of a 0x8E write)."""
        try:
            head = _ITEM_HEAD.pack(self.number, self.axis, self.type)
        except struct.error as exc:
            raise ValueError(f"ScaledItemRecord: {exc}") from None
        return head + ScaledNumber.encode_many(self.values)

    @classmethod
    def decode(cls, data: bytes) -> Self:
        """One record; its slot count is taken from the length."""
        if len(data) < ItemHead.SIZE:
            raise NativePayloadError(f"ScaledItemRecord: {len(data)} bytes", EW.LENGTH)
        head = ItemHead.decode_from(data)
        values = ScaledNumber.decode_many(data[ItemHead.SIZE :])
        return cls(head.number, head.axis, head.type, values)


@dataclass(frozen=True, slots=True)
class ScaledItemValues:
    """``cnc_rdparam`` (0x8D) and ``cnc_diagnoss`` (0x93), 30i class: ``records``, each
    ``8 + 8 * slots`` bytes."""

    records: tuple[ScaledItemRecord, ...]

    def encode(self, max_axis: int | None = None) -> bytes:
        """The records, each with ``max_axis`` slots (default: as many as the first has)."""
        parts: list[bytes] = []
        if max_axis is None and self.records:
            max_axis = len(self.records[0].values)
        for r in self.records:
            if len(r.values) != max_axis:
                raise ValueError(f"record {r.number} has {len(r.values)} slots, not {max_axis}")
            parts.append(r.encode())
        return b"".join(parts)

    @classmethod
    def decode(cls, data: bytes, max_axis: int) -> Self:
        if max_axis < 1:
            raise ValueError(f"max_axis must be positive, got {max_axis}")
        size = ItemHead.SIZE + SCALED_SIZE * max_axis
        check_multiple(data, size, "ScaledItemValues")
        return cls(
            tuple(
                ScaledItemRecord.decode(data[pos : pos + size]) for pos in range(0, len(data), size)
            )
        )


@dataclass(frozen=True, slots=True)
class ParamInfoEntry(NativeRecord):
    """One entry of 0x10: ``i32 number, i32 attribute``. Attribute bits 0-1 are the type (0 bit,
    1 byte, 2 word, 3 two-word), bit 8 marks an axis parameter [V] (answer it 0: with bit 8 set
    ``cnc_wrparam`` refused some lengths)."""

    FORMAT: ClassVar[str] = ">ii"
    number: int
    attribute: int

    @property
    def type(self) -> int:
        return self.attribute & 3

    @property
    def axis(self) -> bool:
        return bool(self.attribute & 0x100)


@dataclass(frozen=True, slots=True)
class ParamInfo:
    """``cnc_rdparainfo`` and ``cnc_wrparam`` (0x10, both classes): ``i32 prev_no,
    i32 next_no``, then one :class:`ParamInfoEntry` per parameter [V]. ``cnc_wrparam`` asks one
    (``(n, 1)``) and needs exactly 16 bytes; ``cnc_rdparainfo`` fills ODBPARAIF with info_no =
    the number of entries, prev_no and next_no from the low 16 bits, and each entry's number and
    attribute (low 16 bits) [V]."""

    prev_no: int
    next_no: int
    entries: tuple[ParamInfoEntry, ...]

    def encode(self) -> bytes:
        try:
            head = struct.pack(">ii", self.prev_no, self.next_no)
        except struct.error as exc:
            raise ValueError(f"ParamInfo: {exc}") from None
        return head + ParamInfoEntry.encode_many(self.entries)

    @classmethod
    def decode(cls, data: bytes) -> Self:
        if len(data) < 8:
            raise NativePayloadError(f"ParamInfo: {len(data)} bytes", EW.LENGTH)
        prev_no, next_no = struct.unpack_from(">ii", data)
        return cls(prev_no, next_no, ParamInfoEntry.decode_many(data[8:]))


@dataclass(frozen=True, slots=True)
class ParamInfo3(NativeRecord):
    """``cnc_wrparam``, 30i class (0xA0): 28 bytes [V for the size]. FANUC's library reads only
    ``type`` (u16 at 12: 0 bit .. 4 real) and ``axis_kind`` (u16 at 14: 2 for an axis
    parameter) [V]. The first three words are named after 0x10's, which they are in the same
    place [I]; the last 12 bytes are unknown (zero works)."""

    FORMAT: ClassVar[str] = ">iiiHH12s"
    prev_no: int
    next_no: int
    number: int
    type: int
    axis_kind: int
    reserved: bytes = bytes(12)


# --------------------------------------------------------------------------------------------
# PMC


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
# Axis names, units and display flags


@dataclass(frozen=True, slots=True)
class AxisName(NativeRecord):
    """One 4-byte axis name of 0x89 with argument 0 (``cnc_rdaxisname``, ``cnc_rdsvmeter``):
    ``name, suffix, suffix2, reserve``, one character each [V]. ``cnc_rdaxisname`` copies name
    and suffix; ``cnc_rdsvmeter`` fills LOADELM name and suff1, and suff2 only at 30i class."""

    FORMAT: ClassVar[str] = ">cccc"
    name: bytes
    suffix: bytes = b"\x00"
    suffix2: bytes = b"\x00"
    reserve: bytes = b"\x00"


@dataclass(frozen=True, slots=True)
class AxisNames(RecordArray[AxisName]):
    """0x89 with argument 0: one :class:`AxisName` per axis [V]."""

    ITEM: ClassVar[type[NativeRecord]] = AxisName
    records: tuple[AxisName, ...]


@dataclass(frozen=True, slots=True)
class PositionAxisName(NativeRecord):
    """One 16-byte entry of 0x89 with argument -1 (``cnc_rdposition``): four 4-byte names
    [V]. ``cnc_rdposition`` takes name and suffix of the absolute and distance positions from
    ``absolute``, of the machine position from ``machine`` and of the relative one from
    ``relative``; ``head`` is not read (unknown)."""

    FORMAT: ClassVar[str] = ">4s4s4s4s"
    head: bytes
    absolute: bytes
    machine: bytes
    relative: bytes

    @classmethod
    def of(cls, absolute: AxisName, machine: AxisName, relative: AxisName) -> Self:
        """The entry from three names (``head`` zero)."""
        return cls(bytes(4), absolute.encode(), machine.encode(), relative.encode())

    def names(self) -> tuple[AxisName, AxisName, AxisName, AxisName]:
        """``head, absolute, machine, relative`` as :class:`AxisName`."""
        return (
            AxisName.decode(self.head),
            AxisName.decode(self.absolute),
            AxisName.decode(self.machine),
            AxisName.decode(self.relative),
        )


@dataclass(frozen=True, slots=True)
class PositionAxisNames(RecordArray[PositionAxisName]):
    """0x89 with argument -1: one :class:`PositionAxisName` per axis [V]."""

    ITEM: ClassVar[type[NativeRecord]] = PositionAxisName
    records: tuple[PositionAxisName, ...]


@dataclass(frozen=True, slots=True)
class AxisUnit(NativeRecord):
    """One 4-byte entry of 0x88 (``cnc_rdposition``): two u16 units [V].

    16i class asks 0x88(2) and takes ``position`` for the absolute, relative and distance
    positions and ``machine`` for the machine position. 30i class asks 0x88(1) and 0x88(2) and
    takes ``position`` of 0x88(1) for absolute, relative and distance, and ``machine`` of
    0x88(2) for the machine position [V]. The other words are not read.
    """

    FORMAT: ClassVar[str] = ">HH"
    position: int
    machine: int


@dataclass(frozen=True, slots=True)
class AxisUnits(RecordArray[AxisUnit]):
    """0x88: one :class:`AxisUnit` per axis [V]."""

    ITEM: ClassVar[type[NativeRecord]] = AxisUnit
    records: tuple[AxisUnit, ...]


@dataclass(frozen=True, slots=True)
class AxisDisplay(NativeRecord):
    """One 4-byte entry of 0xA3 (``cnc_rdposition``, 30i class), per axis: display flags [V].

    Only the last byte, ``flags``, is read: it sets the ``disp`` words of the axis's four
    positions. Bit 0 shows the machine position, bit 1 the absolute and relative ones, bit 2
    the distance to go, bit 3 absolute, relative and distance; bits 4-7 and the first three
    bytes change nothing. Four zero bytes are accepted (every ``disp`` 0).
    """

    FORMAT: ClassVar[str] = ">3sB"
    reserved: bytes
    flags: int


@dataclass(frozen=True, slots=True)
class AxisDisplays(RecordArray[AxisDisplay]):
    """0xA3: one :class:`AxisDisplay` per axis."""

    ITEM: ClassVar[type[NativeRecord]] = AxisDisplay
    records: tuple[AxisDisplay, ...]
