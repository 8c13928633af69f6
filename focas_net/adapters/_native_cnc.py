"""The native adapter's handlers of the CNC's state: identity, status, timers, the motion
figures and positions, the axes, the loads, the PMC and the alarms (``docs/native-protocol.md``;
what a handler is: :mod:`focas_net.adapters.native`).

A block answers for the path in its path word (:func:`block_path`: 0 is the handle's default,
path 1): the identity as that path shows it, its status, motion figures, positions, axes,
spindles, loads and alarms; a path the machine has not is the machine's EW_PATH. The CNC ID,
the PMC and the alarm history are the machine's, whatever the path word.
"""

from __future__ import annotations

import hashlib
import struct
from typing import Any, Final

from focas_net.errors import EW
from focas_net.native import (
    SCALED_SIZE,
    AlarmHistoryRecord,
    AlarmMessage,
    AlarmMessageRequest,
    AlarmMessages,
    AlarmStatus,
    AxisCount,
    AxisCountRequest,
    AxisDisplay,
    AxisDisplayRequest,
    AxisDisplays,
    AxisName,
    AxisNameRequest,
    AxisNames,
    AxisUnit,
    AxisUnitRequest,
    AxisUnits,
    CncId,
    ExecutingProgram,
    HdckStatus,
    NativeAlarmHistoryRequest,
    NativePmcArea,
    NativePositionKind,
    NativePositionRequest,
    NativeProgramNumbers,
    NativeSysInfo,
    PmcDataType,
    PmcReadRequest,
    PmcWriteRequest,
    PositionAxisName,
    PositionAxisNames,
    RequestBlock,
    ScaledNumber,
    SequenceNumber,
    StatInfo,
    TimerRequest,
    TimerValue,
    TmModeStatus,
    resolve_position_kind,
)
from focas_net.sim import PMC_AREAS, POSITION_DECIMALS, Identity, Machine, Session

from ._common import AnswerMemo, Counters, Refused, counters_of, need_room

__all__ = ["CncHandlers", "block_path", "path_sysinfo"]
#: Flags of each axis in the 0xA3 answer: machine, absolute/relative and distance shown.
_DISPLAY_FLAGS: Final = 0x07
#: Most alarm messages one block answers.
_MAX_ALARMS: Final = 32
#: Kind of a position read -> the machine's position kind.
_POSITION_KINDS: Final[dict[NativePositionKind, str]] = {
    NativePositionKind.ABSOLUTE: "absolute",
    NativePositionKind.MACHINE: "machine",
    NativePositionKind.RELATIVE: "relative",
    NativePositionKind.DISTANCE: "distance_to_go",
    NativePositionKind.SKIP: "skip",
}
_ALARM_HEAD_SIZE: Final = 16
_HISTORY_SIZE: Final = AlarmHistoryRecord.SIZE
_FOUR_U32: Final = struct.Struct(">4I")
_FOLLOWS_STATUS: Final = counters_of(["status_version"])
_pack_scaled = ScaledNumber.STRUCT.pack
#: An empty value slot: (0, 10, 0).
_SCALED_ZERO: Final = _pack_scaled(0, 10, 0)


def block_path(block: RequestBlock) -> int:
    """The path a block asks for: its path word, 0 being the handle's default, path 1."""
    return block.path or 1


def path_sysinfo(machine: Machine, path: int) -> Identity:
    """The identity as ``path`` shows it (``cnc_sysinfo`` after ``cnc_setpath``): the
    machine's :meth:`~focas_net.sim.Machine.path_identity`."""
    return machine.path_identity(path)


class _Path:
    """What the handlers keep of one path: its 0x18 answer, its axis names, its spindles."""

    __slots__ = ("axis_names", "spindles", "sysinfo")

    def __init__(self, machine: Machine, path: int) -> None:
        i = path_sysinfo(machine, path)
        self.sysinfo = NativeSysInfo(
            i.addinfo, i.max_axis, i.cnc_type, i.mt_type, i.series, i.version, i.axes
        ).encode()
        info = machine.path_info(path)
        self.axis_names = [_axis_name(a) for a in info.axes]
        self.spindles = info.spindles


