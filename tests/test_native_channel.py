"""The native client's connections (``focas_net/client/_channel.py``), both kinds, against
plain TCP peers on 127.0.0.1: bytes kept before ``start`` and handed on after it, the end
told once, a write the kernel does not take whole, a failed write, closing, the addresses
tried; and the native client on uvloop, where it uses the loop's transports."""

from __future__ import annotations

import asyncio
import errno
import socket
from collections.abc import AsyncIterator, Callable
from contextlib import asynccontextmanager
from decimal import Decimal
from typing import Any, Final, TypeVar

import pytest
from support import IO_TIMEOUT, ChannelLog, serving, wait_until

from focas_net.client import ClientState, ReconnectPolicy, _channel
from focas_net.client._channel import (
    KEEP_LIMIT,
    Channel,
    SocketChannel,
    TransportChannel,
    open_channel,
)
from focas_net.client.native import NativeClient
from focas_net.errors import FocasConnectionError


class Peer:
    """A TCP server on 127.0.0.1 that accepts one connection and does what a test says."""

    def __init__(self) -> None:
        self.accepted: asyncio.Future[tuple[asyncio.StreamReader, asyncio.StreamWriter]] = (
            asyncio.get_running_loop().create_future()
        )
        self.server: asyncio.Server | None = None
        self.port = 0

    async def _accept(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        if not self.accepted.done():
            self.accepted.set_result((reader, writer))

    async def conn(self) -> tuple[asyncio.StreamReader, asyncio.StreamWriter]:
        return await asyncio.wait_for(asyncio.shield(self.accepted), IO_TIMEOUT)


@asynccontextmanager
async def peer() -> AsyncIterator[Peer]:
    p = Peer()
    p.server = await asyncio.start_server(p._accept, "127.0.0.1", 0)
    p.port = p.server.sockets[0].getsockname()[1]
    try:
        yield p
    finally:
        if p.accepted.done():
            p.accepted.result()[1].transport.abort()
        p.server.close()
        await p.server.wait_closed()


@pytest.fixture(params=["sockets", "transports"])
def kind(request: pytest.FixtureRequest, monkeypatch: pytest.MonkeyPatch) -> type[Channel]:
    """Which kind of channel :func:`open_channel` opens in the test."""
    if request.param == "transports":
        monkeypatch.setattr(_channel, "own_sockets", lambda loop: False)
        return TransportChannel
    return SocketChannel


class Heard:
    """What a started channel handed on."""

    def __init__(self) -> None:
        self.data = bytearray()
        self.ends: list[Exception | None] = []

    def on_data(self, data: bytes) -> None:
        self.data += data

    def on_end(self, exc: Exception | None) -> None:
        self.ends.append(exc)


async def _open(p: Peer) -> tuple[Channel, asyncio.StreamReader, asyncio.StreamWriter]:
    channel = await asyncio.wait_for(open_channel("127.0.0.1", p.port), IO_TIMEOUT)
    reader, writer = await p.conn()
    return channel, reader, writer


async def test_the_kind_follows_the_loop(kind: type[Channel]) -> None:
    async with peer() as p:
        channel, _, _ = await _open(p)
        try:
            assert type(channel) is kind
        finally:
            channel.close()


async def test_bytes_before_start_are_kept_for_readexactly(kind: type[Channel]) -> None:
    async with peer() as p:
        channel, _, writer = await _open(p)
        try:
            writer.write(b"abc")
            assert await asyncio.wait_for(channel.readexactly(2), IO_TIMEOUT) == b"ab"
            writer.write(b"defgh")
            assert await asyncio.wait_for(channel.readexactly(6), IO_TIMEOUT) == b"cdefgh"
        finally:
            channel.close()


async def test_start_hands_on_the_kept_bytes_first_then_every_read(kind: type[Channel]) -> None:
    async with peer() as p:
        channel, _, writer = await _open(p)
        heard = Heard()
        try:
            writer.write(b"early")
            assert await asyncio.wait_for(channel.readexactly(1), IO_TIMEOUT) == b"e"
            # the rest of "early" arrives before start (read_exactly waited for one byte only)
            await wait_until(lambda: len(channel._kept) == 4)
            channel.start(heard.on_data, heard.on_end)
            assert heard.data == b"arly"
            writer.write(b"late")
            await wait_until(lambda: heard.data == b"arlylate")
            channel.stop()
            writer.write(b"again")
            assert await asyncio.wait_for(channel.readexactly(5), IO_TIMEOUT) == b"again"
            assert heard.data == b"arlylate"
        finally:
            channel.close()


async def test_the_end_is_told_once(kind: type[Channel]) -> None:
    async with peer() as p:
        channel, _, writer = await _open(p)
        heard = Heard()
        try:
            channel.start(heard.on_data, heard.on_end)
            writer.write(b"last")
            writer.close()
            await wait_until(lambda: heard.ends)
            await asyncio.sleep(0)  # (the transport's connection_lost after its end of file)
            await asyncio.sleep(0)
            assert heard.data == b"last"
            assert heard.ends == [None]
            assert channel.ended
        finally:
            channel.close()


async def test_start_after_the_end_tells_it_at_once(kind: type[Channel]) -> None:
    async with peer() as p:
        channel, _, writer = await _open(p)
        try:
            writer.write(b"xy")
            writer.close()
            await wait_until(lambda: channel.ended)
            heard = Heard()
            channel.start(heard.on_data, heard.on_end)
            assert heard.data == b"xy"
            assert heard.ends == [None]
        finally:
            channel.close()


async def test_readexactly_raises_at_the_end(kind: type[Channel]) -> None:
    async with peer() as p:
        channel, _, writer = await _open(p)
        try:
            writer.write(b"par")
            writer.close()
            with pytest.raises(asyncio.IncompleteReadError) as caught:
                await asyncio.wait_for(channel.readexactly(10), IO_TIMEOUT)
            assert caught.value.partial == b"par"
        finally:
            channel.close()


async def test_a_peer_sending_more_than_is_kept_ends_the_channel(kind: type[Channel]) -> None:
    async with peer() as p:
        channel, _, writer = await _open(p)
        try:
            writer.write(bytes(KEEP_LIMIT + 1))
            with pytest.raises(ConnectionError, match="nobody asked for"):
                await asyncio.wait_for(channel.readexactly(KEEP_LIMIT + 2), IO_TIMEOUT)
            assert channel.ended
            kept = len(channel._kept)
            writer.write(bytes(KEEP_LIMIT))
            await writer.drain()
            for _ in range(20):
                await asyncio.sleep(0)
            assert len(channel._kept) == kept  # nothing more is kept
        finally:
            channel.close()


async def test_writes_arrive_whole_and_in_order(kind: type[Channel]) -> None:
    async with peer() as p:
        channel, reader, _ = await _open(p)
        try:
            chunks = [bytes([i]) * (1000 + i) for i in range(50)]
            for chunk in chunks:
                channel.write(chunk)
            expected = b"".join(chunks)
            got = await asyncio.wait_for(reader.readexactly(len(expected)), IO_TIMEOUT)
            assert got == expected
        finally:
            channel.close()


async def test_a_write_the_kernel_does_not_take_whole_is_finished_in_order() -> None:
    # A peer that does not read yet and a small send buffer: the first write is taken in
    # part, the rest and the later writes are sent by the flushing task, in order.
    async with peer() as p:
        channel, reader, _ = await _open(p)
        assert isinstance(channel, SocketChannel)
        try:
            channel.sock.setsockopt(socket.SOL_SOCKET, socket.SO_SNDBUF, 4096)
            big = bytes(range(256)) * (32 * 1024)  # 8 MiB: more than both buffers hold
            channel.write(big)
            assert channel._flusher is not None
            channel.write(b"after")
            channel.write(b"and more")
            expected = big + b"after" + b"and more"
            got = await asyncio.wait_for(reader.readexactly(len(expected)), IO_TIMEOUT)
            assert got == expected
            await wait_until(lambda: channel._flusher is None)
            assert not channel._pending
            channel.write(b"direct again")
            assert await asyncio.wait_for(reader.readexactly(12), IO_TIMEOUT) == b"direct again"
        finally:
            channel.close()


async def test_a_failed_write_ends_the_channel_from_a_callback_of_its_own() -> None:
    async with peer() as p:
        channel, _, _ = await _open(p)
        assert isinstance(channel, SocketChannel)
        heard = Heard()
        sent: list[object] = []

        def broken(data: object, flags: int = 0) -> int:
            sent.append(data)
            raise BrokenPipeError("broken pipe")

        try:
            channel.start(heard.on_data, heard.on_end)
            channel._send = broken
            channel.write(b"frame")
            assert heard.ends == []  # never from inside write
            channel.write(b"dropped")
            await wait_until(lambda: heard.ends)
            assert len(heard.ends) == 1
            assert isinstance(heard.ends[0], BrokenPipeError)
            assert sent == [b"frame"]
        finally:
            channel.close()


async def test_a_handler_that_fails_ends_the_connection_and_is_reported() -> None:
    async with peer() as p:
        channel, _, writer = await _open(p)
        assert isinstance(channel, SocketChannel)
        loop = asyncio.get_running_loop()
        reported: list[dict[str, object]] = []
        loop.set_exception_handler(lambda loop, context: reported.append(context))
        heard = Heard()

        def fails(data: bytes) -> None:
            raise KeyError("a bug")

        try:
            channel.start(fails, heard.on_end)
            writer.write(b"x")
            await wait_until(lambda: heard.ends)
            assert isinstance(heard.ends[0], KeyError)
            assert [type(c["exception"]) for c in reported] == [KeyError]
            assert channel.ended
        finally:
            loop.set_exception_handler(None)
            channel.close()


async def test_a_failed_write_is_raised_by_a_read_waiting(kind: type[Channel]) -> None:
    async with peer() as p:
        channel, _, writer = await _open(p)
        try:
            if isinstance(channel, SocketChannel):

                def broken(data: object, flags: int = 0) -> int:
                    raise ConnectionResetError("reset")

                channel._send = broken
                channel.write(b"x")
                with pytest.raises(ConnectionResetError):
                    await asyncio.wait_for(channel.readexactly(1), IO_TIMEOUT)
            else:
                writer.transport.abort()  # the peer goes; the read ends one way or the other
                with pytest.raises((asyncio.IncompleteReadError, ConnectionError)):
                    await asyncio.wait_for(channel.readexactly(1), IO_TIMEOUT)
        finally:
            channel.close()


async def test_close_tells_nobody_and_ends_a_read_waiting(kind: type[Channel]) -> None:
    async with peer() as p:
        channel, reader, _ = await _open(p)
        heard = Heard()
        channel.start(heard.on_data, heard.on_end)
        channel.close()
        channel.close()  # twice is once
        channel.write(b"after close")  # dropped
        assert await asyncio.wait_for(reader.read(), IO_TIMEOUT) == b""
        assert heard.ends == []
        channel.stop()
        with pytest.raises(asyncio.IncompleteReadError):
            await asyncio.wait_for(channel.readexactly(1), IO_TIMEOUT)


async def test_a_name_is_resolved_and_each_address_tried(kind: type[Channel]) -> None:
    # "localhost" may resolve to ::1 first, where nothing listens: the next address is tried
    async with peer() as p:
        channel = await asyncio.wait_for(open_channel("localhost", p.port), IO_TIMEOUT)
        try:
            await p.conn()
        finally:
            channel.close()


async def test_an_address_family_the_kernel_has_not_is_passed_over(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # A name resolving to ::1 first on a kernel without IPv6: 127.0.0.1 is tried next, as
    # asyncio's own create_connection does.
    class NoIPv6(socket.socket):
        def __init__(self, family: int = -1, *args: Any, **kwargs: Any) -> None:
            if family == socket.AF_INET6:
                raise OSError(errno.EAFNOSUPPORT, "Address family not supported by protocol")
            super().__init__(family, *args, **kwargs)

    async with peer() as p:
        loop = asyncio.get_running_loop()

        async def resolve(host: str, port: int, **kwargs: Any) -> list[Any]:
            assert host == "cnc.example"
            return [
                (socket.AF_INET6, socket.SOCK_STREAM, 6, "", ("::1", port, 0, 0)),
                (socket.AF_INET, socket.SOCK_STREAM, 6, "", ("127.0.0.1", port)),
            ]

        monkeypatch.setattr(loop, "getaddrinfo", resolve)
        monkeypatch.setattr(socket, "socket", NoIPv6)
        channel = await asyncio.wait_for(open_channel("cnc.example", p.port), IO_TIMEOUT)
        monkeypatch.undo()
        try:
            await p.conn()
        finally:
            channel.close()


async def test_a_connection_made_right_after_closing_one_mid_write_works() -> None:
    # Closing a channel whose flushing task is sending: a socket made in the same step gets
    # the same fd number, and the closed one's watch must not linger over it.
    accepted: list[socket.socket] = []
    with socket.socket() as listener:
        listener.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
        listener.bind(("127.0.0.1", 0))
        listener.listen(4)
        listener.setblocking(False)
        port = listener.getsockname()[1]
        loop = asyncio.get_running_loop()
        first = await asyncio.wait_for(open_channel("127.0.0.1", port), IO_TIMEOUT)
        assert isinstance(first, SocketChannel)
        conn, _ = await asyncio.wait_for(loop.sock_accept(listener), IO_TIMEOUT)
        accepted.append(conn)  # never read
        try:
            first.sock.setsockopt(socket.SOL_SOCKET, socket.SO_SNDBUF, 4096)
            first.write(bytes(8 * 1024 * 1024))
            assert first._flusher is not None
            await asyncio.sleep(0)  # the flushing task's first step: its send waits
            assert first._flusher is not None and not first._flusher.done()
            fd = first.sock.fileno()
            first.close()
            async with asyncio.timeout(IO_TIMEOUT):  # (in this task: no loop turn between)
                second = await open_channel("127.0.0.1", port)
            try:
                assert isinstance(second, SocketChannel)
                assert second.sock.fileno() == fd  # (the case this guards)
                conn, _ = await asyncio.wait_for(loop.sock_accept(listener), IO_TIMEOUT)
                accepted.append(conn)
                conn.setblocking(False)
                heard = Heard()
                second.start(heard.on_data, heard.on_end)
                await loop.sock_sendall(conn, b"hello")
                await wait_until(lambda: heard.data == b"hello")
                second.write(b"back")
                got = await asyncio.wait_for(loop.sock_recv(conn, 4), IO_TIMEOUT)
                assert got == b"back"
            finally:
                second.close()
        finally:
            for c in accepted:
                c.close()


async def test_nothing_listening_raises_oserror_naming_the_address(kind: type[Channel]) -> None:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]  # bound, not listening: refused
        with pytest.raises(OSError, match=str(port)):
            await asyncio.wait_for(open_channel("127.0.0.1", port), IO_TIMEOUT)


# -- the native client on uvloop ------------------------------------------------------------------


_C = TypeVar("_C", bound=Channel)

#: A reconnect that follows a lost connection at once.
_PROMPT: Final = ReconnectPolicy(initial_delay=0.01, max_delay=0.05, max_attempts=200)


def _b_of(log: ChannelLog, kind: type[_C]) -> _C:
    """B of the pair the client opened last, which is a ``kind`` exactly."""
    b = log.b
    assert type(b) is kind and isinstance(b, kind)
    return b


async def _reconnected(native: NativeClient, states: list[ClientState]) -> None:
    """Wait until ``native`` went through RECONNECTING back to CONNECTED."""
    await wait_until(
        lambda: (
            ClientState.RECONNECTING in states
            and states[-1] is ClientState.CONNECTED
            and native.state is ClientState.CONNECTED
        )
    )


def _on_uvloop(main: Callable[[], object]) -> None:
    uvloop = pytest.importorskip("uvloop")
    with asyncio.Runner(loop_factory=uvloop.new_event_loop) as runner:
        runner.run(main())  # type: ignore[arg-type]


def test_the_native_client_on_uvloop_uses_its_transports(monkeypatch: pytest.MonkeyPatch) -> None:
    log = ChannelLog(monkeypatch)

    async def main() -> None:
        assert not _channel.own_sockets(asyncio.get_running_loop())
        async with serving() as served:
            served.machine.write_macro(100, 7)
            async with NativeClient(served.host, served.port, timeout=IO_TIMEOUT) as native:
                _b_of(log, TransportChannel)
                assert [await native.read_macro(100) for _ in range(3)] == [Decimal(7)] * 3
                frames = native.frames_sent
                got = await asyncio.gather(*(native.read_macro(100) for _ in range(25)))
                assert got == [Decimal(7)] * 25
                assert native.frames_sent - frames < 25  # gathered into frames
                status = await native.read_status()
                assert status == (await native.read_status())

    _on_uvloop(main)


def test_the_native_client_on_uvloop_reconnects_after_the_connection_is_lost(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    log = ChannelLog(monkeypatch)

    async def main() -> None:
        async with serving() as served:
            served.machine.write_macro(100, 3)
            states: list[ClientState] = []
            async with NativeClient(
                served.host, served.port, timeout=IO_TIMEOUT, reconnect=_PROMPT,
                on_state_change=states.append,
            ) as native:  # fmt: skip
                assert await native.read_macro(100) == Decimal(3)
                b = _b_of(log, TransportChannel)
                assert b.transport is not None
                b.transport.abort()  # the connection drops
                await _reconnected(native, states)
                assert await native.read_macro(100) == Decimal(3)
            with pytest.raises(FocasConnectionError):
                await native.read_macro(100)

    _on_uvloop(main)


async def test_a_call_whose_frame_cannot_be_sent_fails_and_the_next_reconnects(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # The socket refuses the frame (the kernel says the connection is gone): the call fails
    # as for any lost connection, never hangs, and the reconnect policy opens a new pair.
    log = ChannelLog(monkeypatch)
    async with serving() as served:
        served.machine.write_macro(100, 4)
        states: list[ClientState] = []
        async with NativeClient(
            served.host, served.port, timeout=IO_TIMEOUT, reconnect=_PROMPT,
            on_state_change=states.append,
        ) as native:  # fmt: skip
            assert await native.read_macro(100) == Decimal(4)
            b = _b_of(log, SocketChannel)

            def refused(data: object, flags: int = 0) -> int:
                raise ConnectionResetError("connection reset by peer")

            b._send = refused
            with pytest.raises(FocasConnectionError, match=r"^connection closed by 127\.0\.0\.1:"):
                await asyncio.wait_for(native.read_macro(100), IO_TIMEOUT)
            await _reconnected(native, states)
            assert await native.read_macro(100) == Decimal(4)
