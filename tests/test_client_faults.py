"""The client under the server's fault injection (0x0E05) and under server crashes.

Every test talks to a real server on 127.0.0.1 (port 0): in this process, or, where a crash is
needed, the ``focas-net serve`` command in a child process that is killed. Properties:

* an answer delayed past the call's timeout raises :class:`FocasTimeoutError`; the late answer
  is dropped and every later call gets its own answer;
* forced EW codes surface as :class:`CncError` carrying that code, and change nothing;
* a connection dropped in the middle of a chunked PMC write raises :class:`ChunkedWriteError`
  naming exactly the ranges written and not written; with reconnect on, the next calls work;
* answers sent one byte per write decode the same;
* a server that dies fails the calls in flight at once; after a restart on the same port the
  client reconnects and an :class:`AlarmProjection` goes on without duplicate events;
* 10,000 calls in flight with half of them cancelled: nobody receives another call's answer,
  and no pending entry, lock or task is left behind.
"""

from __future__ import annotations

import asyncio
import contextlib
import random
import signal
import struct
import subprocess
import sys
from collections.abc import AsyncIterator, Awaitable, Callable, Iterator
from decimal import Decimal
from typing import Any, Final

import pytest
from support import IO_TIMEOUT, Served, serving, wait_until

from focas_net.client import (
    AlarmHistoryEvent,
    AlarmProjection,
    AlarmRaised,
    ClientState,
    FocasClient,
    ProjectionMode,
    ReconnectPolicy,
)
from focas_net.errors import (
    EW,
    AccessDeniedError,
    ChunkedWriteError,
    CncError,
    FocasConnectionError,
    FocasTimeoutError,
)
from focas_net.protocol import FaultKind
from focas_net.server import FocasServer
from focas_net.sim import default_machine

FAST_RECONNECT: Final = ReconnectPolicy(initial_delay=0.02, max_delay=0.2, jitter=0.0)


@contextlib.asynccontextmanager
async def client_of(served: Served, **kwargs: Any) -> AsyncIterator[FocasClient]:
    kwargs.setdefault("timeout", IO_TIMEOUT)
    async with FocasClient(served.host, served.port, **kwargs) as cnc:
        yield cnc


def client_leftovers(cnc: FocasClient) -> tuple[int, int, int]:
    """``(in flight, abandoned ids, bit locks)`` of ``cnc``: all 0 when nothing is left
    behind (no connection: nothing in flight, no id reserved)."""
    conn = cnc.connection
    abandoned = conn.abandoned if conn is not None else 0
    return cnc.in_flight, abandoned, cnc.bit_locks


# -- delays past the timeout -------------------------------------------------------------------


async def test_answers_delayed_past_the_timeout_are_dropped() -> None:
    async with serving() as served, client_of(served) as cnc:
        for number in range(1, 11):
            await cnc.write_macro(number, number * 11)
        await cnc.sim.inject_fault(FaultKind.DELAY, count=5, arg=300)
        late = [cnc.read_macro(n, timeout=0.1) for n in range(1, 6)]
        results = await asyncio.gather(*late, return_exceptions=True)
        assert all(isinstance(r, FocasTimeoutError) for r in results), results
        conn = next(iter(served.listener.connections))
        assert conn.delayed_count == 5  # the late answers are still to come
        # calls made while the late answers arrive each get their own answer
        for i in range(200):  # bounded; ends once every late answer has been sent
            number = 1 + i % 10
            assert await cnc.read_macro(number) == Decimal(number * 11)
            if conn.delayed_count == 0 and i >= 10:
                break
            await asyncio.sleep(0.01)
        assert conn.delayed_count == 0
        for number in range(1, 11):
            assert await cnc.read_macro(number) == Decimal(number * 11)
        await wait_until(lambda: client_leftovers(cnc) == (0, 0, 0))


# -- forced EW codes ---------------------------------------------------------------------------

