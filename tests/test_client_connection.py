"""The client's connection layer against the scripted peer of ``peers.py``.

The peer answers with the protocol codecs; tests can hold answers back and release them in
any order, answer late, split answers, drop the connection or send garbage.
"""

from __future__ import annotations

import asyncio
import struct
from collections.abc import AsyncIterator
from decimal import Decimal

import pytest
from peers import RDPARAM, STATUS, ScriptedPeer, tiny_cnc

from focas_net.client import ClientState, FocasClient, ReconnectPolicy
from focas_net.client.connection import Connection, open_connection
from focas_net.errors import (
    EW,
    AccessDeniedError,
    ChunkedWriteError,
    CncError,
    FocasConnectionError,
    FocasTimeoutError,
    ProtocolError,
)
from focas_net.protocol import (
    COMMANDS,
    Command,
    EwReply,
    Frame,
    ParamAttributes,
    ParamDataType,
    encode_frame,
)

BOUND = 10.0  # upper bound for waits that must end much sooner; keeps a broken test finite
WRPARAM = int(Command.WRPARAM)
RDPARAINFO = int(Command.RDPARAINFO)


@pytest.fixture
async def peer() -> AsyncIterator[ScriptedPeer]:
    async with ScriptedPeer(pmc_size=256) as p:  # the chunked write below runs off its end
        yield p


@pytest.fixture
async def client(peer: ScriptedPeer) -> AsyncIterator[FocasClient]:
    async with FocasClient("127.0.0.1", peer.port, timeout=BOUND) as c:
        yield c


def current_connection(client: FocasClient) -> Connection:
    conn = client.connection
    assert conn is not None
    return conn


async def test_pipelined_calls_get_their_own_answers(client: FocasClient) -> None:
    numbers = list(range(1, 301))
    values = await asyncio.gather(*(client.read_param(n) for n in numbers))
    assert values == numbers
    assert current_connection(client).in_flight == 0


async def test_out_of_order_answers_are_matched_by_request_id(
    peer: ScriptedPeer, client: FocasClient
) -> None:
    peer.hold = True
    tasks = [asyncio.create_task(client.read_param(n)) for n in range(10, 20)]
    await peer.wait_received(10)
    peer.release(reverse=True)
    assert await asyncio.gather(*tasks) == list(range(10, 20))


async def test_late_answer_after_timeout_is_dropped(
    peer: ScriptedPeer, client: FocasClient
) -> None:
    peer.hold = True
    with pytest.raises(FocasTimeoutError):
        await client.read_param(7, timeout=0.05)
    conn = current_connection(client)
    assert conn.abandoned == 1 and conn.in_flight == 0
    pending = asyncio.create_task(client.read_param(8))
    await peer.wait_received(2)
    peer.hold = False
    peer.release()  # the late answer to 7, then the answer to 8
    assert await pending == 8
    assert conn.abandoned == 0
    assert await client.read_param(9) == 9


async def test_timeout_error_is_also_builtin_timeout(
    peer: ScriptedPeer, client: FocasClient
) -> None:
    peer.hold = True
    with pytest.raises(TimeoutError):
        await client.read_status(timeout=0.02)
    peer.hold = False
    peer.release()


async def test_cancellation_propagates_and_never_desynchronises(
    peer: ScriptedPeer, client: FocasClient
) -> None:
    peer.hold = True
    victim = asyncio.create_task(client.read_param(1))
    survivor = asyncio.create_task(client.read_param(2))
    await peer.wait_received(2)
    victim.cancel()
    with pytest.raises(asyncio.CancelledError):
        await victim
    peer.hold = False
    peer.release(reverse=True)
    assert await survivor == 2
    assert await client.read_param(3) == 3
    conn = current_connection(client)
    assert conn.in_flight == 0 and conn.abandoned == 0


async def test_cancelling_a_caller_waiting_for_a_slot(peer: ScriptedPeer) -> None:
    async with FocasClient("127.0.0.1", peer.port, timeout=BOUND, max_in_flight=2) as c:
        peer.hold = True
        first = [asyncio.create_task(c.read_param(n)) for n in (1, 2)]
        await peer.wait_received(2)
        waiting = asyncio.create_task(c.read_param(3))
        await asyncio.sleep(0)
        waiting.cancel()
        with pytest.raises(asyncio.CancelledError):
            await waiting
        assert len(peer.received) == 2  # the cancelled call was never sent
        peer.hold = False
        peer.release()
        assert await asyncio.gather(*first) == [1, 2]
        assert await c.read_param(4) == 4


