"""Limits, isolation, backpressure, fleets, TLS and graceful shutdown of ``FocasServer``."""

from __future__ import annotations

import asyncio
import logging
import socket
import ssl
import struct
from pathlib import Path

import pytest
from support import Served, Wire, serving, wait_until

from focas_net.errors import EW, FrameError
from focas_net.protocol import (
    AlarmHistoryRequest,
    ClearAlarms,
    Command,
    FrameDecoder,
    InjectFault,
    MacroRequest,
    MacroValue,
    RaiseAlarm,
    encode_frame,
)
from focas_net.server import FocasServer
from focas_net.sim import default_machine

STATUS = (Command.RDCNCSTAT, b"")


# -- framing violations and isolation --------------------------------------------------------


@pytest.mark.parametrize("length", [0, 3, 65_537, 0xFFFFFFFF])
async def test_bad_length_closes_only_that_connection(
    server: Served, length: int, caplog: pytest.LogCaptureFixture
) -> None:
    digest = server.machine.state_digest()
    good = await server.connect()
    bad = await server.connect()
    async with good, bad:
        assert await good.ew(*STATUS) == 0
        with caplog.at_level(logging.WARNING, logger="focas_net.server"):
            bad.send_raw(struct.pack("<I", length))  # only the length field: acted on at once
            assert await bad.closed_by_peer()
        assert await good.ew(*STATUS) == 0
    assert server.listener.violations == 1
    assert server.machine.state_digest() == digest
    warnings = [r for r in caplog.records if r.levelno == logging.WARNING]
    assert any("closing the connection from" in r.getMessage() for r in warnings)
    local = bad.writer.get_extra_info("sockname")
    assert any(str(local[1]) in r.getMessage() for r in warnings), "peer address logged"
    assert not any("0000" in r.getMessage() for r in warnings), "no hex dump above DEBUG"


async def test_oversize_frame_after_good_ones(server: Served) -> None:
    async with await server.connect() as w:
        w.send(Command.RDCNCSTAT, request_id=1)
        first = await w.recv()
        assert (first.command, first.request_id) == (Command.RDCNCSTAT, 1)
        w.send_raw(struct.pack("<IHH", 70_000, 1, 2))
        assert await w.closed_by_peer()


async def test_good_frames_in_the_same_chunk_as_a_violation_are_answered(
    server: Served,
) -> None:
    async with await server.connect() as w:
        good = encode_frame(Command.RDCNCSTAT, 5) + encode_frame(Command.SYSINFO, 6)
        w.send_raw(good + struct.pack("<IHH", 70_000, 1, 2))
        answers = await w.recv_many(2)
        assert [(a.command, a.request_id) for a in answers] == [
            (Command.RDCNCSTAT, 5),
            (Command.SYSINFO, 6),
        ]
        assert await w.closed_by_peer()


async def test_largest_frame_is_accepted(server: Served, wire: Wire) -> None:
    payload = b"\x00" * (65_536 - 4)
    assert await wire.call(Command.RDMACRO, payload) == struct.pack("<h", EW.LENGTH)
    assert await wire.call(0x0999, payload) == struct.pack("<h", EW.FUNC)


async def test_configurable_max_frame() -> None:
    async with serving(max_frame=100) as served:
        async with await served.connect() as w:
            assert await w.call(0x0999, b"\x00" * 96) == struct.pack("<h", EW.FUNC)
            w.send(0x0999, b"\x00" * 97)
            assert await w.closed_by_peer()


async def test_partial_frame_on_one_connection_does_not_block_another(server: Served) -> None:
    a = await server.connect()
    b = await server.connect()
    async with a, b:
        a.send_raw(encode_frame(Command.RDMACRO, 1, MacroRequest(1).encode())[:7])
        await a.writer.drain()
        assert await b.ew(*STATUS) == 0
        a.send_raw(encode_frame(Command.RDMACRO, 1, MacroRequest(1).encode())[7:])
        frame = await a.recv()
        assert frame.request_id == 1


