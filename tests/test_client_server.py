"""FocasClient against the real server (127.0.0.1, ephemeral port)."""

from __future__ import annotations

import asyncio
import inspect
import random
import ssl
import sys
from collections.abc import AsyncIterator
from decimal import Decimal
from pathlib import Path

import pytest
from support import IO_TIMEOUT, Served, serving, wait_until

from focas_net.client import ClientState, FocasClient, Positions, ReconnectPolicy
from focas_net.errors import (
    EW,
    AccessDeniedError,
    ChunkedWriteError,
    CncError,
    FocasConnectionError,
    FocasTimeoutError,
)
from focas_net.protocol import (
    FaultKind,
    FaultScope,
    PmcArea,
    PositionKind,
    ProgramNumbers,
    StatusInfo,
    SysInfo,
)
from focas_net.server import FocasServer
from focas_net.sim import Machine, default_machine
from focas_net.versamax import BoardId, IOModuleRecord, RefType

MDI, MEM = 0, 1
LONG = 30.0  # per-call timeout for calls that queue behind many others


@pytest.fixture
async def cnc(server: Served) -> AsyncIterator[FocasClient]:
    async with FocasClient(server.host, server.port, timeout=IO_TIMEOUT) as client:
        yield client


async def test_status_and_sysinfo(cnc: FocasClient) -> None:
    status = await cnc.read_status()
    assert isinstance(status, StatusInfo)
    assert status.aut == MEM and status.alarm == 0 and status.emergency == 0
    info = await cnc.read_sysinfo()
    assert isinstance(info, SysInfo)
    assert info.axes == b"03" and info.axes_count == 3


async def test_params_diag_and_width_learning(cnc: FocasClient) -> None:
    assert await cnc.read_param(1420, axis=1) == 24000
    assert (await cnc.read_param_value(3216)).width == 2
    assert isinstance(await cnc.read_diag(300, axis=1), int)
    with pytest.raises(CncError) as info:
        await cnc.read_param(1420)  # an axis item read without an axis
    assert info.value.ew == EW.ATTRIB
    with pytest.raises(AccessDeniedError):  # PWE off, mode MEM: the write gate is closed
        await cnc.write_param(6711, 5, width=4)
    await cnc.sim.set_panel(MDI, pwe=True)
    await cnc.write_param(6711, 1234)  # the width (4) learnt by one read
    assert await cnc.read_param(6711) == 1234
    await cnc.write_param(3216, 7)  # the width (2) kept from the read above
    assert await cnc.read_param(3216) == 7
    await cnc.write_param(20, 3, width=1)
    assert await cnc.read_param(20) == 3
    with pytest.raises(CncError) as info:
        await cnc.write_param(3216, 7, width=4)
    assert info.value.ew == EW.LENGTH
    with pytest.raises(ValueError):
        await cnc.write_param(20, 1000, width=1)  # does not fit a byte: never sent


async def test_write_param_bit(cnc: FocasClient) -> None:
    await cnc.sim.set_panel(MDI, pwe=True)
    before = await cnc.read_param(1815, axis=2)
    await cnc.write_param_bit(1815, 0, True, axis=2)
    await cnc.write_param_bit(1815, 7, True, axis=2)
    await cnc.write_param_bit(1815, 4, False, axis=2)
    after = await cnc.read_param(1815, axis=2) & 0xFF
    assert after == ((before & 0xFF) | 0x81) & ~0x10
    assert await cnc.read_param(1815, axis=1) == before  # other axis untouched
    bits = [random.Random(7).random() < 0.5 for _ in range(8)]
    await asyncio.gather(
        *(cnc.write_param_bit(1815, i % 8, bits[i % 8], axis=3, timeout=LONG) for i in range(200))
    )
    expected = sum(1 << i for i, b in enumerate(bits) if b)
    assert await cnc.read_param(1815, axis=3) & 0xFF == expected
    assert cnc.bit_locks == 0
    with pytest.raises(ValueError):
        await cnc.write_param_bit(1815, 8, True, axis=1)


