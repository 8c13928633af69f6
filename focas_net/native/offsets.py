"""Tool offsets, work zero offsets and tool life management over the native protocol: their
records, their requests and the frames FANUC's library sends for each function
(``cnc_rdtofs(...)``..., named after the FOCAS functions as in :mod:`.calls`, and, like
those, not in ``__all__``).

Both command sets send the same frames, but for ``cnc_rdtlinfo`` (0x4A with a fifth argument
of 0x10000 at 16i class, 0x1C4 at 30i class). "[V]" marks what FANUC's library (libfwlib32
1.0.5) was seen to send, accept and read back, "[I]" what is inferred.

Offset values travel as 8-byte :class:`~.records.ScaledNumber` records of which the library
takes the 32-bit mantissa alone (least input increments) [V]; this project answers them with
base 10 and 3 decimals [I]. The library's writes send ``(value, 0, -1)`` [V].
"""

from __future__ import annotations

import struct
from dataclasses import dataclass
from typing import Any, ClassVar, Final, Self

from focas_net.errors import EW

from .base import NativePayloadError, NativeRecord, RecordArray, check_multiple
from .calls import CommandSet, LibraryCall, _memoized, _one
from .records import ScaledNumber, ScaledValues
from .requests import EXTRA_LENGTH, NativeCommand, NativeRequest, _ArgSpec, _register

__all__ = [
    "SINGLE_TYPE",
    "TLINFO_16I",
    "OffsetWrite",
    "ToolEntry",
    "ToolGroupRecord",
    "ToolGroupRecords",
    "ToolGroupRequest",
    "ToolGroupsInUse",
    "ToolGroupsInUseRequest",
    "ToolLifeCounts",
    "ToolLifeCountsRequest",
    "ToolLifeInfoRequest",
    "ToolNumberRequest",
    "ToolNumbers",
    "ToolOffsetInfoRequest",
    "ToolOffsetMemory",
    "ToolOffsetRequest",
    "ToolOffsetWriteRequest",
    "WorkOffsetRequest",
    "WorkOffsetWriteRequest",
    "offset_type_of",
]

#: ``cnc_rdtofs`` and ``cnc_wrtofs`` send their offset type plus this [V] (``cnc_rdtofsr``
#: sends the type as it is); the CNC answers the type less it [I].
SINGLE_TYPE: Final = 1000
#: The fifth argument of 0x4A when ``cnc_rdtlinfo`` sends it (16i class) [V].
TLINFO_16I: Final = 0x10000
#: The record of a written offset value: ``(value, 0, -1)`` [V].
_WRITE_BASE: Final = 0
_WRITE_DECIMALS: Final = -1
#: The head of a 0x4D answer: the group and the index of its first tool.
_TOOL_HEAD: Final = struct.Struct(">ii")


def offset_type_of(sent: int) -> int | None:
    """The offset type a 0x08/0x09 block asks for: ``sent`` less :data:`SINGLE_TYPE` from
    ``cnc_rdtofs``/``cnc_wrtofs``, as it is from ``cnc_rdtofsr``; None for -1, every type."""
    if sent == -1:
        return None
    return sent - SINGLE_TYPE if sent >= SINGLE_TYPE else sent


# --------------------------------------------------------------------------------------------
# Records


@dataclass(frozen=True, slots=True)
class ToolOffsetMemory(NativeRecord):
    """0x0A (``cnc_rdtofsinfo``, ``cnc_rdtofsinfo2``): ``i32 count, i16 type, i16 enable``.
    ODBTLINF's ``use_no`` is the low 16 bits of ``count``, ``ofs_type`` is ``type``,
    ODBTLINF2's ``ofs_enable`` is ``enable`` [V]. This project answers type 2 (tool offset
    memory C) on a machining centre, 1 on a lathe, and enable 1 [I]."""

    FORMAT: ClassVar[str] = ">ihh"
    count: int
    type: int
    enable: int = 1