async def test_machine_bug_answers_ew_reject_and_keeps_the_connection(
    server: Served, wire: Wire, monkeypatch: pytest.MonkeyPatch, caplog: pytest.LogCaptureFixture
) -> None:
    from focas_net.adapters import PackedAdapter
    from focas_net.sim import Session

    real = PackedAdapter.answer

    def broken(
        adapter: PackedAdapter, session: Session, command: int, payload: bytes, path: int = 1
    ) -> bytes:
        if command == Command.RDMACRO:
            raise RuntimeError("simulated machine bug")
        return real(adapter, session, command, payload, path)

    monkeypatch.setattr(PackedAdapter, "answer", broken)
    with caplog.at_level(logging.ERROR, logger="focas_net.server"):
        assert await wire.ew(Command.RDMACRO, MacroRequest(1).encode()) == EW.REJECT
    assert any("simulated machine bug" in (r.exc_text or "") for r in caplog.records)
    assert await wire.ew(*STATUS) == 0


# -- connection limits -----------------------------------------------------------------------


async def test_max_connections_refuses_extra_and_logs(caplog: pytest.LogCaptureFixture) -> None:
    async with serving(max_connections=3) as served:
        wires = [await served.connect() for _ in range(3)]
        for w in wires:
            assert await w.ew(*STATUS) == 0
        with caplog.at_level(logging.WARNING, logger="focas_net.server"):
            extra = await served.connect()
            assert await extra.closed_by_peer()
            await extra.close()
        assert served.listener.refused == 1
        assert any("refused" in r.getMessage() for r in caplog.records)
        for w in wires:
            assert await w.ew(*STATUS) == 0
        await wires[0].close()
        await wait_until(lambda: len(served.listener.connections) == 2)
        async with await served.connect() as again:
            assert await again.ew(*STATUS) == 0
        for w in wires[1:]:
            await w.close()


async def test_idle_connection_is_closed() -> None:
    async with serving(idle_timeout=0.2) as served:
        async with await served.connect() as w:
            assert await w.ew(*STATUS) == 0
            assert await w.closed_by_peer()
        # a trickle of bytes that never completes a frame is not activity
        async with await served.connect() as slow:
            slow.send_raw(b"\x08")
            await slow.writer.drain()
            assert await slow.closed_by_peer()


async def test_idle_timeout_zero_runs_no_sweeper(server: Served) -> None:
    async with serving(idle_timeout=0) as served:
        assert served.server._sweeper is None
        async with await served.connect() as w:
            assert await w.ew(*STATUS) == 0


# -- backpressure ----------------------------------------------------------------------------


async def _small_window_wire(host: str, port: int) -> Wire:
    """A connection whose receive buffer is small (no autotuning), so unread answers pile up
    at the server rather than in the kernel."""
    sock = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 16 * 1024)
    sock.setblocking(False)
    loop = asyncio.get_running_loop()
    await loop.sock_connect(sock, (host, port))
    reader, writer = await asyncio.open_connection(sock=sock, limit=1 << 20)
    return Wire(reader, writer)


async def test_client_that_never_reads_leaves_server_memory_bounded(server: Served) -> None:
    # 250 alarms in the history: every cnc_rdalmhistry(250) answer is about 11 KB
    async with await server.connect() as setup:
        for i in range(250):
            setup.send(Command.SIM_RAISE_ALARM, RaiseAlarm(0, 3, i, b"ALARM %03d" % i).encode())
        setup.send(Command.SIM_CLEAR_ALARMS, ClearAlarms(-1, -1).encode())
        await setup.recv_many(251)
    history = AlarmHistoryRequest(250).encode()
    n = 6000  # about 66 MB of answers for 60 KB of requests
    w = await _small_window_wire(server.host, server.port)
    async with w:
        w.send_raw(b"".join(encode_frame(Command.RDALMHISTRY, i, history) for i in range(n)))
        conn = next(c for c in server.listener.connections if c.peer[1] == w.sockname[1])
        await wait_until(lambda: conn.reading_paused)
        high = server.server.write_buffer_high
        answer_size = 8 + 2 + 250 * 32
        # unsent output: the high-water mark, plus at most one budget of answers and one more
        assert conn.write_buffer_size <= 2 * high + answer_size
        assert conn.buffered_input <= 256 * 1024 + 16
        # now read everything: every request gets its answer, none lost
        decoder = FrameDecoder()
        got: set[int] = set()
        async with asyncio.timeout(60):
            while len(got) < n:
                chunk = await w.reader.read(1 << 20)
                assert chunk, "server closed the connection"
                for frame in decoder.feed(chunk):
                    assert frame.command == Command.RDALMHISTRY
                    assert struct.unpack_from("<h", frame.payload)[0] == 250
                    got.add(frame.request_id)
        assert got == set(range(n))
        await wait_until(lambda: not conn.reading_paused)
        assert await w.ew(*STATUS) == 0


