"""The client's connection machinery, driven step by step against a scripted peer.

The scripted peer of ``peers.py`` records every frame (and which frames arrived in one
receive), holds answers back when told and answers them in any order, with any payload, or
drops the connection. The tests check outcomes and ordering, never durations:

* the one deadline timer of a connection with mixed per-call timeouts;
* late answers to abandoned requests (a timeout, a refused chunk) dropped, never handed to
  another call (the ids themselves: ``test_connection_ids.py``);
* request slots handed over in FIFO order, and never leaked by cancelled or timed-out waiters;
* chunked PMC reads and writes leaving as one batch in one write, and their failure semantics
  (:class:`CncError` for a read, :class:`ChunkedWriteError` ranges for a write);
* :class:`FrameDecoder` fed ``bytearray`` and ``memoryview`` chunks.
"""

from __future__ import annotations

import asyncio
import random
import time
from collections.abc import AsyncIterator, Callable
from typing import Any

import pytest
from peers import (
    BOUND,
    RDPARAM,
    LoggedConnection,
    ScriptedPeer,
    WriteLog,
    assert_idle,
    connection_of,
    param_request,
    turns,
)
from support import IO_TIMEOUT, serving, wait_until

from focas_net.client import ClientState, FocasClient, ReconnectPolicy
from focas_net.client import connection as connection_module
from focas_net.client._lifecycle import clock_of
from focas_net.client.connection import WRITE_CHUNK, Connection, NotSentError, open_connection
from focas_net.errors import (
    EW,
    AccessDeniedError,
    ChunkedWriteError,
    CncError,
    FocasConnectionError,
    FocasTimeoutError,
)
from focas_net.protocol import (
    COMMANDS,
    Command,
    EwReply,
    Frame,
    FrameDecoder,
    ParamValue,
    encode_frame,
)

SHORT = 0.05  # a timeout meant to pass while the peer holds the answer back
RDPMCRNG = int(Command.RDPMCRNG)
WRPMCRNG = int(Command.WRPMCRNG)


def _is(frame: Frame) -> Callable[[Frame], bool]:
    """A predicate matching exactly ``frame``."""
    return lambda f: f is frame


@pytest.fixture
async def conn(peer: ScriptedPeer) -> AsyncIterator[Connection]:
    c = await open_connection("127.0.0.1", peer.port, max_in_flight=4)
    try:
        yield c
    finally:
        c.close()
        await c.wait_closed()


def log_writes(monkeypatch: pytest.MonkeyPatch) -> None:
    """Connections opened from now on record their writes (:func:`writes_of`)."""
    monkeypatch.setattr(connection_module, "Connection", LoggedConnection)


def writes_of(client: FocasClient) -> WriteLog:
    """The writes of ``client``'s connection, opened after :func:`log_writes`."""
    c = connection_of(client)
    assert isinstance(c, LoggedConnection)
    return c.log


def param_number(frame: Frame) -> int:
    return int(COMMANDS[Command.RDPARAM].request.decode(frame.payload).datano)


def param_value(answer: bytes) -> int:
    return int(COMMANDS[Command.RDPARAM].response.decode(answer).value)


def deadline(seconds: float) -> float:
    return asyncio.get_running_loop().time() + seconds


async def ask(c: Connection, number: int, seconds: float | None = BOUND) -> int:
    """One RDPARAM on ``c``; returns the value the peer answered."""
    when = None if seconds is None else deadline(seconds)
    return param_value(await c.request(RDPARAM, param_request(number), when))


async def assert_bound_is(c: Connection, peer: ScriptedPeer, n: int) -> None:
    """Exactly ``n`` calls go out at once on ``c``; every one of ``n + 2`` calls succeeds."""
    assert_idle(c)
    peer.hold = True
    first = len(peer.received)
    tasks = [asyncio.create_task(ask(c, 9000 + i)) for i in range(n + 2)]
    await peer.wait_received(first + n)
    await turns()
    assert len(peer.received) == first + n
    assert c.in_flight == n and c.waiting_for_slot == 2
    peer.hold = False  # the two waiting calls are answered as soon as they are sent
    peer.release()
    async with asyncio.timeout(BOUND):
        assert await asyncio.gather(*tasks) == [9000 + i for i in range(n + 2)]
    assert_idle(c)


