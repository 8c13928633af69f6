"""The native client's asyncio shell: :class:`NativeLink`, over a
:class:`~focas_net.native.session.NativeSession`.

FANUC's library opens a handle as two TCP connections (``docs/native-client.md``): A, opened
and closed, and B, which carries every data frame. :func:`open_handle` opens both, reads the
open answers and sends the connect-time requests; :class:`Handle` keeps what they said. The
link then only moves bytes and time between B, one timer and the session:

* a call's blocks (encoded by the caller) are submitted as a job whose token is a future; the
  caller awaits the future, and a caller that gives up abandons its job;
* a frame leaves when the session is idle: at once when its caller is the task whose lone
  call was just answered (a sequential caller), else at the end of the loop turn, so that
  calls made together, or by the callers an answer just woke, share one frame; when an answer
  comes and calls wait, the next frame leaves before the results are handed out;
* one timer, armed no later than the earliest deadline the session has (moved only when an
  earlier one comes), ends what expired; a frame unanswered past its last deadline stays in
  flight, and its late answer, when it comes, is dropped and the queued frames go on the same
  connection (answers come in order, and none is sent behind it). A call made behind it ends
  the connection at once when the client has a reconnect policy (the call goes on the next
  connection); without one, the call waits for the late answer, and reaching its deadline
  unsent ends the connection. Bytes no request asked for, or an answer the library refuses,
  end the connection too, and the client reconnects as its policy says (calls still queued
  wait for the next connection).

The session decides; the link turns each ended job into the call's result or exception.
"""

from __future__ import annotations

import asyncio
import logging
import operator
from collections.abc import Callable
from functools import partial
from typing import Any, Final

from focas_net._address import address_text
from focas_net._typed import os_reason
from focas_net.errors import (
    CncError,
    FocasConnectionError,
    FocasError,
    FocasTimeoutError,
    PayloadError,
    ProtocolError,
)

from ..native import (
    MAGIC,
    NATIVE_HEADER,
    NATIVE_HEADER_SIZE,
    NOT_A_FRAME,
    AnswerRefused,
    CommandSet,
    Ending,
    FrameType,
    Job,
    LibraryCall,
    NativeCommand,
    NativeSession,
    NativeSysInfo,
    OpenAnswer,
    OpenHeadV2,
    Part,
    ResponseBlock,
    ScaledNumber,
    answer_blocks,
    calls,
    decode_open_answer,
    encode_close_request,
    encode_open_request,
)
from ._channel import Channel, open_channel
from ._composite import CompositeCalls
from ._failures import (
    ECHOED,
    NEVER_SENT,
    axis_refusal,
    connect_error,
    lost_error,
    native_call_text,
    no_answer_error,
    path_refusal,
    timeout_error,
    undecodable_error,
    violation_error,
)
from .connection import NotSentError
from .reconnect import ClientState, ReconnectPolicy, StateCallback

__all__ = ["Handle", "NativeLink", "open_handle"]

logger = logging.getLogger("focas_net.client.native")

_NEVER: Final = float("inf")
_CLOSE_GRACE: Final = 2.0
_MAGIC: Final = int.from_bytes(MAGIC, "big")
_NO_OPEN_ANSWER: Final = "no answer to the open request"
#: The frame types of a FOCAS/2 answer (open, close, data, error): another comes from no CNC.
_ANSWER_TYPES: Final = frozenset(
    {
        FrameType.OPEN_RESPONSE,
        FrameType.CLOSE_RESPONSE,
        FrameType.DATA_RESPONSE,
        FrameType.DATA_ERROR,
    }
)

#: The frame types the client sends (open, close, data): no CNC answers with one.
_REQUEST_TYPES: Final = frozenset(
    {FrameType.OPEN_REQUEST, FrameType.CLOSE_REQUEST, FrameType.DATA_REQUEST}
)

Future = asyncio.Future[tuple[ResponseBlock, ...]]


#: How an answered job ends, looked up once (asked once per call: on Python 3.11 each
#: ``Ending.ANSWERED`` goes through ``EnumType.__getattr__``, uncached).
_ANSWERED: Final = Ending.ANSWERED
#: Whether the caller of a job (its token: the future it awaits) gave up: it is cancelled.
_cancelled: Final = operator.methodcaller("cancelled")


