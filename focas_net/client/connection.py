"""One pipelined connection to a packed-protocol peer: request ids, answers, timeouts.

:class:`Connection` is an :class:`asyncio.Protocol`, read through :mod:`focas_net._receive`.
It only pumps frames: a call registers a future under a fresh request id, the frame goes out,
and :meth:`Connection.data_received` resolves the future whose id the answer carries. There is
no task per request.

Rules it keeps:

* a request id is never reused while a request with that id may still be answered: an id whose
  caller gave up (timeout or cancellation) stays reserved until its late answer arrives, and the
  late answer is dropped, so no caller ever receives another call's answer;
* at most ``max_in_flight`` calls wait for answers at once (a counter, and a first-in first-out
  line of waiters when every slot is taken; the wait for a slot counts towards the call's
  deadline); a slot is freed once, when its request leaves the table of requests in flight
  (answered, failed by its answer, given up by its caller, failed by a close), and goes
  straight to the first in line;
* one timer per connection, armed no later than the earliest deadline of the requests in
  flight, fails every overdue request when it fires and is armed again for the earliest
  deadline left (a request costs no bookkeeping of its own for its deadline);
* when the connection is lost, every pending call fails at once with
  :class:`FocasConnectionError`;
* when the peer breaks the framing (a length prefix outside ``4..max_frame``: a peer that is
  not a FOCAS server, an HTTP server for example), the connection is aborted and every pending
  call fails with :class:`ProtocolError` naming the peer and what it sent
  (:attr:`Connection.violation`); the client does not reconnect after it;
* a lone request (nothing else in flight) is written at once; frames written while others are
  in flight are gathered during the event-loop turn and leave together, in writes of
  :data:`WRITE_CHUNK` frames at most (so that the peer starts answering the first of them
  while this turn's callers are still making the rest);
* :class:`asyncio.CancelledError` is never swallowed.

Transport exceptions are translated here, once: callers see :class:`FocasConnectionError`
(never a bare :class:`OSError`) and :class:`FocasTimeoutError`.
"""

from __future__ import annotations

import asyncio
import logging
import ssl as _ssl
from collections.abc import Callable, Sequence
from typing import Final, cast

from focas_net._address import address_text
from focas_net._receive import Received
from focas_net._typed import field_unfit
from focas_net.errors import (
    FocasConnectionError,
    FocasError,
    FocasTimeoutError,
    FrameError,
    ProtocolError,
)

from ..protocol import (
    COMMANDS,
    DEFAULT_MAX_FRAME,
    HEADER,
    Command,
    FrameDecoder,
    PathNumber,
    RawFrame,
)
from ._channel import connect_socket, literal_target
from ._failures import (
    NEVER_SENT,
    closed_error,
    command_text,
    connect_error,
    lost_error,
    no_answer_error,
    violation_error,
)
from ._settle import settled as _settled
from ._slots import RequestSlots

__all__ = ["Connection", "NotSentError", "open_connection"]

logger = logging.getLogger(__name__)

#: Reserved ids of abandoned requests a connection tolerates before it is recycled (a peer
#: that stopped answering would otherwise exhaust the 16-bit id space).
MAX_ABANDONED: Final = 16_384
#: Most calls one connection may have waiting for an answer (``max_in_flight``): with the
#: abandoned ids and the overshoot of a chunked batch it stays well inside the 65,536 ids.
MAX_IN_FLIGHT: Final = 32_768
#: Most frames gathered in one loop turn that leave in one write (see the module docstring).
WRITE_CHUNK: Final = 16
_ID_MASK: Final = 0xFFFF
_HEADER: Final = HEADER
_pack_header = HEADER.pack
_unpack_header_from = HEADER.unpack_from
_INF: Final = float("inf")
_SETPATH: Final = COMMANDS[Command.SETPATH]
#: The answer of an accepted ``cnc_setpath``.
_PATH_OK: Final = b"\x00\x00"


class NotSentError(FocasConnectionError):
    """The connection closed before this call's request was written: the peer never saw it.

    A call failing this way is safe to send again on a new connection.
    """


