"""One scripted packed-protocol peer for the client's tests, and the helpers that drive it.

:class:`ScriptedPeer` listens on 127.0.0.1 and answers like a tiny CNC (:func:`tiny_cnc`). It
records every frame (and which frames arrived in one receive), holds answers back when told
(every answer, or those of some commands) and releases them in any order with any payload, can
answer one byte per write, send raw bytes, or drop its connections. Tests check outcomes and
ordering, never durations.

:func:`hand_driven` gives a connection with no peer at all: a clock the test sets and timers
it fires (:class:`ManualLoop`), a transport that keeps what is written (:class:`Sink`), and
answers fed to ``data_received`` by the test. :class:`LoggedConnection` is a connection whose
transport records its writes (:class:`WriteLog`), for tests of how frames leave.

A plain module (not ``conftest``), so that test modules and mypy can import it; the ``peer``
fixture (a started :class:`ScriptedPeer`) is in ``conftest.py``.
"""

from __future__ import annotations

import asyncio
from collections.abc import Callable, Iterable
from typing import Any

from support import wait_until

from focas_net.client import FocasClient
from focas_net.client.connection import Connection
from focas_net.errors import EW
from focas_net.protocol import (
    COMMANDS,
    Command,
    DataRequest,
    EwReply,
    Frame,
    FrameDecoder,
    ParamValue,
    PmcData,
    StatusInfo,
    encode_frame,
)

__all__ = [
    "BOUND",
    "RDPARAM",
    "STATUS",
    "Answer",
    "LoggedConnection",
    "ManualLoop",
    "PeerSide",
    "ScriptedPeer",
    "Sink",
    "WriteLog",
    "assert_idle",
    "connection_of",
    "hand_driven",
    "param_request",
    "tiny_cnc",
    "turns",
]

BOUND = 10.0  # a safety net for waits that must end much sooner; never a measured duration
RDPARAM = int(Command.RDPARAM)
#: What :func:`tiny_cnc` answers to ``cnc_rdcncstat``.
STATUS = StatusInfo(0, 0, 1, 0, 0, 0, 0, 0, 0)

#: ``answer(frame, peer)``: the payload answering ``frame``, or None for no answer at all.
Answer = Callable[[Frame, "ScriptedPeer"], bytes | None]


def tiny_cnc(frame: Frame, peer: ScriptedPeer) -> bytes | None:
    """What a tiny CNC answers.

    The status is :data:`STATUS`; a parameter reads back its own number; the PMC is
    ``peer.pmc`` (a write past its end answers ``EW_NUMBER``, a write chunk starting at an
    address of ``peer.refuse`` the code given there); with ``peer.password_required`` a
    parameter or PMC write answers ``EW_PASSWD`` until the connection is unlocked with
    ``peer.password``; every other command answers ``EW_FUNC``.
    """
    spec = COMMANDS[frame.command]
    request = spec.request.decode(frame.payload)
    locked = peer.password_required and not peer.unlocked
    value: Any
    if frame.command == Command.RDCNCSTAT:
        value = STATUS
    elif frame.command == Command.RDPARAM:
        value = ParamValue(request.datano, request.axis, request.datano, 4)
    elif frame.command == Command.WRPARAM:
        value = EwReply(EW.PASSWD) if locked else None
    elif frame.command == Command.RDPMCRNG:
        data = bytes(peer.pmc[request.datano_s : request.datano_e + 1])
        value = PmcData(request.type_a, 0, request.datano_s, request.datano_e, data)
    elif frame.command == Command.WRPMCRNG:
        if locked:
            value = EwReply(EW.PASSWD)
        elif request.datano_s in peer.refuse:
            value = EwReply(peer.refuse[request.datano_s])
        elif request.datano_e >= len(peer.pmc):
            value = EwReply(EW.NUMBER)
        else:
            peer.pmc[request.datano_s : request.datano_e + 1] = request.data
            value = None
    elif frame.command == Command.WRUNLOCKPARAM:
        peer.unlocks += 1
        peer.unlocked = request.password == peer.password
        value = None if peer.unlocked else EwReply(EW.PASSWD)
    else:
        value = EwReply(EW.FUNC)
    return spec.response.encode(value)


