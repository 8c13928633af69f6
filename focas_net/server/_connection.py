"""One client connection: the per-frame data path of the server.

A plain :class:`asyncio.Protocol` (no task per connection, no task per request): every chunk
read from the socket goes through the incremental :class:`FrameDecoder`; each request is
answered synchronously by the machine's packed adapter, and all answers produced by one chunk
leave in one ``writelines`` call. Delayed answers (fault injection) are timer callbacks.

Backpressure: reading stops while the transport's write buffer is above its high-water mark
(``pause_writing``) or while the connection holds ``max_delayed`` delayed answers, and resumes
when the buffer drained (``resume_writing``) or half the delayed answers went out. A client that
never reads therefore cannot grow the server's memory beyond one read chunk's answers plus the
write buffer's high-water mark.
"""

from __future__ import annotations

import asyncio
import logging
from typing import TYPE_CHECKING, Any, Final, cast

from focas_net.errors import EW, FrameError
from focas_net.protocol import HEADER, Frame, FrameDecoder, encode_ew

from .faults import FaultKind, FaultQueue, FaultScope, parse_inject

if TYPE_CHECKING:
    from focas_net.sim import Machine, Session

    from ._server import Listener

__all__ = ["Connection"]

_log = logging.getLogger("focas_net.server")

_pack_header = HEADER.pack
_CONTROL_FIRST: Final = 0x0E01
_CONTROL_LAST: Final = 0x0E05
_INJECT_FAULT: Final = 0x0E05
_UNLOCK: Final = 0x0105
_EW_OK: Final = encode_ew(EW.OK)
_EW_FUNC: Final = encode_ew(EW.FUNC)
_DEBUG: Final = logging.DEBUG
_HEXDUMP_LIMIT: Final = 256
#: Input is decoded at most this many bytes at a time, so that output backpressure can stop
#: the answering between slices.
_SLICE: Final = 16 * 1024
_DELAY_KIND: Final = FaultKind.DELAY
_ERROR_KIND: Final = FaultKind.ERROR
_DROP_KIND: Final = FaultKind.DROP


def _hexdump(data: bytes | bytearray | memoryview) -> str:
    head = bytes(data[:_HEXDUMP_LIMIT]).hex(" ")
    return head + (f" ... ({len(data)} bytes)" if len(data) > _HEXDUMP_LIMIT else "")


def _dump_frames(frames: list[Frame]) -> str:
    """Decoded frames for a DEBUG log; the payload of an unlock (the password) is never shown."""
    return "; ".join(
        f"0x{command:04X} #{request_id}: "
        + ("<password redacted>" if command == _UNLOCK else _hexdump(payload))
        for command, request_id, payload in frames
    )


class _Delayed:
    """An answer waiting for its delay (fault kind 1)."""

    __slots__ = ("conn", "data", "timer")

    def __init__(self, conn: Connection, data: bytes) -> None:
        self.conn = conn
        self.data = data
        self.timer: asyncio.TimerHandle | None = None

    def fire(self) -> None:
        self.conn._send_delayed(self)


class _Backlog:
    """Input held while output backpressure stops the answering: decoded requests not yet
    answered, then raw bytes not yet decoded. Bounded by one read of the transport."""

    __slots__ = ("frames", "input")

    def __init__(self, frames: list[Frame] | None, data: bytes | memoryview) -> None:
        self.frames = frames
        self.input: bytes | memoryview = data


