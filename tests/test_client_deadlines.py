"""Every call of both clients ends by its deadline, whatever it is given and whatever the wire
does, on a clock the test steps (``virtual_net.VirtualLoop``: machine time, a network in
memory, the real server and both real clients).

Hypothesis draws sequences of concurrent calls on :class:`FocasClient` and
:class:`NativeClient` with arguments valid and invalid (out of range, of the wrong type,
huge, negative, bad timeouts) while faults are armed on the machine's answers (delay, drop,
split, error), with pauses between. Properties:

* every call ends (a result, a CNC error, a timeout, a connection error, or at once a
  ``ValueError``/``TypeError`` naming what was given) no later than its deadline;
* a call refused for its arguments sends nothing and ends before anything else happens;
* nothing stays pending: no call queued or in flight once all have ended;
* the loop's exception handler is never called (nothing a caller gave raises in a callback);
* afterwards, with the faults gone, a valid call of every kind on each client succeeds.

The two hang cases found by hand are plain tests below.
"""

# Calls are given timeout= on purpose (the deadline under test), so ASYNC109 does not apply.

from __future__ import annotations

import asyncio
import math
from collections.abc import Awaitable, Callable, Coroutine
from dataclasses import dataclass, field
from decimal import Decimal
from typing import Any

import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st
from virtual_net import VirtualLoop

from focas_net.client import FocasClient, NativeClient, ReconnectPolicy
from focas_net.errors import FocasError
from focas_net.protocol import FaultKind
from focas_net.server import FocasServer
from focas_net.server.faults import Fault
from focas_net.sim import default_machine

#: The clients' own timeout (a call given none, or a bad one, is held to it... or refused).
DEFAULT_TIMEOUT = 2.0
#: A reconnect that tries again at once and never gives up.
POLICY = ReconnectPolicy(initial_delay=0.05, max_delay=0.5, jitter=0.0)
#: A bound on machine time for one example (every deadline is far inside it).
HORIZON = 600.0

Client = FocasClient | NativeClient
Call = Callable[[Client, tuple[Any, ...], Any], Awaitable[Any]]


# -- arguments, valid and not ------------------------------------------------------------------
def mostly(
    valid: st.SearchStrategy[Any], invalid: st.SearchStrategy[Any]
) -> st.SearchStrategy[Any]:
    """``valid`` about five times in six, else ``invalid``."""
    return st.integers(0, 5).flatmap(lambda i: valid if i else invalid)


WRONG_TYPES = st.sampled_from(["500", 1.5, None, True, b"1", [1]])
HUGE = st.sampled_from([2**40, -(2**40), 2**31, 40000, 32768, -32769, -1])
NUMBERS = mostly(st.integers(100, 110), st.one_of(HUGE, WRONG_TYPES))
SMALL = mostly(st.integers(0, 3), st.one_of(HUGE, WRONG_TYPES))
AREAS = mostly(st.sampled_from(["R", "D", "r"]), st.sampled_from(["Q", 99, None]))
VALUES = mostly(
    st.one_of(
        st.integers(-1000, 1000),
        st.decimals(min_value=-999, max_value=999, places=2, allow_nan=False),
    ),
    st.sampled_from(["abc", float("nan"), 2**40, None, True]),
)
DATA = mostly(st.binary(min_size=1, max_size=40), st.sampled_from(["ab", None, b""]))
TIMEOUTS = mostly(
    st.one_of(st.none(), st.floats(0.01, 5.0)),
    st.sampled_from([0, -1, float("nan"), "1", True]),
)

