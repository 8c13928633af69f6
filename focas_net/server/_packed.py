"""A packed-protocol connection (``docs/protocol.md``): the per-frame data path of the server.

Every chunk read from the socket goes through the incremental :class:`FrameDecoder`; each
request is answered synchronously by the machine's packed adapter, and all answers produced by
one chunk leave in one write, joined. (asyncio's own ``writelines`` on CPython 3.12.0-3.12.8
and 3.13.0-3.13.1 skips the write buffer's high-water check, CPython gh-127655: with it
``pause_writing`` never came, and a peer that never read held the server's memory without
bound. Joining and writing is what ``writelines`` did before 3.12.) Delayed answers (fault
injection) are timer callbacks. Backpressure, the backlog, delays and shutdown are
:class:`~._base.BaseConnection`'s.

The machine is reached only through its :class:`~focas_net.adapters.PackedAdapter` (shared by
the listener's connections, so they share its answer caches): ``answer`` and ``error_answer``.
"""

from __future__ import annotations

import logging
from typing import TYPE_CHECKING, Final

from focas_net._receive import _local, receive_buffer
from focas_net.errors import EW, FrameError
from focas_net.protocol import (
    COMMANDS,
    HEADER,
    Command,
    FaultsCleared,
    FrameDecoder,
    RawFrame,
    encode_ew,
)

from ._base import BaseConnection, CloseCallback, Limits
from .faults import FaultKind, FaultQueue, FaultScope, parse_inject, parse_scope

if TYPE_CHECKING:
    import asyncio

    from focas_net.adapters import PackedAdapter
    from focas_net.sim import Session

__all__ = ["PackedConnection"]

_log = logging.getLogger("focas_net.server")

_pack_header = HEADER.pack
_unpack_header_from = HEADER.unpack_from
#: A chunk's answers as one write (see the module's docstring for why not ``writelines``).
_join: Final = b"".join
_CONTROL_FIRST: Final = int(Command.SIM_SET_PANEL)
_CONTROL_LAST: Final = 0x0EFF  # every simulator control id is 0x0Exx (0x0E10 read_panel too)
_INJECT_FAULT: Final = int(Command.SIM_INJECT_FAULT)
_LIST_FAULTS: Final = int(Command.SIM_LIST_FAULTS)
_CLEAR_FAULTS: Final = int(Command.SIM_CLEAR_FAULTS)
_LIST_ANSWER: Final = COMMANDS[Command.SIM_LIST_FAULTS].response.encode
_CLEAR_ANSWER: Final = COMMANDS[Command.SIM_CLEAR_FAULTS].response.encode
_UNLOCK: Final = int(Command.WRUNLOCKPARAM)
_EW_OK: Final = encode_ew(EW.OK)
_EW_FUNC: Final = encode_ew(EW.FUNC)
_DEBUG: Final = logging.DEBUG
#: The commands the connection answers itself, from its fault queues.
_FAULT_COMMANDS: Final = frozenset((_INJECT_FAULT, _LIST_FAULTS, _CLEAR_FAULTS))
_HEXDUMP_LIMIT: Final = 256
_DELAY_KIND: Final = FaultKind.DELAY
_ERROR_KIND: Final = FaultKind.ERROR
_DROP_KIND: Final = FaultKind.DROP


def _hexdump(data: bytes | bytearray | memoryview) -> str:
    head = bytes(data[:_HEXDUMP_LIMIT]).hex(" ")
    return head + (f" ... ({len(data)} bytes)" if len(data) > _HEXDUMP_LIMIT else "")


def _dump_frames(frames: list[RawFrame]) -> str:
    """Decoded frames for a DEBUG log; the payload of an unlock (the password) is never shown."""
    return "; ".join(
        f"0x{command:04X} #{request_id}: "
        + ("<password redacted>" if command == _UNLOCK else _hexdump(payload))
        for command, request_id, payload in frames
    )


