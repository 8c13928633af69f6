"""The native adapter: one data-request body in, the whole data-response frame out.

Pure and synchronous, like :mod:`focas_net.adapters.packed` on the packed side: a
:class:`NativeAdapter` wraps one protocol-neutral :class:`~focas_net.sim.Machine` and answers
every request block with a response block, in order (device, path and command echoed, an EW
code, the data). The asyncio shell (:mod:`focas_net.native.server`) only moves frames.

Rules of this wire (``docs/native-protocol.md``; the CNC's rules are the machine's, see
:mod:`focas_net.sim.machine`):

* a block whose ``(device, command)`` is not served answers ``EW_FUNC``; a path other than 0
  or 1 answers ``EW_PATH`` (the machine has one path);
* a refusal of the machine answers its EW code (``EW_NUMBER``, ``EW_ATTRIB``, ``EW_PROT``...);
* every answer fits the body size the response version allows (1450 bytes for version 2):
  room for the 16-byte head of every later block is kept, and a block whose data would not fit
  what is left answers ``EW_LENGTH``. The size is computed from the arguments **before** any
  data is gathered (a position read asks the machine first: its EW_NOOPT for the skip position
  and EW_ATTRIB for an axis it has not come before EW_LENGTH, as they always did);
* a request with more blocks than the limit can answer even as bare heads (90 at version 2)
  is a framing violation (:class:`NativeFrameError`): the connection is closed;
* this wire's own numbering and limits: PMC ``adr_type`` codes (an unknown code -> EW_ATTRIB, a
  letter the simulated CNC has no area for, M, N or Z, -> EW_NOOPT, both before the data type
  is looked at; a machine without the area answers EW_NOOPT after the size checks), the PMC
  data type (EW_ATTRIB) and a byte count that is not a whole number of items (EW_LENGTH), both
  position numberings, at most 32 alarm messages per block, and no more data than one answer
  can carry.

A macro value written as a double (0xA8) is the decimal :func:`macro_from_double` makes of it,
written with the machine's own ``write_macro`` (a vacant double, a NaN, makes the variable
vacant; a double with no such decimal is passed on as it is, for the machine to refuse).
"""

from __future__ import annotations

import math
import struct
from bisect import bisect_left, bisect_right
from collections.abc import Callable
from decimal import ROUND_HALF_EVEN, Decimal
from typing import Final

from focas_net.errors import EW
from focas_net.native.codec import (
    _DOUBLE,
    _MAGIC_U32,
    _NAN_BITS,
    _RESPONSE_BLOCK,
    _SCALED,
    _U16,
    DEFAULT_SERVER_VERSION,
    NATIVE_HEADER,
    RESPONSE_BLOCK_SIZE,
    SCALED_SIZE,
    AlarmMessage,
    AlarmMessageRequest,
    AlarmMessages,
    Device,
    DiagnosticRequest,
    FrameType,
    MacroDoubleReadRequest,
    MacroDoubleWriteRequest,
    MacroReadRequest,
    NativeCommand,
    NativeFrameError,
    NativePayloadError,
    NativePmcArea,
    NativePositionKind,
    NativePositionRequest,
    NativeProgramNumbers,
    NativeSysInfo,
    ParamRead3Request,
    ParamReadRequest,
    PmcDataType,
    PmcReadRequest,
    RequestBlock,
    StatInfo,
    decode_request_body,
    max_response_body,
    resolve_position_kind,
)
from focas_net.sim import (
    MAX_MACRO_DECIMALS,
    PMC_AREAS,
    POSITION_DECIMALS,
    DataItem,
    Machine,
    MachineError,
)

__all__ = ["ITEM_TYPES", "ITEM_TYPES_30I", "NativeAdapter", "macro_from_double"]

#: Item ``type`` word of 0x0E/0x30 records by value width in bytes (16i numbering).
ITEM_TYPES: Final[dict[int, int]] = {1: 0, 2: 1, 4: 2}
#: Item ``type`` word of 0x8D records by value width in bytes (30i numbering).
ITEM_TYPES_30I: Final[dict[int, int]] = {1: 1, 2: 2, 4: 3}

_I32_MIN: Final = -(2**31)
_I32_MAX: Final = 2**31 - 1
_QUANTA: Final = tuple(Decimal(1).scaleb(-d) for d in range(MAX_MACRO_DECIMALS + 1))
_SERVED_PATHS: Final = frozenset({0, 1})
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