#: name -> (the call, the strategy of its arguments)
MENU: dict[str, tuple[Call, st.SearchStrategy[tuple[Any, ...]]]] = {
    "read_macro": (lambda c, a, t: c.read_macro(a[0], timeout=t), st.tuples(NUMBERS)),
    "write_macro": (
        lambda c, a, t: c.write_macro(a[0], a[1], timeout=t),
        st.tuples(NUMBERS, VALUES),
    ),
    "read_param": (
        lambda c, a, t: c.read_param(a[0], axis=a[1], timeout=t),
        st.tuples(st.one_of(st.sampled_from([1320, 6711, 1815]), NUMBERS), SMALL),
    ),
    "read_diag": (
        lambda c, a, t: c.read_diag(a[0], axis=a[1], timeout=t),
        st.tuples(NUMBERS, SMALL),
    ),
    "write_param_bit": (
        lambda c, a, t: c.write_param_bit(a[0], a[1], a[2], timeout=t),
        st.tuples(st.one_of(st.just(6711), NUMBERS), SMALL, st.booleans()),
    ),
    "read_pmc": (
        lambda c, a, t: c.read_pmc(a[0], a[1], a[2], timeout=t),
        st.tuples(AREAS, SMALL, mostly(st.integers(1, 3000), st.one_of(HUGE, WRONG_TYPES))),
    ),
    "write_pmc": (
        lambda c, a, t: c.write_pmc(a[0], a[1], a[2], timeout=t),
        st.tuples(AREAS, SMALL, DATA),
    ),
    "write_pmc_bit": (
        lambda c, a, t: c.write_pmc_bit(a[0], a[1], a[2], True, timeout=t),
        st.tuples(AREAS, SMALL, SMALL),
    ),
    "read_status": (lambda c, a, t: c.read_status(timeout=t), st.just(())),
    "read_alarms": (
        lambda c, a, t: c.read_alarms(alm_type=a[0], timeout=t),
        st.tuples(mostly(st.one_of(st.integers(-1, 31), st.just("PS")), st.just(40))),
    ),
    "read_positions": (
        lambda c, a, t: c.read_positions(a[0], axis=a[1], timeout=t),
        st.tuples(
            mostly(st.sampled_from(["absolute", "machine", 2]), st.sampled_from(["nowhere", 7])),
            st.one_of(st.none(), SMALL),
        ),
    ),
    "read_alarm_history": (
        lambda c, a, t: c.read_alarm_history(a[0], timeout=t),
        st.tuples(mostly(st.integers(-5, 300), WRONG_TYPES)),
    ),
}

STEPS = st.lists(
    st.one_of(
        st.tuples(
            st.just("call"),
            st.sampled_from(["packed", "native"]),
            st.sampled_from(sorted(MENU)).flatmap(lambda n: st.tuples(st.just(n), MENU[n][1])),
            TIMEOUTS,
        ),
        st.tuples(st.just("wait"), st.floats(0.0, 3.0), st.just(0), st.just(0)),
        st.tuples(
            st.just("fault"),
            st.sampled_from(list(FaultKind)),
            st.integers(1, 3),
            st.sampled_from([0, 5, 50, 1500, 4000]),
        ),
    ),
    min_size=1,
    max_size=40,
)


def _deadline_of(start: float, timeout: object) -> float:
    """The latest a call started at ``start`` with ``timeout`` may end."""
    if timeout is None:
        return start + DEFAULT_TIMEOUT
    if isinstance(timeout, bool) or not isinstance(timeout, int | float):
        return start  # refused at once
    if math.isnan(timeout) or timeout <= 0:
        return start
    return start + timeout


@dataclass
class Record:
    name: str
    start: float
    deadline: float
    ended: float = math.inf
    outcome: Any = None


@dataclass
class World:
    loop: VirtualLoop
    handler_calls: list[dict[str, Any]] = field(default_factory=list)


def _run(world: World, main: Callable[[], Coroutine[Any, Any, None]]) -> None:
    loop = world.loop
    loop.set_exception_handler(lambda _loop, context: world.handler_calls.append(context))
    try:
        loop.run_until_complete(main())
        loop.run_until_complete(loop.shutdown_asyncgens())
    finally:
        loop.close()


async def _serve_and_connect() -> tuple[FocasServer, FocasClient, NativeClient]:
    machine = default_machine()
    machine.set_panel(mode=0, pwe=1)  # MDI and PWE: parameter writes allowed
    server = FocasServer(machine, host="127.0.0.1", port=0, grace_period=0.5, idle_timeout=0)
    await server.start()
    host, port = server.listeners[0].address
    packed = FocasClient(host, port, timeout=DEFAULT_TIMEOUT, reconnect=POLICY)
    native = NativeClient(host, port, timeout=DEFAULT_TIMEOUT, reconnect=POLICY)
    await packed.connect()
    await native.connect()
    return server, packed, native


async def _valid_calls_succeed(client: Client) -> None:
    """A valid call of each kind, after the faults are gone (waiting out a reconnect)."""
    for _ in range(200):
        if client.connected:
            break
        await asyncio.sleep(0.1)
    assert client.connected, client.state
    await client.write_macro(105, Decimal("1.5"))
    assert await client.read_macro(105) == Decimal("1.5")
    assert await client.read_status() is not None
    await client.write_pmc_bit("R", 10, 3, True)
    assert await client.read_pmc_bit("R", 10, 3)
    await client.write_pmc("D", 0, bytes(range(40)))
    assert await client.read_pmc("D", 0, 40) == bytes(range(40))
    await client.write_param_bit(6711, 2, True)
    assert await client.read_param(6711) & 4
    assert isinstance(await client.read_alarms(), tuple)


