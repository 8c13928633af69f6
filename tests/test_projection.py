"""AlarmProjection against the real server."""

from __future__ import annotations

import asyncio
from collections.abc import AsyncIterator
from datetime import UTC, datetime

import pytest
from support import IO_TIMEOUT, Served, serving

from focas_net.client import (
    AlarmCleared,
    AlarmEvent,
    AlarmHistoryEvent,
    AlarmProjection,
    AlarmRaised,
    FocasClient,
    ProjectionMode,
    ReconnectPolicy,
)
from focas_net.client.projection import MIN_HISTORY_MEMORY
from focas_net.errors import EW
from focas_net.protocol import FaultKind
from focas_net.server import FocasServer
from focas_net.sim import default_machine

HISTORY = ProjectionMode.ACTIVE_PLUS_HISTORY
STILL = datetime(2024, 5, 6, 7, 8, 9, tzinfo=UTC)  # a wall clock standing still


@pytest.fixture
async def cnc(server: Served) -> AsyncIterator[FocasClient]:
    async with FocasClient(server.host, server.port, timeout=IO_TIMEOUT) as client:
        yield client


async def next_events(projection: AlarmProjection, n: int) -> list[AlarmEvent]:
    events: list[AlarmEvent] = []
    async with asyncio.timeout(IO_TIMEOUT):
        for _ in range(n):
            events.append(await anext(projection))
    return events


def history_keys(events: list[AlarmEvent]) -> list[tuple[int, int]]:
    return [(e.entry.alm_type, e.entry.alm_no) for e in events if isinstance(e, AlarmHistoryEvent)]


async def test_active_raised_and_cleared(cnc: FocasClient) -> None:
    await cnc.sim.raise_alarm(3, 100, "ALREADY ACTIVE")
    async with AlarmProjection(cnc, interval=0.01) as projection:
        (first,) = await next_events(projection, 1)
        assert isinstance(first, AlarmRaised) and first.alarm.alm_no == 100
        await cnc.sim.raise_alarm(6, 401, "SV0401", axis_no=1)
        (raised,) = await next_events(projection, 1)
        assert isinstance(raised, AlarmRaised)
        assert raised.alarm.key == (1, 6, 401) and raised.alarm.msg == "SV0401"
        await cnc.sim.clear_alarms(3, 100)
        (cleared,) = await next_events(projection, 1)
        assert isinstance(cleared, AlarmCleared) and cleared.alarm.alm_no == 100
        assert [a.alm_no for a in projection.active] == [401]
    with pytest.raises(StopAsyncIteration):
        await anext(projection)


async def test_history_events_are_never_repeated(cnc: FocasClient) -> None:
    projection = AlarmProjection(cnc, HISTORY, depth=10)
    await cnc.sim.raise_alarm(3, 1)
    await cnc.sim.raise_alarm(3, 2)
    events = await projection.poll()
    assert [type(e) for e in events] == [AlarmRaised, AlarmRaised] + [AlarmHistoryEvent] * 2
    assert history_keys(events) == [(3, 1), (3, 2)]  # oldest first
    assert await projection.poll() == []
    await cnc.sim.clear_alarms()
    await cnc.sim.raise_alarm(4, 3)
    events = await projection.poll()
    assert sum(isinstance(e, AlarmCleared) for e in events) == 2
    assert history_keys(events) == [(4, 3)]
    for _ in range(5):
        assert await projection.poll() == []


async def test_replay_history_off_skips_existing_entries(cnc: FocasClient) -> None:
    await cnc.sim.raise_alarm(3, 7)
    await cnc.sim.clear_alarms()
    projection = AlarmProjection(cnc, HISTORY, replay_history=False)
    assert await projection.poll() == []
    await cnc.sim.raise_alarm(3, 8)
    events = await projection.poll()
    assert history_keys(events) == [(3, 8)]


async def test_failed_poll_yields_nothing_and_keeps_state(cnc: FocasClient) -> None:
    projection = AlarmProjection(cnc, HISTORY)
    await cnc.sim.raise_alarm(3, 9)
    assert len(await projection.poll()) == 2
    await cnc.sim.inject_fault(FaultKind.ERROR, arg=EW.BUSY, count=1)
    assert await projection.poll() == []  # active list failed (count = -1)
    await cnc.sim.inject_fault(FaultKind.ERROR, arg=EW.BUSY, count=1)
    await cnc.sim.inject_fault(FaultKind.DELAY, arg=0, count=1)
    assert await projection.poll() == []  # active list failed again
    assert projection.failed_polls == 2
    assert await projection.poll() == []  # nothing changed: no spurious cleared events
    assert [a.alm_no for a in projection.active] == [9]