async def test_max_in_flight_bounds_the_requests_sent(peer: ScriptedPeer) -> None:
    async with FocasClient("127.0.0.1", peer.port, timeout=BOUND, max_in_flight=4) as c:
        peer.hold = True
        tasks = [asyncio.create_task(c.read_param(n)) for n in range(1, 11)]
        await peer.wait_received(4)
        for _ in range(5):
            await asyncio.sleep(0)
        assert len(peer.received) == 4
        peer.hold = False
        peer.release()
        assert await asyncio.gather(*tasks) == list(range(1, 11))


async def test_connection_loss_fails_every_pending_call_at_once(
    peer: ScriptedPeer, client: FocasClient
) -> None:
    peer.hold = True
    tasks = [asyncio.create_task(client.read_param(n, timeout=60)) for n in range(50)]
    await peer.wait_received(50)
    peer.drop()
    async with asyncio.timeout(BOUND):
        results = await asyncio.gather(*tasks, return_exceptions=True)
    assert all(isinstance(r, FocasConnectionError) for r in results)
    assert all(isinstance(r, ConnectionError) for r in results)
    assert client.state is ClientState.DISCONNECTED
    with pytest.raises(FocasConnectionError):
        await client.read_status()


async def test_framing_violation_closes_and_fails_pending(
    peer: ScriptedPeer, client: FocasClient
) -> None:
    peer.hold = True
    task = asyncio.create_task(client.read_status(timeout=60))
    await peer.wait_received(1)
    peer.send_raw(struct.pack("<I", 2))  # length below 4
    with pytest.raises(ProtocolError, match="does not speak the FOCAS protocol"):
        await task
    assert client.state is ClientState.DISCONNECTED


async def test_answer_with_wrong_command_fails_only_that_call(
    peer: ScriptedPeer, client: FocasClient
) -> None:
    def wrong(frame: Frame, p: ScriptedPeer) -> bytes | None:
        if frame.command == Command.RDCNCSTAT:
            return None
        return tiny_cnc(frame, p)

    peer.answer = wrong
    task = asyncio.create_task(client.read_status())
    await peer.wait_received(1)
    rid = peer.received[-1].request_id
    peer.send_raw(encode_frame(Command.SYSINFO, rid, b"\x01\x00"))
    with pytest.raises(ProtocolError):
        await task
    assert await client.read_param(5) == 5


async def test_unsolicited_frames_are_ignored(peer: ScriptedPeer, client: FocasClient) -> None:
    peer.send_raw(encode_frame(Command.RDPARAM, 999, b"\x00\x00"))
    assert await client.read_param(6) == 6


async def test_answers_split_one_byte_per_write(peer: ScriptedPeer, client: FocasClient) -> None:
    peer.split = True
    values = await asyncio.gather(*(client.read_param(n) for n in range(1, 21)))
    assert values == list(range(1, 21))
    assert await client.read_status() == STATUS


async def test_connect_failure_is_a_connection_error() -> None:
    server = await asyncio.start_server(lambda r, w: None, "127.0.0.1", 0)
    port = server.sockets[0].getsockname()[1]
    server.close()
    await server.wait_closed()
    with pytest.raises(FocasConnectionError):
        await FocasClient("127.0.0.1", port, timeout=BOUND).connect()


async def test_connection_closed_by_caller(peer: ScriptedPeer) -> None:
    conn = await open_connection("127.0.0.1", peer.port)
    peer.hold = True
    loop = asyncio.get_running_loop()
    task = asyncio.create_task(conn.request(Command.RDCNCSTAT, b"", loop.time() + 60))
    await peer.wait_received(1)
    conn.close()
    with pytest.raises(FocasConnectionError):
        await task
    await conn.wait_closed()
    assert conn.closed


async def test_calls_after_close_fail(peer: ScriptedPeer) -> None:
    c = FocasClient("127.0.0.1", peer.port)
    await c.connect()
    await c.aclose()
    assert c.state is ClientState.CLOSED
    with pytest.raises(FocasConnectionError):
        await c.read_status()
    with pytest.raises(FocasConnectionError):
        await c.connect()


async def test_password_retry_once_on_ew_passwd(peer: ScriptedPeer) -> None:
    peer.password_required = True
    async with FocasClient("127.0.0.1", peer.port, password="1234", timeout=BOUND) as c:
        assert peer.unlocks == 1
        peer.unlocked = False  # as if the CNC had locked again
        await c.write_param(1320, 5, axis=1, width=4)
        assert peer.unlocks == 2
    async with FocasClient("127.0.0.1", peer.port, timeout=BOUND) as c:
        with pytest.raises(AccessDeniedError) as info:
            await c.write_param(1320, 5, axis=1, width=4)
        assert info.value.ew == EW.PASSWD


