"""The native adapter: one data-request body in, the whole data-response frame out.

Pure and synchronous, like :mod:`focas_net.sim.packed` on the packed side: a
:class:`NativeAdapter` wraps one :class:`~focas_net.sim.Machine` and answers every request
block with a response block, in order (device, path and command echoed, an EW code, the data).
The asyncio shell (:mod:`focas_net.native.server`) only moves frames.

Rules (also in ``docs/native-protocol.md``):

* a block whose ``(device, command)`` is not served answers ``EW_FUNC``; a path other than 0
  or 1 answers ``EW_PATH`` (the machine has one path);
* a refusal of the machine answers its EW code (``EW_NUMBER``, ``EW_ATTRIB``, ``EW_PROT``...);
* every answer fits the body size the response version allows (1450 bytes for version 2):
  room for the 16-byte head of every later block is kept, and a block whose data would not fit
  what is left answers ``EW_LENGTH``. The size is computed from the arguments **before** any
  data is gathered;
* a request with more blocks than the limit can answer even as bare heads (90 at version 2)
  is a framing violation (:class:`NativeFrameError`): the connection is closed.

Macro values written as doubles (0xA8) are stored as the machine's ``(mcr_val, dec_val)``
pair by :func:`macro_from_double`.
"""

from __future__ import annotations

import math
import struct
from bisect import bisect_left, bisect_right
from collections.abc import Callable
from decimal import ROUND_HALF_EVEN, Decimal
from typing import TYPE_CHECKING, Final

from focas_net.errors import EW
from focas_net.protocol import MAX_PMC_CHUNK
from focas_net.protocol import PmcArea as PackedPmcArea
from focas_net.sim.machine import POSITION_DECIMALS as MACHINE_POSITION_DECIMALS

from .codec import (
    _DOUBLE,
    _MAGIC_U32,
    _NAN_BITS,
    _RESPONSE_BLOCK,
    _SCALED,
    _U16,
    DEFAULT_SERVER_VERSION,
    HEADER,
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
    ParamRead3Request,
    ParamReadRequest,
    PmcArea,
    PmcDataType,
    PmcReadRequest,
    PositionKind,
    PositionRequest,
    ProgramNumbers,
    RequestBlock,
    StatInfo,
    SysInfo,
    decode_request_body,
    max_response_body,
    resolve_position_kind,
)

if TYPE_CHECKING:
    from focas_net.protocol import ParamValue
    from focas_net.sim import Machine

__all__ = [
    "ITEM_TYPES",
    "ITEM_TYPES_30I",
    "POSITION_DECIMALS",
    "NativeAdapter",
    "macro_from_double",
]

#: Decimals of the position records: the machine's least input increment (0.001 mm, IS-B).
POSITION_DECIMALS: Final = MACHINE_POSITION_DECIMALS
#: Item ``type`` word of 0x0E/0x30 records by value width in bytes (16i numbering).
ITEM_TYPES: Final[dict[int, int]] = {1: 0, 2: 1, 4: 2}
#: Item ``type`` word of 0x8D records by value width in bytes (30i numbering).
ITEM_TYPES_30I: Final[dict[int, int]] = {1: 1, 2: 2, 4: 3}

_I32_MIN: Final = -(2**31)
_I32_MAX: Final = 2**31 - 1
_MAX_DECIMALS: Final = 9
_QUANTA: Final = tuple(Decimal(1).scaleb(-d) for d in range(_MAX_DECIMALS + 1))
_SERVED_PATHS: Final = frozenset({0, 1})
_MAX_ALARMS: Final = 32
_ALARM_HEAD_SIZE: Final = 16
_ITEM_HEAD_SIZE: Final = 8

_pack_block = _RESPONSE_BLOCK.pack
_pack_scaled = _SCALED.pack
_pack_double = _DOUBLE.pack
_ITEM_HEAD_PACK: Final = struct.Struct(">ihh").pack
_I32_PACK: Final = struct.Struct(">i").pack
_I32_ZERO: Final = bytes(4)


