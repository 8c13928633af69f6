"""The asyncio client of FANUC's FOCAS/2 Ethernet protocol: :class:`NativeClient`.

It speaks to a CNC the way FANUC's own library (libfwlib32) does, frame for frame (see
``docs/native-client.md`` and ``docs/native-protocol.md``):

* **two TCP connections**, A then B, each opened with an open request (channel 1 on A, 2 on B);
  B's open answer picks the command set (16i class up to version 2, 30i class from 3), the
  max axes, the paths and (30i class) the FOCAS option bits;
* while connecting, on B, one 0x18 (system info) block per present path, and at 16i class
  parameter 9968 (the option bits); ``read_sysinfo`` is answered from that store;
* every call sends the blocks :mod:`focas_net.native.calls` lists for it in the handle's
  command set, on B;
* closing sends a close request on A, waits for its answer, then the same on B.

**One frame in flight.** FOCAS/2 carries no request id: the answer to a data request is the
next data answer on B. So B never has more than one request frame outstanding. Calls made
while a frame is out wait in a queue, and the next frame carries as many of them as fit: at
most ``max_blocks`` blocks (FANUC's library sends up to ten) and an answer no larger than the
open answer's version allows (1450 bytes at version 2). Each call receives its own blocks back;
an EW code in one block fails only the call that block belongs to.

**Timeouts and cancellation.** A call that times out or is cancelled before its frame was sent
is simply taken out of the queue. Once sent, its blocks are part of a frame whose answer is
still awaited for the other calls of that frame, until the latest deadline among them; the
answer's blocks of a call that gave up are dropped. If that latest deadline passes without an
answer, no later answer could be told apart from the answer to the next frame, so the
connection pair is closed (as FANUC's library declares its handle dead) and, with a
:class:`ReconnectPolicy`, opened again; calls still queued then go out on the new connection.
"""

# Every call takes a per-call ``timeout=`` by contract (one deadline per call covers its
# frames, its lock waits and its wait for a reconnect), so ASYNC109 does not apply here.
# ruff: noqa: ASYNC109

from __future__ import annotations

import asyncio
import logging
import struct
from collections import deque
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from datetime import UTC, datetime
from decimal import Decimal
from functools import partial
from typing import Any, Final

from focas_net._memo import Memo
from focas_net.errors import (
    EW,
    ChunkedWriteError,
    CncError,
    FocasConnectionError,
    FocasError,
    FocasTimeoutError,
    PayloadError,
    ProtocolError,
)

from ..native import calls
from ..native.blocks import (
    REQUEST_BLOCK_SIZE,
    ResponseBlock,
    answer_refusal,
    decode_response_body,
    encode_request,
)
from ..native.calls import CommandSet, LibraryCall
from ..native.frame import (
    CLIENT_VERSION,
    MAGIC,
    NATIVE_HEADER,
    NATIVE_HEADER_SIZE,
    FrameType,
    encode_close_request,
    encode_open_request,
    max_response_body,
)
from ..native.opening import OpenAnswer, OpenHeadV2, decode_open_answer
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
    NativeSysInfo,
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
    AlarmMessageRequest,
    MacroReadRequest,
    NativeAlarmHistoryRequest,
    NativeCommand,
    NativePmcArea,
    NativeRequest,
    ParamInfo3Request,
    ParamInfoRequest,
    PmcReadRequest,
)
from ..protocol import (
    MAX_HISTORY_DEPTH,
    ActiveAlarm,
    AlarmHistory,
    AlarmHistoryEntry,
    ParamDataType,
    ParamValue,
    PmcArea,
    PositionKind,
    ProgramNumbers,
    StatusInfo,
    SysInfo,
)
from ._channel import Channel, open_channel
from ._locks import KeyedLocks
from .client import (
    Positions,
    _byte_to_wire,
    _param_int,
    _real_to_wire,
    macro_from_wire,
    macro_to_wire,
)
from .reconnect import ClientState, ReconnectPolicy, StateCallback, _Lifecycle

__all__ = [
    "DynamicData",
    "NativeClient",
    "NativeUnsupportedError",
    "ServoLoad",
]

logger = logging.getLogger(__name__)

#: Most blocks FANUC's library puts in one request frame; the default of ``max_blocks``.
LIBRARY_MAX_BLOCKS: Final = 10
_PATH: Final = 1
#: No deadline (the watch timer not set).
_INF: Final = float("inf")
_current_task: Final = asyncio.current_task
_new: Final = object.__new__


class _Nobody:
    """The type of :data:`_NOBODY`."""


#: ``NativeClient._direct`` after the answer to a lone call of no task (one of many clients
#: read from one task): no caller to send the next frame, and nothing to kick for one.
_NOBODY: Final = _Nobody()
_CLOSE_GRACE: Final = 2.0
_ANSWER_HEAD: Final = 16
_MAX_ACTIVE_ALARMS: Final = 32
_ALARM_TEXT: Final = 64
_U16_LIMIT: Final = 0x10000
_DATA_ANSWER: Final = FrameType.DATA_RESPONSE >> 8
_I32: Final = struct.Struct(">i")
#: A data request frame's header and its block count.
_REQUEST_HEAD: Final = struct.Struct(">IHHHH")
_DATA_REQUEST: Final = int(FrameType.DATA_REQUEST)
_MAGIC: Final = int.from_bytes(MAGIC, "big")
_ERROR_WORDS: Final = struct.Struct(">hhhh")
_PARAM_WIDTH: Final[dict[int, int]] = {
    ParamType.BIT: 1,
    ParamType.BYTE: 1,
    ParamType.WORD: 2,
    ParamType.TWO_WORD: 4,
}
_DIAG_WIDTH: Final[dict[int, int]] = {0: 1, 1: 2, 2: 4, 3: 1, 4: 1}
#: Width of a real value (FANUC's REALPRM, as the packed client's ``ParamValue``).
_REAL_WIDTH: Final = 8
#: The two position numberings: ``cnc_rdposition`` arrays (0..3) and the single reads.
_SINGLE_KIND: Final = {
    PositionKind.ABSOLUTE: 4,
    PositionKind.MACHINE: 1,
    PositionKind.RELATIVE: 6,
    PositionKind.DISTANCE: 7,
}


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


# -- frames ------------------------------------------------------------------------------------


class _Lost(Exception):
    """The connection pair cannot carry any further frame."""


async def _read_frame(channel: Channel) -> tuple[int, int, bytes]:
    """``(version, type, body)`` of the next frame; :class:`_Lost` when it is not one."""
    try:
        head = await channel.readexactly(NATIVE_HEADER_SIZE)
        magic, version, frame_type, length = NATIVE_HEADER.unpack(head)
        if magic != int.from_bytes(MAGIC, "big"):
            raise _Lost("answer does not start with A0 A0 A0 A0")
        body = await channel.readexactly(length)
    except (asyncio.IncompleteReadError, ConnectionError, OSError) as exc:
        raise _Lost(f"connection closed ({exc!r})") from exc
    return version, frame_type, body


#: (request, max axes) -> (its block's bytes, the most answer bytes, the request bytes).
_BLOCKS: Final = Memo(1024)
#: (identity of a job's requests, max axes) -> the requests, and their blocks' bytes, the most
#: answer bytes and their size.
_PARTS: Final = Memo(1024)
#: (a whole answer frame, its header included; the request's block count) -> its blocks, as
#: checked.
_FRAMES: Final = Memo(512)
#: (identity of a request, max axes, answer data) -> the request and its decoded answer.
_ANSWERS: Final = Memo(1024)


def _block_of(request: NativeRequest, max_axes: int) -> tuple[bytes, int, int]:
    """The bytes of ``request``'s block, the most answer bytes it can get and its size."""
    key: tuple[NativeRequest, int] | None = (request, max_axes)
    try:
        known: tuple[bytes, int, int] | None = _BLOCKS.get(key)
    except TypeError:  # a request with an unhashable field: not remembered
        key, known = None, None
    if known is not None:
        return known
    encoded = request.to_block(_PATH).encode()
    value = (encoded, _answer_size(request, max_axes), len(encoded))
    if key is not None:
        _BLOCKS.put(key, value)
    return value


#: One job's blocks: their bytes, the most answer bytes they can get, their size, how many
#: they are and the request frame that carries them alone.
_Part = tuple[bytes, int, int, int, bytes]


#: The part of a job no frame has taken.
_NO_PART: Final[_Part] = (b"", 0, 0, 0, b"")


def _part_of(requests: tuple[NativeRequest, ...], max_axes: int) -> _Part:
    """The blocks of one job's ``requests`` (see :data:`_Part`). Remembered by the identity of
    the tuple (the entry holds it, so the identity stays its own): the library calls a poll
    repeats are built once, and hashing nine requests would cost more than encoding them."""
    key = (id(requests), max_axes)
    known: tuple[tuple[NativeRequest, ...], _Part] | None = _PARTS.get(key)
    if known is not None and known[0] is requests:
        return known[1]
    parts = [_block_of(r, max_axes) for r in requests]
    encoded = b"".join(p[0] for p in parts)
    count = len(requests)
    alone = _frame_of(encoded, count)
    value = (encoded, sum(p[1] for p in parts), sum(p[2] for p in parts), count, alone)
    _PARTS.put(key, (requests, value))
    return value


def _frame_of(blocks: bytes, count: int) -> bytes:
    """The data request frame of ``count`` encoded ``blocks``."""
    head = _REQUEST_HEAD.pack(_MAGIC, CLIENT_VERSION, _DATA_REQUEST, 2 + len(blocks), count)
    return head + blocks


#: (identity of an answer's blocks, from ``_FRAMES``) -> those blocks and a tuple of each of
#: them alone: the blocks handed to the calls of one block each that shared the frame.
_SINGLES: Final = Memo(512)

#: (identity of a call's first answer block) -> its blocks, what else the result depends on
#: (the call, the axes) and the call's result: a poll whose answer repeats gets the very
#: block objects of ``_FRAMES`` again, and builds its result once.
_RESULTS: Final = Memo(1024)


def _known_result(blocks: tuple[ResponseBlock, ...], extra: Any) -> Any:
    """The result remembered for ``blocks`` (the same objects, so the comparison is one of
    identities) and ``extra`` (the same object, or an equal tuple), else None."""
    known: tuple[tuple[ResponseBlock, ...], Any, Any] | None = _RESULTS.get(id(blocks[0]))
    if (
        known is not None
        and (known[0] is blocks or known[0] == blocks)
        and (known[1] is extra or known[1] == extra)
    ):
        return known[2]
    return None