async def test_macros(cnc: FocasClient) -> None:
    assert await cnc.read_macro(100) is None
    await cnc.write_macro(100, Decimal("1.50"))
    assert await cnc.read_macro(100) == Decimal("1.50")
    await cnc.write_macro(101, -42)
    assert await cnc.read_macro(101) == Decimal(-42)
    await cnc.write_macro(102, 0.1)
    assert await cnc.read_macro(102) == Decimal("0.1")
    await cnc.write_macro(103, "-3.14159265")
    assert await cnc.read_macro(103) == Decimal("-3.14159265")
    with pytest.raises(ValueError):
        await cnc.write_macro(104, 1e20)
    with pytest.raises(ValueError):
        await cnc.write_macro(104, "0.0000000001")
    assert await cnc.read_macro(104) is None  # nothing was sent
    with pytest.raises(CncError) as info:
        await cnc.read_macro(5000)
    assert info.value.ew == EW.NUMBER


async def test_pmc_bytes_and_bits(cnc: FocasClient) -> None:
    await cnc.write_pmc("R", 10, b"\x01\x02\x03")
    assert await cnc.read_pmc(PmcArea.R, 10, 3) == b"\x01\x02\x03"
    await cnc.write_pmc_bit("R", 10, 7, True)
    assert await cnc.read_pmc_bit("R", 10, 7) is True
    assert await cnc.read_pmc("R", 10, 1) == b"\x81"
    await cnc.write_pmc_bit("r", 10, 0, False)
    assert await cnc.read_pmc("R", 10, 1) == b"\x80"
    with pytest.raises(CncError) as info:
        await cnc.write_pmc("X", 0, b"\x01")  # X is write-protected for pmc_wrpmcrng
    assert info.value.ew == EW.PROT
    await cnc.sim.set_pmc("X", 0, b"\x5a")
    assert await cnc.read_pmc("X", 0, 1) == b"\x5a"
    with pytest.raises(CncError) as info:
        await cnc.read_pmc("E", 0, 1)
    assert info.value.ew == EW.NOOPT
    with pytest.raises(ValueError):
        await cnc.read_pmc("Q", 0, 1)
    with pytest.raises(ValueError):
        await cnc.read_pmc("R", 0, 0)


async def test_chunked_read_equals_data_written(cnc: FocasClient) -> None:
    data = random.Random(1).randbytes(4096)
    await cnc.write_pmc("D", 0, data)
    assert await cnc.read_pmc("D", 0, 4096) == data
    assert await cnc.read_pmc("D", 1000, 77) == data[1000:1077]
    big = random.Random(2).randbytes(5000)
    await cnc.sim.set_pmc("F", 0, big[:768])
    assert await cnc.read_pmc("F", 0, 768) == big[:768]


async def test_chunked_write_crossing_the_end_of_an_area(cnc: FocasClient) -> None:
    data = bytes(range(1, 95))  # D9950..D10043; D ends at 9999
    with pytest.raises(ChunkedWriteError) as info:
        await cnc.write_pmc("D", 9950, data)
    err = info.value
    assert err.area == "D"
    assert err.written == [(9950, 9981)]
    assert err.not_written == [(9982, 10043)]
    assert isinstance(err.cause, CncError) and err.cause.ew == EW.NUMBER
    assert await cnc.read_pmc("D", 9950, 32) == data[:32]
    assert await cnc.read_pmc("D", 9982, 18) == bytes(18)


async def test_chunked_write_with_injected_error(cnc: FocasClient) -> None:
    await cnc.sim.inject_fault(FaultKind.ERROR, arg=EW.BUSY, count=1)
    with pytest.raises(ChunkedWriteError) as info:
        await cnc.write_pmc("R", 0, bytes(range(96)))
    err = info.value
    assert isinstance(err.cause, CncError) and err.cause.ew == EW.BUSY
    assert len(err.not_written) == 1
    first, last = err.not_written[0]
    assert last - first + 1 == 32
    # every range reported written holds the new bytes
    for a, b in err.written:
        assert await cnc.read_pmc("R", a, b - a + 1) == bytes(range(a, b + 1))


