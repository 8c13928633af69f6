"""Regression tests of the client's concurrency edges, against a scripted peer.

Each test pins one path where a request id, a slot, a lock, a task or a connection could be
lost or left behind, or where the event loop could be kept busy: batches given up past the
abandoned-id limit, a reconnect whose unlock answer does not decode, a chunked read falling
back to one task per chunk, a projection whose first polls fail, a bit lock freed while its
next owner has not run yet, concurrent ``connect()`` calls, calls made between the peer's
end of stream and the loss of the connection, and calls (single or chunked) answered
``EW_PASSWD`` whose connection is lost around the unlock, and the reconnect backoff against a
server that closes every connection at once. Outcomes are asserted, never durations.
"""

from __future__ import annotations

import asyncio
import gc
from itertools import pairwise
from typing import Any

import pytest
from peers import (
    BOUND,
    RDPARAM,
    ScriptedPeer,
    assert_idle,
    connection_of,
    param_request,
    turns,
)
from support import wait_until

from focas_net.client import (
    AlarmProjection,
    ClientState,
    FocasClient,
    ProjectionMode,
    ReconnectPolicy,
)
from focas_net.client import connection as connection_module
from focas_net.client._locks import KeyedLocks
from focas_net.client.connection import NotSentError, open_connection
from focas_net.errors import (
    AccessDeniedError,
    ChunkedWriteError,
    FocasConnectionError,
    FocasTimeoutError,
)
from focas_net.protocol import Command, FrameDecoder, encode_frame

SHORT = 0.05  # a timeout meant to pass while the peer holds the answer back
FAST = ReconnectPolicy(initial_delay=0.0, max_delay=0.01, jitter=0.0)
UNLOCK = int(Command.WRUNLOCKPARAM)


class LoopErrors:
    """Records what the loop's exception handler is given (unretrieved task or future
    exceptions among them) while installed."""

    def __init__(self) -> None:
        self.contexts: list[dict[str, Any]] = []
        self._loop = asyncio.get_running_loop()
        self._before = self._loop.get_exception_handler()

    def __enter__(self) -> LoopErrors:
        self._loop.set_exception_handler(lambda _loop, ctx: self.contexts.append(ctx))
        return self

    def __exit__(self, *exc: object) -> None:
        gc.collect()  # unretrieved exceptions are reported when their task or future goes
        self._loop.set_exception_handler(self._before)

    @property
    def messages(self) -> list[str]:
        return [str(c.get("message")) for c in self.contexts]


# -- connection: ids and slots ------------------------------------------------------------------