def _remember_result(blocks: tuple[ResponseBlock, ...], extra: Any, value: Any) -> None:
    """Remember ``value`` as the result for ``blocks`` and ``extra`` (the entry holds the
    blocks, so the identity of the first stays its own)."""
    _RESULTS.put(id(blocks[0]), (blocks, extra, value))


#: Most library calls a handle keeps built for each of the calls a poll repeats.
_CALL_MEMO: Final = 1024

#: (build, command set, key) -> the library call: equal calls of every handle are one object,
#: so a result remembered by one client is found by the next with a compare of identities.
_CALLS: Final = Memo(4096)


def _memo_call(
    memo: dict[int, LibraryCall],
    key: int,
    build: Callable[[CommandSet, int], LibraryCall],
    cs: CommandSet,
) -> LibraryCall:
    """The library call ``build(cs, key)``, built once (``memo`` is the handle's, whose
    command set is ``cs``)."""
    call = memo.get(key)
    if call is None:
        if len(memo) >= _CALL_MEMO:
            memo.clear()
        call = memo[key] = _shared_call(build, cs, key)
    return call


def _shared_call(
    build: Callable[[CommandSet, int], LibraryCall], cs: CommandSet, key: int
) -> LibraryCall:
    """``build(cs, key)``, the one object of every handle."""
    shared = (build, cs, key)
    call: LibraryCall | None = _CALLS.get(shared)
    if call is None:
        call = build(cs, key)
        _CALLS.put(shared, call)
    return call


def _statinfo(cs: CommandSet, key: int) -> LibraryCall:
    return calls.cnc_statinfo(cs)


def _answer_size(request: NativeRequest, max_axes: int) -> int:
    """The most answer bytes (block head included) ``request`` can be answered with."""
    size: int
    if isinstance(request, MacroReadRequest):
        size = 8 * max(request.last - request.first + 1, 1)
    elif isinstance(request, PmcReadRequest):
        size = max(request.last - request.first + 1, 0)
    elif isinstance(request, AlarmMessageRequest):
        size = request.count * (16 + request.text_length)
    elif isinstance(request, NativeAlarmHistoryRequest):
        size = 60 * max(request.last - request.first + 1, 1)
    else:
        fixed = getattr(request.ANSWER, "SIZE", None)
        size = fixed if isinstance(fixed, int) else 8 + 16 * max_axes
    return _ANSWER_HEAD + size


# -- one handle: the A/B pair --------------------------------------------------------------------


class _Handle:
    """One open A/B connection pair and what its open answer said."""

    def __init__(self, a: Channel, b: Channel, opened: OpenAnswer) -> None:
        #: The two connections: A (the open and the close only) and B (every data frame).
        self.a = a
        self.b = b
        #: The frame in flight on B: its jobs, its block count and its (latest) deadline; the
        #: timer that watches the deadlines of frames in flight and when it fires; and the
        #: bytes of B received and not yet parsed into a frame.
        self.inflight: list[_Job] | None = None
        self.inflight_blocks = 0
        self.deadline: float | None = None
        self.timer: asyncio.TimerHandle | None = None
        self.timer_at = 0.0
        self.rx = bytearray()
        self.opened = opened
        self.version = opened.version
        self.command_set = CommandSet.for_version(opened.version)
        self.limit = max_response_body(opened.version)
        self.max_axes = opened.max_axes
        present = opened.present()
        self.axes = present[0].axes if present else 0
        self.spindles = present[0].spindles if present else 0
        self.paths = len(present)
        self.option_bits = opened.option_bits or 0
        self.sysinfo: NativeSysInfo | None = None
        self.closed = False
        #: The library calls a poll repeats, built once for this handle's command set.
        self.status_call = _shared_call(_statinfo, self.command_set, 0)
        #: What a status result depends on besides the answer (see :func:`_known_result`).
        self.status_key = (self.status_call, self.max_axes)
        self.macro_calls: dict[int, LibraryCall] = {}
        self.dynamic_calls: dict[int, LibraryCall] = {}
        # The library's write buffer: cnc_wrparam leaves the slots it does not write as the
        # previous write left them, and so does this client, byte for byte.
        self.param_slots: list[int] = [0] * max(self.max_axes, 1)
        self.param3_slots: list[ScaledNumber] = [ScaledNumber(0, 0, 0)] * max(self.max_axes, 1)

    @property
    def pmc_chunk(self) -> int:
        """Most PMC bytes one answer carries."""
        return self.limit - 2 - _ANSWER_HEAD

    @property
    def pmc_write_chunk(self) -> int:
        """Most PMC bytes one write request carries (request bodies are kept within the same
        size as answers)."""
        return self.limit - 2 - REQUEST_BLOCK_SIZE

    def detach(self) -> list[_Job]:
        """Stop parsing B's frames (its bytes are kept again, for the close exchange); the
        jobs of the frame in flight, now nobody's."""
        self.b.stop()
        if self.timer is not None:
            self.timer.cancel()
            self.timer = None
        batch, self.inflight = self.inflight or [], None
        return batch

    async def exchange(self, requests: Sequence[NativeRequest]) -> tuple[ResponseBlock, ...]:
        """One data frame on B and its answer (used while connecting, before frames are
        parsed by the client)."""
        self.b.write(encode_request([r.to_block(_PATH) for r in requests]))
        return self.check_answer(await _read_frame(self.b), len(requests))

    def check_answer(self, frame: tuple[int, int, bytes], count: int) -> tuple[ResponseBlock, ...]:
        """The blocks of a data answer, checked as FANUC's library checks them."""
        version, frame_type, body = frame
        if frame_type >> 8 != _DATA_ANSWER:
            raise _Lost(f"answer of frame type 0x{frame_type:04X} to a data request")
        if frame_type == FrameType.DATA_ERROR:
            if len(body) < _ERROR_WORDS.size:
                raise _Lost(f"error answer of {len(body)} bytes")
            _, code, _, _ = _ERROR_WORDS.unpack_from(body)
            raise CncError.from_ew(code, "error answer (0x2103) to the request frame")
        refusal = answer_refusal(body, count, version)
        if refusal is not None:
            raise _Lost(f"data answer refused: {refusal}")
        try:
            return decode_response_body(body)
        except ProtocolError as exc:
            raise _Lost(str(exc)) from exc

    def keep_answer(self, raw: bytes, count: int) -> tuple[ResponseBlock, ...]:
        """:meth:`check_answer` of the whole answer frame ``raw`` (header included) to a
        request of ``count`` blocks, kept in ``_FRAMES`` under ``(raw, count)``: an answer
        already taken is looked up there (by ``NativeClient._complete``) and taken again
        without a second walk (the blocks are the same objects, which
        :func:`_known_result` relies on)."""
        _, version, frame_type, _ = NATIVE_HEADER.unpack_from(raw)
        blocks = self.check_answer((version, frame_type, raw[NATIVE_HEADER_SIZE:]), count)
        _FRAMES.put((raw, count), blocks)
        return blocks

    def abort(self) -> None:
        self.closed = True
        self.a.close()
        self.b.close()

    async def close(self, grace: float) -> None:
        """Close A then B with the close exchange, as the library does; then the sockets."""
        if self.closed:
            return
        self.closed = True
        try:
            async with asyncio.timeout(grace):
                for channel in (self.a, self.b):
                    channel.write(encode_close_request())
                    _, frame_type, _ = await _read_frame(channel)
                    if frame_type != FrameType.CLOSE_RESPONSE:
                        break
        except (TimeoutError, _Lost, OSError):
            pass
        self.a.close()
        self.b.close()


async def _open_channel(
    host: str, port: int, channel: int, deadline: float | None
) -> tuple[Channel, int, bytes]:
    """Connection ``channel`` (1: A, 2: B), opened: the version and body of its open answer."""
    try:
        async with asyncio.timeout_at(deadline):
            conn = await open_channel(host, port)
    except TimeoutError:
        raise FocasTimeoutError(f"connecting to {host}:{port} timed out") from None
    except OSError as exc:
        raise FocasConnectionError(f"cannot connect to {host}:{port}: {exc}") from exc
    try:
        conn.write(encode_open_request(channel))
        async with asyncio.timeout_at(deadline):
            version, frame_type, body = await _read_frame(conn)
    except BaseException:
        conn.close()
        raise
    if frame_type != FrameType.OPEN_RESPONSE:
        conn.close()
        raise FocasConnectionError(f"{host}:{port} answered the open with type 0x{frame_type:04X}")
    return conn, version, body


async def _open_handle(host: str, port: int, deadline: float | None) -> _Handle:
    """Open A and B and run the connect-time requests of ``cnc_allclibhndl3``."""
    where = f"{host}:{port}"
    try:
        a, version_a, body_a = await _open_channel(host, port, 1, deadline)
    except TimeoutError:
        raise FocasTimeoutError(f"no open answer from {where}") from None
    except _Lost as exc:
        raise FocasConnectionError(f"{where}: {exc}") from None
    try:
        b, version, body = await _open_channel(host, port, 2, deadline)
    except BaseException as exc:
        a.close()
        if isinstance(exc, TimeoutError):
            raise FocasTimeoutError(f"no open answer from {where}") from None
        if isinstance(exc, _Lost):
            raise FocasConnectionError(f"{where}: {exc}") from None
        raise
    try:
        try:
            decode_open_answer(body_a, version_a)
            opened = decode_open_answer(body, version)
        except ProtocolError as exc:
            raise FocasConnectionError(f"{where}: open answer refused: {exc}") from None
        if isinstance(opened.head, OpenHeadV2) and opened.head.kind == 2:
            raise FocasConnectionError(f"{where}: an FS15-family control (kind 2) is not supported")
        handle = _Handle(a, b, opened)
        if not handle.paths:
            raise FocasConnectionError(f"{where}: the open answer announces no path")
        async with asyncio.timeout_at(deadline):
            connect = calls.cnc_allclibhndl3(handle.command_set, handle.paths)
            for frame in connect.frames:
                blocks = await handle.exchange(frame)
                for request, block in zip(frame, blocks, strict=True):
                    if block.ew:
                        raise CncError.from_ew(block.ew, "cnc_allclibhndl3")
                    if request.COMMAND == NativeCommand.SYSINFO and handle.sysinfo is None:
                        handle.sysinfo = request.decode_answer(block.data)
                    elif request.COMMAND == NativeCommand.RDPARAM:
                        handle.option_bits = (
                            block.data[11] if len(block.data) >= 12 else 0
                        )  # slot 0's low byte
            if isinstance(opened.head, OpenHeadV2) and opened.head.kind == 3:
                handle.option_bits = 1
    except TimeoutError:
        _abort(a, b)
        raise FocasTimeoutError(f"{where}: the connect requests were not answered") from None
    except _Lost as exc:
        _abort(a, b)
        raise FocasConnectionError(f"{where}: {exc}") from None
    except BaseException:
        _abort(a, b)
        raise
    return handle


