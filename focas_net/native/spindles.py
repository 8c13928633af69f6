"""Spindles and servo figures over the native protocol: the figure selectors of 0x40 and 0x56,
the spindle names (0x8A), and what each FOCAS function of FANUC's library sends for them.

* **0x40** ``(figure, spindle)`` (:class:`~.axes.SpindleLoadRequest`): one 8-byte
  :class:`~.records.ScaledNumber` per spindle (``spindle`` -1 every spindle of the path, n
  spindle n); the library takes the mantissa of each record, eight bytes apart, and counts
  them up to the path's spindles [V]. The first argument selects the figure
  (:class:`SpindleFigure`): 0 load (``cnc_rdspload``), 1 top speed (``cnc_rdspmaxrpm``), 2
  gear (``cnc_rdspgear``), 3 actual speed (``cnc_acts2``), 4 load meter and 5 motor speed
  (``cnc_rdspmeter`` in the 16i set, which takes the decimals from the record and sets the unit
  itself: 0 percent for 4, 1 min^-1 for 5) [V].
* **0x8A** ``(kind)``: the spindle names, 4 bytes per spindle (:class:`SpindleName`): the
  name and three suffix characters [V]. ``cnc_rdspdlname`` sends 0, ``cnc_rdspmeter`` sends 0
  in the 16i set and -1 in the 30i set, ``cnc_rdspeed`` (30i set) sends 1 [V]; every kind is
  answered with every spindle of the path.
* **0x56** ``(figure)`` (:class:`~.axes.ServoMeterRequest`): one 8-byte record per axis; the
  first argument selects the figure (:class:`ServoFigure`): 0 position loop gain
  (``cnc_rdloopgain``), 1 load meter (``cnc_rdsvmeter`` and ``cnc_rdcurrent``: FANUC's library
  sends the same block for both), 2 motor speed (``cnc_rdsrvspeed``) [V].
* **0xA4** ``(3)`` (``cnc_rdspeed``, 30i set): a u16 count, as 0xA4(1) [V]; it is answered
  with the path's spindles.

The functions below give each FOCAS function's frames per command set, as :mod:`.calls` does
for the others. "[V]" marks what FANUC's library (libfwlib32 1.0.5) was seen to send and read
back, "[I]" what is inferred.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass
from typing import Any, ClassVar, Final

from .axes import AxisCountRequest, AxisUnitRequest, ServoMeterRequest, SpindleLoadRequest
from .base import NativeRecord, RecordArray
from .calls import CommandSet, LibraryCall, _memoized, _one
from .items import ParamReadRequest
from .modal import ModalGRequest
from .pmc import PmcReadRequest
from .requests import (
    ActualFeedRequest,
    ActualSpindleSpeedRequest,
    NativeCommand,
    NativeRequest,
    _ArgSpec,
    _register,
)

__all__ = [
    "SPINDLE_METER_UNITS",
    "ServoFigure",
    "SpindleFigure",
    "SpindleName",
    "SpindleNameRequest",
    "SpindleNames",
    "cnc_acts2",
    "cnc_rdcurrent",
    "cnc_rdloopgain",
    "cnc_rdspdlname",
    "cnc_rdspeed",
    "cnc_rdspgear",
    "cnc_rdspload_figure",
    "cnc_rdspmaxrpm",
    "cnc_rdspmeter",
    "cnc_rdsrvspeed",
]


class SpindleFigure(enum.IntEnum):
    """The first argument of 0x40: which figure of each spindle is asked [V] (what the
    library sends); the figures' meaning is [I]."""

    LOAD = 0  # cnc_rdspload: load, percent
    MAX_SPEED = 1  # cnc_rdspmaxrpm: top speed, min^-1
    GEAR = 2  # cnc_rdspgear: the gear it runs in
    SPEED = 3  # cnc_acts2: actual speed, min^-1
    LOAD_METER = 4  # cnc_rdspmeter type 0 (16i set): load meter, percent
    MOTOR_SPEED = 5  # cnc_rdspmeter type 1 (16i set): motor speed, min^-1


