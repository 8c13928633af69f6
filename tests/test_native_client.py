"""The native client against the real server (both command sets) and against a scripted peer.

Against :class:`FocasServer` on 127.0.0.1: the built-in machine answers the 30i command set, a
machine file with ``control_class = "16i"`` the 16i set. Every read is cross-checked with the
packed client on the same server; writes are read back through it. Batching, the error of one
block, PMC chunking, bit storms, cancellation storms, connection loss and a reconnect after a
server restart follow.

A scripted FOCAS/2 peer (:class:`NativePeer`) holds answers back on demand, for timeouts and
late answers. Tests check outcomes, never durations.

Every test runs twice: with the client's connections on sockets it reads itself (asyncio's
selector loop, the default) and on the loop's transports (as on uvloop or the proactor loop).
"""

from __future__ import annotations

import asyncio
import math
from collections.abc import AsyncIterator, Callable
from decimal import Decimal
from pathlib import Path

import pytest
from support import IO_TIMEOUT, ChannelLog, LoopbackPeer, Served, serving, wait_until

from focas_net.client import ClientState, FocasClient, NotSentError, ReconnectPolicy, _channel
from focas_net.client.native import NativeClient, NativeUnsupportedError
from focas_net.errors import EW, CncError, FocasConnectionError, FocasTimeoutError
from focas_net.native import (
    LIBRARY_MAX_REQUEST_BODY,
    FrameType,
    NativeFrameDecoder,
    ParamInfo3,
    PathDescription,
    RequestBlock,
    ResponseBlock,
    ScaledNumber,
    ScaledValues,
    build_open_answer,
    decode_request_body,
    encode_close_response,
    encode_native_response,
    encode_open_response,
    max_response_body,
)
from focas_net.native.calls import CommandSet
from focas_net.native.requests import NativeCommand
from focas_net.protocol import FaultKind, FaultScope
from focas_net.server import FocasServer
from focas_net.sim import Machine, default_machine, load_machine
from focas_net.sim.machine import MDI


@pytest.fixture(autouse=True, params=["sockets", "transports"])
def channel_kind(request: pytest.FixtureRequest, monkeypatch: pytest.MonkeyPatch) -> str:
    """The kind of connection every client of the test opens."""
    kind: str = request.param
    if kind == "transports":
        monkeypatch.setattr(_channel, "own_sockets", lambda loop: False)
    return kind


MACHINE_16I = """
[machine]
name = "fs16i"
axes = ["X", "Y", "Z"]
control_class = "16i"

[sysinfo]
cnc_type = "16"
series = "B0H1"
version = "14.0"

[panel]
mode = "MDI"
pwe = true

[parameters.1320]
type = "i32"
axis = true
value = [999999999, 888888888, -777777777]
[parameters.3216]
type = "i16"
value = -7
[parameters.6711]
type = "i32"
value = 123456789

[diagnostics.300]
type = "i32"
axis = true
value = [11, -22, 33]

[macros]
ranges = [{ first = 1, last = 33 }, { first = 100, last = 999 }]
values = { 100 = [12345, 3] }

[pmc.R]
size = 8000
[pmc.D]
size = 10000
"""

CLASSES = ("30i", "16i")


def _machine(control_class: str, tmp_path: Path) -> Machine:
    if control_class == "30i":
        machine = default_machine()
        machine.set_panel(MDI, 1, 0)
        return machine
    path = tmp_path / "fs16i.toml"
    path.write_text(MACHINE_16I)
    return load_machine(path)


@pytest.fixture(params=CLASSES)
async def served(request: pytest.FixtureRequest, tmp_path: Path) -> AsyncIterator[Served]:
    async with serving(_machine(request.param, tmp_path)) as s:
        yield s


@pytest.fixture
async def both(served: Served) -> AsyncIterator[tuple[NativeClient, FocasClient]]:
    async with (
        NativeClient(served.host, served.port, timeout=IO_TIMEOUT) as native,
        FocasClient(served.host, served.port, timeout=IO_TIMEOUT) as packed,
    ):
        yield native, packed


