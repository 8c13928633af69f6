"""One pipelined connection to a packed-protocol peer: request ids, answers, timeouts.

:class:`Connection` is an :class:`asyncio.Protocol`. It only pumps frames: a call registers a
future under a fresh request id, the frame goes out, and :meth:`Connection.data_received`
resolves the future whose id the answer carries. There is no task per request.

Rules it keeps:

* a request id is never reused while a request with that id may still be answered: an id whose
  caller gave up (timeout or cancellation) stays reserved until its late answer arrives, and the
  late answer is dropped, so no caller ever receives another call's answer;
* at most ``max_in_flight`` calls wait for answers at once (a semaphore; the wait for a slot
  counts towards the call's deadline);
* when the connection is lost, every pending call fails at once with
  :class:`FocasConnectionError`;
* frames written during one event-loop turn leave in one ``transport.writelines`` call;
* :class:`asyncio.CancelledError` is never swallowed.

Transport exceptions are translated here, once: callers see :class:`FocasConnectionError`
(never a bare :class:`OSError`) and :class:`FocasTimeoutError`.
"""

from __future__ import annotations

import asyncio
import logging
import ssl as _ssl
from collections.abc import Callable
from typing import Final, cast

from ..protocol import (
    DEFAULT_MAX_FRAME,
    HEADER,
    FocasConnectionError,
    FocasTimeoutError,
    Frame,
    FrameDecoder,
    FrameError,
    ProtocolError,
    encode_frame,
)

__all__ = ["Connection", "NotSentError", "open_connection"]

logger = logging.getLogger(__name__)

#: Reserved ids of abandoned requests a connection tolerates before it is recycled (a peer
#: that stopped answering would otherwise exhaust the 16-bit id space).
MAX_ABANDONED: Final = 16_384
_ID_MASK: Final = 0xFFFF
_HEADER: Final = HEADER


class NotSentError(FocasConnectionError):
    """The connection closed before this call's request was written: the peer never saw it.

    A call failing this way is safe to send again on a new connection.
    """


class _Pending:
    """An unanswered request: its future and the command its answer must carry."""

    __slots__ = ("command", "future")

    def __init__(self, future: asyncio.Future[bytes], command: int) -> None:
        self.future = future
        self.command = command


def _expire(future: asyncio.Future[bytes], command: int, request_id: int) -> None:
    if not future.done():
        future.set_exception(
            FocasTimeoutError(f"no answer to command 0x{command:04X} (request {request_id})")
        )


