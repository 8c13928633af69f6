"""The packed connection's request ids: an id whose caller gave up stays reserved until its
late answer arrives, that answer is dropped, and the id then serves again.

The connection is driven by hand (``peers.hand_driven``): frames are read from its transport
and answers fed to ``data_received``. Ids are given in turn, modulo 65,536; to bring the
reserved id up as the next one in line, the test sends (and answers) one request for every
other id, so the connection meets it as it would after that many calls.
"""

from __future__ import annotations

import asyncio

import pytest
from peers import ManualLoop, Sink, assert_idle, hand_driven

from focas_net.client.connection import Connection
from focas_net.errors import FocasTimeoutError
from focas_net.protocol import HEADER, encode_frame

COMMAND = 0x0001
ANSWER = b"\x00\x00"
IDS = 0x10000


def _ids_written_last(sink: Sink) -> list[int]:
    """The ids of the requests of the last write (each one a header alone: no payload)."""
    return [request_id for _, _, request_id in HEADER.iter_unpack(sink.frames[-1])]


def _send(conn: Connection, sink: Sink) -> tuple[int, asyncio.Future[bytes]]:
    """One request sent at once: the id it went out with (read from the wire), its answer."""
    entry = conn.try_send(COMMAND, b"", None)
    assert entry is not None
    return _ids_written_last(sink)[-1], entry[0]


async def _bring_up(conn: Connection, sink: Sink, request_id: int) -> None:
    """Send (in one batch) and answer a request for every id from the one after the last
    sent up to the one before ``request_id``, which is then the next id in line."""
    count = (request_id - _ids_written_last(sink)[-1] - 1) % IDS
    batch = asyncio.create_task(conn.request_each(COMMAND, [b""] * count, None))
    await asyncio.sleep(0)  # the batch is written, in one write
    ids = _ids_written_last(sink)
    assert len(ids) == count and ids[-1] == (request_id - 1) % IDS and request_id not in ids
    conn.data_received(b"".join(encode_frame(COMMAND, i, ANSWER) for i in ids))
    assert await batch == [ANSWER] * count


def _given_up(conn: Connection, clock: ManualLoop, sink: Sink) -> int:
    """A request whose deadline passed and whose caller gave up: its id, now reserved."""
    entry = conn.try_send(COMMAND, b"", clock.now + 5.0)
    assert entry is not None
    clock.fire()
    with pytest.raises(FocasTimeoutError):
        entry[0].result()
    conn.finish(entry)
    assert conn.abandoned == 1
    return _ids_written_last(sink)[-1]


async def _serves_again(conn: Connection, sink: Sink, request_id: int) -> None:
    """``request_id``, brought up as the next id in line, goes to a new call, which gets its
    own answer; nothing is left in flight or reserved."""
    await _bring_up(conn, sink, request_id)
    call_id, call = _send(conn, sink)
    assert call_id == request_id
    conn.data_received(encode_frame(COMMAND, call_id, ANSWER))
    assert call.result() == ANSWER
    assert_idle(conn)


async def test_an_id_given_up_is_skipped_until_its_late_answer_which_is_dropped() -> None:
    conn, clock, sink = hand_driven(4)
    late_id = _given_up(conn, clock, sink)
    await _bring_up(conn, sink, late_id)
    # the reserved id is next in line: a new call skips it
    call_id, call = _send(conn, sink)
    assert call_id == (late_id + 1) % IDS
    # the late answer carries what only the abandoned call could have expected
    conn.data_received(encode_frame(COMMAND, late_id, b"late"))
    assert conn.abandoned == 0
    assert not call.done()  # dropped, not given to another call
    conn.data_received(encode_frame(COMMAND, call_id, ANSWER))
    assert call.result() == ANSWER
    await _serves_again(conn, sink, late_id)  # its late answer came: the id is free again


async def test_a_second_answer_to_an_id_is_dropped_and_the_id_serves_again() -> None:
    conn, clock, sink = hand_driven(4)
    late_id = _given_up(conn, clock, sink)
    conn.data_received(encode_frame(COMMAND, late_id, b"late"))
    assert conn.abandoned == 0
    # the same answer again: nobody waits for that id any more, and it is dropped as it is
    # read, before the answer to the next call
    call_id, call = _send(conn, sink)
    conn.data_received(
        encode_frame(COMMAND, late_id, b"late") + encode_frame(COMMAND, call_id, ANSWER)
    )
    assert call.result() == ANSWER
    await _serves_again(conn, sink, late_id)