@dataclass(frozen=True, slots=True)
class ToolLifeCounts(NativeRecord):
    """0x4A and 0x1C4: ``i32 groups, max_groups, max_tools, max_minutes, max_cycles``.
    ``cnc_rdngrp`` reads ``groups``, ``cnc_rdmaxgrp`` and ``cnc_rdmaxtool`` the low 16 bits of
    ``max_groups`` and ``max_tools``, ``cnc_rdtlinfo`` (ODBTLINFO) the last four [V]."""

    FORMAT: ClassVar[str] = ">5i"
    groups: int
    max_groups: int
    max_tools: int
    max_minutes: int
    max_cycles: int


@dataclass(frozen=True, slots=True)
class ToolGroupsInUse(NativeRecord):
    """0x48 (``cnc_rdusegrpid``, ODBUSEGR): ``i32 next, use, select`` group numbers [V]; this
    project answers the group of the tool in use for all three [I]."""

    FORMAT: ClassVar[str] = ">3i"
    next: int
    use: int
    select: int


@dataclass(frozen=True, slots=True)
class ToolGroupRecord(NativeRecord):
    """One 24-byte group of 0x8B: ``i32 group, tools, reserved, life, reserved2, count``.
    ``cnc_rdntool`` reads ``tools``, ``cnc_rdlife`` ``life``, ``cnc_rdcount`` ``count`` (and
    ODBTLIFE3's ``datano`` the low 16 bits of ``group``); ``cnc_rdtoolgrp`` all of them [V].
    The reserved words are not read by the library; this project sends 0 [I]."""

    FORMAT: ClassVar[str] = ">6i"
    group: int
    tools: int
    reserved: int
    life: int
    reserved2: int
    count: int


@dataclass(frozen=True, slots=True)
class ToolGroupRecords(RecordArray[ToolGroupRecord]):
    """0x8B: one :class:`ToolGroupRecord` per group asked [V for one group]."""

    ITEM: ClassVar[type[NativeRecord]] = ToolGroupRecord
    records: tuple[ToolGroupRecord, ...]


@dataclass(frozen=True, slots=True)
class ToolEntry(NativeRecord):
    """One 16-byte tool of 0x4D: ``i32 number, h, d, state`` (T number, H and D codes, the
    tool information: 0 unused, 1 in use, 2 expired, 3 skipped) [V layout, I states]."""

    FORMAT: ClassVar[str] = ">4i"
    number: int
    h: int
    d: int
    state: int


@dataclass(frozen=True, slots=True)
class ToolNumbers:
    """0x4D: ``i32 group, i32 first`` (the group and the index of the first tool), then one
    :class:`ToolEntry` per tool asked [V]. ``cnc_toolnum`` reads ODBTLIFE4 ``datano`` (low 16
    bits of ``group``), ``type`` (of ``first``) and ``data`` (the first tool's T number);
    ``cnc_rdtoolgrp`` copies every entry into ODBTG ``data[]`` with ``tuse_num`` its index [V]."""

    group: int
    first: int
    tools: tuple[ToolEntry, ...]

    def encode(self) -> bytes:
        return _TOOL_HEAD.pack(self.group, self.first) + ToolEntry.encode_many(self.tools)

    @classmethod
    def decode(cls, data: bytes) -> Self:
        head = _TOOL_HEAD.size
        if len(data) < head:
            raise NativePayloadError(f"tool numbers: {len(data)} bytes", EW.LENGTH)
        body = data[head:]
        check_multiple(body, ToolEntry.SIZE, "ToolNumbers")
        group, first = _TOOL_HEAD.unpack_from(data)
        return cls(group, first, ToolEntry.decode_many(body))


