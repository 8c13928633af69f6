"""A packed-protocol connection (``docs/protocol.md``): the per-frame data path of the server.

One loop, :meth:`PackedConnection._run`, answers the requests of a read, in order, each
synchronously by the machine's packed adapter, and all answers produced by one read leave in one
write, joined. (asyncio's own ``writelines`` on CPython 3.12.0-3.12.8 and 3.13.0-3.13.1 skips
the write buffer's high-water check, CPython gh-127655: with it ``pause_writing`` never came,
and a peer that never read held the server's memory without bound. Joining and writing is what
``writelines`` did before 3.12.) Its requests come from one of two places: the usual read
(nothing held from earlier input, no debug log) is scanned where it was read, in the receive
buffer, by the decoder's own :func:`~focas_net.protocol.scan_frames`; any other goes through the
incremental :class:`FrameDecoder`. Delayed answers (fault injection) are timer callbacks.
Backpressure, the backlog, delays and shutdown are :class:`~._base.BaseConnection`'s.

The machine is reached only through its :class:`~focas_net.adapters.PackedAdapter` (shared by
the listener's connections, so they share its answer caches): ``answer`` and ``error_answer``,
the first through :meth:`PackedConnection._answer` alone, which keeps a failing request from
taking the connection down.
"""

from __future__ import annotations

import logging
from typing import TYPE_CHECKING, Final

from focas_net.errors import EW, FrameError
from focas_net.protocol import (
    COMMANDS,
    HEADER,
    Command,
    FaultsCleared,
    FrameDecoder,
    RawFrame,
    encode_ew,
    scan_frames,
)
from focas_net.protocol.frame import foreign_client

from ._base import SLICE, BaseConnection, CloseCallback, Limits
from .faults import FaultKind, FaultQueue, FaultScope, parse_inject, parse_scope

if TYPE_CHECKING:
    import asyncio

    from focas_net.adapters import PackedAdapter
    from focas_net.sim import Session

__all__ = ["PackedConnection"]

_log = logging.getLogger("focas_net.server")

