"""Both protocols on one port: the sniff of the first bytes, the shared shell (limits, idle
sweep, shutdown, counters) and fault injection on native connections.

Every server here is a real :class:`FocasServer` on 127.0.0.1, port 0. Native peers are
pyfocas (an independent client, in a worker thread; its socket has a 1 s timeout) and a small
client on the project's own native codec. Progress is checked through the server's own state,
never through elapsed time; every loop is bounded.
"""

from __future__ import annotations

import asyncio
import logging
import struct
from collections.abc import AsyncIterator, Callable
from decimal import Decimal
from functools import partial
from typing import Any, Final

import pytest
from pyfocas.protocol.protocol import FOCAS
from support import IO_TIMEOUT, Served, Wire, serving, wait_until

from focas_net.adapters import NativeAdapter
from focas_net.client import FocasClient
from focas_net.errors import EW
from focas_net.native import (
    Device,
    FrameType,
    MacroDoubleWriteRequest,
    MacroReadRequest,
    NativeFrame,
    NativeFrameDecoder,
    NativeFrameError,
    NativeSysInfo,
    RequestBlock,
    ResponseBlock,
    ScaledNumber,
    ScaledValues,
    StatInfoRequest,
    SysInfoRequest,
    decode_frame,
    decode_response_body,
    encode_close_request,
    encode_open_request,
    encode_request,
    encode_request_body,
)
from focas_net.protocol import Command, InjectFault, MacroValue
from focas_net.protocol import encode_frame as encode_packed
from focas_net.server import (
    NATIVE_MAGIC_LENGTH,
    FocasServer,
    Listener,
    NativeConnection,
    PackedConnection,
)
from focas_net.sim import default_machine

DELAY, ERROR, DROP, SPLIT = 1, 2, 3, 4
CONN, MACHINE = 0, 1
STATUS: Final = (Command.RDCNCSTAT, b"")
SYSINFO_BLOCK: Final = SysInfoRequest().to_block()


def inject(kind: int, scope: int, count: int, arg: int = 0) -> bytes:
    return InjectFault(kind, scope, count, arg).encode()