# -- the deadline timer -------------------------------------------------------------------------


async def test_short_timeout_behind_long_ones_times_out_first(
    peer: ScriptedPeer, conn: Connection
) -> None:
    peer.hold = True
    long_a = asyncio.create_task(ask(conn, 1, BOUND))
    no_deadline = asyncio.create_task(ask(conn, 2, None))
    short = asyncio.create_task(ask(conn, 3, SHORT))  # behind a later deadline: timer moved
    long_b = asyncio.create_task(ask(conn, 4, 2 * BOUND))
    await peer.wait_received(4)
    with pytest.raises(FocasTimeoutError):
        await short
    assert not long_a.done() and not long_b.done() and not no_deadline.done()
    assert conn.abandoned == 1 and conn.in_flight == 3
    peer.release()  # every answer, the late one to the short call included
    assert list(await asyncio.gather(long_a, no_deadline, long_b)) == [1, 2, 4]
    assert_idle(conn)


async def test_mixed_timeouts_fail_only_the_overdue(peer: ScriptedPeer) -> None:
    peer.hold = True
    c = await open_connection("127.0.0.1", peer.port, max_in_flight=64)
    try:
        timeouts = [BOUND, SHORT, 2 * BOUND, SHORT / 2, BOUND, 2 * SHORT, None, SHORT]
        tasks = [asyncio.create_task(ask(c, n, t)) for n, t in enumerate(timeouts)]
        await peer.wait_received(len(timeouts))
        short = [t for t, s in zip(tasks, timeouts, strict=True) if s is not None and s < 1]
        long = [t for t in tasks if t not in short]
        for task in short:
            with pytest.raises(FocasTimeoutError):
                await task
        assert not any(t.done() for t in long)
        assert c.abandoned == len(short)
        # the timer is re-armed: a new short call behind all of them still times out
        with pytest.raises(FocasTimeoutError):
            await ask(c, 99, SHORT)
        peer.release()
        async with asyncio.timeout(BOUND):
            values = await asyncio.gather(*long)
        assert values == [n for n, t in enumerate(timeouts) if t is None or t >= 1]
        await wait_until(lambda: c.abandoned == 0, within=BOUND)
        assert_idle(c)
    finally:
        c.close()
        await c.wait_closed()


# -- request slots ------------------------------------------------------------------------------


async def test_waiters_get_slots_in_fifo_order(peer: ScriptedPeer, conn: Connection) -> None:
    peer.hold = True
    running = [asyncio.create_task(ask(conn, n)) for n in range(4)]  # max_in_flight=4
    await peer.wait_received(4)
    waiters = []
    for n in range(10, 20):
        waiters.append(asyncio.create_task(ask(conn, n)))
        await turns(1)
    await wait_until(lambda: conn.waiting_for_slot == 10, within=BOUND)
    assert len(peer.received) == 4
    # answer one request at a time: each answer lets exactly the next waiter in
    for expected in range(10, 20):
        oldest = peer.held[0][0]

        peer.release(_is(oldest))
        await peer.wait_received(4 + expected - 9)
        await turns()
        assert param_number(peer.received[-1]) == expected
        assert len(peer.received) == 4 + expected - 9
    peer.release()
    assert await asyncio.gather(*running) == list(range(4))
    assert await asyncio.gather(*waiters) == list(range(10, 20))
    await assert_bound_is(conn, peer, 4)


async def ask_then_cancel(c: Connection, number: int, victim: list[asyncio.Task[int]]) -> int:
    """``ask``, then cancel ``victim[0]`` in the same step: the slot this call released was
    handed to the first waiter in line, which has not run yet."""
    value = await ask(c, number)
    assert c.slots_taken == c.in_flight + 1  # a slot handed over, its request not sent yet
    victim[0].cancel()
    return value