async def _read_frame(channel: Channel, peer: str, answered: bool = True) -> bytes:
    """The next whole frame (header included) read from ``channel`` before it is started.

    :raises ProtocolError: ``peer`` does not speak FOCAS/2 (its answer is no frame, or a
        frame of a type no FOCAS/2 answer has).
    :raises FocasConnectionError: the connection ended first (``answered``: a frame came on
        it before; the start of one counts too).
    """
    try:
        # a start no frame has is refused as it comes, not once the call's time is up
        head = await channel.readexactly(NATIVE_HEADER_SIZE, partial(_check_start, peer))
    except (asyncio.IncompleteReadError, OSError) as exc:
        came = exc.partial if isinstance(exc, asyncio.IncompleteReadError) else channel.kept
        _check_start(peer, came)
        raise lost_error(peer, exc, answered or bool(came)) from exc
    magic, _, kind, length = NATIVE_HEADER.unpack(head)
    if magic != _MAGIC:
        raise violation_error(peer, NOT_A_FRAME, head)
    if kind in _REQUEST_TYPES:  # what the client sends, back: an echo server
        raise violation_error(peer, f"{ECHOED}: a frame of type 0x{kind:04X}", head)
    if kind not in _ANSWER_TYPES:
        raise violation_error(peer, f"its answer is a frame of type 0x{kind:04X}", head)
    try:
        return head + await channel.readexactly(length)
    except (asyncio.IncompleteReadError, OSError) as exc:  # within a frame: no more a rule
        raise lost_error(peer, exc, True) from exc


def _check_start(peer: str, partial: bytes) -> None:
    """Raise the :class:`ProtocolError` of ``peer`` when ``partial``, the bytes of a frame's
    header that came before its connection ended or its call timed out, cannot begin one."""
    if partial and not MAGIC.startswith(partial[: len(MAGIC)]):
        raise violation_error(peer, NOT_A_FRAME, partial) from None


class Handle:
    """One open A/B connection pair and what its open answer and connect requests said."""

    def __init__(self, a: Channel, b: Channel, opened: OpenAnswer, peer: str) -> None:
        self.peer = peer
        self.a = a
        self.b = b
        self.opened = opened
        self.version = opened.version
        self.command_set = CommandSet.for_version(opened.version)
        self.max_axes = opened.max_axes
        present = opened.present()
        self.axes = present[0].axes if present else 0
        self.spindles = present[0].spindles if present else 0
        self.paths = len(present)
        #: The number of axes and of spindles of each path, in path order.
        self.path_axes = tuple(p.axes for p in present)
        self.path_spindles = tuple(p.spindles for p in present)
        self.option_bits = opened.option_bits or 0
        self.sysinfo: NativeSysInfo | None = None
        self.closed = False
        # FANUC's library's write buffer: cnc_wrparam leaves the slots it does not write as
        # the previous write left them, and so does this client, byte for byte.
        self.param_slots: list[int] = [0] * max(self.max_axes, 1)
        self.param3_slots: list[ScaledNumber] = [ScaledNumber(0, 0, 0)] * max(self.max_axes, 1)

    def axes_on(self, path: int) -> int:
        """The number of axes of ``path`` (a path the open answer announces)."""
        return self.path_axes[path - 1] if path <= len(self.path_axes) else 0

    def spindles_on(self, path: int) -> int:
        """The number of spindles of ``path`` (a path the open answer announces)."""
        return self.path_spindles[path - 1] if path <= len(self.path_spindles) else 0

    async def exchange(self, part: Part) -> tuple[ResponseBlock, ...]:
        """One data frame on B, read back before the client takes B over (the connect)."""
        self.b.write(part.frame)
        try:
            # a peer that closes before answering a request reads as on the packed transport
            # ("before any answer"): the open answer alone is no answer to a request
            frame = await _read_frame(self.b, self.peer, answered=False)
            blocks = answer_blocks(frame, part.count)
        except AnswerRefused as exc:  # a frame no FOCAS/2 server sends: as after the connect
            raise violation_error(self.peer, str(exc), frame[:8]) from None
        if isinstance(blocks, int):
            raise CncError.from_ew(blocks, "error answer (0x2103) to the connect requests")
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
                    raw = await _read_frame(channel, self.peer)
                    if NATIVE_HEADER.unpack_from(raw)[2] != FrameType.CLOSE_RESPONSE:
                        break
        except (TimeoutError, OSError, ProtocolError):
            pass
        self.a.close()
        self.b.close()


