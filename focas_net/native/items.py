"""Parameters and diagnostics over the native protocol: their records and their requests.

Two command sets, two record layouts: 16i class reads and writes records of 4-byte value slots
(0x0E, 0x0F, 0x30), 30i class records of 8-byte :class:`~.records.ScaledNumber` slots (0x8D,
0x8E, 0x93); ``cnc_wrparam`` first asks the parameter's type (0x10, 0xA0). "[V]" marks what
FANUC's library (libfwlib32 1.0.5) was seen to accept and read back, "[I]" what is inferred.
"""

from __future__ import annotations

import enum
import struct
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, ClassVar, Final, Self

from focas_net.errors import EW

from .base import NativePayloadError, NativeRecord, check_multiple
from .records import SCALED_SIZE, ScaledNumber
from .requests import EXTRA_LENGTH, NativeCommand, NativeRequest, _ArgSpec, _register

__all__ = [
    "DiagType",
    "Diagnostic3Request",
    "DiagnosticRequest",
    "ItemHead",
    "ItemRecord",
    "ItemValues",
    "ParamInfo",
    "ParamInfo3",
    "ParamInfo3Request",
    "ParamInfoEntry",
    "ParamInfoRequest",
    "ParamRead3Request",
    "ParamReadRequest",
    "ParamType",
    "ParamWrite3Request",
    "ParamWriteRequest",
    "ScaledItemRecord",
    "ScaledItemValues",
]


# --------------------------------------------------------------------------------------------
# Records


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


def _encode_records(
    records: Sequence[ItemRecord | ScaledItemRecord], max_axis: int | None
) -> bytes:
    """``records`` one after the other, each with ``max_axis`` slots (default: as many as the
    first has); ValueError if one has another count."""
    parts: list[bytes] = []
    if max_axis is None and records:
        max_axis = len(records[0].values)
    for r in records:
        if len(r.values) != max_axis:
            raise ValueError(f"record {r.number} has {len(r.values)} slots, not {max_axis}")
        parts.append(r.encode())
    return b"".join(parts)


@dataclass(frozen=True, slots=True)
class ItemValues:
    """``cnc_rdparam`` (0x0E) and ``cnc_diagnoss`` (0x30), 16i class: ``records``, each
    ``8 + 4 * slots`` bytes (slots = the CNC's max axes)."""

    records: tuple[ItemRecord, ...]

    def encode(self, max_axis: int | None = None) -> bytes:
        """The records, each with ``max_axis`` slots (default: as many as the first has)."""
        return _encode_records(self.records, max_axis)

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
        return _encode_records(self.records, max_axis)

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
# Requests


def _item_slots(data: bytes, slot: int, max_axes: int | None, single: bool) -> int:
    """Slots per record: ``max_axes`` when given, else (one record) from the data length."""
    if max_axes is not None:
        return max_axes
    if single and len(data) >= ItemHead.SIZE + slot:
        return (len(data) - ItemHead.SIZE) // slot
    raise ValueError("max_axes is needed to decode several records")


@dataclass(frozen=True, slots=True)
class ParamReadRequest(NativeRequest):
    """0x0E, args ``first, last, axis`` (``cnc_rdparam(n, axis)``, 16i class, sends
    ``(n, n, axis)``, axis 0, k or -1) [V]: :class:`ItemValues` (4-byte slots, type numbering
    :class:`ParamType`). FANUC's library also reads parameter 9968 with it while connecting
    (its "FOCAS option bits", low byte of slot 0) and 3115 in ``cnc_rdposition``."""

    COMMAND: ClassVar[int] = NativeCommand.RDPARAM
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = ("first", "last", "axis")
    ANSWER: ClassVar[Any] = ItemValues
    first: int
    last: int
    axis: int

    def decode_answer(self, data: bytes, max_axes: int | None = None) -> ItemValues:
        slots = _item_slots(data, 4, max_axes, self.first == self.last)
        return ItemValues.decode(data, max(slots, 1))


@dataclass(frozen=True, slots=True)
class ParamInfoRequest(NativeRequest):
    """0x10, args ``first, count`` (``cnc_wrparam`` at 16i class sends ``(n, 1)`` first;
    ``cnc_rdparainfo(s, n)`` sends ``(s, n)`` in both classes) [V]: :class:`ParamInfo`."""

    COMMAND: ClassVar[int] = NativeCommand.RDPARAINFO
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = ("first", "count")
    ANSWER: ClassVar[Any] = ParamInfo
    first: int
    count: int = 1