class Connection(asyncio.Protocol):
    """The protocol of one accepted connection."""

    __slots__ = (
        "_backlog",
        "_closing",
        "_decoder",
        "_delayed",
        "_faults",
        "_listener",
        "_machine",
        "_peer",
        "_read_paused",
        "_session",
        "_tick",
        "_transport",
        "_write_paused",
    )

    def __init__(self, listener: Listener) -> None:
        self._listener = listener
        self._machine: Machine = listener.machine
        self._transport: asyncio.Transport | None = None
        self._session: Session | None = None
        self._decoder = FrameDecoder(listener.server.max_frame)
        self._peer: Any = None
        self._faults: FaultQueue | None = None
        self._delayed: set[_Delayed] | None = None
        self._backlog: _Backlog | None = None
        self._read_paused = False
        self._write_paused = False
        self._closing = False
        self._tick = 0

    # -- state visible to the server and to tests ------------------------------------------

    @property
    def peer(self) -> Any:
        """The peer address (``(host, port)`` for TCP)."""
        return self._peer

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

    @property
    def buffered_input(self) -> int:
        """Bytes received and not answered yet: a partial frame in the decoder, plus the
        backlog held while backpressure stops the answering."""
        held = self._decoder.buffered
        backlog = self._backlog
        if backlog is not None:
            held += len(backlog.input)
            if backlog.frames:
                held += sum(8 + len(f.payload) for f in backlog.frames)
        return held

    # -- asyncio.Protocol ------------------------------------------------------------------

    def connection_made(self, base: asyncio.BaseTransport) -> None:
        # uvloop's transports do not subclass asyncio.Transport, but have its methods
        transport = cast(asyncio.Transport, base)
        listener = self._listener
        self._peer = transport.get_extra_info("peername")
        if not listener.accepting:
            transport.abort()
            return
        if len(listener.connections) >= listener.server.max_connections:
            _log.warning(
                "%s: connection from %s refused: %d connections is the limit",
                listener.label,
                self._peer,
                listener.server.max_connections,
            )
            listener.refused += 1
            transport.abort()
            return
        self._transport = transport
        self._session = self._machine.new_session()
        self._tick = listener.server._tick
        high = listener.server.write_buffer_high
        transport.set_write_buffer_limits(high=high, low=high // 4)
        listener.connections.add(self)
        listener.accepted += 1
        _log.debug("%s: connection from %s", listener.label, self._peer)

    def connection_lost(self, exc: Exception | None) -> None:
        listener = self._listener
        if self._transport is None:
            return
        self._transport = None
        self._closing = True
        self._backlog = None
        self._cancel_delayed()
        listener.connections.discard(self)
        listener.server._connection_done(self)
        _log.debug("%s: connection from %s closed (%s)", listener.label, self._peer, exc)

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
        if len(data) <= _SLICE:
            self._feed(data)
        else:
            self._backlog = _Backlog(None, memoryview(data))
            self._work_backlog()

    def _feed(self, chunk: bytes | memoryview) -> bool:
        """Decode ``chunk`` and answer its frames; False when a framing violation closed the
        connection or output backpressure stopped the answering part way."""
        try:
            frames = self._decoder.feed(chunk)
        except FrameError as exc:
            if exc.frames:
                self._run(exc.frames)
            self._framing_violation(exc, chunk)
            return False
        if not frames:
            return True
        if _log.isEnabledFor(_DEBUG):
            _log.debug("%s: from %s: %s", self._listener.label, self._peer, _dump_frames(frames))
        self._tick = self._listener.server._tick
        return self._run(frames)

    def _run(self, frames: list[Frame]) -> bool:
        """Answer ``frames`` in order; False when output backpressure stopped it part way (the
        rest is kept in the backlog) or the connection was closed."""
        transport = self._transport
        assert transport is not None
        adapter = self._listener.adapter
        session = self._session
        shared = self._listener.faults
        budget = self._listener.server.write_buffer_high
        out: list[bytes] = []
        size = 0
        for index, (command, request_id, payload) in enumerate(frames):
            if command == _INJECT_FAULT:
                answer = self._inject_fault(payload)
            elif (shared.armed or self._faults is not None) and not (
                _CONTROL_FIRST <= command <= _CONTROL_LAST
            ):
                fault = self._take_fault()
                if fault is not None:
                    written = self._apply_fault(fault, command, request_id, payload, out)
                    if written is None:
                        return False  # the connection was closed instead of answering
                    out = written
                    if self._write_paused or self._delayed_full():
                        return self._stop(frames, index + 1, out)
                    continue
                answer = self._answer(command, payload)
            else:
                try:
                    answer = adapter.answer(session, command, payload)  # type: ignore[arg-type]
                except Exception:
                    answer = self._failed(command)
            out.append(_pack_header(len(answer) + 4, command, request_id))
            out.append(answer)
            size += len(answer)
            if size >= budget:
                transport.writelines(out)
                out = []
                size = 0
                if self._write_paused:  # the write buffer passed its high-water mark
                    return self._stop(frames, index + 1, out)
        if out:
            transport.writelines(out)
        return True

    def _stop(self, frames: list[Frame], index: int, out: list[bytes]) -> bool:
        transport = self._transport
        assert transport is not None
        if out:
            transport.writelines(out)
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
            chunk, backlog.input = data[:_SLICE], data[_SLICE:]
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

    # -- helpers ---------------------------------------------------------------------------

    def _answer(self, command: int, payload: bytes) -> bytes:
        try:
            return self._listener.adapter.answer(self._session, command, payload)  # type: ignore[arg-type]
        except Exception:
            return self._failed(command)

    def _failed(self, command: int) -> bytes:
        """A bug in the machine must not take the connection down: log it, answer EW_REJECT."""
        _log.exception(
            "%s: command 0x%04X from %s failed", self._listener.label, command, self._peer
        )
        return self._listener.adapter.error_answer(command, EW.REJECT)

    def _take_fault(self) -> tuple[FaultKind, int] | None:
        """The fault for the next answer (this connection's first, then the machine's)."""
        own = self._faults
        if own is not None:
            fault = own.take()
            if not own.armed:
                self._faults = None
            if fault is not None:
                return fault
        return self._listener.faults.take()

    def _apply_fault(
        self,
        fault: tuple[FaultKind, int],
        command: int,
        request_id: int,
        payload: bytes,
        out: list[bytes],
    ) -> list[bytes] | None:
        """Answer one request under ``fault``; the answers still to write (None: closed).

        A forced EW code (kind 2) and a dropped connection (kind 3) answer without running the
        request, so the rule "an EW code other than 0 means nothing changed" holds; a delayed
        (kind 1) or split (kind 4) answer is the real answer.
        """
        kind, arg = fault
        transport = self._transport
        assert transport is not None
        if kind is _ERROR_KIND:
            answer = self._listener.adapter.error_answer(command, arg)
            out.append(_pack_header(len(answer) + 4, command, request_id))
            out.append(answer)
            return out
        if kind is _DROP_KIND:
            if out:
                transport.writelines(out)
            _log.info(
                "%s: closing the connection from %s instead of answering (injected fault)",
                self._listener.label,
                self._peer,
            )
            self._close_now()
            return None
        answer = self._answer(command, payload)
        frame = _pack_header(len(answer) + 4, command, request_id) + answer
        if kind is _DELAY_KIND:
            self._delay(arg, frame)
            return out
        # SPLIT: what came before goes first, then this answer one byte per write
        if out:
            transport.writelines(out)
        write = transport.write
        for i in range(len(frame)):
            write(frame[i : i + 1])
        return []

    def _framing_violation(self, exc: FrameError, data: bytes | memoryview) -> None:
        listener = self._listener
        _log.warning("%s: %s from %s: %s", listener.label, "framing violation", self._peer, exc)
        if _log.isEnabledFor(_DEBUG):
            # Whole frames only: raw bytes could hold part of an unlock request's password.
            _log.debug(
                "%s: offending chunk from %s: %d bytes, whole frames before the violation: %s",
                listener.label,
                self._peer,
                len(data),
                _dump_frames(exc.frames) or "none",
            )
        listener.violations += 1
        self._close_now()

    def _close_now(self) -> None:
        """Close at once without answering anything more (pending delayed answers dropped)."""
        self._closing = True
        self._backlog = None
        self._cancel_delayed()
        transport = self._transport
        if transport is not None:
            transport.close()

    def _inject_fault(self, payload: bytes) -> bytes:
        machine = self._machine
        if not machine.control_enabled:
            return _EW_FUNC
        parsed = parse_inject(payload, read_only=machine.read_only)
        if isinstance(parsed, int):
            return encode_ew(parsed)
        scope, fault = parsed
        queue: FaultQueue | None
        if scope is FaultScope.MACHINE:
            queue = self._listener.faults
        else:
            queue = self._faults
            if queue is None:
                queue = self._faults = FaultQueue()
        ew = queue.arm(fault)
        if ew:
            return encode_ew(ew)
        _log.info("%s: %s armed by %s (%s)", self._listener.label, fault, self._peer, scope.name)
        return _EW_OK

    def _delay(self, ms: int, frame: bytes) -> None:
        item = _Delayed(self, frame)
        delayed = self._delayed
        if delayed is None:
            delayed = self._delayed = set()
        delayed.add(item)
        item.timer = self._listener.server._loop.call_later(ms / 1000.0, item.fire)
        if len(delayed) >= self._listener.server.max_delayed:
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
            # Server shutdown: the last delayed answer is out, close.
            transport.close()
        elif self._read_paused:
            self._maybe_resume()

    def _delayed_full(self) -> bool:
        delayed = self._delayed
        return delayed is not None and len(delayed) >= self._listener.server.max_delayed

    def _pause_reading(self) -> None:
        if not self._read_paused and self._transport is not None:
            self._read_paused = True
            self._transport.pause_reading()

    def _maybe_resume(self) -> None:
        """Work off the backlog and resume reading once no bound holds any more."""
        if not self._read_paused or self._write_paused or self._transport is None:
            return
        delayed = self._delayed
        if delayed and len(delayed) > self._listener.server.max_delayed // 2:
            return
        if self._backlog is not None:
            self._work_backlog()  # resumes reading itself when done
        elif not self._closing:
            self._read_paused = False
            self._transport.resume_reading()

    def _cancel_delayed(self) -> None:
        delayed = self._delayed
        if delayed:
            for item in delayed:
                if item.timer is not None:
                    item.timer.cancel()
            delayed.clear()

    # -- shutdown (driven by the server) ---------------------------------------------------

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

    @property
    def last_tick(self) -> int:
        """The server's idle-sweep tick at this connection's last complete request."""
        return self._tick