async def test_delayed_answers_bound_pauses_reading() -> None:
    async with serving(max_delayed=4) as served:
        async with await served.connect() as w:
            assert await w.ew(Command.SIM_INJECT_FAULT, InjectFault(1, 0, 10, 60_000).encode()) == 0
            w.send_raw(b"".join(encode_frame(Command.RDCNCSTAT, rid) for rid in range(10)))
            await w.writer.drain()
            conn = next(iter(served.listener.connections))
            await wait_until(lambda: conn.delayed_count == 4 and conn.reading_paused)
            assert conn.buffered_input > 0  # the other requests wait, unanswered
            conn.flush_delayed()  # what a shutdown grace expiry does: the 4 go out now
            conn._maybe_resume()
            frames = await w.recv_many(4)
            assert sorted(f.request_id for f in frames) == [0, 1, 2, 3]
            await wait_until(lambda: conn.delayed_count == 4)  # the next 4 are held


# -- fleets ------------------------------------------------------------------------------------


async def test_fleet_of_50_machines_with_isolated_state() -> None:
    machines = [default_machine(name=f"cnc-{i}") for i in range(50)]
    async with FocasServer(machines, host="127.0.0.1", port=0) as srv:
        assert len({listener.port for listener in srv.listeners}) == 50
        wires = [await Wire.open(host, port) for host, port in srv.addresses]
        try:
            for i, w in enumerate(wires):
                assert await w.ew(Command.WRMACRO, MacroValue(100, 8, i, 0).encode()) == 0
            assert (
                await wires[7].ew(Command.SIM_INJECT_FAULT, InjectFault(2, 1, 1, EW.BUSY).encode())
                == 0
            )
            assert await wires[8].ew(*STATUS) == 0  # another machine: no fault
            assert await wires[7].ew(*STATUS) == EW.BUSY
            for i, w in enumerate(wires):
                value = await w.request(Command.RDMACRO, MacroRequest(100))
                assert value.mcr_val == i
            assert [m.name for m in srv.machines] == [f"cnc-{i}" for i in range(50)]
        finally:
            for w in wires:
                await w.close()


async def test_bind_failure_closes_the_listeners_already_bound() -> None:
    blocker = socket.socket()
    blocker.bind(("127.0.0.1", 0))
    blocker.listen()
    taken = blocker.getsockname()[1]
    try:
        srv = FocasServer(
            [default_machine(), default_machine()], host="127.0.0.1", ports=[0, taken]
        )
        with pytest.raises(OSError):
            await srv.start()
        first = srv.listeners[0]
        assert first.port != 0
        with pytest.raises(OSError):
            await Wire.open("127.0.0.1", first.port)
    finally:
        blocker.close()


@pytest.mark.parametrize(
    "kwargs",
    [
        {"max_frame": 3},
        {"max_connections": 0},
        {"idle_timeout": -1},
        {"max_delayed": 0},
        {"write_buffer_high": 0},
        {"grace_period": -1},
        {"port": 70_000},
        {"ports": [0, 0]},
        {"max_frame": 0xA0A0A0A0},
        {"port": None},  # nothing to serve without native_port
        {"native_port": 70_000},
        {"native_version": 0},
        {"native_max_body": 0x10000},
    ],
)
def test_bad_arguments(kwargs: dict[str, object]) -> None:
    with pytest.raises(ValueError):
        FocasServer(default_machine(), **kwargs)  # type: ignore[arg-type]


def test_no_machines_is_an_error() -> None:
    with pytest.raises(ValueError):
        FocasServer([])


