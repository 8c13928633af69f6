"""``read_status_all`` over :class:`NativeClient` (FOCAS/2), alone and mixed with packed clients,
and ``read_dynamic_all``.

Every test talks to real servers on 127.0.0.1 (port 0) in this process. Properties:

* the results are each client's ``read_status``, in the order of the clients, whatever the mix
  of transports;
* one read failing (not connected, an EW code, a timeout) fails that entry only, with the
  error ``read_status`` raises;
* a native client with a frame in flight queues the read for its next frame, as its own calls
  do;
* cancelling the caller drops the reads still queued and ignores the answers of those sent;
  the next calls get their own answers;
* ``read_dynamic_all`` is each client's ``read_dynamic`` in the same way, its argument checks
  made before anything is sent.
"""

from __future__ import annotations

import asyncio
import random
from collections.abc import AsyncIterator
from contextlib import AsyncExitStack, asynccontextmanager
from decimal import Decimal

import pytest
from support import IO_TIMEOUT, Served, serving

from focas_net import (
    EW,
    CncError,
    FocasClient,
    FocasConnectionError,
    FocasTimeoutError,
    NativeClient,
    ReconnectPolicy,
    StatusInfo,
    read_dynamic_all,
    read_status_all,
)
from focas_net.client import DynamicData
from focas_net.protocol import FaultKind, FaultScope


@asynccontextmanager
async def plant(count: int) -> AsyncIterator[tuple[list[Served], list[NativeClient]]]:
    """``count`` machines, each served on its own port, and a connected native client for
    each."""
    async with AsyncExitStack() as stack:
        served = [await stack.enter_async_context(serving()) for _ in range(count)]
        clients = [
            await stack.enter_async_context(NativeClient(s.host, s.port, timeout=IO_TIMEOUT))
            for s in served
        ]
        yield served, clients


def idle(cnc: NativeClient) -> bool:
    """Nothing queued and no frame in flight."""
    return cnc.idle


async def inject(served: Served, kind: FaultKind, arg: int) -> None:
    """Arm one ``kind`` fault on ``served``'s machine (for its native connections too)."""
    async with FocasClient(served.host, served.port, timeout=IO_TIMEOUT) as packed:
        await packed.sim.inject_fault(kind, count=1, arg=arg, scope=FaultScope.MACHINE)


async def test_the_statuses_of_every_native_client_in_order() -> None:
    async with plant(4) as (served, clients):
        served[1].machine.raise_alarm(0, 2, 100, "overtravel")
        served[3].machine.raise_alarm(0, 2, 101, "overtravel")
        frames = [c.frames_sent for c in clients]
        got = await read_status_all(clients)
        assert [c.frames_sent - n for c, n in zip(clients, frames, strict=True)] == [1] * 4
        one_by_one = [await c.read_status() for c in clients]
        assert got == one_by_one
        assert [s.alarm != 0 for s in got if isinstance(s, StatusInfo)] == [
            False,
            True,
            False,
            True,
        ]
        assert all(idle(c) for c in clients)


async def test_packed_and_native_clients_in_one_list() -> None:
    async with plant(2) as (served, natives), AsyncExitStack() as stack:
        packed = [
            await stack.enter_async_context(FocasClient(s.host, s.port, timeout=IO_TIMEOUT))
            for s in served
        ]
        served[0].machine.raise_alarm(0, 2, 100, "overtravel")
        mixed: list[FocasClient | NativeClient] = [natives[0], packed[0], natives[1], packed[1]]
        got = await read_status_all(mixed)
        assert got[0] == got[1] and got[2] == got[3]
        assert got == [await c.read_status() for c in mixed]
        assert isinstance(got[0], StatusInfo) and got[0].alarm != 0


async def test_a_native_client_not_connected_fails_alone() -> None:
    async with plant(2) as (served, clients):
        never = NativeClient(served[0].host, served[0].port, timeout=IO_TIMEOUT)
        got = await read_status_all([clients[0], never, clients[1]])
        assert isinstance(got[0], StatusInfo) and isinstance(got[2], StatusInfo)
        assert isinstance(got[1], FocasConnectionError)
        assert "not connected" in str(got[1])


async def test_an_ew_code_fails_that_native_read_only() -> None:
    async with plant(3) as (served, clients):
        await inject(served[1], FaultKind.ERROR, int(EW.DATA))
        got = await read_status_all(clients)
        assert isinstance(got[0], StatusInfo) and isinstance(got[2], StatusInfo)
        assert isinstance(got[1], CncError) and got[1].ew == EW.DATA
        assert all(isinstance(s, StatusInfo) for s in await read_status_all(clients))


async def test_an_unanswered_native_read_times_out_alone() -> None:
    """Its frame unanswered at its deadline, the read fails with FocasTimeoutError and the
    connection pair is closed (FOCAS/2 cannot tell a late answer from the next one); with a
    reconnect policy the next read goes out on a new pair."""
    policy = ReconnectPolicy(initial_delay=0.01, max_delay=0.05, jitter=0)
    async with plant(2) as (served, clients):
        async with NativeClient(
            served[1].host, served[1].port, timeout=IO_TIMEOUT, reconnect=policy
        ) as slow:
            await inject(served[1], FaultKind.DELAY, 3000)
            got = await read_status_all([clients[0], slow, clients[1]], timeout=0.1)
            assert isinstance(got[0], StatusInfo) and isinstance(got[2], StatusInfo)
            assert isinstance(got[1], FocasTimeoutError)
            (again,) = await read_status_all([slow], timeout=IO_TIMEOUT)
            assert again == await clients[1].read_status()


