"""The native adapter's handlers of the CNC's clock and the operator panel's signals: 0x45
``cnc_gettimer``, 0x46 ``cnc_settimer`` and 0x5D ``cnc_rdopnlsgnl`` (see
:mod:`focas_net.native.clock`), answered from the machine (:mod:`focas_net.sim._signals`).

* 0x45 answers the CNC's date and time of day whatever its type (the library takes the half
  it asked for); a type other than 0 or 1 answers EW_NUMBER;
* 0x46 sets the half its type names (:meth:`Machine.set_cnc_date`, ``set_cnc_time``): the
  machine's refusals (EW_PROT on a read-only machine, EW_DATA for a date or time that is
  none); a type other than 0 or 1 answers EW_NUMBER;
* 0x5D answers the path's :meth:`Machine.panel_signals` whatever the select bits.
"""

from __future__ import annotations

from focas_net.errors import EW
from focas_net.native import (
    CLOCK_DATE,
    CLOCK_TIME,
    ClockReadRequest,
    ClockValue,
    ClockWriteRequest,
    PanelSignals,
    PanelSignalsRequest,
    RequestBlock,
)
from focas_net.sim import Machine, Session

from ._common import Refused
from ._native_cnc import block_path

__all__ = ["ClockHandlers"]

_TYPES = (CLOCK_DATE, CLOCK_TIME)


class ClockHandlers:
    """Handlers of the clock and the panel's signals for one machine."""

    __slots__ = ("machine",)

    def __init__(self, machine: Machine) -> None:
        self.machine = machine

    def read_clock(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0x45: the CNC's clock, both halves."""
        if ClockReadRequest.from_block(block).type not in _TYPES:
            raise Refused(EW.NUMBER)
        t = self.machine.now()
        return ClockValue(t.year, t.month, t.day, t.hour, t.minute, t.second).encode()

    def write_clock(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0x46: the half of the clock its type names."""
        req = ClockWriteRequest.from_block(block)
        v = req.value
        if req.type == CLOCK_DATE:
            self.machine.set_cnc_date(v.year, v.month, v.day)
        elif req.type == CLOCK_TIME:
            self.machine.set_cnc_time(v.hour, v.minute, v.second)
        else:
            raise Refused(EW.NUMBER)
        return b""

    def read_panel_signals(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0x5D: the operator panel's signals of the block's path."""
        PanelSignalsRequest.from_block(block)
        s = self.machine.panel_signals(path=block_path(block))
        return PanelSignals(
            s.mode,
            s.handle_axis,
            s.handle_move,
            s.rapid,
            s.jog,
            s.feed,
            s.spindle,
            s.block_delete,
            s.single_block,
            s.machine_lock,
            s.dry_run,
            s.memory_protect,
            s.feed_hold,
        ).encode()