async def _open_channel(
    host: str, port: int, channel: int, deadline: float | None
) -> tuple[Channel, bytes]:
    """Connection ``channel`` (1: A, 2: B), opened: it and its open answer frame."""
    where = address_text(host, port)
    try:
        async with asyncio.timeout_at(deadline):
            conn = await open_channel(host, port)
    except TimeoutError:
        raise FocasTimeoutError(f"connecting to {where} timed out") from None
    except OSError as exc:
        raise connect_error(host, port, exc, None) from exc
    try:
        conn.write(encode_open_request(channel))
        try:
            async with asyncio.timeout_at(deadline):
                raw = await _read_frame(conn, where, answered=False)
        except TimeoutError:
            # the start of an answer that never came whole: no frame of FOCAS/2's, or one
            # cut short (not "nothing received", which a silent peer is)
            if not conn.received:
                raise
            if conn.received < NATIVE_HEADER_SIZE:  # (the header's start, still kept)
                _check_start(where, conn.kept)
            raise timeout_error(_NO_OPEN_ANSWER, None) from None
    except BaseException:
        conn.close()
        raise
    kind = NATIVE_HEADER.unpack_from(raw)[2]
    if kind != FrameType.OPEN_RESPONSE:
        conn.close()
        raise violation_error(where, f"its answer to the open is a frame of type 0x{kind:04X}", raw)
    return conn, raw


def _opened(raw: bytes) -> OpenAnswer:
    _, version, _, _ = NATIVE_HEADER.unpack_from(raw)
    return decode_open_answer(raw[NATIVE_HEADER_SIZE:], version)


async def open_handle(host: str, port: int, deadline: float | None) -> Handle:
    """Open A and B and send the connect-time requests of ``cnc_allclibhndl3``."""
    where = address_text(host, port)
    channels: list[Channel] = []
    try:
        a, raw_a = await _open_channel(host, port, 1, deadline)
        channels.append(a)
        b, raw_b = await _open_channel(host, port, 2, deadline)
        channels.append(b)
        raw = raw_a
        try:
            _opened(raw_a)
            raw = raw_b
            opened = _opened(raw_b)
        except ProtocolError as exc:  # FANUC's library: EW_PROTOCOL, as for a data answer
            raise violation_error(where, f"open answer refused: {exc}", raw) from None
        if isinstance(opened.head, OpenHeadV2) and opened.head.kind == 2:
            raise FocasConnectionError(f"{where}: an FS15-family control (kind 2) is not supported")
        handle = Handle(a, b, opened, where)
        if not handle.paths:
            raise FocasConnectionError(f"{where}: the open answer announces no path")
        async with asyncio.timeout_at(deadline):
            await _connect_requests(handle)
        if isinstance(opened.head, OpenHeadV2) and opened.head.kind == 3:
            handle.option_bits = 1
    except FocasTimeoutError:  # (the connect, or an open answer cut short, said what)
        _abort(channels)
        raise
    except TimeoutError:
        _abort(channels)
        if channels:  # A was opened: the peer speaks
            raise FocasTimeoutError(
                f"no answer to the connect requests (cnc_allclibhndl3) from {where}"
            ) from None
        raise timeout_error(_NO_OPEN_ANSWER, where) from None
    except BaseException:
        _abort(channels)
        raise
    return handle


