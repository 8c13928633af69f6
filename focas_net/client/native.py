"""The asyncio client of FANUC's FOCAS/2 Ethernet protocol: :class:`NativeClient`.

It speaks to a CNC the way FANUC's own library (libfwlib32) does, frame for frame
(``docs/native-client.md``, ``docs/native-protocol.md``): each method sends the frames
:mod:`focas_net.native.calls` lists for its FOCAS function in the handle's command set. The
connection pair, the queue, the packing of calls into frames and the deadlines are the link's
(:mod:`._native_link`, over :mod:`focas_net.native.session`); the calls both clients share are
:mod:`._composite`'s. What is here is each call: its arguments checked and its frames encoded
in the caller's frame, then its answer decoded.

One call, ``read_macro(100)``::

    check_macro(100)                        the argument (TypeError, ValueError), nothing sent
    deadline = self._deadline(None)         the client's timeout from now
    handle = self._handle_now() or ...      the open handle (else wait for the reconnect)
    call = calls.cnc_rdmacro(cs, 100)       the library's frame, encoded once for these values
    blocks = await self._exchange(...)      queued, packed into a frame, answered (the link)
    made_once(handle, call, blocks, _macro) EW code -> CncError; the value, made once per answer
"""

# Every call takes a per-call ``timeout=`` by contract (one deadline per call covers its
# frames, its lock waits and its wait for a reconnect), so ASYNC109 does not apply here.
# ruff: noqa: ASYNC109

from __future__ import annotations

import asyncio
from collections.abc import Sequence
from dataclasses import dataclass
from datetime import UTC, datetime
from decimal import Decimal
from typing import Any, Final

from focas_net.errors import EW, CncError, FocasError, PayloadError

from ..native import (
    LIBRARY_MAX_REQUEST_BODY,
    REQUEST_BLOCK_SIZE,
    AlarmMessages,
    AlarmStatus,
    AxisNames,
    CncId,
    CommandSet,
    Ending,
    ExecutingProgram,
    LibraryCall,
    NativeAlarmHistory,
    NativeAlarmHistoryRequest,
    NativeCommand,
    NativePmcArea,
    NativePmcData,
    NativeProgramNumbers,
    PositionAxisNames,
    ResponseBlock,
    ScaledValues,
    SequenceNumber,
    StatInfo,
    TimerValue,
    calls,
    max_response_body,
)
from ..protocol import (
    ActiveAlarm,
    AlarmHistory,
    AlarmHistoryEntry,
    AlarmType,
    PmcArea,
    PositionKind,
    ProgramNumbers,
    StatusInfo,
    SysInfo,
)
from ._composite import ChunkOutcome, macro_named
from ._native_clock import NativeClock
from ._native_files import NativeFiles
from ._native_info import NativeInfo
from ._native_items import (
    axis_name,
    block_data,
    decoded,
    made_once,
    only_answer,
    signed,
    text,
)
from ._native_link import Handle, check_axis_of
from ._native_modal import NativeModal
from ._native_offsets import NativeOffsets
from ._native_spindles import NativeSpindles
from ._native_started import NativeStarted
from ._started import StartedCall
from ._values import (
    I16_MAX,
    AreaLike,
    Paths,
    Positions,
    alarm_type_number,
    check_axis,
    check_int,
    check_macro,
    history_depth,
    macro_from_wire,
    macro_write,
)
from .reconnect import ReconnectPolicy, StateCallback

__all__ = ["DynamicData", "NativeClient", "NativeUnsupportedError", "ServoLoad"]

#: Most blocks FANUC's library puts in one request frame; the default of ``max_blocks``.
LIBRARY_MAX_BLOCKS: Final = 10
_MAX_ACTIVE_ALARMS: Final = 32
_ANSWER_HEAD: Final = 16
_TIMER_TYPES: Final = 4


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


