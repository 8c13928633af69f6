"""The native adapter: the open answer, and one data-request body in, the whole answer out.

Pure and synchronous, like :mod:`focas_net.adapters.packed` on the packed side: a
:class:`NativeAdapter` wraps one protocol-neutral :class:`~focas_net.sim.Machine` and speaks as
a real control of the machine's class does to FANUC's library (``libfwlib32``):

* **the command set** follows the machine's ``control_class``: a 16i, 18i, 21i or 0i-C answers
  with version 2 (the "16i set": parameters 0x0E/0x10/0x0F, diagnostics 0x30, base-2 macro
  writes), a 0i-D, 0i-F, 30i, 31i or 32i with version 3 (the "30i set": 0x8D/0xA0/0x8E, 0x93,
  0xA4/0xA3 wrapping, base-10 macro writes); see :class:`focas_net.native.CommandSet`;
* **the open answer** (:meth:`NativeAdapter.open_answer`) describes one path with the machine
  type, its axes and spindles, and the CNC's max axes; the FOCAS option bits (bit 0, needed by
  ``cnc_rddynamic2``) are in the open answer at version 3 and in parameter 9968 at version 2;
* every request block is answered with a block, in order (device, path and command echoed, an
  EW code, the data). Every command of both sets is served whichever set the handle uses;
* part programs: directory, memory, delete, search and the blocks being executed are data
  requests; uploads and downloads are frames of their own (:meth:`NativeAdapter.transfer`),
  a download kept in the connection's :class:`ProgramTransfer` and stored at its end only.

Rules of this wire (the CNC's rules are the machine's, see :mod:`focas_net.sim.machine`):

* a block whose ``(device, command)`` is not served answers ``EW_FUNC``; a path other than 0
  or 1 answers ``EW_PATH`` (the machine has one path);
* a refusal of the machine answers its EW code (``EW_NUMBER``, ``EW_ATTRIB``, ``EW_PROT``,
  ``EW_PASSWD``, ``EW_LENGTH``...), the code the packed protocol answers for the same request;
  an ``EW_NUMBER`` block carries the detail words ``cnc_getdtailerr`` reads: 1 and the number
  asked (this project's choice);
* every answer fits the body size the answer's version allows (1450 bytes for version 2, 2910
  for 3): room for the 16-byte head of every later block is kept, and a block whose data would
  not fit what is left answers ``EW_LENGTH``. So PMC ranges are limited by one answer, not by
  the packed protocol's 32 bytes;
* a request with more blocks than the limit can answer even as bare heads is a framing
  violation (:class:`NativeFrameError`): the connection is closed;
* parameter and diagnostic records carry the machine's type (:attr:`DataItem.kind`) in the
  library's numbering (:func:`native_param_type`, :func:`native_diag_type`). A real value is
  FANUC's REALPRM, ``(mantissa, 10, decimals)``: one 8-byte slot in the 30i set, two 4-byte
  slots in the 16i set. A bit parameter travels as the byte of its bits (0xB0 for 10110000) and
  is written back as 0..255;
* the 16i set has no way to write a real parameter: 0x10 answers type bits 0-1 of the real type
  (0, a bit parameter), so ``cnc_wrparam`` refuses every length but 5 with EW_LENGTH itself, and
  a 0x0F record of a real parameter (1-byte or REAL slots) answers EW_LENGTH too: FANUC's
  library returns EW_LENGTH (2) for a real parameter in the 16i set, whatever the length;
* the parameters FANUC's library reads on its own, 9968 (its option bits, 16i set, while
  connecting; also the open answer's option bits in the 30i set) and 3115 (position display
  bits, ``cnc_rdposition`` in the 16i set), are the machine's own: every machine has them
  (:class:`~focas_net.sim.Machine` gives the defaults), so both protocols read the same values;
* figures the machine does not model (the free purpose timer, the CNC ID) answer the values
  :class:`NativeAdapter` documents at each handler; the spindle and servo loads are the
  machine's (:meth:`~focas_net.sim.Machine.spindle_loads`, ``servo_loads``).

Answers of reads are kept: a request made of the reads in :data:`_COUNTERS` only, every block
answered without an EW code, is answered again from a memo keyed by its body for as long as the
machine counters those reads follow (``status_version``, ``data_version``, ``macro_version``,
``alarm_version``, ``pmc_version``, ``motion_version``; none for what never changes) stay where
they were before it was answered, as :mod:`focas_net.adapters.packed` keeps its answers. A
poller's repeated frame then costs one look-up and a compare.

A macro value written as a double (0xA8) is the decimal :func:`macro_from_double` makes of it,
written with the machine's own ``write_macro`` (a vacant double, a NaN, makes the variable
vacant; a double with no such decimal is passed on as it is, for the machine to refuse).
"""

from __future__ import annotations

import hashlib
import math
import re
import struct
from bisect import bisect_left, bisect_right
from collections.abc import Callable
from decimal import MAX_EMAX, MAX_PREC, MIN_EMIN, ROUND_HALF_EVEN, Context, Decimal
from operator import attrgetter
from typing import Any, Final

from focas_net._memo import Memo
from focas_net.errors import EW
from focas_net.native import (
    MACHINE_LATHE,
    MACHINE_MILL,
    MAGIC_WORD,
    NATIVE_HEADER,
    OPTION_PARAMETER,
    PROGRAM_CHUNK,
    RESPONSE_BLOCK_SIZE,
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
    BlockCount,
    CncId,
    CommandSet,
    Device,
    DiagType,
    ExecutingBlocks,
    ExecutingBlocksRequest,
    ExecutingProgram,
    FrameType,
    HdckStatus,
    ItemRecord,
    MacroDouble,
    MacroDoubleReadRequest,
    MacroDoubles,
    MacroDoubleWriteRequest,
    MacroReadRequest,
    MacroWriteRequest,
    NativeAlarmHistoryRequest,
    NativeCommand,
    NativeFrameError,
    NativePayloadError,
    NativePmcArea,
    NativePositionKind,
    NativePositionRequest,
    NativeProgramNumbers,
    NativeSysInfo,
    ParamInfo,
    ParamInfo3,
    ParamInfo3Request,
    ParamInfoEntry,
    ParamInfoRequest,
    ParamType,
    ParamWrite3Request,
    ParamWriteRequest,
    PathDescription,
    PmcDataType,
    PmcReadRequest,
    PmcWriteRequest,
    PositionAxisName,
    PositionAxisNames,
    ProgramDeleteRequest,
    ProgramDirEntry,
    ProgramDirRequest,
    ProgramMemory,
    ProgramSearchRequest,
    RequestBlock,
    ResponseBlockHead,
    ScaledItemRecord,
    ScaledNumber,
    ScaledValues,
    SequenceNumber,
    ServoMeterRequest,
    SpindleLoadRequest,
    StatInfo,
    TimerRequest,
    TimerValue,
    TmModeStatus,
    TransferError,
    TransferFrame,
    TransferStart,
    binary_to_decimal,
    build_open_answer,
    decode_request_body,
    encode_close_response,
    encode_native_frame,
    encode_open_response,
    error_frame_type,
    max_response_body,
    parse_program_range,
    resolve_position_kind,
)
from focas_net.sim import (
    MAX_MACRO_DECIMALS,
    PMC_AREAS,
    POSITION_DECIMALS,
    DataItem,
    Machine,
    MachineError,
    ParamKind,
    Session,
)
from focas_net.sim.machine import MAX_REAL_DECIMALS