async def test_batch_given_up_past_the_abandoned_limit_fails_cleanly(
    peer: ScriptedPeer, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A chunked read timing out gives up its chunks; when that crosses the abandoned-id
    limit the connection is recycled in the middle of the give-up loop. The caller still gets
    the timeout (not a KeyError from the bookkeeping) and no slot is leaked."""
    monkeypatch.setattr(connection_module, "MAX_ABANDONED", 3)
    async with FocasClient("127.0.0.1", peer.port, timeout=BOUND, max_in_flight=4) as client:
        c = connection_of(client)
        peer.hold = True
        with pytest.raises(FocasTimeoutError):
            await client.read_pmc("R", 0, 256, timeout=SHORT)  # 8 chunks, none answered
        assert c.closed  # recycled: more than 3 ids were left unanswered
        assert c.slots_taken == 0 and c.waiting_for_slot == 0
        assert c.in_flight == 0 and c.abandoned == 0


# -- reconnect ---------------------------------------------------------------------------------


async def test_reconnect_survives_an_unlock_answer_that_does_not_decode(
    peer: ScriptedPeer,
) -> None:
    """The unlock sent after a reconnect is answered with a payload that does not decode.
    That attempt fails like any other and the next one connects; the reconnect never dies
    leaving the client RECONNECTING for ever (which made waiting calls spin)."""
    peer.password_required = True
    async with FocasClient(
        "127.0.0.1", peer.port, timeout=BOUND, password="1234", reconnect=FAST
    ) as client:
        with LoopErrors() as errors:
            peer.hold_commands = {UNLOCK}
            peer.drop()
            await wait_until(lambda: any(f.command == UNLOCK for f, _ in peer.held), BOUND)
            peer.hold_commands = set()
            peer.release(payload=lambda f: b"\x00")  # too short for an EW code
            await wait_until(lambda: client.state is ClientState.CONNECTED, BOUND)
            assert await client.read_param(1815) == 1815
            assert len(peer.sides) >= 3  # the first, the refused unlock, the good one
        assert not any("never retrieved" in m for m in errors.messages)


async def test_a_call_waiting_for_a_reconnect_fails_when_the_policy_gives_up(
    peer: ScriptedPeer,
) -> None:
    """A call made while reconnecting waits for the next connection; when the reconnect ends
    without one (the policy gives up) the call fails with :class:`FocasConnectionError` at
    once, neither waiting for its timeout nor spinning on the wake-up that ended the wait."""
    peer.password_required = True
    once = ReconnectPolicy(initial_delay=0.0, max_delay=0.0, jitter=0.0, max_attempts=1)
    states: list[ClientState] = []
    async with FocasClient(
        "127.0.0.1",
        peer.port,
        timeout=BOUND,
        password="1234",
        reconnect=once,
        on_state_change=states.append,
    ) as client:
        peer.hold_commands = {UNLOCK}
        peer.drop()
        # the one attempt is connected and waits for the answer to its unlock
        await wait_until(lambda: any(f.command == UNLOCK for f, _ in peer.held), BOUND)
        call = asyncio.create_task(client.read_param(1))
        await turns()
        assert not call.done() and states[-1] is ClientState.RECONNECTING
        peer.drop()  # the attempt fails: the policy gives up
        with pytest.raises(FocasConnectionError, match="not connected"):
            await asyncio.wait_for(call, BOUND)
        assert client.state is ClientState.DISCONNECTED


async def test_concurrent_connects_leave_one_connection(peer: ScriptedPeer) -> None:
    """Two ``connect()`` calls at once: one connection is kept, the other is closed, and
    ``aclose()`` leaves no socket open at the peer."""
    client = FocasClient("127.0.0.1", peer.port, timeout=BOUND)
    await asyncio.gather(client.connect(), client.connect())
    assert await client.read_param(7) == 7
    await client.aclose()
    await wait_until(lambda: all(s.transport is None for s in peer.sides), BOUND)


async def test_connect_while_reconnecting_keeps_one_connection(peer: ScriptedPeer) -> None:
    """``connect()`` called while a reconnect attempt is under way: the client ends with the
    connection ``connect()`` made, the attempt's connection is closed (the reconnect ends),
    calls on the kept one are not failed by another replacing it, and ``aclose()`` leaves no
    socket open at the peer."""
    peer.password_required = True
    states: list[ClientState] = []
    client = FocasClient(
        "127.0.0.1",
        peer.port,
        timeout=4 * BOUND,  # past every wait here: only connect() can end the attempt
        password="1234",
        reconnect=FAST,
        on_state_change=states.append,
    )
    await client.connect()
    peer.hold_commands = {UNLOCK}
    peer.drop()
    # the reconnect's attempt is connected and waits for the answer to its unlock
    await wait_until(lambda: any(f.command == UNLOCK for f, _ in peer.held), BOUND)
    attempt = peer.sides[-1]
    connecting = asyncio.create_task(client.connect())
    await wait_until(lambda: len(peer.held) == 2, BOUND)
    mine = peer.held[-1][0]  # connect()'s unlock: answered; the attempt's stays unanswered
    peer.release(lambda f: f is mine)
    await asyncio.wait_for(connecting, BOUND)
    first = connection_of(client)
    await wait_until(lambda: attempt.transport is None, BOUND)  # the attempt gave up
    assert connection_of(client) is first and not first.closed
    assert await client.read_param(3) == 3
    assert states[-1] is ClientState.CONNECTED
    assert states.count(ClientState.CONNECTED) == 2  # the first connect and connect()
    await client.aclose()
    await wait_until(lambda: all(s.transport is None for s in peer.sides), BOUND)


# -- chunked reads through the per-chunk path ---------------------------------------------------


async def test_chunked_read_when_disconnected_leaves_no_unretrieved_exception(
    peer: ScriptedPeer,
) -> None:
    """Not connected: every chunk of a chunked read fails at once; the caller gets the
    connection error and no chunk's exception is left unretrieved."""
    async with FocasClient("127.0.0.1", peer.port, timeout=BOUND) as client:
        peer.drop()
        await wait_until(lambda: client.state is ClientState.DISCONNECTED, BOUND)
        with LoopErrors() as errors:
            for _ in range(3):
                with pytest.raises(FocasConnectionError):
                    await client.read_pmc("R", 0, 200)
            await turns()
        assert not any("never retrieved" in m for m in errors.messages), errors.messages


# -- bit locks -----------------------------------------------------------------------------------


async def test_bit_lock_wait_keeps_its_deadline_in_the_hand_over_window() -> None:
    """A lock just handed to a waiter that has not run yet looks free. A caller asking for it
    in that window (here the previous holder, asking again in the same step, as a loop of bit
    writes to one byte does) must still wait within its deadline, not until the lock is free."""
    locks: KeyedLocks[int] = KeyedLocks()
    loop = asyncio.get_running_loop()
    first_in = asyncio.Event()
    release_first = asyncio.Event()
    second_in = asyncio.Event()
    release_second = asyncio.Event()

    async def first_then_again() -> None:
        async with locks.hold(1, None):
            first_in.set()
            await release_first.wait()
        # same step: the lock has just been handed to the second holder, which has not run
        async with locks.hold(1, loop.time() + SHORT):
            pass

    async def second_holder() -> None:
        async with locks.hold(1, None):
            second_in.set()
            await release_second.wait()

    first = asyncio.create_task(first_then_again())
    await first_in.wait()
    second = asyncio.create_task(second_holder())
    await turns()  # the second holder waits in the lock's line
    release_first.set()
    await second_in.wait()
    done, _ = await asyncio.wait([first], timeout=BOUND)  # a safety net, not a measurement
    try:
        assert done, "the caller waited for the lock past its deadline"
        with pytest.raises(FocasTimeoutError):
            first.result()
        assert not second.done()  # it still holds the lock
    finally:
        release_second.set()
        await asyncio.gather(first, second, return_exceptions=True)
    assert len(locks) == 0


# -- projection ----------------------------------------------------------------------------------


async def test_projection_waits_a_tick_after_a_failed_first_poll(peer: ScriptedPeer) -> None:
    """The first polls fail (client not connected): the projection waits ``interval`` before
    trying again instead of polling in a loop (which, with calls failing without suspending,
    froze the event loop)."""
    async with FocasClient("127.0.0.1", peer.port, timeout=BOUND) as client:
        peer.drop()
        await wait_until(lambda: client.state is ClientState.DISCONNECTED, BOUND)
        projection = AlarmProjection(client, ProjectionMode.ACTIVE, interval=3600.0)
        original = client.read_alarms

        async def bounded(**kwargs: Any) -> Any:
            if projection.failed_polls > 50:
                projection.stop()  # let a spinning projection end so that the test can fail
            return await original(**kwargs)

        client.read_alarms = bounded  # type: ignore[method-assign]
        consumer = asyncio.create_task(anext(projection, None))
        await turns(20)
        try:
            assert projection.failed_polls == 1
            assert not consumer.done()
        finally:
            projection.stop()
            assert await asyncio.wait_for(consumer, BOUND) is None


# -- end of stream -------------------------------------------------------------------------------


async def test_call_after_the_peers_end_of_stream_is_not_sent(peer: ScriptedPeer) -> None:
    """A request made after the peer ended its stream but before the connection is reported
    lost never reaches the peer: it fails with :class:`NotSentError` (safe to resend), not
    with the error of a request that may have been sent."""
    c = await open_connection("127.0.0.1", peer.port)
    late: list[asyncio.Task[bytes]] = []
    original = c.eof_received

    def eof() -> bool | None:
        late.append(asyncio.create_task(c.request(RDPARAM, param_request(11), None)))
        return original()

    c.eof_received = eof  # type: ignore[method-assign]
    try:
        side = peer.sides[0]
        assert side.transport is not None
        side.transport.write_eof()
        await wait_until(lambda: bool(late), BOUND)
        with pytest.raises(NotSentError):
            await asyncio.wait_for(late[0], BOUND)
    finally:
        c.close()
        await c.wait_closed()
    assert c.slots_taken == 0
    assert not peer.received


async def test_call_after_end_of_stream_goes_out_after_the_reconnect(peer: ScriptedPeer) -> None:
    async with FocasClient("127.0.0.1", peer.port, timeout=BOUND, reconnect=FAST) as client:
        c = connection_of(client)
        late: list[asyncio.Task[int]] = []
        original = c.eof_received

        def eof() -> bool | None:
            late.append(asyncio.create_task(client.read_param(12)))
            return original()

        c.eof_received = eof  # type: ignore[method-assign]
        side = peer.sides[0]
        assert side.transport is not None
        side.transport.write_eof()
        await wait_until(lambda: bool(late), BOUND)
        assert await asyncio.wait_for(late[0], BOUND) == 12
        assert_idle(connection_of(client))


# -- EW_PASSWD retried across a reconnect --------------------------------------------------------

WRPMCRNG = int(Command.WRPMCRNG)


def _lose_after_next_answer(client: FocasClient) -> None:
    """Abort the client's connection right after it receives its next answer, before the
    caller runs again: whatever the caller sends next on it is never sent."""
    c = connection_of(client)
    original = c.data_received

    def received(data: bytes | bytearray | memoryview) -> None:
        original(data)
        c.data_received = original  # type: ignore[method-assign]
        c.abort()

    c.data_received = received  # type: ignore[method-assign]


@pytest.mark.parametrize("unlock_sent", [False, True])
async def test_ew_passwd_retry_goes_through_the_reconnect(
    peer: ScriptedPeer, unlock_sent: bool
) -> None:
    """A call answered ``EW_PASSWD`` whose connection is lost before (or while) its unlock is
    sent: with reconnect on it waits for the new connection, which the reconnect unlocks, and
    is retried there once, instead of failing with the lost connection's error."""
    peer.password_required = True
    async with FocasClient(
        "127.0.0.1", peer.port, timeout=BOUND, password="1234", reconnect=FAST
    ) as client:
        peer.unlocked = False  # as if the CNC had locked again
        if unlock_sent:
            peer.hold_commands = {UNLOCK}
        else:
            _lose_after_next_answer(client)
        write = asyncio.create_task(client.write_pmc("R", 5, b"\x07\x08"))
        if unlock_sent:
            await wait_until(lambda: any(f.command == UNLOCK for f, _ in peer.held), BOUND)
            peer.hold_commands = set()
            peer.drop()  # the unlock left but is never answered
        await asyncio.wait_for(write, BOUND)  # raises if the write failed
        assert bytes(peer.pmc[5:7]) == b"\x07\x08"
        assert len(peer.sides) == 2
        writes = [f for f in peer.received if f.command == WRPMCRNG]
        assert len(writes) == 2  # refused once, then retried once on the new connection
        assert_idle(connection_of(client))


async def test_ew_passwd_retry_is_tried_once_across_a_reconnect(peer: ScriptedPeer) -> None:
    """The retry on the new connection is the only one: refused again (the reconnect's
    unlock was refused too), the call raises ``EW_PASSWD``."""
    peer.password_required = True
    async with FocasClient(
        "127.0.0.1", peer.port, timeout=BOUND, password="1234", reconnect=FAST
    ) as client:
        peer.unlocked = False
        peer.password = b"9999"  # every later unlock is refused
        _lose_after_next_answer(client)
        with pytest.raises(AccessDeniedError):
            await client.write_pmc("R", 5, b"\x07", timeout=BOUND)
        assert len([f for f in peer.received if f.command == WRPMCRNG]) == 2
        assert bytes(peer.pmc[5:6]) == b"\x00"


async def test_ew_passwd_retry_without_reconnect_keeps_the_loss(peer: ScriptedPeer) -> None:
    peer.password_required = True
    async with FocasClient("127.0.0.1", peer.port, timeout=BOUND, password="1234") as client:
        peer.unlocked = False
        _lose_after_next_answer(client)
        with pytest.raises(NotSentError):
            await client.write_pmc("R", 5, b"\x07")
        assert len([f for f in peer.received if f.command == WRPMCRNG]) == 1
        assert peer.unlocks == 1  # only the one of the first connect


@pytest.mark.parametrize("unlock_sent", [False, True])
async def test_chunked_write_resends_refused_chunks_after_the_reconnect(
    peer: ScriptedPeer, unlock_sent: bool
) -> None:
    """Every chunk of a chunked write is answered ``EW_PASSWD`` and the connection is lost
    before (or while) the unlock is sent: with reconnect on the chunks go out again on the
    new connection (unlocked by the reconnect) and the write succeeds."""
    peer.password_required = True
    async with FocasClient(
        "127.0.0.1", peer.port, timeout=BOUND, max_in_flight=4, password="1234", reconnect=FAST
    ) as client:
        peer.unlocked = False
        data = bytes(range(1, 129))  # four chunks
        if unlock_sent:
            peer.hold_commands = {UNLOCK}
        else:
            c = connection_of(client)
            original = c.data_received
            answered = 0

            def received(data: bytes | bytearray | memoryview) -> None:
                nonlocal answered
                waiting = c.in_flight
                original(data)
                answered += waiting - c.in_flight
                if answered >= 4:  # every chunk answered: lost before the unlock leaves
                    c.data_received = original  # type: ignore[method-assign]
                    c.abort()

            c.data_received = received  # type: ignore[method-assign]
        write = asyncio.create_task(client.write_pmc("R", 0, data))
        if unlock_sent:
            await wait_until(lambda: any(f.command == UNLOCK for f, _ in peer.held), BOUND)
            peer.hold_commands = set()
            peer.drop()
        await asyncio.wait_for(write, BOUND)  # raises if the write failed
        assert bytes(peer.pmc[:128]) == data
        assert len(peer.sides) == 2
        assert len([f for f in peer.received if f.command == WRPMCRNG]) == 8  # each twice
        assert_idle(connection_of(client))


async def test_chunked_write_refused_chunks_not_written_without_reconnect(
    peer: ScriptedPeer,
) -> None:
    peer.password_required = True
    async with FocasClient(
        "127.0.0.1", peer.port, timeout=BOUND, max_in_flight=4, password="1234"
    ) as client:
        peer.unlocked = False
        peer.hold_commands = {UNLOCK}
        write = asyncio.create_task(client.write_pmc("R", 0, bytes(range(1, 129))))
        await wait_until(lambda: any(f.command == UNLOCK for f, _ in peer.held), BOUND)
        peer.drop()
        with pytest.raises(ChunkedWriteError) as info:
            await asyncio.wait_for(write, BOUND)
        err = info.value
        assert err.not_written == [(0, 127)] and err.written == [] and err.uncertain == []
        assert isinstance(err.cause, FocasConnectionError)
        assert bytes(peer.pmc[:128]) == bytes(128)


# -- reconnect backoff against a server that closes at once ---------------------------------------


Event = tuple[str, int | ClientState]  # ("attempt", backoff step) or ("state", new state)


class RecordedPolicy(ReconnectPolicy):
    """A policy that records ``("attempt", n)`` into ``events`` for every delay it is asked
    for and waits no time at all (the sequence of ``n`` is the backoff, without a clock)."""

    events: list[Event]

    def delay(self, attempt: int) -> float:
        self.events.append(("attempt", attempt))
        return 0.0


async def _record_reconnects(stable_after: float, attempts: int) -> list[Event]:
    """Connect to a server whose first connection stays up until dropped and whose later ones
    answer their first request (EW_FUNC, as a server without simulator control answers the
    reconnect's own request) and are closed right after; return the reconnect attempts and
    state changes seen until ``attempts`` attempts were made."""
    loop = asyncio.get_running_loop()
    accepted: list[asyncio.Transport] = []

    class Closer(asyncio.Protocol):
        def connection_made(self, transport: asyncio.BaseTransport) -> None:
            assert isinstance(transport, asyncio.Transport)
            accepted.append(transport)
            self.transport = transport
            self.frames = FrameDecoder()

        def data_received(self, data: bytes) -> None:
            for frame in self.frames.feed(data):
                if len(accepted) > 1:  # answered, then closed at once
                    self.transport.write(encode_frame(frame.command, frame.request_id, b"\x01\x00"))
                    self.transport.close()

    server = await loop.create_server(Closer, "127.0.0.1", 0)
    port = server.sockets[0].getsockname()[1]
    policy = RecordedPolicy(initial_delay=0.01, jitter=0.0, stable_after=stable_after)
    events: list[Event] = []
    object.__setattr__(policy, "events", events)
    client = FocasClient(
        "127.0.0.1",
        port,
        timeout=BOUND,
        reconnect=policy,
        on_state_change=lambda s: events.append(("state", s)),
    )
    try:
        await client.connect()
        accepted[0].abort()  # the first connection is lost: the policy starts
        await wait_until(lambda: sum(kind == "attempt" for kind, _ in events) >= attempts, BOUND)
    finally:
        await client.aclose()
        for transport in accepted:
            transport.abort()
        server.close()
        await server.wait_closed()
    return events


async def test_backoff_goes_on_while_connections_close_at_once() -> None:
    """Every reconnect is accepted, answered once and closed: the backoff is not reset by
    those short connections, so the delays grow (up to ``max_delay``) instead of the server
    being retried every ``initial_delay`` for ever."""
    events = await _record_reconnects(stable_after=3600.0, attempts=6)
    steps = [n for _, n in events if isinstance(n, int)]
    assert steps[:6] == [0, 1, 2, 3, 4, 5]
    assert sum(s is ClientState.CONNECTED for kind, s in events if kind == "state") >= 3
    plain = ReconnectPolicy(initial_delay=0.01, jitter=0.0)
    delays = [plain.delay(n) for n in steps[:6]]
    assert all(a < b for a, b in pairwise(delays))


async def test_backoff_resets_after_a_stable_connection() -> None:
    """With ``stable_after=0`` every connection counts as stable: each loss of a connection
    that was up starts the backoff again from its first step."""
    events = await _record_reconnects(stable_after=0.0, attempts=6)
    after_loss = [
        events[i + 1][1]
        for i, (kind, state) in enumerate(events[:-1])
        if kind == "state" and state is ClientState.RECONNECTING and events[i + 1][0] == "attempt"
    ]
    assert len(after_loss) >= 3
    assert set(after_loss) == {0}


def test_stable_after_is_validated() -> None:
    assert ReconnectPolicy().stable_after == 5.0
    assert ReconnectPolicy(stable_after=0.0).stable_after == 0.0
    for bad in (-1.0, float("nan")):
        with pytest.raises(ValueError, match="stable_after"):
            ReconnectPolicy(stable_after=bad)