class CncHandlers:
    """The handlers of the CNC's state of one machine (see the module docstring)."""

    __slots__ = ("_kept", "_paths", "machine", "max_axis")

    def __init__(self, machine: Machine, max_axis: int) -> None:
        self.machine = machine
        #: Position records for all axes: the open answer's max axes.
        self.max_axis = max_axis
        self._paths = {p: _Path(machine, p) for p in range(1, machine.path_count + 1)}
        #: path -> (the status counters, their values then, the 0x19 data)
        self._kept = AnswerMemo(machine.path_count)

    def _path(self, block: RequestBlock) -> _Path:
        """What is kept of the block's path; the machine's EW_PATH for one it has not."""
        path = block_path(block)
        kept = self._paths.get(path)
        if kept is None:
            self.machine.path_info(path)  # raises EW_PATH naming the path and the range
            raise Refused(EW.PATH)  # pragma: no cover - the machine refuses it first
        return kept

    def read_sysinfo(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0x18: the identity as the block's path shows it (:func:`path_sysinfo`)."""
        return self._path(block).sysinfo

    def read_status(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0x19, kept per path while the status holds: a frame of the status and a read never
        kept (a timer) is answered afresh, its status block from here."""
        path = block_path(block)
        kept: tuple[Counters, Any, bytes] | None = self._kept.get(path)
        if kept is not None and kept[0](self.machine) == kept[1]:
            return kept[2]
        seen = _FOLLOWS_STATUS(self.machine)
        data = self.status_info(path).encode()
        self._kept.keep(path, _FOLLOWS_STATUS, seen, data)
        return data

    def status_info(self, path: int = 1) -> StatInfo:
        """The status of ``path`` as a 0x19 answer carries it."""
        s = self.machine.status(path=path)
        return StatInfo(s.aut, s.run, s.motion, s.mstb, s.emergency, s.alarm, s.edit)

    def read_hdck(self, block: RequestBlock, room: int, session: Session) -> bytes:
        return HdckStatus(self.machine.status(path=block_path(block)).hdck).encode()

    def read_tmmode(self, block: RequestBlock, room: int, session: Session) -> bytes:
        return TmModeStatus(self.machine.status(path=block_path(block)).tmmode).encode()

    def read_cnc_id(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """The CNC ID: four words of the SHA-256 of the machine's name (stable per name)."""
        digest = hashlib.sha256(self.machine.name.encode("utf-8")).digest()
        return CncId(*_FOUR_U32.unpack(digest[:16])).encode()

    def read_timer(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """Timers 0 power-on, 1 operating, 2 cutting, 3 cycle, 4 free purpose (the
        general-purpose integrating meter): the machine's (``Machine.timer``, machine time) as
        IODBTIME, whole minutes and the milliseconds past them; another type answers
        EW_NUMBER."""
        req = TimerRequest.from_block(block)
        if not 0 <= req.type <= 4:
            raise Refused(EW.NUMBER)
        ms = self.machine.timer_ms(req.type, path=block_path(block))
        minute, msec = divmod(ms, 60_000)
        return TimerValue(minute, msec).encode()

    def read_program_numbers(self, block: RequestBlock, room: int, session: Session) -> bytes:
        m = self.machine.path_motion(path=block_path(block))
        return NativeProgramNumbers(m.program_running, m.program_main).encode()

    def read_sequence(self, block: RequestBlock, room: int, session: Session) -> bytes:
        return SequenceNumber(self.machine.path_motion(path=block_path(block)).sequence).encode()

    def read_executing_program(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """The running program: its O number and its name ``O<number>`` (four digits at
        least)."""
        number = self.machine.path_motion(path=block_path(block)).program_running
        return ExecutingProgram(number, f"O{number:04d}".encode("ascii")).encode()

    def read_feed(self, block: RequestBlock, room: int, session: Session) -> bytes:
        return _pack_scaled(self.machine.path_motion(path=block_path(block)).feed, 10, 0)

    def read_spindle(self, block: RequestBlock, room: int, session: Session) -> bytes:
        speed = self.machine.path_motion(path=block_path(block)).spindle_speed
        return _pack_scaled(speed, 10, 0)

    def read_positions(self, block: RequestBlock, room: int, session: Session) -> bytes:
        req = NativePositionRequest.from_block(block)
        kind = resolve_position_kind(req.kind)
        if kind is None:
            raise Refused(EW.ATTRIB)
        axis = req.axis
        # the machine's checks first: no skip function (EW_NOOPT), an axis it has not (EW_ATTRIB)
        positions = self.machine.positions(
            _POSITION_KINDS[kind], None if axis == -1 else axis, path=block_path(block)
        )
        if axis == -1:
            need_room(SCALED_SIZE * self.max_axis, room)
            parts = [_pack_scaled(v, 10, POSITION_DECIMALS) for _, v in positions]
            parts.extend([_SCALED_ZERO] * (self.max_axis - len(parts)))
            return b"".join(parts)
        return _pack_scaled(positions[0][1], 10, POSITION_DECIMALS)

    def read_axis_names(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0x89: 4 bytes per axis (argument 0) or 16 (-1: head, absolute, machine and
        relative names)."""
        req = AxisNameRequest.from_block(block)
        names = self._path(block).axis_names
        if req.kind == -1:
            data = PositionAxisNames(tuple(PositionAxisName.of(n, n, n) for n in names)).encode()
        else:
            data = AxisNames(tuple(names)).encode()
        need_room(len(data), room)
        return data

    def read_axis_units(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0x88: per axis, the unit of the positions and of the machine position (0, mm)."""
        AxisUnitRequest.from_block(block)
        axes = len(self._path(block).axis_names)
        need_room(AxisUnit.SIZE * axes, room)
        return AxisUnits((AxisUnit(0, 0),) * axes).encode()

    def read_axis_count(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0xA4: the axes (0), spindles (1; 3, ``cnc_rdspeed``) or servo axes (2) of the
        path."""
        req = AxisCountRequest.from_block(block)
        path = self._path(block)
        if req.kind in (1, 3):
            return AxisCount(path.spindles).encode()
        if req.kind in (0, 2):
            return AxisCount(len(path.axis_names)).encode()
        raise Refused(EW.ATTRIB)

    def read_axis_display(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0xA3: every position of every axis shown."""
        AxisDisplayRequest.from_block(block)
        axes = len(self._path(block).axis_names)
        need_room(AxisDisplay.SIZE * axes, room)
        shown = AxisDisplay(bytes(3), _DISPLAY_FLAGS)
        return AxisDisplays((shown,) * axes).encode()

    def _pmc_area(self, area: int, data_type: int) -> tuple[str, int]:
        try:
            letter = NativePmcArea(area).name
        except ValueError:
            raise Refused(EW.ATTRIB) from None
        if letter not in PMC_AREAS:  # an area the simulated CNC never has
            raise Refused(EW.NOOPT)
        try:
            width = PmcDataType(data_type).width
        except ValueError:
            raise Refused(EW.ATTRIB) from None
        return letter, width

    def read_pmc(self, block: RequestBlock, room: int, session: Session) -> bytes:
        req = PmcReadRequest.from_block(block)
        letter, width = self._pmc_area(req.area, req.data_type)
        count = req.last - req.first + 1
        if count < 1 or count % width:
            raise Refused(EW.LENGTH)
        need_room(count, room)
        raw = self.machine.read_pmc(letter, req.first, count)
        return _swap(raw, width)

    def write_pmc(self, block: RequestBlock, room: int, session: Session) -> bytes:
        req = PmcWriteRequest.from_block(block)
        self.machine.check_writable()
        letter, width = self._pmc_area(req.area, req.data_type)
        data = req.data.raw
        count = req.last - req.first + 1
        if count < 1 or count % width or len(data) != count:
            raise Refused(EW.LENGTH)
        self.machine.write_pmc(letter, req.first, _swap(data, width))
        return b""

    def read_alarm_bits(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0x1A: bit n set when an alarm of type n is active."""
        bits = 0
        for a in self.machine.active_alarms(path=block_path(block)):
            bits |= 1 << a.alm_type
        return AlarmStatus(bits - (1 << 32) if bits & 0x8000_0000 else bits).encode()

    def read_alarms(self, block: RequestBlock, room: int, session: Session) -> bytes:
        req = AlarmMessageRequest.from_block(block)
        if req.count < 1 or req.text_length < 0:
            raise Refused(EW.LENGTH)
        alarms = self.machine.active_alarms(
            req.alarm_type, min(req.count, _MAX_ALARMS), path=block_path(block)
        )
        text_length = req.text_length
        need_room(len(alarms) * (_ALARM_HEAD_SIZE + text_length), room)
        fill = req.text_mode != 0
        return AlarmMessages(
            tuple(
                AlarmMessage(
                    a.alm_no,
                    a.alm_type,
                    a.axis_no,
                    a.msg.encode("latin-1", "replace")[:text_length] if fill else b"",
                )
                for a in alarms
            )
        ).encode(text_length)

    def read_history(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0x6C: entries ``first..last`` of the history (1 = the newest), 60 bytes each;
        EW_NUMBER when ``first`` is past the last entry."""
        req = NativeAlarmHistoryRequest.from_block(block)
        if req.first < 1 or req.last < req.first:
            raise Refused(EW.NUMBER)
        entries = self.machine.alarm_history(req.last)[req.first - 1 :]
        if not entries:
            raise Refused(EW.NUMBER)
        need_room(_HISTORY_SIZE * len(entries), room)
        parts = []
        for e in entries:
            t = e.occurred_at
            text = e.msg.encode("latin-1", "replace")[:32]
            parts.append(
                AlarmHistoryRecord(
                    e.alm_no,
                    e.alm_type,
                    e.axis_no,
                    t.year,
                    t.month,
                    t.day,
                    t.hour,
                    t.minute,
                    t.second,
                    len(text),
                    text,
                ).encode()
            )
        return b"".join(parts)


def _axis_name(name: str) -> AxisName:
    """The 4-byte name of an axis: its first character, then its second as the suffix."""
    raw = name.encode("ascii", "replace")
    return AxisName(raw[:1], raw[1:2] or b"\x00")


def _swap(raw: bytes, width: int) -> bytes:
    """PMC memory is little-endian, the native wire big-endian: reverse each ``width`` item."""
    if width == 1:
        return raw
    out = bytearray(len(raw))
    for i in range(width):
        out[i::width] = raw[width - 1 - i :: width]
    return bytes(out)
