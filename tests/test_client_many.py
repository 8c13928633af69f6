"""``read_status_all``: many clients' status read from one task, each read as ``read_status``.

Every test talks to real servers on 127.0.0.1 (port 0) in this process. Properties:

* the results are each client's ``read_status``, in the order of the clients;
* one read failing (not connected, an EW code, a timeout) fails that entry only, with the
  error ``read_status`` raises;
* a client with every request slot taken, or answered ``EW_PASSWD`` while a password is known,
  is still read (the usual way), and a closed connection's read goes out on the next one
  with a reconnect policy;
* cancelling the caller gives up the unanswered reads: their ids stay reserved, their late
  answers are dropped, and the next calls get their own answers.
"""

from __future__ import annotations

import asyncio
import random
from collections.abc import AsyncIterator
from contextlib import AsyncExitStack, asynccontextmanager
from decimal import Decimal

import pytest
from support import IO_TIMEOUT, Served, serving, wait_until

from focas_net import (
    EW,
    CncError,
    FocasClient,
    FocasConnectionError,
    FocasTimeoutError,
    ReconnectPolicy,
    StatusInfo,
    default_machine,
    read_status_all,
)
from focas_net.protocol import FaultKind


@asynccontextmanager
async def plant(count: int) -> AsyncIterator[tuple[list[Served], list[FocasClient]]]:
    """``count`` machines, each served on its own port, and a connected client for each."""
    async with AsyncExitStack() as stack:
        served = [await stack.enter_async_context(serving()) for _ in range(count)]
        clients = [
            await stack.enter_async_context(FocasClient(s.host, s.port, timeout=IO_TIMEOUT))
            for s in served
        ]
        yield served, clients


def leftovers(cnc: FocasClient) -> tuple[int, int]:
    """``(in flight, abandoned ids)`` of ``cnc``'s connection."""
    conn = cnc.connection
    assert conn is not None
    return conn.in_flight, conn.abandoned


async def test_the_statuses_of_every_client_in_order() -> None:
    async with plant(4) as (served, clients):
        served[1].machine.raise_alarm(0, 2, 100, "overtravel")
        served[3].machine.raise_alarm(0, 2, 101, "overtravel")
        got = await read_status_all(clients)
        one_by_one = [await c.read_status() for c in clients]
        assert got == one_by_one
        assert all(isinstance(s, StatusInfo) for s in got)
        assert [s.alarm != 0 for s in got if isinstance(s, StatusInfo)] == [
            False,
            True,
            False,
            True,
        ]
        assert [leftovers(c) for c in clients] == [(0, 0)] * 4
        assert await read_status_all([]) == []


async def test_a_client_not_connected_fails_alone() -> None:
    async with plant(2) as (served, clients):
        idle = FocasClient(served[0].host, served[0].port, timeout=IO_TIMEOUT)  # never connected
        got = await read_status_all([clients[0], idle, clients[1]])
        assert isinstance(got[0], StatusInfo) and isinstance(got[2], StatusInfo)
        assert isinstance(got[1], FocasConnectionError)
        assert "not connected" in str(got[1])


async def test_an_ew_code_fails_that_read_only() -> None:
    async with plant(3) as (_, clients):
        await clients[1].sim.inject_fault(FaultKind.ERROR, count=1, arg=int(EW.BUSY))
        got = await read_status_all(clients)
        assert isinstance(got[0], StatusInfo) and isinstance(got[2], StatusInfo)
        assert isinstance(got[1], CncError) and got[1].ew == EW.BUSY
        assert all(isinstance(s, StatusInfo) for s in await read_status_all(clients))


async def test_a_late_answer_times_out_alone_and_reaches_nobody() -> None:
    async with plant(3) as (_, clients):
        await clients[2].write_macro(500, 7)
        await clients[2].sim.inject_fault(FaultKind.DELAY, count=1, arg=300)
        got = await read_status_all(clients, timeout=0.1)
        assert isinstance(got[0], StatusInfo) and isinstance(got[1], StatusInfo)
        assert isinstance(got[2], FocasTimeoutError)
        assert leftovers(clients[2]) == (0, 1)  # the id stays reserved for the late answer
        # the calls made while the late answer arrives each get their own answer
        assert await clients[2].read_macro(500) == Decimal(7)
        await wait_until(lambda: leftovers(clients[2]) == (0, 0))
        assert await clients[2].read_macro(500) == Decimal(7)


