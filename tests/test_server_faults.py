"""Fault injection (0x0E05): the pure rules, then every kind and both scopes over TCP."""

from __future__ import annotations

import struct
from typing import Any

import pytest
from support import Served, Wire, ew_of, serving, wait_until

from focas_net.errors import EW
from focas_net.protocol import (
    AlarmHistoryRequest,
    Command,
    DataRequest,
    FaultKind,
    FaultScope,
    InjectFault,
    MacroRequest,
    MacroValue,
    SetPanel,
    StatusInfo,
    encode_frame,
)
from focas_net.server import Fault, FaultQueue
from focas_net.server.faults import MAX_ARMED_FAULTS, fault_refusal, parse_inject
from focas_net.sim import default_machine

DELAY, ERROR, DROP, SPLIT = 1, 2, 3, 4
CONN, MACHINE = 0, 1


def inject(kind: int, scope: int, count: int, arg: int = 0) -> bytes:
    return InjectFault(kind, scope, count, arg).encode()


STATUS = (Command.RDCNCSTAT, b"")
MACRO_1 = (Command.RDMACRO, MacroRequest(1).encode())


# -- pure rules ----------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("kind", "scope", "count", "arg"),
    [
        (0, 0, 1, 0),
        (5, 0, 1, 0),
        (-1, 0, 1, 0),
        (1, 2, 1, 0),
        (1, -1, 1, 0),
        (1, 0, 0, 0),
        (1, 0, 10_001, 0),
        (1, 0, -5, 0),
        (1, 0, 1, -1),  # delay below 0
        (1, 0, 1, 60_001),  # delay above 60,000 ms
        (2, 0, 1, 0),  # EW_OK is not a fault
        (2, 0, 1, 32_768),  # outside i16
        (2, 1, 1, -32_769),
    ],
)
def test_parse_inject_rejects_bad_values(kind: int, scope: int, count: int, arg: int) -> None:
    assert parse_inject(inject(kind, scope, count, arg)) == EW.DATA


@pytest.mark.parametrize(
    ("kind", "scope", "count", "arg"),
    [
        (1, 0, 1, 0),
        (1, 1, 10_000, 60_000),
        (2, 0, 1, -1),
        (2, 1, 3, 32_767),
        (2, 0, 1, -32_768),
        (3, 0, 1, 0),
        (3, 1, 1, 12345),  # arg is ignored by kinds 3 and 4
        (4, 0, 7, -9),
    ],
)
def test_parse_inject_accepts(kind: int, scope: int, count: int, arg: int) -> None:
    parsed = parse_inject(inject(kind, scope, count, arg))
    assert not isinstance(parsed, int)
    got_scope, fault = parsed
    assert got_scope == FaultScope(scope)
    assert (fault.kind, fault.arg, fault.remaining) == (FaultKind(kind), arg, count)


def test_parse_inject_length_then_read_only_then_data() -> None:
    assert parse_inject(b"\x01\x00" * 4) == EW.LENGTH
    assert parse_inject(b"\x01\x00" * 4, read_only=True) == EW.LENGTH
    assert parse_inject(inject(9, 9, 0, 0), read_only=True) == EW.PROT
    assert parse_inject(inject(9, 9, 0, 0)) == EW.DATA


def test_fault_queue_applies_in_order_and_counts() -> None:
    q = FaultQueue()
    assert not q and q.take() is None
    assert q.arm(Fault(FaultKind.ERROR, -1, 2)) == EW.OK
    assert q.arm(Fault(FaultKind.DELAY, 10, 1)) == EW.OK
    assert len(q) == 2
    assert [q.take(), q.take(), q.take(), q.take()] == [
        (FaultKind.ERROR, -1),
        (FaultKind.ERROR, -1),
        (FaultKind.DELAY, 10),
        None,
    ]
    assert not q


