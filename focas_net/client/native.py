"""The asyncio client of FANUC's FOCAS/2 Ethernet protocol: :class:`NativeClient`.

It speaks to a CNC the way FANUC's own library (libfwlib32) does, frame for frame
(``docs/native-client.md``, ``docs/native-protocol.md``): each method sends the frames
:mod:`focas_net.native.calls` lists for its FOCAS function in the handle's command set. The
connection pair, the queue, the packing of calls into frames and the deadlines are the link's
(:mod:`._native_link`, over :mod:`focas_net.native.session`); the calls both clients share are
:mod:`._composite`'s. What is here is each call: its arguments checked and its frames encoded
in the caller's frame, then its answer decoded.

One call, ``read_macro(100)``::

    check_macro(100)                       the argument (TypeError, ValueError), nothing sent
    deadline = self._deadline(None)        the client's timeout from now
    handle = await self._handle_for(...)   the open handle (waits while reconnecting)
    call = calls.cnc_rdmacro(cs, 100)      the library's frame, encoded once for these values
    blocks = await self._exchange(...)     queued, packed into a frame, answered (the link)
    _decoded(request, block, ...)          EW code -> CncError; the answer's value
"""

# Every call takes a per-call ``timeout=`` by contract (one deadline per call covers its
# frames, its lock waits and its wait for a reconnect), so ASYNC109 does not apply here.
# ruff: noqa: ASYNC109

from __future__ import annotations

import asyncio
import struct
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from datetime import UTC, datetime
from decimal import Decimal
from typing import Any, Final

from focas_net._memo import Memo
from focas_net.errors import EW, CncError, FocasError, PayloadError, ProtocolError

from ..native import calls
from ..native.blocks import REQUEST_BLOCK_SIZE, ResponseBlock
from ..native.calls import CommandSet, LibraryCall
from ..native.frame import max_response_body
from ..native.records import (
    AlarmMessages,
    AlarmStatus,
    AxisNames,
    CncId,
    DiagType,
    ExecutingProgram,
    ItemRecord,
    ItemValues,
    NativeAlarmHistory,
    NativePmcData,
    NativeProgramNumbers,
    ParamInfo,
    ParamInfo3,
    ParamType,
    PositionAxisNames,
    ScaledItemRecord,
    ScaledItemValues,
    ScaledNumber,
    ScaledValues,
    SequenceNumber,
    StatInfo,
    TimerValue,
)
from ..native.requests import (
    NativeAlarmHistoryRequest,
    NativeCommand,
    NativePmcArea,
    NativeRequest,
)
from ..native.session import Ending
from ..protocol import (
    ActiveAlarm,
    AlarmHistory,
    AlarmHistoryEntry,
    AlarmType,
    ParamDataType,
    ParamValue,
    PmcArea,
    PositionKind,
    ProgramNumbers,
    StatusInfo,
    SysInfo,
)
from ._composite import ChunkOutcome
from ._native_link import Handle, NativeLink
from ._started import StartedCall
from ._values import (
    I16_MAX,
    REAL_WIDTH,
    AreaLike,
    Positions,
    alarm_type_number,
    byte_to_wire,
    check_axis,
    check_int,
    check_item,
    check_macro,
    history_depth,
    macro_from_wire,
    macro_to_wire,
    param_int,
    real_to_wire,
)
from .reconnect import ReconnectPolicy, StateCallback

__all__ = ["DynamicData", "NativeClient", "NativeUnsupportedError", "ServoLoad"]

#: Most blocks FANUC's library puts in one request frame; the default of ``max_blocks``.
LIBRARY_MAX_BLOCKS: Final = 10
_MAX_ACTIVE_ALARMS: Final = 32
_ANSWER_HEAD: Final = 16
_PARAM_WIDTH: Final[dict[int, int]] = {
    ParamType.BIT: 1,
    ParamType.BYTE: 1,
    ParamType.WORD: 2,
    ParamType.TWO_WORD: 4,
}
_DIAG_WIDTH: Final[dict[int, int]] = {0: 1, 1: 2, 2: 4, 3: 1, 4: 1}
_TIMER_TYPES: Final = 4
#: (a request, the max axes, the answer data) -> the decoded answer.
_DECODED: Final = Memo(2048)


class NativeUnsupportedError(FocasError, NotImplementedError):
    """The call exists on the packed transport but FOCAS/2 Ethernet cannot carry it."""

    def __init__(self, method: str, why: str) -> None:
        super().__init__(
            f"{method} is not available on the native (FOCAS/2 Ethernet) transport: {why}"
        )
        self.method = method


@dataclass(frozen=True, slots=True)
class DynamicData:
    """``cnc_rddynamic2``: alarm bits, program numbers, sequence number, actual feed and
    spindle speed, and the four positions (increments, one per axis or the one asked)."""

    alarm: int
    running: int
    main: int
    sequence: int
    feed: int
    spindle_speed: int
    absolute: tuple[int, ...]
    machine: tuple[int, ...]
    relative: tuple[int, ...]
    distance: tuple[int, ...]


