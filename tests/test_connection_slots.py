"""The packed connection's request slots: each is freed once, when its request leaves the
table of requests in flight (answered, failed by its answer, given up by its caller, or failed
by a close), whatever the caller does afterwards.

The connection is driven by hand: frames are fed to ``data_received`` and the clock of its
timer is set by the test (``peers.hand_driven``).
"""

from __future__ import annotations

import asyncio
from collections.abc import Callable

import pytest
from peers import hand_driven

from focas_net.client.connection import Connection, NotSentError
from focas_net.errors import FocasConnectionError, FocasTimeoutError, ProtocolError
from focas_net.protocol import HEADER, encode_frame

#: Loop turns a test lets pass for a task to reach its next step (a bound, not a delay).
TURNS = 20


COMMAND = 0x0001


def _answer(conn: Connection, request_id: int, command: int = COMMAND) -> None:
    conn.data_received(encode_frame(command, request_id, b"\x00\x00"))


async def _turns_until(what: str, check: Callable[[], bool]) -> None:
    for _ in range(TURNS):
        if check():
            return
        await asyncio.sleep(0)
    raise AssertionError(f"not reached within {TURNS} loop turns: {what}")


async def test_an_answer_hands_its_slot_to_the_first_in_line_as_it_is_read() -> None:
    conn, _, sink = hand_driven(1)
    first = conn.try_send(COMMAND, b"", None)
    assert first is not None
    second = asyncio.create_task(conn.request(COMMAND, b"", None))
    await _turns_until("the second call waits for a slot", lambda: conn.waiting_for_slot == 1)
    assert conn.try_send(COMMAND, b"", None) is None  # the one slot is taken

    _answer(conn, first[2])
    # The slot went to the waiter while the answer was read, before the first caller resumed.
    assert conn.waiting_for_slot == 0
    assert first[0].result() == b"\x00\x00"
    conn.finish(first)  # after an answer: nothing left to release
    assert conn.slots_taken == 1

    await _turns_until("the second request is written", lambda: len(sink.frames) == 2)
    _, _, second_id = HEADER.unpack_from(sink.frames[1])
    _answer(conn, second_id)
    assert await second == b"\x00\x00"
    assert conn.slots_taken == 0 and conn.in_flight == 0


async def test_a_caller_that_gives_up_frees_its_slot_once_and_the_late_answer_frees_none() -> None:
    conn, clock, _ = hand_driven(2)
    entry = conn.try_send(COMMAND, b"", 5.0)
    assert entry is not None
    clock.fire()
    with pytest.raises(FocasTimeoutError):
        entry[0].result()
    assert conn.slots_taken == 1  # still registered until its caller stops waiting
    conn.finish(entry)
    assert conn.slots_taken == 0 and conn.abandoned == 1
    conn.finish(entry)  # twice: the id is already reserved, the slot already free
    assert conn.slots_taken == 0 and conn.abandoned == 1

    _answer(conn, entry[2])  # the late answer: dropped, and no slot to free
    assert conn.slots_taken == 0 and conn.abandoned == 0


async def test_an_answer_with_the_wrong_command_fails_the_call_and_frees_its_slot() -> None:
    conn, _, _ = hand_driven(2)
    entry = conn.try_send(COMMAND, b"", None)
    assert entry is not None
    _answer(conn, entry[2], command=COMMAND + 1)
    with pytest.raises(ProtocolError, match=r"answered cnc_rdcncstat \(0x0001\) with an answer of"):
        entry[0].result()
    assert conn.slots_taken == 0
    conn.finish(entry)
    assert conn.slots_taken == 0 and conn.abandoned == 0


async def test_a_close_frees_the_slots_of_every_call_in_flight_once() -> None:
    conn, _, _ = hand_driven(3)
    entries = [conn.try_send(COMMAND, b"", None) for _ in range(3)]
    waiting = asyncio.create_task(conn.request(COMMAND, b"", None))
    await _turns_until("a fourth call waits for a slot", lambda: conn.waiting_for_slot == 1)
    abandoned = entries[0]
    assert abandoned is not None
    conn.finish(abandoned)  # given up before the close: its id reserved, its slot handed on
    assert conn.waiting_for_slot == 0 and conn.slots_taken == 3

    conn.close()
    for entry in entries[1:]:
        assert entry is not None
        with pytest.raises(FocasConnectionError):
            entry[0].result()
        conn.finish(entry)  # already freed by the close
    with pytest.raises(NotSentError):
        await waiting
    assert conn.slots_taken == 0 and conn.waiting_for_slot == 0 and conn.in_flight == 0


async def test_an_answer_to_a_call_already_ended_is_dropped_and_frees_its_slot_once() -> None:
    conn, clock, _ = hand_driven(2)
    timed_out = conn.try_send(COMMAND, b"", 5.0)
    cancelled = conn.try_send(COMMAND, b"", None)
    assert timed_out is not None and cancelled is not None
    clock.fire()  # the first one's deadline passed
    cancelled[0].cancel()  # the second one's caller was cancelled
    # Both answers arrive in one read before either caller resumed to finish its entry.
    conn.data_received(
        encode_frame(COMMAND, timed_out[2], b"\x00\x00")
        + encode_frame(COMMAND, cancelled[2], b"\x00\x00")
    )
    with pytest.raises(FocasTimeoutError):
        timed_out[0].result()
    assert cancelled[0].cancelled()
    assert conn.slots_taken == 0 and conn.in_flight == 0
    conn.finish(timed_out)
    conn.finish(cancelled)  # the answers left the table: nothing reserved, nothing freed twice
    assert conn.slots_taken == 0 and conn.abandoned == 0
