"""A native FOCAS/2 Ethernet connection (``docs/native-protocol.md``).

Per connection: an open request (``0x0101``) is answered with an open response; data requests
(``0x2101``) are answered block for block, each answer in one ``transport.write``; program
transfer frames (uploads and downloads) are answered by the adapter with this connection's
transfer state; a close request (``0x0201``) is answered and the connection closed. A
framing violation (bad magic, a body longer than ``max_body``, a broken block list, a data
request before the open, a frame type not served) closes that connection only and is logged
at WARNING with the peer's address.

Fault injection applies to data-request answers (the open and close answers are never faulted
and never count): a forced EW code answers every block of the request with that code and no
data, without running the request; a delay holds the answer back; a drop closes the connection
instead of answering; a split writes the answer one byte per write. Backpressure, the backlog,
delays and shutdown are :class:`~._base.BaseConnection`'s.

The native adapter is reached only through :class:`NativeFront` (one per machine).
"""

from __future__ import annotations

import logging
from typing import TYPE_CHECKING, Final

from focas_net.adapters import NativeAdapter, ProgramTransfer
from focas_net.native import (
    FrameType,
    NativeFrame,
    NativeFrameDecoder,
    NativeFrameError,
    OpenRequest,
)
from focas_net.protocol import COMMANDS, DEFAULT_MAX_FRAME, HEADER
from focas_net.protocol.frame import foreign_client

from ._base import BaseConnection, CloseCallback, Limits
from .faults import FaultKind, FaultQueue

if TYPE_CHECKING:
    import asyncio

    from focas_net.sim import Machine, Session

__all__ = ["NativeConnection", "NativeFront"]

_log = logging.getLogger("focas_net.server")

_DEBUG: Final = logging.DEBUG
_DATA_REQUEST: Final = int(FrameType.DATA_REQUEST)
_OPEN_REQUEST: Final = int(FrameType.OPEN_REQUEST)
_CLOSE_REQUEST: Final = int(FrameType.CLOSE_REQUEST)
_DELAY_KIND: Final = FaultKind.DELAY
_ERROR_KIND: Final = FaultKind.ERROR
_DROP_KIND: Final = FaultKind.DROP


def _foreign_client(head: bytes | memoryview) -> str | None:
    """What a client of another protocol whose first bytes are ``head`` is, in words: a packed
    client by the FOCAS function of its first frame, else :func:`foreign_client` (a TLS or an
    HTTP client); no byte is shown."""
    if len(head) >= HEADER.size:
        length, command, _ = HEADER.unpack_from(head)
        spec = COMMANDS.get(command)
        if spec is not None and 4 <= length <= DEFAULT_MAX_FRAME:
            return (
                f"it sent a packed frame ({spec.focas_name}): a packed client, on a port that "
                "speaks FOCAS/2 only"
            )
    return foreign_client(head)


class NativeFront:
    """The native protocol in front of one machine: its answers and its fixed frames.

    ``version`` overrides the version word of every answer, which the machine's control class
    picks otherwise (2 for a 16i-class control, 3 for a 0i-D/0i-F or 30i class one); it also
    picks the command set FANUC's library uses.
    """

    __slots__ = ("_adapter", "close_response", "open_response", "version")

    def __init__(self, machine: Machine, version: int | None = None) -> None:
        self._adapter = NativeAdapter(machine, version=version)
        self.version = self._adapter.version
        self.open_response = self._adapter.open_response()
        self.close_response = self._adapter.close_response()

    @property
    def machine(self) -> Machine:
        return self._adapter.machine

    def answer(self, body: bytes, session: Session | None = None) -> bytes:
        """The data-response frame answering a data-request body (NativeFrameError when the
        block list is broken or too long); ``session`` is the connection's."""
        return self._adapter.answer(body, session)

    def forced_answer(self, body: bytes, ew: int) -> bytes:
        """The data-response frame answering every block of ``body`` with ``ew``."""
        return self._adapter.forced_answer(body, ew)

    def new_transfer(self) -> ProgramTransfer:
        """A connection's program-transfer state (nothing under way)."""
        return ProgramTransfer()

    def transfer(self, frame_type: int, body: bytes, state: ProgramTransfer) -> list[bytes] | None:
        """The frames answering a program-transfer frame (upload, download); None when
        ``frame_type`` is not one (a violation)."""
        return self._adapter.transfer(frame_type, body, state)