async def test_the_connections_are_of_the_kind_chosen(
    served: Served, channel_kind: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    log = ChannelLog(monkeypatch)
    async with NativeClient(served.host, served.port, timeout=IO_TIMEOUT) as native:
        assert await native.read_status() is not None
    kind = _channel.SocketChannel if channel_kind == "sockets" else _channel.TransportChannel
    assert [type(c) for c in log.opened] == [kind, kind]


def _expected_set(served: Served) -> CommandSet:
    return CommandSet.FS16I if served.machine.control_class == "16i" else CommandSet.FS30I


# -- reads and writes against the real server --------------------------------------------------


async def test_command_set_follows_the_control(
    served: Served, both: tuple[NativeClient, FocasClient]
) -> None:
    native, _ = both
    assert native.command_set is _expected_set(served)
    assert native.state is ClientState.CONNECTED


async def test_reads_equal_the_packed_clients(
    served: Served, both: tuple[NativeClient, FocasClient]
) -> None:
    native, packed = both
    m = served.machine
    m.raise_alarm(1, 4, 500, "OVER TRAVEL +X")
    m.raise_alarm(0, 2, 1001, "SPINDLE ALARM")
    m.clear_alarms(2, 1001)
    m.write_macro(101, Decimal("-2.5"))
    m.write_pmc("R", 10, bytes(range(40)))
    assert await native.read_status() == await packed.read_status()
    assert await native.read_sysinfo() == await packed.read_sysinfo()
    assert await native.read_program_numbers() == await packed.read_program_numbers()
    assert await native.read_feed() == await packed.read_feed()
    assert await native.read_spindle_speed() == await packed.read_spindle_speed()
    for kind in ("absolute", "machine", "relative", "distance"):
        assert await native.read_positions(kind) == await packed.read_positions(kind)
        assert await native.read_positions(kind, axis=2) == await packed.read_positions(
            kind, axis=2
        )
    for number in (100, 101, 102):
        assert await native.read_macro(number) == await packed.read_macro(number)
    assert await native.read_pmc("R", 10, 40) == await packed.read_pmc("R", 10, 40)
    assert await native.read_pmc_bit("R", 11, 0) == await packed.read_pmc_bit("R", 11, 0)
    for number, axis in ((1320, 1), (1320, 3), (3216, 0), (6711, 0)):
        assert await native.read_param_value(number, axis=axis) == await packed.read_param_value(
            number, axis=axis
        )
    assert await native.read_diag(300, axis=2) == await packed.read_diag(300, axis=2)
    assert await native.read_alarms() == await packed.read_alarms()
    assert await native.read_alarm_history(5) == await packed.read_alarm_history(5)
    with pytest.raises(ValueError, match=r"history depth 0 is below 1 \(the latest entries"):
        await native.read_alarm_history(0)
    assert await native.read_axis_names() == tuple(m.axes)


async def test_native_only_reads(served: Served, both: tuple[NativeClient, FocasClient]) -> None:
    native, packed = both
    dynamic = await native.read_dynamic()
    absolute = await packed.read_positions("absolute")
    assert dynamic.absolute == tuple(absolute.increments.values())
    programs = await packed.read_program_numbers()
    assert (dynamic.running, dynamic.main) == (programs.running, programs.main)
    one = await native.read_dynamic(2)
    assert one.absolute == (absolute.increments[served.machine.axes[1]],)
    assert len(await native.read_cnc_id()) == 4
    timer = await native.read_timer(0)
    assert timer.minute >= 0 and 0 <= timer.msec
    assert len(await native.read_spindle_loads()) >= 1
    meters = await native.read_servo_meters()
    assert tuple(s.name for s in meters) == tuple(served.machine.axes)
    o_num, name = await native.read_program_name()
    assert o_num == (await packed.read_program_numbers()).running and name
    assert await native.read_sequence_number() >= 0
    served.machine.raise_alarm(0, 3, 10, "X")
    assert await native.read_alarm_status() & (1 << 3)


async def test_a_repeated_answer_and_a_changed_one(
    served: Served, both: tuple[NativeClient, FocasClient]
) -> None:
    native, packed = both
    machine = served.machine
    n = len(machine.axes)
    machine.write_macro(500, 7)
    machine.set_motion(absolute=range(10, 10 + n), feed=40)
    first = (await native.read_macro(500), await native.read_status(), await native.read_dynamic())
    again = (await native.read_macro(500), await native.read_status(), await native.read_dynamic())
    assert again == first
    machine.write_macro(500, 8)
    machine.set_run(3, 1)
    machine.set_motion(absolute=range(20, 20 + n), feed=41)
    assert await native.read_macro(500) == Decimal(8)
    status = await native.read_status()
    assert status == await packed.read_status() and status != first[1]
    dynamic = await native.read_dynamic()
    assert dynamic.absolute == tuple(range(20, 20 + n)) and dynamic.feed == 41
    assert (await native.read_dynamic(1)).absolute == (20,)


async def test_writes_reach_the_machine(both: tuple[NativeClient, FocasClient]) -> None:
    native, packed = both
    for value in ("12.345", -2.5, 100, Decimal("0.000"), 0):
        await native.write_macro(500, value)
        assert await packed.read_macro(500) == await native.read_macro(500)
        assert await packed.read_macro(500) == Decimal(str(value))
    await native.write_param(6711, 987654321)
    assert await packed.read_param(6711) == 987654321
    await native.write_param(1320, 42, axis=2)
    assert await packed.read_param(1320, axis=2) == 42
    with pytest.raises(CncError) as caught:
        await native.write_param(6711, 1, width=2)
    assert caught.value.ew == EW.LENGTH
    data = bytes((i * 7) % 256 for i in range(5000))
    await native.write_pmc("D", 100, data)
    assert await packed.read_pmc("D", 100, len(data)) == data
    assert await native.read_pmc("D", 100, len(data)) == data


async def test_refusals_raise_cnc_error(both: tuple[NativeClient, FocasClient]) -> None:
    native, packed = both
    for call in (native.read_macro, packed.read_macro):
        with pytest.raises(CncError) as caught:
            await call(30000)
        assert caught.value.ew == EW.NUMBER
    with pytest.raises(CncError) as axis:
        await native.read_positions(axis=9)
    assert axis.value.ew == EW.ATTRIB


async def test_what_the_native_transport_cannot_carry(
    both: tuple[NativeClient, FocasClient],
) -> None:
    native, _ = both
    checks: list[Callable[[], object]] = [
        lambda: native.sim,
    ]
    for check in checks:
        with pytest.raises(NativeUnsupportedError, match="native"):
            check()
    with pytest.raises(NativeUnsupportedError, match="native"):
        await native.unlock("secret")
    with pytest.raises(NativeUnsupportedError, match="native"):
        await native.read_config_record(0, 1)
    with pytest.raises(NativeUnsupportedError, match="native"):
        await native.read_module_config(0, 1)


# -- batching ---------------------------------------------------------------------------------


async def test_concurrent_calls_share_frames(
    served: Served, both: tuple[NativeClient, FocasClient]
) -> None:
    native, _ = both
    for n in range(100, 164):
        served.machine.write_macro(n, n)
    frames = native.frames_sent
    values = await asyncio.gather(*(native.read_macro(n) for n in range(100, 164)))
    assert values == [Decimal(n) for n in range(100, 164)]
    assert native.frames_sent - frames == math.ceil(64 / native.max_blocks)


async def test_interleaved_methods_share_frames_and_keep_their_answers(
    served: Served, both: tuple[NativeClient, FocasClient]
) -> None:
    native, packed = both
    for n in range(100, 130):
        served.machine.write_macro(n, n)
    status = await native.read_status()
    frames = native.frames_sent
    # macro, macro, status, macro, macro, status...: runs of equal calls and changes of call
    calls = [native.read_status() if i % 3 == 2 else native.read_macro(100 + i) for i in range(30)]
    got = await asyncio.gather(*calls)
    assert got == [status if i % 3 == 2 else Decimal(100 + i) for i in range(30)]
    # 20 blocks of macros and 30 of statuses, ten to a frame, in the order of the calls
    assert native.frames_sent - frames == 5
    assert status == await packed.read_status()


async def test_a_lone_callers_next_call_leaves_at_once(
    served: Served, monkeypatch: pytest.MonkeyPatch
) -> None:
    served.machine.write_macro(100, 7)
    log = ChannelLog(monkeypatch)
    async with NativeClient(served.host, served.port, timeout=IO_TIMEOUT) as native:
        b = log.b
        write = b.write
        writers: list[asyncio.Task[object] | None] = []

        def spy(data: bytes) -> None:
            writers.append(asyncio.current_task())
            write(data)

        b.write = spy
        # Each call after the first was alone in the frame answered last, so its task
        # writes it itself (not a callback at the end of the loop turn).
        assert [await native.read_macro(100) for _ in range(3)] == [7, 7, 7]
        this = asyncio.current_task()
        assert writers[1:] == [this, this]
        # Calls of other tasks made together still share one frame, sent from a callback.
        frames = native.frames_sent
        values = await asyncio.gather(*(native.read_macro(100) for _ in range(native.max_blocks)))
        assert values == [7] * native.max_blocks
        assert native.frames_sent - frames == 1
        assert writers[-1] is None


async def test_frames_split_by_the_answer_and_request_size(served: Served) -> None:
    async with NativeClient(served.host, served.port, max_blocks=200) as native:
        for n in range(100, 164):
            served.machine.write_macro(n, -n)
        frames = native.frames_sent
        values = await asyncio.gather(*(native.read_macro(n) for n in range(100, 164)))
        assert values == [Decimal(-n) for n in range(100, 164)]
        assert native.version is not None
        per_answer = (max_response_body(native.version) - 2) // (16 + 8)
        per_request = (LIBRARY_MAX_REQUEST_BODY - 2) // 28
        per_frame = min(per_answer, per_request)
        assert native.frames_sent - frames == math.ceil(64 / per_frame)


async def test_an_error_fails_its_own_call_only(both: tuple[NativeClient, FocasClient]) -> None:
    native, packed = both
    frames = native.frames_sent
    results = await asyncio.gather(
        native.read_macro(100), native.read_macro(30000), native.read_status(),
        return_exceptions=True,
    )  # fmt: skip
    assert native.frames_sent - frames == 1
    assert results[0] == await packed.read_macro(100)
    assert isinstance(results[1], CncError) and results[1].ew == EW.NUMBER
    assert results[2] == await packed.read_status()


async def test_pmc_ranges_chunked_by_the_answer(
    served: Served, both: tuple[NativeClient, FocasClient]
) -> None:
    native, packed = both
    assert native.version is not None
    data = bytes((i * 13) % 251 for i in range(6000))
    served.machine.write_pmc("D", 0, data)
    frames = native.frames_sent
    assert await native.read_pmc("D", 0, len(data)) == data
    per_answer = max_response_body(native.version) - 2 - 16  # a block's head and the count
    assert native.frames_sent - frames == math.ceil(len(data) / per_answer)
    assert await packed.read_pmc("D", 0, len(data)) == data


# -- locks, storms, losses --------------------------------------------------------------------


async def test_pmc_bit_storm_loses_no_bit(both: tuple[NativeClient, FocasClient]) -> None:
    native, packed = both
    await packed.write_pmc("R", 200, bytes(8))
    await asyncio.gather(
        *(native.write_pmc_bit("R", 200 + byte, bit, True) for bit in range(8) for byte in range(8))
    )
    assert await packed.read_pmc("R", 200, 8) == b"\xff" * 8
    await asyncio.gather(*(native.write_pmc_bit("R", 203, bit, False) for bit in range(0, 8, 2)))
    assert (await packed.read_pmc("R", 203, 1))[0] == 0b10101010


async def test_param_bit_storm_loses_no_bit(both: tuple[NativeClient, FocasClient]) -> None:
    native, packed = both
    await packed.write_param(6711, 0)
    await asyncio.gather(*(native.write_param_bit(6711, bit, True) for bit in range(16)))
    assert await packed.read_param(6711) == 0xFFFF


async def test_cancellation_storm_misroutes_nothing(
    served: Served, both: tuple[NativeClient, FocasClient]
) -> None:
    native, _ = both
    for n in range(500, 700):
        served.machine.write_macro(n, n)
    for round_ in range(3):
        tasks = [asyncio.ensure_future(native.read_macro(n)) for n in range(500, 700)]
        for _ in range(round_ + 1):
            await asyncio.sleep(0)
        for i, task in enumerate(tasks):
            if i % 3 == round_ % 3:
                task.cancel()
        await asyncio.wait(tasks)
        for n, task in zip(range(500, 700), tasks, strict=True):
            if not task.cancelled():
                assert task.result() == Decimal(n)
    assert native.state is ClientState.CONNECTED
    assert await asyncio.gather(*(native.read_macro(n) for n in range(500, 530))) == [
        Decimal(n) for n in range(500, 530)
    ]


async def test_connection_loss_fails_pending_calls() -> None:
    async with NativePeer() as peer:
        async with NativeClient("127.0.0.1", peer.port, timeout=IO_TIMEOUT) as native:
            peer.hold = True
            calls = [asyncio.ensure_future(native.read_macro(n)) for n in range(1, 31)]
            await wait_until(lambda: peer.data_frames == 1)
            peer.drop()
            results = await asyncio.gather(*calls, return_exceptions=True)
            sent = [r for r in results[: native.max_blocks]]
            queued = results[native.max_blocks :]
            closed = f"connection closed by 127.0.0.1:{peer.port}"
            assert all(type(r) is FocasConnectionError and str(r) == closed for r in sent)
            assert all(type(r) is NotSentError for r in queued)
            assert all(str(r) == f"{closed} (the request was never sent)" for r in queued)
            assert native.state is ClientState.DISCONNECTED
            with pytest.raises(FocasConnectionError, match="not connected"):
                await native.read_macro(1)


async def test_reconnects_after_a_server_restart(tmp_path: Path) -> None:
    machine = _machine("30i", tmp_path)
    policy = ReconnectPolicy(initial_delay=0.01, max_delay=0.05, jitter=0)
    async with FocasServer(machine, host="127.0.0.1", port=0, grace_period=1.0) as first:
        host, port = first.listeners[0].address
        native = NativeClient(host, port, timeout=IO_TIMEOUT, reconnect=policy)
        await native.connect()
        machine.write_macro(100, 7)
        assert await native.read_macro(100) == 7
    try:
        await wait_until(lambda: native.state is ClientState.RECONNECTING)
        async with FocasServer(machine, host=host, port=port, grace_period=1.0):
            machine.write_macro(100, 8)
            assert await native.read_macro(100) == 8
            assert native.state is ClientState.CONNECTED
    finally:
        await native.aclose()
    states: set[ClientState] = {native.state}
    assert states == {ClientState.CLOSED}


# -- a scripted peer: timeouts and late answers ---------------------------------------------


class NativePeer(LoopbackPeer):
    """A FOCAS/2 peer answering macro reads with the variable's number; holds answers while
    ``hold`` is set, and releases them in order with :meth:`release`."""

    def __init__(self, version: int = 3) -> None:
        self.version = version
        self.hold = False
        self.held: list[tuple[asyncio.StreamWriter, bytes]] = []
        self.data_frames = 0
        self.connections = 0
        #: A command after whose answer the connection is closed.
        self.close_after: int | None = None
        #: How many of the next connections send a byte nobody asked for, with the answer to
        #: the connect-time system information.
        self.stray = 0

    def _answer(self, block: RequestBlock) -> ResponseBlock:
        if block.command == NativeCommand.RDMACRO:
            return block.reply(ScaledValues((ScaledNumber(block.args[0], 0),)).encode())
        if block.command == NativeCommand.RDPARAINFO3:
            return block.reply(ParamInfo3(0, 0, block.args[0], 3, 0).encode())
        if block.command == NativeCommand.SYSINFO:
            return block.reply(bytes(4) + b" 0 MD4F132.003")
        return block.reply(ew=EW.FUNC)

    async def _serve(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        self.connections += 1
        decoder = NativeFrameDecoder()
        body = build_open_answer([PathDescription()], 8, version=self.version)
        try:
            while data := await reader.read(65536):
                for frame in decoder.feed(data):
                    if frame.type == FrameType.OPEN_REQUEST:
                        writer.write(encode_open_response(body, self.version))
                    elif frame.type == FrameType.CLOSE_REQUEST:
                        writer.write(encode_close_response(self.version))
                    else:
                        blocks = decode_request_body(frame.body)
                        answer = encode_native_response(
                            [self._answer(b) for b in blocks], self.version
                        )
                        if any(b.command == NativeCommand.RDMACRO for b in blocks):
                            self.data_frames += 1
                            if self.hold:
                                self.held.append((writer, answer))
                                continue
                        if self.stray and blocks[0].command == NativeCommand.SYSINFO:
                            self.stray -= 1
                            answer += b"\x00"  # in the same write: read with the answer
                        writer.write(answer)
                        if any(b.command == self.close_after for b in blocks):
                            await writer.drain()
                            writer.transport.abort()
                            return
        except ConnectionError:
            pass
        finally:
            writer.close()

    def drop(self) -> None:
        """Close every connection that has answers held."""
        for writer, _ in self.held:
            writer.transport.abort()
        self.held.clear()

    def release(self) -> None:
        for writer, answer in self.held:
            if not writer.is_closing():
                writer.write(answer)
        self.held.clear()


async def test_a_reconnect_whose_connection_is_lost_as_it_is_installed_goes_on() -> None:
    # B sends a byte nobody asked for with its connect-time answer: the new pair is lost as
    # soon as it is installed, and the reconnect tries again rather than giving up.
    policy = ReconnectPolicy(initial_delay=0.01, max_delay=0.05, jitter=0)
    async with NativePeer() as peer:
        async with NativeClient(
            "127.0.0.1", peer.port, timeout=IO_TIMEOUT, reconnect=policy
        ) as native:
            assert await native.read_macro(5) == 5
            peer.stray = 2
            peer.hold = True
            call = asyncio.ensure_future(native.read_macro(1))
            await wait_until(lambda: peer.data_frames == 2)
            peer.hold = False
            peer.drop()
            with pytest.raises(FocasConnectionError):
                await asyncio.wait_for(call, IO_TIMEOUT)
            assert await native.read_macro(2) == 2
            assert peer.stray == 0
            assert peer.connections == 8  # A and B, four times
            assert native.state is ClientState.CONNECTED


async def test_a_late_answer_never_reaches_another_call() -> None:
    # (no reconnect policy: the next call waits for the late answer on the same pair; with a
    # policy it would go on a new pair at once, test_native_late_answers.py)
    async with NativePeer() as peer:
        async with NativeClient("127.0.0.1", peer.port) as native:
            assert await native.read_macro(5) == 5
            peer.hold = True
            with pytest.raises(FocasTimeoutError):
                await native.read_macro(1, timeout=0.05)
            peer.release()  # the late answer: matched to its frame and dropped
            peer.hold = False
            assert await native.read_macro(2, timeout=IO_TIMEOUT) == 2
            assert peer.connections == 2  # the same A and B
            assert native.state is ClientState.CONNECTED


async def test_a_timed_out_call_does_not_fail_its_frame_partners() -> None:
    async with NativePeer() as peer:
        async with NativeClient("127.0.0.1", peer.port, timeout=IO_TIMEOUT) as native:
            peer.hold = True
            short = asyncio.ensure_future(native.read_macro(1, timeout=0.05))
            long = asyncio.ensure_future(native.read_macro(2))
            with pytest.raises(FocasTimeoutError):
                await short
            assert peer.data_frames == 1  # both in one frame
            peer.hold = False
            peer.release()
            assert await long == 2
            assert native.state is ClientState.CONNECTED
            assert await native.read_macro(3) == 3


async def test_a_call_that_times_out_queued_is_never_sent() -> None:
    async with NativePeer() as peer:
        async with NativeClient("127.0.0.1", peer.port, timeout=IO_TIMEOUT) as native:
            peer.hold = True
            first = asyncio.ensure_future(native.read_macro(1))
            await wait_until(lambda: peer.data_frames == 1)
            with pytest.raises(FocasTimeoutError, match="never sent"):
                await native.read_macro(2, timeout=0.05)
            peer.hold = False
            peer.release()
            assert await first == 1
            assert await native.read_macro(4) == 4
            assert peer.data_frames == 2  # macro 2 never left


async def test_an_earlier_calls_deadline_does_not_expire_a_later_frame() -> None:
    async with NativePeer() as peer:
        async with NativeClient("127.0.0.1", peer.port, timeout=IO_TIMEOUT) as native:
            assert await native.read_macro(1, timeout=0.05) == 1
            peer.hold = True
            later = asyncio.ensure_future(native.read_macro(2))
            await wait_until(lambda: peer.data_frames == 2)
            await asyncio.sleep(0.1)  # the first call's deadline passes while this one is out
            peer.hold = False
            peer.release()
            assert await later == 2
            assert native.state is ClientState.CONNECTED
            assert peer.connections == 2  # the same A and B


async def test_calls_left_out_of_a_full_frame_keep_their_timeouts() -> None:
    async with NativePeer() as peer:
        async with NativeClient("127.0.0.1", peer.port, timeout=IO_TIMEOUT, max_blocks=2) as native:
            peer.hold = True
            # issued in one loop turn: the frame takes two, the third waits in the queue
            first = asyncio.ensure_future(native.read_macro(1))
            second = asyncio.ensure_future(native.read_macro(2))
            third = asyncio.ensure_future(native.read_macro(3, timeout=0.05))
            with pytest.raises(FocasTimeoutError, match="never sent"):
                await third
            assert peer.data_frames == 1
            peer.hold = False
            peer.release()
            assert list(await asyncio.gather(first, second)) == [Decimal(1), Decimal(2)]
            assert await native.read_macro(4) == 4
            assert peer.data_frames == 2  # macro 3 never left
            assert native.state is ClientState.CONNECTED


async def test_a_queued_call_with_an_earlier_deadline_than_those_ahead_times_out_first() -> None:
    async with NativePeer() as peer:
        async with NativeClient("127.0.0.1", peer.port, timeout=IO_TIMEOUT) as native:
            peer.hold = True
            first = asyncio.ensure_future(native.read_macro(1))
            await wait_until(lambda: peer.data_frames == 1)
            patient = asyncio.ensure_future(native.read_macro(2))  # queued, a long deadline
            await asyncio.sleep(0)
            with pytest.raises(FocasTimeoutError, match="never sent"):
                await native.read_macro(3, timeout=0.05)  # queued after, due first
            assert not patient.done()
            peer.hold = False
            peer.release()
            assert await first == 1
            assert await patient == 2
            assert peer.data_frames == 2  # macro 3 never left
            assert native.state is ClientState.CONNECTED


async def test_the_watch_moves_on_past_calls_answered_before_their_deadline() -> None:
    async with NativePeer() as peer:
        async with NativeClient("127.0.0.1", peer.port, timeout=IO_TIMEOUT) as native:
            peer.hold = True
            first = asyncio.ensure_future(native.read_macro(1))
            await wait_until(lambda: peer.data_frames == 1)
            # queued with a short deadline: the watch is armed for it
            quick = asyncio.ensure_future(native.read_macro(2, timeout=0.1))
            await asyncio.sleep(0)
            peer.hold = False
            peer.release()
            assert await first == 1
            assert await quick == 2  # answered well before its deadline
            peer.hold = True
            held = asyncio.ensure_future(native.read_macro(3))
            await wait_until(lambda: peer.data_frames == 3)
            # queued behind the held frame, due after the answered call's deadline
            with pytest.raises(FocasTimeoutError, match="never sent"):
                await native.read_macro(4, timeout=0.2)
            peer.hold = False
            peer.release()
            assert await held == 3
            assert await native.read_macro(5) == 5
            assert native.state is ClientState.CONNECTED


async def test_closing_stops_the_watch() -> None:
    async with NativePeer() as peer:
        native = NativeClient("127.0.0.1", peer.port, timeout=IO_TIMEOUT)
        await native.connect()
        peer.hold = True
        first = asyncio.ensure_future(native.read_macro(1))
        await wait_until(lambda: peer.data_frames == 1)
        queued = asyncio.ensure_future(native.read_macro(2))
        await asyncio.sleep(0)
        await native.aclose()
        for call in (first, queued):
            with pytest.raises(FocasConnectionError, match="closed"):
                await call
        assert native.idle


async def test_calls_made_as_answers_arrive_share_a_frame() -> None:
    async with NativePeer() as peer:
        async with NativeClient("127.0.0.1", peer.port, timeout=IO_TIMEOUT) as native:

            async def twice(n: int) -> list[Decimal | None]:
                return [await native.read_macro(n), await native.read_macro(n + 10)]

            frames = native.frames_sent
            results = await asyncio.gather(*(twice(n) for n in range(3)))
            assert results == [[n, n + 10] for n in range(3)]
            assert native.frames_sent - frames == 2


async def test_a_loss_between_two_frames_of_one_call_fails_it_at_once() -> None:
    async with NativePeer() as peer:
        async with NativeClient("127.0.0.1", peer.port, timeout=None) as native:
            peer.close_after = NativeCommand.RDPARAINFO3
            async with asyncio.timeout(IO_TIMEOUT):  # a safety net: it must fail, not hang
                with pytest.raises(FocasConnectionError):
                    await native.write_param(6711, 1)
            assert native.state is ClientState.DISCONNECTED


async def test_connect_refuses_what_is_not_a_cnc() -> None:
    async def close_at_once(r: asyncio.StreamReader, w: asyncio.StreamWriter) -> None:
        w.close()

    server = await asyncio.start_server(close_at_once, "127.0.0.1", 0)
    port = server.sockets[0].getsockname()[1]
    try:
        with pytest.raises(FocasConnectionError):
            await NativeClient("127.0.0.1", port).connect()
    finally:
        server.close()
        await server.wait_closed()


@pytest.mark.parametrize("kind", [FaultKind.DELAY, FaultKind.ERROR, FaultKind.DROP])
async def test_server_faults_on_the_native_transport(served: Served, kind: FaultKind) -> None:
    """A delayed answer times the call out, an injected EW code fails the call, a dropped
    connection fails it; with a reconnect policy the next call works on a new connection."""
    policy = ReconnectPolicy(initial_delay=0.01, max_delay=0.05, jitter=0)
    served.machine.write_macro(100, 5)
    async with (
        FocasClient(served.host, served.port, timeout=IO_TIMEOUT) as packed,
        NativeClient(served.host, served.port, timeout=IO_TIMEOUT, reconnect=policy) as native,
    ):
        arg = {FaultKind.DELAY: 3000, FaultKind.ERROR: int(EW.DATA), FaultKind.DROP: 0}[kind]
        await packed.sim.inject_fault(kind, arg=arg, scope=FaultScope.MACHINE)
        if kind is FaultKind.DELAY:
            with pytest.raises(FocasTimeoutError):
                await native.read_macro(100, timeout=0.1)
        elif kind is FaultKind.ERROR:
            with pytest.raises(CncError) as caught:
                await native.read_macro(100)
            assert caught.value.ew == EW.DATA
        else:
            with pytest.raises(FocasConnectionError):
                await native.read_macro(100)
        assert await native.read_macro(100) == 5
        assert native.state is ClientState.CONNECTED
