"""A FOCAS/2 answer that comes after its call's deadline is matched to its frame and dropped,
and the connection pair goes on, as the packed client keeps its connection past a late
answer: answers come in order on B and no frame leaves behind an unanswered one, so the next
data answer is always the overdue frame's. A call queued behind that frame which reaches its
own deadline unsent ends the connection (the CNC is taken as no longer answering).

Run on ``virtual_net.VirtualLoop`` (the real server and client, a network in memory, a clock
that moves only when nothing else can happen): every step is taken by hand, no time is
measured.
"""

# Calls are given timeout= on purpose (the deadline under test), so ASYNC109 does not apply.

from __future__ import annotations

import asyncio
from collections.abc import Callable, Coroutine
from decimal import Decimal
from typing import Any

import pytest
from virtual_net import VirtualLoop

from focas_net.client import ClientState, NativeClient, ReconnectPolicy
from focas_net.errors import FocasConnectionError, FocasTimeoutError
from focas_net.protocol import FaultKind
from focas_net.server import FocasServer
from focas_net.server.faults import Fault
from focas_net.sim import default_machine

#: The client's timeout, in machine seconds.
TIMEOUT = 1.0


def _run(main: Callable[[FocasServer], Coroutine[Any, Any, None]]) -> None:
    loop = VirtualLoop()
    errors: list[dict[str, Any]] = []
    loop.set_exception_handler(lambda _loop, context: errors.append(context))

    async def served() -> None:
        server = FocasServer(default_machine(), host="127.0.0.1", port=0, idle_timeout=0)
        await server.start()
        try:
            await main(server)
        finally:
            await server.aclose()

    try:
        loop.run_until_complete(served())
        loop.run_until_complete(loop.shutdown_asyncgens())
    finally:
        loop.close()
    assert errors == []


def _delay_next_answer(server: FocasServer, ms: int) -> None:
    """The next data answer of the machine leaves ``ms`` milliseconds late."""
    server.listeners[0].faults.arm(Fault(FaultKind.DELAY, ms, 1))


def _client(server: FocasServer, reconnect: bool | ReconnectPolicy = False) -> NativeClient:
    host, port = server.listeners[0].address
    return NativeClient(host, port, timeout=TIMEOUT, reconnect=reconnect)


def test_a_late_answer_is_dropped_and_the_connection_goes_on() -> None:
    async def main(server: FocasServer) -> None:
        listener = server.listeners[0]
        async with _client(server) as native:  # no reconnect: a closed pair would stay closed
            await native.write_macro(100, Decimal(7))
            pair = set(listener.native_connections)
            _delay_next_answer(server, 1500)
            with pytest.raises(FocasTimeoutError, match="cnc_rdmacro"):
                await native.read_macro(100)
            assert native.state is ClientState.CONNECTED
            assert native.idle  # the overdue frame carries no call: its answer is awaited
            # the next call waits behind the late answer, then gets its own answer
            assert await native.read_macro(101) is None
            assert await native.read_macro(100) == 7
            assert native.state is ClientState.CONNECTED and native.idle
            assert set(listener.native_connections) == pair  # the same A and B

    _run(main)


def test_calls_made_together_after_a_timeout_all_get_their_own_answers() -> None:
    async def main(server: FocasServer) -> None:
        async with _client(server) as native:
            for n in range(100, 104):
                await native.write_macro(n, Decimal(n))
            _delay_next_answer(server, 1200)
            with pytest.raises(FocasTimeoutError):
                await native.read_macro(100)
            values = await asyncio.gather(*(native.read_macro(n) for n in range(100, 104)))
            assert values == [Decimal(n) for n in range(100, 104)]
            assert native.state is ClientState.CONNECTED

    _run(main)


def test_a_call_that_gives_up_behind_an_answer_that_never_comes_ends_the_pair() -> None:
    async def main(server: FocasServer) -> None:
        async with _client(server) as native:
            _delay_next_answer(server, 60_000)  # as good as never
            with pytest.raises(FocasTimeoutError):
                await native.read_macro(100)
            states = [native.state]  # still connected: the late answer is awaited
            with pytest.raises(FocasTimeoutError, match="never sent"):
                await native.read_macro(101)
            states.append(native.state)  # no reconnect policy
            assert states == [ClientState.CONNECTED, ClientState.DISCONNECTED]
            with pytest.raises(FocasConnectionError):
                await native.read_macro(102)
            assert native.idle

    _run(main)


def test_with_a_reconnect_policy_a_call_behind_a_late_answer_goes_on_a_new_pair() -> None:
    async def main(server: FocasServer) -> None:
        listener = server.listeners[0]
        policy = ReconnectPolicy(initial_delay=0.05, max_delay=0.5, jitter=0.0)
        async with _client(server, policy) as native:
            await native.write_macro(100, Decimal(3))
            first = set(listener.native_connections)
            _delay_next_answer(server, 60_000)
            with pytest.raises(FocasTimeoutError):
                await native.read_macro(100)
            assert native.state is ClientState.CONNECTED  # the late answer is awaited
            # the next call does not wait for it: the pair is given up, the call goes on a new
            # one and gets its answer
            assert await native.read_macro(100) == 3
            assert native.state is ClientState.CONNECTED
            assert len(set(listener.native_connections) - first) == 2  # a new A and B

    _run(main)
