"""The packed-protocol adapter: one request payload in, the answer payload out.

:class:`PackedAdapter` answers every command of ``docs/protocol.md`` sections 3-5 and 8 (the
part programs 0x0030..0x0032 and 0x0110..0x0112 among them) and the control commands
0x0E01..0x0E04, 0x0E10, 0x0E11, 0x0E20 and 0x0E21 from a protocol-neutral
:class:`~focas_net.sim.Machine`. The server adds the frame header (same command, same request
id). 0x0E05..0x0E07 (the fault queues) are not handled here: faults are about I/O and the
server answers those commands itself (here they answer EW_FUNC). Pure and
synchronous: no socket, no event loop.

Every request is decoded and every answer encoded with the codecs of
:data:`~focas_net.protocol.COMMANDS`; the machine gets domain values (PMC letters, ``Decimal``
macro values, ``None`` for all axes) and gives them back.

The wire's rules are here, the CNC's are the machine's (:mod:`focas_net.sim.machine`). Order of
the checks, per command (each stops at the first that fails; ``docs/protocol.md`` section 8):

* unknown command -> EW_FUNC;
* control commands: control disabled -> EW_FUNC (before the payload is looked at);
* a payload of the wrong size or layout -> EW_LENGTH (counted lists: ``count = -1, ew``);
* writes and control commands on a read-only machine -> EW_PROT (the machine's first check;
  asked first where a check of the wire would come before the machine's other checks);
* then the command's own checks. Those of the wire, between the machine's:

  - ``pmc_rdpmcrng``/``pmc_wrpmcrng``/``set_pmc``: an unknown ``type_a`` code -> EW_ATTRIB,
    then the machine's EW_NOOPT (no such area), then ``type_d`` other than 0 -> EW_ATTRIB, a
    count outside 1..32 -> EW_LENGTH, (writes) data length other than the count -> EW_LENGTH,
    then the machine's EW_NUMBER and EW_PROT;
  - ``cnc_wrmacro``: the ``length`` word other than 8 -> EW_LENGTH, before the machine's
    checks. The value is ``mcr_val / 10**dec_val`` with ``dec_val`` decimals: a ``dec_val``
    outside 0..9 is a value the machine refuses (EW_DATA, after EW_NUMBER and EW_PROT);
  - ``cnc_rdalmmsg``: ``max`` outside 1..32 -> EW_LENGTH; ``cnc_rdalmhistry``: ``depth``
    outside 1..250 -> EW_LENGTH;
  - ``versamax_rdconfig``: the machine's EW_NUMBER for an empty slot, then ``length`` outside
    1..128 -> EW_LENGTH, then the machine's EW_NUMBER for the offset;
  - ``cnc_rdposition``: a ``type`` outside 0..3 -> EW_ATTRIB; ``axis`` -1 means every axis;
  - ``cnc_wrunlockparam``: a payload longer than 4 bytes is a wrong password (EW_PASSWD, the
    session locked), shorter is EW_LENGTH;
  - ``cnc_rdparam``/``cnc_wrparam``: a bit parameter's 0..255 travels as the signed byte of
    the same bits, a real parameter as REALPRM (width 8: mantissa and decimals);
  - ``set_panel``: a field of -1 leaves its switch as it is.

:meth:`PackedAdapter.answer` never raises for anything a peer sends nor for what the machine
holds: a payload that does not decode answers EW_LENGTH, every refusal its EW code, and an
answer the wire cannot carry EW_DATA (:mod:`focas_net.adapters._common`). The dispatch is a
dict from command id to a bound handler, built once per adapter.

Answers of successful reads are kept by the adapter, keyed by command and request payload,
while the machine counter of what they show (:data:`_COUNTERS`: ``status_version``,
``data_version``, ``macro_version``, ``alarm_version``, ``pmc_version``, ``motion_version``)
stays where it was, with the native adapter's mechanism (:mod:`focas_net.adapters._common`): a
poller's repeated request costs one look-up and a compare. The machine keeps no answers of its
own.
"""

from __future__ import annotations

from collections.abc import Callable
from decimal import Decimal
from typing import Any, ClassVar, Final