@dataclass(frozen=True, slots=True)
class OffsetWrite:
    """The extra bytes of 0x09 and 0x0C: one ``(value, 0, -1)`` record per value [V]."""

    values: tuple[int, ...]

    def encode(self) -> bytes:
        return ScaledNumber.encode_many(
            ScaledNumber(v, _WRITE_DECIMALS, _WRITE_BASE) for v in self.values
        )

    @classmethod
    def decode(cls, data: bytes) -> Self:
        check_multiple(data, ScaledNumber.SIZE, "offset write")
        return cls(tuple(r.mantissa for r in ScaledNumber.decode_many(data)))


# --------------------------------------------------------------------------------------------
# Requests


class _OffsetWriteRequest(NativeRequest):
    """A write of offsets carrying its values as :class:`OffsetWrite` in the extra bytes."""

    __slots__ = ()
    values: OffsetWrite

    def extra(self) -> bytes:
        return self.values.encode()

    @classmethod
    def _extra_fields(cls, extra: bytes) -> dict[str, Any]:
        return {"values": OffsetWrite.decode(extra)}


@dataclass(frozen=True, slots=True)
class ToolOffsetRequest(NativeRequest):
    """0x08, args ``first, last, type`` [V]: ``cnc_rdtofs(n, t)`` sends ``(n, n, 1000 + t)``,
    ``cnc_rdtofsr(s, t, e)`` ``(s, e, t)`` with ``t = -1`` for every type. Answered with
    :class:`ScaledValues`, one record per number and type (by number, then type); the library
    takes each mantissa [V]."""

    COMMAND: ClassVar[int] = NativeCommand.RDTOFS
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = ("first", "last", "type")
    ANSWER: ClassVar[Any] = ScaledValues
    first: int
    last: int
    type: int


@dataclass(frozen=True, slots=True)
class ToolOffsetWriteRequest(_OffsetWriteRequest):
    """0x09, args ``(n, n, 1000 + type, 0, 8)``, extra: :class:`OffsetWrite` of one value
    (``cnc_wrtofs``) [V]. No answer data."""

    COMMAND: ClassVar[int] = NativeCommand.WRTOFS
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = ("first", "last", "type", 0, EXTRA_LENGTH)
    WRITE: ClassVar[bool] = True
    first: int
    last: int
    type: int
    values: OffsetWrite


@dataclass(frozen=True, slots=True)
class ToolOffsetInfoRequest(NativeRequest):
    """0x0A, no arguments: :class:`ToolOffsetMemory` (``cnc_rdtofsinfo``) [V]."""

    COMMAND: ClassVar[int] = NativeCommand.RDTOFSINFO
    ANSWER: ClassVar[Any] = ToolOffsetMemory


@dataclass(frozen=True, slots=True)
class WorkOffsetRequest(NativeRequest):
    """0x0B, args ``first, last, axis`` [V]: ``cnc_rdzofs(n, a)`` sends ``(n, n, a)``,
    ``cnc_rdzofsr(s, a, e)`` ``(s, e, a)``; number 0 is the external offset, 1..6 G54..G59,
    axis -1 every axis. Answered with :class:`ScaledValues`: for axis -1 the open answer's max
    axes records per number (FANUC's library refuses fewer; it copies the path's axes at 16i
    class, all max axes at 30i class), otherwise one per number [V]."""

    COMMAND: ClassVar[int] = NativeCommand.RDZOFS
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = ("first", "last", "axis")
    ANSWER: ClassVar[Any] = ScaledValues
    first: int
    last: int
    axis: int


@dataclass(frozen=True, slots=True)
class WorkOffsetWriteRequest(_OffsetWriteRequest):
    """0x0C, args ``(n, n, axis, 0, 8 * k)``, extra: :class:`OffsetWrite` of ``k`` values, max
    axes of them for axis -1 (``cnc_wrzofs``) [V]. No answer data."""

    COMMAND: ClassVar[int] = NativeCommand.WRZOFS
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = ("first", "last", "axis", 0, EXTRA_LENGTH)
    WRITE: ClassVar[bool] = True
    first: int
    last: int
    axis: int
    values: OffsetWrite


