"""The packed-protocol adapter: one request payload in, the response payload out.

:func:`handle` implements every command of PROTOCOL.md sections 3-5 and the control commands
0x0E01..0x0E04 on a :class:`~focas_net.sim.machine.Machine`. The server adds the frame header
(same command, same request id). 0x0E05 inject_fault is not handled here: faults are about I/O
and the server answers that command itself (an unhandled 0x0E05 answers EW_FUNC).

Order of the checks, per command (each stops at the first that fails):

* unknown command -> EW_FUNC;
* control commands: control disabled -> EW_FUNC (before the payload is looked at);
* wrong payload size -> EW_LENGTH (counted lists: ``count = -1, ew = EW_LENGTH``);
* writes and control commands on a read-only machine -> EW_PROT;
* then the checks of the command, in the order of PROTOCOL.md (see :mod:`.machine`).

:func:`handle` never raises: a payload that does not decode answers EW_LENGTH and every refusal
of the machine answers its EW code. The success path raises nothing: the dispatch is a dict from
command id to a handler bound to the machine, built once per machine.
"""

from __future__ import annotations

import struct
from collections.abc import Callable
from typing import Final

from focas_net.errors import EW, PayloadError

from ..protocol import (
    COMMANDS,
    EW_OK_BYTES,
    ActiveAlarmList,
    ClearAlarms,
    Command,
    DataRequest,
    MacroRequest,
    MacroValue,
    ParamValue,
    PmcData,
    PmcRange,
    RaiseAlarm,
    SetPanel,
    VersaMaxRequest,
    encode_ew,
)
from .machine import POSITION_DECIMALS, Machine, MachineError, PackedTable, Session

__all__ = ["error_payload", "handle", "handled_commands"]

_EW_FUNC: Final = encode_ew(EW.FUNC)
_EW_LENGTH: Final = encode_ew(EW.LENGTH)
_COUNTED_LENGTH: Final = COMMANDS[Command.RDALMMSG].error_payload(EW.LENGTH)
_COUNTED: Final = frozenset(c for c, spec in COMMANDS.items() if spec.counted)
_ERRORS: dict[tuple[int, int], bytes] = {}

_unpack_data = DataRequest.STRUCT.unpack
_unpack_macro = MacroRequest.STRUCT.unpack
_unpack_pmc = PmcRange.STRUCT.unpack
_unpack_clear = ClearAlarms.STRUCT.unpack
_unpack_panel = SetPanel.STRUCT.unpack
_MACRO_SIZE: Final = MacroValue.STRUCT.size
_decode_param = ParamValue.decode
_decode_pmc_data = PmcData.decode
_decode_raise = RaiseAlarm.decode
_decode_versamax = VersaMaxRequest.decode
_HISTORY_REQUEST_SIZE: Final = 2
_POSITION_REQUEST_SIZE: Final = 4
_TWO_I32: Final = struct.Struct("<hii")  # ew, then two i32
_ONE_I32: Final = struct.Struct("<hi")  # ew, then one i32
_ALMMSG_REQUEST_SIZE: Final = 4
_ALMMSG_CACHE: Final = 1024


def error_payload(command: int, ew: int) -> bytes:
    """The answer of ``command`` carrying only ``ew`` (``count = -1, ew`` for counted lists).

    The server uses it for forced EW answers (fault kind 2)."""
    key = (command, ew)
    payload = _ERRORS.get(key)
    if payload is None:
        spec = COMMANDS.get(command)
        payload = spec.error_payload(ew) if spec is not None else encode_ew(ew)
        if len(_ERRORS) < 4096:
            _ERRORS[key] = payload
    return payload


def handled_commands() -> frozenset[int]:
    """The command ids :func:`handle` answers (everything but 0x0E05)."""
    return frozenset(_Handlers.IDS)


def _table(machine: Machine) -> PackedTable:
    table = machine.packed_table
    if table is None:
        table = machine.packed_table = _Handlers(machine).table()
    return table


def handle(machine: Machine, session: Session, command: int, payload: bytes) -> bytes:
    """Answer one request of the packed protocol: the complete response payload."""
    fn = (machine.packed_table or _table(machine)).get(command)
    if fn is None:
        return _EW_FUNC
    if type(payload) is not bytes:  # the read caches key on the payload: make it hashable
        payload = bytes(payload)
    try:
        return fn(session, payload)
    except MachineError as exc:
        return error_payload(command, exc.ew)
    except PayloadError:
        return _COUNTED_LENGTH if command in _COUNTED else _EW_LENGTH