def test_fault_queue_is_bounded() -> None:
    q = FaultQueue()
    for _ in range(MAX_ARMED_FAULTS):
        assert q.arm(Fault(FaultKind.SPLIT, 0, 1)) == EW.OK
    assert q.arm(Fault(FaultKind.SPLIT, 0, 1)) == EW.OVRFLOW
    assert len(q) == MAX_ARMED_FAULTS
    q.clear()
    assert not q


# -- over TCP ------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "payload",
    [
        inject(0, 0, 1),
        inject(1, 3, 1),
        inject(1, 0, 0),
        inject(1, 0, 10_001),
        inject(1, 0, 1, 60_001),
        inject(2, 0, 1, 0),
        inject(2, 0, 1, 40_000),
    ],
)
async def test_bad_inject_is_ew_data_and_arms_nothing(wire: Wire, payload: bytes) -> None:
    assert await wire.ew(Command.SIM_INJECT_FAULT, payload) == EW.DATA
    assert isinstance(await wire.request(Command.RDCNCSTAT), StatusInfo)


async def test_delay_lets_other_answers_overtake(server: Served, wire: Wire) -> None:
    assert await wire.ew(Command.SIM_INJECT_FAULT, inject(DELAY, CONN, 1, 1000)) == 0
    # one chunk: the later answers are written at once, the delayed one by its timer
    wire.send_raw(
        encode_frame(Command.RDMACRO, 100, MacroRequest(1).encode())
        + encode_frame(Command.RDCNCSTAT, 101)
        + encode_frame(Command.SYSINFO, 102)
    )
    first, second = await wire.recv_many(2)
    assert (first.request_id, second.request_id) == (101, 102)
    conn = next(iter(server.listener.connections))
    late = await wire.recv()
    assert (late.command, late.request_id) == (Command.RDMACRO, 100)
    assert MacroValue.decode(late.payload[2:]) == MacroValue(1, 8, 0, -1)
    assert conn.delayed_count == 0


async def test_delay_zero_and_count(wire: Wire) -> None:
    assert await wire.ew(Command.SIM_INJECT_FAULT, inject(DELAY, CONN, 3, 0)) == 0
    for rid in range(1, 6):
        wire.send(*STATUS, request_id=rid)
    frames = await wire.recv_many(5)
    assert sorted(f.request_id for f in frames) == [1, 2, 3, 4, 5]
    assert all(ew_of(f.command, f.payload) == 0 for f in frames)


async def test_forced_ew_and_counted_lists(wire: Wire) -> None:
    assert await wire.ew(Command.SIM_INJECT_FAULT, inject(ERROR, CONN, 3, EW.BUSY)) == 0
    assert await wire.call(*STATUS) == struct.pack("<h", -1)
    assert await wire.call(Command.RDALMHISTRY, AlarmHistoryRequest(10).encode()) == (
        struct.pack("<hh", -1, -1)
    )
    assert await wire.call(Command.RDALMMSG, struct.pack("<hh", -1, 32)) == (
        struct.pack("<hh", -1, -1)
    )
    # the count is used up: back to normal
    assert await wire.ew(*STATUS) == 0
    assert await wire.call(Command.RDALMHISTRY, AlarmHistoryRequest(10).encode()) == b"\x00\x00"


async def test_forced_ew_on_a_write_changes_nothing(wire: Wire) -> None:
    assert await wire.ew(Command.SIM_INJECT_FAULT, inject(ERROR, CONN, 1, EW.RESET)) == 0
    write = MacroValue(100, 8, 5, 0).encode()
    assert await wire.ew(Command.WRMACRO, write) == EW.RESET
    assert (await wire.request(Command.RDMACRO, MacroRequest(100))).vacant
    assert await wire.ew(Command.WRMACRO, write) == 0
    assert (await wire.request(Command.RDMACRO, MacroRequest(100))).mcr_val == 5


async def test_unknown_command_answer_is_faulted_too(wire: Wire) -> None:
    assert await wire.ew(Command.SIM_INJECT_FAULT, inject(ERROR, CONN, 1, EW.ALARM)) == 0
    assert await wire.call(0x0777) == struct.pack("<h", EW.ALARM)
    assert await wire.call(0x0777) == struct.pack("<h", EW.FUNC)