def _nothing_pending(packed: FocasClient, native: NativeClient) -> None:
    assert native.idle
    assert packed.in_flight == 0


@settings(
    max_examples=60,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)
@given(steps=STEPS)
@example(  # a call made while a delayed answer closes the pair on its deadline
    steps=[
        ("call", "native", ("read_status", ()), None),
        ("fault", FaultKind.DELAY, 2, 4000),
        ("wait", 2.0, 0, 0),
        ("call", "native", ("read_alarm_history", (1,)), None),
    ]
)
def test_every_call_ends_by_its_deadline(steps: list[tuple[Any, ...]]) -> None:
    world = World(VirtualLoop())
    records: list[Record] = []

    async def main() -> None:
        loop = world.loop
        server, packed, native = await _serve_and_connect()
        clients: dict[str, Client] = {"packed": packed, "native": native}
        tasks: list[asyncio.Task[Any]] = []

        def started(record: Record, call: Awaitable[Any]) -> None:
            async def run() -> None:
                try:
                    record.outcome = await call
                except (FocasError, ValueError, TypeError) as exc:
                    record.outcome = exc
                record.ended = loop.time()

            tasks.append(loop.create_task(run()))

        faults = server.listeners[0].faults
        for step in steps:
            kind = step[0]
            if kind == "call":
                _, transport, (name, args), timeout = step
                now = loop.time()
                record = Record(name, now, _deadline_of(now, timeout))
                records.append(record)
                started(record, MENU[name][0](clients[transport], args, timeout))
            elif kind == "wait":
                await asyncio.sleep(step[1])
            else:
                _, fault, count, arg = step
                if fault is FaultKind.ERROR:
                    arg = 5
                faults.arm(Fault(fault, arg, count))
        await asyncio.wait(tasks, timeout=HORIZON) if tasks else None
        for record in records:
            assert record.ended <= record.deadline, record
            if isinstance(record.outcome, ValueError | TypeError):
                assert record.ended == record.start, record  # refused before anything else
        faults.clear()
        _nothing_pending(packed, native)
        for client in clients.values():
            await _valid_calls_succeed(client)
        _nothing_pending(packed, native)
        await packed.aclose()
        await native.aclose()
        await server.aclose()

    _run(world, main)
    assert world.handler_calls == []
    assert all(r.ended < math.inf for r in records)


# -- the two hangs of a native call given an argument the wire cannot carry --------------------


@pytest.mark.parametrize("transport", ["packed", "native"])
def test_an_argument_the_wire_cannot_carry_raises_at_once(transport: str) -> None:
    world = World(VirtualLoop())

    async def main() -> None:
        server, packed, native = await _serve_and_connect()
        client: Client = packed if transport == "packed" else native
        start = world.loop.time()
        with pytest.raises(ValueError, match="1099511627776"):
            await client.read_macro(2**40)
        assert world.loop.time() == start
        assert await client.read_macro(100) is None or True
        await packed.aclose()
        await native.aclose()
        await server.aclose()

    _run(world, main)
    assert world.handler_calls == []


@pytest.mark.parametrize("transport", ["packed", "native"])
def test_a_bad_call_behind_a_frame_in_flight_touches_nothing(transport: str) -> None:
    world = World(VirtualLoop())

    async def main() -> None:
        server, packed, native = await _serve_and_connect()
        client: Client = packed if transport == "packed" else native
        server.listeners[0].faults.arm(Fault(FaultKind.DELAY, 500, 1))  # the first answer late
        first = asyncio.ensure_future(client.read_macro(100))
        await asyncio.sleep(0.1)  # its frame is out, its answer held
        for bad in (2**40, "500", -(2**40)):
            with pytest.raises((ValueError, TypeError)):
                await client.read_macro(bad)  # type: ignore[arg-type]
        second = asyncio.ensure_future(client.read_macro(101))
        assert await first is None or True
        await second
        assert client.connected
        await packed.aclose()
        await native.aclose()
        await server.aclose()

    _run(world, main)
    assert world.handler_calls == []
