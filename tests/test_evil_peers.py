"""Peers that misbehave on purpose: slowloris, never reading, connection floods, resets in the
middle of a frame, half-closed connections.

Every test runs a real :class:`FocasServer` on 127.0.0.1 (port 0) in this process and checks
behaviour through the server's own state (its connections, counters, paused reading and
buffered bytes), never through elapsed time. Every loop is bounded.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import socket
import struct
from collections.abc import Iterator
from typing import Any, Final

import pytest
from support import IO_TIMEOUT, Served, ew_of, serving, wait_until

from focas_net.adapters import PackedAdapter
from focas_net.protocol import (
    AlarmHistory,
    AlarmHistoryRequest,
    Command,
    FrameDecoder,
    InjectFault,
    MacroRequest,
    MacroValue,
    RaiseAlarm,
    encode_frame,
)
from focas_net.server import PackedConnection

STATUS: Final = int(Command.RDCNCSTAT)
RDPMC: Final = int(Command.RDPMCRNG)
#: asyncio's selector transports read at most this many bytes per ``recv``.
READ_CHUNK: Final = 256 * 1024
MAX_FRAME: Final = 65_536


@pytest.fixture
def server_errors(caplog: pytest.LogCaptureFixture) -> Iterator[list[logging.LogRecord]]:
    """Records at ERROR or above logged by the library during the test (must stay empty)."""
    caplog.set_level(logging.INFO, logger="focas_net")
    records: list[logging.LogRecord] = []
    yield records
    records.extend(
        r for r in caplog.records if r.levelno >= logging.ERROR and r.name.startswith("focas_net")
    )
    assert not records, [r.getMessage() for r in records]


async def assert_serves(served: Served) -> None:
    """A fresh connection is accepted and answered."""
    async with await served.connect() as wire:
        assert ew_of(STATUS, await wire.call(STATUS)) == 0


def reset(sock: socket.socket) -> None:
    """Close with SO_LINGER 0: the peer gets a RST instead of a FIN."""
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, struct.pack("ii", 1, 0))
    sock.close()


async def raw_socket(
    served: Served, rcvbuf: int | None = None, sndbuf: int | None = None
) -> socket.socket:
    """A non-blocking socket connected to ``served`` (the server has accepted it)."""
    loop = asyncio.get_running_loop()
    sock = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
    sock.setblocking(False)
    if rcvbuf is not None:
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, rcvbuf)
    if sndbuf is not None:
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_SNDBUF, sndbuf)
    async with asyncio.timeout(IO_TIMEOUT):
        await loop.sock_connect(sock, (served.host, served.port))
    me = sock.getsockname()[:2]
    await wait_until(lambda: any(c.peer[:2] == me for c in served.listener.connections))
    return sock


def connection_of(served: Served, sock: socket.socket) -> PackedConnection:
    """The server side of ``sock``."""
    me = sock.getsockname()[:2]
    (conn,) = [c for c in served.listener.connections if c.peer[:2] == me]
    return conn


HISTORY: Final = int(Command.RDALMHISTRY)
HISTORY_DEPTH: Final = 5
HISTORY_REQUEST: Final = AlarmHistoryRequest(HISTORY_DEPTH).encode()
HISTORY_FRAME_SIZE: Final = 8 + len(HISTORY_REQUEST)


async def fill_history(served: Served) -> None:
    """20 alarms in the history: each history answer is about 300 bytes, 30 times its
    request."""
    async with await served.connect() as wire:
        for no in range(20):
            raise_alarm = RaiseAlarm(0, 3, 1000 + no, b"M" * 32).encode()
            assert await wire.ew(Command.SIM_RAISE_ALARM, raise_alarm) == 0


def history_requests(count: int) -> memoryview:
    return memoryview(
        b"".join(encode_frame(HISTORY, i & 0xFFFF, HISTORY_REQUEST) for i in range(count))
    )


# -- slowloris -----------------------------------------------------------------------------


async def test_one_byte_slower_than_the_idle_timeout_is_closed(
    server_errors: list[logging.LogRecord],
) -> None:
    async with serving(idle_timeout=0.5) as served:
        frame = encode_frame(STATUS, 1)
        sent = 0
        closed = False
        async with await served.connect() as wire:
            for i in range(len(frame)):  # at most one frame, one byte at a time
                try:
                    wire.send_raw(frame[i : i + 1])
                    await wire.writer.drain()
                except ConnectionError:
                    closed = True
                    break
                sent += 1
                # wait longer than the idle timeout before the next byte
                if await wire.closed_by_peer(within=0.8):
                    closed = True
                    break
        assert closed, "the server kept a connection that never completed a request"
        assert sent < len(frame), "the request was completed before the close"
        await wait_until(lambda: not served.listener.connections)
        await assert_serves(served)


async def test_dripping_faster_than_the_timeout_without_a_whole_request_is_closed(
    server_errors: list[logging.LogRecord],
) -> None:
    """The idle timeout counts complete requests, not bytes: a peer trickling a large frame a
    byte at a time, well within the timeout per byte, is still closed."""
    async with serving(idle_timeout=0.5) as served:
        frame = encode_frame(STATUS, 1, bytes(1_000))  # never completed below
        closed = False
        async with await served.connect() as wire:
            for i in range(60):  # 60 bytes at most, each well within the timeout
                try:
                    wire.send_raw(frame[i : i + 1])
                    await wire.writer.drain()
                except ConnectionError:
                    closed = True
                    break
                if await wire.closed_by_peer(within=0.1):
                    closed = True
                    break
        assert closed
        assert served.listener.violations == 0  # closed as idle, not as a framing violation
        await assert_serves(served)


async def test_a_client_with_regular_requests_outlives_the_idle_timeout(
    server_errors: list[logging.LogRecord],
) -> None:
    async with serving(idle_timeout=0.5) as served:
        async with await served.connect() as wire:
            for _ in range(8):  # 8 requests 0.15 s apart: together longer than the timeout
                assert ew_of(STATUS, await wire.call(STATUS)) == 0
                await asyncio.sleep(0.15)
            assert ew_of(STATUS, await wire.call(STATUS)) == 0
            assert len(served.listener.connections) == 1


# -- a client that sends but never reads ---------------------------------------------------


def _unchecked_writelines(transport: Any, list_of_data: Any) -> None:
    """A selector transport's ``writelines`` as CPython 3.12.0-3.12.8 and 3.13.0-3.13.1 have
    it (gh-127655): written without the high-water check, so ``pause_writing`` never comes."""
    paused = transport._protocol_paused
    transport._protocol_paused = True  # the transport's check skips a paused protocol
    try:
        transport.write(b"".join(list_of_data))
    finally:
        transport._protocol_paused = paused


@pytest.mark.parametrize("writelines", ["asyncio's", "without the high-water check"])
async def test_a_client_that_never_reads_is_held_by_backpressure(
    server_errors: list[logging.LogRecord], writelines: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    if writelines != "asyncio's":
        # the server's backpressure must not depend on writelines checking the limit
        transport_class = asyncio.selector_events._SelectorSocketTransport  # type: ignore[attr-defined]
        monkeypatch.setattr(transport_class, "writelines", _unchecked_writelines)
    high = 16 * 1024
    async with serving(write_buffer_high=high) as served:
        loop = asyncio.get_running_loop()
        await fill_history(served)
        history, size = HISTORY, HISTORY_FRAME_SIZE
        data = history_requests(200_000)
        sock = await raw_socket(served, rcvbuf=4_096, sndbuf=8_192)
        try:
            sent = 0
            stalls = 0
            for _ in range(100_000):  # bounded: ends when the kernel buffers are full
                if stalls >= 40 or sent == len(data):
                    break
                try:
                    sent += sock.send(data[sent:])
                    stalls = 0
                except BlockingIOError:
                    stalls += 1
                    await asyncio.sleep(0.01)
            assert sent < len(data), "the server kept reading from a peer that never reads"
            requests = -(-sent // size)  # a last partial frame is finished below
            conn = connection_of(served, sock)
            await wait_until(lambda: conn.reading_paused)
            # bounded: the write buffer stays near its high-water mark and the input held back
            # is at most one read of the transport, however long the peer keeps pushing
            bound_out = 2 * high + 16 * 1024
            bound_in = READ_CHUNK + MAX_FRAME
            for _ in range(20):
                assert conn.reading_paused
                assert conn.write_buffer_size <= bound_out
                assert conn.buffered_input <= bound_in
                with contextlib.suppress(BlockingIOError):
                    sent += sock.send(data[sent : requests * size])
                await asyncio.sleep(0.01)
            # now read: every request sent is answered exactly once, in order
            sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 1 << 20)
            machine = served.machine
            expected = PackedAdapter(machine).answer(
                machine.new_session(), Command.RDALMHISTRY, HISTORY_REQUEST
            )
            assert len(AlarmHistory.decode(expected).entries) == HISTORY_DEPTH
            tail = data[sent : requests * size]
            decoder = FrameDecoder()
            answered = 0
            async with asyncio.timeout(60):
                while answered < requests:
                    if tail:
                        with contextlib.suppress(BlockingIOError):
                            tail = tail[sock.send(tail) :]
                    chunk = await loop.sock_recv(sock, 1 << 20)
                    assert chunk, "the server closed a connection that only read slowly"
                    for command, request_id, answer in decoder.feed(chunk):
                        assert (command, request_id) == (history, answered & 0xFFFF)
                        assert answer == expected
                        answered += 1
            assert answered == requests
            await wait_until(lambda: not conn.reading_paused)
        finally:
            sock.close()
        await assert_serves(served)


# -- a flood of connections ----------------------------------------------------------------


async def test_a_thousand_connections_at_once_respect_the_limit(
    server_errors: list[logging.LogRecord],
) -> None:
    limit = 256
    flood = 1_000
    async with serving(max_connections=limit, backlog=1_024) as served:
        listener = served.listener
        async with await served.connect() as steady:
            peak = len(listener.connections)
            opened: list[tuple[asyncio.StreamReader, asyncio.StreamWriter]] = []

            async def open_one() -> None:
                with contextlib.suppress(ConnectionError):
                    opened.append(await asyncio.open_connection(served.host, served.port))

            storm = asyncio.gather(*(open_one() for _ in range(flood)))
            served_during = 0
            try:
                for _ in range(100_000):  # the steady client is served all along
                    if storm.done():
                        break
                    assert ew_of(STATUS, await steady.call(STATUS)) == 0
                    served_during += 1
                    peak = max(peak, len(listener.connections))
                async with asyncio.timeout(30):
                    await storm
                await wait_until(lambda: listener.accepted + listener.refused == flood + 1)
                peak = max(peak, len(listener.connections))

                async def probe(reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> bool:
                    """True when this connection is served, False when the server closed it."""
                    try:
                        writer.write(encode_frame(STATUS, 7))
                        await writer.drain()
                        async with asyncio.timeout(IO_TIMEOUT):
                            head = await reader.readexactly(8)
                    except (ConnectionError, asyncio.IncompleteReadError):
                        return False
                    return struct.unpack("<IHH", head)[1:] == (STATUS, 7)

                results = await asyncio.gather(*(probe(r, w) for r, w in opened))
            finally:
                for _, writer in opened:
                    writer.close()
                for _, writer in opened:
                    with contextlib.suppress(ConnectionError, TimeoutError):
                        async with asyncio.timeout(IO_TIMEOUT):
                            await writer.wait_closed()
            assert peak <= limit
            assert sum(results) == limit - 1  # the steady client holds the last place
            assert listener.accepted == limit
            assert listener.refused == flood + 1 - limit
            assert served_during >= 1
            assert ew_of(STATUS, await steady.call(STATUS)) == 0
        await wait_until(lambda: not listener.connections)
        await assert_serves(served)


# -- resets ----------------------------------------------------------------------------------


async def test_a_reset_in_the_middle_of_a_write_frame_changes_nothing(
    server_errors: list[logging.LogRecord],
) -> None:
    async with serving() as served:
        loop = asyncio.get_running_loop()
        machine = served.machine
        before = machine.state_digest()
        frame = encode_frame(Command.WRMACRO, 1, MacroValue(100, 8, 4242, 0).encode())
        sock = await raw_socket(served)
        await loop.sock_sendall(sock, frame[:11])
        conn = connection_of(served, sock)
        await wait_until(lambda: conn.buffered_input == 11)
        reset(sock)
        await wait_until(lambda: not served.listener.connections)
        assert machine.state_digest() == before
        async with await served.connect() as wire:
            value = MacroValue.decode(
                (await wire.call(Command.RDMACRO, MacroRequest(100).encode()))[2:]
            )
            assert (value.mcr_val, value.dec_val) == (0, -1)  # still vacant


async def test_a_reset_with_answers_unread_is_cleaned_up(
    server_errors: list[logging.LogRecord],
) -> None:
    async with serving(write_buffer_high=8 * 1024) as served:
        loop = asyncio.get_running_loop()
        await fill_history(served)
        sock = await raw_socket(served, rcvbuf=4_096)
        conn = connection_of(served, sock)
        with contextlib.suppress(BlockingIOError):
            sock.send(history_requests(20_000))
        await wait_until(lambda: conn.reading_paused)
        await loop.sock_sendall(sock, b"\x10\x00")  # and half a length prefix on top
        reset(sock)
        await wait_until(lambda: not served.listener.connections)
        assert conn.write_buffer_size == 0
        await assert_serves(served)


# -- half-closed connections -------------------------------------------------------------------


async def test_half_close_delivers_every_pending_answer_then_closes(
    server_errors: list[logging.LogRecord],
) -> None:
    async with serving(write_buffer_high=8 * 1024) as served:
        count = 20_000
        async with await served.connect() as wire:
            wire.send_raw(b"".join(encode_frame(STATUS, i & 0xFFFF) for i in range(count)))
            wire.writer.write_eof()
            await wire.writer.drain()
            ids = []
            with pytest.raises(EOFError):
                for _ in range(count + 1):
                    frame = await wire.recv()
                    assert frame.command == STATUS
                    ids.append(frame.request_id)
        assert ids == [i & 0xFFFF for i in range(count)]
        await wait_until(lambda: not served.listener.connections)
        await assert_serves(served)


async def test_half_close_after_a_partial_frame_answers_the_whole_ones(
    server_errors: list[logging.LogRecord],
) -> None:
    async with serving() as served:
        async with await served.connect() as wire:
            wire.send_raw(encode_frame(STATUS, 1) + encode_frame(STATUS, 2) + b"\x08\x00\x00")
            wire.writer.write_eof()
            await wire.writer.drain()
            got = []
            with pytest.raises(EOFError):
                for _ in range(3):
                    got.append((await wire.recv()).request_id)
        assert got == [1, 2]
        assert served.listener.violations == 0
        await assert_serves(served)


async def test_half_close_delivers_delayed_answers(
    server_errors: list[logging.LogRecord],
) -> None:
    async with serving() as served:
        async with await served.connect() as wire:
            assert (
                ew_of(
                    Command.SIM_INJECT_FAULT,
                    await wire.call(Command.SIM_INJECT_FAULT, InjectFault(1, 0, 1, 200).encode()),
                )
                == 0
            )
            rid = wire.send(STATUS)
            wire.writer.write_eof()
            await wire.writer.drain()
            frame = await wire.recv()
            assert (frame.command, frame.request_id) == (STATUS, rid)
            assert await wire.closed_by_peer()