async def test_drop_closes_only_that_connection_without_running_it(server: Served) -> None:
    a = await server.connect()
    b = await server.connect()
    async with a, b:
        assert await a.ew(Command.SIM_INJECT_FAULT, inject(DROP, CONN, 1)) == 0
        a.send(Command.WRMACRO, MacroValue(101, 8, 9, 0).encode())
        a.send(*STATUS)  # after the dropped one: never answered
        assert await a.closed_by_peer()
        assert (await b.request(Command.RDMACRO, MacroRequest(101))).vacant
        assert await b.ew(*STATUS) == 0
    assert server.server.connection_count <= 1


async def test_drop_sends_the_answers_before_it(server: Served, wire: Wire) -> None:
    assert await wire.ew(Command.SIM_INJECT_FAULT, inject(DROP, CONN, 1)) == 0
    # one chunk: set_panel (control, never faulted), then status (dropped)
    wire.send_raw(
        encode_frame(Command.SIM_SET_PANEL, 1, SetPanel(0, 0, 0).encode())
        + encode_frame(Command.RDCNCSTAT, 2)
    )
    first = await wire.recv()
    assert (first.command, first.request_id, first.payload) == (Command.SIM_SET_PANEL, 1, b"\0\0")
    assert await wire.closed_by_peer()


class _RecordingTransport:
    """Wraps the server side transport of a connection and records each write."""

    def __init__(self, inner: Any) -> None:
        self.inner = inner
        self.writes: list[bytes] = []

    def write(self, data: bytes) -> None:
        self.writes.append(bytes(data))
        self.inner.write(data)

    def writelines(self, chunks: list[bytes]) -> None:
        self.writes.append(b"".join(chunks))
        self.inner.writelines(chunks)

    def __getattr__(self, name: str) -> Any:
        return getattr(self.inner, name)


async def test_split_sends_one_byte_per_write(server: Served, wire: Wire) -> None:
    assert await wire.ew(Command.SIM_INJECT_FAULT, inject(SPLIT, CONN, 1)) == 0
    conn = next(iter(server.listener.connections))
    recorder = _RecordingTransport(conn._transport)
    conn._transport = recorder  # type: ignore[assignment]
    rid = wire.send(Command.RDPARAM, DataRequest(1320, 1).encode())
    frame = await wire.recv()
    assert frame.request_id == rid and ew_of(frame.command, frame.payload) == 0
    expected = encode_frame(frame.command, frame.request_id, frame.payload)
    assert recorder.writes == [expected[i : i + 1] for i in range(len(expected))]
    # next answer: whole again
    recorder.writes.clear()
    await wire.call(*STATUS)
    assert len(recorder.writes) == 1


async def test_connection_scope_does_not_touch_other_connections(server: Served) -> None:
    a = await server.connect()
    b = await server.connect()
    async with a, b:
        assert await a.ew(Command.SIM_INJECT_FAULT, inject(ERROR, CONN, 1, EW.BUSY)) == 0
        assert await b.ew(*STATUS) == 0
        assert await a.ew(*STATUS) == EW.BUSY
        assert await a.ew(*STATUS) == 0


async def test_machine_scope_one_shared_count(server: Served) -> None:
    a = await server.connect()
    b = await server.connect()
    async with a, b:
        assert await a.ew(Command.SIM_INJECT_FAULT, inject(ERROR, MACHINE, 2, EW.BUSY)) == 0
        assert await b.ew(*STATUS) == EW.BUSY
        assert await a.ew(*STATUS) == EW.BUSY
        assert await b.ew(*STATUS) == 0
        assert await a.ew(*STATUS) == 0
    # a new connection sees machine faults armed before it connected
    async with await server.connect() as c:
        assert await c.ew(Command.SIM_INJECT_FAULT, inject(ERROR, MACHINE, 1, EW.STOP)) == 0
        async with await server.connect() as d:
            assert await d.ew(*STATUS) == EW.STOP
            assert await c.ew(*STATUS) == 0