from focas_net.errors import EW, PayloadError
from focas_net.protocol import (
    COMMANDS,
    FAULT_COMMANDS,
    MAX_CONFIG_CHUNK,
    MAX_DIRECTORY_ENTRIES,
    MAX_HISTORY_DEPTH,
    MAX_PMC_CHUNK,
    MAX_PROGRAM_CHUNK,
    PASSWORD_SIZE,
    PATH_COMMANDS,
    PATH_INDEPENDENT_COMMANDS,
    ActiveAlarm,
    ActiveAlarmList,
    ActualValue,
    AlarmHistory,
    AlarmHistoryEntry,
    AxisPosition,
    Command,
    CycleAction,
    LoadMeters,
    MacroValue,
    ParamAttributes,
    ParamValue,
    PathSelection,
    PmcArea,
    PmcData,
    PositionData,
    ProgramChunk,
    ProgramDirectory,
    ProgramEntry,
    ProgramNumber,
    ProgramNumbers,
    RunInfo,
    SetPanel,
    StatusInfo,
    SysInfo,
    VersaMaxReply,
    encode_ew,
)
from focas_net.sim import (
    POSITION_DECIMALS,
    POSITION_KINDS,
    TIMER_KINDS,
    DataItem,
    Machine,
    MachineError,
    ParamKind,
    Session,
)

from ._common import (
    REFUSALS,
    UNENCODABLE,
    AnswerMemo,
    Counters,
    Refused,
    counters_of,
    refusal_code,
    unencodable_code,
)

__all__ = ["PackedAdapter"]

#: One handler: ``(session, payload, path) -> answer``; raises one of :data:`REFUSALS`.
_Handler = Callable[[Session, bytes, int], bytes]

#: ``type_a`` code -> PMC area letter.
_AREA_LETTERS: Final[dict[int, str]] = {area.value: area.name for area in PmcArea}
#: Most entries one ``cnc_rdalmmsg`` answer carries (``max`` 1..32).
_MAX_ALARMS: Final = 32
#: The ``length`` word of ODBM.
_ODBM_LENGTH: Final = 8
#: The machine counter the answer of each read follows: its answers are kept while it holds.
#: Absent are writes, control commands and reads that move with time alone or with the
#: program store (run info, loads, the program directory and text, VersaMax configuration).
_COUNTERS: Final[dict[Command, str]] = {
    Command.RDCNCSTAT: "status_version",
    Command.RDPARAM: "data_version",
    Command.RDDIAG: "data_version",
    Command.RDMACRO: "macro_version",
    Command.RDALMMSG: "alarm_version",
    Command.RDALMHISTRY: "alarm_version",
    Command.RDPMCRNG: "pmc_version",
    Command.RDPRGNUM: "motion_version",
    Command.ACTF: "motion_version",
    Command.ACTS: "motion_version",
    Command.RDPOSITION: "motion_version",
}
#: Command id -> the reader of the counter its answers follow.
_FOLLOWS: Final[dict[int, Counters]] = {int(k): counters_of([v]) for k, v in _COUNTERS.items()}
#: Answers one adapter keeps per command (a few dozen bytes each, a position read of every
#: axis a few hundred).
_KEPT_ANSWERS: Final = 1024
#: Entries of the table of error answers at most.
_ERROR_LIMIT: Final = 4096

_EW_FUNC: Final = encode_ew(EW.FUNC)
#: A ``set_panel`` field that leaves its switch as it is.
_UNCHANGED: Final = -1
#: The IODBPSD width of a real parameter (REALPRM: mantissa and decimals).
_REAL_WIDTH: Final = 8


def _param_value(datano: int, axis: int, value: int, item: DataItem) -> ParamValue:
    """The IODBPSD of ``value`` of ``item``: a bit item's 0..255 as the signed byte of the
    same eight bits, a real item's mantissa with its decimals."""
    if item.kind is ParamKind.BIT and value > 0x7F:
        value -= 0x100
    return ParamValue(datano, axis, value, item.width, item.decimals)


def _item(
    req: Any,
    value: int,
    item_of: Callable[[int], DataItem | None],
    encode: Callable[[ParamValue], bytes],
) -> bytes:
    """The answer of a parameter or diagnostic read (IODBPSD) of ``value``."""
    item = item_of(req.datano)
    assert item is not None
    return encode(_param_value(req.datano, req.axis, value, item))


def _request(command: Command) -> Callable[[bytes], Any]:
    return COMMANDS[command].request.decode