@dataclass(frozen=True, slots=True)
class ToolGroupsInUseRequest(NativeRequest):
    """0x48, no arguments: :class:`ToolGroupsInUse` (``cnc_rdusegrpid``) [V]."""

    COMMAND: ClassVar[int] = NativeCommand.RDUSEGRPID
    ANSWER: ClassVar[Any] = ToolGroupsInUse


@dataclass(frozen=True, slots=True)
class ToolLifeCountsRequest(NativeRequest):
    """0x4A, args ``(0, 0, 0, 0, mode)``: :class:`ToolLifeCounts` (``cnc_rdngrp``,
    ``cnc_rdmaxgrp``, ``cnc_rdmaxtool`` send mode 0; ``cnc_rdtlinfo`` at 16i class
    :data:`TLINFO_16I`) [V]."""

    COMMAND: ClassVar[int] = NativeCommand.RDNGRP
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = (0, 0, 0, 0, "mode")
    ANSWER: ClassVar[Any] = ToolLifeCounts
    mode: int = 0


@dataclass(frozen=True, slots=True)
class ToolLifeInfoRequest(NativeRequest):
    """0x1C4, no arguments: :class:`ToolLifeCounts` (``cnc_rdtlinfo``, 30i class) [V]."""

    COMMAND: ClassVar[int] = NativeCommand.RDTLINFO
    ANSWER: ClassVar[Any] = ToolLifeCounts


@dataclass(frozen=True, slots=True)
class ToolGroupRequest(NativeRequest):
    """0x8B, args ``first, last, 0`` (groups; the library sends ``(g, g, 0)``):
    :class:`ToolGroupRecords` [V]."""

    COMMAND: ClassVar[int] = NativeCommand.RDTOOLGRP
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = ("first", "last", 0)
    ANSWER: ClassVar[Any] = ToolGroupRecords
    first: int
    last: int


@dataclass(frozen=True, slots=True)
class ToolNumberRequest(NativeRequest):
    """0x4D, args ``group, first, last`` (tool indexes 1..; ``cnc_toolnum(g, n)`` sends
    ``(g, n, n)``, ``cnc_rdtoolgrp`` ``(g, 1, tools)`` after 0x8B): :class:`ToolNumbers` [V]."""

    COMMAND: ClassVar[int] = NativeCommand.TOOLNUM
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = ("group", "first", "last")
    ANSWER: ClassVar[Any] = ToolNumbers
    group: int
    first: int
    last: int


_register(
    ToolOffsetRequest,
    ToolOffsetWriteRequest,
    ToolOffsetInfoRequest,
    WorkOffsetRequest,
    WorkOffsetWriteRequest,
    ToolGroupsInUseRequest,
    ToolLifeCountsRequest,
    ToolLifeInfoRequest,
    ToolGroupRequest,
    ToolNumberRequest,
)


# --------------------------------------------------------------------------------------------
# What FANUC's library sends for each function (the same in both command sets unless named)


@_memoized
def cnc_rdtofs(cs: CommandSet, number: int, offset_type: int) -> LibraryCall:
    """0x08 ``(n, n, 1000 + type)`` [V]."""
    return _one("cnc_rdtofs", ToolOffsetRequest(number, number, SINGLE_TYPE + offset_type))


@_memoized
def cnc_rdtofsr(cs: CommandSet, first: int, offset_type: int, last: int) -> LibraryCall:
    """0x08 ``(s, e, type)`` [V]."""
    return _one("cnc_rdtofsr", ToolOffsetRequest(first, last, offset_type))


@_memoized
def cnc_wrtofs(cs: CommandSet, number: int, offset_type: int, value: int) -> LibraryCall:
    """0x09 ``(n, n, 1000 + type, 0, 8)`` + ``(value, 0, -1)`` [V]."""
    request = ToolOffsetWriteRequest(
        number, number, SINGLE_TYPE + offset_type, OffsetWrite((value,))
    )
    return _one("cnc_wrtofs", request)