__all__ = [
    "NativeAdapter",
    "ProgramTransfer",
    "command_set_of",
    "macro_from_double",
    "native_diag_type",
    "native_param_type",
]

#: Control classes that speak the 16i command set; every other class speaks the 30i set.
_CLASSES_16I: Final = frozenset({"16i", "18i", "21i", "0i-C"})
#: Version word of the answers of each command set (a 16i answers 2, a 0i-D 3).
_SET_VERSIONS: Final = {CommandSet.FS16I: 2, CommandSet.FS30I: 3}
#: FOCAS option bits of a machine whose parameter 9968 is an axis parameter (otherwise the
#: open answer of the 30i set carries 9968's value): bit 0 is what ``cnc_rddynamic2`` needs.
OPTION_BITS: Final = 1
#: Spindles of the path (the machine models one spindle speed).
SPINDLES: Final = 1
#: Flags of each axis in the 0xA3 answer: machine, absolute/relative and distance shown.
_DISPLAY_FLAGS: Final = 0x07

_I32_MIN: Final = -(2**31)
_I32_MAX: Final = 2**31 - 1
_QUANTA: Final = tuple(Decimal(1).scaleb(-d) for d in range(MAX_MACRO_DECIMALS + 1))
_SERVED_PATHS: Final = frozenset({0, 1})
#: The machine counter the answer of each read block follows ("" for what never changes: the
#: identity, the axes): a request of these only is answered from a memo while those counters
#: hold. Absent are writes, and reads that move with time alone or with the program store
#: (timers, loads, servo meters, program directory and memory, the blocks being executed).
_COUNTERS: Final[dict[tuple[int, int], str]] = {
    (Device.CNC, NativeCommand.SYSINFO): "",
    (Device.CNC, NativeCommand.RDCNCID): "",
    (Device.CNC, NativeCommand.AXIS_NAME): "",
    (Device.CNC, NativeCommand.AXIS_UNIT): "",
    (Device.CNC, NativeCommand.AXIS_COUNT): "",
    (Device.CNC, NativeCommand.AXIS_DISPLAY): "",
    (Device.CNC, NativeCommand.STATINFO): "status_version",
    (Device.CNC, NativeCommand.STAT_HDCK): "status_version",
    (Device.CNC, NativeCommand.STAT_TMMODE): "status_version",
    (Device.CNC, NativeCommand.RDPARAM): "data_version",
    (Device.CNC, NativeCommand.RDPARAINFO): "data_version",
    (Device.CNC, NativeCommand.RDPARAM3): "data_version",
    (Device.CNC, NativeCommand.RDPARAINFO3): "data_version",
    (Device.CNC, NativeCommand.RDDIAG): "data_version",
    (Device.CNC, NativeCommand.RDDIAG3): "data_version",
    (Device.CNC, NativeCommand.RDMACRO): "macro_version",
    (Device.CNC, NativeCommand.RDMACRO_DOUBLE): "macro_version",
    (Device.CNC, NativeCommand.ALARM): "alarm_version",
    (Device.CNC, NativeCommand.RDALMMSG): "alarm_version",
    (Device.CNC, NativeCommand.RDALMHISTRY): "alarm_version",
    (Device.PMC, NativeCommand.PMC_RDPMCRNG): "pmc_version",
    (Device.CNC, NativeCommand.RDPRGNUM): "motion_version",
    (Device.CNC, NativeCommand.RDSEQNUM): "motion_version",
    (Device.CNC, NativeCommand.EXEPRGNAME): "motion_version",
    (Device.CNC, NativeCommand.ACTF): "motion_version",
    (Device.CNC, NativeCommand.ACTS): "motion_version",
    (Device.CNC, NativeCommand.POSITION): "motion_version",
}
#: Answers one adapter keeps: the request bodies a poller repeats. An answer is 1.5 KiB at most
#: (2.9 at version 3), so a machine keeps under 100 KiB of them at worst.
_KEPT_ANSWERS: Final = 32


def _no_counters(machine: Machine) -> tuple[()]:
    """The counters of a request whose answer never changes: none."""
    return ()


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
_ITEM_HEAD_SIZE: Final = 8
_HISTORY_SIZE: Final = AlarmHistoryRecord.SIZE
#: Width in bytes of a value of each 16i/30i parameter type (BIT travels as a byte, REAL as
#: REALPRM).
_PARAM_WIDTHS: Final[dict[int, int]] = {
    ParamType.BIT: 1,
    ParamType.BYTE: 1,
    ParamType.WORD: 2,
    ParamType.TWO_WORD: 4,
    ParamType.REAL: 8,
}
#: Diagnostic type word of each kind (the library reads no bit type in a diagnostic).
_DIAG_TYPES: Final[dict[ParamKind, DiagType]] = {
    ParamKind.BIT: DiagType.BYTE,
    ParamKind.BYTE: DiagType.BYTE,
    ParamKind.WORD: DiagType.WORD,
    ParamKind.TWO_WORD: DiagType.TWO_WORD,
    ParamKind.REAL: DiagType.REAL,
}

#: The sequence number a block starts with.
_SEQUENCE: Final = re.compile(r"\s*N(\d+)")

#: data-request body -> its request blocks (a poll sends the same body again and again).
_REQUEST_BODIES: Final = Memo(512)

#: A context that neither rounds nor overflows: scaling a coefficient by its exponent is exact.
_EXACT: Final = Context(prec=MAX_PREC, Emax=MAX_EMAX, Emin=MIN_EMIN)

_pack_block = ResponseBlockHead.STRUCT.pack
_pack_scaled = ScaledNumber.STRUCT.pack
_pack_count = BlockCount.STRUCT.pack
_ITEM_HEAD_PACK: Final = struct.Struct(">ihh").pack
_I32_PACK: Final = struct.Struct(">i").pack
_I32_ZERO: Final = bytes(4)
_FOUR_U32: Final = struct.Struct(">4I")


def command_set_of(machine: Machine) -> CommandSet:
    """The command set a control of ``machine``'s class speaks to FANUC's library."""
    return CommandSet.FS16I if machine.control_class in _CLASSES_16I else CommandSet.FS30I


def native_param_type(item: DataItem) -> ParamType:
    """The type word of parameter ``item`` in FANUC's library's numbering (0 bit, 1 byte,
    2 word, 3 two-word, 4 real): its :attr:`~focas_net.sim.DataItem.kind`, which FANUC numbers
    the same way."""
    assert item.kind is not None
    return ParamType(int(item.kind))


def native_diag_type(item: DataItem) -> DiagType:
    """The type word of diagnostic ``item`` in FANUC's library's numbering (0 byte, 1 word,
    2 two-word, 5 real); a bit diagnostic is a byte."""
    assert item.kind is not None
    return _DIAG_TYPES[item.kind]