async def _connect_requests(handle: Handle) -> None:
    """The frames ``cnc_allclibhndl3`` sends once connected: the system information of each
    path and, at 16i class, the FOCAS option bits (parameter 9968)."""
    connect = calls.cnc_allclibhndl3(handle.command_set, handle.paths)
    for frame, part in zip(connect.frames, connect.parts, strict=True):
        blocks = await handle.exchange(part)
        for request, block in zip(frame, blocks, strict=True):
            if block.ew:
                raise CncError.from_ew(block.ew, "cnc_allclibhndl3")
            if request.COMMAND == NativeCommand.SYSINFO and handle.sysinfo is None:
                try:
                    handle.sysinfo = request.decode_answer(block.data)
                except PayloadError as exc:
                    what = native_call_text(connect.function, request.COMMAND)
                    raise undecodable_error(handle.peer, what, exc) from None
            elif request.COMMAND == NativeCommand.RDPARAM:
                # slot 0's low byte
                handle.option_bits = block.data[11] if len(block.data) >= 12 else 0


def check_path_of(handle: Handle, path: int, function: str) -> None:
    """EW_PATH (:class:`CncError`) unless ``handle``'s open answer announces ``path``."""
    if path > handle.paths:
        raise path_refusal(function, path, handle.paths)


def check_axis_of(handle: Handle, axis: int, function: str, path: int = 1) -> None:
    """EW_ATTRIB (:class:`CncError`), before anything is sent, for an ``axis`` past ``path``'s
    axes, as FANUC's library checks every per-axis argument against the path's axis count (a
    spindle diagnostic's too: the library sends ``cnc_diagnoss(411, axis 2)`` to a CNC of one
    spindle and three axes, and refuses spindle 3 of a path of two axes); EW_PATH first for a
    path the CNC has not (it has no axes)."""
    check_path_of(handle, path, function)
    axes = handle.axes_on(path)
    if axis > axes:
        raise axis_refusal(function, axis, axes)


def _abort(channels: list[Channel]) -> None:
    for channel in channels:
        channel.close()