async def test_a_native_client_with_a_frame_in_flight_queues_the_read() -> None:
    async with plant(2) as (served, clients):
        served[0].machine.write_macro(500, 7)
        await inject(served[0], FaultKind.DELAY, 50)
        holder = asyncio.ensure_future(clients[0].read_macro(500))  # its frame goes out first
        for _ in range(100):
            if not idle(clients[0]):
                break
            await asyncio.sleep(0)
        assert not idle(clients[0])
        got = await read_status_all(clients)
        assert all(isinstance(s, StatusInfo) for s in got)
        assert await holder == Decimal(7)
        assert all(idle(c) for c in clients)


async def test_cancelling_the_caller_drops_every_unanswered_native_read() -> None:
    async with plant(3) as (served, clients):
        for s in served:
            s.machine.write_macro(500, 9)
            await inject(s, FaultKind.DELAY, 200)
        reading = asyncio.ensure_future(read_status_all(clients))
        for _ in range(100):
            if not any(idle(c) for c in clients):
                break
            await asyncio.sleep(0)
        reading.cancel()
        with pytest.raises(asyncio.CancelledError):
            await reading
        # the frames already sent are answered late and their blocks dropped; the next calls
        # get their own answers
        assert [await c.read_macro(500) for c in clients] == [Decimal(9)] * 3
        assert all(isinstance(s, StatusInfo) for s in await read_status_all(clients))
        assert all(idle(c) for c in clients)


async def test_a_storm_of_native_reads_cancelled_at_random_leaves_nothing_behind() -> None:
    """Rounds of ``read_status_all`` over 6 native clients of one machine, some with a call of
    their own in flight, about half the rounds cancelled at a random point: every round that
    ends returns a status per client, the calls of their own get their own answers, and
    nothing is left queued or in flight."""
    rng = random.Random(1412)
    async with serving() as served, AsyncExitStack() as stack:
        served.machine.write_macro(500, 3)
        clients = [
            await stack.enter_async_context(
                NativeClient(served.host, served.port, timeout=IO_TIMEOUT)
            )
            for _ in range(6)
        ]
        for _ in range(40):
            own = [asyncio.ensure_future(c.read_macro(500)) for c in rng.sample(clients, 2)]
            reading = asyncio.ensure_future(read_status_all(clients))
            if rng.random() < 0.5:
                for _ in range(rng.randint(0, 3)):
                    await asyncio.sleep(0)
                reading.cancel()
            try:
                got = await reading
            except asyncio.CancelledError:
                pass
            else:
                assert all(isinstance(s, StatusInfo) for s in got), got
            assert await asyncio.gather(*own) == [Decimal(3)] * len(own)
        for _ in range(100):
            if all(idle(c) for c in clients):
                break
            await asyncio.sleep(0.01)
        assert all(idle(c) for c in clients)
        assert all(isinstance(s, StatusInfo) for s in await read_status_all(clients))


async def test_read_dynamic_all_is_each_clients_read_dynamic() -> None:
    async with plant(3) as (served, clients):
        for k, s in enumerate(served):
            n = len(s.machine.axes)
            s.machine.set_motion(absolute=range(10 * k, 10 * k + n), feed=40 + k)
        frames = [c.frames_sent for c in clients]
        every = await read_dynamic_all(clients)
        assert [c.frames_sent - n for c, n in zip(clients, frames, strict=True)] == [1] * 3
        assert every == [await c.read_dynamic() for c in clients]
        assert [d.feed for d in every if isinstance(d, DynamicData)] == [40, 41, 42]
        second = await read_dynamic_all(clients, 2, timeout=IO_TIMEOUT)
        assert second == [await c.read_dynamic(2) for c in clients]
        assert [d.absolute for d in second if isinstance(d, DynamicData)] == [(1,), (11,), (21,)]
        assert all(idle(c) for c in clients)


async def test_read_dynamic_all_checks_before_sending() -> None:
    async with plant(2) as (served, clients):
        never = NativeClient(served[0].host, served[0].port, timeout=IO_TIMEOUT)
        with pytest.raises(ValueError, match=r"axis 0 is outside 1\.\.32767"):
            await read_dynamic_all(clients, 0)
        frames = [c.frames_sent for c in clients]
        beyond = len(served[0].machine.axes) + 1
        got = await read_dynamic_all([clients[0], never, clients[1]], beyond)
        assert [c.frames_sent for c in clients] == frames  # nothing sent
        assert isinstance(got[0], CncError) and got[0].ew == EW.ATTRIB
        assert isinstance(got[1], FocasConnectionError) and "not connected" in str(got[1])
        assert isinstance(got[2], CncError) and got[2].ew == EW.ATTRIB


async def test_read_dynamic_all_fails_an_unanswered_read_alone() -> None:
    async with plant(3) as (served, clients):
        await inject(served[0], FaultKind.DELAY, 3000)
        got = await read_dynamic_all(clients, timeout=0.1)
        assert isinstance(got[0], FocasTimeoutError)
        assert all(isinstance(d, DynamicData) for d in got[1:])