async def test_cancelled_waiters_never_leak_a_slot(peer: ScriptedPeer, conn: Connection) -> None:
    peer.hold = True
    victim: list[asyncio.Task[int]] = []
    running = [asyncio.create_task(ask_then_cancel(conn, 0, victim))]
    running += [asyncio.create_task(ask(conn, n)) for n in range(1, 4)]
    await peer.wait_received(4)
    waiters = [asyncio.create_task(ask(conn, n)) for n in range(10, 16)]
    await wait_until(lambda: conn.waiting_for_slot == 6, within=BOUND)
    # cancelled before being handed a slot
    for i in (0, 2):
        waiters[i].cancel()
    for i in (0, 2):
        with pytest.raises(asyncio.CancelledError):
            await waiters[i]
    assert conn.waiting_for_slot == 4
    # cancelled after being handed a slot, before it could use it (10 and 12 are gone, so
    # 11 is first in line when the answer to 0 frees a slot)
    victim.append(waiters[1])
    peer.release(lambda f: param_number(f) == 0)
    assert await running[0] == 0
    with pytest.raises(asyncio.CancelledError):
        await waiters[1]
    await peer.wait_received(5)
    assert param_number(peer.received[-1]) == 13  # the slot went on to the next in line
    peer.hold = False
    peer.release()
    async with asyncio.timeout(BOUND):
        assert await asyncio.gather(*running[1:]) == [1, 2, 3]
        assert await asyncio.gather(*waiters[3:]) == [13, 14, 15]
    sent = {param_number(f) for f in peer.received}
    assert sent.isdisjoint({10, 11, 12})  # no cancelled waiter was sent
    await assert_bound_is(conn, peer, 4)


async def test_cancelled_waiters_with_a_deadline_pass_the_slot_on(
    peer: ScriptedPeer, conn: Connection
) -> None:
    """The same hand-over, for a waiter whose wait runs under a deadline and one without."""
    for seconds in (BOUND, None):
        peer.hold = True
        first = len(peer.received)
        victim: list[asyncio.Task[int]] = []
        running = [asyncio.create_task(ask_then_cancel(conn, 0, victim))]
        running += [asyncio.create_task(ask(conn, n)) for n in range(1, 4)]
        await peer.wait_received(first + 4)
        victim.append(asyncio.create_task(ask(conn, 10, seconds)))
        heir = asyncio.create_task(ask(conn, 11, seconds))
        await wait_until(lambda: conn.waiting_for_slot == 2, within=BOUND)
        peer.release(lambda f: param_number(f) == 0)
        with pytest.raises(asyncio.CancelledError):
            await victim[0]
        await peer.wait_received(first + 5)
        assert param_number(peer.received[-1]) == 11
        peer.hold = False
        peer.release()
        async with asyncio.timeout(BOUND):
            assert await heir == 11
            assert await asyncio.gather(*running) == [0, 1, 2, 3]
        await assert_bound_is(conn, peer, 4)


async def test_waiter_timing_out_for_a_slot_leaks_nothing(
    peer: ScriptedPeer, conn: Connection
) -> None:
    peer.hold = True
    running = [asyncio.create_task(ask(conn, n)) for n in range(4)]
    await peer.wait_received(4)
    behind = asyncio.create_task(ask(conn, 11))  # waits without a short deadline
    with pytest.raises(FocasTimeoutError, match="no free request slot"):
        await ask(conn, 10, SHORT)
    assert len(peer.received) == 4  # never sent
    assert conn.abandoned == 0 and conn.waiting_for_slot == 1
    peer.hold = False
    peer.release()
    assert await asyncio.gather(*running) == [0, 1, 2, 3]
    assert await behind == 11
    await assert_bound_is(conn, peer, 4)


async def test_slot_storm_with_random_cancellations(peer: ScriptedPeer, conn: Connection) -> None:
    rng = random.Random(4242)
    peer.hold = True
    tasks = [asyncio.create_task(ask(conn, n)) for n in range(60)]
    await peer.wait_received(4)
    cancelled: set[int] = set()
    for _ in range(300):  # bounded: each round answers or cancels something
        if all(t.done() for t in tasks):
            break
        pick = rng.random()
        live = [i for i, t in enumerate(tasks) if not t.done() and i not in cancelled]
        if pick < 0.3 and live:
            i = rng.choice(live)
            tasks[i].cancel()
            cancelled.add(i)
        elif peer.held:
            peer.release(_is(peer.held[0][0]))
        await turns(rng.choice([0, 1, 3]))
        if not peer.held and not all(t.done() for t in tasks):
            await wait_until(lambda: bool(peer.held) or all(t.done() for t in tasks), within=BOUND)
    peer.hold = False
    peer.release()
    async with asyncio.timeout(BOUND):
        results = await asyncio.gather(*tasks, return_exceptions=True)
    assert len(cancelled) > 5
    for i, result in enumerate(results):
        if isinstance(result, asyncio.CancelledError):
            assert i in cancelled
        else:
            assert result == i  # every call got its own answer
    await wait_until(lambda: conn.abandoned == 0, within=BOUND)
    await assert_bound_is(conn, peer, 4)