def _status(
    handle: Handle, call: LibraryCall, blocks: tuple[ResponseBlock, ...], _path: int
) -> StatusInfo:
    """The status of ``cnc_statinfo``'s answer ``blocks`` (hdck and tmmode read 0 when the CNC
    refuses them, as the library reads them)."""
    _, hd, tm = blocks
    stat: StatInfo = decoded(handle, call, blocks, 0, handle.max_axes)
    hdck = 0 if hd.ew else decoded(handle, call, blocks, 1, 0).hdck
    tmmode = 0 if tm.ew else decoded(handle, call, blocks, 2, 0).tmmode
    return StatusInfo(
        hdck, tmmode, stat.aut, stat.run, stat.motion, stat.mstb, stat.emergency, stat.alarm,
        stat.edit,
    )  # fmt: skip


def _dynamic(
    handle: Handle, call: LibraryCall, blocks: tuple[ResponseBlock, ...], path: int
) -> DynamicData:
    """The result of a ``cnc_rddynamic2`` ``call`` (of every axis, or of one) on ``path`` from
    its answer ``blocks``."""
    values = [decoded(handle, call, blocks, i, handle.max_axes) for i in range(5)]
    axis = call.frames[0][-1].axis  # type: ignore[attr-defined]
    count = handle.axes_on(path) if axis == -1 else 1
    alarm: AlarmStatus = values[0]
    prg: NativeProgramNumbers = values[1]
    seq: SequenceNumber = values[2]

    def first(v: ScaledValues) -> int:
        return v.values[0].mantissa if v.values else 0

    def mantissas(i: int) -> tuple[int, ...]:
        # (the path's axes only: the answer holds a record for each of the CNC's most axes)
        return ScaledValues.mantissas(block_data(blocks[i], call.function), count)

    return DynamicData(
        alarm.alarm & 0xFFFF, prg.running, prg.main, seq.number, first(values[3]),
        first(values[4]), mantissas(5), mantissas(6), mantissas(7), mantissas(8),
    )  # fmt: skip


def _macro(
    handle: Handle, call: LibraryCall, blocks: tuple[ResponseBlock, ...], _path: int
) -> Decimal | None:
    """The value of a ``cnc_rdmacro`` answer (binary records converted as the library
    converts them)."""
    values: ScaledValues = only_answer(handle, call, blocks)
    if not values.values:
        raise PayloadError("cnc_rdmacro: the answer carries no value")
    return macro_from_wire(*values.values[0].to_macro())


def _check_dynamic_axis(axis: object) -> None:
    """``cnc_rddynamic2``'s axis: -1 (every axis) or 1..n."""
    check_axis(axis, every=-1)