def _response(command: Command) -> Callable[[Any], bytes]:
    return COMMANDS[command].response.encode


_OK: Final = _response(Command.WRPARAM)(None)


def _macro_parts(value: Decimal | None) -> tuple[int, int]:
    """``(mcr_val, dec_val)`` of a macro value (a machine's value has 0..9 decimals); vacant is
    ``(0, -1)``."""
    if value is None:
        return 0, -1
    sign, digits, exponent = value.as_tuple()
    assert isinstance(exponent, int)
    coefficient = int("".join(map(str, digits)))
    return (-coefficient if sign else coefficient), -exponent


class PackedAdapter:
    """Answers packed-protocol requests from one machine (see the module docstring)."""

    #: The command ids :meth:`answer` answers (every command but the fault queues' 0x0E05..7).
    handled: ClassVar[frozenset[int]] = frozenset(
        int(c) for c in COMMANDS if c not in FAULT_COMMANDS and c not in PATH_COMMANDS
    )

    __slots__ = ("_errors", "_kept", "_kept_paths", "_sysinfo", "_table", "machine")

    def __init__(self, machine: Machine) -> None:
        self.machine = machine
        i = machine.identity()
        self._sysinfo = _encode_sysinfo(
            SysInfo(
                i.addinfo,
                i.max_axis,
                i.cnc_type.encode("latin-1"),
                i.mt_type.encode("latin-1"),
                i.series.encode("latin-1"),
                i.version.encode("latin-1"),
                i.axes.encode("latin-1"),
            )
        )
        #: command -> its kept answers: payload -> (its counter, the counter's value then, answer)
        self._kept: dict[int, AnswerMemo] = self._new_memos()
        #: the same for the paths after the first, made when a path is first asked
        self._kept_paths: dict[int, dict[int, AnswerMemo]] = {}
        self._errors: dict[tuple[int, int], bytes] = {}
        by_id: dict[Command, _Handler] = {
            Command.RDCNCSTAT: self._rdcncstat,
            Command.RDPARAM: self._rdparam,
            Command.RDMACRO: self._rdmacro,
            Command.RDDIAG: self._rddiag,
            Command.SYSINFO: self._sysinfo_answer,
            Command.RDALMMSG: self._rdalmmsg,
            Command.RDPRGNUM: self._rdprgnum,
            Command.ACTF: self._actf,
            Command.ACTS: self._acts,
            Command.RDPOSITION: self._rdposition,
            Command.RDPMCRNG: self._rdpmcrng,
            Command.WRPARAM: self._wrparam,
            Command.WRMACRO: self._wrmacro,
            Command.WRPMCRNG: self._wrpmcrng,
            Command.WRUNLOCKPARAM: self._unlock,
            Command.VERSAMAX_RDCONFIG: self._versamax,
            Command.SIM_SET_PANEL: self._set_panel,
            Command.SIM_RAISE_ALARM: self._raise_alarm,
            Command.SIM_CLEAR_ALARMS: self._clear_alarms,
            Command.SIM_SET_PMC: self._set_pmc,
            Command.RDALMHISTRY: self._rdalmhistry,
            Command.RDPARAINFO: self._rdparainfo,
            Command.SIM_READ_PANEL: self._read_panel,
            Command.SIM_VACATE_MACRO: self._vacate_macro,
            Command.RDPROGDIR: self._rdprogdir,
            Command.RDPROGRAM: self._rdprogram,
            Command.RDRUNINFO: self._rdruninfo,
            Command.RDLOADS: self._rdloads,
            Command.WRPROGRAM: self._wrprogram,
            Command.DELPROGRAM: self._delprogram,
            Command.SELPROGRAM: self._selprogram,
            Command.SIM_CYCLE: self._cycle,
            Command.SIM_SET_OVERRIDES: self._set_overrides,
        }
        assert frozenset(by_id) == self.handled
        # plain int keys: a lookup by int must not go through IntEnum hashing
        self._table: dict[int, _Handler] = {int(k): v for k, v in by_id.items()}

    def __repr__(self) -> str:
        return f"PackedAdapter({self.machine!r})"

    @staticmethod
    def _new_memos() -> dict[int, AnswerMemo]:
        return {c: AnswerMemo(_KEPT_ANSWERS) for c in _FOLLOWS}

    def answer(self, session: Session, command: int, payload: bytes, path: int = 1) -> bytes:
        """The complete answer payload of one request on a connection whose selected path is
        ``path`` (0: none, after a refused ``cnc_setpath``); never raises for what a peer
        sends nor for what the machine holds.

        A per-path command answers for ``path``; with no path selected it answers EW_PATH
        (a control command on a machine with control off EW_FUNC first). A path-independent
        command (:data:`~focas_net.protocol.PATH_INDEPENDENT_COMMANDS`) ignores ``path``.

        The machine answers at one instant (:meth:`Machine.instant`): the figures of one
        answer (the run information's timers and parts, the loads of every axis) are of one
        moment, that of the counters a kept answer is kept with. A kept answer whose counters
        hold is returned without stopping machine time (the counters read it once)."""
        if type(payload) is not bytes:  # kept answers key on payload: make it hashable
            payload = bytes(payload)
        if path == 1:
            memos = self._kept
        elif command in _PATH_INDEPENDENT:
            memos, path = self._kept, 1
        elif path:
            memos = self._kept_paths.get(path) or self._kept_paths.setdefault(
                path, self._new_memos()
            )
        else:
            return self._no_path(command)
        memo = memos.get(command)
        if memo is not None:
            kept: tuple[Counters, Any, bytes] | None = memo.get(payload)
            if kept is not None and kept[0](self.machine) == kept[1]:
                return kept[2]  # a poller's request again, what it reads unchanged
        fn = self._table.get(command)
        if fn is None:
            return _EW_FUNC
        try:
            with self.machine.instant():
                if memo is None:
                    return fn(session, payload, path)
                counters = _FOLLOWS[command]
                # The counters at the answer's instant: a machine that moves later makes a miss.
                seen = counters(self.machine)
                answer = fn(session, payload, path)
        except REFUSALS as exc:
            return self.error_answer(command, refusal_code(exc))
        except UNENCODABLE as exc:
            ew = unencodable_code(self.machine, f"command 0x{command:04X}", exc)
            return self.error_answer(command, ew)
        memo.keep(payload, counters, seen, answer)
        return answer

    def _no_path(self, command: int) -> bytes:
        """The answer of a per-path ``command`` on a connection with no path selected."""
        if command not in self._table:
            return _EW_FUNC
        if _CONTROL_FIRST <= command <= _CONTROL_LAST and not self.machine.control_enabled:
            return _EW_FUNC
        return self.error_answer(command, EW.PATH)

    # -- the path selection (0x0040, 0x0140) ---------------------------------------------
    def select_path(self, payload: bytes) -> tuple[bytes, int]:
        """``cnc_setpath``: its answer and the connection's selection from now on: the path
        asked when the machine has it, else 0 (none) with EW_PATH (EW_LENGTH for a payload
        that is not one ``i16``), so that no later request reads another path."""
        try:
            path = _decode_setpath(payload).path
        except PayloadError:
            return self.error_answer(_SETPATH, EW.LENGTH), 0
        if not 1 <= path <= self.machine.path_count:
            return self.error_answer(_SETPATH, EW.PATH), 0
        return _OK, path

    def path_answer(self, payload: bytes, path: int) -> bytes:
        """``cnc_getpath`` on a connection whose selection is ``path`` (0: none)."""
        if payload:
            return self.error_answer(_GETPATH, EW.LENGTH)
        return _encode_getpath(PathSelection(path, self.machine.path_count))

    def error_answer(self, command: int, ew: int) -> bytes:
        """The answer of ``command`` carrying only ``ew`` (``count = -1, ew`` for counted
        lists): what a refusal answers, and a forced EW code of fault injection."""
        key = (command, ew)
        answer = self._errors.get(key)
        if answer is None:
            spec = COMMANDS.get(command)
            answer = spec.error_payload(ew) if spec is not None else encode_ew(ew)
            if len(self._errors) < _ERROR_LIMIT:
                self._errors[key] = answer
        return answer

    # -- reads ---------------------------------------------------------------------------
    def _rdcncstat(self, _session: Session, payload: bytes, path: int) -> bytes:
        if payload:
            _decode_empty(payload)  # raises: this request is empty
        s = self.machine.status(path=path)
        info = StatusInfo(
            s.hdck, s.tmmode, s.aut, s.run, s.motion, s.mstb, s.emergency, s.alarm, s.edit
        )
        return _encode_status(info)

    def _sysinfo_answer(self, _session: Session, payload: bytes, _path: int) -> bytes:
        if payload:
            _decode_empty(payload)
        return self._sysinfo

    def _rdparam(self, _session: Session, payload: bytes, path: int) -> bytes:
        m = self.machine
        req = _decode_param_request(payload)
        value = m.read_param(req.datano, req.axis, path=path)
        return _item(req, value, m.param_item, _encode_param)

    def _rddiag(self, _session: Session, payload: bytes, path: int) -> bytes:
        m = self.machine
        req = _decode_diag_request(payload)
        value = m.read_diag(req.datano, req.axis, path=path)
        return _item(req, value, m.diag_item, _encode_diag)

    def _rdparainfo(self, _session: Session, payload: bytes, _path: int) -> bytes:
        datano = _decode_parainfo_request(payload).datano
        item = self.machine.param_item(datano)
        if item is None:
            raise MachineError(EW.NUMBER, f"no parameter {datano}")
        assert item.kind is not None and item.low is not None and item.high is not None
        info = ParamAttributes(
            datano, int(item.kind), int(item.axis), item.decimals, item.low, item.high
        )
        return _encode_parainfo(info)

    def _rdmacro(self, _session: Session, payload: bytes, path: int) -> bytes:
        number = _decode_macro_request(payload).number
        mcr_val, dec_val = _macro_parts(self.machine.read_macro(number, path=path))
        return _encode_macro(MacroValue(number, _ODBM_LENGTH, mcr_val, dec_val))

    def _rdalmmsg(self, _session: Session, payload: bytes, path: int) -> bytes:
        req = _decode_almmsg_request(payload)
        if not 1 <= req.max <= _MAX_ALARMS:
            raise Refused(EW.LENGTH)
        entries = tuple(
            ActiveAlarm(a.axis_no, a.alm_type, a.alm_no, a.msg)
            for a in self.machine.active_alarms(req.type, req.max, path=path)
        )
        return _encode_almmsg(ActiveAlarmList(entries))

    def _rdalmhistry(self, _session: Session, payload: bytes, _path: int) -> bytes:
        depth = _decode_history_request(payload).depth
        if not 1 <= depth <= MAX_HISTORY_DEPTH:
            raise Refused(EW.LENGTH)
        entries = tuple(
            AlarmHistoryEntry(e.occurred_at, e.axis_no, e.alm_type, e.alm_no, e.msg)
            for e in self.machine.alarm_history(depth)
        )
        return _encode_history(AlarmHistory(entries))

    def _rdprgnum(self, _session: Session, payload: bytes, path: int) -> bytes:
        _decode_prgnum_request(payload)
        mo = self.machine.path_motion(path=path)
        return _encode_prgnum(ProgramNumbers(mo.program_running, mo.program_main))

    def _actf(self, _session: Session, payload: bytes, path: int) -> bytes:
        _decode_actf_request(payload)
        return _encode_actf(ActualValue(self.machine.path_motion(path=path).feed))

    def _acts(self, _session: Session, payload: bytes, path: int) -> bytes:
        _decode_acts_request(payload)
        return _encode_acts(ActualValue(self.machine.path_motion(path=path).spindle_speed))

    def _rdposition(self, _session: Session, payload: bytes, path: int) -> bytes:
        req = _decode_position_request(payload)
        if not 0 <= req.type < len(POSITION_KINDS):
            raise Refused(EW.ATTRIB)
        axis = None if req.axis == -1 else req.axis
        values = self.machine.positions(POSITION_KINDS[req.type], axis, path=path)
        axes = tuple(AxisPosition(name[:4], value) for name, value in values)
        return _encode_position(PositionData(POSITION_DECIMALS, axes))

    def _pmc_letter(self, type_a: int) -> str:
        """The area of ``type_a``: EW_ATTRIB for an unknown code, EW_NOOPT for an area the
        machine does not have."""
        letter = _AREA_LETTERS.get(type_a)
        if letter is None:
            raise Refused(EW.ATTRIB)
        self.machine.check_pmc_area(letter)
        return letter

    @staticmethod
    def _pmc_count(type_d: int, start: int, end: int) -> int:
        if type_d != 0:
            raise Refused(EW.ATTRIB)
        count = end - start + 1
        if not 1 <= count <= MAX_PMC_CHUNK:
            raise Refused(EW.LENGTH)
        return count

    def _rdpmcrng(self, _session: Session, payload: bytes, _path: int) -> bytes:
        r = _decode_pmc_request(payload)
        letter = self._pmc_letter(r.type_a)
        count = self._pmc_count(r.type_d, r.datano_s, r.datano_e)
        data = self.machine.read_pmc(letter, r.datano_s, count)
        return _encode_pmc(PmcData(r.type_a, r.type_d, r.datano_s, r.datano_e, data))

    def _versamax(self, _session: Session, payload: bytes, _path: int) -> bytes:
        req = _decode_versamax_request(payload)
        m = self.machine
        m.config_record(req.rack, req.slot)
        if not 1 <= req.length <= MAX_CONFIG_CHUNK:
            raise Refused(EW.LENGTH)
        data = m.read_config(req.rack, req.slot, req.offset, req.length)
        return _encode_versamax(VersaMaxReply(req.rack, req.slot, req.offset, data))

    # -- writes --------------------------------------------------------------------------
    def _wrparam(self, session: Session, payload: bytes, path: int) -> bytes:
        pv = _decode_param_write(payload)
        m = self.machine
        item = m.param_item(pv.datano)
        value = pv.value
        if item is not None and item.kind is ParamKind.BIT and pv.width == 1:
            value &= 0xFF  # the signed byte carries the eight bits #7..#0
        decimals = pv.decimals if pv.width == _REAL_WIDTH else None
        m.write_param(
            session, pv.datano, pv.axis, value, width=pv.width, decimals=decimals, path=path
        )
        return _OK

    def _wrmacro(self, _session: Session, payload: bytes, path: int) -> bytes:
        mv = _decode_macro_write(payload)
        if mv.length != _ODBM_LENGTH:
            raise Refused(EW.LENGTH)
        self.machine.write_macro(mv.number, Decimal(f"{mv.mcr_val}E{-mv.dec_val}"), path=path)
        return _OK

    def _write_pmc(self, d: PmcData, *, force: bool) -> bytes:
        m = self.machine
        m.check_writable()
        letter = self._pmc_letter(d.type_a)
        count = self._pmc_count(d.type_d, d.datano_s, d.datano_e)
        if len(d.data) != count:
            raise Refused(EW.LENGTH)
        m.write_pmc(letter, d.datano_s, d.data, force=force)
        return _OK

    def _wrpmcrng(self, _session: Session, payload: bytes, _path: int) -> bytes:
        return self._write_pmc(_decode_pmc_write(payload), force=False)

    def _unlock(self, session: Session, payload: bytes, _path: int) -> bytes:
        # A password longer than the 4 bytes of the payload is a wrong one (EW_PASSWD, the
        # session locked), never cut to its first 4 bytes; a shorter payload is EW_LENGTH.
        if len(payload) > PASSWORD_SIZE:
            self.machine.unlock(session, payload)
        self.machine.unlock(session, _decode_password(payload).password)
        return _OK

    # -- part programs (0x0030..0x0032, 0x0110..0x0112) ----------------------------------------
    def _rdprogdir(self, _session: Session, payload: bytes, path: int) -> bytes:
        req = _decode_dir_request(payload)
        if not 1 <= req.max <= MAX_DIRECTORY_ENTRIES:
            raise Refused(EW.LENGTH)
        chosen = [p for p in self.machine.program_directory(path=path) if p.number >= req.first]
        entries = tuple(
            ProgramEntry(p.number, p.size, p.name.encode("ascii", "replace").decode("ascii"))
            for p in chosen[: req.max]
        )
        return _encode_dir(ProgramDirectory(entries))

    def _rdprogram(self, _session: Session, payload: bytes, path: int) -> bytes:
        req = _decode_chunk_request(payload)
        raw = self.machine.program_text(req.number, path=path).encode("ascii", "replace")
        if not 0 <= req.offset <= len(raw):
            raise Refused(EW.DATA)
        chunk = raw[req.offset : req.offset + MAX_PROGRAM_CHUNK].decode("ascii")
        return _encode_chunk(ProgramChunk(len(raw), chunk))

    def _rdruninfo(self, _session: Session, payload: bytes, path: int) -> bytes:
        if payload:
            _decode_empty(payload)
        m = self.machine
        feed, rapid, spindle = m.overrides(path=path)
        timers = [m.timer_ms(k, path=path) for k in range(len(TIMER_KINDS))]
        count, total = m.parts_counts(path=path)
        return _encode_runinfo(RunInfo(feed, rapid, spindle, count, total, *timers))

    def _rdloads(self, _session: Session, payload: bytes, path: int) -> bytes:
        if payload:
            _decode_empty(payload)
        m = self.machine
        return _encode_loads(LoadMeters(m.spindle_loads(path=path), m.servo_loads(path=path)))

    def _wrprogram(self, _session: Session, payload: bytes, path: int) -> bytes:
        req = _decode_program_text(payload)
        self.machine.check_writable()
        if req.replace not in (0, 1):
            raise Refused(EW.DATA)
        number = self.machine.store_program(req.text, replace=bool(req.replace), path=path)
        return _encode_stored(ProgramNumber(number))

    def _delprogram(self, _session: Session, payload: bytes, path: int) -> bytes:
        self.machine.delete_program(_decode_program_number(payload).number, path=path)
        return _OK

    def _selprogram(self, _session: Session, payload: bytes, path: int) -> bytes:
        self.machine.select_program(_decode_program_number(payload).number, path=path)
        return _OK

    # -- simulator control: the cycle (0x0E20, 0x0E21) -------------------------------------
    def _cycle(self, _session: Session, payload: bytes, path: int) -> bytes:
        if not self.machine.control_enabled:
            return _EW_FUNC
        action = _decode_cycle(payload).action
        m = self.machine
        m.check_writable()
        if action == CycleAction.START:
            m.cycle_start(path=path)
        elif action == CycleAction.HOLD:
            m.feed_hold(path=path)
        elif action == CycleAction.RESET:
            m.reset(path=path)
        else:
            raise Refused(EW.DATA)
        return _OK

    def _set_overrides(self, _session: Session, payload: bytes, path: int) -> bytes:
        if not self.machine.control_enabled:
            return _EW_FUNC
        o = _decode_overrides(payload)
        self.machine.set_overrides(
            None if o.feed == _UNCHANGED else o.feed,
            None if o.rapid == _UNCHANGED else o.rapid,
            None if o.spindle == _UNCHANGED else o.spindle,
            path=path,
        )
        return _OK

    # -- simulator control (0x0E01..0x0E04) -------------------------------------------------
    def _set_panel(self, _session: Session, payload: bytes, path: int) -> bytes:
        if not self.machine.control_enabled:
            return _EW_FUNC
        p = _decode_set_panel(payload)
        # -1 leaves a switch as it is (docs/protocol.md section 8)
        self.machine.set_panel(
            None if p.mode == _UNCHANGED else p.mode,
            None if p.pwe == _UNCHANGED else p.pwe,
            None if p.emergency == _UNCHANGED else p.emergency,
            path=path,
        )
        return _OK

    def _read_panel(self, _session: Session, payload: bytes, path: int) -> bytes:
        if not self.machine.control_enabled:
            return _EW_FUNC
        if payload:
            _decode_empty(payload)
        p = self.machine.path_panel(path)
        return _encode_panel(SetPanel(p.mode, p.pwe, p.emergency))

    def _vacate_macro(self, _session: Session, payload: bytes, path: int) -> bytes:
        if not self.machine.control_enabled:
            return _EW_FUNC
        self.machine.write_macro(_decode_vacate_macro(payload).number, None, path=path)
        return _OK

    def _raise_alarm(self, _session: Session, payload: bytes, path: int) -> bytes:
        if not self.machine.control_enabled:
            return _EW_FUNC
        a = _decode_raise_alarm(payload)
        self.machine.raise_alarm(
            a.axis_no, a.alm_type, a.alm_no, a.msg.decode("latin-1"), path=path
        )
        return _OK

    def _clear_alarms(self, _session: Session, payload: bytes, path: int) -> bytes:
        if not self.machine.control_enabled:
            return _EW_FUNC
        c = _decode_clear_alarms(payload)
        self.machine.clear_alarms(c.alm_type, c.alm_no, path=path)
        return _OK

    def _set_pmc(self, _session: Session, payload: bytes, _path: int) -> bytes:
        if not self.machine.control_enabled:
            return _EW_FUNC
        return self._write_pmc(_decode_set_pmc(payload), force=True)