class ServoFigure(enum.IntEnum):
    """The first argument of 0x56: which figure of each axis is asked [V]."""

    LOOP_GAIN = 0  # cnc_rdloopgain: position loop gain, 0.01/s
    LOAD = 1  # cnc_rdsvmeter and cnc_rdcurrent: load meter, percent
    SPEED = 2  # cnc_rdsrvspeed: motor speed, min^-1


#: The unit word ``cnc_rdspmeter`` puts in LOADELM for each of its figures [V].
SPINDLE_METER_UNITS: Final = {SpindleFigure.LOAD_METER: 0, SpindleFigure.MOTOR_SPEED: 1}


@dataclass(frozen=True, slots=True)
class SpindleName(NativeRecord):
    """One 4-byte spindle name of 0x8A: ``name`` and three suffix characters (ODBSPDLNAME
    ``name, suff1, suff2, suff3``) [V]. ``cnc_rdspmeter`` copies name and suff1 into LOADELM
    (suff2 as well in the 30i set)."""

    FORMAT: ClassVar[str] = ">cccc"
    name: bytes
    suffix: bytes = b"\x00"
    suffix2: bytes = b"\x00"
    suffix3: bytes = b"\x00"

    @property
    def text(self) -> str:
        """The name and its suffixes as text (``"S1"``), NULs left out."""
        raw = self.name + self.suffix + self.suffix2 + self.suffix3
        return raw.replace(b"\x00", b"").decode("latin-1")


@dataclass(frozen=True, slots=True)
class SpindleNames(RecordArray[SpindleName]):
    """0x8A: one :class:`SpindleName` per spindle; ``cnc_rdspdlname`` counts them from the
    data length, up to the number asked [V]."""

    ITEM: ClassVar[type[NativeRecord]] = SpindleName
    records: tuple[SpindleName, ...]


@dataclass(frozen=True, slots=True)
class SpindleNameRequest(NativeRequest):
    """0x8A, args ``kind`` (0 ``cnc_rdspdlname``; 0 or -1 ``cnc_rdspmeter``; 1 ``cnc_rdspeed``)
    [V]: :class:`SpindleNames`."""

    COMMAND: ClassVar[int] = NativeCommand.SPDLNAME
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = ("kind",)
    ANSWER: ClassVar[Any] = SpindleNames
    kind: int = 0


_register(SpindleNameRequest)

_16I: Final = CommandSet.FS16I
#: The 0xA4 argument ``cnc_rdspeed`` sends in the 30i set [V].
SPEED_COUNT: Final = 3


@_memoized
def cnc_rdspload_figure(cs: CommandSet, figure: SpindleFigure, spindle: int) -> LibraryCall:
    """0x40 ``(figure, sp)``, at 30i class between two 0xA4(1) [V]: ``cnc_rdspload`` (0),
    ``cnc_rdspmaxrpm`` (1), ``cnc_rdspgear`` (2), ``cnc_acts2`` (3)."""
    names = {
        SpindleFigure.LOAD: "cnc_rdspload",
        SpindleFigure.MAX_SPEED: "cnc_rdspmaxrpm",
        SpindleFigure.GEAR: "cnc_rdspgear",
        SpindleFigure.SPEED: "cnc_acts2",
    }
    request = SpindleLoadRequest(int(figure), spindle)
    name = names.get(figure, "cnc_rdspmeter")
    if cs is _16I:
        return _one(name, request)
    return _one(name, AxisCountRequest(1), request, AxisCountRequest(1))


def cnc_rdspmaxrpm(cs: CommandSet, spindle: int) -> LibraryCall:
    """0x40 ``(1, sp)`` [V]."""
    return cnc_rdspload_figure(cs, SpindleFigure.MAX_SPEED, spindle)


def cnc_rdspgear(cs: CommandSet, spindle: int) -> LibraryCall:
    """0x40 ``(2, sp)`` [V]."""
    return cnc_rdspload_figure(cs, SpindleFigure.GEAR, spindle)


