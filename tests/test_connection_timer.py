"""The packed connection's one deadline timer, on a clock the test moves by hand.

The connection's loop is wrapped so that ``time()`` reads a number the test sets and
``call_at`` records the timer instead of arming it; the test fires the recorded timer itself.
The transport keeps the frames written, and answers are fed to ``data_received``. So every
step in time is explicit: which deadline the timer is armed for, what it fails when it
fires, and what it is armed for next.
"""

from __future__ import annotations

import asyncio

import pytest
from peers import ManualLoop, Sink, hand_driven

from focas_net.client.connection import Connection
from focas_net.errors import FocasTimeoutError
from focas_net.protocol import HEADER, encode_frame

COMMAND = 0x0001


@pytest.fixture
async def timed() -> tuple[Connection, ManualLoop, Sink]:
    return hand_driven()


def _send(conn: Connection, deadline: float | None) -> tuple[int, asyncio.Future[bytes]]:
    entry = conn.try_send(COMMAND, b"", deadline)
    assert entry is not None
    return entry[2], entry[0]


def _answer(conn: Connection, request_id: int) -> None:
    conn.data_received(encode_frame(COMMAND, request_id, b"\x00\x00"))


async def test_the_timer_moves_on_from_an_answered_request_to_the_next(
    timed: tuple[Connection, ManualLoop, Sink],
) -> None:
    conn, clock, sink = timed
    a, fa = _send(conn, 10.0)
    assert clock.armed() == [10.0]
    _answer(conn, a)
    assert fa.result() == b"\x00\x00"
    clock.now = 5.0
    _, fb = _send(conn, 15.0)
    assert clock.armed() == [10.0]  # a later deadline: the timer armed for the first covers it
    clock.fire()  # at 10: the answered request is gone, the other one not due yet
    assert not fb.done()
    assert clock.armed() == [15.0]
    clock.fire()
    with pytest.raises(FocasTimeoutError):
        fb.result()
    assert clock.armed() == []
    assert len(sink.frames) == 2


async def test_an_earlier_deadline_moves_the_timer_and_fails_first(
    timed: tuple[Connection, ManualLoop, Sink],
) -> None:
    conn, clock, _ = timed
    _, late = _send(conn, 20.0)
    _, none = _send(conn, None)
    _, early = _send(conn, 12.0)
    assert clock.armed() == [12.0]  # moved from 20 (the old timer cancelled)
    clock.fire()
    with pytest.raises(FocasTimeoutError):
        early.result()
    assert not late.done() and not none.done()
    assert clock.armed() == [20.0]
    clock.fire()
    with pytest.raises(FocasTimeoutError):
        late.result()
    assert not none.done()
    assert clock.armed() == []  # no deadline left: nothing armed for the call without one


async def test_requests_without_deadlines_arm_nothing(
    timed: tuple[Connection, ManualLoop, Sink],
) -> None:
    conn, clock, _ = timed
    ids = [_send(conn, None)[0] for _ in range(3)]
    assert clock.armed() == []
    for request_id in ids:
        _answer(conn, request_id)
    assert conn.in_flight == 0


async def test_a_timer_firing_early_is_armed_again_for_the_same_deadline(
    timed: tuple[Connection, ManualLoop, Sink],
) -> None:
    """The loop may run a timer a clock resolution early: the request is not failed before
    its deadline, and the timer is armed for it again."""
    conn, clock, _ = timed
    _, future = _send(conn, 10.0)
    (timer,) = clock.timers
    clock.timers.clear()
    clock.now = 9.999
    timer.callback()
    assert not future.done()
    assert clock.armed() == [10.0]
    clock.fire()
    with pytest.raises(FocasTimeoutError):
        future.result()


async def test_a_given_up_id_is_skipped_and_its_late_answer_dropped(
    timed: tuple[Connection, ManualLoop, Sink],
) -> None:
    conn, clock, sink = timed
    entry = conn.try_send(COMMAND, b"", 10.0)
    assert entry is not None
    _, other = _send(conn, 30.0)
    clock.fire()
    with pytest.raises(FocasTimeoutError):
        entry[0].result()
    conn.finish(entry)  # the caller gives up: the id stays reserved
    assert conn.abandoned == 1
    assert clock.armed() == [30.0]
    (_, _, request_id) = HEADER.unpack_from(sink.frames[0])
    _answer(conn, request_id)  # the late answer: dropped, the id free again
    assert conn.abandoned == 0
    assert not other.done()