# -- chunked reads: one batch -------------------------------------------------------------------


async def test_calls_of_one_turn_leave_in_writes_of_at_most_write_chunk_frames(
    peer: ScriptedPeer, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A lone call is written at once; the calls made in one loop turn while it is in flight
    leave in writes of WRITE_CHUNK frames, in order, and every one gets its own answer."""
    log_writes(monkeypatch)
    async with FocasClient("127.0.0.1", peer.port, timeout=BOUND, max_in_flight=64) as client:
        counting = writes_of(client)
        peer.hold = True
        first = asyncio.create_task(client.read_param_value(9000))
        await peer.wait_received(1)
        assert counting.writes == 1
        more = 2 * WRITE_CHUNK + 3
        tasks = [asyncio.create_task(client.read_param_value(9001 + i)) for i in range(more)]
        await peer.wait_received(1 + more)
        assert counting.writes == 1 + 3  # two full writes, then the rest at the turn's end
        assert [param_number(f) for f in peer.received] == list(range(9000, 9001 + more))
        peer.hold = False
        peer.release()
        async with asyncio.timeout(BOUND):
            values = await asyncio.gather(first, *tasks)
        assert [v.value for v in values] == list(range(9000, 9001 + more))
        assert_idle(connection_of(client))


@pytest.fixture
async def client(peer: ScriptedPeer) -> AsyncIterator[FocasClient]:
    async with FocasClient("127.0.0.1", peer.port, timeout=BOUND, max_in_flight=4) as c:
        yield c


@pytest.fixture
async def logged_client(
    peer: ScriptedPeer, monkeypatch: pytest.MonkeyPatch
) -> AsyncIterator[FocasClient]:
    """A client like ``client``'s whose connection records its writes (:func:`writes_of`)."""
    log_writes(monkeypatch)
    async with FocasClient("127.0.0.1", peer.port, timeout=BOUND, max_in_flight=4) as c:
        yield c


async def test_chunked_read_leaves_in_one_write(
    peer: ScriptedPeer, logged_client: FocasClient
) -> None:
    client = logged_client
    peer.pmc[:] = random.Random(1).randbytes(len(peer.pmc))
    counting = writes_of(client)
    assert await client.read_pmc("D", 0, 128) == bytes(peer.pmc[:128])
    assert counting.writes == 1
    assert [len(r) for r in peer.receives] == [4]  # 4 frames in one receive
    first = len(peer.received)
    assert await client.read_pmc("D", 0, 4096) == bytes(peer.pmc)
    assert counting.writes == 2
    assert len(peer.received) - first == 128
    assert_idle(connection_of(client))


async def test_chunked_read_frames_arrive_before_any_answer(
    peer: ScriptedPeer, client: FocasClient
) -> None:
    await client.read_pmc("R", 0, 100)
    chunk_frames = [i for i, f in enumerate(peer.received) if f.command == RDPMCRNG]
    assert len(chunk_frames) == 4
    assert {peer.answered_before[i] for i in chunk_frames} == {0}


async def test_refused_chunk_fails_the_read_and_late_answers_are_dropped(
    peer: ScriptedPeer, client: FocasClient
) -> None:
    peer.hold = True
    read = asyncio.create_task(client.read_pmc("D", 0, 128))
    await peer.wait_received(4)
    ids = {f.request_id for f in peer.received}
    busy = COMMANDS[Command.RDPMCRNG].response.encode(EwReply(EW.BUSY))
    peer.release(lambda f: f is peer.received[2], lambda f: busy)
    with pytest.raises(CncError) as info:
        await read
    assert info.value.ew == EW.BUSY
    c = connection_of(client)
    assert c.abandoned == 3 and c.in_flight == 0
    other = asyncio.create_task(client.read_param(5))
    await peer.wait_received(5)
    assert peer.received[-1].request_id not in ids
    peer.release(lambda f: f.command == RDPMCRNG)  # the late answers
    await wait_until(lambda: c.abandoned == 0, within=BOUND)
    await turns()
    assert not other.done()
    peer.release()
    assert await other == 5
    assert_idle(c)


async def test_chunked_read_timeout(peer: ScriptedPeer, client: FocasClient) -> None:
    peer.hold = True
    with pytest.raises(FocasTimeoutError):
        await client.read_pmc("D", 0, 128, timeout=SHORT)
    c = connection_of(client)
    assert c.abandoned == 4 and c.in_flight == 0
    peer.hold = False
    peer.release()
    await wait_until(lambda: c.abandoned == 0, within=BOUND)
    assert await client.read_pmc("D", 0, 128) == bytes(128)
    assert_idle(c)


async def test_chunked_read_with_some_chunks_answered_then_timeout(
    peer: ScriptedPeer, client: FocasClient
) -> None:
    peer.hold = True
    read = asyncio.create_task(client.read_pmc("D", 0, 128, timeout=SHORT * 2))
    await peer.wait_received(4)
    peer.release(lambda f: f in peer.received[:2])
    with pytest.raises(FocasTimeoutError):
        await read
    c = connection_of(client)
    assert c.abandoned == 2
    peer.hold = False
    peer.release()
    await wait_until(lambda: c.abandoned == 0, within=BOUND)
    assert_idle(c)


async def test_bound_holds_around_a_batch(peer: ScriptedPeer, client: FocasClient) -> None:
    c = connection_of(client)
    peer.hold = True
    # every slot taken: the batch waits in line like one call
    calls = [asyncio.create_task(client.read_param(n)) for n in range(4)]
    await peer.wait_received(4)
    read = asyncio.create_task(client.read_pmc("D", 0, 256))  # 8 chunks
    await wait_until(lambda: c.waiting_for_slot == 1, within=BOUND)
    await turns()
    assert len(peer.received) == 4
    peer.release()
    assert await asyncio.gather(*calls) == [0, 1, 2, 3]
    await peer.wait_received(12)  # the 8 chunks, at once
    # while the batch is over the bound, nothing else is admitted
    late = asyncio.create_task(client.read_param(50))
    await turns()
    assert len(peer.received) == 12 and c.waiting_for_slot == 1
    peer.release()
    assert await read == bytes(256)
    await peer.wait_received(13)
    peer.release()
    assert await late == 50
    await assert_bound_is(c, peer, 4)


async def test_request_all_of_nothing_returns_at_once(conn: Connection) -> None:
    assert await conn.request_all(RDPARAM, [], deadline(BOUND)) == []
    assert await conn.request_each(RDPARAM, [], deadline(BOUND)) == []
    assert_idle(conn)


# -- the frame decoder ------------------------------------------------------------------------


def test_frame_decoder_accepts_bytearray_and_memoryview_chunks() -> None:
    frames = [(RDPARAM, i, bytes(range(i % 7)) * 3) for i in range(20)]
    wire = b"".join(encode_frame(c, i, p) for c, i, p in frames)
    for step in (1, 3, 8, 13, 64, len(wire)):
        for kind in ("bytearray", "memoryview"):
            decoder = FrameDecoder()
            got: list[Frame] = []
            for pos in range(0, len(wire), step):
                buf = bytearray(wire[pos : pos + step])
                if kind == "bytearray":
                    got += decoder.feed(buf)
                else:
                    with memoryview(buf) as view:
                        got += decoder.feed(view)
                buf[:] = bytes(len(buf))  # the caller reuses its buffer
            assert [(f.command, f.request_id, f.payload) for f in got] == frames, (step, kind)
            assert all(type(f.payload) is bytes for f in got)
            assert decoder.buffered == 0


def test_frame_decoder_copies_out_of_a_reused_buffer() -> None:
    wire = encode_frame(RDPARAM, 1, b"abcdef") + encode_frame(RDPARAM, 2, b"ghij")
    buffer = bytearray(wire[:15])  # the first frame whole and 1 byte of the second
    decoder = FrameDecoder()
    first = decoder.feed(memoryview(buffer))
    buffer[:] = bytes(len(buffer))  # the caller overwrites its buffer
    rest = decoder.feed(bytearray(wire[15:]))
    assert [(f.request_id, f.payload) for f in first + rest] == [(1, b"abcdef"), (2, b"ghij")]


async def test_connection_decodes_answers_fed_as_bytearray_and_memoryview(
    peer: ScriptedPeer, conn: Connection
) -> None:
    peer.hold_commands = {RDPARAM}
    tasks = [asyncio.create_task(ask(conn, n)) for n in (1, 2)]
    await peer.wait_received(2)
    spec = COMMANDS[Command.RDPARAM].response
    a, b = (
        encode_frame(RDPARAM, f.request_id, spec.encode(ParamValue(100 + i, 0, 100 + i, 4)))
        for i, f in enumerate(peer.received)
    )
    conn.data_received(bytearray(a[:5]))
    conn.data_received(memoryview(a[5:] + b[:9]))
    conn.data_received(bytearray(b[9:]))
    assert await asyncio.gather(*tasks) == [100, 101]
    peer.held.clear()
    assert_idle(conn)


# -- chunked writes: one batch ------------------------------------------------------------------


async def test_chunked_write_leaves_in_one_write_without_tasks(
    peer: ScriptedPeer, logged_client: FocasClient
) -> None:
    client = logged_client
    data = random.Random(2).randbytes(4096)
    counting = writes_of(client)
    peer.hold = True
    before = len(asyncio.all_tasks())
    write = asyncio.create_task(client.write_pmc("D", 0, data))
    await peer.wait_received(128)
    assert len(asyncio.all_tasks()) == before + 1  # the write itself, no task per chunk
    assert counting.writes == 1
    peer.hold = False
    peer.release()
    await write
    assert bytes(peer.pmc) == data
    await client.write_pmc("D", 0, data[:100])
    assert counting.writes == 2
    assert len(peer.receives[-1]) == 4 and peer.receives[-1][0].command == WRPMCRNG
    assert_idle(connection_of(client))


async def test_chunked_write_waits_for_every_chunk_and_names_the_refused_one(
    peer: ScriptedPeer, client: FocasClient
) -> None:
    peer.refuse[32] = EW.BUSY
    peer.hold = True
    write = asyncio.create_task(client.write_pmc("R", 0, bytes(range(1, 129))))
    await peer.wait_received(4)
    peer.release(lambda f: f is peer.received[1])  # the refusal comes first
    await turns()
    assert not write.done()  # unlike a read, a write waits for every chunk
    peer.release()
    with pytest.raises(ChunkedWriteError) as info:
        await write
    err = info.value
    assert err.written == [(0, 31), (64, 127)]
    assert err.not_written == [(32, 63)]
    assert err.uncertain == []
    assert isinstance(err.cause, CncError) and err.cause.ew == EW.BUSY
    assert bytes(peer.pmc[:128]) == bytes(range(1, 33)) + bytes(32) + bytes(range(65, 129))
    assert_idle(connection_of(client))


async def test_chunked_write_cause_is_the_first_failing_chunk(
    peer: ScriptedPeer, client: FocasClient
) -> None:
    peer.refuse.update({64: EW.NUMBER, 32: EW.BUSY})
    peer.hold = True
    write = asyncio.create_task(client.write_pmc("R", 0, bytes(160)))
    await peer.wait_received(5)
    peer.release(lambda f: f is peer.received[2])  # the later chunk is refused first
    peer.release()
    with pytest.raises(ChunkedWriteError) as info:
        await write
    err = info.value
    assert err.written == [(0, 31), (96, 159)]
    assert err.not_written == [(32, 95)]
    assert isinstance(err.cause, CncError) and err.cause.ew == EW.BUSY


async def test_drop_in_the_middle_of_a_batched_write_leaves_uncertain_ranges(
    peer: ScriptedPeer, client: FocasClient
) -> None:
    peer.hold = True
    write = asyncio.create_task(client.write_pmc("R", 0, bytes(range(1, 129))))
    await peer.wait_received(4)
    peer.release(lambda f: f in peer.received[:2])
    await wait_until(lambda: connection_of(client).in_flight == 2, within=BOUND)
    peer.drop()
    with pytest.raises(ChunkedWriteError) as info:
        await write
    err = info.value
    assert err.written == [(0, 63)]
    assert err.uncertain == [(64, 127)]
    assert err.not_written == []
    assert isinstance(err.cause, FocasConnectionError)
    await wait_until(lambda: client.state is ClientState.DISCONNECTED, within=BOUND)


async def test_timeout_in_the_middle_of_a_batched_write_leaves_uncertain_ranges(
    peer: ScriptedPeer, client: FocasClient
) -> None:
    peer.hold = True
    write = asyncio.create_task(client.write_pmc("R", 0, bytes(range(1, 129)), timeout=SHORT * 2))
    await peer.wait_received(4)
    peer.release(lambda f: f in (peer.received[0], peer.received[2]))
    with pytest.raises(ChunkedWriteError) as info:
        await write
    err = info.value
    assert err.written == [(0, 31), (64, 95)]
    assert err.uncertain == [(32, 63), (96, 127)]
    assert err.not_written == []
    assert isinstance(err.cause, FocasTimeoutError)
    c = connection_of(client)
    assert c.abandoned == 2
    peer.hold = False
    peer.release()
    await wait_until(lambda: c.abandoned == 0, within=BOUND)
    assert_idle(c)


async def test_write_on_a_lost_connection_is_not_written(
    peer: ScriptedPeer, client: FocasClient
) -> None:
    peer.drop()
    await wait_until(lambda: client.state is ClientState.DISCONNECTED, within=BOUND)
    with pytest.raises(ChunkedWriteError) as info:
        await client.write_pmc("R", 0, bytes(100))
    err = info.value
    assert err.written == [] and err.uncertain == []
    assert err.not_written == [(0, 99)]
    assert isinstance(err.cause, FocasConnectionError)


async def test_write_timing_out_for_a_slot_is_not_written(
    peer: ScriptedPeer, client: FocasClient
) -> None:
    peer.hold = True
    calls = [asyncio.create_task(client.read_param(n)) for n in range(4)]
    await peer.wait_received(4)
    with pytest.raises(ChunkedWriteError) as info:
        await client.write_pmc("R", 0, bytes(100), timeout=SHORT)
    err = info.value
    assert err.not_written == [(0, 99)] and err.written == [] and err.uncertain == []
    assert isinstance(err.cause, FocasTimeoutError)
    assert len(peer.received) == 4
    peer.hold = False
    peer.release()
    assert await asyncio.gather(*calls) == [0, 1, 2, 3]
    await assert_bound_is(connection_of(client), peer, 4)


def _queue_then_abort(client: FocasClient, data: bytes) -> list[asyncio.Task[Any]]:
    """Two reads and a chunked write queued in one loop turn, the connection aborted before
    the turn's frames are flushed: the second read and the write's chunks never leave."""
    loop = asyncio.get_running_loop()
    c = connection_of(client)
    tasks: list[asyncio.Task[Any]] = [
        asyncio.create_task(client.read_param(1)),
        asyncio.create_task(client.read_param(2)),
        asyncio.create_task(client.write_pmc("R", 0, data)),
    ]
    loop.call_soon(c.abort)  # runs after the three steps, before the scheduled flush
    return tasks


async def test_never_sent_chunks_are_not_written_without_reconnect(
    peer: ScriptedPeer, client: FocasClient
) -> None:
    tasks = _queue_then_abort(client, bytes(range(1, 101)))
    async with asyncio.timeout(BOUND):
        first, second, write = await asyncio.gather(*tasks, return_exceptions=True)
    assert isinstance(first, FocasConnectionError)
    assert isinstance(second, NotSentError)
    assert isinstance(write, ChunkedWriteError)
    assert write.not_written == [(0, 99)] and write.written == [] and write.uncertain == []
    assert isinstance(write.cause, NotSentError)
    assert all(f.command != WRPMCRNG for f in peer.received)


async def test_never_sent_chunks_go_out_after_the_reconnect(peer: ScriptedPeer) -> None:
    policy = ReconnectPolicy(initial_delay=0.0, max_delay=0.01, jitter=0.0)
    async with FocasClient(
        "127.0.0.1", peer.port, timeout=BOUND, max_in_flight=4, reconnect=policy
    ) as c:
        data = bytes(range(1, 101))
        tasks = _queue_then_abort(c, data)
        async with asyncio.timeout(BOUND):
            first, second, write = await asyncio.gather(*tasks, return_exceptions=True)
        assert isinstance(first, FocasConnectionError)  # sent, then lost: not sent again
        assert second == 2 and write is None  # never sent: sent on the new connection
        assert bytes(peer.pmc[:100]) == data
        assert len(peer.sides) == 2
        assert c.state is ClientState.CONNECTED
        assert_idle(connection_of(c))


async def test_chunked_write_unlocks_once_and_resends_on_ew_passwd(peer: ScriptedPeer) -> None:
    peer.password_required = True
    async with FocasClient(
        "127.0.0.1", peer.port, timeout=BOUND, max_in_flight=4, password="1234"
    ) as c:
        assert peer.unlocks == 1
        peer.unlocked = False  # as if the CNC had locked again
        data = bytes(range(1, 129))
        await c.write_pmc("R", 0, data)
        assert bytes(peer.pmc[:128]) == data
        assert peer.unlocks == 2  # one unlock for the whole batch
        writes = [f for f in peer.received if f.command == WRPMCRNG]
        assert len(writes) == 8  # every chunk refused once, then sent again
        # the password no longer works: the chunks were refused, nothing is uncertain
        peer.password = b"9999"
        peer.unlocked = False
        with pytest.raises(ChunkedWriteError) as info:
            await c.write_pmc("R", 0, bytes(128))
        err = info.value
        assert err.not_written == [(0, 127)] and err.written == [] and err.uncertain == []
        assert isinstance(err.cause, AccessDeniedError)
        assert bytes(peer.pmc[:128]) == data
        assert_idle(connection_of(c))


async def test_chunked_write_without_password_is_refused_once(peer: ScriptedPeer) -> None:
    peer.password_required = True
    async with FocasClient("127.0.0.1", peer.port, timeout=BOUND, max_in_flight=4) as c:
        with pytest.raises(ChunkedWriteError) as info:
            await c.write_pmc("R", 0, bytes(70))
        err = info.value
        assert err.not_written == [(0, 69)]
        assert isinstance(err.cause, AccessDeniedError)
        assert len([f for f in peer.received if f.command == WRPMCRNG]) == 3
        assert peer.unlocks == 0


async def test_cancelled_batched_write_gives_up_its_chunks(
    peer: ScriptedPeer, client: FocasClient
) -> None:
    peer.hold = True
    write = asyncio.create_task(client.write_pmc("R", 0, bytes(128)))
    await peer.wait_received(4)
    peer.release(lambda f: f is peer.received[0])
    c = connection_of(client)
    await wait_until(lambda: c.in_flight == 3, within=BOUND)
    write.cancel()
    with pytest.raises(asyncio.CancelledError):
        await write
    assert c.abandoned == 3 and c.in_flight == 0
    peer.hold = False
    peer.release()
    await wait_until(lambda: c.abandoned == 0, within=BOUND)
    await assert_bound_is(c, peer, 4)


async def test_set_pmc_is_batched_against_the_simulator(monkeypatch: pytest.MonkeyPatch) -> None:
    log_writes(monkeypatch)
    async with (
        serving() as served,
        FocasClient(served.host, served.port, timeout=IO_TIMEOUT, max_in_flight=2) as cnc,
    ):
        counting = writes_of(cnc)
        data = random.Random(3).randbytes(300)
        await cnc.sim.set_pmc("F", 0, data)
        assert counting.writes == 1
        await cnc.write_pmc("D", 100, data)
        assert counting.writes == 2
        assert await cnc.read_pmc("F", 0, 300) == data
        assert await cnc.read_pmc("D", 100, 300) == data
        assert_idle(connection_of(cnc))


class _SteppedLoop(asyncio.SelectorEventLoop):
    """A loop with a clock of its own, set by hand."""

    now = 100.0

    def time(self) -> float:
        return self.now


def test_deadlines_read_the_loops_own_clock_unless_it_is_the_stock_one() -> None:
    stock = asyncio.new_event_loop()
    patched = asyncio.new_event_loop()
    stepped = _SteppedLoop()
    try:
        # Stock asyncio's loop.time is time.monotonic behind a Python method: read directly.
        assert clock_of(stock) is time.monotonic
        # A loop whose clock is its own, by subclass or on the instance, is asked every time.
        clock = clock_of(stepped)
        assert clock() == 100.0
        stepped.now = 107.5
        assert clock() == 107.5
        patched.time = lambda: 42.0  # type: ignore[method-assign]
        assert clock_of(patched)() == 42.0
    finally:
        for loop in (stock, patched, stepped):
            loop.close()