class PeerSide(asyncio.Protocol):
    """The peer's end of one connection."""

    def __init__(self, peer: ScriptedPeer) -> None:
        self.peer = peer
        self.decoder = FrameDecoder()
        self.transport: asyncio.Transport | None = None

    def connection_made(self, transport: asyncio.BaseTransport) -> None:
        assert isinstance(transport, asyncio.Transport)
        self.transport = transport
        self.peer.sides.append(self)
        self.peer.unlocked = False

    def data_received(self, data: bytes) -> None:
        peer = self.peer
        frames = self.decoder.feed(data)
        peer.receives.append(frames)
        before = peer.answers_sent
        for frame in frames:
            peer.received.append(frame)
            peer.answered_before.append(before)
            if peer.hold or frame.command in peer.hold_commands:
                peer.held.append((frame, self))
            else:
                self.reply(frame)

    def reply(self, frame: Frame, payload: bytes | None = None) -> None:
        """Answer ``frame`` with ``payload`` (None: what ``peer.answer`` gives, which may be
        no answer at all)."""
        if self.transport is None or self.transport.is_closing():
            return
        if payload is None:
            payload = self.peer.answer(frame, self.peer)
            if payload is None:
                return
        self.peer.answers_sent += 1
        self.write(encode_frame(frame.command, frame.request_id, payload))

    def write(self, data: bytes) -> None:
        """Write ``data`` (one byte per write when ``peer.split`` is set)."""
        if self.transport is None or self.transport.is_closing():
            return
        if self.peer.split:
            for i in range(len(data)):
                self.transport.write(data[i : i + 1])
        else:
            self.transport.write(data)

    def connection_lost(self, exc: Exception | None) -> None:
        self.transport = None


class ScriptedPeer:
    """A packed-protocol peer on 127.0.0.1 whose answers the test scripts.

    ``async with ScriptedPeer() as peer:`` starts it on an ephemeral port (``peer.port``)
    and stops it. ``pmc_size`` is the size of its PMC memory.
    """

    def __init__(self, *, pmc_size: int = 4096) -> None:
        self.answer: Answer = tiny_cnc
        self.hold = False
        self.hold_commands: set[int] = set()
        self.held: list[tuple[Frame, PeerSide]] = []
        self.received: list[Frame] = []
        self.receives: list[list[Frame]] = []  # the frames completed by each receive
        self.answered_before: list[int] = []  # answers sent before each frame's receive
        self.answers_sent = 0
        self.sides: list[PeerSide] = []
        self.split = False  # answers (and raw sends) one byte per write
        self.pmc = bytearray(pmc_size)
        self.refuse: dict[int, int] = {}  # first address of a write chunk -> EW code
        self.password = b"1234"
        self.password_required = False
        self.unlocked = False
        self.unlocks = 0
        self.port = 0
        self._server: asyncio.Server | None = None

    @property
    def connections(self) -> int:
        """Connections accepted so far."""
        return len(self.sides)

    async def start(self, port: int = 0) -> None:
        """Listen on ``port`` (0: an ephemeral one)."""
        loop = asyncio.get_running_loop()
        self._server = await loop.create_server(lambda: PeerSide(self), "127.0.0.1", port)
        self.port = self._server.sockets[0].getsockname()[1]

    async def stop(self) -> None:
        """Stop listening and drop every connection (again: no-op)."""
        server, self._server = self._server, None
        if server is not None:
            server.close()
            self.drop()
            await server.wait_closed()

    async def __aenter__(self) -> ScriptedPeer:
        await self.start()
        return self

    async def __aexit__(self, *exc: object) -> None:
        await self.stop()

    def drop(self) -> None:
        """Abort every connection."""
        for side in self.sides:
            if side.transport is not None:
                side.transport.abort()

    async def wait_received(self, n: int) -> None:
        """Wait until ``n`` frames have arrived in all."""
        await wait_until(lambda: len(self.received) >= n, within=BOUND)

    def release(
        self,
        which: Callable[[Frame], bool] = lambda f: True,
        payload: Callable[[Frame], bytes | None] = lambda f: None,
        *,
        reverse: bool = False,
    ) -> list[Frame]:
        """Answer the held frames ``which`` selects, in arrival order (``reverse``: last
        first), with ``payload(frame)`` (None: the usual answer); return them."""
        chosen = [(f, s) for f, s in self.held if which(f)]
        self.held = [(f, s) for f, s in self.held if not which(f)]
        if reverse:
            chosen.reverse()
        for frame, side in chosen:
            side.reply(frame, payload(frame))
        return [f for f, _ in chosen]

    def send_raw(self, data: bytes) -> None:
        """Write ``data`` as it is on every open connection."""
        for side in self.sides:
            side.write(data)


def connection_of(client: FocasClient) -> Connection:
    """The client's current connection (there must be one)."""
    c = client.connection
    assert c is not None
    return c


def param_request(number: int) -> bytes:
    return COMMANDS[Command.RDPARAM].request.encode(DataRequest(number, 0))