def _sent_since(peer: ScriptedPeer, first: int) -> list[tuple[int, int]]:
    """``(command, parameter)`` of each frame received from ``first`` on."""
    return [
        (f.command, COMMANDS[f.command].request.decode(f.payload).datano)
        for f in peer.received[first:]
    ]


def _typed_cnc(frame: Frame, p: ScriptedPeer) -> bytes | None:
    """:func:`tiny_cnc` that tells each parameter's type: a two-word parameter."""
    if frame.command == RDPARAINFO:
        number = COMMANDS[RDPARAINFO].request.decode(frame.payload).datano
        attrs = ParamAttributes(number, ParamDataType.TWO_WORD, 0, 0, -(2**31), 2**31 - 1)
        return COMMANDS[RDPARAINFO].response.encode(attrs)
    return tiny_cnc(frame, p)


async def test_write_param_learns_the_width_from_the_type_and_keeps_it(
    peer: ScriptedPeer, client: FocasClient
) -> None:
    """Without ``width=``, the first write of a parameter asks its type once
    (``cnc_rdparainfo``, which needs no axis, as FOCAS/2's ``cnc_wrparam`` asks it) for its
    width (4 bytes here), and later writes use what was kept; a read keeps the width too; a
    write answered ``EW_LENGTH`` drops what was kept, so the next write asks again."""
    peer.answer = _typed_cnc
    await client.write_param(6711, 1234)
    assert _sent_since(peer, 0) == [(RDPARAINFO, 6711), (WRPARAM, 6711)]
    written = COMMANDS[Command.WRPARAM].request.decode(peer.received[-1].payload)
    assert (written.value, written.width) == (1234, 4)
    await client.write_param(6711, 99)
    assert _sent_since(peer, 2) == [(WRPARAM, 6711)]  # the type kept
    assert await client.read_param(20) == 20
    await client.write_param(20, 3)
    assert _sent_since(peer, 3) == [(RDPARAM, 20), (WRPARAM, 20)]  # the width kept by the read

    def refuse_length(frame: Frame, p: ScriptedPeer) -> bytes | None:
        if frame.command == WRPARAM:
            return COMMANDS[WRPARAM].response.encode(EwReply(EW.LENGTH))
        return _typed_cnc(frame, p)

    peer.answer = refuse_length
    with pytest.raises(CncError) as info:
        await client.write_param(6711, 5)
    assert info.value.ew == EW.LENGTH
    peer.answer = _typed_cnc
    await client.write_param(6711, 6)
    assert _sent_since(peer, 5) == [(WRPARAM, 6711), (RDPARAINFO, 6711), (WRPARAM, 6711)]
    with pytest.raises(ValueError, match=r"^parameter 7000 is not a real parameter: 1\.5 is no"):
        await client.write_param(7000, Decimal("1.5"))  # refused by the type, no axis needed
    assert _sent_since(peer, 8) == [(RDPARAINFO, 7000)]


async def test_write_param_of_a_cnc_that_cannot_tell_the_type_learns_the_width_by_a_read(
    peer: ScriptedPeer, client: FocasClient
) -> None:
    """``cnc_rdparainfo`` answered ``EW_FUNC``: the width is the one of one read, kept."""
    await client.write_param(6711, 1234)
    assert _sent_since(peer, 0) == [(RDPARAINFO, 6711), (RDPARAM, 6711), (WRPARAM, 6711)]
    await client.write_param(6711, 99)
    assert _sent_since(peer, 3) == [(WRPARAM, 6711)]


async def test_a_refusal_of_the_type_ask_is_the_writes(
    peer: ScriptedPeer, client: FocasClient
) -> None:
    """The CNC has no such parameter: the refusal names ``cnc_wrparam``, as on FOCAS/2."""

    def no_parameter(frame: Frame, p: ScriptedPeer) -> bytes | None:
        if frame.command == RDPARAINFO:
            return COMMANDS[RDPARAINFO].response.encode(EwReply(EW.NUMBER))
        return tiny_cnc(frame, p)

    peer.answer = no_parameter
    with pytest.raises(CncError) as info:
        await client.write_param(9999, 1)
    assert (info.value.ew, info.value.detail) == (
        EW.NUMBER,
        "cnc_wrparam: the CNC has no parameter 9999",
    )
    assert _sent_since(peer, 0) == [(RDPARAINFO, 9999)]