FORCED: Final = [EW.BUSY, EW.RESET, EW.HANDLE, EW.NUMBER, EW.PROT, EW.ALARM, EW.PASSWD, 999]


@pytest.mark.parametrize("code", FORCED, ids=lambda c: f"ew{int(c)}")
async def test_injected_codes_surface_as_cnc_error(code: int) -> None:
    async with serving() as served, client_of(served) as cnc:
        await cnc.write_macro(100, 7)
        before = served.machine.state_digest()
        calls: list[Callable[[], Awaitable[object]]] = [
            lambda: cnc.read_param(1320, axis=1),
            lambda: cnc.read_macro(100),
            lambda: cnc.write_macro(100, 8),
            lambda: cnc.write_pmc("R", 10, b"\x55"),
            lambda: cnc.read_pmc("R", 0, 4),
            lambda: cnc.read_status(),
            lambda: cnc.read_alarms(),
            lambda: cnc.read_alarm_history(),
        ]
        for call in calls:
            await cnc.sim.inject_fault(FaultKind.ERROR, count=1, arg=int(code))
            with pytest.raises(CncError) as caught:
                await call()
            assert caught.value.ew == code
            if code == EW.PASSWD:
                assert isinstance(caught.value, AccessDeniedError)
        assert served.machine.state_digest() == before  # forced errors ran nothing
        # the next calls are answered normally
        assert await cnc.read_macro(100) == Decimal(7)
        await cnc.write_macro(100, 8)
        assert await cnc.read_macro(100) == Decimal(8)


async def test_busy_on_every_connection_of_the_machine() -> None:
    """A machine-wide fault (scope 1) reaches a second client; its count is shared."""
    async with serving() as served, client_of(served) as a, client_of(served) as b:
        await a.sim.inject_fault(FaultKind.ERROR, count=2, arg=int(EW.BUSY), scope=1)
        with pytest.raises(CncError) as first:
            await b.read_status()
        with pytest.raises(CncError) as second:
            await a.read_status()
        assert first.value.ew == second.value.ew == EW.BUSY
        await a.read_status()
        await b.read_status()


def merged(spans: list[tuple[int, int]]) -> list[tuple[int, int]]:
    """Sorted inclusive ranges, touching ones merged."""
    out: list[tuple[int, int]] = []
    for first, last in sorted(spans):
        if out and out[-1][1] + 1 >= first:
            out[-1] = (out[-1][0], max(out[-1][1], last))
        else:
            out.append((first, last))
    return out


# -- a connection dropped in the middle of a chunked write ---------------------------------------


async def test_drop_in_the_middle_of_a_chunked_pmc_write() -> None:
    async with (
        serving() as served,
        client_of(served, reconnect=FAST_RECONNECT) as cnc,
    ):
        old = bytes(range(128))
        await cnc.write_pmc("R", 0, old)
        new = bytes(255 - b for b in range(128))
        # the first two chunks are answered (one byte per write), the third one drops
        await cnc.sim.inject_fault(FaultKind.SPLIT, count=2)
        await cnc.sim.inject_fault(FaultKind.DROP, count=1)
        with pytest.raises(ChunkedWriteError) as caught:
            await cnc.write_pmc("R", 0, new)
        err = caught.value
        assert err.area == "R"
        assert err.written == [(0, 63)]
        # R64..R127 were sent (or not) without an answer: not written, or unconfirmed
        assert merged(err.not_written + err.uncertain) == [(64, 127)]
        assert isinstance(err.cause, FocasConnectionError)
        assert "R0..R63" in str(err)
        # reconnected: the next calls succeed, and the bytes are exactly as the error says
        assert await cnc.read_pmc("R", 0, 128) == new[:64] + old[64:]
        assert cnc.state is ClientState.CONNECTED
        await cnc.write_pmc("R", 64, new[64:])
        assert await cnc.read_pmc("R", 0, 128) == new