async def turns(n: int = 10) -> None:
    """Let the loop run ``n`` turns (for checks that something did NOT happen)."""
    for _ in range(n):
        await asyncio.sleep(0)


def assert_idle(c: Connection) -> None:
    """Nothing in flight, no id reserved, no slot taken or waited for on ``c``."""
    assert c.in_flight == 0
    assert c.abandoned == 0
    assert c.slots_taken == 0
    assert c.waiting_for_slot == 0


class _Timer:
    """A timer :class:`ManualLoop` recorded instead of arming it."""

    def __init__(self, when: float, callback: Callable[[], None]) -> None:
        self.when = when
        self.callback = callback
        self.cancelled = False

    def cancel(self) -> None:
        self.cancelled = True


class ManualLoop:
    """The running loop, but with a clock set by hand and timers fired by hand."""

    def __init__(self, loop: asyncio.AbstractEventLoop) -> None:
        self._loop = loop
        self.now = 0.0
        self.timers: list[_Timer] = []

    def time(self) -> float:
        return self.now

    def call_at(self, when: float, callback: Callable[[], None]) -> _Timer:
        timer = _Timer(when, callback)
        self.timers.append(timer)
        return timer

    def armed(self) -> list[float]:
        return [t.when for t in self.timers if not t.cancelled]

    def fire(self) -> None:
        """Move the clock to the one armed timer and run it."""
        (timer,) = [t for t in self.timers if not t.cancelled]
        self.timers.remove(timer)
        self.now = max(self.now, timer.when)
        timer.callback()

    def __getattr__(self, name: str) -> Any:
        return getattr(self._loop, name)


class Sink:
    """A transport that keeps what is written."""

    def __init__(self) -> None:
        self.frames: list[bytes] = []

    def write(self, data: bytes) -> None:
        self.frames.append(bytes(data))

    def writelines(self, chunks: list[bytes]) -> None:
        self.frames.extend(bytes(c) for c in chunks)

    def is_closing(self) -> bool:
        return False

    def get_extra_info(self, name: str, default: Any = None) -> Any:
        return default

    def set_write_buffer_limits(self, high: int | None = None, low: int | None = None) -> None:
        pass

    def close(self) -> None:
        pass

    def abort(self) -> None:
        pass


class WriteLog(asyncio.Transport):
    """A transport that records the size of every call handing it bytes (``write``, or
    ``writelines`` as one) and passes everything on to the transport it wraps."""

    def __init__(self, inner: asyncio.BaseTransport) -> None:
        super().__init__()
        assert isinstance(inner, asyncio.Transport)
        self.inner = inner
        self.sizes: list[int] = []

    @property
    def writes(self) -> int:
        """Calls that handed bytes to the transport so far."""
        return len(self.sizes)

    def write(self, data: bytes | bytearray | memoryview) -> None:
        self.sizes.append(len(data))
        self.inner.write(data)

    def writelines(self, list_of_data: Iterable[bytes | bytearray | memoryview]) -> None:
        chunks = list(list_of_data)
        self.sizes.append(sum(len(c) for c in chunks))
        self.inner.writelines(chunks)

    def get_extra_info(self, name: str, default: Any = None) -> Any:
        return self.inner.get_extra_info(name, default)

    def is_closing(self) -> bool:
        return self.inner.is_closing()

    def close(self) -> None:
        self.inner.close()

    def abort(self) -> None:
        self.inner.abort()


class LoggedConnection(Connection):
    """A :class:`Connection` whose transport is a :class:`WriteLog` (``log``)."""

    log: WriteLog

    def connection_made(self, transport: asyncio.BaseTransport) -> None:
        self.log = WriteLog(transport)
        super().connection_made(self.log)


def hand_driven(max_in_flight: int = 64) -> tuple[Connection, ManualLoop, Sink]:
    """A connection driven by hand: its loop's clock is a :class:`ManualLoop`'s (the
    connection is made while that is the running loop, so it is the loop the connection
    keeps), its transport a :class:`Sink`, its frames written at once (no gathering per loop
    turn), and its answers whatever the test feeds to ``data_received``."""
    loop = asyncio.get_running_loop()
    clock = ManualLoop(loop)
    asyncio._set_running_loop(clock)  # type: ignore[arg-type]
    try:
        conn = Connection(max_in_flight=max_in_flight, batch_writes=False)
    finally:
        asyncio._set_running_loop(loop)
    sink = Sink()
    conn.connection_made(sink)  # type: ignore[arg-type]
    return conn, clock, sink