async def test_injected_ew_surfaces_as_cnc_error(cnc: FocasClient) -> None:
    await cnc.sim.inject_fault(FaultKind.ERROR, arg=EW.BUSY, count=2)
    with pytest.raises(CncError) as info:
        await cnc.read_status()
    assert info.value.ew == EW.BUSY
    with pytest.raises(CncError) as info:
        await cnc.read_alarms()  # a counted list answers count = -1, EW_BUSY
    assert info.value.ew == EW.BUSY
    assert (await cnc.read_status()).aut == MEM


async def test_late_answers_dropped_next_calls_correct(cnc: FocasClient) -> None:
    await cnc.sim.inject_fault(FaultKind.DELAY, arg=300, count=1)
    with pytest.raises(FocasTimeoutError):
        await cnc.read_param(1420, axis=1, timeout=0.05)
    results = await asyncio.gather(*(cnc.read_param(1420, axis=a) for a in (1, 2, 3)))
    assert results == [24000, 24000, 24000]
    assert await cnc.read_param(3216) == 10
    conn = cnc.connection
    assert conn is not None
    await wait_until(lambda: conn.abandoned == 0)  # the late answer arrived and was dropped
    assert await cnc.read_param(6711) == 0


async def test_answers_split_one_byte_per_write(cnc: FocasClient) -> None:
    await cnc.sim.inject_fault(FaultKind.SPLIT, count=20)
    values = await asyncio.gather(*(cnc.read_param(1420, axis=1) for _ in range(20)))
    assert values == [24000] * 20


async def test_alarms_and_history(cnc: FocasClient) -> None:
    assert await cnc.read_alarms() == ()
    await cnc.sim.raise_alarm(3, 10, "PS0010 TEST")
    await cnc.sim.raise_alarm(6, 401, "SV0401", axis_no=2)
    active = await cnc.read_alarms()
    assert [(a.axis_no, a.alm_type, a.alm_no, a.msg) for a in active] == [
        (0, 3, 10, "PS0010 TEST"),
        (2, 6, 401, "SV0401"),
    ]
    assert [a.alm_no for a in await cnc.read_alarms(alm_type=6)] == [401]
    assert (await cnc.read_status()).alarm == 1
    history = await cnc.read_alarm_history(10)
    assert history.ew == 0
    assert [e.alm_no for e in history.entries] == [401, 10]  # newest first
    for depth in (0, -5):
        with pytest.raises(ValueError, match=rf"history depth {depth} is below 1 \("):
            await cnc.read_alarm_history(depth)
    assert len((await cnc.read_alarm_history(1)).entries) == 1
    assert len((await cnc.read_alarm_history(10_000)).entries) == 2  # clamped to 250
    await cnc.sim.clear_alarms(3)
    assert [a.alm_no for a in await cnc.read_alarms()] == [401]
    await cnc.sim.clear_alarms()
    assert await cnc.read_alarms() == ()
    assert len((await cnc.read_alarm_history(250)).entries) == 2


async def test_history_error_answer_raises_like_the_active_list(cnc: FocasClient) -> None:
    """An error answer (count -1, then the code) raises CncError for the history as for the
    active list; it is never returned as an empty history."""
    await cnc.sim.raise_alarm(3, 11)
    for read in (cnc.read_alarm_history, cnc.read_alarms):
        await cnc.sim.inject_fault(FaultKind.ERROR, arg=EW.BUSY, count=1)
        with pytest.raises(CncError) as info:
            await read()
        assert info.value.ew == EW.BUSY
    await cnc.sim.inject_fault(FaultKind.ERROR, arg=EW.PASSWD, count=1)
    with pytest.raises(AccessDeniedError):
        await cnc.read_alarm_history(5)
    history = await cnc.read_alarm_history(5)
    assert history.ew == 0 and [e.alm_no for e in history.entries] == [11]


async def test_module_config(cnc: FocasClient) -> None:
    record = await cnc.read_module_config(0, 3)
    assert isinstance(record, IOModuleRecord)
    assert record.label == "D844"
    assert record.inputs == 16 and record.outputs == 16
    assert len(await cnc.read_config_record(0, 3)) == 76
    with pytest.raises(CncError) as info:
        await cnc.read_module_config(0, 9)
    assert info.value.ew == EW.NUMBER