async def test_error_answer_in_the_middle_of_a_chunked_write_names_the_chunk() -> None:
    async with serving() as served, client_of(served) as cnc:
        await cnc.sim.inject_fault(FaultKind.SPLIT, count=1)
        await cnc.sim.inject_fault(FaultKind.ERROR, count=1, arg=int(EW.BUSY))
        with pytest.raises(ChunkedWriteError) as caught:
            await cnc.write_pmc("D", 100, bytes(range(1, 97)))
        err = caught.value
        assert err.written == [(100, 131), (164, 195)]
        assert err.not_written == [(132, 163)]  # refused by the CNC: certainly not written
        assert err.uncertain == []
        assert isinstance(err.cause, CncError) and err.cause.ew == EW.BUSY
        data = await cnc.read_pmc("D", 100, 96)
        assert data[:32] == bytes(range(1, 33))
        assert data[32:64] == bytes(32)
        assert data[64:] == bytes(range(65, 97))


# -- answers split one byte per write ------------------------------------------------------------


async def test_answers_split_one_byte_per_write_decode_the_same() -> None:
    async with serving() as served, client_of(served) as cnc:
        await cnc.write_pmc("D", 0, bytes(range(100)))
        await cnc.sim.raise_alarm(3, 100, "SPLIT ME")
        plain = (
            await cnc.read_sysinfo(),
            await cnc.read_status(),
            await cnc.read_pmc("D", 0, 100),
            await cnc.read_alarm_history(),
            await cnc.read_alarms(),
            await cnc.read_module_config(0, 3),
            await cnc.read_param(1320, axis=2),
        )
        await cnc.sim.inject_fault(FaultKind.SPLIT, count=100)
        split = (
            await cnc.read_sysinfo(),
            await cnc.read_status(),
            await cnc.read_pmc("D", 0, 100),
            await cnc.read_alarm_history(),
            await cnc.read_alarms(),
            await cnc.read_module_config(0, 3),
            await cnc.read_param(1320, axis=2),
        )
        assert split == plain


# -- a server that dies and comes back -----------------------------------------------------------


class ServeProcess:
    """``focas-net serve`` in a child process."""

    def __init__(self, *args: str) -> None:
        self.proc = subprocess.Popen(
            [sys.executable, "-m", "focas_net", "serve", "--host", "127.0.0.1", *args],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )

    async def address(self) -> tuple[str, int]:
        """Wait for the ``listening on HOST:PORT`` line."""
        assert self.proc.stdout is not None
        line = await asyncio.wait_for(asyncio.to_thread(self.proc.stdout.readline), 20)
        assert "listening on" in line, line + (self.proc.stderr.read() if self.proc.stderr else "")
        host, port = line.rsplit(" ", 1)[1].strip().rsplit(":", 1)
        return host, int(port)

    def kill(self) -> None:
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGKILL)
        self.proc.wait(10)

    def stop(self) -> int:
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGTERM)
        return self.proc.wait(20)

    def close(self) -> None:
        self.kill()
        for stream in (self.proc.stdout, self.proc.stderr):
            if stream is not None:
                stream.close()


@pytest.fixture
def processes() -> Iterator[list[ServeProcess]]:
    started: list[ServeProcess] = []
    yield started
    for proc in started:
        proc.close()