_pack_header = HEADER.pack
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
_GETPATH: Final = int(Command.GETPATH)
_SETPATH: Final = int(Command.SETPATH)
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

    __slots__ = ("_adapter", "_decoder", "_machine", "_path", "_session")

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
        #: The path this connection's per-path requests are answered for: 1 when it opens,
        #: set by cnc_setpath in the order the requests arrive; 0 after a refused one (none:
        #: every per-path request answers EW_PATH until a cnc_setpath is accepted).
        self._path = 1
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
        _log.debug("%s: connection from %s", self._label, self.peer_text)

    # -- the data path ---------------------------------------------------------------------

    def buffer_updated(self, nbytes: int) -> None:
        # The usual read, of at most SLICE bytes with nothing held from earlier input and no
        # debug log: a poller's one request, or a pipelining client's many. Its whole requests
        # are found in the receive buffer by the decoder's own scan and answered at once, the
        # read not copied and the decoder left out; what follows them (a partial request, a
        # length out of bounds) goes on to data_received after their answers. Any other read
        # goes to data_received whole.
        view = self._view
        if (
            nbytes > SLICE
            or self._backlog is not None
            or self._decoder.held
            or self._transport is None
            or self._closing
            or _log.isEnabledFor(_DEBUG)
        ):
            self.data_received(view[:nbytes].tobytes())
            return
        frames, end, _ = scan_frames(view, self._decoder.max_frame, nbytes)
        if frames:
            self.idle_sweeps = 0
            self._run(frames)
        if end < nbytes:
            self.data_received(view[end:nbytes].tobytes())

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
            _log.debug("%s: from %s: %s", self._label, self.peer_text, _dump_frames(frames))
        self.idle_sweeps = 0
        return self._run(frames)

    def _run(self, frames: list[RawFrame]) -> bool:
        """Answer ``frames`` in order, their answers joined in one write (one more each time
        they reach the write budget); False when output backpressure stopped it part way (the
        rest is kept in the backlog) or the connection was closed.

        The fault commands are answered from the fault queues; while a fault is armed, every
        request but a simulator control takes the next one (:meth:`_apply_fault`).
        """
        transport = self._transport
        assert transport is not None
        shared = self._shared
        budget = self._limits.write_buffer_high
        out: list[bytes] = []
        size = 0
        index = 0  # requests taken from frames so far
        for command, request_id, payload in frames:
            index += 1
            if command in _FAULT_COMMANDS:
                if command == _INJECT_FAULT:
                    reply = self._inject_fault(payload)
                else:
                    reply = self._fault_queue(command, payload)
            else:
                if (
                    (shared.armed or self._faults is not None)
                    and not (_CONTROL_FIRST <= command <= _CONTROL_LAST)
                    and command != _SETPATH
                    and command != _GETPATH
                ):
                    fault = self._take_fault()
                    if fault is not None:
                        if not self._apply_fault(fault, command, request_id, payload, out):
                            return False  # the connection was closed instead of answering
                        if self._write_paused or self._delayed_full():
                            return self._stop_writing(frames, index, out)
                        continue
                reply = self._answer(command, payload)
            out.append(_pack_header(len(reply) + 4, command, request_id))
            out.append(reply)
            size += len(reply)
            if size >= budget:
                transport.write(_join(out))
                out.clear()
                size = 0
                if self._write_paused:  # the write buffer passed its high-water mark
                    return self._stop_writing(frames, index, out)
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
        """The machine's answer to one request. A bug in the machine must not take the
        connection down: it is logged and answered EW_REJECT."""
        try:
            if command == _SETPATH:
                answer, self._path = self._adapter.select_path(payload)
                return answer
            if command == _GETPATH:
                return self._adapter.path_answer(payload, self._path)
            return self._adapter.answer(self._session, command, payload, self._path)  # type: ignore[arg-type]
        except Exception:
            _log.exception(
                "%s: command 0x%04X from %s failed", self._label, command, self.peer_text
            )
            return self._adapter.error_answer(command, EW.REJECT)

    def _apply_fault(
        self,
        fault: tuple[FaultKind, int],
        command: int,
        request_id: int,
        payload: bytes,
        out: list[bytes],
    ) -> bool:
        """Answer one request under ``fault``, ``out`` holding the answers not written yet;
        False when the connection was closed instead.

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
            return True
        if kind is _DROP_KIND:
            if out:
                transport.write(_join(out))
            self._drop()
            return False
        answer = self._answer(command, payload)
        frame = _pack_header(len(answer) + 4, command, request_id) + answer
        if kind is _DELAY_KIND:
            self._delay(arg, frame)
            return True
        # SPLIT: what came before goes first, then this answer one byte per write
        if out:
            transport.write(_join(out))
            out.clear()
        self._write_split(frame)
        return True

    def _framing_violation(self, exc: FrameError, data: bytes | memoryview) -> None:
        why = str(exc).removesuffix("; closing the connection")
        if not exc.frames:  # (a client of another protocol fails at its first bytes)
            hint = foreign_client(data)
            if hint is not None:
                why = f"{why}; {hint}"
        _log.warning("%s: closing the connection from %s: %s", self._label, self.peer_text, why)
        if _log.isEnabledFor(_DEBUG):
            # Whole frames only: raw bytes could hold part of an unlock request's password.
            _log.debug(
                "%s: offending chunk from %s: %d bytes, whole frames before the violation: %s",
                self._label,
                self.peer_text,
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
        _log.info("%s: %s armed by %s (%s)", self._label, fault, self.peer_text, scope.name)
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
                "%s: %d fault(s) cleared by %s (%s)",
                self._label,
                cleared,
                self.peer_text,
                scope.name,
            )
        return _CLEAR_ANSWER(FaultsCleared(cleared))