def macro_from_double(value: float) -> tuple[int, int] | None:
    """The ``(mcr_val, dec_val)`` a double written with 0xA8 is stored as; None when it cannot
    be (infinite, NaN, or too large for a 32-bit mantissa even with no decimals).

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
    decimals = min(max(-exponent, 0), _MAX_DECIMALS)
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


class NativeAdapter:
    """Answers native data requests from one machine (see the module docstring)."""

    __slots__ = (
        "_diag_numbers",
        "_handlers",
        "_machine_error",
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
        from focas_net.sim import MachineError

        self.machine = machine
        #: Version word of every answer; it sets :attr:`limit`.
        self.version = version
        #: Largest answer body (:func:`max_response_body` of the version).
        self.limit = max_response_body(version)
        self._max_blocks = (self.limit - 2) // RESPONSE_BLOCK_SIZE
        self._machine_error = MachineError
        si = machine.sysinfo()
        #: Value slots per parameter/diagnostic record and position records for all axes.
        self.max_axis = max(si.max_axis, len(machine.axes), 1)
        self._sysinfo = SysInfo(
            si.addinfo,
            si.max_axis,
            si.cnc_type.decode("latin-1"),
            si.mt_type.decode("latin-1"),
            si.series.decode("latin-1"),
            si.version.decode("latin-1"),
            si.axes.decode("latin-1"),
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

    @property
    def served(self) -> frozenset[tuple[int, int]]:
        """``(device, command)`` of every block this adapter answers with data."""
        return frozenset(self._handlers)

    # -- requests ------------------------------------------------------------------------

    def answer(self, body: bytes) -> bytes:
        """The whole data-response frame answering the data-request ``body``.

        Raises :class:`NativeFrameError` when the block list is broken or longer than an
        answer can hold; everything else is answered in its block.
        """
        blocks = decode_request_body(body)
        count = len(blocks)
        if count > self._max_blocks:
            raise NativeFrameError(
                f"{count} request blocks: at most {self._max_blocks} can be answered"
            )
        parts: list[bytes] = [b"", _U16.pack(count)]
        left = self.limit - 2 - RESPONSE_BLOCK_SIZE * count
        handlers = self._handlers
        machine_error = self._machine_error
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
                except machine_error as exc:
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
        length = sum(map(len, parts))
        parts[0] = HEADER.pack(_MAGIC_U32, self.version, FrameType.DATA_RESPONSE, length)
        return b"".join(parts)

    # -- identity and status -------------------------------------------------------------

    def _read_sysinfo(self, block: RequestBlock, room: int) -> bytes:
        return self._sysinfo

    def _read_status(self, block: RequestBlock, room: int) -> bytes:
        machine = self.machine
        if self._status_version != machine.version:
            s = machine.status()
            self._status = StatInfo(
                s.aut, s.run, s.motion, s.mstb, s.emergency, s.alarm, s.edit
            ).encode()
            self._status_version = machine.version
        return self._status

    def status_info(self) -> StatInfo:
        """The status as a 0x19 answer carries it."""
        self._read_status(RequestBlock(Device.CNC, 1, NativeCommand.STATINFO), self.limit)
        return StatInfo.decode(self._status)

    # -- motion figures ------------------------------------------------------------------

    def _read_program_numbers(self, block: RequestBlock, room: int) -> bytes:
        m = self.machine.motion
        return ProgramNumbers(m.program_running, m.program_main).encode()

    def _read_feed(self, block: RequestBlock, room: int) -> bytes:
        return _pack_scaled(self.machine.motion.feed, 10, 0)

    def _read_spindle(self, block: RequestBlock, room: int) -> bytes:
        return _pack_scaled(self.machine.motion.spindle_speed, 10, 0)

    def _read_positions(self, block: RequestBlock, room: int) -> bytes:
        req = PositionRequest.from_block(block)
        kind = resolve_position_kind(req.kind)
        if kind is None:
            raise _Refused(EW.ATTRIB)
        m = self.machine.motion
        if kind is PositionKind.ABSOLUTE:
            values = m.absolute
        elif kind is PositionKind.MACHINE:
            values = m.machine
        elif kind is PositionKind.RELATIVE:
            values = m.relative
        elif kind is PositionKind.DISTANCE:
            values = m.distance_to_go
        else:  # skip position: the simulated machine has no skip function
            raise _Refused(EW.NOOPT)
        axis = req.axis
        if axis == -1:
            _need_room(SCALED_SIZE * self.max_axis, room)
            parts = [_pack_scaled(v, 10, POSITION_DECIMALS) for v in values]
            parts.extend([self._scaled_zero] * (self.max_axis - len(parts)))
            return b"".join(parts)
        if not 1 <= axis <= len(values):
            raise _Refused(EW.ATTRIB)
        return _pack_scaled(values[axis - 1], 10, POSITION_DECIMALS)

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
            v = read(number)
            parts.append(_pack_scaled(v.mcr_val, 10, v.dec_val))  # vacant: (0, -1)
        return b"".join(parts)

    def _read_macro_doubles(self, block: RequestBlock, room: int) -> bytes:
        req = MacroDoubleReadRequest.from_block(block)
        if req.count < 1:
            raise _Refused(EW.LENGTH)
        _need_room(_DOUBLE.size * req.count, room)
        read = self.machine.read_macro
        parts = []
        for number in range(req.first, req.first + req.count):
            v = read(number)
            if v.dec_val < 0:
                parts.append(_NAN_BITS)
            else:
                parts.append(_pack_double(v.mcr_val / 10**v.dec_val))
        return b"".join(parts)

    def _write_macro_double(self, block: RequestBlock, room: int) -> bytes:
        req = MacroDoubleWriteRequest.from_block(block)
        machine = self.machine
        if req.value is None:
            machine.clear_macro(req.number)
            return b""
        stored = macro_from_double(req.value)
        if stored is None:
            # the checks of a write come before the value's: EW_PROT, EW_NUMBER, EW_PROT
            if machine.read_only:
                raise _Refused(EW.PROT)
            writable = machine.macro_writable(req.number)
            if writable is None:
                raise _Refused(EW.NUMBER)
            raise _Refused(EW.DATA if writable else EW.PROT)
        machine.write_macro(req.number, *stored)
        return b""

    # -- parameters and diagnostics ------------------------------------------------------

    def _items(
        self,
        block: RequestBlock,
        room: int,
        numbers: tuple[int, ...],
        read: Callable[[int, int], ParamValue],
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
                except self._machine_error as exc:
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
            parts.append(_ITEM_HEAD_PACK(number, record_axis, types[values[0].width]))
            if scaled:
                parts.extend(_pack_scaled(v.value, 10, 0) for v in values)
                zero = self._scaled_zero
            else:
                parts.extend(_I32_PACK(v.value) for v in values)
                zero = _I32_ZERO
            parts.extend([zero] * (max_axis - len(values)))
        return b"".join(parts)

    def _read_params(self, block: RequestBlock, room: int) -> bytes:
        ParamReadRequest.from_block(block)
        return self._items(block, room, self._param_numbers, self.machine.read_param, False)

    def _read_params_30i(self, block: RequestBlock, room: int) -> bytes:
        ParamRead3Request.from_block(block)
        return self._items(block, room, self._param_numbers, self.machine.read_param, True)

    def _read_diags(self, block: RequestBlock, room: int) -> bytes:
        DiagnosticRequest.from_block(block)
        return self._items(block, room, self._diag_numbers, self.machine.read_diag, False)

    # -- PMC -----------------------------------------------------------------------------

    def _read_pmc(self, block: RequestBlock, room: int) -> bytes:
        req = PmcReadRequest.from_block(block)
        try:
            letter = PmcArea(req.area).name
        except ValueError:
            raise _Refused(EW.ATTRIB) from None
        packed = PackedPmcArea.__members__.get(letter)
        if packed is None:
            raise _Refused(EW.NOOPT)
        try:
            width = PmcDataType(req.data_type).width
        except ValueError:
            raise _Refused(EW.ATTRIB) from None
        count = req.last - req.first + 1
        if count < 1 or count % width:
            raise _Refused(EW.LENGTH)
        _need_room(count, room)
        read = self.machine.read_pmc
        code = int(packed)
        chunks = [
            read(code, 0, start, min(start + MAX_PMC_CHUNK, req.last + 1) - 1)
            for start in range(req.first, req.last + 1, MAX_PMC_CHUNK)
        ]
        raw = b"".join(chunks)
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