@dataclass(frozen=True, slots=True)
class ServoLoad:
    """One entry of ``cnc_rdsvmeter``: the axis name and its servo load meter (percent)."""

    name: str
    load: Decimal


# -- answers -----------------------------------------------------------------------------------
def _data(block: ResponseBlock, function: str) -> bytes:
    """The data of ``block``; :class:`CncError` for its EW code."""
    if block.ew:
        raise CncError.from_ew(block.ew, function)
    return block.data


def _decoded(request: NativeRequest, block: ResponseBlock, function: str, max_axes: int) -> Any:
    """The answer of ``request`` in ``block`` (kept by the values it depends on: a poll whose
    answer repeats decodes it once); :class:`CncError` for its EW code, :class:`PayloadError`
    for data that does not decode."""
    data = _data(block, function)
    key = (request, max_axes, data)
    value = _DECODED.get(key)
    if value is None:
        try:
            value = request.decode_answer(data, max_axes)
        except (ProtocolError, ValueError, struct.error) as exc:
            raise PayloadError(
                f"{function}: answer to 0x{request.COMMAND:X} does not decode: {exc}"
            ) from None
        _DECODED.put(key, value)
    return value


def _text(raw: bytes | str) -> str:
    if isinstance(raw, str):
        return raw.rstrip("\x00")
    return raw.split(b"\x00", 1)[0].decode("latin-1")


def _name(entry: bytes) -> str:
    """The axis name of a 4-byte name entry (its first character; the suffix only tells
    which position a display shows)."""
    return entry[:1].replace(b"\x00", b"").decode("latin-1").strip()


def _signed(raw: int, width: int) -> int:
    """The signed integer of the ``8 * width`` bits of ``raw``."""
    bits = 8 * width
    raw &= (1 << bits) - 1
    return raw - (1 << bits) if raw >= 1 << (bits - 1) else raw


def _status(handle: Handle, call: LibraryCall, blocks: tuple[ResponseBlock, ...]) -> StatusInfo:
    """The status of ``cnc_statinfo``'s answer ``blocks`` (hdck and tmmode read 0 when the CNC
    refuses them, as the library reads them)."""
    frame = call.frames[0]
    st, hd, tm = blocks
    stat: StatInfo = _decoded(frame[0], st, "cnc_statinfo", handle.max_axes)
    hdck = 0 if hd.ew else _decoded(frame[1], hd, "cnc_statinfo", 0).hdck
    tmmode = 0 if tm.ew else _decoded(frame[2], tm, "cnc_statinfo", 0).tmmode
    return StatusInfo(
        hdck, tmmode, stat.aut, stat.run, stat.motion, stat.mstb, stat.emergency, stat.alarm,
        stat.edit,
    )  # fmt: skip


def _dynamic(
    handle: Handle, call: LibraryCall, axis: int, blocks: tuple[ResponseBlock, ...]
) -> DynamicData:
    """The result of the ``cnc_rddynamic2`` ``call`` of ``axis`` from its answer ``blocks``."""
    values = [
        _decoded(r, b, "cnc_rddynamic2", handle.max_axes)
        for r, b in zip(call.frames[0], blocks, strict=True)
    ]
    count = handle.axes if axis == -1 else 1
    alarm: AlarmStatus = values[0]
    prg: NativeProgramNumbers = values[1]
    seq: SequenceNumber = values[2]

    def first(v: ScaledValues) -> int:
        return v.values[0].mantissa if v.values else 0

    def mantissas(v: ScaledValues) -> tuple[int, ...]:
        return tuple(x.mantissa for x in v.values[:count])

    return DynamicData(
        alarm.alarm & 0xFFFF, prg.running, prg.main, seq.number, first(values[3]),
        first(values[4]), mantissas(values[5]), mantissas(values[6]), mantissas(values[7]),
        mantissas(values[8]),
    )  # fmt: skip


def _check_dynamic_axis(axis: object) -> None:
    """``cnc_rddynamic2``'s axis: -1 (every axis) or 1..n."""
    check_axis(axis, every=-1)