def cnc_acts2(cs: CommandSet, spindle: int) -> LibraryCall:
    """0x40 ``(3, sp)`` [V]."""
    return cnc_rdspload_figure(cs, SpindleFigure.SPEED, spindle)


@_memoized
def cnc_rdspdlname(cs: CommandSet) -> LibraryCall:
    """0x8A(0), in both sets [V]."""
    return _one("cnc_rdspdlname", SpindleNameRequest(0))


@_memoized
def cnc_rdspmeter(cs: CommandSet, kind: int) -> LibraryCall:
    """16i set: 0x40(4, -1), 0x40(5, -1), 0x8A(0), whatever ``kind``. 30i set: 0xA4(1),
    0x8A(-1), 0x40(4, -1) for ``kind`` 0, 0x40(5, -1) for 1, both for -1, 0xA4(1); the
    library refuses the call itself (EW_NOOPT, nothing sent) when the open answer's
    controlled spindles (body[20:22]) are 0 [V]."""
    if cs is _16I:
        both = (SpindleLoadRequest(4, -1), SpindleLoadRequest(5, -1))
        return _one("cnc_rdspmeter", *both, SpindleNameRequest(0))
    figures = {0: (4,), 1: (5,)}.get(kind, (4, 5))
    data = tuple(SpindleLoadRequest(f, -1) for f in figures)
    return _one(
        "cnc_rdspmeter", AxisCountRequest(1), SpindleNameRequest(-1), *data, AxisCountRequest(1)
    )


#: The parameters ``cnc_rdspeed`` reads in the 16i set (display bits), and the G signal byte
#: (G28) and modal group (0x21 kind 4) it reads with them [V].
SPEED_PARAMS: Final = (3106, 3107, 9936)
SPEED_SIGNAL_BYTE: Final = 28
SPEED_MODAL_KIND: Final = 4


@_memoized
def cnc_rdspeed(cs: CommandSet, kind: int) -> LibraryCall:
    """16i set: 0x24, 0x25, 0x88(0), 0x0E for 3106, 3107 and 9936, 0x21(4), PMC 0x8001 G28
    (whatever ``kind``). 30i set: 0xA4(3), 0x8A(1), 0x88(3), 0x88(4), 0x24 (not for ``kind``
    1), 0x25, 0xA4(3) [V]."""
    if cs is _16I:
        return _one(
            "cnc_rdspeed",
            ActualFeedRequest(),
            ActualSpindleSpeedRequest(),
            AxisUnitRequest(0),
            *(ParamReadRequest(n, n, 0) for n in SPEED_PARAMS),
            ModalGRequest(SPEED_MODAL_KIND),
            PmcReadRequest(SPEED_SIGNAL_BYTE, SPEED_SIGNAL_BYTE, 0, 0),
        )
    head: tuple[NativeRequest, ...] = (
        AxisCountRequest(SPEED_COUNT),
        SpindleNameRequest(1),
        AxisUnitRequest(3),
        AxisUnitRequest(4),
    )
    feed: tuple[NativeRequest, ...] = () if kind == 1 else (ActualFeedRequest(),)
    return _one(
        "cnc_rdspeed",
        *head,
        *feed,
        ActualSpindleSpeedRequest(),
        AxisCountRequest(SPEED_COUNT),
    )


@_memoized
def _servo(function: str, figure: ServoFigure) -> LibraryCall:
    return _one(function, ServoMeterRequest(int(figure)))


def cnc_rdloopgain(cs: CommandSet) -> LibraryCall:
    """0x56(0), in both sets [V]."""
    return _servo("cnc_rdloopgain", ServoFigure.LOOP_GAIN)


def cnc_rdcurrent(cs: CommandSet) -> LibraryCall:
    """0x56(1), in both sets [V] (the block ``cnc_rdsvmeter`` sends for the load meter)."""
    return _servo("cnc_rdcurrent", ServoFigure.LOAD)


def cnc_rdsrvspeed(cs: CommandSet) -> LibraryCall:
    """0x56(2), in both sets [V]."""
    return _servo("cnc_rdsrvspeed", ServoFigure.SPEED)