async def test_history_failure_alone_fails_the_tick(cnc: FocasClient) -> None:
    projection = AlarmProjection(cnc, HISTORY)
    await projection.poll()
    await cnc.sim.raise_alarm(3, 12)
    await cnc.sim.inject_fault(FaultKind.DELAY, arg=0, count=1)  # the active list passes
    await cnc.sim.inject_fault(FaultKind.ERROR, arg=EW.BUSY, count=1)  # the history fails
    assert await projection.poll() == []
    events = await projection.poll()
    assert [type(e) for e in events] == [AlarmRaised, AlarmHistoryEvent]


async def test_stop_wakes_a_waiting_iterator(cnc: FocasClient) -> None:
    projection = AlarmProjection(cnc, interval=3600)
    waiter = asyncio.create_task(anext(projection))
    await asyncio.sleep(0.05)  # first poll done, now sleeping for an hour
    projection.stop()
    with pytest.raises(StopAsyncIteration):
        async with asyncio.timeout(IO_TIMEOUT):
            await waiter


async def test_iteration_ends_when_the_client_closes(server: Served) -> None:
    client = FocasClient(server.host, server.port, timeout=IO_TIMEOUT)
    await client.connect()
    projection = AlarmProjection(client, interval=0.01)
    await projection.poll()
    await client.aclose()
    with pytest.raises(StopAsyncIteration):
        async with asyncio.timeout(IO_TIMEOUT):
            await anext(projection)


async def test_history_memory_is_bounded(server: Served, cnc: FocasClient) -> None:
    """The projection remembers the keys of MIN_HISTORY_MEMORY history entries (its bound at
    any depth up to 250): an entry whose key it remembers is never reported again; once more
    keys than that have come, the oldest is forgotten, and an entry with it is reported again.
    The machine's clock stands still, so that an alarm raised again has the key it had."""
    assert 4 * 250 <= MIN_HISTORY_MEMORY
    machine = server.machine
    machine.clock = lambda: STILL
    projection = AlarmProjection(cnc, HISTORY, depth=250)

    async def raise_then_poll(numbers: range) -> list[tuple[int, int]]:
        for number in numbers:
            assert machine.raise_alarm(0, 3, number)
        machine.clear_alarms()
        return history_keys(await projection.poll())

    assert await raise_then_poll(range(1, 2)) == [(3, 1)]
    # every key up to the bound, none twice; the first one is the oldest
    for first in range(2, MIN_HISTORY_MEMORY + 1, 240):
        batch = range(first, min(first + 240, MIN_HISTORY_MEMORY + 1))
        assert await raise_then_poll(batch) == [(3, n) for n in batch]
    assert await raise_then_poll(range(1, 2)) == []  # remembered: not reported again
    beyond = MIN_HISTORY_MEMORY + 1
    assert await raise_then_poll(range(beyond, beyond + 1)) == [(3, beyond)]
    # one key past the bound: the oldest is forgotten, and the entry with it that is still
    # in the history (raised again above) is reported again
    assert history_keys(await projection.poll()) == [(3, 1)]


async def test_projection_resumes_after_restart_without_duplicates() -> None:
    machine = default_machine()
    policy = ReconnectPolicy(initial_delay=0.01, max_delay=0.05)
    async with serving(machine, grace_period=0.1) as served:
        port = served.port
        client = FocasClient("127.0.0.1", port, timeout=IO_TIMEOUT, reconnect=policy)
        await client.connect()
        projection = AlarmProjection(client, HISTORY, interval=0.01, timeout=0.2)
        await client.sim.raise_alarm(3, 21)
        events = await next_events(projection, 2)
        assert history_keys(events) == [(3, 21)]
    try:
        waiter = asyncio.create_task(next_events(projection, 1))
        await asyncio.sleep(0.3)  # polls (timeout 0.2 s) fail while the server is down
        assert not waiter.done()
        async with FocasServer(machine, host="127.0.0.1", port=port, grace_period=0.1):
            await client.sim.raise_alarm(3, 22, timeout=IO_TIMEOUT)
            await client.sim.clear_alarms(3, 21, timeout=IO_TIMEOUT)
            got = await waiter
            got += await next_events(projection, 2)
            assert history_keys(got) == [(3, 22)]  # 21 is not repeated
            assert {type(e) for e in got} == {AlarmRaised, AlarmCleared, AlarmHistoryEvent}
            assert projection.failed_polls > 0
    finally:
        projection.stop()
        await client.aclose()