async def test_a_client_with_every_slot_taken_is_read_in_turn() -> None:
    async with serving() as served:
        async with (
            FocasClient(served.host, served.port, timeout=IO_TIMEOUT, max_in_flight=1) as busy,
            FocasClient(served.host, served.port, timeout=IO_TIMEOUT) as other,
        ):
            await busy.sim.inject_fault(FaultKind.DELAY, count=1, arg=50)
            holder = asyncio.ensure_future(busy.read_status())  # takes busy's one slot
            await wait_until(lambda: leftovers(busy) == (1, 0))
            got = await read_status_all([busy, other])
            assert all(isinstance(s, StatusInfo) for s in got)
            assert isinstance(await holder, StatusInfo)
            assert leftovers(busy) == (0, 0)


async def test_ew_passwd_with_a_password_unlocks_and_reads_again() -> None:
    async with serving(default_machine(param_password="1234")) as served:
        async with FocasClient(
            served.host, served.port, timeout=IO_TIMEOUT, password="1234"
        ) as cnc:
            await cnc.sim.inject_fault(FaultKind.ERROR, count=1, arg=int(EW.PASSWD))
            (got,) = await read_status_all([cnc])
            assert got == await cnc.read_status()


async def test_a_closed_connection_reads_on_the_next_one() -> None:
    policy = ReconnectPolicy(initial_delay=0.01, max_delay=0.05)
    async with serving() as served:
        async with FocasClient(
            served.host, served.port, timeout=IO_TIMEOUT, reconnect=policy
        ) as cnc:
            conn = cnc.connection
            assert conn is not None
            conn.close()  # closing: the read cannot go out on it
            (got,) = await read_status_all([cnc])
            assert isinstance(got, StatusInfo)
            assert cnc.connection is not conn


async def test_cancelling_the_caller_gives_up_every_unanswered_read() -> None:
    async with plant(3) as (_, clients):
        for c in clients:
            await c.sim.inject_fault(FaultKind.DELAY, count=1, arg=200)
        reading = asyncio.ensure_future(read_status_all(clients))
        await wait_until(lambda: all(leftovers(c) == (1, 0) for c in clients))
        reading.cancel()
        with pytest.raises(asyncio.CancelledError):
            await reading
        assert [leftovers(c) for c in clients] == [(0, 1)] * 3
        await wait_until(lambda: all(leftovers(c) == (0, 0) for c in clients))
        assert all(isinstance(s, StatusInfo) for s in await read_status_all(clients))


async def test_a_storm_of_reads_cancelled_at_random_leaves_nothing_behind() -> None:
    """Rounds of ``read_status_all`` over 8 clients of one machine, some answers delayed,
    about half the rounds cancelled at a random point: every round that ends returns a status
    or a timeout per client, and once the late answers are in nothing is left in flight."""
    rng = random.Random(1505)
    async with serving() as served, AsyncExitStack() as stack:
        clients = [
            await stack.enter_async_context(
                FocasClient(served.host, served.port, timeout=IO_TIMEOUT, max_in_flight=2)
            )
            for _ in range(8)
        ]
        for _ in range(40):
            for cnc in rng.sample(clients, 2):
                await cnc.sim.inject_fault(FaultKind.DELAY, count=1, arg=rng.randint(1, 30))
            reading = asyncio.ensure_future(read_status_all(clients, timeout=0.5))
            if rng.random() < 0.5:
                for _ in range(rng.randint(0, 3)):
                    await asyncio.sleep(0)
                reading.cancel()
            try:
                got = await reading
            except asyncio.CancelledError:
                continue
            assert len(got) == len(clients)
            assert all(isinstance(s, StatusInfo | FocasTimeoutError) for s in got), got
        await wait_until(lambda: all(leftovers(c) == (0, 0) for c in clients))
        final = await read_status_all(clients)
        assert all(isinstance(s, StatusInfo) for s in final)