class NativeConnection(BaseConnection[NativeFrame]):
    """One native connection: frames in, answers out.

    ``front`` answers for the machine, ``faults`` is the machine-wide fault queue, ``limits``
    the server's bounds, ``on_close`` is called once when the transport is gone; ``label``
    names the connection's machine in logs.
    """

    __slots__ = ("_decoder", "_front", "_opened", "_session", "_transfer")

    def __init__(
        self,
        front: NativeFront,
        faults: FaultQueue,
        limits: Limits,
        on_close: CloseCallback,
        label: str,
    ) -> None:
        super().__init__(label, faults, limits, on_close)
        self._front = front
        self._decoder = NativeFrameDecoder(limits.max_body)
        self._opened = False
        #: This connection's parameter-write state (FANUC's library has no unlock call).
        self._session = front.machine.new_session()
        #: This connection's program transfer (upload, download), if one is under way.
        self._transfer = front.new_transfer()

    @property
    def buffered_input(self) -> int:
        """Bytes received and not answered yet (a partial frame, plus any backlog)."""
        held = self._decoder.buffered
        backlog = self._backlog
        if backlog is not None:
            held += len(backlog.input)
            if backlog.frames:
                held += sum(10 + len(f.body) for f in backlog.frames)
        return held

    # -- asyncio.Protocol ------------------------------------------------------------------

    def connection_made(self, base: asyncio.BaseTransport) -> None:
        super().connection_made(base)
        _log.debug("%s: connection from %s", self._label, self.peer_text)

    # -- the data path ---------------------------------------------------------------------

    def _feed(self, chunk: bytes | memoryview) -> bool:
        if _log.isEnabledFor(_DEBUG):
            _log.debug("%s: %s >> %s", self._label, self.peer_text, bytes(chunk).hex(" "))
        try:
            frames = self._decoder.feed(chunk)
        except NativeFrameError as exc:
            # The frames before the violation are answered first; a close request among them
            # ends the connection before the violating bytes are read.
            if not exc.frames or self._run(exc.frames) or not self._closing:
                why = str(exc)
                hint = None if exc.frames or self._opened else _foreign_client(chunk)
                self._violation(why if hint is None else f"{why}; {hint}")
            return False
        if not frames:
            return True
        self.idle_sweeps = 0
        return self._run(frames)

    def _run(self, frames: list[NativeFrame]) -> bool:
        transport = self._transport
        assert transport is not None
        front = self._front
        shared = self._shared
        for index, (version, frame_type, body) in enumerate(frames):
            if frame_type == _DATA_REQUEST:
                if not self._opened:
                    self._violation("data request before the open request")
                    return False
                if shared.armed or self._faults is not None:
                    fault = self._take_fault()
                    if fault is not None:
                        if not self._apply_fault(fault, body):
                            return False
                        if self._write_paused or self._delayed_full():
                            return self._stop(frames, index + 1)
                        continue
                answer = self._answer(body)
                if answer is None:
                    return False
                self._write(answer)
            elif frame_type == _OPEN_REQUEST:
                try:
                    OpenRequest.decode(body)
                except NativeFrameError as exc:
                    self._violation(str(exc))
                    return False
                self._opened = True
                self._write(front.open_response)
            elif frame_type == _CLOSE_REQUEST:
                self._write(front.close_response)
                # Nothing after a close request is read; delayed answers still go out first.
                self._closing = True
                self._backlog = None
                if not self._delayed:
                    transport.close()
                return False
            else:
                answers = front.transfer(frame_type, body, self._transfer) if self._opened else None
                if answers is None:
                    self._violation(f"frame type 0x{frame_type:04X} (version {version}) not served")
                    return False
                for answer in answers:
                    self._write(answer)
            if self._write_paused:
                return self._stop(frames, index + 1)
        return True

    # -- helpers ---------------------------------------------------------------------------

    def _write(self, answer: bytes) -> None:
        transport = self._transport
        assert transport is not None
        if _log.isEnabledFor(_DEBUG):
            _log.debug("%s: %s << %s", self._label, self.peer_text, answer.hex(" "))
        transport.write(answer)

    def _answer(self, body: bytes, ew: int | None = None) -> bytes | None:
        """The data-response frame answering the data-request ``body`` (with ``ew``: every
        block answered that EW code, the request not run); None when the body is broken (a
        violation: the connection was closed)."""
        try:
            if ew is not None:
                return self._front.forced_answer(body, ew)
            return self._front.answer(body, self._session)
        except NativeFrameError as exc:
            self._violation(str(exc))
            return None

    def _apply_fault(self, fault: tuple[FaultKind, int], body: bytes) -> bool:
        """Answer one data request under ``fault``; False when the connection was closed."""
        kind, arg = fault
        if kind is _DROP_KIND:
            self._drop()
            return False
        answer = self._answer(body, arg if kind is _ERROR_KIND else None)
        if answer is None:
            return False
        if kind is _ERROR_KIND:
            self._write(answer)
        elif kind is _DELAY_KIND:
            self._delay(arg, answer)
        else:  # SPLIT
            self._write_split(answer)
        return True

    def _violation(self, reason: str) -> None:
        _log.warning("%s: closing the connection from %s: %s", self._label, self.peer_text, reason)
        self.violated = True
        self._closing = True
        self._backlog = None
        self._cancel_delayed()
        transport = self._transport
        if transport is not None:
            transport.close()  # what was written already is still sent
