"""The native adapter's handlers of the spindles and the servo figures: 0x40 (a figure of
each spindle), 0x8A (the spindle names) and 0x56 (a figure of each axis)
(``docs/native-protocol.md``; what a handler is: :mod:`focas_net.adapters.native`).

Every figure is the machine's (:meth:`~focas_net.sim.Machine.spindles`,
:meth:`~focas_net.sim.Machine.servo_loads`, ``servo_speeds``, ``loop_gains``), read for the
path of the block, so it follows the running program:

* 0x40 ``(figure, spindle)``: one 8-byte record per spindle of the path (``spindle`` -1 or 0),
  or the one asked (1..n; another number is EW_NUMBER); the figure
  (:class:`~focas_net.native.SpindleFigure`) is the load in percent (0, 4), the top speed
  (1), the gear (2), the actual speed (3) or the motor speed (5) in min^-1, every record with
  no decimals; a figure outside 0..5 is EW_ATTRIB;
* 0x8A: the name of every spindle of the path (``S`` and the spindle's number);
* 0x56 ``(figure)``: one record per axis of the path
  (:class:`~focas_net.native.ServoFigure`): the loop gain in 0.01/s (0), the load meter in
  percent (1), the motor speed in min^-1 (2); another figure is EW_ATTRIB.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Final

from focas_net.errors import EW
from focas_net.native import (
    SCALED_SIZE,
    RequestBlock,
    ScaledNumber,
    ServoFigure,
    SpindleFigure,
    SpindleLoadRequest,
    SpindleName,
    SpindleNameRequest,
    SpindleNames,
)
from focas_net.native import ServoMeterRequest as _ServoRequest
from focas_net.sim import Machine, Session, Spindle

from ._common import Refused, need_room
from ._native_cnc import block_path

__all__ = ["SpindleHandlers"]

_pack_scaled = ScaledNumber.STRUCT.pack
#: Spindle numbers that ask for every spindle of the path.
_EVERY: Final = frozenset({-1, 0})


def _figure(spindle: Spindle, figure: SpindleFigure) -> int:
    if figure in (SpindleFigure.LOAD, SpindleFigure.LOAD_METER):
        return spindle.load
    if figure is SpindleFigure.MAX_SPEED:
        return spindle.max_speed
    if figure is SpindleFigure.GEAR:
        return spindle.gear
    return spindle.speed  # SPEED, MOTOR_SPEED: a spindle driven one to one


def _records(values: Sequence[int]) -> bytes:
    return b"".join(_pack_scaled(v, 10, 0) for v in values)


class SpindleHandlers:
    """The handlers of the spindles and servo figures of one machine (module docstring)."""

    __slots__ = ("machine",)

    def __init__(self, machine: Machine) -> None:
        self.machine = machine

    def read_spindle_data(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0x40: one figure of every spindle of the path, or of the one asked."""
        req = SpindleLoadRequest.from_block(block)
        try:
            figure = SpindleFigure(req.kind)
        except ValueError:
            raise Refused(EW.ATTRIB) from None
        spindles = self.machine.spindles(path=block_path(block))
        if req.spindle not in _EVERY:
            if not 1 <= req.spindle <= len(spindles):
                raise Refused(EW.NUMBER)
            spindles = spindles[req.spindle - 1 : req.spindle]
        need_room(SCALED_SIZE * len(spindles), room)
        return _records([_figure(s, figure) for s in spindles])

    def read_spindle_names(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0x8A: the name of every spindle of the path (every kind)."""
        SpindleNameRequest.from_block(block)
        spindles = self.machine.spindles(path=block_path(block))
        names = SpindleNames(
            tuple(
                SpindleName(s.name.encode("ascii"), s.suffix.encode("ascii")[:1]) for s in spindles
            )
        )
        need_room(SpindleName.SIZE * len(spindles), room)
        return names.encode()

    def read_servo_data(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0x56: one figure of every axis of the path."""
        req = _ServoRequest.from_block(block)
        path = block_path(block)
        machine = self.machine
        if req.kind == ServoFigure.LOOP_GAIN:
            values = machine.loop_gains(path=path)
        elif req.kind == ServoFigure.LOAD:
            values = machine.servo_loads(path=path)
        elif req.kind == ServoFigure.SPEED:
            values = machine.servo_speeds(path=path)
        else:
            raise Refused(EW.ATTRIB)
        need_room(SCALED_SIZE * len(values), room)
        return _records(values)