class NativeClient(
    NativeInfo,
    NativeOffsets,
    NativeFiles,
    NativeClock,
    NativeModal,
    NativeSpindles,
    NativeStarted,
):
    """An asyncio client of FANUC's FOCAS/2 Ethernet protocol (port 8193 on a real control).

    It has the methods of :class:`~focas_net.client.FocasClient` that FOCAS/2 carries, with
    the same results, exceptions, per-call ``timeout=`` and :class:`ReconnectPolicy`, plus
    :meth:`read_dynamic`, :meth:`read_timer`, :meth:`read_spindle_loads`,
    :meth:`read_servo_meters`, :meth:`read_cnc_id`, :meth:`read_sequence_number`,
    :meth:`read_program_name`, :meth:`read_alarm_status` and :meth:`read_param_type` (in
    place of ``read_param_attributes``), the tool and work offsets and tool life calls of
    :class:`~focas_net.client._native_offsets.NativeOffsets`, the program folders of a
    30i-class control (:class:`~focas_net.client._native_files.NativeFiles`), and reads
    started now and finished later for a poller (``start_read_status``, ``start_read_dynamic``
    here, ``start_read_macro``, ``start_read_alarms``, ``start_read_pmc`` of
    :class:`~focas_net.client._native_started.NativeStarted`). Concurrent
    calls are gathered into frames of at most ``max_blocks`` blocks (``docs/native-client.md``).
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
        path: int = 1,
    ) -> None:
        super().__init__(
            host,
            port,
            timeout=timeout,
            reconnect=reconnect,
            max_blocks=max_blocks,
            on_state_change=on_state_change,
            path=path,
        )
        self._init_items()

    # -- status and identity -------------------------------------------------------------
    async def read_status(
        self, *, path: int | None = None, timeout: float | None = None
    ) -> StatusInfo:
        """``cnc_statinfo``: the ODBST status (0x19; hdck 0xE1 and tmmode 0x98 read 0 when
        the CNC refuses them, as the library reads them)."""
        p = self._path_of(path)
        deadline = self._deadline(timeout)
        handle = self._handle_now() or await self._handle_for(deadline)
        call = calls.cnc_statinfo(handle.command_set)
        blocks = await self._exchange(handle, call, deadline, 0, p)
        return made_once(handle, call, blocks, _status, p)

    def start_read_status(
        self, *, path: int | None = None, timeout: float | None = None
    ) -> StartedCall[StatusInfo]:
        """:meth:`read_status` started now (its frame queued at once when the client is
        connected) and finished by awaiting :meth:`StartedCall.result` (see
        :func:`~focas_net.client.read_status_all`)."""
        p = self._path_of(path)
        return self._start(
            lambda handle: calls.cnc_statinfo(handle.command_set), p, timeout, _status,
            lambda: self.read_status(path=p, timeout=timeout),
        )  # fmt: skip

    async def read_sysinfo(self, *, timeout: float | None = None) -> SysInfo:
        """``cnc_sysinfo``: ODBSYS as the CNC answered it while connecting (nothing is sent,
        like FANUC's library)."""
        deadline = self._deadline(timeout)  # checked even when nothing is sent
        handle = self._handle_now() or await self._handle_for(deadline)
        info = handle.sysinfo
        if info is None:
            raise PayloadError("cnc_sysinfo: the connect-time system information is missing")

        def raw(text: str, size: int) -> bytes:
            return text.encode("latin-1")[:size].ljust(size, b"\x00")

        return SysInfo(
            info.addinfo, info.max_axis, raw(info.cnc_type, 2), raw(info.mt_type, 2),
            raw(info.series, 4), raw(info.version, 4), raw(info.axes, 2),
        )  # fmt: skip

    async def read_paths(self, *, timeout: float | None = None) -> Paths:
        """``cnc_getpath``: the client's :attr:`path` (what calls given no ``path=`` read) and
        the number of paths the open answer announced; nothing is sent, as with FANUC's
        library."""
        deadline = self._deadline(timeout)  # checked even when nothing is sent
        handle = self._handle_now() or await self._handle_for(deadline)
        return Paths(self.path, handle.paths)

    @property
    def path_count(self) -> int | None:
        """The number of paths the open answer announced (None while not connected)."""
        handle = self._handle
        return None if handle is None else handle.paths

    async def read_cnc_id(self, *, timeout: float | None = None) -> tuple[int, int, int, int]:
        """``cnc_rdcncid``: the four 32-bit words of the CNC ID."""
        deadline = self._deadline(timeout)
        handle = self._handle_now() or await self._handle_for(deadline)
        call = calls.cnc_rdcncid(handle.command_set)
        cid: CncId = only_answer(handle, call, await self._exchange(handle, call, deadline))
        return (cid.id1, cid.id2, cid.id3, cid.id4)

    async def read_timer(
        self, timer_type: int, *, path: int | None = None, timeout: float | None = None
    ) -> TimerValue:
        """``cnc_rdtimer``: a timer (0 power-on, 1 operating, 2 cutting, 3 cycle, 4 free) as
        minutes and milliseconds."""
        p = self._path_of(path)
        check_int("timer type", timer_type, 0, _TIMER_TYPES)
        deadline = self._deadline(timeout)
        handle = self._handle_now() or await self._handle_for(deadline)
        call = calls.cnc_rdtimer(handle.command_set, timer_type)
        value: TimerValue = only_answer(
            handle, call, await self._exchange(handle, call, deadline, 0, p)
        )
        return value

    # -- program, feed, spindle ----------------------------------------------------------
    async def read_program_numbers(
        self, *, path: int | None = None, timeout: float | None = None
    ) -> ProgramNumbers:
        """``cnc_rdprgnumo8``: the running and the main program numbers (0 = none)."""
        p = self._path_of(path)
        deadline = self._deadline(timeout)
        handle = self._handle_now() or await self._handle_for(deadline)
        call = calls.cnc_rdprgnumo8(handle.command_set)
        value: NativeProgramNumbers = only_answer(
            handle, call, await self._exchange(handle, call, deadline, 0, p)
        )
        return ProgramNumbers(value.running, value.main)

    async def read_program_name(
        self, *, path: int | None = None, timeout: float | None = None
    ) -> tuple[int, str]:
        """``cnc_exeprgname``: the O number and the name of the executing program."""
        p = self._path_of(path)
        deadline = self._deadline(timeout)
        handle = self._handle_now() or await self._handle_for(deadline)
        call = calls.cnc_exeprgname(handle.command_set)
        value: ExecutingProgram = only_answer(
            handle, call, await self._exchange(handle, call, deadline, 0, p)
        )
        return value.o_num, text(value.name)

    async def read_sequence_number(
        self, *, path: int | None = None, timeout: float | None = None
    ) -> int:
        """``cnc_rdseqnum``: the sequence number being executed."""
        p = self._path_of(path)
        deadline = self._deadline(timeout)
        handle = self._handle_now() or await self._handle_for(deadline)
        call = calls.cnc_rdseqnum(handle.command_set)
        value: SequenceNumber = only_answer(
            handle, call, await self._exchange(handle, call, deadline, 0, p)
        )
        return value.number

    async def read_feed(self, *, path: int | None = None, timeout: float | None = None) -> int:
        """``cnc_actf``: the actual feed rate."""
        p = self._path_of(path)
        deadline = self._deadline(timeout)
        handle = self._handle_now() or await self._handle_for(deadline)
        call = calls.cnc_actf(handle.command_set)
        value: ScaledValues = only_answer(
            handle, call, await self._exchange(handle, call, deadline, 0, p)
        )
        return value.values[0].mantissa if value.values else 0

    async def read_spindle_speed(
        self, *, path: int | None = None, timeout: float | None = None
    ) -> int:
        """``cnc_acts``: the actual spindle speed."""
        p = self._path_of(path)
        deadline = self._deadline(timeout)
        handle = self._handle_now() or await self._handle_for(deadline)
        call = calls.cnc_acts(handle.command_set)
        value: ScaledValues = only_answer(
            handle, call, await self._exchange(handle, call, deadline, 0, p)
        )
        return value.values[0].mantissa if value.values else 0

    async def read_spindle_loads(
        self, spindle: int = -1, *, path: int | None = None, timeout: float | None = None
    ) -> tuple[int, ...]:
        """``cnc_rdspload``: the load of every spindle (``spindle=-1``) or of one (1..n)."""
        p = self._path_of(path)
        check_axis(spindle, "spindle", every=-1)
        deadline = self._deadline(timeout)
        handle = self._handle_now() or await self._handle_for(deadline)
        call = calls.cnc_rdspload(handle.command_set, spindle)
        blocks = await self._exchange(handle, call, deadline, 0, p)
        for i, request in enumerate(call.frames[0]):
            block_data(blocks[i], "cnc_rdspload")
            if request.COMMAND == NativeCommand.AXIS_COUNT:
                if decoded(handle, call, blocks, i, 0).count == 0:
                    raise CncError.from_ew(EW.NOOPT, "cnc_rdspload: no spindle")
        index = 0 if handle.command_set is CommandSet.FS16I else 1
        loads: ScaledValues = decoded(handle, call, blocks, index, 0)
        limit = handle.spindles_on(p) if spindle == -1 else 1
        return tuple(signed(v.mantissa, 2) for v in loads.values[: max(limit, 1)])

    async def read_servo_meters(
        self, *, path: int | None = None, timeout: float | None = None
    ) -> tuple[ServoLoad, ...]:
        """``cnc_rdsvmeter``: the servo load meter of every axis, with its name."""
        p = self._path_of(path)
        deadline = self._deadline(timeout)
        handle = self._handle_now() or await self._handle_for(deadline)
        call = calls.cnc_rdsvmeter(handle.command_set)
        blocks = await self._exchange(handle, call, deadline, 0, p)
        names: AxisNames | None = None
        loads: ScaledValues | None = None
        for i, request in enumerate(call.frames[0]):
            value = decoded(handle, call, blocks, i, handle.max_axes)
            if request.COMMAND == NativeCommand.AXIS_NAME:
                names = value
            elif request.COMMAND == NativeCommand.RDSVMETER:
                loads = value
        assert names is not None and loads is not None
        count = min(handle.axes_on(p), len(loads.values), len(names.records))
        return tuple(
            ServoLoad(
                axis_name(names.records[i].encode()),
                Decimal(abs(loads.values[i].mantissa)).scaleb(-max(loads.values[i].decimals, 0)),
            )
            for i in range(count)
        )

    async def read_axis_names(
        self, *, path: int | None = None, timeout: float | None = None
    ) -> tuple[str, ...]:
        """``cnc_rdaxisname``: the names of the path's axes, in order."""
        p = self._path_of(path)
        deadline = self._deadline(timeout)
        handle = self._handle_now() or await self._handle_for(deadline)
        call = calls.cnc_rdaxisname(handle.command_set)
        blocks = await self._exchange(handle, call, deadline, 0, p)
        names: AxisNames = only_answer(handle, call, blocks)
        return tuple(axis_name(n.encode()) for n in names.records[: handle.axes_on(p)])

    async def read_dynamic(
        self, axis: int = -1, *, path: int | None = None, timeout: float | None = None
    ) -> DynamicData:
        """``cnc_rddynamic2``: alarm bits, program numbers, sequence number, feed, spindle
        speed and the four positions of every axis (``axis=-1``) or of one (1..n), in one
        frame. Needs the CNC's FOCAS option bit 0, as in FANUC's library (EW_NOOPT)."""
        p = self._path_of(path)
        _check_dynamic_axis(axis)
        deadline = self._deadline(timeout)
        handle = self._handle_now() or await self._handle_for(deadline)
        call = self._dynamic_call(handle, axis, p)
        blocks = await self._exchange(handle, call, deadline, 0, p)
        return made_once(handle, call, blocks, _dynamic, p)

    def start_read_dynamic(
        self, axis: int = -1, *, path: int | None = None, timeout: float | None = None
    ) -> StartedCall[DynamicData]:
        """:meth:`read_dynamic` started now and finished by awaiting
        :meth:`StartedCall.result` (see :func:`~focas_net.client.read_dynamic_all`)."""
        _check_dynamic_axis(axis)
        p = self._path_of(path)
        return self._start(
            lambda handle: self._dynamic_call(handle, axis, p), p, timeout, _dynamic,
            lambda: self.read_dynamic(axis, path=p, timeout=timeout),
        )  # fmt: skip

    @staticmethod
    def _dynamic_call(handle: Handle, axis: int, path: int) -> LibraryCall:
        """The ``cnc_rddynamic2`` call of ``axis`` on ``handle``'s ``path``; :class:`CncError`
        when the CNC lacks the option, the path or the axis."""
        if not handle.option_bits & 1:
            raise CncError.from_ew(EW.NOOPT, "cnc_rddynamic2: the CNC lacks FOCAS option bit 0")
        check_axis_of(handle, axis, "cnc_rddynamic2", path)
        return calls.cnc_rddynamic2(handle.command_set, axis)

    async def read_positions(
        self,
        kind: str | int | PositionKind = PositionKind.ABSOLUTE,
        *,
        axis: int | None = None,
        path: int | None = None,
        timeout: float | None = None,
    ) -> Positions:
        """``cnc_rdposition``: positions of every axis (``axis=None``) or of axis ``axis``
        (1..n), with the axis names; the frame reads all four kinds, as the library does.

        An unknown ``kind`` or an ``axis`` below 1 raises :class:`ValueError` before anything
        is sent; an axis the CNC does not have raises EW_ATTRIB (:class:`CncError`).
        """
        p = self._path_of(path)
        which = PositionKind.parse(kind)
        check_axis(axis)
        deadline = self._deadline(timeout)
        handle = self._handle_now() or await self._handle_for(deadline)
        check_axis_of(handle, axis or 0, "cnc_rdposition", p)
        call = calls.cnc_rdposition(handle.command_set)
        blocks = await self._exchange(handle, call, deadline, 0, p)
        names: PositionAxisNames | None = None
        positions: ScaledValues | None = None
        for i, request in enumerate(call.frames[0]):
            command = request.COMMAND
            block = blocks[i]
            if command == NativeCommand.AXIS_NAME:
                names = decoded(handle, call, blocks, i, handle.max_axes)
            elif (
                command == NativeCommand.POSITION and getattr(request, "kind", None) == which.value
            ):
                positions = decoded(handle, call, blocks, i, handle.max_axes)
            elif command in (
                NativeCommand.POSITION,
                NativeCommand.AXIS_COUNT,
                NativeCommand.STATINFO,
            ):
                block_data(block, "cnc_rdposition")
        assert names is not None and positions is not None
        count = min(handle.axes_on(p), len(positions.values), len(names.records))
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
            name = axis_name(raw) or f"axis{i + 1}"
            values[name] = Decimal(record.mantissa).scaleb(-record.decimals)
            increments[name] = record.mantissa
        return Positions(which, decimals, values, increments)

    # -- macros --------------------------------------------------------------------------
    async def read_macro(
        self, number: int, *, path: int | None = None, timeout: float | None = None
    ) -> Decimal | None:
        """``cnc_rdmacro``: the value of ``#number`` as a Decimal, or None when vacant
        (binary records converted as the library converts them)."""
        p = self._path_of(path)
        check_macro(number)
        deadline = self._deadline(timeout)
        handle = self._handle_now() or await self._handle_for(deadline)
        call = calls.cnc_rdmacro(handle.command_set, number)
        blocks = await self._exchange(handle, call, deadline, 0, p)
        return made_once(handle, call, blocks, _macro, p)

    async def write_macro(
        self,
        number: int,
        value: int | Decimal | float | str,
        *,
        path: int | None = None,
        timeout: float | None = None,
    ) -> None:
        """``cnc_wrmacro``: write ``#number`` (a binary record at 16i class, base 10 at 30i,
        as the library sends it); see :func:`~focas_net._typed.macro_to_wire`."""
        p = self._path_of(path)
        mcr_val, dec_val = macro_write(number, value)
        deadline = self._deadline(timeout)
        handle = self._handle_now() or await self._handle_for(deadline)
        call = calls.cnc_wrmacro(handle.command_set, number, mcr_val, dec_val)
        async with macro_named(number, value):
            (block,) = await self._exchange(handle, call, deadline, 0, p)
            block_data(block, "cnc_wrmacro")

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
        """Most PMC bytes one write carries: 1420, a request body of
        :data:`LIBRARY_MAX_REQUEST_BODY` as FANUC's library cuts it, whatever the version."""
        return LIBRARY_MAX_REQUEST_BODY - 2 - REQUEST_BLOCK_SIZE

    async def _read_pmc_chunk(
        self, code: int, start: int, count: int, deadline: float | None
    ) -> bytes:
        handle = self._handle_now() or await self._handle_for(deadline)
        call = calls.pmc_rdpmcrng(handle.command_set, code, 0, start, start + count - 1)
        data: NativePmcData = only_answer(
            handle, call, await self._exchange(handle, call, deadline)
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
        handle = self._handle_now() or await self._handle_for(deadline)
        cs = handle.command_set
        jobs = []
        for first, data in chunks:
            call = calls.pmc_wrpmcrng(cs, code, 0, first, first + len(data) - 1, data)
            jobs.append(self._submit(call.parts[0], cs, deadline))
        outcomes: list[ChunkOutcome] = []
        try:
            for job in jobs:
                try:
                    (block,) = await job.token
                    block_data(block, "pmc_wrpmcrng")
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
    async def read_alarm_status(
        self, *, path: int | None = None, timeout: float | None = None
    ) -> int:
        """``cnc_alarm2``: the alarm bits (bit n set while an alarm of type n is active)."""
        p = self._path_of(path)
        deadline = self._deadline(timeout)
        handle = self._handle_now() or await self._handle_for(deadline)
        call = calls.cnc_alarm2(handle.command_set)
        value: AlarmStatus = only_answer(
            handle, call, await self._exchange(handle, call, deadline, 0, p)
        )
        return value.alarm

    async def read_alarms(
        self,
        *,
        alm_type: AlarmType | str | int = -1,
        count: int = _MAX_ACTIVE_ALARMS,
        path: int | None = None,
        timeout: float | None = None,
    ) -> tuple[ActiveAlarm, ...]:
        """``cnc_rdalmmsg2``: up to ``count`` active alarms (all types, -1, or only
        ``alm_type``: by name, ``"PS"``, an :class:`AlarmType` or a number)."""
        p = self._path_of(path)
        t = alarm_type_number(alm_type, every=True)
        check_int("alarm count", count, 1, I16_MAX)
        deadline = self._deadline(timeout)
        handle = self._handle_now() or await self._handle_for(deadline)
        call = calls.cnc_rdalmmsg2(handle.command_set, t, count)
        value: AlarmMessages = only_answer(
            handle, call, await self._exchange(handle, call, deadline, 0, p)
        )
        return tuple(
            ActiveAlarm(a.axis, a.alarm_type, a.number, text(a.message)) for a in value.alarms
        )

    async def read_alarm_history(
        self, depth: int = 10, *, timeout: float | None = None
    ) -> AlarmHistory:
        """``cnc_rdalmhistry``: up to ``depth`` (1.., above 250 read as 250) latest entries,
        newest first, read 23 at a time as the library does. An error on the first chunk
        raises :class:`CncError`; EW_NUMBER on a later one ends the list."""
        depth = history_depth(depth)
        deadline = self._deadline(timeout)
        handle = self._handle_now() or await self._handle_for(deadline)
        call = calls.cnc_rdalmhistry(handle.command_set, 1, depth)
        entries: list[AlarmHistoryEntry] = []
        for n, frame in enumerate(call.frames):
            blocks = await self._exchange(handle, call, deadline, n)
            if blocks[0].ew == EW.NUMBER:
                break  # no entry from here on (from the first: the history is empty)
            history: NativeAlarmHistory = decoded(handle, call, blocks, 0, 0, frame=n)
            for r in history.records:
                try:
                    when = datetime(r.year, r.month, r.day, r.hour, r.minute, r.second, tzinfo=UTC)
                except ValueError as exc:
                    raise PayloadError(f"cnc_rdalmhistry: bad date in an entry: {exc}") from None
                message = text(r.text[: max(min(r.length, len(r.text)), 0)])
                entries.append(AlarmHistoryEntry(when, r.axis, r.group, r.alarm_no, message))
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
    """Run ``coros`` (reads, safe to give up) together; a failure cancels those still
    running, and the first failure in chunk order is raised: the chunk that was sent, not
    one queued behind it that ended with it (``never sent``)."""
    tasks = [asyncio.ensure_future(c) for c in coros]
    try:
        await asyncio.wait(tasks, return_when=asyncio.FIRST_EXCEPTION)
    finally:
        for t in tasks:
            if not t.done():
                t.cancel()
        await asyncio.wait(tasks)
        # every failure retrieved (none reported unseen), also while this call is cancelled
        failures = [t.exception() for t in tasks if not t.cancelled()]
    first = next((e for e in failures if e is not None), None)
    if first is not None:
        raise first
    return [t.result() for t in tasks]