@pytest.mark.parametrize("module_bytes", [202, 300])  # records of 256 and 354 bytes
async def test_module_config_longer_than_128_bytes(module_bytes: int) -> None:
    big = IOModuleRecord.build(
        BoardId(0x8011),
        BoardId(0x8011),
        "BIG1",
        [(RefType.I, 0, 2)],
        module_data=bytes(i % 251 for i in range(module_bytes - 8)),
    )
    machine = Machine("big", station={(0, 5): big})
    async with (
        serving(machine) as served,
        FocasClient(served.host, served.port, timeout=IO_TIMEOUT) as cnc,
    ):
        raw = await cnc.read_config_record(0, 5)
        assert raw == big.encode() and len(raw) > 128
        assert await cnc.read_module_config(0, 5) == big


async def test_unlock_and_password_retry() -> None:
    machine = default_machine(param_password="1234")
    async with (
        serving(machine) as served,
        FocasClient(served.host, served.port, timeout=IO_TIMEOUT, password="1234") as cnc,
    ):
        await cnc.sim.set_panel(MDI, pwe=True)
        await cnc.write_param(6712, 9, width=4)
        with pytest.raises(AccessDeniedError):
            await cnc.unlock("nope")  # a failed unlock locks this connection again
        await cnc.write_param(6712, 10, width=4)  # EW_PASSWD -> unlock with 1234, retry once
        assert await cnc.read_param(6712) == 10
    async with (
        serving(default_machine(param_password="1234")) as served,
        FocasClient(served.host, served.port, timeout=IO_TIMEOUT) as cnc,
    ):
        await cnc.sim.set_panel(MDI, pwe=True)
        with pytest.raises(AccessDeniedError):
            await cnc.write_param(6712, 9, width=4)
        await cnc.unlock("1234")
        await cnc.write_param(6712, 9, width=4)
        assert await cnc.read_param(6712) == 9
    with pytest.raises(AccessDeniedError):
        async with (
            serving(default_machine(param_password="1234")) as served,
            FocasClient(served.host, served.port, password="0000") as cnc,
        ):
            pass