async def test_server_killed_and_restarted_on_the_same_port(
    processes: list[ServeProcess],
) -> None:
    first = ServeProcess("--port", "0")
    processes.append(first)
    host, port = await first.address()
    async with FocasClient(host, port, timeout=IO_TIMEOUT, reconnect=FAST_RECONNECT) as cnc:
        await cnc.write_macro(100, 1)
        await cnc.sim.inject_fault(FaultKind.DELAY, count=1, arg=30_000)
        pending = asyncio.ensure_future(cnc.read_macro(100, timeout=60))
        await asyncio.sleep(0)  # its request goes out first
        # the server answers in order: once this answer is in, the delayed request is held
        assert await cnc.read_macro(100) == Decimal(1)
        assert not pending.done()
        first.kill()
        # the call in flight fails at once with a connection error, long before its timeout
        with pytest.raises(FocasConnectionError):
            async with asyncio.timeout(IO_TIMEOUT):
                await pending
        # while nothing listens, calls fail within their own timeout
        with pytest.raises((FocasConnectionError, FocasTimeoutError)):
            await cnc.read_status(timeout=0.3)
        second = ServeProcess("--port", str(port))
        processes.append(second)
        assert await second.address() == (host, port)
        # later calls succeed on the new server (a fresh machine: the macro is vacant)
        assert await cnc.read_macro(100, timeout=10) is None
        await cnc.write_macro(100, 2)
        assert await cnc.read_macro(100) == Decimal(2)
        assert cnc.state is ClientState.CONNECTED
    assert second.stop() == 0


async def test_alarm_projection_resumes_after_a_restart_without_duplicates() -> None:
    machine = default_machine()
    server = FocasServer(machine, host="127.0.0.1", port=0, grace_period=0.5)
    await server.start()
    port = server.listeners[0].port
    restarted: FocasServer | None = None
    try:
        async with FocasClient("127.0.0.1", port, timeout=1.0, reconnect=FAST_RECONNECT) as cnc:
            projection = AlarmProjection(
                cnc, ProjectionMode.ACTIVE_PLUS_HISTORY, interval=0.05, depth=50
            )
            await cnc.sim.raise_alarm(3, 100, "BEFORE")
            events = await projection.poll()
            assert sorted(type(e).__name__ for e in events) == ["AlarmHistoryEvent", "AlarmRaised"]
            assert await projection.poll() == []
            await server.aclose()
            await wait_until(lambda: cnc.state is not ClientState.CONNECTED)
            failed = projection.failed_polls
            assert await projection.poll() == []  # nothing to poll: no events, no change
            assert projection.failed_polls == failed + 1
            machine.raise_alarm(0, 3, 101, "DURING")  # raised while the server is down
            restarted = FocasServer(machine, host="127.0.0.1", port=port, grace_period=0.5)
            await restarted.start()
            await wait_until(lambda: cnc.state is ClientState.CONNECTED, within=10)
            events = await projection.poll()
            raised = [e.alarm.alm_no for e in events if isinstance(e, AlarmRaised)]
            history = [e.entry.alm_no for e in events if isinstance(e, AlarmHistoryEvent)]
            assert raised == [101] and history == [101], events  # nothing about 100 again
            assert await projection.poll() == []
            await cnc.sim.raise_alarm(3, 102, "AFTER")
            events = await projection.poll()
            assert [type(e).__name__ for e in events] == ["AlarmRaised", "AlarmHistoryEvent"]
            assert {e.alarm.alm_no for e in events if isinstance(e, AlarmRaised)} == {102}
            # iterating goes on from the same state: no event is repeated
            await cnc.sim.clear_alarms(3, 100)
            async with asyncio.timeout(IO_TIMEOUT):
                event = await anext(projection)
            assert type(event).__name__ == "AlarmCleared"
            projection.stop()
    finally:
        await server.aclose()
        if restarted is not None:
            await restarted.aclose()


# -- cancellation storm --------------------------------------------------------------------------

D_WORDS: Final = 5_000  # D0..D9999 as 2-byte words holding k
R_WORDS: Final = 3_900  # R0..R7799 as 2-byte words holding 10,000 + k
BIT_BYTES: Final = range(7_800, 8_000)  # bit writes go here
MACROS: Final = [*range(1, 34), *range(100, 200), *range(500, 1000)]


def _macro_value(number: int) -> int:
    return number * 3 + 1


async def _fill(cnc: FocasClient) -> None:
    await cnc.write_pmc("D", 0, b"".join(struct.pack("<H", k) for k in range(D_WORDS)))
    await cnc.write_pmc("R", 0, b"".join(struct.pack("<H", 10_000 + k) for k in range(R_WORDS)))
    await asyncio.gather(*(cnc.write_macro(n, _macro_value(n)) for n in MACROS))