def _abort(*channels: Channel) -> None:
    for channel in channels:
        channel.close()


# -- jobs: one frame's worth of one call --------------------------------------------------------


class _Job:
    """The blocks of one frame of one call, waiting to be sent or answered. Slotted, every
    attribute set when it is made: an instance dict would be built for each job otherwise
    (attributes first set after the first few instances of a class force one)."""

    __slots__ = ("command_set", "deadline", "future", "part", "requests", "task", "unarmed")

    def __init__(
        self,
        requests: tuple[NativeRequest, ...],
        command_set: CommandSet,
        deadline: float | None,
        future: asyncio.Future[tuple[ResponseBlock, ...]],
        task: asyncio.Task[Any] | None,
    ) -> None:
        self.requests = requests
        self.command_set = command_set
        self.deadline = deadline
        self.future = future
        self.task = task
        #: Its blocks as :func:`_part_of` gives them, once a frame takes it (and is sent).
        self.part: _Part = _NO_PART
        #: Queued for the frame the coming kick sends, whether its deadline is watched not
        #: yet decided.
        self.unarmed = False

    @property
    def sent(self) -> bool:
        """Whether a frame carrying it was sent."""
        return self.part is not _NO_PART


def _fail(jobs: Sequence[_Job], make: Callable[..., BaseException], *args: Any) -> None:
    """Fail every job of ``jobs`` still waiting with a fresh ``make(*args)``."""
    for job in jobs:
        if not job.future.done():
            job.future.set_exception(make(*args))


def _check(block: ResponseBlock, function: str) -> bytes:
    """The data of ``block``; :class:`CncError` for its EW code."""
    if block.ew:
        raise CncError.from_ew(block.ew, function)
    return block.data


def _decode(request: NativeRequest, block: ResponseBlock, function: str, max_axes: int) -> Any:
    data = _check(block, function)
    # by the request's identity (the entry holds it), as _part_of
    key = (id(request), max_axes, data)
    known: tuple[NativeRequest, Any] | None = _ANSWERS.get(key)
    if known is not None and known[0] is request:
        return known[1]
    try:
        value = request.decode_answer(data, max_axes)
    except (ProtocolError, ValueError, struct.error) as exc:
        raise PayloadError(
            f"{function}: answer to 0x{request.COMMAND:X} does not decode: {exc}"
        ) from None
    _ANSWERS.put(key, (request, value))
    return value


def _check_dynamic_axis(axis: int) -> None:
    """:class:`ValueError` unless ``axis`` is -1 (every axis) or 1..0x7FFF, as
    ``cnc_rddynamic2`` takes it."""
    if axis != -1 and not 1 <= axis <= 0x7FFF:
        raise ValueError(f"axis must be 1..n or -1 for every axis, got {axis}")


def _text(raw: bytes | str) -> str:
    if isinstance(raw, str):
        return raw.rstrip("\x00")
    return raw.split(b"\x00", 1)[0].decode("latin-1")


def _name(entry: bytes) -> str:
    """The axis name of a 4-byte name entry (its first character; the suffix only tells
    which position a display shows)."""
    return entry[:1].replace(b"\x00", b"").decode("latin-1").strip()