async def test_default_machine_and_repr() -> None:
    async with FocasServer(host="127.0.0.1", port=0) as srv:
        (listener,) = srv.listeners
        assert listener.host == "127.0.0.1"
        assert listener.address_text == f"127.0.0.1:{listener.port}"
        assert "serving" in repr(srv)
        stats = srv.stats()[listener.label]
        assert stats["connections"] == 0
    assert "closed" in repr(srv)


# -- graceful shutdown -------------------------------------------------------------------------


async def test_shutdown_answers_delayed_requests_in_flight() -> None:
    served_cm = serving(grace_period=5.0)
    served = await served_cm.__aenter__()
    try:
        w = await served.connect()
        assert await w.ew(Command.SIM_INJECT_FAULT, InjectFault(1, 0, 3, 300).encode()) == 0
        for rid in (10, 11, 12):
            w.send(*STATUS, request_id=rid)
        await w.writer.drain()
        conn = next(iter(served.listener.connections))
        await wait_until(lambda: conn.delayed_count == 3)
    except BaseException:
        await served_cm.__aexit__(None, None, None)
        raise
    closing = asyncio.create_task(served_cm.__aexit__(None, None, None))
    frames = await w.recv_many(3)
    assert sorted(f.request_id for f in frames) == [10, 11, 12]
    assert await w.closed_by_peer()
    await closing
    await w.close()
    with pytest.raises(OSError):
        await Wire.open(served.host, served.port)


async def test_shutdown_grace_expiry_sends_delayed_answers_early() -> None:
    async with serving() as served:
        w = await served.connect()
        assert await w.ew(Command.SIM_INJECT_FAULT, InjectFault(1, 0, 2, 60_000).encode()) == 0
        w.send(*STATUS, request_id=1)
        w.send(*STATUS, request_id=2)
        await w.writer.drain()
        conn = next(iter(served.listener.connections))
        await wait_until(lambda: conn.delayed_count == 2)
        await served.server.aclose(grace_period=0.1)
        frames = await w.recv_many(2)
        assert sorted(f.request_id for f in frames) == [1, 2]
        assert await w.closed_by_peer()
        await w.close()
        assert served.server.connection_count == 0


async def test_shutdown_closes_idle_connections(server: Served) -> None:
    w = await server.connect()
    assert await w.ew(*STATUS) == 0
    await server.server.aclose()
    assert await w.closed_by_peer()
    await w.close()


# -- TLS ---------------------------------------------------------------------------------------


async def test_tls(certificate: tuple[Path, Path]) -> None:
    cert, key = certificate
    server_ctx = ssl.SSLContext(ssl.PROTOCOL_TLS_SERVER)
    server_ctx.load_cert_chain(cert, key)
    client_ctx = ssl.create_default_context(cafile=str(cert))
    async with serving(ssl=server_ctx) as served:
        async with await Wire.open(served.host, served.port, ssl=client_ctx) as w:
            assert await w.ew(*STATUS) == 0
            value = await w.request(Command.RDMACRO, MacroRequest(1))
            assert value.vacant
        # a plain-text client gets nothing it can decode and does not disturb the server
        async with await served.connect() as plain:
            plain.send(*STATUS)
            with pytest.raises((EOFError, TimeoutError, ConnectionError, FrameError)):
                await plain.recv(within=2.0)
        async with await Wire.open(served.host, served.port, ssl=client_ctx) as again:
            assert await again.ew(*STATUS) == 0


# -- uvloop ------------------------------------------------------------------------------------


def test_serves_on_uvloop() -> None:
    pytest.importorskip("uvloop")
    import anyio

    async def main() -> int:
        async with serving() as served:
            async with await served.connect() as w:
                assert await w.ew(Command.SIM_INJECT_FAULT, InjectFault(1, 0, 1, 10).encode()) == 0
                w.send(*STATUS, request_id=1)
                w.send(Command.RDMACRO, MacroRequest(1).encode(), request_id=2)
                frames = await w.recv_many(2)
                return len(frames)

    assert anyio.run(main, backend="asyncio", backend_options={"use_uvloop": True}) == 2