@_memoized
def cnc_rdtofsinfo(cs: CommandSet) -> LibraryCall:
    """0x0A [V]."""
    return _one("cnc_rdtofsinfo", ToolOffsetInfoRequest())


@_memoized
def cnc_rdzofs(cs: CommandSet, number: int, axis: int) -> LibraryCall:
    """0x0B ``(n, n, axis)`` [V]."""
    return _one("cnc_rdzofs", WorkOffsetRequest(number, number, axis))


@_memoized
def cnc_rdzofsr(cs: CommandSet, first: int, axis: int, last: int) -> LibraryCall:
    """0x0B ``(s, e, axis)`` [V]."""
    return _one("cnc_rdzofsr", WorkOffsetRequest(first, last, axis))


@_memoized
def cnc_wrzofs(cs: CommandSet, number: int, axis: int, values: tuple[int, ...]) -> LibraryCall:
    """0x0C ``(n, n, axis, 0, 8 * k)`` + one ``(value, 0, -1)`` per value [V]."""
    return _one("cnc_wrzofs", WorkOffsetWriteRequest(number, number, axis, OffsetWrite(values)))


@_memoized
def cnc_rdusegrpid(cs: CommandSet) -> LibraryCall:
    """0x48 [V]."""
    return _one("cnc_rdusegrpid", ToolGroupsInUseRequest())


@_memoized
def cnc_rdngrp(cs: CommandSet) -> LibraryCall:
    """0x4A ``(0, 0, 0, 0, 0)`` [V]."""
    return _one("cnc_rdngrp", ToolLifeCountsRequest())


@_memoized
def cnc_rdmaxgrp(cs: CommandSet) -> LibraryCall:
    """0x4A ``(0, 0, 0, 0, 0)`` [V]."""
    return _one("cnc_rdmaxgrp", ToolLifeCountsRequest())


@_memoized
def cnc_rdmaxtool(cs: CommandSet) -> LibraryCall:
    """0x4A ``(0, 0, 0, 0, 0)`` [V]."""
    return _one("cnc_rdmaxtool", ToolLifeCountsRequest())


@_memoized
def cnc_rdtlinfo(cs: CommandSet) -> LibraryCall:
    """0x4A ``(0, 0, 0, 0, 0x10000)`` at 16i class, 0x1C4 at 30i class [V]."""
    if cs is CommandSet.FS16I:
        return _one("cnc_rdtlinfo", ToolLifeCountsRequest(TLINFO_16I))
    return _one("cnc_rdtlinfo", ToolLifeInfoRequest())


def _group_call(function: str, group: int) -> LibraryCall:
    return _one(function, ToolGroupRequest(group, group))


@_memoized
def cnc_rdntool(cs: CommandSet, group: int) -> LibraryCall:
    """0x8B ``(g, g, 0)`` [V]."""
    return _group_call("cnc_rdntool", group)


@_memoized
def cnc_rdlife(cs: CommandSet, group: int) -> LibraryCall:
    """0x8B ``(g, g, 0)`` [V]."""
    return _group_call("cnc_rdlife", group)


@_memoized
def cnc_rdcount(cs: CommandSet, group: int) -> LibraryCall:
    """0x8B ``(g, g, 0)`` [V]."""
    return _group_call("cnc_rdcount", group)


@_memoized
def cnc_rdtoolgrp(cs: CommandSet, group: int, tools: int = 0) -> LibraryCall:
    """0x8B ``(g, g, 0)``; then, in a frame of its own, 0x4D ``(group answered, 1, tools)``
    with the tool count 0x8B answered (``tools`` here; 0: the first frame alone) [V]."""
    if not tools:
        return _group_call("cnc_rdtoolgrp", group)
    return _one("cnc_rdtoolgrp", ToolNumberRequest(group, 1, tools))


@_memoized
def cnc_toolnum(cs: CommandSet, group: int, index: int) -> LibraryCall:
    """0x4D ``(g, n, n)`` [V]."""
    return _one("cnc_toolnum", ToolNumberRequest(group, index, index))