class _Handlers:
    """The handlers of one machine; each takes ``(session, payload)``."""

    IDS: Final = (
        Command.RDCNCSTAT,
        Command.RDPARAM,
        Command.RDMACRO,
        Command.RDDIAG,
        Command.SYSINFO,
        Command.RDALMMSG,
        Command.RDPRGNUM,
        Command.ACTF,
        Command.ACTS,
        Command.RDPOSITION,
        Command.RDPMCRNG,
        Command.WRPARAM,
        Command.WRMACRO,
        Command.WRPMCRNG,
        Command.WRUNLOCKPARAM,
        Command.VERSAMAX_RDCONFIG,
        Command.SIM_SET_PANEL,
        Command.SIM_RAISE_ALARM,
        Command.SIM_CLEAR_ALARMS,
        Command.SIM_SET_PMC,
        Command.RDALMHISTRY,
    )

    def __init__(self, machine: Machine) -> None:
        self.m = machine
        # answers of successful reads keyed by request payload, dropped when the machine's
        # matching version counter moves (bounded: only valid requests are stored)
        self._param: dict[bytes, bytes] = {}
        self._diag: dict[bytes, bytes] = {}
        self._data_version = machine.data_version
        self._macro: dict[bytes, bytes] = {}
        self._macro_version = machine.macro_version
        self._almmsg: dict[bytes, bytes] = {}
        self._alarm_version = machine.alarm_version
        n = len(machine.axes)
        # cnc_rdposition answers: ew, dec, count, then (i32 value, char name[4]) per axis
        self._pos_all = struct.Struct("<hhh" + "i4s" * n)
        self._pos_one = struct.Struct("<hhhi4s")
        self._names = [name.encode("latin-1")[:4] for name in machine.axes]

    def table(self) -> PackedTable:
        by_id: dict[int, Callable[[Session, bytes], bytes]] = {
            Command.RDCNCSTAT: self.rdcncstat,
            Command.RDPARAM: self.rdparam,
            Command.RDMACRO: self.rdmacro,
            Command.RDDIAG: self.rddiag,
            Command.SYSINFO: self.sysinfo,
            Command.RDALMMSG: self.rdalmmsg,
            Command.RDPRGNUM: self.rdprgnum,
            Command.ACTF: self.actf,
            Command.ACTS: self.acts,
            Command.RDPOSITION: self.rdposition,
            Command.RDPMCRNG: self.rdpmcrng,
            Command.WRPARAM: self.wrparam,
            Command.WRMACRO: self.wrmacro,
            Command.WRPMCRNG: self.wrpmcrng,
            Command.WRUNLOCKPARAM: self.unlock,
            Command.VERSAMAX_RDCONFIG: self.versamax,
            Command.SIM_SET_PANEL: self.set_panel,
            Command.SIM_RAISE_ALARM: self.raise_alarm,
            Command.SIM_CLEAR_ALARMS: self.clear_alarms,
            Command.SIM_SET_PMC: self.set_pmc,
            Command.RDALMHISTRY: self.rdalmhistry,
        }
        # plain int keys: a lookup by int must not go through IntEnum hashing
        return {int(k): v for k, v in by_id.items()}

    # -- reads ---------------------------------------------------------------------------
    def rdcncstat(self, _session: Session, payload: bytes) -> bytes:
        if payload:
            return _EW_LENGTH
        return self.m.status_payload()

    def sysinfo(self, _session: Session, payload: bytes) -> bytes:
        if payload:
            return _EW_LENGTH
        return self.m.sysinfo_payload()

    def _data_fresh(self) -> None:
        self._param.clear()
        self._diag.clear()
        self._data_version = self.m.data_version

    def rdparam(self, _session: Session, payload: bytes) -> bytes:
        if self._data_version != self.m.data_version:
            self._data_fresh()
        answer = self._param.get(payload)
        if answer is None:
            if len(payload) != 4:
                return _EW_LENGTH
            answer = EW_OK_BYTES + self.m.read_param(*_unpack_data(payload)).encode()
            self._param[payload] = answer
        return answer

    def rddiag(self, _session: Session, payload: bytes) -> bytes:
        if self._data_version != self.m.data_version:
            self._data_fresh()
        answer = self._diag.get(payload)
        if answer is None:
            if len(payload) != 4:
                return _EW_LENGTH
            answer = EW_OK_BYTES + self.m.read_diag(*_unpack_data(payload)).encode()
            self._diag[payload] = answer
        return answer

    def rdmacro(self, _session: Session, payload: bytes) -> bytes:
        if self._macro_version != self.m.macro_version:
            self._macro.clear()
            self._macro_version = self.m.macro_version
        answer = self._macro.get(payload)
        if answer is None:
            if len(payload) != 2:
                return _EW_LENGTH
            answer = EW_OK_BYTES + self.m.read_macro(_unpack_macro(payload)[0]).encode()
            self._macro[payload] = answer
        return answer

    def rdalmmsg(self, _session: Session, payload: bytes) -> bytes:
        if self._alarm_version != self.m.alarm_version:
            self._almmsg.clear()
            self._alarm_version = self.m.alarm_version
        answer = self._almmsg.get(payload)
        if answer is None:
            if len(payload) != _ALMMSG_REQUEST_SIZE:
                return _COUNTED_LENGTH
            alm_type, max_ = _unpack_data(payload)
            entries = tuple(self.m.active_alarms(alm_type, max_))
            answer = ActiveAlarmList(entries).encode()
            if len(self._almmsg) < _ALMMSG_CACHE:
                self._almmsg[payload] = answer
        return answer

    def rdalmhistry(self, _session: Session, payload: bytes) -> bytes:
        if len(payload) != _HISTORY_REQUEST_SIZE:
            return _COUNTED_LENGTH
        return self.m.alarm_history_payload(_unpack_macro(payload)[0])

    def rdprgnum(self, _session: Session, payload: bytes) -> bytes:
        if payload:
            return _EW_LENGTH
        m = self.m.motion
        return _TWO_I32.pack(0, m.program_running, m.program_main)

    def actf(self, _session: Session, payload: bytes) -> bytes:
        if payload:
            return _EW_LENGTH
        return _ONE_I32.pack(0, self.m.motion.feed)

    def acts(self, _session: Session, payload: bytes) -> bytes:
        if payload:
            return _EW_LENGTH
        return _ONE_I32.pack(0, self.m.motion.spindle_speed)

    def rdposition(self, _session: Session, payload: bytes) -> bytes:
        if len(payload) != _POSITION_REQUEST_SIZE:
            return _EW_LENGTH
        kind, axis = _unpack_data(payload)
        values = self.m.positions(kind, axis)
        if axis == -1:
            args: list[int | bytes] = [0, POSITION_DECIMALS, len(values)]
            for (_, value), name in zip(values, self._names, strict=True):
                args.append(value)
                args.append(name)
            return self._pos_all.pack(*args)
        return self._pos_one.pack(0, POSITION_DECIMALS, 1, values[0][1], self._names[axis - 1])

    def rdpmcrng(self, _session: Session, payload: bytes) -> bytes:
        if len(payload) != 8:
            return _EW_LENGTH
        return EW_OK_BYTES + payload + self.m.read_pmc(*_unpack_pmc(payload))

    def versamax(self, _session: Session, payload: bytes) -> bytes:
        req = _decode_versamax(payload)
        reply = self.m.versamax_read(req.rack, req.length, req.slot, req.offset)
        return EW_OK_BYTES + reply.encode()

    # -- writes --------------------------------------------------------------------------
    def wrparam(self, session: Session, payload: bytes) -> bytes:
        pv = _decode_param(payload)
        self.m.write_param(session, pv.datano, pv.axis, pv.value, pv.width)
        return EW_OK_BYTES

    def wrmacro(self, _session: Session, payload: bytes) -> bytes:
        if len(payload) != _MACRO_SIZE:
            return _EW_LENGTH
        mv = MacroValue.decode(payload)
        if mv.length != 8:
            return _EW_LENGTH
        self.m.write_macro(mv.number, mv.mcr_val, mv.dec_val)
        return EW_OK_BYTES

    def wrpmcrng(self, _session: Session, payload: bytes) -> bytes:
        d = _decode_pmc_data(payload)
        self.m.write_pmc(d.type_a, d.type_d, d.datano_s, d.datano_e, d.data)
        return EW_OK_BYTES

    def unlock(self, session: Session, payload: bytes) -> bytes:
        if len(payload) != 4:
            return _EW_LENGTH
        self.m.unlock(session, payload)
        return EW_OK_BYTES

    # -- simulator control (0x0E01..0x0E04) -------------------------------------------------
    def set_panel(self, _session: Session, payload: bytes) -> bytes:
        if not self.m.control_enabled:
            return _EW_FUNC
        if len(payload) != 6:
            return _EW_LENGTH
        self.m.set_panel(*_unpack_panel(payload))
        return EW_OK_BYTES

    def raise_alarm(self, _session: Session, payload: bytes) -> bytes:
        if not self.m.control_enabled:
            return _EW_FUNC
        a = _decode_raise(payload)
        self.m.raise_alarm(a.axis_no, a.alm_type, a.alm_no, a.msg)
        return EW_OK_BYTES

    def clear_alarms(self, _session: Session, payload: bytes) -> bytes:
        if not self.m.control_enabled:
            return _EW_FUNC
        if len(payload) != 4:
            return _EW_LENGTH
        self.m.clear_alarms(*_unpack_clear(payload))
        return EW_OK_BYTES

    def set_pmc(self, _session: Session, payload: bytes) -> bytes:
        if not self.m.control_enabled:
            return _EW_FUNC
        d = _decode_pmc_data(payload)
        self.m.write_pmc(d.type_a, d.type_d, d.datano_s, d.datano_e, d.data, force=True)
        return EW_OK_BYTES