@dataclass(frozen=True, slots=True)
class ParamWriteRequest(NativeRequest):
    """0x0F, args ``(0, 0, 0, 0, 8 + 4 * max_axes)``, extra: one :class:`ItemRecord` with
    ``max_axes`` slots (``cnc_wrparam``, 16i class, after 0x10) [V]. The value sits
    sign-extended in slot 0 (one axis) or slots 0..axes-1; unused slots hold whatever the
    library's buffer held. No answer data."""

    COMMAND: ClassVar[int] = NativeCommand.WRPARAM
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = (0, 0, 0, 0, EXTRA_LENGTH)
    WRITE: ClassVar[bool] = True
    record: ItemRecord

    def extra(self) -> bytes:
        return self.record.encode()

    @classmethod
    def _extra_fields(cls, extra: bytes) -> dict[str, Any]:
        return {"record": ItemRecord.decode(extra)}


@dataclass(frozen=True, slots=True)
class ParamRead3Request(NativeRequest):
    """0x8D, args ``first, last, axis`` (``cnc_rdparam``, 30i class) [V]:
    :class:`ScaledItemValues` (8-byte slots)."""

    COMMAND: ClassVar[int] = NativeCommand.RDPARAM3
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = ("first", "last", "axis")
    ANSWER: ClassVar[Any] = ScaledItemValues
    first: int
    last: int
    axis: int

    def decode_answer(self, data: bytes, max_axes: int | None = None) -> ScaledItemValues:
        slots = _item_slots(data, 8, max_axes, self.first == self.last)
        return ScaledItemValues.decode(data, max(slots, 1))


@dataclass(frozen=True, slots=True)
class ParamInfo3Request(NativeRequest):
    """0xA0, args ``first, count`` (``cnc_wrparam``, 30i class, sends ``(n, 1)`` first) [V]:
    :class:`ParamInfo3` (28 bytes)."""

    COMMAND: ClassVar[int] = NativeCommand.RDPARAINFO3
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = ("first", "count")
    ANSWER: ClassVar[Any] = ParamInfo3
    first: int
    count: int = 1


@dataclass(frozen=True, slots=True)
class ParamWrite3Request(NativeRequest):
    """0x8E, args ``(0, 0, 0, 0, 8 + 8 * max_axes)``, extra: one :class:`ScaledItemRecord`
    with ``max_axes`` slots (``cnc_wrparam``, 30i class, after 0xA0) [V]. No answer data."""

    COMMAND: ClassVar[int] = NativeCommand.WRPARAM3
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = (0, 0, 0, 0, EXTRA_LENGTH)
    WRITE: ClassVar[bool] = True
    record: ScaledItemRecord

    def extra(self) -> bytes:
        return self.record.encode()

    @classmethod
    def _extra_fields(cls, extra: bytes) -> dict[str, Any]:
        return {"record": ScaledItemRecord.decode(extra)}


@dataclass(frozen=True, slots=True)
class DiagnosticRequest(NativeRequest):
    """0x30, args ``first, last, axis`` (``cnc_diagnoss``, 16i class) [V]: :class:`ItemValues`
    with the :class:`DiagType` numbering."""

    COMMAND: ClassVar[int] = NativeCommand.RDDIAG
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = ("first", "last", "axis")
    ANSWER: ClassVar[Any] = ItemValues
    first: int
    last: int
    axis: int

    def decode_answer(self, data: bytes, max_axes: int | None = None) -> ItemValues:
        slots = _item_slots(data, 4, max_axes, self.first == self.last)
        return ItemValues.decode(data, max(slots, 1))


@dataclass(frozen=True, slots=True)
class Diagnostic3Request(NativeRequest):
    """0x93, args ``first, last, axis`` (``cnc_diagnoss``, 30i class) [V]:
    :class:`ScaledItemValues` with the :class:`DiagType` numbering."""

    COMMAND: ClassVar[int] = NativeCommand.RDDIAG3
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = ("first", "last", "axis")
    ANSWER: ClassVar[Any] = ScaledItemValues
    first: int
    last: int
    axis: int

    def decode_answer(self, data: bytes, max_axes: int | None = None) -> ScaledItemValues:
        slots = _item_slots(data, 8, max_axes, self.first == self.last)
        return ScaledItemValues.decode(data, max(slots, 1))


_register(
    ParamReadRequest,
    ParamInfoRequest,
    ParamWriteRequest,
    ParamRead3Request,
    ParamInfo3Request,
    ParamWrite3Request,
    DiagnosticRequest,
    Diagnostic3Request,
)