class NativeLink(CompositeCalls):
    """The connection pair of a :class:`~focas_net.client.NativeClient`, its session and its
    lifecycle (see the module docstring). The arguments are the client's."""

    _logger = logger

    def __init__(
        self,
        host: str,
        port: int,
        *,
        timeout: float | None,
        reconnect: bool | ReconnectPolicy,
        max_blocks: int,
        on_state_change: StateCallback | None,
        path: int = 1,
    ) -> None:
        super().__init__(
            host,
            port,
            timeout=timeout,
            reconnect=reconnect,
            on_state_change=on_state_change,
            path=path,
        )
        self._init_composite()
        self._session: NativeSession[Future] = NativeSession(max_blocks, _cancelled)
        #: The last job submitted while the session was idle, and its caller's task: when it
        #: was alone in its frame, that task's next call is sent at once (see _on_data).
        self._idle_job: Job[Future] | None = None
        self._idle_task: asyncio.Task[Any] | None = None
        self._handle: Handle | None = None
        #: Why the peer is no FOCAS/2 server (bytes no frame starts with, or an answer the
        #: library refuses): calls raise it, no reconnect follows, until ``connect()``.
        self._violation: ProtocolError | None = None
        #: The task whose lone call was answered last: its next call is sent at once; any
        #: other at the end of the loop turn (``_flush_soon`` set while that is scheduled).
        self._sequential: asyncio.Task[Any] | None = None
        self._flush_soon = False
        #: The one timer, and when it fires (``inf``: not set).
        self._timer: asyncio.TimerHandle | None = None
        self._timer_at = _NEVER
        #: Why jobs that end LOST ended (the last connection's end, or the close).
        self._why = "closed"

    # -- what the client shows -------------------------------------------------------------
    @property
    def max_blocks(self) -> int:
        """Most blocks one frame carries."""
        return self._session.max_blocks

    @property
    def frames_sent(self) -> int:
        """Data frames sent since the client was made."""
        return self._session.frames_sent

    @property
    def blocks_sent(self) -> int:
        """Blocks those frames carried."""
        return self._session.blocks_sent

    @property
    def command_set(self) -> CommandSet | None:
        """The command set of the open handle (16i or 30i class), None when not connected."""
        return None if self._handle is None else self._handle.command_set

    @property
    def version(self) -> int | None:
        """The version word of the open answer (it sets the command set and the most bytes
        of an answer body), None when not connected."""
        return None if self._handle is None else self._handle.version

    @property
    def max_axes(self) -> int | None:
        """The CNC's max axes from the open answer, None when not connected."""
        return None if self._handle is None else self._handle.max_axes

    @property
    def idle(self) -> bool:
        """Whether no call of this client is queued or in flight (a call given up while
        queued is never sent, so it counts no more; a frame whose late answer is awaited
        carries no call)."""
        session = self._session
        return (session.in_flight is None or session.overdue) and not session.queued

    # -- lifecycle -----------------------------------------------------------------------
    async def connect(self) -> None:
        """Open the A/B pair and send the connect-time requests (``cnc_allclibhndl3``).

        Raises :class:`FocasConnectionError` (or :class:`FocasTimeoutError`) when the CNC
        cannot be reached or its open answer is refused; the first connect is not retried.
        """
        if self._state is ClientState.CLOSED:
            raise self._closed()
        if self._linked():
            return
        self._bind_loop()
        self._violation = None
        try:
            handle = await open_handle(self.host, self.port, self._deadline(None))
        except FocasError as exc:
            self._connect_failed(exc)
            raise
        if self.state is ClientState.CLOSED:  # closed while connecting
            handle.abort()
            raise self._closed()
        if self._linked():  # a concurrent connect() won
            handle.abort()
            return
        self._install(handle)

    async def aclose(self) -> None:
        """Close the handle (close exchange on A, then B); pending calls fail with
        :class:`FocasConnectionError`."""
        await self._stop_reconnecting()
        handle, self._handle = self._handle, None
        self._why = "client is closed"
        self._complete(self._session.close())
        if self._timer is not None:
            self._timer.cancel()
            self._timer, self._timer_at = None, _NEVER
        if handle is not None:
            handle.b.stop()
            await handle.close(_CLOSE_GRACE)

    def _linked(self) -> bool:
        handle = self._handle
        return handle is not None and not handle.closed

    async def _handle_for(self, deadline: float | None) -> Handle:
        """The open handle, waiting (until ``deadline``) while reconnecting (a call takes
        ``self._handle_now() or await self._handle_for(deadline)``: no wait when open)."""
        handle = self._handle_now()
        if handle is None:
            await self._wait_linked(deadline)
            handle = self._handle
            assert handle is not None
        return handle

    def _install(self, handle: Handle) -> None:
        self._handle = handle
        stale = self._session.connected(handle.command_set, handle.version, handle.max_axes)
        self._sequential = None
        self._linked_now()
        self._complete(stale)
        # (B ended while connecting: the end is told at once, and the handle lost)
        handle.b.start(partial(self._on_data, handle), partial(self._on_end, handle))
        if handle is self._handle:
            self._send()

    async def _reconnect_attempt(self, attempt: int) -> bool:
        try:
            handle = await open_handle(self.host, self.port, self._deadline(None))
        except ProtocolError as exc:  # not a FOCAS/2 server: connecting again meets it again
            logger.warning("%s; not reconnecting", exc)
            self._attempt_error = self._violation = exc
            self._set_state(ClientState.DISCONNECTED)
            return True
        except Exception as exc:  # refused, unreachable, or an answer that does not decode
            logger.debug("reconnect attempt %d to %s: %s", attempt, self.address, os_reason(exc))
            self._attempt_error = exc
            return False
        self._install(handle)
        # (lost again while installed, for bytes nobody asked for or the end of B: the next
        # attempt follows)
        return self._handle is handle

    def _reconnect_ended(self) -> None:
        if self._state is ClientState.DISCONNECTED:
            last = self._attempt_error
            self._why = f"could not reconnect to {self.address}" + (f": {last}" if last else "")
            self._complete(self._session.lost(keep_queued=False))

    def _nothing_to_wait_for(self) -> Exception:
        if self._violation is not None:
            return ProtocolError(str(self._violation))
        return super()._nothing_to_wait_for()

    def _broken(self, handle: Handle, why: str, head: bytes) -> None:
        """The peer broke FOCAS/2 on ``handle`` (``why``; ``head``: the bytes it sent): as on
        the packed transport, every call in flight or queued fails with the
        :class:`ProtocolError` of a peer that does not speak the FOCAS protocol, and no
        reconnect follows (the same peer would answer it)."""
        if handle is not self._handle:
            return
        self._violation = violation_error(self.address, why, head)
        logger.warning("%s; not reconnecting", self._violation)
        self._handle = None
        handle.abort()
        self._complete(self._session.lost(keep_queued=False))
        if self._state is not ClientState.CLOSED:
            self._set_state(ClientState.DISCONNECTED)

    def _lose(self, handle: Handle, why: str) -> None:
        """``handle`` can carry no further frame: its jobs in flight end, and the client
        reconnects (its queued jobs wait) or not (they end too), as its policy says."""
        if handle is not self._handle:
            return
        self._handle = None
        handle.abort()
        keep = self._policy is not None and self._state is not ClientState.CLOSED
        self._why = why
        self._complete(self._session.lost(keep_queued=keep))
        if self._state is ClientState.CLOSED:
            return
        if not keep:
            logger.warning("connection to %s lost: %s", self.address, why)
            self._lost_why = FocasConnectionError(why)
            self._set_state(ClientState.DISCONNECTED)
            return
        self._reconnecting(FocasConnectionError(why))

    def _handle_now(self) -> Handle | None:
        """The open handle, or None while there is none (then :meth:`_handle_for` waits for
        the reconnect, until a call's deadline)."""
        handle = self._handle
        return None if handle is None or handle.closed else handle

    # -- jobs ----------------------------------------------------------------------------
    def _exchange(
        self,
        handle: Handle,
        call: LibraryCall,
        deadline: float | None,
        frame: int = 0,
        path: int = 1,
    ) -> Future:
        """Frame ``frame`` of library ``call`` on ``handle``, its blocks on ``path``, submitted:
        the future of its answer blocks (an EW code in a block is the caller's to raise). A
        caller that gives up cancels the future (awaiting it does): queued, the job is then
        never sent; sent, its blocks are dropped. A path the open answer does not announce
        raises EW_PATH (:class:`CncError`) and sends nothing, as FANUC's library refuses it."""
        if path != 1:
            check_path_of(handle, path, call.function)
        return self._submit(call.part(frame, path), handle.command_set, deadline).token

    async def _only(
        self,
        call_of: Callable[..., LibraryCall],
        path: int | None,
        timeout: float | None,  # noqa: ASYNC109 - a call's own timeout, by contract
        *args: Any,
    ) -> tuple[Handle, LibraryCall, tuple[ResponseBlock, ...]]:
        """One call of one frame, ``call_of(command set, *args)``, on ``path``: the handle
        it went on, the call and its answer blocks."""
        p = self._path_of(path)
        deadline = self._deadline(timeout)
        handle = self._handle_now() or await self._handle_for(deadline)
        call = call_of(handle.command_set, *args)
        return handle, call, await self._exchange(handle, call, deadline, 0, p)

    def _submit(self, part: Part, command_set: CommandSet, deadline: float | None) -> Job[Future]:
        """Queue a job and have it sent (see the module docstring); the caller awaits its
        token, or abandons it."""
        if self._handle is None and self._state is not ClientState.RECONNECTING:
            # (between two frames of one call, the connection lost with nothing to wait for)
            raise (
                self._nothing_to_wait_for()
                if self._state is not ClientState.CLOSED
                else self._closed()
            )
        loop = self._loop or asyncio.get_running_loop()
        session = self._session
        idle = session.idle and not self._flush_soon
        future = loop.create_future()
        job = session.submit(part, _NEVER if deadline is None else deadline, command_set, future)
        if job.ending is not None:
            self._complete([job])
            return job
        handle = self._handle
        given_up = session.overdue and self._policy is not None and handle is not None
        if given_up and handle is not None:
            # a call waits behind an answer already late: a new pair carries it at once (its
            # deadline still holds while the pair is made: the timer below ends it on time)
            self._lose(handle, "no answer within the timeout")
        if session.wake_at < self._timer_at:
            self._arm(session.wake_at)
        if given_up:
            return job
        if idle:
            # (a call queued behind a frame in flight has no need of its task: see _on_data)
            task = asyncio.current_task(loop)
            self._idle_job, self._idle_task = job, task
            if task is not None and task is self._sequential:
                self._sequential = None
                self._send()
            else:
                self._flush_soon = True
                loop.call_soon(self._flush)
        return job

    def _send(self) -> None:
        """Write the next frame, if the session has one to send now."""
        frame = self._session.next_frame()
        if frame is not None:
            assert self._handle is not None
            self._handle.b.write(frame)

    def _flush(self) -> None:
        self._flush_soon = False
        self._send()

    def _on_data(self, handle: Handle, data: bytes) -> None:
        """B's bytes: the answer hands the calls of the frame their blocks; calls waiting go
        in the next frame, sent first."""
        session = self._session
        in_flight = session.in_flight
        ended = session.receive(data)
        if session.failure is not None:
            # (the jobs it ended fail with why, set before they complete)
            why = session.failure
            if session.broken:
                self._broken(handle, why, data[:8])
            else:  # a stray answer: lost, as a connection the peer ended, named alike
                why = self._why = f"{self.address} sent {why}"
            self._complete(ended)
            self._lose(handle, why)
            return
        if session.queue:
            self._send()
        lone = in_flight is not None and len(in_flight) == 1
        if lone and in_flight is not None and in_flight[0] is self._idle_job:
            self._sequential = self._idle_task
        else:
            self._sequential = None
        self._complete(ended)
        if not lone and not self._flush_soon and session.in_flight is None:
            # the callers just answered will likely call again when they wake: their calls
            # leave together, after them
            self._flush_soon = True
            (self._loop or asyncio.get_running_loop()).call_soon(self._flush)

    def _on_end(self, handle: Handle, exc: Exception | None) -> None:
        self._lose(handle, str(lost_error(self.address, exc)))

    def _arm(self, when: float) -> None:
        if self._timer is not None:
            self._timer.cancel()
        loop = self._loop or asyncio.get_running_loop()
        self._timer = loop.call_at(when, self._expire)
        self._timer_at = when

    def _expire(self) -> None:
        """The timer fired: end what expired; arm it again for the earliest deadline left."""
        loop = self._loop or asyncio.get_running_loop()
        now = max(loop.time(), self._timer_at)
        self._timer, self._timer_at = None, _NEVER
        session = self._session
        ended = session.expire(now)
        handle = self._handle
        if session.failure is not None and handle is not None:
            self._why = session.failure  # (before the jobs it ended complete)
        self._complete(ended)
        if session.failure is not None and handle is not None:
            self._lose(handle, session.failure)
        if session.wake_at < _NEVER:
            self._arm(session.wake_at)

    def _complete(self, jobs: list[Job[Future]]) -> None:
        """Hand each ended job's caller its blocks or its exception."""
        for job in jobs:
            future = job.token
            if future.done():
                continue
            if job.ending is _ANSWERED:
                future.set_result(job.blocks)
            else:
                future.set_exception(self._failure(job))

    def _failure(self, job: Job[Future]) -> FocasError:
        """The exception of a job that ended without its answer."""
        ending = job.ending
        if ending is Ending.TIMED_OUT:
            if not job.sent and self._state is ClientState.RECONNECTING:
                return FocasConnectionError(self._still_reconnecting())
            return no_answer_error(job.part.function, None, job.sent)
        if ending is Ending.REFUSED:
            return CncError.from_ew(job.ew, "error answer (0x2103) to the request frame")
        if ending is Ending.STALE:
            return FocasConnectionError("the CNC's command set changed on reconnect; call again")
        if self._state is ClientState.CLOSED:
            return self._closed()
        if self._violation is not None:
            return ProtocolError(str(self._violation))
        if job.sent:
            return FocasConnectionError(self._why)
        return NotSentError(f"{self._why} {NEVER_SENT}")