#: An unanswered request: ``(future, command, request_id, deadline)``, the future of its
#: answer, the command that answer must carry, its id and its deadline (``loop.time()`` units;
#: infinite for none). A plain tuple: made once per call, it is the cheapest record there is.
_Pending = tuple["asyncio.Future[bytes]", int, int, float]


def _timed_out(entry: _Pending, silent_peer: str | None) -> None:
    """Fail ``entry`` for its deadline (``silent_peer``: the peer, when the connection never
    received a byte)."""
    future, command, _, _ = entry
    future.set_exception(no_answer_error(command_text(command), silent_peer))


class Connection(RequestSlots, Received, asyncio.Protocol):
    """A pipelined packed-protocol connection (create it with :func:`open_connection`).

    ``on_lost(connection, exc)`` is called once when the connection goes away, after every
    pending call has been failed.
    """

    def __init__(
        self,
        *,
        max_in_flight: int = 64,
        max_frame: int = DEFAULT_MAX_FRAME,
        on_lost: Callable[[Connection, BaseException | None], None] | None = None,
        batch_writes: bool = True,
    ) -> None:
        why = field_unfit("max_in_flight", max_in_flight, 1, MAX_IN_FLIGHT)
        if why is not None:
            raise ValueError(why)
        self._loop = asyncio.get_running_loop()
        self._decoder = FrameDecoder(max_frame)
        self._max_frame = max_frame
        self._held = self._decoder.held  # the start of a frame the decoder holds
        self._transport: asyncio.Transport | None = None
        # request id -> pending call, or None for an abandoned id awaiting its late answer
        self._pending: dict[int, _Pending | None] = {}
        self._abandoned = 0
        self._next_id = 0
        self._init_slots(max_in_flight)
        # One timer per connection, armed (at _timer_when; infinite: none) no later than the
        # earliest deadline of the requests in flight. Requests are not tracked one by one:
        # the timer, when it fires, looks at those in flight then (see _expire).
        self._timer: asyncio.TimerHandle | None = None
        self._timer_when = _INF
        self._wbuf: list[bytes] = []
        self._batch = batch_writes
        self._closed_exc: FocasConnectionError | None = None
        self._lost: asyncio.Future[None] = self._loop.create_future()
        self._on_lost = on_lost
        self._violation: ProtocolError | None = None
        self._answered = False  # any byte received yet
        self._tls = False  # a TLS connection
        self.peer: str = "?"
        #: The path the peer answers this connection's per-path requests for, as far as what
        #: was sent on it tells: 1 when it opens, then the path of the last ``cnc_setpath``
        #: sent (see :meth:`select_path`).
        self.path = 1

    # -- state ---------------------------------------------------------------------------
    @property
    def closed(self) -> bool:
        """True once the connection is closing or closed."""
        return self._closed_exc is not None

    @property
    def end(self) -> FocasConnectionError | None:
        """Why the connection ended, in the words its calls get (None: open)."""
        return self._closed_exc

    @property
    def violation(self) -> ProtocolError | None:
        """Why the connection was aborted, when the peer broke the wire protocol."""
        return self._violation

    @property
    def in_flight(self) -> int:
        """Calls waiting for an answer."""
        return len(self._pending) - self._abandoned

    @property
    def abandoned(self) -> int:
        """Ids reserved for requests whose callers gave up (their answers will be dropped)."""
        return self._abandoned

    # -- asyncio.Protocol ----------------------------------------------------------------
    def connection_made(self, transport: asyncio.BaseTransport) -> None:
        # uvloop's transports implement the interface without subclassing asyncio.Transport
        self._transport = cast(asyncio.Transport, transport)
        self._tls = transport.get_extra_info("ssl_object") is not None
        peer = transport.get_extra_info("peername")
        if peer:
            self.peer = address_text(peer[0], peer[1])

    def data_received(self, data: bytes | bytearray | memoryview) -> None:
        self._answered = True
        pending = self._pending
        live = len(pending) - self._abandoned  # the slots of those answered are freed below
        if type(data) is bytes and self._violation is None and not self._held:
            # The usual read: whole frames, each answer handed to its caller as it is parsed
            # (no list of frames in between). What is left, a frame not yet complete or a
            # length out of bounds, goes through the decoder as below.
            size = len(data)
            pos = 0
            max_frame = self._max_frame
            while size - pos >= 8:
                length, command, request_id = _unpack_header_from(data, pos)
                end = pos + 4 + length
                if length < 4 or length > max_frame or end > size:
                    break
                entry = pending.pop(request_id, _MISSING)
                if type(entry) is tuple and command == entry[1]:
                    try:
                        entry[0].set_result(data[pos + 8 : end])
                    except asyncio.InvalidStateError:
                        pass  # its call already ended (timed out, cancelled), not yet finished
                else:
                    self._unmatched(entry, command, request_id)
                pos = end
            if pos == size:
                freed = live - len(pending) + self._abandoned
                if self._slot_waiters:
                    self._release_slots(freed)
                else:
                    self._slots_taken -= freed  # (what _release_slots does with nobody waiting)
                return
            data = data[pos:]
        try:
            frames = self._decoder.feed_raw(data)
        except FrameError as exc:
            self._deliver(exc.frames)  # answers that arrived whole before the violation
            self._release_slots(live - self.in_flight)
            violation = violation_error(self.peer, exc, bytes(data[:16]), self._max_frame)
            logger.warning("closing connection to %s: %s", self.peer, violation)
            self._violation = violation
            self._abort(violation)
            return
        self._deliver(frames)
        self._release_slots(live - self.in_flight)

    def _deliver(self, frames: list[RawFrame]) -> None:
        pending = self._pending
        for command, request_id, payload in frames:
            entry = pending.pop(request_id, _MISSING)
            if type(entry) is tuple and command == entry[1]:
                try:
                    entry[0].set_result(payload)
                except asyncio.InvalidStateError:
                    pass  # its call already ended (timed out, cancelled), not yet finished
            else:
                self._unmatched(entry, command, request_id)

    def _unmatched(self, entry: _Pending | _Missing | None, command: int, request_id: int) -> None:
        """An answer that completes no call as it is: one carrying another command than its
        request (the call fails, unless it already ended), a late answer to an id whose caller
        gave up (dropped, the id free again) or one to an id nobody sent (dropped)."""
        if type(entry) is tuple:
            future, expected = entry[0], entry[1]
            if not future.done():
                future.set_exception(
                    ProtocolError(
                        f"{self.peer} answered {command_text(expected)} with an answer of "
                        f"{command_text(command)} (request {request_id})"
                    )
                )
        elif entry is None:
            self._abandoned -= 1
            logger.debug("dropped late answer to request %d", request_id)
        else:
            logger.debug("dropped unsolicited frame (command 0x%04X, id %d)", command, request_id)

    def connection_lost(self, exc: Exception | None) -> None:
        if self._closed_exc is None:
            self._closed_exc = lost_error(self.peer, exc, self._answered, self._tls)
        self._transport = None
        self._fail_all()
        if not self._lost.done():
            self._lost.set_result(None)
        if self._on_lost is not None:
            callback, self._on_lost = self._on_lost, None
            try:
                callback(self, exc)
            except Exception:
                logger.exception("connection-lost callback failed")

    def eof_received(self) -> bool | None:
        # The peer ended its stream: the transport closes now and connection_lost follows on
        # a later loop turn. Calls made until then must not be written into the closing
        # transport (where they would vanish and fail as maybe sent): they fail as not sent.
        if self._closed_exc is None:
            self._closed_exc = closed_error(self.peer, self._answered, self._tls)
        return None  # close the transport

    # -- requests ------------------------------------------------------------------------
    async def request(
        self, command: int, payload: bytes, deadline: float | None, path: int = 0
    ) -> bytes:
        """Send one request and return the payload of its answer (for a per-path request,
        ``path`` 1..10: after a ``cnc_setpath`` when the connection's :attr:`path` is another
        at the moment it leaves; 0: a request of no path).

        ``deadline`` is in ``loop.time()`` units (None: wait for ever). Raises
        :class:`FocasTimeoutError` when it passes, :class:`FocasConnectionError` when the
        connection is lost first (:class:`NotSentError` if the request never left), and
        :class:`ProtocolError` for an answer carrying the wrong command.
        """
        if path and path != self.path:
            self.select_path(path, deadline)
        entry = self.try_send(command, payload, deadline)
        if entry is None:
            await self._wait_for_slot(command, deadline)
            if path and path != self.path:  # another path was selected meanwhile
                self.select_path(path, deadline)
            entry = self.try_send(command, payload, deadline, slot_taken=True)
            assert entry is not None  # sent in the slot taken, or raised
        try:
            return await entry[0]
        finally:
            self.finish(entry)

    def try_send(
        self, command: int, payload: bytes, deadline: float | None, slot_taken: bool = False
    ) -> _Pending | None:  # (slot_taken is not keyword-only: such a default costs every call)
        """:meth:`request` without its coroutine, for a caller that awaits the answer itself.

        With a slot free and nobody waiting for one, the request is registered and sent and
        its entry returned: the caller awaits the entry's future (``entry[0]``) and calls
        :meth:`finish` with the entry unless the future gave its result (a timeout, a
        cancellation, a failure: the request's slot and id are settled there). With no slot free
        it returns None and takes nothing: the caller uses :meth:`request`. Raises
        :class:`NotSentError` when the connection is closed (nothing taken). With
        ``slot_taken`` the caller already holds a slot (it waited for one): the request is
        sent in it, and the slot is released if that fails.
        """
        if self._closed_exc is not None:
            if slot_taken:
                self._release_slot()
            raise NotSentError(str(self._closed_exc))
        if not slot_taken:
            if self._slots_taken >= self._max_in_flight or self._slot_waiters:
                return None
            self._slots_taken += 1  # a free slot: taken without suspending
        # Register and send (the usual case of _write inlined: one call per request costs),
        # the slot released on failure.
        entry: _Pending | None = None
        try:
            pending = self._pending
            request_id = self._next_id
            while request_id in pending:
                request_id = (request_id + 1) & _ID_MASK
            self._next_id = (request_id + 1) & _ID_MASK
            future: asyncio.Future[bytes] = self._loop.create_future()
            when = _INF if deadline is None else deadline
            # (entry is set once it is registered: until then a failure releases the slot)
            pending[request_id] = entry = (future, command, request_id, when)
            frame = _pack_header(len(payload) + 4, command, request_id) + payload
            buf = self._wbuf
            if buf:
                # Others in flight: frames written during this loop turn leave together, in
                # writes of WRITE_CHUNK frames at most, so that the peer starts on the first
                # ones while the callers of this turn are still making the rest.
                buf.append(frame)
                if len(buf) >= WRITE_CHUNK:
                    self._flush()
            elif self._batch and len(pending) - self._abandoned > 1:
                buf.append(frame)  # the first frame of this loop turn's
                self._loop.call_soon(self._flush)
            else:
                # A lone request (sequential use) goes out at once.
                assert self._transport is not None
                self._transport.write(frame)
            if when < self._timer_when:
                self._arm(when)  # else the timer armed for an earlier one covers it
        except BaseException:
            if entry is None:
                self._release_slot()
            else:
                self.finish(entry)
            raise
        return entry

    def select_path(self, path: int, deadline: float | None) -> None:
        """Send ``cnc_setpath(path)`` now, so that the requests sent after it are answered
        for ``path`` (the peer applies a connection's requests in the order they arrive), and
        make ``path`` the connection's :attr:`path`.

        It takes a request slot of its own, beyond ``max_in_flight`` if need be (as a batch
        does), and nobody awaits its answer: an answer other than ``EW_OK`` (``EW_PATH``: the
        peer has no such path) is logged, and the peer then answers ``EW_PATH`` to every
        per-path request until the next accepted ``cnc_setpath``, so no request sent behind
        it reads another path. Raises :class:`NotSentError` when the connection is closed.
        """
        if self._closed_exc is not None:
            raise NotSentError(str(self._closed_exc))
        self._slots_taken += 1  # a slot of its own, beyond the bound if need be
        entry = self.try_send(
            _SETPATH.command, _SETPATH.request.encode(PathNumber(path)), deadline, True
        )
        assert entry is not None
        self.path = path
        entry[0].add_done_callback(lambda future: self._path_answered(entry, path, future))

    def _path_answered(self, entry: _Pending, path: int, future: asyncio.Future[bytes]) -> None:
        """The answer of a ``cnc_setpath`` (see :meth:`select_path`): logged unless EW_OK."""
        self.finish(entry)
        if future.cancelled():
            return
        exc = future.exception()
        if exc is not None:
            logger.debug("%s: cnc_setpath(%d) got no answer: %s", self.peer, path, exc)
            return
        answer = future.result()
        if answer != _PATH_OK:
            logger.warning(
                "%s: cnc_setpath(%d) refused (%s): per-path calls on it answer EW_PATH",
                self.peer,
                path,
                answer.hex(" "),
            )

    def finish(self, entry: _Pending) -> None:
        """The caller of ``entry`` (from :meth:`try_send`) stopped waiting: if the request is
        still unanswered its id stays reserved (its late answer is dropped) and its slot is
        released. An entry that left the table (answered, failed by the answer or by a close)
        freed its slot then, and this does nothing: a caller whose future gave its result may
        skip it."""
        request_id = entry[2]
        if self._pending.get(request_id) is entry:
            self._give_up(request_id)
            self._release_slot()

    async def request_all(
        self,
        command: int,
        payloads: Sequence[bytes],
        deadline: float | None,
        failed: Callable[[bytes], bool] | None = None,
    ) -> list[bytes | None]:
        """Send one request per payload in one write and return their answers, in order.

        The batch is admitted like one call (it waits in line for a free slot) and then takes
        one slot per request at once: while it is in flight the connection may carry up to
        ``len(payloads) - 1`` requests more than ``max_in_flight``, and no other call is
        admitted until the count is back under the bound. On the first request that fails
        (the exceptions of :meth:`request`), or whose answer ``failed(answer)`` rejects, the
        others are given up (their ids stay reserved until their late answers) and the
        failure is raised, or the answers are returned with None for those given up.
        """
        count = len(payloads)
        await self._admit(command, count, deadline)
        entries: list[_Pending] = []
        try:
            self._send_batch(command, payloads, deadline, entries)
            await _settled(self._loop, entries, True, failed)
            answers: list[bytes | None] = []
            failure: BaseException | None = None
            for entry in entries:
                future = entry[0]
                if not future.done() or future.cancelled():
                    answers.append(None)
                    continue
                exc = future.exception()  # every failure is retrieved; the first is raised
                if exc is None:
                    answers.append(future.result())
                elif failure is None:
                    failure = exc
            if failure is not None:
                raise failure
            return answers
        finally:
            self._end_batch(entries, count)

    async def request_each(
        self, command: int, payloads: Sequence[bytes], deadline: float | None
    ) -> list[bytes | BaseException]:
        """Send one request per payload in one write and wait for every one of them.

        Admitted and bounded like :meth:`request_all`, but no request is given up when
        another fails: the result holds, in order, each request's answer or the exception it
        ended with (:class:`FocasTimeoutError`, :class:`FocasConnectionError` when the
        connection was lost after the request left, :class:`NotSentError` when it was lost
        before, :class:`ProtocolError`). Raises only when nothing was sent: no free slot
        before ``deadline`` (:class:`FocasTimeoutError`), the connection already closed
        (:class:`NotSentError`), or the caller cancelled while waiting for a slot. A caller
        cancelled after sending gives up every request still unanswered (their ids stay
        reserved until their late answers).
        """
        count = len(payloads)
        await self._admit(command, count, deadline)
        entries: list[_Pending] = []
        try:
            self._send_batch(command, payloads, deadline, entries)
            await _settled(self._loop, entries, False, None)
            results: list[bytes | BaseException] = []
            for entry in entries:
                future = entry[0]
                exc = future.exception()
                results.append(future.result() if exc is None else exc)
            return results
        finally:
            self._end_batch(entries, count)

    def _send_batch(
        self,
        command: int,
        payloads: Sequence[bytes],
        deadline: float | None,
        entries: list[_Pending],
    ) -> None:
        """Register one request per payload (appended to ``entries``) and write them all at
        once, behind any frames of this loop turn not flushed yet."""
        if self._closed_exc is not None:
            raise NotSentError(str(self._closed_exc))
        loop = self._loop
        pending = self._pending
        frames: list[bytes] = []
        request_id = self._next_id
        when = _INF if deadline is None else deadline
        for payload in payloads:
            while request_id in pending:
                request_id = (request_id + 1) & _ID_MASK
            entry = (loop.create_future(), command, request_id, when)
            pending[request_id] = entry
            entries.append(entry)
            frames.append(_pack_header(len(payload) + 4, command, request_id) + payload)
            request_id = (request_id + 1) & _ID_MASK
        self._next_id = request_id
        if self._wbuf:
            self._wbuf.extend(frames)  # flushed together by the call already scheduled
        else:
            assert self._transport is not None
            self._transport.write(b"".join(frames))
        if deadline is not None and deadline < self._timer_when:
            self._arm(deadline)

    def _end_batch(self, entries: list[_Pending], count: int) -> None:
        """Give up the requests of a batch still unanswered and release their slots (those
        answered freed theirs then), and the slots of requests of it never registered."""
        for entry in entries:
            future = entry[0]
            if not future.done():
                future.cancel()
            elif not future.cancelled():
                future.exception()  # retrieved, so that no failure is reported as unseen
            # (looked up afresh: a give-up crossing MAX_ABANDONED closes the connection, whose
            # close frees the slots of every request then in flight)
            self.finish(entry)
        self._release_slots(count - len(entries))

    def _give_up(self, request_id: int) -> None:
        """The caller of ``request_id`` stopped waiting (timeout or cancellation)."""
        if self._closed_exc is None:
            # Keep the id reserved until the late answer arrives so that it can never reach
            # another call.
            self._pending[request_id] = None
            self._abandoned += 1
            if self._abandoned > MAX_ABANDONED:
                self._abort(
                    FocasConnectionError(f"{self._abandoned} requests unanswered; recycling")
                )
        else:
            # Closed: the pending table was replaced when every call was failed (possibly by
            # an earlier give-up of this same batch crossing MAX_ABANDONED).
            self._pending.pop(request_id, None)

    # -- deadlines -----------------------------------------------------------------------
    def _arm(self, when: float) -> None:
        """Have the timer fire at ``when`` (earlier than it is armed for, or not armed)."""
        if self._timer is not None:
            self._timer.cancel()
        self._timer_when = when
        self._timer = self._loop.call_at(when, self._expire)

    def _expire(self) -> None:
        """Fail every request in flight whose deadline passed; arm the timer for the
        earliest deadline left. While answers flow it fires about once a timeout (armed for
        the deadline of a request long answered, it finds the next one's) and looks at no
        more requests than are in flight then."""
        self._timer = None
        self._timer_when = _INF
        now = self._loop.time()
        nxt = _INF
        # (a future's callbacks run on a later loop turn: failing one changes no entry here)
        for entry in self._pending.values():
            if entry is None or entry[0].done():
                continue  # an abandoned id awaiting its late answer, or a call just ended
            deadline = entry[3]
            if deadline <= now:
                _timed_out(entry, None if self._answered else self.peer)
            elif deadline < nxt:
                nxt = deadline
        if nxt != _INF and self._closed_exc is None:
            self._arm(nxt)

    def _write(self, frame: bytes) -> None:
        buf = self._wbuf
        if not self._batch or (not buf and len(self._pending) - self._abandoned <= 1):
            # A lone request (sequential use) goes out at once; when others are in flight,
            # frames written during this loop turn are flushed together.
            assert self._transport is not None
            self._transport.write(frame)
            return
        buf.append(frame)
        if len(buf) == 1:
            self._loop.call_soon(self._flush)

    def _flush(self) -> None:
        buf = self._wbuf
        if not buf:
            return
        transport = self._transport
        if transport is None or transport.is_closing() or self._closed_exc is not None:
            return  # never sent: connection_lost fails these calls with NotSentError
        if len(buf) == 1:
            transport.write(buf[0])
        else:
            transport.writelines(buf)
        buf.clear()

    # -- closing -------------------------------------------------------------------------
    def _fail_all(self) -> None:
        live = self.in_flight
        pending, self._pending = self._pending, {}
        self._abandoned = 0
        if self._timer is not None:
            self._timer.cancel()
            self._timer = None
            self._timer_when = _INF
        # Frames still in the write buffer never reached the peer.
        unsent = {_HEADER.unpack_from(frame)[2] for frame in self._wbuf}
        self._wbuf.clear()
        reason = self._closed_exc
        violation = self._violation
        for request_id, entry in pending.items():
            if entry is not None and not entry[0].done():
                err: FocasError
                if violation is not None:
                    err = ProtocolError(str(violation))
                    err.__cause__ = violation
                else:
                    err = (
                        NotSentError(f"{reason} {NEVER_SENT}")
                        if request_id in unsent
                        else FocasConnectionError(str(reason))
                    )
                    err.__cause__ = reason
                entry[0].set_exception(err)
        self._release_slots(live)  # the calls in flight end here, and so do their slots

    def _abort(self, exc: BaseException) -> None:
        if self._closed_exc is None:
            self._closed_exc = lost_error(self.peer, exc, self._answered, self._tls)
        self._fail_all()
        if self._transport is not None:
            self._transport.abort()

    def close(self) -> None:
        """Start closing: every pending call fails with :class:`FocasConnectionError`."""
        if self._closed_exc is None:
            self._closed_exc = FocasConnectionError(f"connection to {self.peer} closed")
        self._fail_all()
        if self._transport is not None:
            self._flush()
            self._transport.close()

    def abort(self) -> None:
        """Close at once, discarding unsent data."""
        self._abort(FocasConnectionError(f"connection to {self.peer} aborted"))

    async def wait_closed(self) -> None:
        """Wait until the transport has gone (``connection_lost`` ran)."""
        await asyncio.shield(self._lost)