class Connection(asyncio.Protocol):
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
        if max_in_flight < 1:
            raise ValueError(f"max_in_flight must be at least 1, got {max_in_flight}")
        self._loop = asyncio.get_running_loop()
        self._decoder = FrameDecoder(max_frame)
        self._transport: asyncio.Transport | None = None
        # request id -> pending call, or None for an abandoned id awaiting its late answer
        self._pending: dict[int, _Pending | None] = {}
        self._abandoned = 0
        self._next_id = 0
        self._slots = asyncio.Semaphore(max_in_flight)
        self._wbuf: list[bytes] = []
        self._batch = batch_writes
        self._closed_exc: FocasConnectionError | None = None
        self._lost: asyncio.Future[None] = self._loop.create_future()
        self._on_lost = on_lost
        self.peer: str = "?"

    # -- state ---------------------------------------------------------------------------
    @property
    def closed(self) -> bool:
        """True once the connection is closing or closed."""
        return self._closed_exc is not None

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
        peer = transport.get_extra_info("peername")
        if peer:
            self.peer = f"{peer[0]}:{peer[1]}"

    def data_received(self, data: bytes) -> None:
        try:
            frames = self._decoder.feed(data)
        except FrameError as exc:
            self._deliver(exc.frames)  # answers that arrived whole before the violation
            logger.warning("closing connection to %s: %s", self.peer, exc)
            self._abort(exc)
            return
        self._deliver(frames)

    def _deliver(self, frames: list[Frame]) -> None:
        pending = self._pending
        for command, request_id, payload in frames:
            entry = pending.pop(request_id, _MISSING)
            if isinstance(entry, _Pending):
                future = entry.future
                if future.done():
                    continue
                if command == entry.command:
                    future.set_result(payload)
                else:
                    future.set_exception(
                        ProtocolError(
                            f"answer to request {request_id} carries command 0x{command:04X}, "
                            f"expected 0x{entry.command:04X}"
                        )
                    )
            elif entry is None:
                self._abandoned -= 1
                logger.debug("dropped late answer to request %d", request_id)
            else:
                logger.debug(
                    "dropped unsolicited frame (command 0x%04X, id %d)", command, request_id
                )

    def connection_lost(self, exc: Exception | None) -> None:
        if self._closed_exc is None:
            self._closed_exc = _lost_error(self.peer, exc)
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
        return None  # close the transport

    # -- requests ------------------------------------------------------------------------
    async def request(self, command: int, payload: bytes, deadline: float | None) -> bytes:
        """Send one request and return the payload of its answer.

        ``deadline`` is in ``loop.time()`` units (None: wait for ever). Raises
        :class:`FocasTimeoutError` when it passes, :class:`FocasConnectionError` when the
        connection is lost first (:class:`NotSentError` if the request never left), and
        :class:`ProtocolError` for an answer carrying the wrong command.
        """
        slots = self._slots
        if slots.locked():
            try:
                async with asyncio.timeout_at(deadline):
                    await slots.acquire()
            except TimeoutError:
                raise FocasTimeoutError(
                    f"no free request slot for command 0x{command:04X} in time"
                ) from None
        else:
            await slots.acquire()  # uncontended: returns without suspending
        try:
            if self._closed_exc is not None:
                raise NotSentError(str(self._closed_exc))
            pending = self._pending
            request_id = self._next_id
            while request_id in pending:
                request_id = (request_id + 1) & _ID_MASK
            self._next_id = (request_id + 1) & _ID_MASK
            future: asyncio.Future[bytes] = self._loop.create_future()
            entry = _Pending(future, command)
            pending[request_id] = entry
            self._write(encode_frame(command, request_id, payload))
            timer = (
                None
                if deadline is None
                else self._loop.call_at(deadline, _expire, future, command, request_id)
            )
            try:
                return await future
            finally:
                if timer is not None:
                    timer.cancel()
                if pending.get(request_id) is entry:
                    if self._closed_exc is None:
                        # Gave up (timeout or cancellation): keep the id reserved until the
                        # late answer arrives so that it can never reach another call.
                        pending[request_id] = None
                        self._abandoned += 1
                        if self._abandoned > MAX_ABANDONED:
                            self._abort(
                                FocasConnectionError(
                                    f"{self._abandoned} requests unanswered; recycling"
                                )
                            )
                    else:
                        del pending[request_id]
        finally:
            slots.release()

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
        if transport is None or transport.is_closing():
            buf.clear()
            return
        if len(buf) == 1:
            transport.write(buf[0])
        else:
            transport.writelines(buf)
        buf.clear()

    # -- closing -------------------------------------------------------------------------
    def _fail_all(self) -> None:
        pending, self._pending = self._pending, {}
        self._abandoned = 0
        # Frames still in the write buffer never reached the peer.
        unsent = {_HEADER.unpack_from(frame)[2] for frame in self._wbuf}
        self._wbuf.clear()
        reason = self._closed_exc
        for request_id, entry in pending.items():
            if entry is not None and not entry.future.done():
                kind = NotSentError if request_id in unsent else FocasConnectionError
                err = kind(f"request {request_id}: {reason}")
                err.__cause__ = reason
                entry.future.set_exception(err)

    def _abort(self, exc: BaseException) -> None:
        if self._closed_exc is None:
            self._closed_exc = _lost_error(self.peer, exc)
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


def _lost_error(peer: str, exc: BaseException | None) -> FocasConnectionError:
    if isinstance(exc, FocasConnectionError):
        return exc
    text = f"connection to {peer} lost" + (f": {exc}" if exc else "")
    err = FocasConnectionError(text)
    err.__cause__ = exc
    return err


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

    try:
        async with asyncio.timeout_at(deadline):
            _, protocol = await loop.create_connection(
                factory,
                host,
                port,
                ssl=ssl,
                server_hostname=(server_hostname or host) if ssl is not None else None,
            )
    except TimeoutError:
        raise FocasTimeoutError(f"connecting to {host}:{port} timed out") from None
    except (OSError, _ssl.SSLError) as exc:
        raise FocasConnectionError(f"cannot connect to {host}:{port}: {exc}") from exc
    return protocol