async def test_machine_scope_drop_and_delay(server: Served) -> None:
    a = await server.connect()
    b = await server.connect()
    async with a, b:
        assert await a.ew(Command.SIM_INJECT_FAULT, inject(DELAY, MACHINE, 1, 100)) == 0
        assert await b.ew(*STATUS) == 0  # delayed, but the answer comes
        assert await a.ew(Command.SIM_INJECT_FAULT, inject(DROP, MACHINE, 1)) == 0
        b.send(*STATUS)
        assert await b.closed_by_peer()
        assert await a.ew(*STATUS) == 0


async def test_connection_fault_applies_before_machine_fault(server: Served, wire: Wire) -> None:
    assert await wire.ew(Command.SIM_INJECT_FAULT, inject(ERROR, MACHINE, 1, EW.ALARM)) == 0
    assert await wire.ew(Command.SIM_INJECT_FAULT, inject(ERROR, CONN, 1, EW.BUSY)) == 0
    assert await wire.ew(*STATUS) == EW.BUSY
    assert await wire.ew(*STATUS) == EW.ALARM
    assert await wire.ew(*STATUS) == 0


async def test_faults_armed_in_order(wire: Wire) -> None:
    assert await wire.ew(Command.SIM_INJECT_FAULT, inject(ERROR, CONN, 1, EW.BUSY)) == 0
    assert await wire.ew(Command.SIM_INJECT_FAULT, inject(ERROR, CONN, 2, EW.RESET)) == 0
    codes = [await wire.ew(*STATUS) for _ in range(4)]
    assert codes == [EW.BUSY, EW.RESET, EW.RESET, 0]


async def test_queue_full_is_ew_ovrflow(wire: Wire) -> None:
    for _ in range(MAX_ARMED_FAULTS):
        assert await wire.ew(Command.SIM_INJECT_FAULT, inject(ERROR, CONN, 1, EW.BUSY)) == 0
    assert await wire.ew(Command.SIM_INJECT_FAULT, inject(ERROR, CONN, 1, EW.BUSY)) == EW.OVRFLOW


@pytest.mark.parametrize(
    ("command", "payload"),
    [
        (Command.SIM_SET_PANEL, SetPanel(1, 0, 0).encode()),
        (Command.SIM_CLEAR_ALARMS, struct.pack("<hh", -1, -1)),
        (Command.SIM_SET_PMC, struct.pack("<hhHH", 5, 0, 0, 0) + b"\x01"),
        (Command.SIM_RAISE_ALARM, struct.pack("<hhhh", 0, 3, 1, 1) + b"A"),
        (Command.SIM_INJECT_FAULT, inject(ERROR, CONN, 1, EW.ALARM)),
    ],
)
async def test_control_answers_never_faulted_and_never_count(
    wire: Wire, command: Command, payload: bytes
) -> None:
    assert await wire.ew(Command.SIM_INJECT_FAULT, inject(ERROR, CONN, 1, EW.BUSY)) == 0
    assert await wire.ew(Command.SIM_INJECT_FAULT, inject(DROP, MACHINE, 1)) == 0
    assert await wire.ew(command, payload) == 0
    assert await wire.ew(*STATUS) == EW.BUSY  # the connection fault, not yet used
    if command == Command.SIM_INJECT_FAULT:
        assert await wire.ew(*STATUS) == EW.ALARM
    wire.send(*STATUS)  # now the machine-wide drop
    assert await wire.closed_by_peer()


async def test_delayed_answers_still_go_out_after_the_peer_stops_sending(
    server: Served,
) -> None:
    # EOF may be a half-close: the peer can still read, so held answers are sent when due,
    # then the connection closes by itself.
    a = await server.connect()
    assert await a.ew(Command.SIM_INJECT_FAULT, inject(DELAY, CONN, 5, 300)) == 0
    for rid in range(5):
        a.send(*STATUS, request_id=rid)
    await a.writer.drain()
    conn = next(iter(server.listener.connections))
    await wait_until(lambda: conn.delayed_count == 5)
    await a.close()
    await wait_until(lambda: server.server.connection_count == 0)
    assert conn.delayed_count == 0