class _Missing:
    pass


_MISSING: Final = _Missing()


async def open_connection(
    host: str,
    port: int,
    *,
    deadline: float | None = None,
    max_in_flight: int = 64,
    max_frame: int = DEFAULT_MAX_FRAME,
    ssl: _ssl.SSLContext | None = None,
    server_hostname: str | None = None,
    on_lost: Callable[[Connection, BaseException | None], None] | None = None,
    batch_writes: bool = True,
) -> Connection:
    """Connect to ``host:port`` and return the :class:`Connection`.

    Every failure to connect is :class:`FocasConnectionError` (or :class:`FocasTimeoutError`
    when ``deadline`` passes first).
    """
    loop = asyncio.get_running_loop()

    def factory() -> Connection:
        return Connection(
            max_in_flight=max_in_flight,
            max_frame=max_frame,
            on_lost=on_lost,
            batch_writes=batch_writes,
        )

    hostname = (server_hostname or host) if ssl is not None else None
    try:
        async with asyncio.timeout_at(deadline):
            if literal_target(host, port) is not None:  # an IPv4 address: one address to connect
                _, protocol = await loop.create_connection(
                    factory, host, port, ssl=ssl, server_hostname=hostname
                )
            else:  # each address in turn, as the native client does, and said alike
                sock = await connect_socket(host, port)
                try:
                    _, protocol = await loop.create_connection(
                        factory, sock=sock, ssl=ssl, server_hostname=hostname
                    )
                except BaseException:
                    sock.close()
                    raise
    except TimeoutError:
        raise FocasTimeoutError(f"connecting to {address_text(host, port)} timed out") from None
    except (OSError, _ssl.SSLError) as exc:
        raise connect_error(host, port, exc, ssl) from exc
    except UnicodeError as exc:  # the idna codec refusing a host name (a label over 63)
        raise FocasConnectionError(
            f"cannot connect to {address_text(host, port)}: not a valid host name ({exc})"
        ) from exc
    return protocol