_pack_block = _RESPONSE_BLOCK.pack
_pack_scaled = _SCALED.pack
_pack_double = _DOUBLE.pack
_ITEM_HEAD_PACK: Final = struct.Struct(">ihh").pack
_I32_PACK: Final = struct.Struct(">i").pack
_I32_ZERO: Final = bytes(4)


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
    while decimals and mantissa % 10 == 0:
        mantissa //= 10
        decimals -= 1
    return mantissa, decimals


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
    sign, digits, exponent = value.as_tuple()
    assert isinstance(exponent, int)
    coefficient = int("".join(map(str, digits)))
    return (-coefficient if sign else coefficient), -exponent


def _macro_of_double(value: float) -> Decimal:
    """The value :func:`macro_from_double` makes of ``value``, or ``value`` itself as a decimal
    when there is none (for the machine to refuse with EW_DATA after its other checks)."""
    stored = macro_from_double(value)
    if stored is None:
        return Decimal(repr(value))
    mantissa, decimals = stored
    return Decimal(f"{mantissa}E-{decimals}")


class NativeAdapter:
    """Answers native data requests from one machine (see the module docstring)."""

    __slots__ = (
        "_diag_numbers",
        "_handlers",
        "_max_blocks",
        "_param_numbers",
        "_scaled_zero",
        "_status",
        "_status_version",
        "_sysinfo",
        "limit",
        "machine",
        "max_axis",
        "version",
    )

    def __init__(self, machine: Machine, *, version: int = DEFAULT_SERVER_VERSION) -> None:
        self.machine = machine
        #: Version word of every answer; it sets :attr:`limit`.
        self.version = version
        #: Largest answer body (:func:`max_response_body` of the version).
        self.limit = max_response_body(version)
        self._max_blocks = (self.limit - 2) // RESPONSE_BLOCK_SIZE
        i = machine.identity()
        #: Value slots per parameter/diagnostic record and position records for all axes.
        self.max_axis = max(i.max_axis, len(machine.axes), 1)
        self._sysinfo = NativeSysInfo(
            i.addinfo, i.max_axis, i.cnc_type, i.mt_type, i.series, i.version, i.axes
        ).encode()
        self._status = b""
        self._status_version = -1
        self._param_numbers = machine.param_numbers()
        self._diag_numbers = machine.diag_numbers()
        self._scaled_zero = _pack_scaled(0, 10, 0)
        cnc, pmc = Device.CNC, Device.PMC
        self._handlers: dict[tuple[int, int], _Handler] = {
            (cnc, NativeCommand.SYSINFO): self._read_sysinfo,
            (cnc, NativeCommand.STATINFO): self._read_status,
            (cnc, NativeCommand.RDPRGNUM): self._read_program_numbers,
            (cnc, NativeCommand.ACTF): self._read_feed,
            (cnc, NativeCommand.ACTS): self._read_spindle,
            (cnc, NativeCommand.RDMACRO): self._read_macros,
            (cnc, NativeCommand.RDMACRO_DOUBLE): self._read_macro_doubles,
            (cnc, NativeCommand.WRMACRO_DOUBLE): self._write_macro_double,
            (cnc, NativeCommand.RDPARAM): self._read_params,
            (cnc, NativeCommand.RDPARAM3): self._read_params_30i,
            (cnc, NativeCommand.RDDIAG): self._read_diags,
            (cnc, NativeCommand.RDALMMSG): self._read_alarms,
            (cnc, NativeCommand.POSITION): self._read_positions,
            (pmc, NativeCommand.PMC_RDPMCRNG): self._read_pmc,
        }

    def __repr__(self) -> str:
        return f"NativeAdapter({self.machine!r}, version={self.version})"

    @property
    def served(self) -> frozenset[tuple[int, int]]:
        """``(device, command)`` of every block this adapter answers with data."""
        return frozenset(self._handlers)

    # -- requests ------------------------------------------------------------------------

    def _blocks(self, body: bytes) -> tuple[RequestBlock, ...]:
        blocks = decode_request_body(body)
        if len(blocks) > self._max_blocks:
            raise NativeFrameError(
                f"{len(blocks)} request blocks: at most {self._max_blocks} can be answered"
            )
        return blocks

    def _frame(self, parts: list[bytes]) -> bytes:
        """The data-response frame of ``parts`` (``parts[0]`` is the place of its header)."""
        length = sum(map(len, parts))
        parts[0] = NATIVE_HEADER.pack(_MAGIC_U32, self.version, FrameType.DATA_RESPONSE, length)
        return b"".join(parts)

    def answer(self, body: bytes) -> bytes:
        """The whole data-response frame answering the data-request ``body``.

        Raises :class:`NativeFrameError` when the block list is broken or longer than an
        answer can hold; everything else is answered in its block.
        """
        blocks = self._blocks(body)
        count = len(blocks)
        parts: list[bytes] = [b"", _U16.pack(count)]
        left = self.limit - 2 - RESPONSE_BLOCK_SIZE * count
        handlers = self._handlers
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
            parts.append(
                _pack_block(
                    RESPONSE_BLOCK_SIZE + size,
                    block.device,
                    block.path,
                    block.command,
                    ew,
                    0,
                    0,
                    size,
                )
            )
            if size:
                parts.append(data)
        return self._frame(parts)

    def forced_answer(self, body: bytes, ew: int) -> bytes:
        """The data-response frame answering ``body`` with ``ew`` and no data in every block
        (a forced EW code of fault injection: nothing runs). Raises :class:`NativeFrameError`
        as :meth:`answer` does."""
        blocks = self._blocks(body)
        parts: list[bytes] = [b"", _U16.pack(len(blocks))]
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

    # -- motion figures ------------------------------------------------------------------

    def _read_program_numbers(self, block: RequestBlock, room: int) -> bytes:
        m = self.machine.motion
        return NativeProgramNumbers(m.program_running, m.program_main).encode()

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

    def _read_macro_doubles(self, block: RequestBlock, room: int) -> bytes:
        req = MacroDoubleReadRequest.from_block(block)
        if req.count < 1:
            raise _Refused(EW.LENGTH)
        _need_room(_DOUBLE.size * req.count, room)
        read = self.machine.read_macro
        parts = []
        for number in range(req.first, req.first + req.count):
            value = read(number)
            if value is None:
                parts.append(_NAN_BITS)
            else:
                mantissa, decimals = _macro_parts(value)
                parts.append(_pack_double(mantissa / 10**decimals))
        return b"".join(parts)

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
        scaled: bool,
    ) -> bytes:
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
        _need_room((hi - lo) * (_ITEM_HEAD_SIZE + slot * max_axis), room)
        n_axes = len(self.machine.axes)
        types = ITEM_TYPES_30I if scaled else ITEM_TYPES
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
            parts.append(_ITEM_HEAD_PACK(number, record_axis, types[item.width]))
            if scaled:
                parts.extend(_pack_scaled(v, 10, 0) for v in values)
                zero = self._scaled_zero
            else:
                parts.extend(_I32_PACK(v) for v in values)
                zero = _I32_ZERO
            parts.extend([zero] * (max_axis - len(values)))
        return b"".join(parts)

    def _read_params(self, block: RequestBlock, room: int) -> bytes:
        ParamReadRequest.from_block(block)
        m = self.machine
        return self._items(block, room, self._param_numbers, m.read_param, m.param_item, False)

    def _read_params_30i(self, block: RequestBlock, room: int) -> bytes:
        ParamRead3Request.from_block(block)
        m = self.machine
        return self._items(block, room, self._param_numbers, m.read_param, m.param_item, True)

    def _read_diags(self, block: RequestBlock, room: int) -> bytes:
        DiagnosticRequest.from_block(block)
        m = self.machine
        return self._items(block, room, self._diag_numbers, m.read_diag, m.diag_item, False)

    # -- PMC -----------------------------------------------------------------------------

    def _read_pmc(self, block: RequestBlock, room: int) -> bytes:
        req = PmcReadRequest.from_block(block)
        try:
            letter = NativePmcArea(req.area).name
        except ValueError:
            raise _Refused(EW.ATTRIB) from None
        if letter not in PMC_AREAS:  # an area the simulated CNC never has
            raise _Refused(EW.NOOPT)
        try:
            width = PmcDataType(req.data_type).width
        except ValueError:
            raise _Refused(EW.ATTRIB) from None
        count = req.last - req.first + 1
        if count < 1 or count % width:
            raise _Refused(EW.LENGTH)
        _need_room(count, room)
        raw = self.machine.read_pmc(letter, req.first, count)
        if width == 1:
            return raw
        out = bytearray(len(raw))
        for i in range(width):  # PMC memory is little-endian; the native answer big-endian
            out[i::width] = raw[width - 1 - i :: width]
        return bytes(out)

    # -- alarms --------------------------------------------------------------------------

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