class NativeClient(NativeLink):
    """An asyncio client of FANUC's FOCAS/2 Ethernet protocol (port 8193 on a real control).

    It has the methods of :class:`~focas_net.client.FocasClient` that FOCAS/2 carries, with
    the same results, exceptions, per-call ``timeout=`` and :class:`ReconnectPolicy`, plus
    :meth:`read_dynamic`, :meth:`read_timer`, :meth:`read_spindle_loads`,
    :meth:`read_servo_meters`, :meth:`read_cnc_id`, :meth:`read_sequence_number`,
    :meth:`read_program_name`, :meth:`read_alarm_status` and :meth:`read_param_type` (in
    place of ``read_param_attributes``). Concurrent calls are gathered into frames of at most
    ``max_blocks`` blocks (``docs/native-client.md``).
    """

    def __init__(
        self,
        host: str,
        port: int = 8193,
        *,
        timeout: float | None = 3.0,
        reconnect: bool | ReconnectPolicy = False,
        max_blocks: int = LIBRARY_MAX_BLOCKS,
        on_state_change: StateCallback | None = None,
    ) -> None:
        super().__init__(
            host,
            port,
            timeout=timeout,
            reconnect=reconnect,
            max_blocks=max_blocks,
            on_state_change=on_state_change,
        )
        #: The type word (0 bit .. 4 real) of each parameter read or written.
        self._param_types: dict[int, int] = {}

    async def _single(
        self, deadline: float | None, build: Callable[..., LibraryCall], *args: Any
    ) -> tuple[Handle, LibraryCall, tuple[ResponseBlock, ...]]:
        """A call of one frame, ``build(command set, *args)``: its handle, the call and its
        answer blocks."""
        handle = await self._handle_for(deadline)
        call = build(handle.command_set, *args)
        blocks = await self._exchange(call.parts[0], handle.command_set, deadline)
        return handle, call, blocks

    async def _one(
        self, deadline: float | None, build: Callable[..., LibraryCall], *args: Any
    ) -> Any:
        """The decoded answer of a call of one frame of one block."""
        handle, call, (block,) = await self._single(deadline, build, *args)
        return _decoded(call.frames[0][0], block, call.function, handle.max_axes)

    # -- status and identity -------------------------------------------------------------
    async def read_status(self, *, timeout: float | None = None) -> StatusInfo:
        """``cnc_statinfo``: the ODBST status (0x19; hdck 0xE1 and tmmode 0x98 read 0 when
        the CNC refuses them, as the library reads them)."""
        handle, call, blocks = await self._single(self._deadline(timeout), calls.cnc_statinfo)
        return _status(handle, call, blocks)

    def start_read_status(self, *, timeout: float | None = None) -> StartedCall[StatusInfo]:
        """:meth:`read_status` started now (its frame queued at once when the client is
        connected) and finished by awaiting :meth:`StartedCall.result` (see
        :func:`~focas_net.client.read_status_all`)."""
        deadline = self._deadline(timeout)
        handle = self._handle
        if handle is None or handle.closed:
            return StartedCall.running(self.read_status(timeout=timeout))
        call = calls.cnc_statinfo(handle.command_set)
        job = self._submit(call.parts[0], handle.command_set, deadline)

        async def finish() -> StatusInfo:
            return _status(handle, call, await job.token[0])

        return StartedCall(finish, lambda: self._session.abandon(job))

    async def read_sysinfo(self, *, timeout: float | None = None) -> SysInfo:
        """``cnc_sysinfo``: ODBSYS as the CNC answered it while connecting (nothing is sent,
        like FANUC's library)."""
        handle = await self._handle_for(self._deadline(timeout))
        info = handle.sysinfo
        if info is None:
            raise PayloadError("cnc_sysinfo: the connect-time system information is missing")

        def raw(text: str, size: int) -> bytes:
            return text.encode("latin-1")[:size].ljust(size, b"\x00")

        return SysInfo(
            info.addinfo, info.max_axis, raw(info.cnc_type, 2), raw(info.mt_type, 2),
            raw(info.series, 4), raw(info.version, 4), raw(info.axes, 2),
        )  # fmt: skip

    async def read_cnc_id(self, *, timeout: float | None = None) -> tuple[int, int, int, int]:
        """``cnc_rdcncid``: the four 32-bit words of the CNC ID."""
        cid: CncId = await self._one(self._deadline(timeout), calls.cnc_rdcncid)
        return (cid.id1, cid.id2, cid.id3, cid.id4)

    async def read_timer(self, timer_type: int, *, timeout: float | None = None) -> TimerValue:
        """``cnc_rdtimer``: a timer (0 power-on, 1 operating, 2 cutting, 3 cycle, 4 free) as
        minutes and milliseconds."""
        check_int("timer type", timer_type, 0, _TIMER_TYPES)
        value: TimerValue = await self._one(self._deadline(timeout), calls.cnc_rdtimer, timer_type)
        return value

    # -- program, feed, spindle ----------------------------------------------------------
    async def read_program_numbers(self, *, timeout: float | None = None) -> ProgramNumbers:
        """``cnc_rdprgnumo8``: the running and the main program numbers (0 = none)."""
        value: NativeProgramNumbers = await self._one(self._deadline(timeout), calls.cnc_rdprgnumo8)
        return ProgramNumbers(value.running, value.main)

    async def read_program_name(self, *, timeout: float | None = None) -> tuple[int, str]:
        """``cnc_exeprgname``: the O number and the name of the executing program."""
        value: ExecutingProgram = await self._one(self._deadline(timeout), calls.cnc_exeprgname)
        return value.o_num, _text(value.name)

    async def read_sequence_number(self, *, timeout: float | None = None) -> int:
        """``cnc_rdseqnum``: the sequence number being executed."""
        value: SequenceNumber = await self._one(self._deadline(timeout), calls.cnc_rdseqnum)
        return value.number

    async def read_feed(self, *, timeout: float | None = None) -> int:
        """``cnc_actf``: the actual feed rate."""
        value: ScaledValues = await self._one(self._deadline(timeout), calls.cnc_actf)
        return value.values[0].mantissa if value.values else 0

    async def read_spindle_speed(self, *, timeout: float | None = None) -> int:
        """``cnc_acts``: the actual spindle speed."""
        value: ScaledValues = await self._one(self._deadline(timeout), calls.cnc_acts)
        return value.values[0].mantissa if value.values else 0

    async def read_spindle_loads(
        self, spindle: int = -1, *, timeout: float | None = None
    ) -> tuple[int, ...]:
        """``cnc_rdspload``: the load of every spindle (``spindle=-1``) or of one (1..n)."""
        check_axis(spindle, "spindle", every=-1)
        handle, call, blocks = await self._single(
            self._deadline(timeout), calls.cnc_rdspload, spindle
        )
        frame = call.frames[0]
        for request, block in zip(frame, blocks, strict=True):
            _data(block, "cnc_rdspload")
            if request.COMMAND == NativeCommand.AXIS_COUNT:
                if _decoded(request, block, "cnc_rdspload", 0).count == 0:
                    raise CncError.from_ew(EW.NOOPT, "cnc_rdspload: no spindle")
        index = 0 if handle.command_set is CommandSet.FS16I else 1
        loads: ScaledValues = _decoded(frame[index], blocks[index], "cnc_rdspload", 0)
        limit = handle.spindles if spindle == -1 else 1
        return tuple(_signed(v.mantissa, 2) for v in loads.values[: max(limit, 1)])

    async def read_servo_meters(self, *, timeout: float | None = None) -> tuple[ServoLoad, ...]:
        """``cnc_rdsvmeter``: the servo load meter of every axis, with its name."""
        handle, call, blocks = await self._single(self._deadline(timeout), calls.cnc_rdsvmeter)
        names: AxisNames | None = None
        loads: ScaledValues | None = None
        for request, block in zip(call.frames[0], blocks, strict=True):
            value = _decoded(request, block, "cnc_rdsvmeter", handle.max_axes)
            if request.COMMAND == NativeCommand.AXIS_NAME:
                names = value
            elif request.COMMAND == NativeCommand.RDSVMETER:
                loads = value
        assert names is not None and loads is not None
        count = min(handle.axes, len(loads.values), len(names.records))
        return tuple(
            ServoLoad(
                _name(names.records[i].encode()),
                Decimal(abs(loads.values[i].mantissa)).scaleb(-max(loads.values[i].decimals, 0)),
            )
            for i in range(count)
        )

    async def read_axis_names(self, *, timeout: float | None = None) -> tuple[str, ...]:
        """``cnc_rdaxisname``: the names of the path's axes, in order."""
        handle, call, (block,) = await self._single(self._deadline(timeout), calls.cnc_rdaxisname)
        names: AxisNames = _decoded(call.frames[0][0], block, "cnc_rdaxisname", handle.max_axes)
        return tuple(_name(n.encode()) for n in names.records[: handle.axes])

    async def read_dynamic(self, axis: int = -1, *, timeout: float | None = None) -> DynamicData:
        """``cnc_rddynamic2``: alarm bits, program numbers, sequence number, feed, spindle
        speed and the four positions of every axis (``axis=-1``) or of one (1..n), in one
        frame. Needs the CNC's FOCAS option bit 0, as in FANUC's library (EW_NOOPT)."""
        _check_dynamic_axis(axis)
        deadline = self._deadline(timeout)
        handle = await self._handle_for(deadline)
        call = self._dynamic_call(handle, axis)
        blocks = await self._exchange(call.parts[0], handle.command_set, deadline)
        return _dynamic(handle, call, axis, blocks)

    def start_read_dynamic(
        self, axis: int = -1, *, timeout: float | None = None
    ) -> StartedCall[DynamicData]:
        """:meth:`read_dynamic` started now and finished by awaiting
        :meth:`StartedCall.result` (see :func:`~focas_net.client.read_dynamic_all`)."""
        _check_dynamic_axis(axis)
        deadline = self._deadline(timeout)
        handle = self._handle
        if handle is None or handle.closed:
            return StartedCall.running(self.read_dynamic(axis, timeout=timeout))
        try:
            call = self._dynamic_call(handle, axis)
        except CncError as exc:
            return StartedCall.failed(exc)
        job = self._submit(call.parts[0], handle.command_set, deadline)

        async def finish() -> DynamicData:
            return _dynamic(handle, call, axis, await job.token[0])

        return StartedCall(finish, lambda: self._session.abandon(job))

    @staticmethod
    def _dynamic_call(handle: Handle, axis: int) -> LibraryCall:
        """The ``cnc_rddynamic2`` call of ``axis`` on ``handle``; :class:`CncError` when the
        CNC lacks the option or the axis."""
        if not handle.option_bits & 1:
            raise CncError.from_ew(EW.NOOPT, "cnc_rddynamic2: the CNC lacks FOCAS option bit 0")
        if axis > handle.axes:
            raise CncError.from_ew(EW.ATTRIB, f"cnc_rddynamic2: axis {axis} of {handle.axes}")
        return calls.cnc_rddynamic2(handle.command_set, axis)

    async def read_positions(
        self,
        kind: str | int | PositionKind = PositionKind.ABSOLUTE,
        *,
        axis: int | None = None,
        timeout: float | None = None,
    ) -> Positions:
        """``cnc_rdposition``: positions of every axis (``axis=None``) or of axis ``axis``
        (1..n), with the axis names; the frame reads all four kinds, as the library does.

        An unknown ``kind`` or an ``axis`` below 1 raises :class:`ValueError` before anything
        is sent; an axis the CNC does not have raises EW_ATTRIB (:class:`CncError`).
        """
        which = PositionKind.parse(kind)
        check_axis(axis)
        deadline = self._deadline(timeout)
        handle = await self._handle_for(deadline)
        if axis is not None and axis > handle.axes:
            raise CncError.from_ew(EW.ATTRIB, f"cnc_rdposition: axis {axis} of {handle.axes}")
        call = calls.cnc_rdposition(handle.command_set)
        blocks = await self._exchange(call.parts[0], handle.command_set, deadline)
        names: PositionAxisNames | None = None
        positions: ScaledValues | None = None
        for request, block in zip(call.frames[0], blocks, strict=True):
            command = request.COMMAND
            if command == NativeCommand.AXIS_NAME:
                names = _decoded(request, block, "cnc_rdposition", handle.max_axes)
            elif (
                command == NativeCommand.POSITION and getattr(request, "kind", None) == which.value
            ):
                positions = _decoded(request, block, "cnc_rdposition", handle.max_axes)
            elif command in (
                NativeCommand.POSITION,
                NativeCommand.AXIS_COUNT,
                NativeCommand.STATINFO,
            ):
                _data(block, "cnc_rdposition")
        assert names is not None and positions is not None
        count = min(handle.axes, len(positions.values), len(names.records))
        picked = range(count) if axis is None else [axis - 1]
        values: dict[str, Decimal] = {}
        increments: dict[str, int] = {}
        decimals = 0
        for i in picked:
            entry = names.records[i]
            raw = {PositionKind.MACHINE: entry.machine, PositionKind.RELATIVE: entry.relative}.get(
                which, entry.absolute
            )
            record = positions.values[i]
            decimals = record.decimals
            name = _name(raw) or f"axis{i + 1}"
            values[name] = Decimal(record.mantissa).scaleb(-record.decimals)
            increments[name] = record.mantissa
        return Positions(which, decimals, values, increments)

    # -- parameters and diagnostics ------------------------------------------------------
    @staticmethod
    def _check_axis_of(handle: Handle, axis: int, function: str) -> None:
        if axis > handle.axes:
            raise CncError.from_ew(EW.ATTRIB, f"{function}: axis {axis} of {handle.axes}")

    async def _read_item(
        self, number: int, axis: int, deadline: float | None, *, diagnostic: bool
    ) -> ParamValue:
        """``cnc_rdparam`` or ``cnc_diagnoss`` of a checked number and axis as a
        :class:`ParamValue`."""
        function = "cnc_diagnoss" if diagnostic else "cnc_rdparam"
        handle = await self._handle_for(deadline)
        self._check_axis_of(handle, axis, function)
        build = calls.cnc_diagnoss if diagnostic else calls.cnc_rdparam
        call = build(handle.command_set, number, axis)
        (block,) = await self._exchange(call.parts[0], handle.command_set, deadline)
        items: ItemValues | ScaledItemValues = _decoded(
            call.frames[0][0], block, function, handle.max_axes
        )
        if not items.records:
            raise PayloadError(f"{function}: answer for {number} carries no record")
        record = items.records[0]
        if not diagnostic:
            self._param_types[number] = record.type
        if record.type == (DiagType.REAL if diagnostic else ParamType.REAL):
            # REALPRM: (mantissa, 10, decimals)
            if isinstance(record, ItemRecord):
                reals = record.reals()
                if not reals:
                    raise PayloadError(f"{function}: real record of {number} has one slot")
                value = reals[0]
            else:
                value = record.values[0]
            return ParamValue(number, axis, value.mantissa, REAL_WIDTH, value.decimals)
        width = (_DIAG_WIDTH if diagnostic else _PARAM_WIDTH).get(record.type)
        if width is None:
            raise PayloadError(f"{function}: {number} has type {record.type}, which has no value")
        first = record.values[0]
        raw = first.mantissa if isinstance(first, ScaledNumber) else first
        return ParamValue(number, axis, _signed(raw, width), width)

    async def _read_param_value(self, number: int, axis: int, deadline: float | None) -> ParamValue:
        value = await self._read_item(number, axis, deadline, diagnostic=False)
        self._param_widths[number] = value.width
        return value

    async def _is_bit(self, number: int, value: ParamValue, deadline: float | None) -> bool:
        return self._param_types.get(number) == ParamType.BIT

    async def read_param_type(
        self, number: int, *, axis: int = 0, timeout: float | None = None
    ) -> ParamDataType | None:
        """The data type of parameter ``number`` (bit, byte, word, two-word, real) from the
        type word of its ``cnc_rdparam`` record, None for a word FANUC does not number (an
        axis parameter needs its ``axis``).

        This stands in for the packed client's ``read_param_attributes``: FOCAS/2's
        ``cnc_rdparainfo`` answer has the type in two bits (no real type), and no decimals or
        range, while the record of ``cnc_rdparam`` names all five types."""
        check_item(number, axis, "parameter")
        await self._read_param_value(number, axis, self._deadline(timeout))
        ptype = self._param_types[number]
        return ParamDataType(ptype) if ptype in ParamDataType._value2member_map_ else None

    async def read_diag(self, number: int, *, axis: int = 0, timeout: float | None = None) -> int:
        """``cnc_diagnoss``: the value of diagnostic ``number``."""
        check_item(number, axis, "diagnostic")
        value = await self._read_item(number, axis, self._deadline(timeout), diagnostic=True)
        return value.value

    async def _param_info(
        self, handle: Handle, number: int, width: int | None, deadline: float | None
    ) -> tuple[int, int]:
        """The first frame of ``cnc_wrparam``: the parameter's type word and its width;
        EW_LENGTH (before anything is written) when ``width`` differs, as the library."""
        call = calls.wrparam_info(handle.command_set, number)
        (block,) = await self._exchange(call.parts[0], handle.command_set, deadline)
        info = _decoded(call.frames[0][0], block, "cnc_wrparam", handle.max_axes)
        if isinstance(info, ParamInfo3):
            ptype = info.type
        else:
            assert isinstance(info, ParamInfo)
            if not info.entries:
                raise PayloadError(f"cnc_wrparam: no information on parameter {number}")
            ptype = info.entries[0].attribute & 3
        self._param_types[number] = ptype
        size = REAL_WIDTH if ptype == ParamType.REAL else _PARAM_WIDTH.get(ptype)
        if size is None:
            raise PayloadError(f"cnc_wrparam: {number} has type {ptype}, which has no value")
        if width is not None and width != size:
            self._param_widths.pop(number, None)
            raise CncError.from_ew(
                EW.LENGTH, f"cnc_wrparam: {number} is {size} bytes wide, not {width}"
            )
        return ptype, size

    async def _write_param(
        self,
        number: int,
        value: int | Decimal | str,
        axis: int,
        width: int | None,
        deadline: float | None,
    ) -> None:
        # both readings of the value, before anything is sent: one is refused only if the
        # parameter's type turns out to be the one it does not fit
        as_int: int | ValueError
        as_real: tuple[int, int] | ValueError
        try:
            as_int = param_int(number, value)
        except ValueError as exc:
            as_int = exc
        try:
            as_real = real_to_wire(number, value)
        except ValueError as exc:
            as_real = exc
        if isinstance(as_int, ValueError) and isinstance(as_real, ValueError):
            raise ValueError(
                f"parameter {number}: {value!r} is not a value of any parameter type (an "
                "integer, or a real value within an i32 mantissa and 0..9 decimals)"
            )
        handle = await self._handle_for(deadline)
        self._check_axis_of(handle, axis, "cnc_wrparam")
        ptype, size = await self._param_info(handle, number, width, deadline)
        if ptype == ParamType.REAL:
            if isinstance(as_real, ValueError):
                raise as_real
            record = self._param_record(handle, number, axis, ptype, *as_real)
        else:
            if isinstance(as_int, ValueError):
                raise as_int
            if ptype == ParamType.BIT:
                raw = byte_to_wire(number, as_int, ParamDataType.BIT)
            else:
                bits = 8 * size
                if not -(1 << (bits - 1)) <= as_int < 1 << bits:
                    raise ValueError(f"value {as_int} does not fit a {size}-byte parameter")
                raw = _signed(as_int, size)
            record = self._param_record(handle, number, axis, ptype, raw)
        await self._write_record(handle, record, deadline)

    async def _write_param_bits(
        self, number: int, axis: int, bits: int, width: int, deadline: float | None
    ) -> None:
        handle = await self._handle_for(deadline)
        self._check_axis_of(handle, axis, "cnc_wrparam")
        ptype, _ = await self._param_info(handle, number, width, deadline)
        raw = byte_to_wire(number, bits, ParamDataType.BIT) if ptype == ParamType.BIT else bits
        record = self._param_record(handle, number, axis, ptype, _signed(raw, width))
        await self._write_record(handle, record, deadline)

    async def _write_record(
        self, handle: Handle, record: ItemRecord | ScaledItemRecord, deadline: float | None
    ) -> None:
        """The second frame of ``cnc_wrparam``: the write of ``record``."""
        call = calls.cnc_wrparam(handle.command_set, record)
        (done,) = await self._exchange(call.parts[1], handle.command_set, deadline)
        _data(done, "cnc_wrparam")

    @staticmethod
    def _param_record(
        handle: Handle, number: int, axis: int, ptype: int, value: int, decimals: int | None = None
    ) -> ItemRecord | ScaledItemRecord:
        """The write record, slot 0 holding ``value`` (a real one's mantissa with
        ``decimals``) and the other slots what the previous write left there (the library's
        buffer)."""
        if handle.command_set is CommandSet.FS16I:
            slots = handle.param_slots
            slots[0] = value
            return ItemRecord(number, axis, ptype, tuple(slots))
        scaled = handle.param3_slots
        scaled[0] = (
            ScaledNumber(value, -1, 0) if decimals is None else ScaledNumber(value, decimals, 10)
        )
        return ScaledItemRecord(number, axis, ptype, tuple(scaled))

    # -- macros --------------------------------------------------------------------------
    async def read_macro(self, number: int, *, timeout: float | None = None) -> Decimal | None:
        """``cnc_rdmacro``: the value of ``#number`` as a Decimal, or None when vacant
        (binary records converted as the library converts them)."""
        check_macro(number)
        values: ScaledValues = await self._one(self._deadline(timeout), calls.cnc_rdmacro, number)
        if not values.values:
            raise PayloadError(f"cnc_rdmacro: answer for #{number} carries no value")
        return macro_from_wire(*values.values[0].to_macro())

    async def write_macro(
        self, number: int, value: int | Decimal | float | str, *, timeout: float | None = None
    ) -> None:
        """``cnc_wrmacro``: write ``#number`` (a binary record at 16i class, base 10 at 30i,
        as the library sends it); see :func:`~focas_net.client.client.macro_to_wire`."""
        check_macro(number)
        mcr_val, dec_val = macro_to_wire(value)
        _, _, (block,) = await self._single(
            self._deadline(timeout), calls.cnc_wrmacro, number, mcr_val, dec_val
        )
        _data(block, "cnc_wrmacro")

    # -- PMC -----------------------------------------------------------------------------
    def _pmc_area(self, area: AreaLike) -> PmcArea:
        a = PmcArea.parse(area)
        if a.name not in NativePmcArea.__members__:
            raise ValueError(f"PMC area {a.name} has no FOCAS/2 address type")
        return a

    def _read_chunk(self) -> int:
        """Most PMC bytes one answer carries (the open handle's)."""
        handle = self._handle
        version = handle.version if handle is not None else 1
        return max_response_body(version) - 2 - _ANSWER_HEAD

    def _pmc_write_chunk(self) -> int:
        """Most PMC bytes one write carries (request bodies are kept within the answers'
        limit)."""
        handle = self._handle
        version = handle.version if handle is not None else 1
        return max_response_body(version) - 2 - REQUEST_BLOCK_SIZE

    async def _read_pmc_chunk(
        self, code: int, start: int, count: int, deadline: float | None
    ) -> bytes:
        data: NativePmcData = await self._one(
            deadline, calls.pmc_rdpmcrng, code, 0, start, start + count - 1
        )
        if len(data.raw) != count:
            raise PayloadError(f"pmc_rdpmcrng answer: {len(data.raw)} bytes, asked {count}")
        return data.raw

    async def _read_pmc(
        self, area: PmcArea, start: int, count: int, deadline: float | None
    ) -> bytes:
        code = NativePmcArea[area.name].value
        await self._handle_for(deadline)
        step = self._read_chunk()
        if count <= step:
            return await self._read_pmc_chunk(code, start, count, deadline)
        return b"".join(
            await _all_or_first_error(
                self._read_pmc_chunk(code, s, min(step, start + count - s), deadline)
                for s in range(start, start + count, step)
            )
        )

    async def _write_pmc_chunks(
        self, area: PmcArea, chunks: Sequence[tuple[int, bytes]], deadline: float | None
    ) -> list[ChunkOutcome]:
        code = NativePmcArea[area.name].value
        handle = await self._handle_for(deadline)
        cs = handle.command_set
        jobs = []
        for first, data in chunks:
            call = calls.pmc_wrpmcrng(cs, code, 0, first, first + len(data) - 1, data)
            jobs.append(self._submit(call.parts[0], cs, deadline))
        outcomes: list[ChunkOutcome] = []
        try:
            for job in jobs:
                try:
                    (block,) = await job.token[0]
                    _data(block, "pmc_wrpmcrng")
                except FocasError as exc:
                    unanswered = job.sent and job.ending in (Ending.TIMED_OUT, Ending.LOST)
                    outcomes.append((exc, unanswered))
                else:
                    outcomes.append(None)
        finally:
            for job in jobs:
                self._session.abandon(job)
        return outcomes

    # -- alarms --------------------------------------------------------------------------
    async def read_alarm_status(self, *, timeout: float | None = None) -> int:
        """``cnc_alarm2``: the alarm bits (bit n set while an alarm of type n is active)."""
        value: AlarmStatus = await self._one(self._deadline(timeout), calls.cnc_alarm2)
        return value.alarm

    async def read_alarms(
        self,
        *,
        alm_type: AlarmType | str | int = -1,
        count: int = _MAX_ACTIVE_ALARMS,
        timeout: float | None = None,
    ) -> tuple[ActiveAlarm, ...]:
        """``cnc_rdalmmsg2``: up to ``count`` active alarms (all types, -1, or only
        ``alm_type``: by name, ``"PS"``, an :class:`AlarmType` or a number)."""
        t = alarm_type_number(alm_type, every=True)
        check_int("alarm count", count, 1, I16_MAX)
        value: AlarmMessages = await self._one(
            self._deadline(timeout), calls.cnc_rdalmmsg2, t, count
        )
        return tuple(
            ActiveAlarm(a.axis, a.alarm_type, a.number, _text(a.message)) for a in value.alarms
        )

    async def read_alarm_history(
        self, depth: int = 10, *, timeout: float | None = None
    ) -> AlarmHistory:
        """``cnc_rdalmhistry``: up to ``depth`` (clamped to 1..250) most recent entries,
        newest first, read 23 at a time as the library does. An error on the first chunk
        raises :class:`CncError`; EW_NUMBER on a later one ends the list."""
        depth = history_depth(depth)
        deadline = self._deadline(timeout)
        handle = await self._handle_for(deadline)
        call = calls.cnc_rdalmhistry(handle.command_set, 1, depth)
        entries: list[AlarmHistoryEntry] = []
        for frame, part in zip(call.frames, call.parts, strict=True):
            (block,) = await self._exchange(part, handle.command_set, deadline)
            if block.ew == EW.NUMBER:
                break  # no entry from here on (from the first: the history is empty)
            history: NativeAlarmHistory = _decoded(frame[0], block, "cnc_rdalmhistry", 0)
            for r in history.records:
                try:
                    when = datetime(r.year, r.month, r.day, r.hour, r.minute, r.second, tzinfo=UTC)
                except ValueError as exc:
                    raise PayloadError(f"cnc_rdalmhistry: bad date in an entry: {exc}") from None
                text = r.text[: max(min(r.length, len(r.text)), 0)]
                entries.append(AlarmHistoryEntry(when, r.axis, r.group, r.alarm_no, _text(text)))
            request = frame[0]
            assert isinstance(request, NativeAlarmHistoryRequest)
            if len(history.records) < request.last - request.first + 1:
                break
        return AlarmHistory(tuple(entries[:depth]))

    # -- what FOCAS/2 does not carry -----------------------------------------------------
    async def unlock(self, password: str | bytes, *, timeout: float | None = None) -> None:
        """Not carried: FOCAS/2 has no ``cnc_wrunlockparam`` (FANUC's library lacks it)."""
        raise NativeUnsupportedError("unlock", "FOCAS/2 has no cnc_wrunlockparam")

    async def read_config_record(
        self, rack: int, slot: int, *, timeout: float | None = None
    ) -> bytes:
        """Not carried: ``versamax_rdconfig`` is a packed-protocol command only."""
        raise NativeUnsupportedError("read_config_record", "versamax_rdconfig is packed-only")

    async def read_module_config(
        self, rack: int, slot: int, *, timeout: float | None = None
    ) -> Any:
        """Not carried: ``versamax_rdconfig`` is a packed-protocol command only."""
        raise NativeUnsupportedError("read_module_config", "versamax_rdconfig is packed-only")

    @property
    def sim(self) -> Any:
        """Not carried: the simulator's control commands exist on the packed protocol only."""
        raise NativeUnsupportedError("sim", "the simulator controls are packed-protocol commands")


async def _all_or_first_error(coros: Any) -> list[bytes]:
    """Run ``coros`` (reads, safe to give up) together; the first failure cancels the rest and
    is raised."""
    tasks = [asyncio.ensure_future(c) for c in coros]
    try:
        return list(await asyncio.gather(*tasks))
    finally:
        for t in tasks:
            if not t.done():
                t.cancel()
        await asyncio.wait(tasks)
        for t in tasks:
            if not t.cancelled():
                t.exception()  # retrieved: none is reported unseen