def macro_from_double(value: float) -> tuple[int, int] | None:
    """``(digits, decimals)`` of the decimal a double written with 0xA8 stands for (the value
    is ``digits / 10**decimals``); None when there is none a macro variable can hold
    (infinite, NaN, or too large for a 32-bit mantissa even with no decimals).

    Rule: take the shortest decimal that reads back as the same double (Python's ``repr``),
    round it half-even to at most 9 decimals, drop decimals (rounding again) until the mantissa
    fits a signed 32-bit integer, then drop trailing zeros. So 100.0 -> (100, 0), 1.5 -> (15, 1),
    0.1 -> (1, 1), 1/3 -> (333333333, 9), 12345.678901234 -> (123456789, 4).
    """
    if not math.isfinite(value) or abs(value) > -_I32_MIN:
        return None
    exact = Decimal(repr(value))
    exponent = exact.as_tuple().exponent
    assert isinstance(exponent, int)
    decimals = min(max(-exponent, 0), MAX_MACRO_DECIMALS)
    while True:
        rounded = exact.quantize(_QUANTA[decimals], rounding=ROUND_HALF_EVEN)
        mantissa = int(rounded.scaleb(decimals))
        if _I32_MIN <= mantissa <= _I32_MAX:
            break
        if decimals == 0:
            return None
        decimals -= 1
    return _trimmed(mantissa, decimals)


def _trimmed(mantissa: int, decimals: int) -> tuple[int, int]:
    while decimals > 0 and mantissa % 10 == 0:
        mantissa //= 10
        decimals -= 1
    return mantissa, decimals


def _acceptable(item: DataItem, value: int, decimals: list[int] | None, i: int) -> bool:
    """Whether the machine takes ``value`` for ``item`` (a real one's mantissa with
    ``decimals[i]`` decimals, rescaled to the item's own exactly), as to its range."""
    if decimals is not None and item.kind is ParamKind.REAL:
        if not 0 <= decimals[i] <= MAX_REAL_DECIMALS:
            return False
        shift = item.decimals - decimals[i]
        if shift >= 0:
            value *= 10**shift
        elif value % 10**-shift:
            return False
        else:
            value //= 10**-shift
    assert item.low is not None and item.high is not None
    return item.low <= value <= item.high


class _Refused(Exception):
    """A block refused by the adapter itself (not by the machine): answer it with ``ew``."""

    def __init__(self, ew: int) -> None:
        super().__init__(ew)
        self.ew = ew


#: block, room for its data -> data. Raises MachineError, NativePayloadError or _Refused.
_Handler = Callable[[RequestBlock, int], bytes]


def _need_room(size: int, room: int) -> None:
    if size > room:
        raise _Refused(EW.LENGTH)


def _macro_parts(value: Decimal | None) -> tuple[int, int]:
    """``(mantissa, decimals)`` of a macro value (a machine's value has 0..9 decimals); vacant
    is ``(0, -1)``."""
    if value is None:
        return 0, -1
    exponent = value.as_tuple()[2]
    assert isinstance(exponent, int)
    return int(value.scaleb(-exponent, _EXACT)), -exponent


def _macro_of_double(value: float) -> Decimal:
    """The value :func:`macro_from_double` makes of ``value``, or ``value`` itself as a decimal
    when there is none (for the machine to refuse with EW_DATA after its other checks)."""
    stored = macro_from_double(value)
    if stored is None:
        return Decimal(repr(value))
    mantissa, decimals = stored
    return Decimal(f"{mantissa}E-{decimals}")


def _i16(value: int) -> int:
    """``value`` as a signed 16-bit word (its low 16 bits)."""
    return ((value + 0x8000) & 0xFFFF) - 0x8000


def _axis_name(name: str) -> AxisName:
    """The 4-byte name of an axis: its first character, then its second as the suffix."""
    raw = name.encode("ascii", "replace")
    return AxisName(raw[:1], raw[1:2] or b"\x00")


#: Most bytes of one download (a larger one answers EW_OVRFLOW at its end).
MAX_DOWNLOAD: Final = 1 << 20


class ProgramTransfer:
    """One connection's program download (``cnc_dwnstart``... ``cnc_dwnend``): whether one
    is under way and the text received so far. The server keeps one per connection, so a
    connection dropped in the middle of a download stores nothing; the machine sees only the
    whole program, at the download's end."""

    __slots__ = ("downloading", "overflow", "received")

    def __init__(self) -> None:
        #: Whether a download was started and not ended.
        self.downloading = False
        #: Whether the download went past :data:`MAX_DOWNLOAD` (its bytes were dropped).
        self.overflow = False
        #: The download's bytes so far.
        self.received = bytearray()

    def reset(self) -> None:
        self.downloading = False
        self.overflow = False
        self.received.clear()