# The codecs of each command, looked up once.
_decode_empty: Final = _request(Command.RDCNCSTAT)
_encode_status: Final = _response(Command.RDCNCSTAT)
_encode_sysinfo: Final = _response(Command.SYSINFO)
_decode_param_request: Final = _request(Command.RDPARAM)
_encode_param: Final = _response(Command.RDPARAM)
_decode_diag_request: Final = _request(Command.RDDIAG)
_encode_diag: Final = _response(Command.RDDIAG)
_decode_macro_request: Final = _request(Command.RDMACRO)
_encode_macro: Final = _response(Command.RDMACRO)
_decode_almmsg_request: Final = _request(Command.RDALMMSG)
_encode_almmsg: Final = _response(Command.RDALMMSG)
_decode_history_request: Final = _request(Command.RDALMHISTRY)
_encode_history: Final = _response(Command.RDALMHISTRY)
_decode_prgnum_request: Final = _request(Command.RDPRGNUM)
_encode_prgnum: Final = _response(Command.RDPRGNUM)
_decode_actf_request: Final = _request(Command.ACTF)
_encode_actf: Final = _response(Command.ACTF)
_decode_acts_request: Final = _request(Command.ACTS)
_encode_acts: Final = _response(Command.ACTS)
_decode_position_request: Final = _request(Command.RDPOSITION)
_encode_position: Final = _response(Command.RDPOSITION)
_decode_pmc_request: Final = _request(Command.RDPMCRNG)
_encode_pmc: Final = _response(Command.RDPMCRNG)
_decode_versamax_request: Final = _request(Command.VERSAMAX_RDCONFIG)
_encode_versamax: Final = _response(Command.VERSAMAX_RDCONFIG)
_decode_param_write: Final = _request(Command.WRPARAM)
_decode_macro_write: Final = _request(Command.WRMACRO)
_decode_pmc_write: Final = _request(Command.WRPMCRNG)
_decode_password: Final = _request(Command.WRUNLOCKPARAM)
_decode_set_panel: Final = _request(Command.SIM_SET_PANEL)
_encode_panel: Final = _response(Command.SIM_READ_PANEL)
_decode_parainfo_request: Final = _request(Command.RDPARAINFO)
_encode_parainfo: Final = _response(Command.RDPARAINFO)
_decode_raise_alarm: Final = _request(Command.SIM_RAISE_ALARM)
_decode_clear_alarms: Final = _request(Command.SIM_CLEAR_ALARMS)
_decode_set_pmc: Final = _request(Command.SIM_SET_PMC)
_decode_vacate_macro: Final = _request(Command.SIM_VACATE_MACRO)
_decode_dir_request: Final = _request(Command.RDPROGDIR)
_encode_dir: Final = _response(Command.RDPROGDIR)
_decode_chunk_request: Final = _request(Command.RDPROGRAM)
_encode_chunk: Final = _response(Command.RDPROGRAM)
_encode_runinfo: Final = _response(Command.RDRUNINFO)
_encode_loads: Final = _response(Command.RDLOADS)
_decode_program_text: Final = _request(Command.WRPROGRAM)
_encode_stored: Final = _response(Command.WRPROGRAM)
_decode_program_number: Final = _request(Command.DELPROGRAM)
_decode_cycle: Final = _request(Command.SIM_CYCLE)
_decode_overrides: Final = _request(Command.SIM_SET_OVERRIDES)
_decode_setpath: Final = _request(Command.SETPATH)
_encode_getpath: Final = _response(Command.GETPATH)
_SETPATH: Final = int(Command.SETPATH)
_GETPATH: Final = int(Command.GETPATH)
#: Commands answered the same on every path (plain ints, as the wire's).
_PATH_INDEPENDENT: Final = frozenset(int(c) for c in PATH_INDEPENDENT_COMMANDS)
#: Every simulator control id is 0x0Exx.
_CONTROL_FIRST: Final = 0x0E00
_CONTROL_LAST: Final = 0x0EFF