class Native:
    """A native FOCAS/2 connection on the project's codec (asyncio streams)."""

    def __init__(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        self.reader = reader
        self.writer = writer
        self.decoder = NativeFrameDecoder(0xFFFF)
        self.pending: list[NativeFrame] = []

    @classmethod
    async def open(cls, host: str, port: int, *, handshake: bool = True) -> Native:
        async with asyncio.timeout(IO_TIMEOUT):
            reader, writer = await asyncio.open_connection(host, port)
        native = cls(reader, writer)
        if handshake:
            frame = await native.exchange(encode_open_request())
            assert frame.type == FrameType.OPEN_RESPONSE
        return native

    @property
    def local_port(self) -> int:
        return int(self.writer.get_extra_info("sockname")[1])

    async def frame(self) -> NativeFrame:
        async with asyncio.timeout(IO_TIMEOUT):
            while not self.pending:
                chunk = await self.reader.read(65_536)
                if not chunk:
                    raise EOFError("connection closed by the server")
                self.pending.extend(self.decoder.feed(chunk))
        return self.pending.pop(0)

    async def exchange(self, data: bytes) -> NativeFrame:
        self.writer.write(data)
        await self.writer.drain()
        return await self.frame()

    async def blocks(self, *blocks: RequestBlock) -> tuple[ResponseBlock, ...]:
        frame = await self.exchange(encode_request(list(blocks)))
        assert frame.type == FrameType.DATA_RESPONSE
        answer = decode_response_body(frame.body)
        assert [(a.device, a.path, a.command) for a in answer] == [
            (b.device, b.path, b.command) for b in blocks
        ]
        return answer

    async def closed_by_peer(self) -> bool:
        try:
            async with asyncio.timeout(IO_TIMEOUT):
                for _ in range(1_000):
                    if not await self.reader.read(65_536):
                        return True
        except (ConnectionResetError, BrokenPipeError):
            return True
        except TimeoutError:
            return False
        return False

    async def close(self) -> None:
        self.writer.close()
        try:
            async with asyncio.timeout(IO_TIMEOUT):
                await self.writer.wait_closed()
        except (ConnectionError, TimeoutError):
            pass

    async def __aenter__(self) -> Native:
        return self

    async def __aexit__(self, *exc: object) -> None:
        await self.close()


def server_side(listener: Listener, local_port: int) -> PackedConnection | NativeConnection | None:
    """The server's end of the connection whose client end has ``local_port``."""
    for conn in listener.all_connections():
        if conn.peer is not None and conn.peer[1] == local_port:
            return conn
    return None


async def pyfocas(host: str, port: int, work: Callable[[FOCAS], Any]) -> Any:
    """``work(client)`` with a connected pyfocas client, in a worker thread."""

    def run() -> Any:
        client = FOCAS(host, port)
        assert client.connect() is True
        try:
            return work(client)
        finally:
            assert client.socket is not None
            client.socket.close()

    async with asyncio.timeout(4 * IO_TIMEOUT):
        return await asyncio.to_thread(run)


@pytest.fixture
async def native(server: Served) -> AsyncIterator[Native]:
    """A native connection, opened, on the ``server`` fixture's (two-protocol) port."""
    async with await Native.open(server.host, server.port) as client:
        yield client


# -- one port, three clients -----------------------------------------------------------------


async def test_focas_client_and_pyfocas_share_one_port_and_one_machine(server: Served) -> None:
    host, port = server.host, server.port
    async with FocasClient(host, port, timeout=IO_TIMEOUT) as cnc:
        await cnc.write_macro(530, Decimal("12.5"))
        assert await pyfocas(host, port, lambda c: c.read_macro(530)) == {530: 12.5}
        await pyfocas(host, port, lambda c: c.write_macro_double(531, -0.25))
        assert await cnc.read_macro(531) == Decimal("-0.25")
        info = await pyfocas(host, port, lambda c: c.get_sys_info())
        sysinfo = await cnc.read_sysinfo()
        assert (info.max_axis, info.series) == (sysinfo.max_axis, sysinfo.series.decode())
        status = await cnc.read_status()
        seen = await pyfocas(host, port, lambda c: c.get_status_info())
        assert (seen.aut, seen.run) == (status.aut, status.run)
    listener = server.listener
    await wait_until(lambda: listener.connection_count == 0)
    assert listener.native_accepted == 4 and listener.native_violations == 0
    assert listener.accepted == 1 and listener.violations == 0
    stats = server.server.stats()[listener.label]
    assert {k: stats[k] for k in ("address", "accepted", "refused", "violations")} == {
        "address": listener.address_text,
        "accepted": 1,
        "refused": 0,
        "violations": 0,
    }
    assert stats["native"] == {
        "address": listener.address_text,
        "connections": 0,
        "accepted": 4,
        "refused": 0,
        "violations": 0,
    }


async def test_packed_and_native_connections_open_side_by_side(
    server: Served, wire: Wire, native: Native
) -> None:
    listener = server.listener
    assert await wire.ew(Command.WRMACRO, MacroValue(540, 8, 77, 1).encode()) == 0
    (answer,) = await native.blocks(MacroReadRequest(540, 540).to_block())
    assert ScaledValues.decode(answer.data).values == (ScaledNumber(77, 1),)
    (sysinfo,) = await native.blocks(SYSINFO_BLOCK)
    assert NativeSysInfo.decode(sysinfo.data).max_axis == 32  # a 0i-F's
    assert await wire.ew(*STATUS) == 0
    assert len(listener.connections) == 1 and len(listener.native_connections) == 1
    assert isinstance(server_side(listener, native.local_port), NativeConnection)
    assert type(server_side(listener, wire.sockname[1])) is PackedConnection
    stats = server.server.stats()[listener.label]
    assert (stats["connections"], stats["native"]["connections"]) == (1, 1)


async def test_bad_native_input_on_the_shared_port_closes_only_that_connection(
    server: Served, wire: Wire, native: Native, caplog: pytest.LogCaptureFixture
) -> None:
    async with await Native.open(server.host, server.port, handshake=False) as bad:
        port = bad.local_port
        with caplog.at_level(logging.WARNING, logger="focas_net.server"):
            bad.writer.write(encode_request([SYSINFO_BLOCK]))  # a data request before the open
            await bad.writer.drain()
            assert await bad.closed_by_peer()
    warnings = [r.getMessage() for r in caplog.records if r.levelno == logging.WARNING]
    assert any(f"127.0.0.1:{port}" in w and "before the open" in w for w in warnings), warnings
    listener = server.listener
    await wait_until(lambda: listener.native_violations == 1)
    assert listener.violations == 0
    assert (await native.blocks(SYSINFO_BLOCK))[0].ew == 0
    assert await wire.ew(*STATUS) == 0


# -- the first bytes -------------------------------------------------------------------------


def _holds(listener: Listener, local_port: int, count: int) -> bool:
    """True when the server's end of that connection holds ``count`` bytes not answered yet."""
    conn = server_side(listener, local_port)
    return conn is not None and conn.buffered_input == count


async def _drip(
    listener: Listener, writer: asyncio.StreamWriter, data: bytes, local_port: int, held: int = 0
) -> None:
    """Write ``data`` one byte at a time, each once the server holds the one before (it holds
    ``held`` bytes of the frame already)."""
    for i in range(len(data)):
        writer.write(data[i : i + 1])
        await writer.drain()
        await wait_until(partial(_holds, listener, local_port, held + i + 1))


async def test_native_frame_one_byte_at_a_time(server: Served) -> None:
    listener = server.listener
    async with await Native.open(server.host, server.port, handshake=False) as client:
        port = client.local_port
        await wait_until(lambda: server_side(listener, port) is not None)
        opening = encode_open_request()
        for i in range(4):  # the magic, byte by byte: undecided, then native
            client.writer.write(opening[i : i + 1])
            await client.writer.drain()
            await wait_until(partial(_holds, listener, port, i + 1))
            kind = PackedConnection if i < 3 else NativeConnection
            assert isinstance(server_side(listener, port), kind), i
        await _drip(listener, client.writer, opening[4:-1], port, held=4)
        assert (await client.exchange(opening[-1:])).type == FrameType.OPEN_RESPONSE
        request = encode_request([SYSINFO_BLOCK, StatInfoRequest().to_block()])
        await _drip(listener, client.writer, request[:-1], port)
        frame = await client.exchange(request[-1:])
        assert [b.ew for b in decode_response_body(frame.body)] == [0, 0]
    assert listener.native_accepted == 1 and listener.accepted == 0


@pytest.mark.parametrize(
    ("name", "frame"),
    [
        ("status", encode_packed(Command.RDCNCSTAT, 7)),
        # a length whose low byte is A0 (160): packed from the second byte on
        ("length A0 00 00 00", encode_packed(0x0999, 7, bytes(160 - 4))),
        # a length A0 A0 00 00 (41120): packed from the third byte on
        ("length A0 A0 00 00", encode_packed(0x0999, 7, bytes(0xA0A0 - 4))),
    ],
)
async def test_packed_frame_one_byte_at_a_time(server: Served, name: str, frame: bytes) -> None:
    listener = server.listener
    async with await server.connect() as w:
        port = w.sockname[1]
        await wait_until(lambda: server_side(listener, port) is not None)
        cut = min(len(frame) - 1, 12)
        head, rest = frame[:cut], frame[cut:]
        await _drip(listener, w.writer, head, port)
        assert type(server_side(listener, port)) is PackedConnection, name
        w.send_raw(rest)
        answer = await w.recv()
        assert answer.request_id == 7
        assert answer.command == struct.unpack_from("<H", frame, 4)[0]
    assert listener.native_accepted == 0 and listener.violations == 0


async def test_a_native_frame_in_the_first_chunk_with_a_request_behind_it(server: Served) -> None:
    async with await Native.open(server.host, server.port, handshake=False) as client:
        both = encode_open_request() + encode_request([SYSINFO_BLOCK])
        assert (await client.exchange(both)).type == FrameType.OPEN_RESPONSE
        frame = await client.frame()
        assert decode_response_body(frame.body)[0].ew == 0


@pytest.mark.parametrize("head", [b"\xa0", b"\xa0\xa0\xa0", b"\x08\x00\x00"])
async def test_fewer_than_four_bytes_then_silence_is_closed_when_idle(head: bytes) -> None:
    async with serving(idle_timeout=0.2) as served:
        async with await served.connect() as slow:
            slow.send_raw(head)
            await slow.writer.drain()
            assert await slow.closed_by_peer()
        listener = served.listener
        await wait_until(lambda: listener.connection_count == 0)
        assert (listener.violations, listener.native_violations) == (0, 0)
        async with await Native.open(served.host, served.port) as client:  # still serving
            assert (await client.blocks(SYSINFO_BLOCK))[0].ew == 0


async def test_idle_native_connection_is_closed() -> None:
    async with serving(idle_timeout=0.2) as served:
        async with await Native.open(served.host, served.port) as client:
            assert (await client.blocks(SYSINFO_BLOCK))[0].ew == 0
            assert await client.closed_by_peer()
        # half a native header on the native-only port: closed too
    async with serving(idle_timeout=0.2, native_port=0) as served:
        assert served.listener.native is not None
        host, port = served.listener.native.address
        async with await Native.open(host, port, handshake=False) as client:
            client.writer.write(encode_open_request()[:5])
            await client.writer.drain()
            assert await client.closed_by_peer()
        assert served.listener.native.native_violations == 0


async def test_end_of_stream_before_four_bytes_closes_quietly(server: Served) -> None:
    async with await server.connect() as w:
        w.send_raw(b"\xa0\xa0")
        w.writer.write_eof()
        await w.writer.drain()
        assert await w.closed_by_peer()
    await wait_until(lambda: server.listener.connection_count == 0)
    assert (server.listener.violations, server.listener.native_violations) == (0, 0)


# -- max_frame -------------------------------------------------------------------------------


@pytest.mark.parametrize("value", [NATIVE_MAGIC_LENGTH, NATIVE_MAGIC_LENGTH + 1, 2**32])
def test_max_frame_at_or_above_the_native_magic_is_refused(value: int) -> None:
    with pytest.raises(ValueError, match=str(value)) as info:
        FocasServer(default_machine(), port=0, max_frame=value)
    assert "0xA0A0A0A0" in str(info.value)


async def test_the_largest_max_frame_still_tells_the_protocols_apart() -> None:
    async with serving(max_frame=NATIVE_MAGIC_LENGTH - 1) as served:
        async with await served.connect() as w:
            assert await w.ew(*STATUS) == 0
        async with await Native.open(served.host, served.port) as client:
            assert (await client.blocks(SYSINFO_BLOCK))[0].ew == 0


# -- limits and shutdown over both protocols ------------------------------------------------


async def test_connection_limit_counts_both_protocols() -> None:
    async with serving(max_connections=2) as served:
        listener = served.listener
        async with await served.connect() as w, await Native.open(served.host, served.port):
            assert await w.ew(*STATUS) == 0
            async with await Native.open(served.host, served.port, handshake=False) as extra:
                assert await extra.closed_by_peer()
            assert listener.refused == 1
            stats = served.server.stats()[listener.label]
            assert (stats["refused"], stats["native"]["refused"]) == (1, 0)
            assert served.server.connection_count == 2


async def test_shutdown_answers_a_delayed_native_request() -> None:
    served_cm = serving(grace_period=5.0)
    served = await served_cm.__aenter__()
    try:
        client = await Native.open(served.host, served.port)
        async with await served.connect() as w:
            assert await w.ew(Command.SIM_INJECT_FAULT, inject(DELAY, MACHINE, 1, 60_000)) == 0
        client.writer.write(encode_request([SYSINFO_BLOCK]))
        await client.writer.drain()
        conn = server_side(served.listener, client.local_port)
        assert conn is not None
        await wait_until(lambda: conn.delayed_count == 1)
    except BaseException:
        await served_cm.__aexit__(None, None, None)
        raise
    closing = asyncio.create_task(served.server.aclose(grace_period=0.1))
    frame = await client.frame()
    assert decode_response_body(frame.body)[0].ew == 0
    assert await client.closed_by_peer()
    await closing
    await client.close()
    await served_cm.__aexit__(None, None, None)
    assert served.server.connection_count == 0


async def test_native_close_request_waits_for_a_delayed_answer(server: Served, wire: Wire) -> None:
    async with await Native.open(server.host, server.port) as client:
        assert await wire.ew(Command.SIM_INJECT_FAULT, inject(DELAY, MACHINE, 1, 200)) == 0
        client.writer.write(encode_request([SYSINFO_BLOCK]) + encode_close_request())
        await client.writer.drain()
        first, second = await client.frame(), await client.frame()
        assert (first.type, second.type) == (FrameType.CLOSE_RESPONSE, FrameType.DATA_RESPONSE)
        assert await client.closed_by_peer()


# -- fault injection on native connections ----------------------------------------------------


async def test_forced_ew_answers_every_block_with_the_code_and_runs_nothing(
    server: Served, wire: Wire, native: Native
) -> None:
    assert await wire.ew(Command.SIM_INJECT_FAULT, inject(ERROR, MACHINE, 1, EW.BUSY)) == 0
    blocks = (
        SYSINFO_BLOCK,
        MacroDoubleWriteRequest(550, 3.5).to_block(),
        RequestBlock(Device.PMC, 1, 0x7777),  # not served: still the forced code
    )
    answers = await native.blocks(*blocks)
    assert [(a.ew, a.data, a.detail1, a.detail2) for a in answers] == [(EW.BUSY, b"", 0, 0)] * 3
    assert server.machine.read_macro(550) is None  # the write was not run
    answers = await native.blocks(*blocks)  # the count is used up
    assert [a.ew for a in answers] == [0, 0, EW.FUNC]
    assert server.machine.read_macro(550) == Decimal("3.5")


async def test_forced_ew_through_pyfocas_on_a_write(server: Served, wire: Wire) -> None:
    assert await wire.ew(Command.SIM_INJECT_FAULT, inject(ERROR, MACHINE, 1, EW.PROT)) == 0
    block = await pyfocas(
        server.host, server.port, lambda c: c.write_macro_double(551, 1.0).data[0]
    )
    assert struct.unpack(">h", block[6:8])[0] == EW.PROT
    assert server.machine.read_macro(551) is None


async def test_one_machine_count_shared_by_packed_and_native_answers(
    wire: Wire, native: Native
) -> None:
    assert await wire.ew(Command.SIM_INJECT_FAULT, inject(ERROR, MACHINE, 2, EW.ALARM)) == 0
    assert (await native.blocks(SYSINFO_BLOCK))[0].ew == EW.ALARM
    assert await wire.ew(*STATUS) == EW.ALARM
    assert (await native.blocks(SYSINFO_BLOCK))[0].ew == 0
    assert await wire.ew(*STATUS) == 0


async def test_a_connection_fault_of_a_packed_connection_leaves_native_ones_alone(
    wire: Wire, native: Native
) -> None:
    assert await wire.ew(Command.SIM_INJECT_FAULT, inject(ERROR, CONN, 1, EW.BUSY)) == 0
    assert (await native.blocks(SYSINFO_BLOCK))[0].ew == 0
    assert await wire.ew(*STATUS) == EW.BUSY


async def test_open_and_close_answers_are_never_faulted(server: Served, wire: Wire) -> None:
    assert await wire.ew(Command.SIM_INJECT_FAULT, inject(ERROR, MACHINE, 1, EW.BUSY)) == 0
    async with await Native.open(server.host, server.port) as client:  # open: not faulted
        closing = await client.exchange(encode_close_request())
        assert (closing.type, closing.body) == (FrameType.CLOSE_RESPONSE, b"")
        assert await client.closed_by_peer()
    assert await wire.ew(*STATUS) == EW.BUSY  # still armed


async def test_delayed_native_answer(server: Served, wire: Wire, native: Native) -> None:
    assert await wire.ew(Command.SIM_INJECT_FAULT, inject(DELAY, MACHINE, 1, 300)) == 0
    native.writer.write(encode_request([MacroReadRequest(1, 1).to_block()]))
    await native.writer.drain()
    conn = server_side(server.listener, native.local_port)
    assert isinstance(conn, NativeConnection)
    await wait_until(lambda: conn.delayed_count == 1)
    frame = await native.frame()
    (block,) = decode_response_body(frame.body)
    assert (block.ew, ScaledValues.decode(block.data).values) == (0, (ScaledNumber(0, -1),))
    assert conn.delayed_count == 0


async def test_dropped_native_connection(server: Served, wire: Wire, native: Native) -> None:
    assert await wire.ew(Command.SIM_INJECT_FAULT, inject(DROP, MACHINE, 1)) == 0
    async with await Native.open(server.host, server.port) as victim:
        victim.writer.write(encode_request([MacroDoubleWriteRequest(552, 9.0).to_block()]))
        await victim.writer.drain()
        assert await victim.closed_by_peer()
    assert server.machine.read_macro(552) is None
    assert (await native.blocks(SYSINFO_BLOCK))[0].ew == 0
    assert server.listener.native_violations == 0


class _RecordingTransport:
    """Wraps a connection's transport and records each write."""

    def __init__(self, inner: Any) -> None:
        self.inner = inner
        self.writes: list[bytes] = []

    def write(self, data: bytes) -> None:
        self.writes.append(bytes(data))
        self.inner.write(data)

    def __getattr__(self, name: str) -> Any:
        return getattr(self.inner, name)


async def test_split_native_answer(server: Served, wire: Wire, native: Native) -> None:
    conn = server_side(server.listener, native.local_port)
    assert isinstance(conn, NativeConnection)
    recorder = _RecordingTransport(conn._transport)
    conn._transport = recorder  # type: ignore[assignment]
    assert await wire.ew(Command.SIM_INJECT_FAULT, inject(SPLIT, MACHINE, 1)) == 0
    (block,) = await native.blocks(SYSINFO_BLOCK)
    assert block.ew == 0
    whole = b"".join(recorder.writes)
    assert all(len(w) == 1 for w in recorder.writes) and len(recorder.writes) == len(whole)
    assert decode_frame(whole).type == FrameType.DATA_RESPONSE
    recorder.writes.clear()
    await native.blocks(SYSINFO_BLOCK)  # the next answer is whole again
    assert len(recorder.writes) == 1


async def test_faults_apply_on_the_native_only_port_too() -> None:
    async with serving(native_port=0) as served:
        native_listener = served.listener.native
        assert native_listener is not None
        async with (
            await served.connect() as w,
            await Native.open(*native_listener.address) as client,
        ):
            assert await w.ew(Command.SIM_INJECT_FAULT, inject(ERROR, MACHINE, 1, EW.RESET)) == 0
            assert (await client.blocks(SYSINFO_BLOCK))[0].ew == EW.RESET
            assert await w.ew(Command.SIM_INJECT_FAULT, inject(DROP, MACHINE, 1)) == 0
            client.writer.write(encode_request([SYSINFO_BLOCK]))
            await client.writer.drain()
            assert await client.closed_by_peer()
            stats = served.server.stats()[served.listener.label]["native"]
            assert stats["address"] == native_listener.address_text
            assert stats["accepted"] == 1


# -- the forced answer, pure -----------------------------------------------------------------


def forced_answer(body: bytes, ew: int, version: int = 2) -> bytes:
    return NativeAdapter(default_machine(), version=version).forced_answer(body, ew)


def test_forced_answer_frame() -> None:
    blocks = [SYSINFO_BLOCK, RequestBlock(Device.PMC, 2, 0x8001, (1, 2, 3, 4, 5), b"xy")]
    frame = decode_frame(forced_answer(encode_request_body(blocks), EW.NUMBER))
    assert (frame.version, frame.type) == (2, FrameType.DATA_RESPONSE)
    assert decode_response_body(frame.body) == (
        ResponseBlock(Device.CNC, 1, SYSINFO_BLOCK.command, EW.NUMBER),
        ResponseBlock(Device.PMC, 2, 0x8001, EW.NUMBER),
    )
    assert len(frame.body) == 2 + 2 * 16
    assert decode_frame(forced_answer(b"", EW.BUSY)).body == b"\x00\x00"
    assert decode_frame(forced_answer(b"", -1, version=4)).version == 4


@pytest.mark.parametrize(
    "body", [b"\x00", b"\x00\x02\x00\x1c", encode_request_body([SYSINFO_BLOCK] * 91)]
)
def test_forced_answer_refuses_what_a_real_answer_refuses(body: bytes) -> None:
    with pytest.raises(NativeFrameError):
        forced_answer(body, EW.BUSY)


# -- uvloop --------------------------------------------------------------------------------------


def test_both_protocols_on_one_port_on_uvloop() -> None:
    pytest.importorskip("uvloop")
    import anyio

    async def main() -> tuple[int, int]:
        async with serving() as served:
            listener = served.listener
            async with await served.connect() as w:
                port = w.sockname[1]
                frame = encode_packed(Command.RDCNCSTAT, 3)
                await _drip(listener, w.writer, frame[:1], port)  # the first byte alone
                w.send_raw(frame[1:])
                packed = await w.recv()
                async with await Native.open(served.host, served.port) as client:
                    (block,) = await client.blocks(SYSINFO_BLOCK)
                return packed.request_id, block.ew

    result = anyio.run(main, backend="asyncio", backend_options={"use_uvloop": True})
    assert result == (3, 0)


# -- the command line ------------------------------------------------------------------------


def test_cli_max_frame_at_the_native_magic_is_refused(capsys: pytest.CaptureFixture[str]) -> None:
    import argparse

    from focas_net.cli import serve

    parser = argparse.ArgumentParser()
    serve.register(parser.add_subparsers())
    with pytest.raises(SystemExit) as exc:
        parser.parse_args(["serve", "--max-frame", "0xA0A0A0A0"])
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert "--max-frame" in err and "got 0xA0A0A0A0" in err
    args = parser.parse_args(["serve", "--max-frame", str(NATIVE_MAGIC_LENGTH - 1)])
    assert args.max_frame == NATIVE_MAGIC_LENGTH - 1
