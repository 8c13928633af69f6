"""What every connection of the listener shell shares, whichever protocol it speaks.

A connection is an :class:`asyncio.Protocol` read into the thread's receive buffer
(:mod:`focas_net._receive`, taken once when the connection is made, in its event loop's
thread): no task per connection, no task per request. It holds a frozen
:class:`Limits`, the machine-wide fault queue, its own fault queue (armed by its own requests)
and a close callback; it never sees the server. The shell (``_server.py``) accepts, counts,
sweeps idle connections and shuts down; the protocol modules (``_packed.py`` for
``docs/protocol.md``, ``_native.py`` for ``docs/native-protocol.md``) decode frames and answer
them. This module holds the machinery in between:

* **Input in slices.** Input is decoded at most :data:`SLICE` bytes at a time; when output
  backpressure stops the answering part way, the requests not answered yet and the bytes not
  decoded yet are held in a backlog (bounded by one read of the transport) and reading pauses.
* **Backpressure.** Reading stops while the transport's write buffer is above its high-water
  mark (``pause_writing``) or while the connection holds ``max_delayed`` delayed answers, and
  resumes when the buffer drained (``resume_writing``) or half the delayed answers went out. A
  peer that never reads therefore cannot grow the server's memory beyond one read chunk's
  answers plus the write buffer's high-water mark.
* **Fault injection** (``docs/protocol.md`` section 4, queues in :mod:`.faults`): the fault for
  the next answer (the connection's own first, then the machine's), a delayed answer (a timer
  callback), an answer written one byte per write, a connection dropped instead of answering.
* **Shutdown**, driven by the shell: stop reading, answer what is held, close.
"""

from __future__ import annotations

import asyncio
import logging
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Final, Generic, TypeVar, cast

from focas_net._receive import Received, receive_buffer
from focas_net._tls import ssl_error_text
from focas_net.native import DEFAULT_MAX_BODY
from focas_net.protocol import DEFAULT_MAX_FRAME

from .faults import FaultKind, FaultQueue

__all__ = [
    "DEFAULT_MAX_DELAYED",
    "DEFAULT_WRITE_BUFFER_HIGH",
    "NATIVE_MAGIC_LENGTH",
    "SLICE",
    "BaseConnection",
    "CloseCallback",
    "Limits",
    "peer_text",
]

_log = logging.getLogger("focas_net.server")

#: Delayed answers one connection may hold before the server stops reading from it.
DEFAULT_MAX_DELAYED: Final = 1024
#: High-water mark of each connection's write buffer; above it the server stops reading.
DEFAULT_WRITE_BUFFER_HIGH: Final = 64 * 1024
#: The first four bytes of a native frame (``A0 A0 A0 A0``) read as a packed little-endian
#: length: ``max_frame`` stays below it, so the two protocols can share a port.
NATIVE_MAGIC_LENGTH: Final = 0xA0A0A0A0
#: Input is decoded at most this many bytes at a time, so that output backpressure can stop
#: the answering between slices.
SLICE: Final = 16 * 1024


@dataclass(frozen=True, slots=True)
class Limits:
    """The bounds every connection of a server works within (validated by the server).

    ``max_frame``: the largest packed length prefix (``docs/protocol.md`` section 1);
    ``max_body``: the largest native frame body (``docs/native-protocol.md``);
    ``max_delayed``: delayed answers held before reading stops; ``write_buffer_high``: unsent
    output before reading stops (also how much output one chunk's answers gather before they
    are written).
    """

    max_frame: int = DEFAULT_MAX_FRAME
    max_body: int = DEFAULT_MAX_BODY
    max_delayed: int = DEFAULT_MAX_DELAYED
    write_buffer_high: int = DEFAULT_WRITE_BUFFER_HIGH


def peer_text(peer: Any) -> str:
    """A transport's ``peername`` as logs show it: ``127.0.0.1:50000``, ``[::1]:50000``
    (``?`` when unknown)."""
    if not peer:
        return "?"
    host, port = peer[0], peer[1]
    return f"[{host}]:{port}" if ":" in str(host) else f"{host}:{port}"


