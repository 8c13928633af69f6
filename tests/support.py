"""Helpers shared by the test modules: a real server on 127.0.0.1, a raw wire to it, waiting.

A plain module (not ``conftest``), so that test modules and mypy can import it; the fixtures
built on it are in ``conftest.py``.
"""

from __future__ import annotations

import asyncio
import logging
import os
import re
import socket
import struct
import sys
from collections.abc import AsyncIterator, Iterable
from contextlib import asynccontextmanager
from dataclasses import dataclass
from typing import Any, Self

import pytest

from focas_net.client import FocasClient, NativeClient
from focas_net.protocol import COMMANDS, Frame, FrameDecoder, encode_frame
from focas_net.server import FocasServer, Listener
from focas_net.sim import Machine, MotionData, PathSpec, default_machine
from focas_net.sim.nc import Engine, ManualClock, NcSettings

__all__ = [
    "IO_TIMEOUT",
    "REAL_FILE",
    "SERVE_READY",
    "Served",
    "Wire",
    "ew_of",
    "frame_bytes",
    "sent_until_closed",
    "serve_process",
    "serving",
    "the_warning",
    "two_path_lathe",
    "wait_until",
]

#: Upper bound of any single wait on the network in a test (a hang fails, it never blocks).
IO_TIMEOUT = 5.0

#: A machine file of a parameter of each FANUC kind: real 1420 (3 decimals, per axis), bit
#: 1815 (per axis), word 3216 and 32-bit 6711.
REAL_FILE = """
[machine]
name = "real"
axes = ["X", "Y"]

[parameters.1420]
type = "real"
decimals = 3
axis = true
range = [0, 99999.999]
value = [12.345, "7.5"]

[parameters.1815]
type = "bit"
axis = true
value = ["10110000", 0b00000001]

[parameters.3216]
type = "word"
value = 10

[parameters.6711]
type = "i32"
"""