class PackedConnection(BaseConnection[RawFrame]):
    """One packed-protocol connection to ``machine``.

    ``faults`` is the machine-wide fault queue, ``limits`` the server's bounds, ``on_close``
    is called once when the transport is gone; ``label`` names the machine in logs.
    """

    __slots__ = ("_adapter", "_decoder", "_machine", "_session")

    def __init__(
        self,
        adapter: PackedAdapter,
        faults: FaultQueue,
        limits: Limits,
        on_close: CloseCallback,
        label: str | None = None,
    ) -> None:
        machine = adapter.machine
        super().__init__(machine.name if label is None else label, faults, limits, on_close)
        self._adapter = adapter
        self._machine = machine
        self._session: Session | None = None
        self._decoder = FrameDecoder(limits.max_frame)

    @property
    def buffered_input(self) -> int:
        """Bytes received and not answered yet: a partial frame in the decoder, plus the
        backlog held while backpressure stops the answering."""
        held = self._decoder.buffered
        backlog = self._backlog
        if backlog is not None:
            held += len(backlog.input)
            if backlog.frames:
                held += sum(8 + len(payload) for _, _, payload in backlog.frames)
        return held

    # -- asyncio.Protocol ------------------------------------------------------------------

    def connection_made(self, base: asyncio.BaseTransport) -> None:
        super().connection_made(base)
        self._session = self._machine.new_session()
        _log.debug("%s: connection from %s", self._label, self._peer)

    # -- the data path ---------------------------------------------------------------------

    def buffer_updated(self, nbytes: int) -> None:
        # The usual reads: whole requests, nothing held from earlier input, no fault armed, no
        # debug log. They are answered straight from the receive buffer in one write, the
        # decoder, the backlog and the fault path left out: a poller's one request, or a
        # pipelining client's many. What is left of the read (a fault command, a length out
        # of bounds, a partial request, answers past the write budget) takes data_received.
        try:
            view: memoryview = _local.view  # receive_buffer() without its call
        except AttributeError:
            view = receive_buffer()
        pos = 0
        if (
            nbytes >= 8
            and self._backlog is None
            and self._faults is None
            and not self._shared.armed
            and not self._decoder.held
            and not self._closing
        ):
            transport = self._transport
            length, command, request_id = _unpack_header_from(view)
            max_frame = self._decoder.max_frame
            if (
                4 <= length <= max_frame
                and length + 4 <= nbytes
                and command not in _FAULT_COMMANDS
                and transport is not None
                and not _log.isEnabledFor(_DEBUG)
            ):
                self.idle_sweeps = 0
                answer = self._answer(command, bytes(view[8 : length + 4]) if length > 4 else b"")
                if length + 4 == nbytes:  # one request: one write
                    transport.write(_pack_header(len(answer) + 4, command, request_id) + answer)
                    return
                pos = self._answer_more(view, nbytes, length + 4, command, request_id, answer)
                if pos == nbytes:
                    return
        self.data_received(bytes(view[pos:nbytes]))

    def _answer_more(
        self,
        view: memoryview,
        nbytes: int,
        pos: int,
        command: int,
        request_id: int,
        answer: bytes,
    ) -> int:
        """:meth:`buffer_updated` past its first request (``answer``, to ``command`` and
        ``request_id``, ending at ``pos``): answer the whole requests that follow in
        ``view[:nbytes]`` while they take the fast path and their answers stay within the write
        budget, write every answer at once, and return where the first request not answered
        here starts."""
        transport = self._transport
        assert transport is not None
        out = [_pack_header(len(answer) + 4, command, request_id), answer]
        append = out.append
        size = len(answer)
        budget = self._limits.write_buffer_high
        max_frame = self._decoder.max_frame
        answer_of = self._adapter.answer
        session = self._session
        while nbytes - pos >= 8 and size < budget:
            length, command, request_id = _unpack_header_from(view, pos)
            end = pos + 4 + length
            if length < 4 or length > max_frame or end > nbytes or command in _FAULT_COMMANDS:
                break
            try:
                answer = answer_of(session, command, bytes(view[pos + 8 : end]))  # type: ignore[arg-type]
            except Exception:
                answer = self._failed(command)
            append(_pack_header(len(answer) + 4, command, request_id))
            append(answer)
            size += len(answer)
            pos = end
        transport.write(_join(out))
        return pos

    def _feed(self, chunk: bytes | memoryview) -> bool:
        """Decode ``chunk`` and answer its frames; False when a framing violation closed the
        connection or output backpressure stopped the answering part way."""
        try:
            frames = self._decoder.feed_raw(chunk)
        except FrameError as exc:
            if exc.frames:
                self._run(exc.frames)
            self._framing_violation(exc, chunk)
            return False
        if not frames:
            return True
        if _log.isEnabledFor(_DEBUG):
            _log.debug("%s: from %s: %s", self._label, self._peer, _dump_frames(frames))
        self.idle_sweeps = 0
        return self._run(frames)

    def _run(self, frames: list[RawFrame]) -> bool:
        """Answer ``frames`` in order; False when output backpressure stopped it part way (the
        rest is kept in the backlog) or the connection was closed.

        The usual case, no fault armed, is this one loop: each request straight to the
        adapter. A fault command, or a fault armed, hands the rest to :meth:`_run_from`.
        """
        if self._shared.armed or self._faults is not None:
            return self._run_from(frames, 0, [], 0)
        transport = self._transport
        assert transport is not None
        answer_of = self._adapter.answer
        session = self._session
        if len(frames) == 1:
            # One request in the read (sequential use, or one per connection): one write.
            command, request_id, payload = frames[0]
            if command not in _FAULT_COMMANDS:
                answer = self._answer(command, payload)
                transport.write(_pack_header(len(answer) + 4, command, request_id) + answer)
                return True  # a write past the high-water mark pauses reading (pause_writing)
        budget = self._limits.write_buffer_high
        out: list[bytes] = []
        append = out.append
        size = 0
        for index, (command, request_id, payload) in enumerate(frames):
            if command in _FAULT_COMMANDS:
                return self._run_from(frames, index, out, size)
            try:
                answer = answer_of(session, command, payload)  # type: ignore[arg-type]
            except Exception:
                answer = self._failed(command)
            append(_pack_header(len(answer) + 4, command, request_id))
            append(answer)
            size += len(answer)
            if size >= budget:
                transport.write(_join(out))
                out = []
                append = out.append
                size = 0
                if self._write_paused:  # the write buffer passed its high-water mark
                    return self._stop_writing(frames, index + 1, out)
        if out:
            transport.write(_join(out))
        return True

    def _run_from(self, frames: list[RawFrame], start: int, out: list[bytes], size: int) -> bool:
        """:meth:`_run` from ``frames[start]`` on, with ``out`` (``size`` payload bytes)
        answered and not written yet: fault commands, and faults taken for every answer."""
        transport = self._transport
        assert transport is not None
        adapter = self._adapter
        session = self._session
        shared = self._shared
        budget = self._limits.write_buffer_high
        for index in range(start, len(frames)):
            command, request_id, payload = frames[index]
            if command == _INJECT_FAULT:
                answer = self._inject_fault(payload)
            elif command == _LIST_FAULTS or command == _CLEAR_FAULTS:
                answer = self._fault_queue(command, payload)
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
                        return self._stop_writing(frames, index + 1, out)
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
                transport.write(_join(out))
                out = []
                size = 0
                if self._write_paused:  # the write buffer passed its high-water mark
                    return self._stop_writing(frames, index + 1, out)
        if out:
            transport.write(_join(out))
        return True

    def _stop_writing(self, frames: list[RawFrame], index: int, out: list[bytes]) -> bool:
        transport = self._transport
        assert transport is not None
        if out:
            transport.write(_join(out))
        return self._stop(frames, index)

    # -- helpers ---------------------------------------------------------------------------

    def _answer(self, command: int, payload: bytes) -> bytes:
        try:
            return self._adapter.answer(self._session, command, payload)  # type: ignore[arg-type]
        except Exception:
            return self._failed(command)

    def _failed(self, command: int) -> bytes:
        """A bug in the machine must not take the connection down: log it, answer EW_REJECT."""
        _log.exception("%s: command 0x%04X from %s failed", self._label, command, self._peer)
        return self._adapter.error_answer(command, EW.REJECT)

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
            answer = self._adapter.error_answer(command, arg)
            out.append(_pack_header(len(answer) + 4, command, request_id))
            out.append(answer)
            return out
        if kind is _DROP_KIND:
            if out:
                transport.write(_join(out))
            self._drop()
            return None
        answer = self._answer(command, payload)
        frame = _pack_header(len(answer) + 4, command, request_id) + answer
        if kind is _DELAY_KIND:
            self._delay(arg, frame)
            return out
        # SPLIT: what came before goes first, then this answer one byte per write
        if out:
            transport.write(_join(out))
        self._write_split(frame)
        return []

    def _framing_violation(self, exc: FrameError, data: bytes | memoryview) -> None:
        _log.warning("%s: %s from %s: %s", self._label, "framing violation", self._peer, exc)
        if _log.isEnabledFor(_DEBUG):
            # Whole frames only: raw bytes could hold part of an unlock request's password.
            _log.debug(
                "%s: offending chunk from %s: %d bytes, whole frames before the violation: %s",
                self._label,
                self._peer,
                len(data),
                _dump_frames(exc.frames) or "none",
            )
        self.violated = True
        self._close_now()

    def _inject_fault(self, payload: bytes) -> bytes:
        machine = self._machine
        if not machine.control_enabled:
            return _EW_FUNC
        parsed = parse_inject(payload, read_only=machine.read_only)
        if isinstance(parsed, int):
            return encode_ew(parsed)
        scope, fault = parsed
        queue = self._shared if scope is FaultScope.MACHINE else self._own_faults()
        ew = queue.arm(fault)
        if ew:
            return encode_ew(ew)
        _log.info("%s: %s armed by %s (%s)", self._label, fault, self._peer, scope.name)
        return _EW_OK

    def _fault_queue(self, command: int, payload: bytes) -> bytes:
        """0x0E06 list_faults and 0x0E07 clear_faults (listing is a read: it answers on a
        read-only machine; clearing answers EW_PROT there, like every control write)."""
        machine = self._machine
        if not machine.control_enabled:
            return _EW_FUNC
        clear = command == _CLEAR_FAULTS
        scope = parse_scope(payload, refused=clear and machine.read_only)
        if not isinstance(scope, FaultScope):
            return encode_ew(scope)
        if scope is FaultScope.MACHINE:
            queue: FaultQueue | None = self._shared
        else:
            queue = self._faults
        if not clear:
            return _LIST_ANSWER(FaultQueue().listing() if queue is None else queue.listing())
        cleared = 0 if queue is None else queue.clear()
        if queue is not None and queue is self._faults:
            self._faults = None
        if cleared:
            _log.info(
                "%s: %d fault(s) cleared by %s (%s)", self._label, cleared, self._peer, scope.name
            )
        return _CLEAR_ANSWER(FaultsCleared(cleared))