#: Called once by a connection when its transport is gone (``connection_lost``).
CloseCallback = Callable[["BaseConnection[Any]"], None]
#: What a protocol's decoder yields: one request frame.
F = TypeVar("F")

_DELAY_KIND: Final = FaultKind.DELAY


class _Delayed:
    """An answer waiting for its delay (fault kind 1)."""

    __slots__ = ("conn", "data", "timer")

    def __init__(self, conn: BaseConnection[Any], data: bytes) -> None:
        self.conn = conn
        self.data = data
        self.timer: asyncio.TimerHandle | None = None

    def fire(self) -> None:
        self.conn._send_delayed(self)


class _Backlog(Generic[F]):
    """Input held while output backpressure stops the answering: decoded requests not yet
    answered, then raw bytes not yet decoded. Bounded by one read of the transport."""

    __slots__ = ("frames", "input")

    def __init__(self, frames: list[F] | None, data: bytes | memoryview) -> None:
        self.frames = frames
        self.input: bytes | memoryview = data


class BaseConnection(Received, asyncio.Protocol, Generic[F]):
    """The part of a connection that does not depend on the protocol.

    A subclass decodes with :meth:`_feed` (a chunk of at most :data:`SLICE` bytes; False when
    it stopped: closed, or backpressure held the rest in the backlog) and answers decoded
    requests with :meth:`_run`.
    """

    __slots__ = (
        "_backlog",
        "_closing",
        "_delayed",
        "_faults",
        "_label",
        "_limits",
        "_on_close",
        "_peer",
        "_read_paused",
        "_shared",
        "_transport",
        "_view",
        "_write_paused",
        "idle_sweeps",
        "violated",
    )

    def __init__(
        self, label: str, faults: FaultQueue, limits: Limits, on_close: CloseCallback
    ) -> None:
        self._label = label
        #: The machine-wide fault queue (scope 1), shared by every connection to the machine.
        self._shared = faults
        self._limits = limits
        self._on_close = on_close
        self._transport: asyncio.Transport | None = None
        self._peer: Any = None
        #: This connection's own faults (scope 0), created when the first one is armed.
        self._faults: FaultQueue | None = None
        self._delayed: set[_Delayed] | None = None
        self._backlog: _Backlog[F] | None = None
        self._read_paused = False
        self._write_paused = False
        self._closing = False
        #: Idle sweeps of the server since the last complete request (the server counts up,
        #: the connection resets it).
        self.idle_sweeps = 0
        #: True once the connection closed itself for a framing violation.
        self.violated = False
        #: The receive buffer of the thread that made the connection, which is the thread of
        #: its event loop: taken once here, where a thread-local look-up per read would cost
        #: about as much as answering a short request.
        self._view = receive_buffer()

    # -- to implement ----------------------------------------------------------------------

    def _feed(self, chunk: bytes | memoryview) -> bool:
        raise NotImplementedError

    def _run(self, frames: list[F]) -> bool:
        raise NotImplementedError

    # -- state visible to the server and to tests ------------------------------------------

    @property
    def peer(self) -> Any:
        """The peer address (``(host, port)`` for TCP)."""
        return self._peer

    @property
    def label(self) -> str:
        """The name the connection's logs give its machine."""
        return self._label

    @property
    def peer_text(self) -> str:
        """The peer address as logs show it: ``127.0.0.1:50000``, ``[::1]:50000``."""
        return peer_text(self._peer)

    @property
    def closing(self) -> bool:
        """True once the connection is being closed (nothing more is read)."""
        return self._closing

    @property
    def reading_paused(self) -> bool:
        """True while the server does not read from this connection (backpressure)."""
        return self._read_paused

    @property
    def delayed_count(self) -> int:
        """Answers held back by a delay fault, not sent yet."""
        return len(self._delayed) if self._delayed else 0

    @property
    def write_buffer_size(self) -> int:
        """Bytes written to the transport and not yet sent."""
        t = self._transport
        return t.get_write_buffer_size() if t is not None else 0

    # -- asyncio.Protocol ------------------------------------------------------------------

    # Received's reads, from the buffer taken when the connection was made

    def get_buffer(self, sizehint: int) -> memoryview:
        return self._view

    def buffer_updated(self, nbytes: int) -> None:
        self.data_received(self._view[:nbytes].tobytes())

    def connection_made(self, base: asyncio.BaseTransport) -> None:
        # uvloop's transports do not subclass asyncio.Transport, but have its methods
        transport = cast(asyncio.Transport, base)
        self._transport = transport
        self._peer = transport.get_extra_info("peername")
        high = self._limits.write_buffer_high
        transport.set_write_buffer_limits(high=high, low=high // 4)

    def connection_lost(self, exc: Exception | None) -> None:
        if self._transport is None:
            return
        self._transport = None
        self._closing = True
        self._backlog = None
        self._cancel_delayed()
        self._on_close(self)
        if _log.isEnabledFor(logging.DEBUG):  # (why, in the system's words: a reset)
            if exc is None:
                why = ""
            else:
                why = f": {ssl_error_text(exc) if isinstance(exc, OSError) else exc}"
            _log.debug("%s: connection from %s closed%s", self._label, self.peer_text, why)

    def pause_writing(self) -> None:
        self._write_paused = True
        self._pause_reading()

    def resume_writing(self) -> None:
        self._write_paused = False
        self._maybe_resume()

    def eof_received(self) -> bool:
        # The peer sends nothing more. Requests already received are answered (delayed
        # answers when due) and flushed, then the connection closes.
        if self._backlog is None and not self._delayed:
            transport = self._transport
            if transport is not None and getattr(transport, "holding", False):
                transport.close()  # held until durable (serve --state): closes once sent
                return True
            return False  # the transport closes itself after flushing
        self._closing = True
        return True  # closed by _work_backlog / _send_delayed once everything is answered

    def data_received(self, data: bytes) -> None:
        if self._transport is None or self._closing:
            return
        if self._backlog is not None:
            # Still working off earlier input (reading is paused): keep the order.
            backlog = self._backlog
            backlog.input = bytes(backlog.input) + data
            return
        if len(data) <= SLICE:
            self._feed(data)
        else:
            self._backlog = _Backlog(None, memoryview(data))
            self._work_backlog()

    # -- the backlog -----------------------------------------------------------------------

    def _stop(self, frames: list[F], index: int) -> bool:
        """Keep ``frames[index:]`` for later (backpressure stopped the answering); False."""
        rest = frames[index:]
        backlog = self._backlog
        if backlog is None:
            self._backlog = _Backlog(rest or None, b"")
        else:
            backlog.frames = rest or None
        return False

    def _work_backlog(self) -> None:
        """Answer held requests, then feed held input a slice at a time, until done or paused
        again. Reading resumes (or the connection closes) when the backlog is empty."""
        backlog = self._backlog
        while backlog is not None and self._transport is not None:
            if self._write_paused or self._delayed_full():
                return
            frames = backlog.frames
            if frames is not None:
                backlog.frames = None
                if not self._run(frames):
                    return
                continue
            data = backlog.input
            if not data:
                break
            chunk, backlog.input = data[:SLICE], data[SLICE:]
            if not self._feed(chunk):
                return
        self._backlog = None
        if self._transport is None:
            return
        if self._closing:
            if not self._delayed:
                self._transport.close()
        elif self._read_paused and not self._write_paused and not self._delayed_full():
            self._read_paused = False
            self._transport.resume_reading()

    # -- faults ----------------------------------------------------------------------------

    def _take_fault(self) -> tuple[FaultKind, int] | None:
        """The fault for the next answer (this connection's first, then the machine's)."""
        own = self._faults
        if own is not None:
            fault = own.take()
            if not own.armed:
                self._faults = None
            if fault is not None:
                return fault
        return self._shared.take()

    def _own_faults(self) -> FaultQueue:
        """This connection's fault queue (scope 0), created on first use."""
        queue = self._faults
        if queue is None:
            queue = self._faults = FaultQueue()
        return queue

    def _drop(self) -> None:
        """Fault kind 3: close instead of answering."""
        _log.info(
            "%s: closing the connection from %s instead of answering (injected fault)",
            self._label,
            self.peer_text,
        )
        self._close_now()

    def _write_split(self, frame: bytes) -> None:
        """Fault kind 4: ``frame`` one byte per write."""
        transport = self._transport
        assert transport is not None
        write = transport.write
        for i in range(len(frame)):
            write(frame[i : i + 1])

    def _delay(self, ms: int, frame: bytes) -> None:
        """Fault kind 1: write ``frame`` ``ms`` milliseconds from now."""
        item = _Delayed(self, frame)
        delayed = self._delayed
        if delayed is None:
            delayed = self._delayed = set()
        delayed.add(item)
        item.timer = asyncio.get_running_loop().call_later(ms / 1000.0, item.fire)
        if len(delayed) >= self._limits.max_delayed:
            self._pause_reading()

    def _send_delayed(self, item: _Delayed) -> None:
        delayed = self._delayed
        if delayed is None or item not in delayed:
            return
        delayed.discard(item)
        item.timer = None
        transport = self._transport
        if transport is None:
            return
        transport.write(item.data)
        if not delayed and self._closing and self._backlog is None:
            # Shutdown or the peer's end of stream: the last delayed answer is out, close.
            transport.close()
        elif self._read_paused:
            self._maybe_resume()

    def _delayed_full(self) -> bool:
        delayed = self._delayed
        return delayed is not None and len(delayed) >= self._limits.max_delayed

    def _cancel_delayed(self) -> None:
        delayed = self._delayed
        if delayed:
            for item in delayed:
                if item.timer is not None:
                    item.timer.cancel()
            delayed.clear()

    # -- reading on and off ----------------------------------------------------------------

    def _pause_reading(self) -> None:
        if not self._read_paused and self._transport is not None:
            self._read_paused = True
            self._transport.pause_reading()

    def _maybe_resume(self) -> None:
        """Work off the backlog and resume reading once no bound holds any more."""
        if not self._read_paused or self._write_paused or self._transport is None:
            return
        delayed = self._delayed
        if delayed and len(delayed) > self._limits.max_delayed // 2:
            return
        if self._backlog is not None:
            self._work_backlog()  # resumes reading itself when done
        elif not self._closing:
            self._read_paused = False
            self._transport.resume_reading()

    def _close_now(self) -> None:
        """Close at once without answering anything more (pending delayed answers dropped);
        what was written already is still sent."""
        self._closing = True
        self._backlog = None
        self._cancel_delayed()
        transport = self._transport
        if transport is not None:
            transport.close()

    # -- driven by the server --------------------------------------------------------------

    def close_idle(self, idle_timeout: float) -> None:
        """Close at once: no complete request for ``idle_timeout`` seconds."""
        _log.info(
            "%s: closing the connection from %s: idle for %g s",
            self._label,
            self.peer_text,
            idle_timeout,
        )
        self.abort()

    def begin_shutdown(self) -> None:
        """Stop reading; close once held requests and delayed answers (if any) are answered."""
        self._closing = True
        self._pause_reading()
        if not self._delayed and self._backlog is None:
            self.close()

    def flush_delayed(self) -> None:
        """Send every delayed answer now (the grace period is over)."""
        delayed = self._delayed
        transport = self._transport
        if not delayed:
            return
        items = sorted(delayed, key=lambda d: d.timer.when() if d.timer else 0.0)
        delayed.clear()
        for item in items:
            if item.timer is not None:
                item.timer.cancel()
                item.timer = None
            if transport is not None:
                transport.write(item.data)

    def detach(self) -> None:
        """Let go of the transport without closing it (another connection takes it over)."""
        self._transport = None
        self._closing = True

    def close(self) -> None:
        """Close after the write buffer drained."""
        self._closing = True
        transport = self._transport
        if transport is not None:
            transport.close()

    def abort(self) -> None:
        """Close at once, dropping anything unsent."""
        transport = self._transport
        if transport is not None:
            transport.abort()