async def _call(cnc: FocasClient, index: int) -> tuple[str, Any]:
    """Call number ``index``: a read whose answer names what was read, or a bit write."""
    kind = index % 4
    if kind == 0:
        k = (index // 4) % D_WORDS
        return "D", (k, struct.unpack("<H", await cnc.read_pmc("D", 2 * k, 2))[0])
    if kind == 1:
        k = (index // 4) % R_WORDS
        return "R", (k, struct.unpack("<H", await cnc.read_pmc("R", 2 * k, 2))[0] - 10_000)
    if kind == 2:
        number = MACROS[(index // 4) % len(MACROS)]
        return "M", (number, await cnc.read_macro(number))
    if index % 8 == 3:
        byte = BIT_BYTES[(index // 8) % len(BIT_BYTES)]
        bit = (index // 8 // len(BIT_BYTES)) % 8
        await cnc.write_pmc_bit("R", byte, bit, True)
        return "bit", (byte, bit)
    axis = 1 + index % 3
    return "P", (axis, await cnc.read_param(1320, axis=axis))


def _check(index: int, result: tuple[str, Any]) -> None:
    kind, (key, value) = result
    if kind == "D":
        assert key == (index // 4) % D_WORDS and value == key, (index, result)
    elif kind == "R":
        assert key == (index // 4) % R_WORDS and value == key, (index, result)
    elif kind == "M":
        assert key == MACROS[(index // 4) % len(MACROS)], (index, result)
        assert value == Decimal(_macro_value(key)), (index, result)
    elif kind == "P":
        assert key == index % 3 + 1 and value == 1_000 * key, (index, result)


async def test_cancellation_storm_leaves_nothing_behind() -> None:
    calls = 10_000
    rng = random.Random(20_240_611)
    async with serving(max_delayed=20_000) as served:
        async with client_of(served) as setup:
            await _fill(setup)
            for axis in (1, 2, 3):  # distinct values of 1320 per axis: 1000, 2000, 3000
                await setup.sim.set_panel(0, pwe=True)
                await setup.write_param(1320, 1_000 * axis, axis=axis)
        clients = [
            FocasClient(served.host, served.port, timeout=30, max_in_flight=calls) for _ in range(2)
        ]
        async with contextlib.AsyncExitStack() as stack:
            for cnc in clients:
                await stack.enter_async_context(cnc)
                # every answer a little late, so that the cancellations find calls in flight
                await cnc.sim.inject_fault(FaultKind.DELAY, count=10_000, arg=100)
            tasks = [asyncio.ensure_future(_call(clients[i % 2], i)) for i in range(calls)]
            doomed = rng.sample(range(calls), calls // 2)
            for start in range(0, len(doomed), 250):  # cancel in waves, at random moments
                for i in doomed[start : start + 250]:
                    tasks[i].cancel()
                await asyncio.sleep(rng.choice([0, 0, 0.001, 0.005]))
            results = await asyncio.gather(*tasks, return_exceptions=True)
            doomed_set = set(doomed)
            cancelled = 0
            bits_set: list[tuple[int, int]] = []
            for i, result in enumerate(results):
                if isinstance(result, asyncio.CancelledError):
                    assert i in doomed_set
                    cancelled += 1
                    continue
                assert not isinstance(result, BaseException), (i, result)
                _check(i, result)
                if result[0] == "bit":
                    bits_set.append(result[1])
            assert cancelled > calls // 10  # many cancellations hit calls still in flight
            for cnc in clients:
                await wait_until(lambda c=cnc: client_leftovers(c) == (0, 0, 0), within=30)
            # every bit write that returned is on the machine
            async with client_of(served) as check:
                for byte, bit in bits_set:
                    assert await check.read_pmc_bit("R", byte, bit)
                assert await check.read_pmc("D", 0, 4) == struct.pack("<HH", 0, 1)