async def test_wrong_password_fails_connect(peer: ScriptedPeer) -> None:
    c = FocasClient("127.0.0.1", peer.port, password="nope", timeout=BOUND)
    with pytest.raises(AccessDeniedError):
        await c.connect()
    await c.aclose()


async def test_reconnect_after_drop_and_password_resent(peer: ScriptedPeer) -> None:
    states: list[ClientState] = []
    policy = ReconnectPolicy(initial_delay=0.01, max_delay=0.05)
    async with FocasClient(
        "127.0.0.1",
        peer.port,
        timeout=BOUND,
        reconnect=policy,
        password="1234",
        on_state_change=states.append,
    ) as c:
        assert peer.unlocks == 1
        lost = asyncio.Event()
        c.add_state_callback(lambda s: lost.set() if s is ClientState.RECONNECTING else None)
        peer.drop()
        async with asyncio.timeout(BOUND):
            await lost.wait()
        assert await c.read_param(11) == 11  # waits for the reconnect
        assert c.state is ClientState.CONNECTED
        assert peer.unlocks == 2 and peer.connections == 2
        assert ClientState.RECONNECTING in states
    assert states[-1] is ClientState.CLOSED


async def test_calls_while_reconnecting_wait_within_their_timeout(peer: ScriptedPeer) -> None:
    policy = ReconnectPolicy(initial_delay=0.01, max_delay=0.02)
    async with FocasClient("127.0.0.1", peer.port, timeout=BOUND, reconnect=policy) as c:
        port = peer.port
        await peer.stop()
        with pytest.raises(FocasConnectionError):
            await c.read_status(timeout=0.1)
        assert c.state is ClientState.RECONNECTING
        revived = ScriptedPeer()
        await revived.start(port)
        try:
            assert await c.read_param(12, timeout=BOUND) == 12
        finally:
            await revived.stop()


async def test_reconnect_gives_up_after_max_attempts(peer: ScriptedPeer) -> None:
    policy = ReconnectPolicy(initial_delay=0.0, max_delay=0.0, max_attempts=2)
    gave_up = asyncio.Event()

    def watch(state: ClientState) -> None:
        if state is ClientState.DISCONNECTED:
            gave_up.set()

    async with FocasClient(
        "127.0.0.1", peer.port, timeout=BOUND, reconnect=policy, on_state_change=watch
    ) as c:
        await peer.stop()
        async with asyncio.timeout(BOUND):
            await gave_up.wait()
        with pytest.raises(FocasConnectionError):
            await c.read_status()
        assert c.state is ClientState.DISCONNECTED


async def test_chunked_pmc_over_fake_peer(peer: ScriptedPeer, client: FocasClient) -> None:
    data = bytes(range(200))
    await client.write_pmc("R", 0, data)
    assert bytes(peer.pmc[:200]) == data
    assert await client.read_pmc("R", 0, 200) == data
    writes = [f for f in peer.received if f.command == Command.WRPMCRNG]
    assert len(writes) == 7  # 6 x 32 + 8


async def test_chunked_write_error_names_ranges(peer: ScriptedPeer, client: FocasClient) -> None:
    with pytest.raises(ChunkedWriteError) as info:
        await client.write_pmc("D", 200, bytes(range(1, 101)))  # the peer's memory ends at 255
    err = info.value
    # chunks 200..231 | 232..263 (crosses the end) | 264..295 | 296..299
    assert err.written == [(200, 231)]
    assert err.not_written == [(232, 299)]
    assert bytes(peer.pmc[200:232]) == bytes(range(1, 33))
    assert bytes(peer.pmc[232:256]) == bytes(24)
    assert isinstance(err.cause, CncError) and err.cause.ew == EW.NUMBER


async def test_connection_counts_reset_after_many_timeouts(peer: ScriptedPeer) -> None:
    # (the connection within BOUND: only the calls are to time out, whatever the load)
    async with FocasClient("127.0.0.1", peer.port, timeout=BOUND) as c:
        peer.hold = True
        results = await asyncio.gather(
            *(c.read_param(n, timeout=0.01) for n in range(100)), return_exceptions=True
        )
        assert all(isinstance(r, FocasTimeoutError) for r in results)
        conn = current_connection(c)
        # At least 64 were sent and abandoned; the others timed out waiting for a free slot
        # (or took a slot freed by an earlier timeout before their own deadline).
        sent = conn.abandoned
        assert 64 <= sent <= 100
        await peer.wait_received(sent)
        assert len(peer.received) == sent
        peer.hold = False
        peer.release()
        assert await c.read_param(1, timeout=BOUND) == 1
        assert conn.abandoned == 0 and conn.in_flight == 0
