"""The CNC's clock and the operator panel's signals: ``cnc_gettimer`` (0x45),
``cnc_settimer`` (0x46) and ``cnc_rdopnlsgnl`` (0x5D), the same in both command sets.

* 0x45, args ``(type)``: 0 date, 1 time of day. The answer is always the whole
  :class:`ClockValue` (six words); FANUC's library copies year, month, day for type 0 and
  hour, minute, second for type 1 into IODBTIMER [V].
* 0x46, args ``(type, 0, 0, 0, 12)``, extra: a :class:`ClockValue`. The library fills the half
  of ``type`` from the caller's IODBTIMER and sends the other half as it last held it, so the
  CNC takes only the half ``type`` names [V]. No answer data.
* 0x5D, args ``(select)``: :class:`PanelSignals`, 13 words the library copies whole into
  IODBSGNL after ``datano`` and ``type`` (``type`` = the select bits, whatever the answer) [V].
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache
from typing import Any, ClassVar

from focas_net.errors import EW

from .base import NativePayloadError, NativeRecord
from .calls import LibraryCall
from .requests import EXTRA_LENGTH, NativeCommand, NativeRequest, _ArgSpec, _register

__all__ = [
    "CLOCK_DATE",
    "CLOCK_TIME",
    "ClockReadRequest",
    "ClockValue",
    "ClockWriteRequest",
    "PanelSignals",
    "PanelSignalsRequest",
    "cnc_gettimer",
    "cnc_rdopnlsgnl",
    "cnc_settimer",
]

#: ``type`` of IODBTIMER: the date (year, month, day) or the time of day.
CLOCK_DATE = 0
CLOCK_TIME = 1


@dataclass(frozen=True, slots=True)
class ClockValue(NativeRecord):
    """The CNC's date and time of day, six i16 words [V]."""

    FORMAT: ClassVar[str] = ">6h"
    year: int
    month: int
    day: int
    hour: int
    minute: int
    second: int


@dataclass(frozen=True, slots=True)
class PanelSignals(NativeRecord):
    """IODBSGNL after its ``datano`` and ``type``: 13 i16 words [V] for the layout; what each
    word means is FANUC's IODBSGNL (mode, manual handle axis and distance, rapid, jog and
    feed override, spindle override (FS15 only), block delete, single block, machine lock,
    dry run, memory protection, feed hold)."""

    FORMAT: ClassVar[str] = ">13h"
    mode: int
    handle_axis: int
    handle_move: int
    rapid: int
    jog: int
    feed: int
    spindle: int
    block_delete: int
    single_block: int
    machine_lock: int
    dry_run: int
    memory_protect: int
    feed_hold: int


@dataclass(frozen=True, slots=True)
class ClockReadRequest(NativeRequest):
    """0x45, args ``type``: :class:`ClockValue` (``cnc_gettimer``) [V]."""

    COMMAND: ClassVar[int] = NativeCommand.GETTIMER
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = ("type",)
    ANSWER: ClassVar[Any] = ClockValue
    type: int = CLOCK_DATE


@dataclass(frozen=True, slots=True)
class ClockWriteRequest(NativeRequest):
    """0x46, args ``(type, 0, 0, 0, 12)``, extra: a :class:`ClockValue` (``cnc_settimer``)
    [V]. No answer data."""

    COMMAND: ClassVar[int] = NativeCommand.SETTIMER
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = ("type", 0, 0, 0, EXTRA_LENGTH)
    WRITE: ClassVar[bool] = True
    type: int
    value: ClockValue

    def extra(self) -> bytes:
        return self.value.encode()

    @classmethod
    def _extra_fields(cls, extra: bytes) -> dict[str, Any]:
        if len(extra) != ClockValue.SIZE:
            raise NativePayloadError(
                f"clock write carries {len(extra)} data bytes, expected {ClockValue.SIZE}",
                EW.LENGTH,
            )
        return {"value": ClockValue.decode(extra)}


@dataclass(frozen=True, slots=True)
class PanelSignalsRequest(NativeRequest):
    """0x5D, args ``select`` (IODBSGNL's data select bits): :class:`PanelSignals`
    (``cnc_rdopnlsgnl``) [V]."""

    COMMAND: ClassVar[int] = NativeCommand.RDOPNLSGNL
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = ("select",)
    ANSWER: ClassVar[Any] = PanelSignals
    select: int = 0


_register(ClockReadRequest, ClockWriteRequest, PanelSignalsRequest)


# -- the calls FANUC's library makes of them (one frame of one block, both command sets) -------


@cache
def cnc_gettimer(timer_type: int) -> LibraryCall:
    """0x45 ``(type)`` [V]."""
    return LibraryCall("cnc_gettimer", ((ClockReadRequest(timer_type),),))


def cnc_settimer(timer_type: int, value: ClockValue) -> LibraryCall:
    """0x46 ``(type, 0, 0, 0, 12)`` + the six words [V]."""
    return LibraryCall("cnc_settimer", ((ClockWriteRequest(timer_type, value),),))


@cache
def cnc_rdopnlsgnl(select: int) -> LibraryCall:
    """0x5D ``(select)`` [V]."""
    return LibraryCall("cnc_rdopnlsgnl", ((PanelSignalsRequest(select),),))
