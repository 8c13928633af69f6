"""Axes and spindles over the native protocol: positions, axis names, units, display flags and
counts, spindle loads and servo meters; their records and their requests.

The values themselves are runs of :class:`~.records.ScaledNumber` (:class:`~.records.ScaledValues`);
``cnc_rdposition`` also asks the names, units and, at 30i class, display flags and counts of
the axes. "[V]" marks what FANUC's library (libfwlib32 1.0.5) was seen to accept and read back,
"[I]" what is inferred.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass
from typing import Any, ClassVar, Final, Self

from .base import NativeRecord, RecordArray
from .records import ScaledValues
from .requests import NativeCommand, NativeRequest, _ArgSpec, _register

__all__ = [
    "AxisCount",
    "AxisCountRequest",
    "AxisDisplay",
    "AxisDisplayRequest",
    "AxisDisplays",
    "AxisName",
    "AxisNameRequest",
    "AxisNames",
    "AxisUnit",
    "AxisUnitRequest",
    "AxisUnits",
    "NativePositionKind",
    "NativePositionRequest",
    "PositionAxisName",
    "PositionAxisNames",
    "ServoMeterRequest",
    "SpindleLoadRequest",
    "resolve_position_kind",
]


# --------------------------------------------------------------------------------------------
# Records


@dataclass(frozen=True, slots=True)
class AxisCount(NativeRecord):
    """0xA4, 30i class (answer version >= 3): ``u16`` count of the path's controlled axes
    (argument 0, ``cnc_rdposition``), spindles (1, ``cnc_rdspload``; 3, ``cnc_rdspeed``) or
    servo axes (2, ``cnc_rdsvmeter``). Two bytes are enough for FANUC's library [V]; a spindle
    count of 0 makes ``cnc_rdspload`` return EW_NOOPT [I]."""

    FORMAT: ClassVar[str] = ">H"
    count: int


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


# --------------------------------------------------------------------------------------------
# Requests


class NativePositionKind(enum.Enum):
    """What a position read (0x26) asks for."""

    ABSOLUTE = "absolute"
    MACHINE = "machine"
    RELATIVE = "relative"
    DISTANCE = "distance"
    SKIP = "skip"


#: Both numberings FANUC's library sends [V]: 4/1/6/7 (``cnc_absolute``, ``cnc_machine``,
#: ``cnc_relative``, ``cnc_distance``, ``cnc_rddynamic2``; 8 skip from public captures) and
#: 0..3 (``cnc_rdposition``); 1 means the machine position in both.
_POSITION_KINDS: Final[dict[int, NativePositionKind]] = {
    0: NativePositionKind.ABSOLUTE,
    1: NativePositionKind.MACHINE,
    2: NativePositionKind.RELATIVE,
    3: NativePositionKind.DISTANCE,
    4: NativePositionKind.ABSOLUTE,
    6: NativePositionKind.RELATIVE,
    7: NativePositionKind.DISTANCE,
    8: NativePositionKind.SKIP,
}


def resolve_position_kind(code: int) -> NativePositionKind | None:
    """The position a 0x26 kind code asks for, or None for a code this codec does not know."""
    return _POSITION_KINDS.get(code)


@dataclass(frozen=True, slots=True)
class NativePositionRequest(NativeRequest):
    """0x26, args ``kind, axis`` (axis -1 = all axes, n = axis n) [V]: :class:`ScaledValues`,
    one record per axis (for -1 send max-axes records: ``cnc_rddynamic2`` packs its four
    arrays with a stride of the number received)."""

    COMMAND: ClassVar[int] = NativeCommand.POSITION
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = ("kind", "axis")
    ANSWER: ClassVar[Any] = ScaledValues
    kind: int
    axis: int = -1

    @property
    def position_kind(self) -> NativePositionKind | None:
        return resolve_position_kind(self.kind)


@dataclass(frozen=True, slots=True)
class AxisNameRequest(NativeRequest):
    """0x89, args ``kind``: 0 -> :class:`AxisNames` (4 bytes per axis; ``cnc_rdaxisname``,
    ``cnc_rdsvmeter``), -1 -> :class:`PositionAxisNames` (16 bytes per axis;
    ``cnc_rdposition``) [V]."""

    COMMAND: ClassVar[int] = NativeCommand.AXIS_NAME
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = ("kind",)
    ANSWER: ClassVar[Any] = AxisNames
    kind: int = 0

    def decode_answer(
        self, data: bytes, max_axes: int | None = None
    ) -> AxisNames | PositionAxisNames:
        if self.kind == -1:
            return PositionAxisNames.decode(data)
        return AxisNames.decode(data)


@dataclass(frozen=True, slots=True)
class AxisUnitRequest(NativeRequest):
    """0x88, args ``kind`` (``cnc_rdposition``: 2 at 16i class, 1 then 2 at 30i class) [V]:
    :class:`AxisUnits`."""

    COMMAND: ClassVar[int] = NativeCommand.AXIS_UNIT
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = ("kind",)
    ANSWER: ClassVar[Any] = AxisUnits
    kind: int = 2


@dataclass(frozen=True, slots=True)
class AxisCountRequest(NativeRequest):
    """0xA4, args ``kind``: 0 axes (``cnc_rdposition``), 1 spindles (``cnc_rdspload``), 2 servo
    axes (``cnc_rdsvmeter``), 30i class; sent before and after the read [V]:
    :class:`AxisCount`."""

    COMMAND: ClassVar[int] = NativeCommand.AXIS_COUNT
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = ("kind",)
    ANSWER: ClassVar[Any] = AxisCount
    kind: int = 0


@dataclass(frozen=True, slots=True)
class AxisDisplayRequest(NativeRequest):
    """0xA3, args ``(0, -1)`` (``cnc_rdposition``, 30i class) [V]: :class:`AxisDisplays`."""

    COMMAND: ClassVar[int] = NativeCommand.AXIS_DISPLAY
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = ("kind", "axis")
    ANSWER: ClassVar[Any] = AxisDisplays
    kind: int = 0
    axis: int = -1


@dataclass(frozen=True, slots=True)
class SpindleLoadRequest(NativeRequest):
    """0x40, args ``(figure, spindle)`` (``cnc_rdspload(sp)`` sends ``(0, sp)``, -1 all) [V]:
    :class:`ScaledValues`, one per spindle (``cnc_rdspload`` keeps the low 16 bits of each
    mantissa). ``kind`` selects the figure: :class:`~.spindles.SpindleFigure`."""

    COMMAND: ClassVar[int] = NativeCommand.RDSPLOAD
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = ("kind", "spindle")
    ANSWER: ClassVar[Any] = ScaledValues
    kind: int = 0
    spindle: int = -1


@dataclass(frozen=True, slots=True)
class ServoMeterRequest(NativeRequest):
    """0x56, args ``(figure)`` (``cnc_rdsvmeter`` sends 1) [V]: :class:`ScaledValues`, one per
    axis (the library takes |mantissa| and the decimals; it does not check the length).
    ``kind`` selects the figure: :class:`~.spindles.ServoFigure`."""

    COMMAND: ClassVar[int] = NativeCommand.RDSVMETER
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = ("kind",)
    ANSWER: ClassVar[Any] = ScaledValues
    kind: int = 1


_register(
    NativePositionRequest,
    AxisNameRequest,
    AxisUnitRequest,
    AxisCountRequest,
    AxisDisplayRequest,
    SpindleLoadRequest,
    ServoMeterRequest,
)