class NativeClient(_Lifecycle):
    """An asyncio client of FANUC's FOCAS/2 Ethernet protocol (port 8193 on a real control).

    It has the methods of :class:`~focas_net.client.FocasClient` that FOCAS/2 carries, with
    the same results, exceptions, per-call ``timeout=`` and :class:`ReconnectPolicy`, plus
    :meth:`read_dynamic`, :meth:`read_timer`, :meth:`read_spindle_loads`,
    :meth:`read_servo_meters`, :meth:`read_cnc_id`, :meth:`read_sequence_number`,
    :meth:`read_program_name`, :meth:`read_alarm_status` and :meth:`read_param_type` (in
    place of ``read_param_attributes``). Concurrent calls are gathered
    into frames of at most ``max_blocks`` blocks (see the module docstring).
    """

    _logger = logger

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
        if timeout is not None and timeout <= 0:
            raise ValueError(f"timeout must be positive, got {timeout}")
        if not 1 <= max_blocks <= 0xFFFF:
            raise ValueError(f"max_blocks must be within 1..65535, got {max_blocks}")
        super().__init__(host, port, reconnect, on_state_change)
        self.timeout = timeout
        self.max_blocks = max_blocks
        self._handle: _Handle | None = None
        self._queue: deque[_Job] = deque()
        self._kick_soon = False
        #: The task whose call was alone in the frame last answered: that answer woke no
        #: other caller of this client to gather with, so the task's next call is sent at
        #: once (with whatever else is queued) rather than at the end of the loop turn
        #: (``_NOBODY``: the lone call had no task of its own, see ``_start_job``).
        self._direct: asyncio.Task[Any] | _Nobody | None = None
        #: Jobs queued for the coming kick whose watch that kick decides (see ``_send``).
        self._unarmed: list[_Job] = []
        #: One timer for the deadlines of calls queued, or in flight in a frame whose own
        #: deadline is later (see ``_watch``), and when it fires (inf: not set).
        self._watch_timer: asyncio.TimerHandle | None = None
        self._watch_at = _INF
        self._param_widths: dict[int, int] = {}
        #: The type word (0 bit .. 4 real) of each parameter read or written.
        self._param_types: dict[int, int] = {}
        self._pmc_locks: KeyedLocks[tuple[int, int]] = KeyedLocks()
        self._param_locks: KeyedLocks[tuple[int, int]] = KeyedLocks()
        #: Frames sent and blocks carried since the client was made (for batching checks).
        self.frames_sent = 0
        self.blocks_sent = 0

    # -- lifecycle -----------------------------------------------------------------------
    @property
    def command_set(self) -> CommandSet | None:
        """The command set of the open handle (16i or 30i class), None when not connected."""
        return None if self._handle is None else self._handle.command_set

    @property
    def max_axes(self) -> int | None:
        """The CNC's max axes from the open answer, None when not connected."""
        return None if self._handle is None else self._handle.max_axes

    async def connect(self) -> None:
        """Open the A/B pair and run the connect-time requests (``cnc_allclibhndl3``).

        Raises :class:`FocasConnectionError` (or :class:`FocasTimeoutError`) when the CNC
        cannot be reached or its open answer is refused; the first connect is not retried.
        """
        if self._state is ClientState.CLOSED:
            raise FocasConnectionError("client is closed")
        if self._handle is not None and not self._handle.closed:
            return
        self._bind_loop()
        if self._ready is None:
            self._ready = asyncio.Event()
        handle = await _open_handle(self.host, self.port, self._deadline(None))
        if self.state is ClientState.CLOSED:  # closed while connecting
            handle.abort()
            raise FocasConnectionError("client is closed")
        if self._handle is not None and not self._handle.closed:
            handle.abort()
            return
        self._install(handle)

    async def aclose(self) -> None:
        """Close the handle (close exchange on A, then B); pending calls fail with
        :class:`FocasConnectionError`."""
        self._set_state(ClientState.CLOSED)
        task, self._reconnect_task = self._reconnect_task, None
        if task is not None and not task.done():
            task.cancel()
            await asyncio.wait([task])
        handle, self._handle = self._handle, None
        self._direct = None
        if handle is not None:
            _fail(handle.detach(), lambda: FocasConnectionError("client is closed"))
        queued = list(self._queue)
        self._queue.clear()
        _fail(queued, lambda: FocasConnectionError("client is closed"))
        if self._watch_timer is not None:
            self._watch_timer.cancel()
            self._watch_timer = None
            self._watch_at = _INF
        if self._ready is not None:
            self._ready.set()
        if handle is not None:
            await handle.close(_CLOSE_GRACE)

    def _install(self, handle: _Handle) -> None:
        task = self._reconnect_task
        if task is not None and not task.done() and task is not asyncio.current_task():
            task.cancel()
        loop = self._loop or asyncio.get_running_loop()
        self._handle = handle
        self._up_since = loop.time()
        self._set_state(ClientState.CONNECTED)
        assert self._ready is not None
        self._ready.set()
        # (B ended while connecting: the end is told at once, and the handle lost)
        handle.b.start(partial(self._on_data, handle), partial(self._on_end, handle))
        self._kick(handle)

    def _on_lost(self, handle: _Handle, exc: BaseException | None) -> None:
        if handle is not self._handle:
            return
        self._handle = None
        self._direct = None
        handle.abort()
        if self._state is ClientState.CLOSED:
            return
        if self._policy is None:
            logger.warning("connection to %s:%s lost: %s", self.host, self.port, exc or "closed")
            queued = list(self._queue)
            self._queue.clear()
            _fail(
                queued,
                lambda: FocasConnectionError(
                    f"connection to {self.host}:{self.port} lost before the request was sent"
                ),
            )
            self._set_state(ClientState.DISCONNECTED)
            return
        self._reconnecting(exc)

    async def _reconnect_attempt(self, attempt: int) -> bool:
        try:
            handle = await _open_handle(self.host, self.port, self._deadline(None))
        except Exception as exc:  # refused, unreachable, or an answer that does not decode
            logger.debug("reconnect attempt %d to %s:%s: %s", attempt, self.host, self.port, exc)
            return False
        self._install(handle)
        # (lost again while installed, for bytes nobody asked for or the end of B: the next
        # attempt follows)
        return self._handle is handle

    def _linked(self) -> bool:
        return self._handle is not None

    def _reconnect_ended(self) -> None:
        if self._state is ClientState.DISCONNECTED:
            queued = list(self._queue)
            self._queue.clear()
            _fail(
                queued,
                lambda: FocasConnectionError(f"could not reconnect to {self.host}:{self.port}"),
            )

    # -- the request path ----------------------------------------------------------------
    def _deadline(self, timeout: float | None) -> float | None:
        if timeout is None:
            timeout = self.timeout  # checked when the client was made
            if timeout is None:
                return None
        elif timeout <= 0:
            raise ValueError(f"timeout must be positive, got {timeout}")
        clock = self._clock
        if clock is None:
            clock = asyncio.get_running_loop().time
        return clock() + timeout

    async def _live(self, deadline: float | None) -> _Handle:
        """The open handle, waiting (until ``deadline``) while reconnecting."""
        while True:
            handle = self._handle
            if handle is not None and not handle.closed:
                return handle
            if self._state is ClientState.CLOSED:
                raise FocasConnectionError("client is closed")
            if self._state is not ClientState.RECONNECTING or self._ready is None:
                raise FocasConnectionError(f"not connected to {self.host}:{self.port}")
            try:
                async with asyncio.timeout_at(deadline):
                    await self._ready.wait()
            except TimeoutError:
                raise FocasConnectionError(
                    f"still reconnecting to {self.host}:{self.port} when the call timed out"
                ) from None

    def _send(
        self, requests: tuple[NativeRequest, ...], command_set: CommandSet, deadline: float | None
    ) -> asyncio.Future[tuple[ResponseBlock, ...]]:
        """Queue one frame's worth of blocks of one call; the future its caller awaits for
        the answer blocks. A plain method, so that a call is one coroutine (the caller's):
        the future fails with the call's own error (a timeout set by the watch or the frame
        timer, a lost connection, an error answer), and a caller that gives up (cancelled)
        cancels it, which drops a call still queued and ignores the blocks of one sent."""
        handle = self._handle
        if handle is None and self._state is not ClientState.RECONNECTING:
            # lost between two frames of one call, with no reconnect to wait for
            if self._state is ClientState.CLOSED:
                raise FocasConnectionError("client is closed")
            raise FocasConnectionError(f"not connected to {self.host}:{self.port}")
        loop = self._loop or asyncio.get_running_loop()
        future: asyncio.Future[tuple[ResponseBlock, ...]] = loop.create_future()
        # _Job(requests, command_set, deadline, future, task) without the class call, a good
        # part of a call's cost (every slot is set on each path: tested)
        job: _Job = _new(_Job)
        job.requests = requests
        job.command_set = command_set
        job.deadline = deadline
        job.future = future
        job.part = _NO_PART
        job.unarmed = False
        if handle is not None and handle.inflight is not None:
            # Queued behind the frame in flight (calls pipelined): the client's one watch
            # timer covers it (it is armed already for an earlier deadline in the usual case).
            # No task noted: one that ends up alone in a frame sends its next call after the
            # answer's callbacks, like the calls of many clients read from one task.
            job.task = None
            self._queue.append(job)
            if deadline is not None and deadline < self._watch_at:
                self._watch(deadline)
            return future
        job.task = task = _current_task(loop)
        if (
            task is self._direct
            and task is not None
            and handle is not None
            and not self._queue
            and not handle.closed
            and command_set is handle.command_set
        ):
            # The caller just answered calls again with nothing else waiting (a sequential
            # caller): its frame leaves now, its deadline the frame's (_send_one, inline).
            self._direct = None
            known: tuple[tuple[NativeRequest, ...], _Part] | None = _PARTS.get(
                (id(requests), handle.max_axes)
            )
            if known is not None and known[0] is requests:
                part = known[1]  # (the usual case of _part_of, inline)
            else:
                part = _part_of(requests, handle.max_axes)
            job.part = part
            handle.b.write(part[4])
            self.frames_sent += 1
            self.blocks_sent += part[3]
            handle.inflight = [job]
            handle.inflight_blocks = part[3]
            handle.deadline = deadline
            if deadline is not None and (handle.timer is None or handle.timer_at > deadline):
                self._arm_frame(handle, deadline)
        else:
            self._queue.append(job)
            self._queue_job(job, handle, loop)
        return future

    def _expired(self, job: _Job) -> FocasError:
        """What a call whose job's deadline passed raises."""
        if not job.sent and self._state is ClientState.RECONNECTING:
            return FocasConnectionError(
                f"still reconnecting to {self.host}:{self.port} when the call timed out"
            )
        return FocasTimeoutError(
            f"no answer from {self.host}:{self.port} within the call's timeout"
            + ("" if job.sent else " (the request was never sent)")
        )

    def _start_job(
        self, handle: _Handle, requests: tuple[NativeRequest, ...], deadline: float | None
    ) -> _Job:
        """:meth:`_send` for a caller awaiting many clients' answers in one task
        (:mod:`focas_net.client.many`): the frame of ``requests`` (of ``handle``'s command
        set) sent now when ``handle`` is idle, whoever called last, else queued for the next
        frame; the job, whose future is what :meth:`_send` returns. The caller cancels the
        future if it gives up first."""
        loop = self._loop or asyncio.get_running_loop()
        job = _Job(requests, handle.command_set, deadline, loop.create_future(), None)
        if handle.inflight is None and not self._queue:
            job.part = _part_of(requests, handle.max_axes)
            self._send_one(handle, job)
        else:
            self._queue.append(job)
            self._queue_job(job, handle, loop)
        return job

    def _queue_job(
        self, job: _Job, handle: _Handle | None, loop: asyncio.AbstractEventLoop
    ) -> None:
        """Have ``job``, queued, sent: now (its caller is the one just answered), at the end
        of this loop turn, or after the frame in flight."""
        deadline = job.deadline
        if handle is not None and handle.inflight is None:
            if deadline is not None:
                # The kick decides: a job whose deadline is its frame's needs no timer of its
                # own (the frame's fails it at that deadline); any other gets one there.
                job.unarmed = True
                self._unarmed.append(job)
            if job.task is self._direct and job.task is not None:
                self._direct = None
                self._kick_later(handle)
            elif not self._kick_soon:
                # at the end of this loop turn, so that calls made together share the frame
                self._kick_soon = True
                loop.call_soon(self._kick_later, handle)
        elif deadline is not None and deadline < self._watch_at:
            # Queued behind a frame in flight: the client's one watch timer covers it (it
            # is armed already for an earlier deadline in the usual case).
            self._watch(deadline)

    async def _one(
        self, build: Callable[[CommandSet], LibraryCall], deadline: float | None
    ) -> tuple[_Handle, LibraryCall, tuple[ResponseBlock, ...]]:
        """A one-frame library call: its handle, the call and its answer blocks."""
        handle = self._handle
        if handle is None or handle.closed:
            handle = await self._live(deadline)
        library_call = build(handle.command_set)
        (frame,) = library_call.frames
        return handle, library_call, await self._send(frame, handle.command_set, deadline)

    def _kick_later(self, handle: _Handle) -> None:
        self._kick_soon = False
        self._kick(handle)
        unarmed = self._unarmed
        if unarmed:
            # left in the queue (the frame was full, or no frame could be sent): watched
            for job in unarmed:
                if job.unarmed:
                    job.unarmed = False
                    if not job.future.done() and job.deadline is not None:
                        self._watch(job.deadline)
            unarmed.clear()

    def _kick(self, handle: _Handle) -> None:
        """Send the next frame of queued jobs on ``handle`` unless one is in flight: the jobs
        at the queue's head that one frame carries (at least one), within the block limit and
        the answer and request sizes the open answer allows. Jobs of one call in a row share
        their part, so the room for them is reckoned once a run, not once a job."""
        if handle.inflight is not None or handle is not self._handle or handle.closed:
            return
        queue = self._queue
        popleft = queue.popleft
        command_set = handle.command_set
        max_axes = handle.max_axes
        blocks_left = self.max_blocks
        # answer and request bodies: the block count (2 bytes), then the blocks
        answer_left = send_left = handle.limit - 2
        batch: list[_Job] = []
        append = batch.append
        parts: list[bytes] = []
        # the run of jobs of one call: its requests, its part, how many of it still fit and
        # how many the frame takes
        last: tuple[NativeRequest, ...] | None = None
        part = _NO_PART
        room = taken = 0
        latest: float | None = 0.0
        while queue:
            job = popleft()
            if job.future.done():
                continue
            requests = job.requests
            if requests is not last:
                # (requests are built for one command set: a run shares its job's)
                if job.command_set is not command_set:
                    job.future.set_exception(
                        FocasConnectionError(
                            "the CNC's command set changed on reconnect; call again"
                        )
                    )
                    continue
                if taken:
                    parts.append(part[0] * taken if taken > 1 else part[0])
                    blocks_left -= taken * part[3]
                    answer_left -= taken * part[1]
                    send_left -= taken * part[2]
                part = _part_of(requests, max_axes)
                last = requests
                room = min(blocks_left // part[3], answer_left // part[1], send_left // part[2])
                taken = 0
                if room <= 0:
                    if batch:
                        queue.appendleft(job)
                        break
                    room = 1  # alone in its frame, whatever its size
            elif taken == room:
                queue.appendleft(job)
                break
            taken += 1
            job.part = part
            append(job)
            deadline = job.deadline
            if deadline is None:
                latest = None
            elif latest is not None and deadline > latest:
                latest = deadline
        if not batch:
            return
        if len(batch) == 1:
            self._send_one(handle, batch[0])
            return
        if taken:  # (none when the frame ended at a new run that did not fit)
            parts.append(part[0] * taken if taken > 1 else part[0])
            blocks_left -= taken * part[3]
        blocks = self.max_blocks - blocks_left
        handle.b.write(_frame_of(b"".join(parts), blocks))
        self.frames_sent += 1
        self.blocks_sent += blocks
        handle.inflight = batch
        handle.inflight_blocks = blocks
        handle.deadline = latest
        if latest is not None and (handle.timer is None or handle.timer_at > latest):
            self._arm_frame(handle, latest)
        if self._unarmed:
            for job in batch:
                if job.unarmed:
                    # Its deadline is the frame's: the frame's timer fails it then (and ends
                    # the connection, as it would for any frame unanswered at its latest
                    # deadline). An earlier one is watched.
                    job.unarmed = False
                    if latest is None or job.deadline != latest:
                        assert job.deadline is not None
                        self._watch(job.deadline)

    def _send_one(self, handle: _Handle, job: _Job) -> None:
        """Send the frame of ``job`` alone (with its part) on ``handle``, idle: the frame is
        the one its part keeps, its deadline the frame's."""
        part = job.part
        handle.b.write(part[4])
        self.frames_sent += 1
        self.blocks_sent += part[3]
        handle.inflight = [job]
        handle.inflight_blocks = part[3]
        deadline = handle.deadline = job.deadline
        if deadline is not None and (handle.timer is None or handle.timer_at > deadline):
            self._arm_frame(handle, deadline)
        if job.unarmed:
            job.unarmed = False  # the frame's timer fails it at its deadline

    def _arm_frame(self, handle: _Handle, deadline: float) -> None:
        """Set ``handle``'s frame timer for ``deadline``, earlier than it is set for (or not
        set). One timer watches the frames in flight one after another: one set for an
        earlier frame's deadline, which is no later than the next one's, is moved on when it
        fires (so sequential calls do not set a timer each)."""
        if handle.timer is not None:
            handle.timer.cancel()
        loop = self._loop or asyncio.get_running_loop()
        handle.timer = loop.call_at(deadline, self._frame_timer, handle)
        handle.timer_at = deadline

    def _on_data(self, handle: _Handle, data: bytes) -> None:
        """B's bytes: complete the frame in flight with its answer, then send the next one.
        Bytes while no frame is in flight are what nobody asked for: the connection ends."""
        rx = handle.rx
        batch = handle.inflight
        if not rx and batch is not None:
            if len(batch) == 1 and not self._queue:
                # A lone call answered with nothing queued (a sequential caller): bytes that
                # are a whole answer that came before for as many blocks (only whole, checked
                # answers are kept) are its answer, and their blocks its blocks.
                blocks = _FRAMES.get((data, handle.inflight_blocks))
                if blocks is not None:
                    handle.inflight = None
                    job = batch[0]
                    task = job.task
                    self._direct = _NOBODY if task is None else task
                    future = job.future
                    if not future.done():
                        future.set_result(blocks)
                    return
            if len(data) >= NATIVE_HEADER_SIZE:
                # the usual case: the whole answer in one read, nothing held
                magic, _, _, length = NATIVE_HEADER.unpack_from(data)
                if magic == _MAGIC and len(data) == NATIVE_HEADER_SIZE + length:
                    self._complete(handle, data, send_next=True)
                    # (a lone call answered with nothing queued: its caller sends its next
                    # call itself, so there is nothing to kick)
                    if handle is self._handle and (self._queue or self._direct is None):
                        self._next(handle)
                    return
        rx += data
        while len(rx) >= NATIVE_HEADER_SIZE:
            magic, _, _, length = NATIVE_HEADER.unpack_from(rx)
            if magic != _MAGIC:
                self._lose(handle, _Lost("answer does not start with A0 A0 A0 A0"))
                return
            end = NATIVE_HEADER_SIZE + length
            if len(rx) < end:
                break
            raw = bytes(rx[:end])
            del rx[:end]
            if handle.inflight is None:
                self._lose(handle, _Lost("unsolicited data on B"))
                return
            self._complete(handle, raw)
            if handle is not self._handle:
                return
        if rx and handle.inflight is None:
            self._lose(handle, _Lost("unsolicited data on B"))
            return
        self._next(handle)

    def _next(self, handle: _Handle) -> None:
        """After an answer: send the next frame now if calls wait, else once the callers the
        answer woke have run."""
        if self._queue or handle.inflight is not None:
            self._kick(handle)
        elif self._direct is None and not self._kick_soon:
            # Nothing queued: the callers just answered will likely call again in the turn
            # their futures wake them in. Sending after them (rather than from a callback each
            # new call schedules) gathers those calls into one frame and saves a loop turn.
            self._kick_soon = True
            loop = self._loop or asyncio.get_running_loop()
            loop.call_soon(self._kick_later, handle)

    def _complete(self, handle: _Handle, raw: bytes, send_next: bool = False) -> None:
        """Hand each job of the frame in flight (``handle.inflight``, not None) its answer
        blocks from the whole answer frame ``raw``; with ``send_next`` (the answer was all the
        bytes read), send the next frame of queued calls first: it leaves before the results
        are handed out (the callers run after this callback either way)."""
        batch = handle.inflight
        assert batch is not None
        count = handle.inflight_blocks
        blocks: tuple[ResponseBlock, ...] | None = _FRAMES.get((raw, count))
        if blocks is None:
            try:
                blocks = handle.keep_answer(raw, count)  # an answer not seen before
            except CncError as exc:
                handle.inflight = None
                _fail(batch, CncError.from_ew, exc.ew, exc.detail)
                return
            except _Lost as exc:
                self._lose(handle, exc)
                return
        handle.inflight = None
        if len(batch) == 1:
            # a lone call: its blocks are the whole answer's
            job = batch[0]
            # (a job of no task, of a caller reading many clients or queued behind a frame,
            # sends nothing more here)
            self._direct = _NOBODY if job.task is None else job.task
            if send_next and self._queue:
                self._kick(handle)
            future = job.future
            if not future.done():
                future.set_result(blocks)
            return
        self._direct = None
        if send_next and self._queue:
            self._kick(handle)
        if count == len(batch):
            # every job one block: each its own block alone, the very tuples of the last time
            # this answer came (so a result remembered for them is found by identity)
            singles = _SINGLES.get(id(blocks))
            if singles is None or singles[0] is not blocks:
                singles = (blocks, tuple([(block,) for block in blocks]))
                _SINGLES.put(id(blocks), singles)
            for job, one in zip(batch, singles[1], strict=True):
                future = job.future
                if not future.done():
                    future.set_result(one)
            return
        pos = 0
        for job in batch:
            end = pos + job.part[3]
            future = job.future
            if not future.done():
                future.set_result(blocks[pos:end])
            pos = end

    def _watch(self, deadline: float) -> None:
        """Have the watch timer fire no later than ``deadline``."""
        if deadline < self._watch_at:
            if self._watch_timer is not None:
                self._watch_timer.cancel()
            loop = self._loop or asyncio.get_running_loop()
            self._watch_timer = loop.call_at(deadline, self._watch_fired)
            self._watch_at = deadline

    def _watch_fired(self) -> None:
        """Fail every call queued, or in flight before its frame's deadline, whose own
        deadline has passed; arm again for the earliest deadline left. (Calls answered since
        the timer was armed are simply gone: the timer fires about once a timeout while
        calls flow, and looks at the calls waiting then, no others.)"""
        self._watch_timer = None
        self._watch_at = _INF
        loop = self._loop or asyncio.get_running_loop()
        now = loop.time()
        nxt = _INF
        handle = self._handle
        waiting: list[_Job] = list(self._queue)
        frame_deadline = _INF
        if handle is not None and handle.inflight is not None:
            waiting += handle.inflight
            if handle.deadline is not None:
                frame_deadline = handle.deadline
        for job in waiting:
            deadline = job.deadline
            if deadline is None or job.future.done():
                continue
            if job.sent and deadline >= frame_deadline:
                continue  # its frame's timer fails it (and ends the connection)
            if deadline <= now:
                job.future.set_exception(self._expired(job))
            elif deadline < nxt:
                nxt = deadline
        if nxt != _INF:
            self._watch(nxt)

    def _frame_timer(self, handle: _Handle) -> None:
        """The frame timer fired: nothing to do with no frame in flight (or one without a
        deadline); moved on to the deadline of the frame in flight if that is later; else
        that frame has expired."""
        handle.timer = None
        deadline = handle.deadline
        if handle.inflight is None or deadline is None:
            return
        if deadline > handle.timer_at:
            self._arm_frame(handle, deadline)
            return
        self._frame_expired(handle)

    def _frame_expired(self, handle: _Handle) -> None:
        """The latest deadline of the frame in flight passed without its answer: no later
        answer could be told from the next frame's, so the connection is closed."""
        batch, handle.inflight = handle.inflight or [], None
        _fail(
            batch,
            lambda: FocasTimeoutError(
                f"no answer from {self.host}:{self.port}; the connection is closed"
            ),
        )
        self._lose(handle, _Lost("no answer within the timeout"))

    def _on_end(self, handle: _Handle, exc: Exception | None) -> None:
        why = f"connection closed ({exc!r})" if exc is not None else "connection closed by the CNC"
        self._lose(handle, _Lost(why))

    def _lose(self, handle: _Handle, exc: _Lost) -> None:
        """``handle`` can carry no further frame: its frame in flight fails, and the client
        reconnects (or not) as its policy says."""
        lost = f"connection to {self.host}:{self.port} lost after the request was sent ({exc})"
        _fail(handle.detach(), FocasConnectionError, lost)
        self._on_lost(handle, exc)

    # -- status and identity -------------------------------------------------------------
    async def read_status(self, *, timeout: float | None = None) -> StatusInfo:
        """``cnc_statinfo``: the ODBST status (0x19; hdck 0xE1 and tmmode 0x98 read 0 when
        the CNC refuses them, as the library reads them)."""
        clock = self._clock
        if timeout is None and clock is not None and (wait := self.timeout) is not None:
            deadline: float | None = clock() + wait  # (the usual case of _deadline, inline)
        else:
            deadline = self._deadline(timeout)
        handle = self._handle
        if handle is None or handle.closed:
            handle = await self._live(deadline)
        blocks = await self._send(handle.status_call.frames[0], handle.command_set, deadline)
        known: tuple[Any, Any, StatusInfo] | None = _RESULTS.get(id(blocks[0]))
        if known is not None and known[0] is blocks and known[1] is handle.status_key:
            return known[2]  # (the usual case of _known_result, inline)
        return self._status_of(handle, blocks)

    def _start_status(self, deadline: float | None) -> tuple[_Handle, _Job] | None:
        """:meth:`read_status`'s frame started by :meth:`_start_job` (None: no open
        handle); its blocks make the status by :meth:`_status_of`."""
        handle = self._handle
        if handle is None or handle.closed:
            return None
        return handle, self._start_job(handle, handle.status_call.frames[0], deadline)

    @staticmethod
    def _status_of(handle: _Handle, blocks: tuple[ResponseBlock, ...]) -> StatusInfo:
        """The status of ``cnc_statinfo``'s answer ``blocks`` on ``handle``."""
        call = handle.status_call
        extra = handle.status_key
        known: StatusInfo | None = _known_result(blocks, extra)
        if known is not None:
            return known
        st, hd, tm = blocks
        stat: StatInfo = _decode(call.frames[0][0], st, "cnc_statinfo", handle.max_axes)
        hdck = 0 if hd.ew else _decode(call.frames[0][1], hd, "cnc_statinfo", 0).hdck
        tmmode = 0 if tm.ew else _decode(call.frames[0][2], tm, "cnc_statinfo", 0).tmmode
        status = StatusInfo(
            hdck, tmmode, stat.aut, stat.run, stat.motion, stat.mstb, stat.emergency,
            stat.alarm, stat.edit,
        )  # fmt: skip
        _remember_result(blocks, extra, status)
        return status

    async def read_sysinfo(self, *, timeout: float | None = None) -> SysInfo:
        """``cnc_sysinfo``: ODBSYS as the CNC answered it while connecting (nothing is sent,
        like FANUC's library)."""
        handle = await self._live(self._deadline(timeout))
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
        handle, call, (block,) = await self._one(calls.cnc_rdcncid, self._deadline(timeout))
        cid: CncId = _decode(call.frames[0][0], block, "cnc_rdcncid", handle.max_axes)
        return (cid.id1, cid.id2, cid.id3, cid.id4)

    async def read_timer(self, timer_type: int, *, timeout: float | None = None) -> TimerValue:
        """``cnc_rdtimer``: a timer (0 power-on, 1 operating, 2 cutting, 3 cycle, 4 free) as
        minutes and milliseconds."""
        handle, call, (block,) = await self._one(
            lambda cs: calls.cnc_rdtimer(cs, timer_type), self._deadline(timeout)
        )
        value: TimerValue = _decode(call.frames[0][0], block, "cnc_rdtimer", handle.max_axes)
        return value

    # -- program, feed, spindle ----------------------------------------------------------
    async def read_program_numbers(self, *, timeout: float | None = None) -> ProgramNumbers:
        """``cnc_rdprgnumo8``: the running and the main program numbers (0 = none)."""
        _, call, (block,) = await self._one(calls.cnc_rdprgnumo8, self._deadline(timeout))
        value: NativeProgramNumbers = _decode(call.frames[0][0], block, "cnc_rdprgnumo8", 0)
        return ProgramNumbers(value.running, value.main)

    async def read_program_name(self, *, timeout: float | None = None) -> tuple[int, str]:
        """``cnc_exeprgname``: the O number and the name of the executing program."""
        _, call, (block,) = await self._one(calls.cnc_exeprgname, self._deadline(timeout))
        value: ExecutingProgram = _decode(call.frames[0][0], block, "cnc_exeprgname", 0)
        return value.o_num, _text(value.name)

    async def read_sequence_number(self, *, timeout: float | None = None) -> int:
        """``cnc_rdseqnum``: the sequence number being executed."""
        _, call, (block,) = await self._one(calls.cnc_rdseqnum, self._deadline(timeout))
        value: SequenceNumber = _decode(call.frames[0][0], block, "cnc_rdseqnum", 0)
        return value.number

    async def read_feed(self, *, timeout: float | None = None) -> int:
        """``cnc_actf``: the actual feed rate."""
        _, call, (block,) = await self._one(calls.cnc_actf, self._deadline(timeout))
        value: ScaledValues = _decode(call.frames[0][0], block, "cnc_actf", 0)
        return value.values[0].mantissa if value.values else 0

    async def read_spindle_speed(self, *, timeout: float | None = None) -> int:
        """``cnc_acts``: the actual spindle speed."""
        _, call, (block,) = await self._one(calls.cnc_acts, self._deadline(timeout))
        value: ScaledValues = _decode(call.frames[0][0], block, "cnc_acts", 0)
        return value.values[0].mantissa if value.values else 0

    async def read_spindle_loads(
        self, spindle: int = -1, *, timeout: float | None = None
    ) -> tuple[int, ...]:
        """``cnc_rdspload``: the load of every spindle (``spindle=-1``) or of one (1..n)."""
        if spindle != -1 and not 1 <= spindle <= 0x7FFF:
            raise ValueError(f"spindle must be 1..n or -1 for every spindle, got {spindle}")
        handle, call, blocks = await self._one(
            lambda cs: calls.cnc_rdspload(cs, spindle), self._deadline(timeout)
        )
        frame = call.frames[0]
        for request, block in zip(frame, blocks, strict=True):
            _check(block, "cnc_rdspload")
            if request.COMMAND == NativeCommand.AXIS_COUNT:
                count = _decode(request, block, "cnc_rdspload", 0).count
                if count == 0:
                    raise CncError.from_ew(EW.NOOPT, "cnc_rdspload: no spindle")
        index = 0 if handle.command_set is CommandSet.FS16I else 1
        loads: ScaledValues = _decode(frame[index], blocks[index], "cnc_rdspload", 0)
        limit = handle.spindles if spindle == -1 else 1
        return tuple(
            int.from_bytes((v.mantissa & 0xFFFF).to_bytes(2, "big"), "big", signed=True)
            for v in loads.values[: max(limit, 1)]
        )

    async def read_servo_meters(self, *, timeout: float | None = None) -> tuple[ServoLoad, ...]:
        """``cnc_rdsvmeter``: the servo load meter of every axis, with its name."""
        handle, call, blocks = await self._one(calls.cnc_rdsvmeter, self._deadline(timeout))
        names: AxisNames | None = None
        loads: ScaledValues | None = None
        for request, block in zip(call.frames[0], blocks, strict=True):
            value = _decode(request, block, "cnc_rdsvmeter", handle.max_axes)
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
        handle, call, (block,) = await self._one(calls.cnc_rdaxisname, self._deadline(timeout))
        names: AxisNames = _decode(call.frames[0][0], block, "cnc_rdaxisname", handle.max_axes)
        return tuple(_name(n.encode()) for n in names.records[: handle.axes])

    async def read_dynamic(self, axis: int = -1, *, timeout: float | None = None) -> DynamicData:
        """``cnc_rddynamic2``: alarm bits, program numbers, sequence number, feed, spindle
        speed and the four positions of every axis (``axis=-1``) or of one (1..n), in one
        frame. Needs the CNC's FOCAS option bit 0, as in FANUC's library (EW_NOOPT)."""
        _check_dynamic_axis(axis)
        deadline = self._deadline(timeout)
        handle = await self._live(deadline)
        call = self._dynamic_call(handle, axis)
        blocks = await self._send(call.frames[0], handle.command_set, deadline)
        return self._dynamic_of(handle, call, axis, blocks)

    def _start_dynamic(
        self, axis: int, deadline: float | None
    ) -> tuple[_Handle, LibraryCall, _Job] | None:
        """:meth:`read_dynamic`'s frame started by :meth:`_start_job` (None: no open handle;
        ``axis`` checked by :func:`_check_dynamic_axis`); its blocks make the result by
        :meth:`_dynamic_of`. Raises :class:`CncError` as :meth:`read_dynamic` does, nothing
        sent."""
        handle = self._handle
        if handle is None or handle.closed:
            return None
        call = self._dynamic_call(handle, axis)
        return handle, call, self._start_job(handle, call.frames[0], deadline)

    @staticmethod
    def _dynamic_call(handle: _Handle, axis: int) -> LibraryCall:
        """The ``cnc_rddynamic2`` call of ``axis`` on ``handle``; :class:`CncError` when the
        CNC lacks the option or the axis."""
        if not handle.option_bits & 1:
            raise CncError.from_ew(EW.NOOPT, "cnc_rddynamic2: the CNC lacks FOCAS option bit 0")
        if axis > handle.axes:
            raise CncError.from_ew(EW.ATTRIB, f"cnc_rddynamic2: axis {axis} of {handle.axes}")
        return _memo_call(handle.dynamic_calls, axis, calls.cnc_rddynamic2, handle.command_set)

    @staticmethod
    def _dynamic_of(
        handle: _Handle, call: LibraryCall, axis: int, blocks: tuple[ResponseBlock, ...]
    ) -> DynamicData:
        """The result of the ``cnc_rddynamic2`` ``call`` of ``axis`` from its answer
        ``blocks`` on ``handle``."""
        frame = call.frames[0]
        count = handle.axes if axis == -1 else 1
        extra = (call, handle.max_axes, count)
        known: DynamicData | None = _known_result(blocks, extra)
        if known is not None:
            return known
        values = [
            _decode(r, b, "cnc_rddynamic2", handle.max_axes)
            for r, b in zip(frame, blocks, strict=True)
        ]
        alarm: AlarmStatus = values[0]
        prg: NativeProgramNumbers = values[1]
        seq: SequenceNumber = values[2]

        def mantissas(v: ScaledValues) -> tuple[int, ...]:
            return tuple(x.mantissa for x in v.values[:count])

        feed: ScaledValues = values[3]
        speed: ScaledValues = values[4]
        dynamic = DynamicData(
            alarm.alarm & 0xFFFF, prg.running, prg.main, seq.number,
            feed.values[0].mantissa if feed.values else 0,
            speed.values[0].mantissa if speed.values else 0,
            mantissas(values[5]), mantissas(values[6]), mantissas(values[7]), mantissas(values[8]),
        )  # fmt: skip
        _remember_result(blocks, extra, dynamic)
        return dynamic

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
        if axis is not None and not 1 <= axis <= 0x7FFF:
            raise ValueError(f"axis must be 1..n (None for every axis), got {axis}")
        deadline = self._deadline(timeout)
        handle = await self._live(deadline)
        if axis is not None and axis > handle.axes:
            raise CncError.from_ew(EW.ATTRIB, f"cnc_rdposition: axis {axis} of {handle.axes}")
        call = calls.cnc_rdposition(handle.command_set)
        frame = call.frames[0]
        blocks = await self._send(frame, handle.command_set, deadline)
        names: PositionAxisNames | None = None
        positions: ScaledValues | None = None
        for request, block in zip(frame, blocks, strict=True):
            command = request.COMMAND
            if command == NativeCommand.AXIS_NAME:
                names = _decode(request, block, "cnc_rdposition", handle.max_axes)
            elif (
                command == NativeCommand.POSITION and getattr(request, "kind", None) == which.value
            ):
                positions = _decode(request, block, "cnc_rdposition", handle.max_axes)
            elif command in (
                NativeCommand.POSITION,
                NativeCommand.AXIS_COUNT,
                NativeCommand.STATINFO,
            ):
                _check(block, "cnc_rdposition")
        assert names is not None and positions is not None
        count = min(handle.axes, len(positions.values), len(names.records))
        picked = range(count) if axis is None else [axis - 1]
        values: dict[str, Decimal] = {}
        increments: dict[str, int] = {}
        decimals = 0
        for i in picked:
            entry = names.records[i]
            raw = (
                entry.machine
                if which is PositionKind.MACHINE
                else (entry.relative if which is PositionKind.RELATIVE else entry.absolute)
            )
            record = positions.values[i]
            decimals = record.decimals
            name = _name(raw) or f"axis{i + 1}"
            values[name] = Decimal(record.mantissa).scaleb(-record.decimals)
            increments[name] = record.mantissa
        return Positions(which, decimals, values, increments)

    # -- parameters and diagnostics ------------------------------------------------------
    async def _read_item(
        self, number: int, axis: int, deadline: float | None, *, diagnostic: bool
    ) -> ParamValue:
        function = "cnc_diagnoss" if diagnostic else "cnc_rdparam"
        if not 0 <= number <= 0x7FFFFFFF:
            raise ValueError(f"{function}: number {number} is negative")
        if axis < 0:
            raise ValueError(f"axis must be 0 (no axis) or 1..n, got {axis}")
        handle = await self._live(deadline)
        if axis > handle.axes:
            raise CncError.from_ew(EW.ATTRIB, f"{function}: axis {axis} of {handle.axes}")
        build = calls.cnc_diagnoss if diagnostic else calls.cnc_rdparam
        call = build(handle.command_set, number, axis)
        frame = call.frames[0]
        (block,) = await self._send(frame, handle.command_set, deadline)
        items: ItemValues | ScaledItemValues = _decode(frame[0], block, function, handle.max_axes)
        if not items.records:
            raise PayloadError(f"{function}: answer for {number} carries no record")
        record = items.records[0]
        if not diagnostic:
            self._param_types[number] = record.type
        real = DiagType.REAL if diagnostic else ParamType.REAL
        if record.type == real:  # REALPRM: (mantissa, 10, decimals)
            if isinstance(record, ItemRecord):
                reals = record.reals()
                if not reals:
                    raise PayloadError(f"{function}: real record of {number} has one slot")
                value = reals[0]
            else:
                value = record.values[0]
            return ParamValue(number, axis, value.mantissa, _REAL_WIDTH, value.decimals)
        widths = _DIAG_WIDTH if diagnostic else _PARAM_WIDTH
        width = widths.get(record.type)
        if width is None:
            raise PayloadError(f"{function}: {number} has type {record.type}, which has no value")
        first = record.values[0]
        raw = first.mantissa if isinstance(first, ScaledNumber) else first
        bits = 8 * width
        raw &= (1 << bits) - 1
        if raw >= 1 << (bits - 1):
            raw -= 1 << bits
        return ParamValue(number, axis, raw, width)

    async def _read_param_value(self, number: int, axis: int, deadline: float | None) -> ParamValue:
        value = await self._read_item(number, axis, deadline, diagnostic=False)
        self._param_widths[number] = value.width
        return value

    async def read_param_value(
        self, number: int, *, axis: int = 0, timeout: float | None = None
    ) -> ParamValue:
        """``cnc_rdparam`` as an IODBPSD: the value as the wire carries it and its width (1, 2,
        4 bytes, or 8 for a real parameter's REALPRM with its ``decimals``), as the packed
        client gives it."""
        return await self._read_param_value(number, axis, self._deadline(timeout))

    async def read_param_type(
        self, number: int, *, axis: int = 0, timeout: float | None = None
    ) -> ParamDataType | None:
        """The data type of parameter ``number`` (bit, byte, word, two-word, real) from the
        type word of its ``cnc_rdparam`` record, None for a word FANUC does not number.

        This stands in for the packed client's ``read_param_attributes``: FOCAS/2's
        ``cnc_rdparainfo`` answer has the type in two bits (no real type), and no decimals or
        range, while the record of ``cnc_rdparam`` names all five types."""
        await self._read_param_value(number, axis, self._deadline(timeout))
        ptype = self._param_types[number]
        return ParamDataType(ptype) if ptype in ParamDataType._value2member_map_ else None

    async def read_param(self, number: int, *, axis: int = 0, timeout: float | None = None) -> int:
        """``cnc_rdparam``: the value of parameter ``number`` (``axis`` 1..n for axis items).

        A bit parameter reads as its eight bits, 0..255 (the record's type says so); the others
        as the signed integer they hold. A real parameter raises :class:`ValueError`: read it
        with :meth:`read_param_real`.
        """
        value = await self._read_param_value(number, axis, self._deadline(timeout))
        if value.width == _REAL_WIDTH:
            raise ValueError(
                f"parameter {number} is a real parameter ({value.real}): read it with "
                "read_param_real"
            )
        if self._param_types.get(number) == ParamType.BIT:
            return value.bits
        return value.value

    async def read_param_real(
        self, number: int, *, axis: int = 0, timeout: float | None = None
    ) -> Decimal:
        """``cnc_rdparam``: the value of parameter ``number`` as a :class:`~decimal.Decimal`:
        a real parameter with its decimals (``12.345``), any other as its integer value (a bit
        parameter as 0..255)."""
        value = await self._read_param_value(number, axis, self._deadline(timeout))
        if value.width == _REAL_WIDTH:
            return value.real
        if self._param_types.get(number) == ParamType.BIT:
            return Decimal(value.bits)
        return Decimal(value.value)

    async def read_diag(self, number: int, *, axis: int = 0, timeout: float | None = None) -> int:
        """``cnc_diagnoss``: the value of diagnostic ``number``."""
        value = await self._read_item(number, axis, self._deadline(timeout), diagnostic=True)
        return value.value

    async def write_param(
        self,
        number: int,
        value: int | Decimal | str,
        *,
        axis: int = 0,
        width: int | None = None,
        timeout: float | None = None,
    ) -> None:
        """``cnc_wrparam``: write ``value`` (two frames, as the library sends them: the
        parameter's information, then the write).

        The width is the CNC's (its parameter information); a ``width`` given that differs
        raises EW_LENGTH before the write is sent, as ``cnc_wrparam`` does. As with the packed
        client, a bit parameter takes 0..255 or its bits as text, #7 first (``"0b10110000"``),
        and a real parameter a number with decimals (``Decimal("12.345")``, ``"12.345"``, an
        ``int``), width 8. The 16i command set has no way to write a real parameter: its
        parameter information gives a real parameter as a bit one, and the CNC answers the
        write EW_LENGTH, as FANUC's library returns.
        """
        if width is not None and width not in (1, 2, 4, _REAL_WIDTH):
            raise ValueError(f"parameter width must be 1, 2, 4 or 8 (real), got {width}")
        await self._write_param(number, value, axis, width, self._deadline(timeout))

    async def _write_param(
        self,
        number: int,
        value: int | Decimal | str,
        axis: int,
        width: int | None,
        deadline: float | None,
    ) -> None:
        if not 0 <= number <= 0x7FFFFFFF:
            raise ValueError(f"cnc_wrparam: number {number} is negative")
        if axis < 0:
            raise ValueError(f"axis must be 0 (no axis) or 1..n, got {axis}")
        handle = await self._live(deadline)
        if axis > handle.axes:
            raise CncError.from_ew(EW.ATTRIB, f"cnc_wrparam: axis {axis} of {handle.axes}")
        cs = handle.command_set
        info_request: tuple[NativeRequest, ...] = (
            (ParamInfoRequest(number, 1),)
            if cs is CommandSet.FS16I
            else (ParamInfo3Request(number, 1),)
        )
        (block,) = await self._send(info_request, cs, deadline)
        info = _decode(info_request[0], block, "cnc_wrparam", handle.max_axes)
        if isinstance(info, ParamInfo3):
            ptype = info.type
        else:
            assert isinstance(info, ParamInfo)
            if not info.entries:
                raise PayloadError(f"cnc_wrparam: no information on parameter {number}")
            ptype = info.entries[0].attribute & 3
        self._param_types[number] = ptype
        size = _REAL_WIDTH if ptype == ParamType.REAL else _PARAM_WIDTH.get(ptype)
        if size is None:
            raise PayloadError(f"cnc_wrparam: {number} has type {ptype}, which has no value")
        if width is not None and width != size:
            self._param_widths.pop(number, None)
            raise CncError.from_ew(
                EW.LENGTH, f"cnc_wrparam: {number} is {size} bytes wide, not {width}"
            )
        if ptype == ParamType.REAL:
            mantissa, decimals = _real_to_wire(number, value)
            record = self._param_record(handle, number, axis, ptype, mantissa, decimals)
        else:
            raw = _param_int(number, value)
            if ptype == ParamType.BIT:
                raw = _byte_to_wire(number, raw, ParamDataType.BIT)
            else:
                bits = 8 * size
                if not -(1 << (bits - 1)) <= raw < 1 << bits:
                    raise ValueError(f"value {raw} does not fit a {size}-byte parameter")
                if raw >= 1 << (bits - 1):
                    raw -= 1 << bits
            record = self._param_record(handle, number, axis, ptype, raw)
        write = calls.cnc_wrparam(cs, record).frames[1]
        (done,) = await self._send(write, cs, deadline)
        _check(done, "cnc_wrparam")

    def _param_record(
        self,
        handle: _Handle,
        number: int,
        axis: int,
        ptype: int,
        value: int,
        decimals: int | None = None,
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

    async def write_param_bit(
        self,
        number: int,
        bit: int,
        value: bool,
        *,
        axis: int = 0,
        timeout: float | None = None,
    ) -> None:
        """Set or clear one bit of a parameter by read-modify-write under the lock of
        ``(number, axis)``, like the packed client."""
        if not 0 <= bit < 32:
            raise ValueError(f"bit {bit} outside 0..31")
        deadline = self._deadline(timeout)
        async with self._param_locks.hold((number, axis), deadline):
            current = await self._read_param_value(number, axis, deadline)
            width = current.width
            if width == _REAL_WIDTH:
                raise ValueError(f"parameter {number} is a real parameter: it has no bits")
            if bit >= 8 * width:
                raise ValueError(f"bit {bit} outside 0..{8 * width - 1}")
            bits = 8 * width
            raw = current.value & ((1 << bits) - 1)
            raw = raw | (1 << bit) if value else raw & ~(1 << bit)
            if raw >= 1 << (bits - 1) and self._param_types.get(number) != ParamType.BIT:
                raw -= 1 << bits
            await self._write_param(number, raw, axis, width, deadline)

    # -- macros --------------------------------------------------------------------------
    async def read_macro(self, number: int, *, timeout: float | None = None) -> Decimal | None:
        """``cnc_rdmacro``: the value of ``#number`` as a Decimal, or None when vacant
        (binary records converted as the library converts them)."""
        clock = self._clock
        if timeout is None and clock is not None and (wait := self.timeout) is not None:
            deadline: float | None = clock() + wait  # (the usual case of _deadline, inline)
        else:
            deadline = self._deadline(timeout)
        handle = self._handle
        if handle is None or handle.closed:
            handle = await self._live(deadline)
        call = handle.macro_calls.get(number)
        if call is None:
            call = _memo_call(handle.macro_calls, number, calls.cnc_rdmacro, handle.command_set)
        if handle.inflight is not None:
            future = (self._loop or asyncio.get_running_loop()).create_future()
            job: _Job = _new(_Job)
            job.requests = call.frames[0]
            job.command_set = handle.command_set
            job.deadline = deadline
            job.future = future
            job.task = None
            job.part = _NO_PART
            job.unarmed = False
            self._queue.append(job)
            if deadline is not None and deadline < self._watch_at:
                self._watch(deadline)
            blocks = await future
        else:
            blocks = await self._send(call.frames[0], handle.command_set, deadline)
        known: tuple[Any, Any, tuple[Decimal | None]] | None = _RESULTS.get(id(blocks[0]))
        if known is not None and known[0] is blocks and known[1] is call:
            return known[2][0]  # (the usual case of _known_result, inline)
        known_value: tuple[Decimal | None] | None = _known_result(blocks, call)
        if known_value is not None:
            return known_value[0]
        (block,) = blocks
        values: ScaledValues = _decode(call.frames[0][0], block, "cnc_rdmacro", 0)
        if not values.values:
            raise PayloadError(f"cnc_rdmacro: answer for #{number} carries no value")
        mcr_val, dec_val = values.values[0].to_macro()
        value = macro_from_wire(mcr_val, dec_val)
        _remember_result(blocks, call, (value,))
        return value

    async def write_macro(
        self, number: int, value: int | Decimal | float | str, *, timeout: float | None = None
    ) -> None:
        """``cnc_wrmacro``: write ``#number`` (a binary record at 16i class, base 10 at 30i,
        as the library sends it); see :func:`~focas_net.client.client.macro_to_wire`."""
        mcr_val, dec_val = macro_to_wire(value)
        _, _, (block,) = await self._one(
            lambda cs: calls.cnc_wrmacro(cs, number, mcr_val, dec_val), self._deadline(timeout)
        )
        _check(block, "cnc_wrmacro")

    # -- PMC -----------------------------------------------------------------------------
    @staticmethod
    def _area(area: str | int | PmcArea) -> tuple[PmcArea, int]:
        a = PmcArea.parse(area)
        try:
            return a, NativePmcArea[a.name].value
        except KeyError:
            raise ValueError(f"PMC area {a.name} has no FOCAS/2 address type") from None

    @staticmethod
    def _range(start: int, count: int) -> None:
        if not 0 <= start < _U16_LIMIT:
            raise ValueError(f"start address {start} outside 0..65535")
        if count < 1 or start + count > _U16_LIMIT:
            raise ValueError(f"count {count} at {start}: must be at least 1 and end by 65535")

    async def _read_pmc_chunk(
        self, code: int, start: int, count: int, deadline: float | None
    ) -> bytes:
        _, call, (block,) = await self._one(
            lambda cs: calls.pmc_rdpmcrng(cs, code, 0, start, start + count - 1), deadline
        )
        data: NativePmcData = _decode(call.frames[0][0], block, "pmc_rdpmcrng", 0)
        if len(data.raw) != count:
            raise PayloadError(f"pmc_rdpmcrng answer: {len(data.raw)} bytes, asked {count}")
        return data.raw

    async def read_pmc(
        self, area: str | int | PmcArea, start: int, count: int, *, timeout: float | None = None
    ) -> bytes:
        """``pmc_rdpmcrng``: ``count`` bytes of ``area`` from ``start``; a range longer than
        one answer carries is read as several calls issued together."""
        _, code = self._area(area)
        self._range(start, count)
        deadline = self._deadline(timeout)
        handle = await self._live(deadline)
        step = handle.pmc_chunk
        if count <= step:
            return await self._read_pmc_chunk(code, start, count, deadline)
        parts = [
            self._read_pmc_chunk(code, s, min(step, start + count - s), deadline)
            for s in range(start, start + count, step)
        ]
        tasks = [asyncio.ensure_future(p) for p in parts]
        try:
            return b"".join(await asyncio.gather(*tasks))
        finally:
            for t in tasks:
                if not t.done():
                    t.cancel()
            await asyncio.wait(tasks)

    async def write_pmc(
        self, area: str | int | PmcArea, start: int, data: bytes, *, timeout: float | None = None
    ) -> None:
        """``pmc_wrpmcrng``: write ``data`` to ``area`` from ``start``. Longer than one frame
        carries, the write is split into calls issued together; if any fails,
        :class:`ChunkedWriteError` lists the ranges written, not written and uncertain."""
        a, code = self._area(area)
        data = bytes(data)
        self._range(start, len(data))
        deadline = self._deadline(timeout)
        handle = await self._live(deadline)
        step = handle.pmc_write_chunk
        chunks = [
            (s, data[s - start : s - start + step]) for s in range(start, start + len(data), step)
        ]

        async def one(first: int, part: bytes) -> None:
            _, _, (block,) = await self._one(
                lambda cs: calls.pmc_wrpmcrng(cs, code, 0, first, first + len(part) - 1, part),
                deadline,
            )
            _check(block, "pmc_wrpmcrng")

        if len(chunks) == 1:
            await one(*chunks[0])
            return
        results = await asyncio.gather(*(one(s, p) for s, p in chunks), return_exceptions=True)
        errors = [r for r in results if isinstance(r, BaseException)]
        if not errors:
            return
        for r in errors:
            if not isinstance(r, Exception):
                raise r
        written: list[tuple[int, int]] = []
        not_written: list[tuple[int, int]] = []
        uncertain: list[tuple[int, int]] = []
        for (first, part), outcome in zip(chunks, results, strict=True):
            span = (first, first + len(part) - 1)
            if outcome is None:
                written.append(span)
            elif isinstance(outcome, FocasTimeoutError | FocasConnectionError):
                uncertain.append(span)
            else:
                not_written.append(span)
        cause = errors[0]
        assert isinstance(cause, Exception)
        raise ChunkedWriteError(a.name, written, not_written, cause, uncertain) from cause

    async def read_pmc_bit(
        self, area: str | int | PmcArea, byte: int, bit: int, *, timeout: float | None = None
    ) -> bool:
        """One bit of a PMC byte (``R100.3`` is ``read_pmc_bit("R", 100, 3)``)."""
        if not 0 <= bit < 8:
            raise ValueError(f"bit {bit} outside 0..7")
        data = await self.read_pmc(area, byte, 1, timeout=timeout)
        return bool(data[0] >> bit & 1)

    async def write_pmc_bit(
        self,
        area: str | int | PmcArea,
        byte: int,
        bit: int,
        value: bool,
        *,
        timeout: float | None = None,
    ) -> None:
        """Set or clear one PMC bit by read-modify-write under the lock of ``(area, byte)``,
        so that concurrent bit writes never lose one another."""
        a, code = self._area(area)
        if not 0 <= bit < 8:
            raise ValueError(f"bit {bit} outside 0..7")
        self._range(byte, 1)
        deadline = self._deadline(timeout)
        async with self._pmc_locks.hold((a.value, byte), deadline):
            current = (await self._read_pmc_chunk(code, byte, 1, deadline))[0]
            new = current | (1 << bit) if value else current & ~(1 << bit)
            _, _, (block,) = await self._one(
                lambda cs: calls.pmc_wrpmcrng(cs, code, 0, byte, byte, bytes((new,))), deadline
            )
            _check(block, "pmc_wrpmcrng")

    # -- alarms --------------------------------------------------------------------------
    async def read_alarm_status(self, *, timeout: float | None = None) -> int:
        """``cnc_alarm2``: the alarm bits (bit n set while an alarm of type n is active)."""
        _, call, (block,) = await self._one(calls.cnc_alarm2, self._deadline(timeout))
        value: AlarmStatus = _decode(call.frames[0][0], block, "cnc_alarm2", 0)
        return value.alarm

    async def read_alarms(
        self, *, alm_type: int = -1, count: int = _MAX_ACTIVE_ALARMS, timeout: float | None = None
    ) -> tuple[ActiveAlarm, ...]:
        """``cnc_rdalmmsg2``: up to ``count`` active alarms (all types, or only ``alm_type``)."""
        if not 1 <= count <= 0x7FFF:
            raise ValueError(f"count must be within 1..32767, got {count}")
        _, call, (block,) = await self._one(
            lambda cs: calls.cnc_rdalmmsg2(cs, alm_type, count),
            self._deadline(timeout),
        )
        value: AlarmMessages = _decode(call.frames[0][0], block, "cnc_rdalmmsg2", 0)
        return tuple(
            ActiveAlarm(a.axis, a.alarm_type, a.number, _text(a.message)) for a in value.alarms
        )

    async def read_alarm_history(
        self, depth: int = 10, *, timeout: float | None = None
    ) -> AlarmHistory:
        """``cnc_rdalmhistry``: up to ``depth`` (clamped to 1..250) most recent entries,
        newest first, read 23 at a time as the library does. An error on the first chunk
        raises :class:`CncError`; EW_NUMBER on a later one ends the list."""
        depth = min(max(int(depth), 1), MAX_HISTORY_DEPTH)
        deadline = self._deadline(timeout)
        handle = await self._live(deadline)
        call = calls.cnc_rdalmhistry(handle.command_set, 1, depth)
        entries: list[AlarmHistoryEntry] = []
        for frame in call.frames:
            (block,) = await self._send(frame, handle.command_set, deadline)
            if block.ew == EW.NUMBER:
                break  # no entry from here on (from the first: the history is empty)
            history: NativeAlarmHistory = _decode(frame[0], block, "cnc_rdalmhistry", 0)
            for r in history.records:
                try:
                    when = datetime(r.year, r.month, r.day, r.hour, r.minute, r.second, tzinfo=UTC)
                except ValueError as exc:
                    raise PayloadError(f"cnc_rdalmhistry: bad date in an entry: {exc}") from None
                text = r.text[: max(min(r.length, len(r.text)), 0)]
                entries.append(AlarmHistoryEntry(when, r.axis, r.group, r.alarm_no, _text(text)))
            if len(history.records) < frame[0].last - frame[0].first + 1:  # type: ignore[attr-defined]
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