@pytest.mark.parametrize("spread", [1, 100])
async def test_thousand_concurrent_bit_writes(cnc: FocasClient, spread: int) -> None:
    rng = random.Random(spread)
    target = rng.randbytes(spread)
    await cnc.write_pmc("R", 500, bytes(b ^ 0xFF for b in target))  # every bit must change
    writes = [(i % spread, (i // spread) % 8) for i in range(1000)]
    rng.shuffle(writes)
    await asyncio.gather(
        *(
            cnc.write_pmc_bit("R", 500 + byte, bit, bool(target[byte] >> bit & 1), timeout=LONG)
            for byte, bit in writes
        )
    )
    assert await cnc.read_pmc("R", 500, spread) == target
    assert cnc.bit_locks == 0


async def test_cancellation_storm_never_crosses_answers(cnc: FocasClient) -> None:
    values = bytes(i % 256 for i in range(2000))
    await cnc.write_pmc("D", 0, values)
    rng = random.Random(3)
    calls = [rng.randrange(2000) for _ in range(10_000)]
    tasks = [asyncio.create_task(cnc.read_pmc("D", n, 1, timeout=60)) for n in calls]
    for _ in range(20):
        await asyncio.sleep(0)
    for task in rng.sample(tasks, 5000):
        task.cancel()
    results = await asyncio.gather(*tasks, return_exceptions=True)
    completed = 0
    for n, result in zip(calls, results, strict=True):
        if isinstance(result, BaseException):
            assert isinstance(result, asyncio.CancelledError)
        else:
            completed += 1
            assert result == values[n : n + 1]
    assert completed >= 5000
    assert await cnc.read_pmc("D", 10, 4) == values[10:14]
    conn = cnc.connection
    assert conn is not None and conn.in_flight == 0


async def test_drop_during_chunked_write_then_reconnect() -> None:
    policy = ReconnectPolicy(initial_delay=0.01, max_delay=0.05)
    async with (
        serving() as served,
        FocasClient(served.host, served.port, timeout=IO_TIMEOUT, reconnect=policy) as cnc,
    ):
        await cnc.sim.inject_fault(FaultKind.DROP, count=1)
        with pytest.raises(ChunkedWriteError) as info:
            await cnc.write_pmc("R", 0, bytes(range(128)))
        err = info.value
        assert isinstance(err.cause, FocasConnectionError)
        spans = sorted(err.written + err.not_written + err.uncertain)
        assert spans[0][0] == 0 and spans[-1][1] == 127
        # the dropped chunk was sent and never answered: it is unconfirmed, not "not written"
        assert err.uncertain
        assert await cnc.read_pmc("R", 0, 4, timeout=IO_TIMEOUT) is not None
        await cnc.write_pmc("R", 0, bytes(range(128)))
        assert await cnc.read_pmc("R", 0, 128) == bytes(range(128))


async def test_pending_calls_fail_fast_when_the_connection_drops(cnc: FocasClient) -> None:
    await cnc.sim.inject_fault(FaultKind.DELAY, arg=60_000, count=1)
    await cnc.sim.inject_fault(FaultKind.DROP, count=1)
    slow = asyncio.create_task(cnc.read_status(timeout=60))
    await asyncio.sleep(0.05)
    with pytest.raises(FocasConnectionError):
        await cnc.read_sysinfo(timeout=60)
    with pytest.raises(FocasConnectionError):  # fails at once, not after 60 s
        async with asyncio.timeout(IO_TIMEOUT):
            await slow
    assert cnc.state is ClientState.DISCONNECTED


async def test_reconnect_after_server_restart() -> None:
    machine = default_machine(param_password="1234")
    states: list[ClientState] = []
    policy = ReconnectPolicy(initial_delay=0.01, max_delay=0.1)
    async with serving(machine, grace_period=0.1) as served:
        port = served.port
        cnc = FocasClient("127.0.0.1", port, timeout=IO_TIMEOUT, reconnect=policy, password="1234")
        cnc.add_state_callback(states.append)
        await cnc.connect()
        await cnc.sim.set_panel(MDI, pwe=True)
        assert (await cnc.read_status()).aut == MDI
    try:
        with pytest.raises(FocasConnectionError):  # still reconnecting when the call times out
            await cnc.read_status(timeout=0.2)
        assert cnc.state is ClientState.RECONNECTING
        async with FocasServer(machine, host="127.0.0.1", port=port, grace_period=0.1):
            assert (await cnc.read_status(timeout=IO_TIMEOUT)).aut == MDI
            await cnc.write_param(6711, 77, width=4)  # unlocked again after the reconnect
            assert await cnc.read_param(6711) == 77
            assert cnc.connected
        assert ClientState.RECONNECTING in states
    finally:
        await cnc.aclose()
    assert states[-1] is ClientState.CLOSED and not cnc.connected


async def test_machine_scope_fault_on_second_client(server: Served) -> None:
    async with (
        FocasClient(server.host, server.port, timeout=IO_TIMEOUT) as a,
        FocasClient(server.host, server.port, timeout=IO_TIMEOUT) as b,
    ):
        await a.sim.inject_fault(FaultKind.ERROR, arg=EW.BUSY, count=1, scope=FaultScope.MACHINE)
        with pytest.raises(CncError) as info:
            await b.read_status()
        assert info.value.ew == EW.BUSY
        assert (await a.read_status()).aut == MEM


async def test_tls(certificate: tuple[Path, Path]) -> None:
    cert, key = certificate
    server_ctx = ssl.SSLContext(ssl.PROTOCOL_TLS_SERVER)
    server_ctx.load_cert_chain(cert, key)
    trusted = ssl.create_default_context(cafile=str(cert))
    async with serving(ssl=server_ctx) as served:
        async with FocasClient(served.host, served.port, timeout=IO_TIMEOUT, ssl=trusted) as cnc:
            assert (await cnc.read_status()).aut == MEM
            data = random.Random(5).randbytes(300)
            await cnc.write_pmc("D", 0, data)
            assert await cnc.read_pmc("D", 0, 300) == data
        untrusted = ssl.create_default_context()  # does not know the self-signed certificate
        with pytest.raises(FocasConnectionError):
            await FocasClient(served.host, served.port, timeout=IO_TIMEOUT, ssl=untrusted).connect()


async def test_program_numbers_feed_and_spindle(server: Served, cnc: FocasClient) -> None:
    assert await cnc.read_program_numbers() == ProgramNumbers(1, 1)
    assert await cnc.read_feed() == 0
    assert await cnc.read_spindle_speed() == 0
    server.machine.set_motion(
        feed=1500, spindle_speed=3000, program_running=1234, program_main=1000
    )
    numbers = await cnc.read_program_numbers()
    assert (numbers.running, numbers.main) == (1234, 1000)
    assert await cnc.read_feed() == 1500
    assert await cnc.read_spindle_speed() == 3000


async def test_read_positions(server: Served, cnc: FocasClient) -> None:
    server.machine.set_motion(
        absolute=[12345, -2, 100_000], machine=[1, 2, 3], distance_to_go=[0, 0, -500]
    )
    pos = await cnc.read_positions()
    assert pos == Positions(
        PositionKind.ABSOLUTE,
        3,
        {"X": Decimal("12.345"), "Y": Decimal("-0.002"), "Z": Decimal("100.000")},
        {"X": 12345, "Y": -2, "Z": 100_000},
    )
    assert list(pos.values) == ["X", "Y", "Z"]
    assert str(pos.values["Z"]) == "100.000"
    machine = await cnc.read_positions("machine", axis=2)
    assert machine.kind is PositionKind.MACHINE
    assert machine.values == {"Y": Decimal("0.002")}
    dist = await cnc.read_positions(PositionKind.DISTANCE, axis=3)
    assert dist.values == {"Z": Decimal("-0.500")} and dist.increments == {"Z": -500}
    relative = await cnc.read_positions(2)
    assert relative.values == {"X": Decimal("0.000"), "Y": Decimal("0.000"), "Z": Decimal("0.000")}


async def test_read_positions_errors(cnc: FocasClient) -> None:
    with pytest.raises(CncError) as info:
        await cnc.read_positions(axis=4)  # the machine has 3 axes
    assert info.value.ew == EW.ATTRIB
    with pytest.raises(ValueError):
        await cnc.read_positions("skip")  # never sent
    with pytest.raises(ValueError):
        await cnc.read_positions(axis=0)
    with pytest.raises(ValueError):
        await cnc.read_positions(axis=-1)
    # the connection is still usable
    assert (await cnc.read_positions(axis=1)).increments == {"X": 0}


async def test_motion_reads_surface_injected_errors(cnc: FocasClient) -> None:
    await cnc.sim.inject_fault(FaultKind.ERROR, arg=EW.BUSY, count=4, scope=FaultScope.CONNECTION)
    for read in (cnc.read_program_numbers, cnc.read_feed, cnc.read_spindle_speed):
        with pytest.raises(CncError) as info:
            await read()
        assert info.value.ew == EW.BUSY
    with pytest.raises(CncError) as info:
        await cnc.read_positions()
    assert info.value.ew == EW.BUSY
    assert await cnc.read_feed() == 0


PLAIN_READS = ("read_status", "read_sysinfo", "read_program_numbers", "read_run_info", "read_loads")


@pytest.mark.parametrize("name", PLAIN_READS)
async def test_plain_reads_are_awaited_scheduled_and_gathered_as_coroutines(
    cnc: FocasClient, name: str
) -> None:
    # These reads are plain methods returning the request's coroutine: a call sends nothing
    # until it is awaited or scheduled, as an ``async def`` would.
    conn = cnc.connection
    assert conn is not None
    method = getattr(cnc, name)
    pending = method()
    assert asyncio.iscoroutine(pending)
    await asyncio.sleep(0)
    assert conn.in_flight == 0
    awaited = await pending
    scheduled = await asyncio.create_task(method(timeout=LONG))
    gathered = await asyncio.gather(method(), method(timeout=LONG))
    assert {type(awaited), type(scheduled), type(gathered[0]), type(gathered[1])} == {type(awaited)}
    if name != "read_run_info":  # (its timers move between two reads)
        assert awaited == scheduled == gathered[0] == gathered[1]
    method().close()  # dropped unawaited: never sent, nothing left behind
    assert conn.in_flight == 0 and cnc.connected
    assert inspect.iscoroutinefunction(method) is (sys.version_info >= (3, 12))