class Wire:
    """A raw TCP connection speaking frames: no client class, only the protocol codecs."""

    def __init__(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        self.reader = reader
        self.writer = writer
        self.decoder = FrameDecoder()
        self._frames: list[Frame] = []
        self._next_id = 1

    @classmethod
    async def open(cls, host: str, port: int, **kwargs: Any) -> Wire:
        async with asyncio.timeout(IO_TIMEOUT):
            reader, writer = await asyncio.open_connection(host, port, **kwargs)
        return cls(reader, writer)

    @property
    def sockname(self) -> Any:
        """This end's address."""
        return self.writer.get_extra_info("sockname")

    def next_id(self) -> int:
        rid = self._next_id
        self._next_id = (rid + 1) & 0xFFFF
        return rid

    def send(self, command: int, payload: bytes = b"", request_id: int | None = None) -> int:
        """Queue one request frame; returns its request id."""
        rid = self.next_id() if request_id is None else request_id
        self.writer.write(encode_frame(command, rid, payload))
        return rid

    def send_raw(self, data: bytes) -> None:
        self.writer.write(data)

    async def recv(self, within: float = IO_TIMEOUT) -> Frame:
        """The next answer frame (EOFError when the server closed the connection)."""
        async with asyncio.timeout(within):
            while not self._frames:
                chunk = await self.reader.read(65_536)
                if not chunk:
                    raise EOFError("connection closed by the server")
                self._frames.extend(self.decoder.feed(chunk))
        return self._frames.pop(0)

    async def recv_many(self, n: int, within: float = IO_TIMEOUT) -> list[Frame]:
        """The next ``n`` answer frames, all within ``within`` seconds."""
        async with asyncio.timeout(within):
            return [await self.recv() for _ in range(n)]

    async def call(self, command: int, payload: bytes = b"") -> bytes:
        """Send one request, wait for its answer, check command and id; the answer payload."""
        rid = self.send(command, payload)
        await self.writer.drain()
        frame = await self.recv()
        assert frame.command == command, f"answer to 0x{command:04X} has 0x{frame.command:04X}"
        assert frame.request_id == rid
        return frame.payload

    async def request(self, command: int, value: Any = None) -> Any:
        """Encode ``value`` with the command's request codec; decode the answer."""
        spec = COMMANDS[command]
        answer = await self.call(command, spec.request.encode(value))
        return spec.response.decode(answer)

    async def ew(self, command: int, payload: bytes = b"") -> int:
        """The EW code of an answer (for counted lists: the code after ``count = -1``)."""
        answer = await self.call(command, payload)
        return ew_of(command, answer)

    async def closed_by_peer(self, within: float = IO_TIMEOUT) -> bool:
        """True when the server closes this connection (reads until EOF, dropping data)."""
        try:
            async with asyncio.timeout(within):
                while True:
                    chunk = await self.reader.read(65_536)
                    if not chunk:
                        return True
        except (ConnectionResetError, BrokenPipeError):
            return True
        except TimeoutError:
            return False

    async def close(self) -> None:
        self.writer.close()
        try:
            async with asyncio.timeout(IO_TIMEOUT):
                await self.writer.wait_closed()
        except (ConnectionError, TimeoutError):
            pass

    async def __aenter__(self) -> Wire:
        return self

    async def __aexit__(self, *exc: object) -> None:
        await self.close()


def ew_of(command: int, answer: bytes) -> int:
    """The EW code an answer carries (0 on success)."""
    if COMMANDS.get(command) is not None and COMMANDS[command].counted:
        (count,) = struct.unpack_from("<h", answer, 0)
        if count >= 0:
            return 0
        return int(struct.unpack_from("<h", answer, 2)[0])
    return int(struct.unpack_from("<h", answer, 0)[0])


def frame_bytes(frames: Iterable[tuple[int, int, bytes]]) -> bytes:
    return b"".join(encode_frame(c, r, p) for c, r, p in frames)


@dataclass
class Served:
    """What the ``server`` fixture yields."""

    server: FocasServer
    host: str
    port: int
    machine: Machine

    @property
    def listener(self) -> Listener:
        return self.server.listeners[0]

    async def connect(self) -> Wire:
        return await Wire.open(self.host, self.port)


@asynccontextmanager
async def serving(machine: Machine | None = None, **kwargs: Any) -> AsyncIterator[Served]:
    """Serve ``machine`` (default: a fresh default machine) on 127.0.0.1, an ephemeral port."""
    machine = default_machine() if machine is None else machine
    kwargs.setdefault("grace_period", 1.0)
    async with FocasServer(machine, host="127.0.0.1", port=0, **kwargs) as srv:
        host, port = srv.listeners[0].address
        yield Served(srv, host, port, machine)


class LoopbackPeer:
    """A stream server on 127.0.0.1, an ephemeral port, answering with :meth:`_serve`
    (a subclass's): started and stopped by ``async with`` or :meth:`start`/:meth:`stop`."""

    port = 0
    _server: asyncio.Server | None = None

    async def _serve(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        raise NotImplementedError

    async def start(self) -> None:
        self._server = await asyncio.start_server(self._serve, "127.0.0.1", 0)
        self.port = self._server.sockets[0].getsockname()[1]

    async def stop(self) -> None:
        assert self._server is not None
        self._server.close()
        await self._server.wait_closed()

    async def __aenter__(self) -> Self:
        await self.start()
        return self

    async def __aexit__(self, *exc: object) -> None:
        await self.stop()


def reset_at_close(sock: socket.socket) -> None:
    """SO_LINGER 0 on ``sock``: its close sends a reset, whatever the peer sent (a bare close
    resets only when data the peer sent is unread, else it ends with a FIN)."""
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, struct.pack("ii", 1, 0))


def free_port() -> int:
    """A port of 127.0.0.1 free a moment ago, for a server that must be told its port before
    it starts (a broker's file, a restart on the same port)."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port: int = s.getsockname()[1]
        return port


async def wait_until(predicate: Any, within: float = IO_TIMEOUT) -> None:
    """Yield to the loop until ``predicate()`` is true; fail after ``within`` seconds."""
    step = 0.005
    for _ in range(int(within / step) + 1):
        if predicate():
            return
        await asyncio.sleep(step)
    pytest.fail(f"condition not met within {within} s: {predicate}")


#: A ready line of ``focas-net serve``: the machine's name, its modes, its address.
SERVE_READY = re.compile(
    r"^focas-net: (?P<name>\S+)(?: \((?P<modes>[^)]*)\))? listening on "
    r"(?P<host>[\d.]+):(?P<port>\d+)$"
)


@asynccontextmanager
async def killed_at_exit(
    proc: asyncio.subprocess.Process,
) -> AsyncIterator[asyncio.subprocess.Process]:
    """``proc`` for the block; killed (and waited for) at its end unless it ended already:
    a test that fails or times out leaves no process behind."""
    try:
        yield proc
    finally:
        if proc.returncode is None:
            proc.kill()
            await proc.wait()


@asynccontextmanager
async def serve_process(
    *args: str, lines: int, start_timeout: float
) -> AsyncIterator[tuple[asyncio.subprocess.Process, list[re.Match[str]]]]:
    """``python -m focas_net serve --host 127.0.0.1 --port 0 ARGS`` until ``lines`` ready
    lines came (each must be one, within ``start_timeout`` in all); killed at the end if it
    is still running."""
    proc = await asyncio.create_subprocess_exec(
        sys.executable, "-m", "focas_net", "serve", "--host", "127.0.0.1", "--port", "0", *args,
        stdout=asyncio.subprocess.PIPE, stderr=asyncio.subprocess.PIPE,
        env={**os.environ, "PYTHONUNBUFFERED": "0"},
    )  # fmt: skip
    assert proc.stdout is not None
    ready: list[re.Match[str]] = []
    async with killed_at_exit(proc):
        async with asyncio.timeout(start_timeout):
            for _ in range(lines):
                line = (await proc.stdout.readline()).decode().rstrip("\n")
                match = SERVE_READY.match(line)
                assert match is not None, f"unexpected output: {line!r}"
                ready.append(match)
        yield proc, ready


class ChannelLog:
    """The connections the native client opens, as it opens them (A, B, A, B...): installed
    over the module function the client connects with, so a test can watch or break them
    without reaching into the client."""

    def __init__(self, monkeypatch: pytest.MonkeyPatch) -> None:
        from focas_net.client import _native_link
        from focas_net.client._channel import open_channel as real

        self.opened: list[Any] = []

        async def recording(host: str, port: int) -> Any:
            channel = await real(host, port)
            self.opened.append(channel)
            return channel

        monkeypatch.setattr(_native_link, "open_channel", recording)

    @property
    def b(self) -> Any:
        """Connection B of the pair opened last."""
        assert len(self.opened) >= 2, "no connection pair opened yet"
        return self.opened[-1]


def drop_native(served: Served) -> None:
    """The server ends every native connection it has (as a CNC that goes away)."""
    for listener in served.server.listeners:
        for conn in list(listener.native_connections):
            conn.abort()


def _motion(axes: int, base: int, feed: int, running: int) -> MotionData:
    return MotionData(
        [base + i for i in range(axes)],
        [2 * base + i for i in range(axes)],
        [3 * base + i for i in range(axes)],
        [0] * axes,
        feed=feed,
        spindle_speed=feed // 2,
        program_running=running,
        program_main=running,
    )


def two_path_lathe() -> Machine:
    """A machine of two paths for the path tests: two turrets, X1/Z1 and X2/Z2/C2, each
    path's figures (positions, feed, program numbers) its own."""
    return Machine(
        "lathe",
        paths=[
            PathSpec(("X1", "Z1"), kind="T", motion=_motion(2, 1000, 1500, 1)),
            PathSpec(("X2", "Z2", "C2"), kind="T", motion=_motion(3, 5000, 700, 2)),
        ],
    )


def started_engine(text: str, settings: NcSettings | None = None) -> tuple[Engine, ManualClock]:
    """An engine of its own manual clock (and ``settings``, a machining centre's by default)
    at cycle start of ``text``, its first program, with that clock."""
    clock = ManualClock()
    engine = Engine(clock, settings or NcSettings())
    engine.store.select(engine.store.store(text).number)
    engine.cycle_start()
    return engine, clock


def alarm_words(engine: Engine) -> str | None:
    """``engine``'s alarm as its code and detail (``PS0010 G99 ...``); None without one."""
    alarm = engine.alarm
    return None if alarm is None else f"PS{alarm.number:04d} {alarm.detail}"


def block_run(block: str, seconds: float = 5.0) -> Engine:
    """An engine of its own manual clock that ran ``O1``, ``block``, ``M30`` from cycle start
    for ``seconds`` of that clock."""
    clock = ManualClock()
    engine = Engine(clock)
    engine.store.store(f"O1\n{block}\nM30\n")
    engine.store.select(1)
    engine.cycle_start()
    clock.advance(seconds)
    return engine


@asynccontextmanager
async def with_both_clients(
    machine: Machine,
) -> AsyncIterator[tuple[Machine, FocasClient, NativeClient]]:
    """``machine`` served on 127.0.0.1, with a packed and a FOCAS/2 client connected to it."""
    async with FocasServer(machine, port=0) as server:
        host, port = server.addresses[0]
        async with (
            FocasClient(host, port, timeout=5) as cnc,
            NativeClient(host, port, timeout=5) as native,
        ):
            yield machine, cnc, native


async def sent_until_closed(port: int, sent: bytes, caplog: pytest.LogCaptureFixture) -> int:
    """Send ``sent`` on a new connection to 127.0.0.1:``port`` and read until the server
    closes it (its warnings captured meanwhile); the connection's own port."""
    reader, writer = await asyncio.open_connection("127.0.0.1", port)
    local: int = writer.get_extra_info("sockname")[1]
    with caplog.at_level(logging.WARNING, logger="focas_net.server"):
        writer.write(sent)
        assert await asyncio.wait_for(reader.read(), IO_TIMEOUT) == b""
    writer.close()
    return local


def the_warning(caplog: pytest.LogCaptureFixture) -> str:
    """The one warning logged (it fails when there were none or more)."""
    (record,) = [r for r in caplog.records if r.levelno == logging.WARNING]
    return record.getMessage()