async def test_no_control_answers_ew_func() -> None:
    async with serving(default_machine(control_enabled=False)) as served:
        async with await served.connect() as w:
            for command, payload in [
                (Command.SIM_SET_PANEL, SetPanel(0, 1, 0).encode()),
                (Command.SIM_RAISE_ALARM, struct.pack("<hhhh", 0, 3, 1, 1) + b"A"),
                (Command.SIM_CLEAR_ALARMS, struct.pack("<hh", -1, -1)),
                (Command.SIM_SET_PMC, struct.pack("<hhHH", 5, 0, 0, 0) + b"\x01"),
                (Command.SIM_INJECT_FAULT, inject(ERROR, CONN, 1, EW.BUSY)),
                (Command.SIM_INJECT_FAULT, b"short"),  # before the payload is looked at
            ]:
                assert await w.ew(command, payload) == EW.FUNC
            assert await w.ew(*STATUS) == 0
            assert (await w.request(Command.RDCNCSTAT)).aut == 1


async def test_read_only_answers_ew_prot_for_every_write() -> None:
    async with serving(default_machine(read_only=True)) as served:
        async with await served.connect() as w:
            for command, payload in [
                (Command.WRPARAM, struct.pack("<hhh", 3216, 0, 5)),
                (Command.WRMACRO, MacroValue(100, 8, 1, 0).encode()),
                (Command.WRPMCRNG, struct.pack("<hhHH", 5, 0, 0, 0) + b"\x01"),
                (Command.SIM_SET_PANEL, SetPanel(0, 1, 0).encode()),
                (Command.SIM_RAISE_ALARM, struct.pack("<hhhh", 0, 3, 1, 1) + b"A"),
                (Command.SIM_CLEAR_ALARMS, struct.pack("<hh", -1, -1)),
                (Command.SIM_SET_PMC, struct.pack("<hhHH", 5, 0, 0, 0) + b"\x01"),
                (Command.SIM_INJECT_FAULT, inject(ERROR, CONN, 1, EW.BUSY)),
                (Command.SIM_INJECT_FAULT, inject(0, 0, 0)),  # EW_PROT before EW_DATA
            ]:
                assert await w.ew(command, payload) == EW.PROT, hex(command)
            # size is still checked first, and reads work
            assert await w.ew(Command.SIM_INJECT_FAULT, b"\x00" * 3) == EW.LENGTH
            assert await w.ew(*STATUS) == 0
            assert (await w.request(Command.RDMACRO, MacroRequest(100))).vacant
            assert await w.ew(Command.RDPARAM, DataRequest(3216, 0).encode()) == 0


@pytest.mark.parametrize(
    ("kind", "scope", "count", "arg", "reason"),
    [
        (9, 0, 1, 0, "no fault kind 9 (one of 1 DELAY, 2 ERROR, 3 DROP, 4 SPLIT)"),
        (1, 2, 1, 0, "no fault scope 2 (one of 0 CONNECTION, 1 MACHINE)"),
        (3, 0, 0, 0, "a fault's count is 1..10000, got 0"),
        (1, 1, 1, 60_001, "a delay is 0..60000 ms, got 60001"),
        (2, 0, 1, 0, "an error fault's EW code is a nonzero -32768..32767, got 0"),
        (2, 0, 1, 40_000, "an error fault's EW code is a nonzero -32768..32767, got 40000"),
        (1, 1, 10_000, 60_000, None),
        (3, 0, 1, -5, None),  # a drop ignores its arg
    ],
)
def test_one_function_gives_the_reason_and_parse_inject_follows_it(
    kind: int, scope: int, count: int, arg: int, reason: str | None
) -> None:
    assert fault_refusal(kind, scope, count, arg) == reason
    parsed = parse_inject(inject(kind, scope, count, arg))
    assert (parsed == EW.DATA) is (reason is not None)