class NativeAdapter:
    """Answers FANUC's library for one machine (see the module docstring).

    ``version`` overrides the version word the machine's control class picks (it also picks
    the command set: 16i up to 2, 30i from 3).
    """

    __slots__ = (
        "_answers",
        "_axis_names",
        "_diag_numbers",
        "_handlers",
        "_max_blocks",
        "_own_session",
        "_param_numbers",
        "_scaled_zero",
        "_session",
        "_status",
        "_status_version",
        "_sysinfo",
        "command_set",
        "limit",
        "machine",
        "max_axis",
        "version",
    )

    def __init__(self, machine: Machine, *, version: int | None = None) -> None:
        self.machine = machine
        if version is None:
            version = _SET_VERSIONS[command_set_of(machine)]
        #: Version word of every answer; it sets :attr:`limit` and :attr:`command_set`.
        self.version = version
        #: The command set FANUC's library uses with this adapter.
        self.command_set = CommandSet.for_version(version)
        #: Largest answer body (:func:`max_response_body` of the version).
        self.limit = max_response_body(version)
        self._max_blocks = (self.limit - 2) // RESPONSE_BLOCK_SIZE
        i = machine.identity()
        #: Value slots per parameter/diagnostic record and position records for all axes: the
        #: open answer's max axes.
        self.max_axis = max(i.max_axis, len(machine.axes), 1)
        self._sysinfo = NativeSysInfo(
            i.addinfo, i.max_axis, i.cnc_type, i.mt_type, i.series, i.version, i.axes
        ).encode()
        self._axis_names = [_axis_name(a) for a in machine.axes]
        self._status = b""
        self._status_version = -1
        #: request body -> (the counters its answer follows, their values then, the frame)
        self._answers = Memo(_KEPT_ANSWERS)
        self._param_numbers = machine.param_numbers()
        self._diag_numbers = machine.diag_numbers()
        self._scaled_zero = _pack_scaled(0, 10, 0)
        self._own_session = machine.new_session()
        self._session = self._own_session
        cnc, pmc, c = Device.CNC, Device.PMC, NativeCommand
        self._handlers: dict[tuple[int, int], _Handler] = {
            (cnc, c.SYSINFO): self._read_sysinfo,
            (cnc, c.STATINFO): self._read_status,
            (cnc, c.STAT_HDCK): self._read_hdck,
            (cnc, c.STAT_TMMODE): self._read_tmmode,
            (cnc, c.RDCNCID): self._read_cnc_id,
            (cnc, c.RDTIMER): self._read_timer,
            (cnc, c.RDPRGNUM): self._read_program_numbers,
            (cnc, c.RDSEQNUM): self._read_sequence,
            (cnc, c.EXEPRGNAME): self._read_executing_program,
            (cnc, c.ACTF): self._read_feed,
            (cnc, c.ACTS): self._read_spindle,
            (cnc, c.ALARM): self._read_alarm_bits,
            (cnc, c.RDALMMSG): self._read_alarms,
            (cnc, c.RDALMHISTRY): self._read_history,
            (cnc, c.RDMACRO): self._read_macros,
            (cnc, c.WRMACRO): self._write_macro,
            (cnc, c.RDMACRO_DOUBLE): self._read_macro_doubles,
            (cnc, c.WRMACRO_DOUBLE): self._write_macro_double,
            (cnc, c.RDPARAM): self._read_params,
            (cnc, c.RDPARAINFO): self._read_param_info,
            (cnc, c.WRPARAM): self._write_param,
            (cnc, c.RDPARAM3): self._read_params_30i,
            (cnc, c.RDPARAINFO3): self._read_param_info_30i,
            (cnc, c.WRPARAM3): self._write_param_30i,
            (cnc, c.RDDIAG): self._read_diags,
            (cnc, c.RDDIAG3): self._read_diags_30i,
            (cnc, c.POSITION): self._read_positions,
            (cnc, c.AXIS_NAME): self._read_axis_names,
            (cnc, c.AXIS_UNIT): self._read_axis_units,
            (cnc, c.AXIS_COUNT): self._read_axis_count,
            (cnc, c.AXIS_DISPLAY): self._read_axis_display,
            (cnc, c.RDSPLOAD): self._read_spindle_load,
            (cnc, c.RDSVMETER): self._read_servo_meter,
            (cnc, c.RDPROGDIR): self._read_program_directory,
            (cnc, c.RDPROGINFO): self._read_program_memory,
            (cnc, c.DELETE): self._delete_program,
            (cnc, c.SEARCH): self._search_program,
            (cnc, c.RDEXECPROG): self._read_executing_blocks,
            (pmc, c.PMC_RDPMCRNG): self._read_pmc,
            (pmc, c.PMC_WRPMCRNG): self._write_pmc,
        }

    def __repr__(self) -> str:
        return f"NativeAdapter({self.machine!r}, version={self.version})"

    @property
    def served(self) -> frozenset[tuple[int, int]]:
        """``(device, command)`` of every block this adapter answers with data."""
        return frozenset(self._handlers)

    # -- open and close ------------------------------------------------------------------

    def open_answer(self) -> bytes:
        """The body of the open answer: one path (machine type from the identity, the
        machine's axes, one spindle) and the CNC's max axes; at version 3 the option bits."""
        mt = self.machine.identity().mt_type
        machine_type = MACHINE_LATHE if mt.strip() == "T" else MACHINE_MILL
        path = PathDescription(machine_type, len(self.machine.axes), SPINDLES)
        return build_open_answer(
            [path], self.max_axis, option_bits=self._option_bits(), version=self.version
        )

    def _option_bits(self) -> int:
        """The FOCAS option bits: parameter 9968 of the machine (read by the library itself in
        the 16i set)."""
        item = self.machine.param_item(OPTION_PARAMETER)
        if item is None or item.axis:
            return OPTION_BITS
        return item.values[0] & 0xFFFF

    def open_response(self) -> bytes:
        """The whole open-answer frame."""
        return encode_open_response(self.open_answer(), self.version)

    def close_response(self) -> bytes:
        """The whole close-answer frame."""
        return encode_close_response(self.version)

    # -- requests ------------------------------------------------------------------------

    def _blocks(self, data: bytes | bytearray | memoryview) -> tuple[RequestBlock, ...]:
        # a bytearray or a view is looked up as bytes: a memo key is immutable
        body = data if type(data) is bytes else bytes(data)
        blocks: tuple[RequestBlock, ...] | None = _REQUEST_BODIES.get(body)
        if blocks is None:
            blocks = decode_request_body(body)
            _REQUEST_BODIES.put(body, blocks)
        if len(blocks) > self._max_blocks:
            raise NativeFrameError(
                f"{len(blocks)} request blocks: at most {self._max_blocks} can be answered"
            )
        return blocks

    def _frame(self, parts: list[bytes]) -> bytes:
        """The data-response frame of ``parts`` (``parts[0]`` is the place of its header)."""
        length = sum(map(len, parts))
        parts[0] = NATIVE_HEADER.pack(MAGIC_WORD, self.version, FrameType.DATA_RESPONSE, length)
        return b"".join(parts)

    def answer(self, body: bytes, session: Session | None = None) -> bytes:
        """The whole data-response frame answering the data-request ``body``; ``session`` is
        the connection's (parameter writes), the adapter's own when None.

        Raises :class:`NativeFrameError` when the block list is broken or longer than an
        answer can hold; everything else is answered in its block. A request of no block is
        answered with one EW_FUNC block (FANUC's library refuses an answer of no block).
        """
        key = body if type(body) is bytes else bytes(body)
        kept: tuple[Callable[[Machine], Any], Any, bytes] | None = self._answers.get(key)
        machine = self.machine
        if kept is not None and kept[0](machine) == kept[1]:
            return kept[2]  # a poller's request again, what it reads unchanged
        blocks = self._blocks(key)
        if not blocks:
            blocks = (RequestBlock(Device.CNC, 1, 0),)
        kinds = [_COUNTERS.get((b.device, b.command)) for b in blocks]
        if None in kinds:
            return self._answer(blocks, session)[0]
        names = sorted({k for k in kinds if k})
        counters: Callable[[Machine], Any] = (
            attrgetter(names[0], *names[1:]) if names else _no_counters
        )
        # Read before answering: a machine that moves meanwhile only makes the memo miss.
        seen = counters(machine)
        frame, failed = self._answer(blocks, session)
        if not failed:
            self._answers.put(key, (counters, seen, frame))
        return frame

    def _answer(
        self, blocks: tuple[RequestBlock, ...], session: Session | None
    ) -> tuple[bytes, bool]:
        """The answer frame of ``blocks``, and whether a block of it answered an EW code."""
        self._session = self._own_session if session is None else session
        count = len(blocks)
        parts: list[bytes] = [b"", _pack_count(count)]
        left = self.limit - 2 - RESPONSE_BLOCK_SIZE * count
        handlers = self._handlers
        failed = False
        for block in blocks:
            handler = handlers.get((block.device, block.command))
            ew = 0
            data = b""
            if handler is None:
                ew = EW.FUNC
            elif block.path not in _SERVED_PATHS:
                ew = EW.PATH
            else:
                try:
                    data = handler(block, left)
                except MachineError as exc:
                    ew = exc.ew
                except (NativePayloadError, _Refused) as exc:
                    ew = exc.ew
                else:
                    if len(data) > left:  # a handler's own check guards this already
                        ew, data = EW.LENGTH, b""
            size = len(data)
            left -= size
            detail1 = detail2 = 0
            if ew:
                failed = True
                if ew == EW.NUMBER:
                    detail1, detail2 = 1, _i16(block.args[0])
            parts.append(
                _pack_block(
                    RESPONSE_BLOCK_SIZE + size,
                    block.device,
                    block.path,
                    block.command,
                    ew,
                    detail1,
                    detail2,
                    size,
                )
            )
            if size:
                parts.append(data)
        return self._frame(parts), failed

    def forced_answer(self, body: bytes, ew: int) -> bytes:
        """The data-response frame answering ``body`` with ``ew`` and no data in every block
        (a forced EW code of fault injection: nothing runs). Raises :class:`NativeFrameError`
        as :meth:`answer` does."""
        blocks = self._blocks(body)
        parts: list[bytes] = [b"", _pack_count(len(blocks))]
        parts.extend(
            _pack_block(RESPONSE_BLOCK_SIZE, b.device, b.path, b.command, ew, 0, 0, 0)
            for b in blocks
        )
        return self._frame(parts)

    # -- identity and status -------------------------------------------------------------

    def _read_sysinfo(self, block: RequestBlock, room: int) -> bytes:
        return self._sysinfo

    def _read_status(self, block: RequestBlock, room: int) -> bytes:
        machine = self.machine
        if self._status_version != machine.status_version:
            s = machine.status()
            self._status = StatInfo(
                s.aut, s.run, s.motion, s.mstb, s.emergency, s.alarm, s.edit
            ).encode()
            self._status_version = machine.status_version
        return self._status

    def status_info(self) -> StatInfo:
        """The status as a 0x19 answer carries it."""
        self._read_status(RequestBlock(Device.CNC, 1, NativeCommand.STATINFO), self.limit)
        return StatInfo.decode(self._status)

    def _read_hdck(self, block: RequestBlock, room: int) -> bytes:
        return HdckStatus(self.machine.status().hdck).encode()

    def _read_tmmode(self, block: RequestBlock, room: int) -> bytes:
        return TmModeStatus(self.machine.status().tmmode).encode()

    def _read_cnc_id(self, block: RequestBlock, room: int) -> bytes:
        """The CNC ID: four words of the SHA-256 of the machine's name (stable per name)."""
        digest = hashlib.sha256(self.machine.name.encode("utf-8")).digest()
        return CncId(*_FOUR_U32.unpack(digest[:16])).encode()

    def _read_timer(self, block: RequestBlock, room: int) -> bytes:
        """Timers 0 power-on, 1 operating, 2 cutting, 3 cycle: the machine's (``Machine.timer``,
        machine time) as IODBTIME, whole minutes and the milliseconds past them; 4 (the free
        purpose timer, which the machine does not keep) reads 0; another type answers
        EW_NUMBER."""
        req = TimerRequest.from_block(block)
        if not 0 <= req.type <= 4:
            raise _Refused(EW.NUMBER)
        if req.type == 4:
            return TimerValue(0, 0).encode()
        ms = self.machine.timer_ms(req.type)
        minute, msec = divmod(ms, 60_000)
        return TimerValue(minute, msec).encode()

    # -- motion figures ------------------------------------------------------------------

    def _read_program_numbers(self, block: RequestBlock, room: int) -> bytes:
        m = self.machine.motion
        return NativeProgramNumbers(m.program_running, m.program_main).encode()

    def _read_sequence(self, block: RequestBlock, room: int) -> bytes:
        return SequenceNumber(self.machine.motion.sequence).encode()

    def _read_executing_program(self, block: RequestBlock, room: int) -> bytes:
        """The running program: its O number and its name ``O<number>`` (four digits at
        least)."""
        number = self.machine.motion.program_running
        return ExecutingProgram(number, f"O{number:04d}".encode("ascii")).encode()

    def _read_feed(self, block: RequestBlock, room: int) -> bytes:
        return _pack_scaled(self.machine.motion.feed, 10, 0)

    def _read_spindle(self, block: RequestBlock, room: int) -> bytes:
        return _pack_scaled(self.machine.motion.spindle_speed, 10, 0)

    def _read_positions(self, block: RequestBlock, room: int) -> bytes:
        req = NativePositionRequest.from_block(block)
        kind = resolve_position_kind(req.kind)
        if kind is None:
            raise _Refused(EW.ATTRIB)
        axis = req.axis
        # the machine's checks first: no skip function (EW_NOOPT), an axis it has not (EW_ATTRIB)
        positions = self.machine.positions(_POSITION_KINDS[kind], None if axis == -1 else axis)
        if axis == -1:
            _need_room(SCALED_SIZE * self.max_axis, room)
            parts = [_pack_scaled(v, 10, POSITION_DECIMALS) for _, v in positions]
            parts.extend([self._scaled_zero] * (self.max_axis - len(parts)))
            return b"".join(parts)
        return _pack_scaled(positions[0][1], 10, POSITION_DECIMALS)

    def _read_axis_names(self, block: RequestBlock, room: int) -> bytes:
        """0x89: 4 bytes per axis (argument 0) or 16 (-1: head, absolute, machine and
        relative names)."""
        req = AxisNameRequest.from_block(block)
        names = self._axis_names
        if req.kind == -1:
            data = PositionAxisNames(tuple(PositionAxisName.of(n, n, n) for n in names)).encode()
        else:
            data = AxisNames(tuple(names)).encode()
        _need_room(len(data), room)
        return data

    def _read_axis_units(self, block: RequestBlock, room: int) -> bytes:
        """0x88: per axis, the unit of the positions and of the machine position (0, mm)."""
        AxisUnitRequest.from_block(block)
        _need_room(AxisUnit.SIZE * len(self._axis_names), room)
        return AxisUnits((AxisUnit(0, 0),) * len(self._axis_names)).encode()

    def _read_axis_count(self, block: RequestBlock, room: int) -> bytes:
        """0xA4: the axes (0), spindles (1) or servo axes (2) of the path."""
        req = AxisCountRequest.from_block(block)
        if req.kind == 1:
            return AxisCount(SPINDLES).encode()
        if req.kind in (0, 2):
            return AxisCount(len(self.machine.axes)).encode()
        raise _Refused(EW.ATTRIB)

    def _read_axis_display(self, block: RequestBlock, room: int) -> bytes:
        """0xA3: every position of every axis shown."""
        AxisDisplayRequest.from_block(block)
        _need_room(AxisDisplay.SIZE * len(self._axis_names), room)
        shown = AxisDisplay(bytes(3), _DISPLAY_FLAGS)
        return AxisDisplays((shown,) * len(self._axis_names)).encode()

    def _read_spindle_load(self, block: RequestBlock, room: int) -> bytes:
        """0x40: the load of each spindle in percent (:meth:`Machine.spindle_loads`)."""
        spindle = SpindleLoadRequest.from_block(block).spindle
        if spindle != -1 and not 1 <= spindle <= SPINDLES:
            raise _Refused(EW.NUMBER)
        loads = self.machine.spindle_loads()[:SPINDLES]
        return ScaledValues(tuple(ScaledNumber(v, 0) for v in loads)).encode()

    def _read_servo_meter(self, block: RequestBlock, room: int) -> bytes:
        """0x56: the servo load of each axis in percent (:meth:`Machine.servo_loads`)."""
        ServoMeterRequest.from_block(block)
        _need_room(SCALED_SIZE * len(self._axis_names), room)
        loads = self.machine.servo_loads()
        return ScaledValues(tuple(ScaledNumber(v, 0) for v in loads)).encode()

    # -- part programs -------------------------------------------------------------------

    def _read_program_directory(self, block: RequestBlock, room: int) -> bytes:
        """0x06: the programs from O number ``top`` on, by number, at most ``count`` (and what
        the answer holds), 72 bytes each; none from ``top`` on is no data (the end)."""
        req = ProgramDirRequest.from_block(block)
        if req.count < 1:
            raise _Refused(EW.LENGTH)
        most = min(req.count, room // ProgramDirEntry.SIZE)
        entries = [e for e in self.machine.program_directory() if e.number >= req.top][:most]
        return b"".join(
            ProgramDirEntry(e.number, e.size, _program_comment(e.name)).encode() for e in entries
        )

    def _read_program_memory(self, block: RequestBlock, room: int) -> bytes:
        """0x07: programs stored and the room for more, characters used and free (the
        machine's program store: its directory, capacity and most programs)."""
        machine = self.machine
        directory = machine.program_directory()
        store = machine.programs
        used = sum(e.size for e in directory)
        return ProgramMemory(
            len(directory),
            max(store.max_programs - len(directory), 0),
            used,
            max(store.capacity - used, 0),
        ).encode()

    def _delete_program(self, block: RequestBlock, room: int) -> bytes:
        """0x05: the machine's ``delete_program`` (EW_PROT, EW_NUMBER, EW_BUSY)."""
        self.machine.delete_program(ProgramDeleteRequest.from_block(block).number)
        return b""

    def _search_program(self, block: RequestBlock, room: int) -> bytes:
        """0x03: the machine's ``select_program`` (EW_PROT, EW_MODE, EW_NUMBER, EW_BUSY)."""
        self.machine.select_program(ProgramSearchRequest.from_block(block).number)
        return b""

    def _read_executing_blocks(self, block: RequestBlock, room: int) -> bytes:
        """0x20: the blocks of the running program from the one being executed on (the block
        of the sequence number the machine shows, else the program's first block), whole
        blocks of at most ``length`` characters and what the answer holds; the block count
        first. No running program is no block."""
        req = ExecutingBlocksRequest.from_block(block)
        if req.length < 1:
            raise _Refused(EW.LENGTH)
        motion = self.machine.motion
        try:
            text = self.machine.program_text(motion.program_running)
        except MachineError:
            return ExecutingBlocks(0, b"").encode()
        lines = text.splitlines()[1:]  # after the O line
        start = 0
        if motion.sequence > 0:
            for i, line in enumerate(lines):
                match = _SEQUENCE.match(line)
                if match is not None and int(match.group(1)) == motion.sequence:
                    start = i
                    break
        most = min(req.length, room - 4)
        out: list[bytes] = []
        size = 0
        for line in lines[start:]:
            raw = (line + "\n").encode("latin-1", "replace")
            if size + len(raw) > most:
                break
            out.append(raw)
            size += len(raw)
        return ExecutingBlocks(len(out), b"".join(out)).encode()

    def transfer(self, frame_type: int, body: bytes, state: ProgramTransfer) -> list[bytes] | None:
        """The frames answering one program-transfer frame of a connection whose transfer
        state is ``state`` (see :mod:`focas_net.native.programs`); None when ``frame_type``
        is not a transfer request (the connection's violation).

        * ``0x1501`` upload: ``0x1502``, the text as ``%``, newline, each program's text,
          ``%`` in ``0x1604`` frames of at most :data:`PROGRAM_CHUNK` bytes, then ``0x1701``;
          ``0x1702`` and ``0x1804`` (the library's end and abort) answer nothing;
        * ``0x1101`` download start: ``0x1102`` (EW_PROT on a read-only machine); ``0x1204``
          data is kept in ``state``; ``0x1301`` stores the program, ``0x1302``.

        A refusal is a ``0x..03`` frame carrying the EW code (:class:`TransferError`), the
        code the packed protocol gives for the same program operation.
        """
        try:
            kind = TransferFrame(frame_type)
        except ValueError:
            return None
        try:
            if kind is TransferFrame.UPLOAD_START:
                return self._upload(body)
            if kind is TransferFrame.DOWNLOAD_START:
                TransferStart.decode(body)
                state.reset()
                self.machine.check_writable()
                state.downloading = True
                return [self._transfer_frame(TransferFrame.DOWNLOAD_START_ANSWER)]
            if kind is TransferFrame.DOWNLOAD_DATA:
                if state.downloading and not state.overflow:
                    if len(state.received) + len(body) > MAX_DOWNLOAD:
                        state.overflow = True
                        state.received.clear()
                    else:
                        state.received += body
                return []
            if kind is TransferFrame.DOWNLOAD_END:
                return self._download_end(state)
        except MachineError as exc:
            return [self._transfer_refusal(frame_type, exc.ew)]
        except (NativePayloadError, _Refused) as exc:
            return [self._transfer_refusal(frame_type, exc.ew)]
        if kind in (TransferFrame.UPLOAD_END_ANSWER, TransferFrame.UPLOAD_ABORT):
            return []
        return None  # an answer type: never sent to a CNC

    def _transfer_frame(self, frame_type: int, body: bytes = b"") -> bytes:
        return encode_native_frame(frame_type, body, self.version)

    def _transfer_refusal(self, frame_type: int, ew: int) -> bytes:
        return self._transfer_frame(
            error_frame_type(frame_type), TransferError(0, ew, 0, 0).encode()
        )

    def _upload(self, body: bytes) -> list[bytes]:
        first, last = parse_program_range(TransferStart.decode(body).name)
        machine = self.machine
        if first == last:
            texts = [machine.program_text(first)]  # EW_NUMBER when there is none
        else:
            numbers = [e.number for e in machine.program_directory() if first <= e.number <= last]
            if not numbers:
                raise _Refused(EW.NUMBER)
            texts = [machine.program_text(n) for n in numbers]
        data = ("%\n" + "".join(texts) + "%").encode("latin-1", "replace")
        frames = [self._transfer_frame(TransferFrame.UPLOAD_START_ANSWER)]
        frames.extend(
            self._transfer_frame(TransferFrame.UPLOAD_DATA, data[i : i + PROGRAM_CHUNK])
            for i in range(0, len(data), PROGRAM_CHUNK)
        )
        frames.append(self._transfer_frame(TransferFrame.UPLOAD_END))
        return frames

    def _download_end(self, state: ProgramTransfer) -> list[bytes]:
        """Store the downloaded program: EW_FUNC when no download was started, EW_OVRFLOW
        past :data:`MAX_DOWNLOAD`, EW_DATA for text that is not ASCII, then the machine's
        ``store_program`` refusals (EW_PROT, EW_DATA, EW_NUMBER, EW_REJECT, EW_OVRFLOW)."""
        downloading, overflow = state.downloading, state.overflow
        raw = bytes(state.received)
        state.reset()
        if not downloading:
            raise _Refused(EW.FUNC)
        if overflow:
            raise _Refused(EW.OVRFLOW)
        try:
            text = raw.decode("ascii")
        except UnicodeDecodeError:
            raise _Refused(EW.DATA) from None
        self.machine.store_program(_downloaded_program(text))
        return [self._transfer_frame(TransferFrame.DOWNLOAD_END_ANSWER)]

    # -- macro variables -----------------------------------------------------------------

    def _read_macros(self, block: RequestBlock, room: int) -> bytes:
        req = MacroReadRequest.from_block(block)
        count = req.last - req.first + 1
        if count < 1:
            raise _Refused(EW.LENGTH)
        _need_room(SCALED_SIZE * count, room)
        read = self.machine.read_macro
        parts = []
        for number in range(req.first, req.last + 1):
            mantissa, decimals = _macro_parts(read(number))
            parts.append(_pack_scaled(mantissa, 10, decimals))  # vacant: (0, -1)
        return b"".join(parts)

    def _write_macro(self, block: RequestBlock, room: int) -> bytes:
        """0x16: a base-10 record as it is (decimals -1: vacant); a binary one (the 16i set)
        as the decimal ``cnc_rdmacro`` shows of it, trailing zeros dropped (12.345 sent as
        ``62C28F5C 0002 001B`` is written 12.345)."""
        req = MacroWriteRequest.from_block(block)
        v = req.value
        value: Decimal | None
        if v.vacant:
            value = None
        elif v.binary:
            mantissa, decimals = _trimmed(*binary_to_decimal(v.mantissa, v.decimals))
            value = Decimal(mantissa).scaleb(-decimals)
        else:
            value = Decimal(v.mantissa).scaleb(-v.decimals)
        self.machine.write_macro(req.number, value)
        return b""

    def _read_macro_doubles(self, block: RequestBlock, room: int) -> bytes:
        req = MacroDoubleReadRequest.from_block(block)
        if req.count < 1:
            raise _Refused(EW.LENGTH)
        _need_room(MacroDouble.SIZE * req.count, room)
        read = self.machine.read_macro
        values: list[float | None] = []
        for number in range(req.first, req.first + req.count):
            value = read(number)
            if value is None:
                values.append(None)  # a quiet NaN
            else:
                mantissa, decimals = _macro_parts(value)
                values.append(mantissa / 10**decimals)
        return MacroDoubles(tuple(values)).encode()

    def _write_macro_double(self, block: RequestBlock, room: int) -> bytes:
        req = MacroDoubleWriteRequest.from_block(block)
        value = None if req.value is None else _macro_of_double(req.value)
        self.machine.write_macro(req.number, value)
        return b""

    # -- parameters and diagnostics ------------------------------------------------------

    def _items(
        self,
        block: RequestBlock,
        room: int,
        numbers: tuple[int, ...],
        read: Callable[[int, int], int],
        item_of: Callable[[int], DataItem | None],
        type_of: Callable[[DataItem], int],
        scaled: bool,
    ) -> bytes:
        """Records of the items ``first..last`` (``axis`` 0, k or -1): 4-byte slots (16i set)
        or 8-byte slots (30i set), ``max_axis`` of them; a real value is ``(mantissa, 10,
        decimals)``, two 4-byte slots or one 8-byte slot."""
        args = block.args
        first, last, axis = args[0], args[1], args[2]
        if last < first:
            raise _Refused(EW.LENGTH)
        lo = bisect_left(numbers, first)
        hi = bisect_right(numbers, last)
        if lo == hi:
            raise _Refused(EW.NUMBER)
        max_axis = self.max_axis
        slot = SCALED_SIZE if scaled else 4
        n_axes = len(self.machine.axes)
        # a real record of the 16i set takes two slots per value
        _need_room((hi - lo) * (_ITEM_HEAD_SIZE + slot * max(max_axis, 2 * n_axes)), room)
        slots_size = slot * max_axis
        parts: list[bytes] = []
        for number in numbers[lo:hi]:
            if axis == -1:
                try:
                    first_value = read(number, 0)
                except MachineError as exc:
                    if exc.ew != EW.ATTRIB:
                        raise
                    values = [read(number, a) for a in range(1, n_axes + 1)]
                    record_axis = -1
                else:
                    values = [first_value]
                    record_axis = 0
            else:
                values = [read(number, axis)]
                record_axis = axis
            item = item_of(number)
            assert item is not None
            parts.append(_ITEM_HEAD_PACK(number, record_axis, type_of(item)))
            if item.kind is ParamKind.REAL:
                decimals = item.decimals
                data = b"".join(_pack_scaled(v, 10, decimals) for v in values)
            elif scaled:
                data = b"".join(_pack_scaled(v, 10, 0) for v in values)
            else:
                data = b"".join(map(_I32_PACK, values))
            parts.append(data)
            if len(data) < slots_size:  # empty slots: (0, 10, 0) or a zero i32
                empty = self._scaled_zero if scaled else _I32_ZERO
                parts.append(empty * ((slots_size - len(data)) // len(empty)))
        return b"".join(parts)

    def _read_params(self, block: RequestBlock, room: int) -> bytes:
        m = self.machine
        numbers = self._param_numbers
        return self._items(
            block, room, numbers, m.read_param, m.param_item, native_param_type, False
        )

    def _read_params_30i(self, block: RequestBlock, room: int) -> bytes:
        m = self.machine
        numbers = self._param_numbers
        return self._items(
            block, room, numbers, m.read_param, m.param_item, native_param_type, True
        )

    def _read_diags(self, block: RequestBlock, room: int) -> bytes:
        m = self.machine
        numbers = self._diag_numbers
        return self._items(block, room, numbers, m.read_diag, m.diag_item, native_diag_type, False)

    def _read_diags_30i(self, block: RequestBlock, room: int) -> bytes:
        m = self.machine
        numbers = self._diag_numbers
        return self._items(block, room, numbers, m.read_diag, m.diag_item, native_diag_type, True)

    def _info_items(self, first: int, count: int) -> tuple[int, int, list[DataItem]]:
        """``prev, next`` and the parameters from ``first`` on, ``count`` of them."""
        if count < 1:
            raise _Refused(EW.LENGTH)
        numbers = self._param_numbers
        lo = bisect_left(numbers, first)
        chosen = numbers[lo : lo + count]
        if not chosen:
            raise _Refused(EW.NUMBER)
        prev_no = numbers[lo - 1] if lo else 0
        end = lo + len(chosen)
        next_no = numbers[end] if end < len(numbers) else 0
        items = [self.machine.param_item(n) for n in chosen]
        return prev_no, next_no, [i for i in items if i is not None]

    def _read_param_info(self, block: RequestBlock, room: int) -> bytes:
        """0x10: ``prev, next``, then per parameter from ``first`` on its number and attribute
        (type in bits 0-1; bit 8, the axis bit, is left 0 as ``cnc_wrparam`` needs)."""
        req = ParamInfoRequest.from_block(block)
        prev_no, next_no, items = self._info_items(req.first, req.count)
        _need_room(8 + ParamInfoEntry.SIZE * len(items), room)
        entries = tuple(ParamInfoEntry(i.number, native_param_type(i) & 3) for i in items)
        return ParamInfo(prev_no, next_no, entries).encode()

    def _read_param_info_30i(self, block: RequestBlock, room: int) -> bytes:
        """0xA0: 28 bytes of the parameter ``first``: its type (0..4) and 2 for an axis
        parameter."""
        req = ParamInfo3Request.from_block(block)
        prev_no, next_no, items = self._info_items(req.first, 1)
        item = items[0]
        axis_kind = 2 if item.axis else 0
        return ParamInfo3(
            prev_no, next_no, item.number, native_param_type(item), axis_kind
        ).encode()

    def _write_items(
        self,
        number: int,
        axis: int,
        ptype: int,
        values: list[int],
        decimals: list[int] | None = None,
    ) -> None:
        """Write parameter ``number`` (``axis`` 0, k or -1 for every axis, ``values`` one per
        slot) given as type ``ptype`` (a real one's mantissas, each with its ``decimals``)."""
        m = self.machine
        m.check_writable()
        width = _PARAM_WIDTHS.get(ptype)
        if width is None:
            raise _Refused(EW.ATTRIB)
        item = m.param_item(number)
        if item is not None and item.kind is ParamKind.BIT and width == 1:
            values = [v & 0xFF for v in values]  # the byte carries the eight bits #7..#0
        session = self._session

        def write(a: int, i: int) -> None:
            d = None if decimals is None else decimals[i]
            m.write_param(session, number, a, values[i], width=width, decimals=d)

        if axis == -1:
            n = len(m.axes)
            if len(values) < n:
                raise _Refused(EW.LENGTH)
            if item is not None and not item.axis:
                write(0, 0)
                return
            # the machine writes one axis at a time: an axis whose value it would refuse is
            # written first, so that a refused write changes no axis
            order = list(range(1, n + 1))
            if item is not None:
                order.sort(key=lambda a: _acceptable(item, values[a - 1], decimals, a - 1))
            for a in order:
                write(a, a - 1)
            return
        if not values:
            raise _Refused(EW.LENGTH)
        write(axis, 0)

    def _write_param(self, block: RequestBlock, room: int) -> bytes:
        """0x0F: one record with 4-byte slots (16i set). A real value cannot be given in it:
        a REAL record answers EW_LENGTH (as a 1-byte value of a real parameter does)."""
        rec: ItemRecord = ParamWriteRequest.from_block(block).record
        if rec.type == ParamType.REAL:
            self.machine.check_writable()
            raise _Refused(EW.LENGTH)
        width = _PARAM_WIDTHS.get(rec.type, 4)
        bits = 8 * width
        values = [((v + (1 << (bits - 1))) % (1 << bits)) - (1 << (bits - 1)) for v in rec.values]
        self._write_items(rec.number, rec.axis, rec.type, values)
        return b""

    def _write_param_30i(self, block: RequestBlock, room: int) -> bytes:
        """0x8E: one record with 8-byte slots (30i set); the mantissa of each slot, and of a
        REAL record the decimals of each slot."""
        rec: ScaledItemRecord = ParamWrite3Request.from_block(block).record
        decimals = None
        if rec.type == ParamType.REAL:
            decimals = [v.decimals for v in rec.values]
        self._write_items(
            rec.number, rec.axis, rec.type, [v.mantissa for v in rec.values], decimals
        )
        return b""

    # -- PMC -----------------------------------------------------------------------------

    def _pmc_area(self, area: int, data_type: int) -> tuple[str, int]:
        try:
            letter = NativePmcArea(area).name
        except ValueError:
            raise _Refused(EW.ATTRIB) from None
        if letter not in PMC_AREAS:  # an area the simulated CNC never has
            raise _Refused(EW.NOOPT)
        try:
            width = PmcDataType(data_type).width
        except ValueError:
            raise _Refused(EW.ATTRIB) from None
        return letter, width

    def _read_pmc(self, block: RequestBlock, room: int) -> bytes:
        req = PmcReadRequest.from_block(block)
        letter, width = self._pmc_area(req.area, req.data_type)
        count = req.last - req.first + 1
        if count < 1 or count % width:
            raise _Refused(EW.LENGTH)
        _need_room(count, room)
        raw = self.machine.read_pmc(letter, req.first, count)
        return _swap(raw, width)

    def _write_pmc(self, block: RequestBlock, room: int) -> bytes:
        req = PmcWriteRequest.from_block(block)
        self.machine.check_writable()
        letter, width = self._pmc_area(req.area, req.data_type)
        data = req.data.raw
        count = req.last - req.first + 1
        if count < 1 or count % width or len(data) != count:
            raise _Refused(EW.LENGTH)
        self.machine.write_pmc(letter, req.first, _swap(data, width))
        return b""

    # -- alarms --------------------------------------------------------------------------

    def _read_alarm_bits(self, block: RequestBlock, room: int) -> bytes:
        """0x1A: bit n set when an alarm of type n is active."""
        bits = 0
        for a in self.machine.active_alarms():
            bits |= 1 << a.alm_type
        return AlarmStatus(bits - (1 << 32) if bits & 0x8000_0000 else bits).encode()

    def _read_alarms(self, block: RequestBlock, room: int) -> bytes:
        req = AlarmMessageRequest.from_block(block)
        if req.count < 1 or req.text_length < 0:
            raise _Refused(EW.LENGTH)
        alarms = self.machine.active_alarms(req.alarm_type, min(req.count, _MAX_ALARMS))
        text_length = req.text_length
        _need_room(len(alarms) * (_ALARM_HEAD_SIZE + text_length), room)
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

    def _read_history(self, block: RequestBlock, room: int) -> bytes:
        """0x6C: entries ``first..last`` of the history (1 = the newest), 60 bytes each;
        EW_NUMBER when ``first`` is past the last entry."""
        req = NativeAlarmHistoryRequest.from_block(block)
        if req.first < 1 or req.last < req.first:
            raise _Refused(EW.NUMBER)
        entries = self.machine.alarm_history(req.last)[req.first - 1 :]
        if not entries:
            raise _Refused(EW.NUMBER)
        _need_room(_HISTORY_SIZE * len(entries), room)
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


def _program_comment(name: str) -> bytes:
    """A directory entry's comment: the program's name in parentheses, as a control shows it
    (at most 63 bytes, so a NUL always ends it); empty without a name."""
    if not name:
        return b""
    return f"({name[:61]})".encode("latin-1", "replace")


def _downloaded_program(text: str) -> str:
    """The program of a download's text: without a first ``%`` (and the blank lines around
    it) and without anything from the ending ``%`` on, as a control reads punched tape."""
    text = text.lstrip()
    if text.startswith("%"):
        text = text[1:].lstrip()
    end = text.find("%")
    return text if end < 0 else text[:end]


def _swap(raw: bytes, width: int) -> bytes:
    """PMC memory is little-endian, the native wire big-endian: reverse each ``width`` item."""
    if width == 1:
        return raw
    out = bytearray(len(raw))
    for i in range(width):
        out[i::width] = raw[width - 1 - i :: width]
    return bytes(out)
