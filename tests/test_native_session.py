"""The FOCAS/2 client session without I/O (``focas_net.native.session``): packing, matching,
deadlines and the connection's end, driven by hand with bytes and times, no socket and no loop.

Properties:

* jobs are packed greedily in call order: a frame takes the jobs at the queue's head while
  its blocks stay within ``max_blocks`` and its answer and request bodies within the limit of
  the open answer's version, and at least one;
* each job of a frame gets its own blocks of the answer, however the answer's bytes arrive
  (whole, a byte at a time, in random pieces); an error answer (0x2103) ends every job of
  the frame REFUSED with its code, and the connection goes on;
* every job ends by its deadline: queued ones never sent, sent ones with their blocks
  dropped when the answer comes; ``wake_at`` is never later than the earliest deadline of a
  job waiting; a frame unanswered past its latest deadline ends the connection;
* bytes no request asked for, or an answer the library refuses, end the connection;
* a lost connection ends the jobs in flight; queued ones wait for the next connection and
  end STALE there if it has another command set.
"""

from __future__ import annotations

import itertools

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from focas_net.native.blocks import ResponseBlock, encode_native_response
from focas_net.native.calls import CommandSet, cnc_rdmacro, cnc_statinfo
from focas_net.native.frame import FrameType, encode_native_frame, max_response_body
from focas_net.native.session import Ending, Job, NativeSession, Part, request_frame

INF = float("inf")
VERSION = 2
LIMIT = max_response_body(VERSION)
KEY = CommandSet.FS16I
_tokens = itertools.count()


def part(count: int, answer: int = 24, request: int = 28) -> Part:
    """A part of ``count`` blocks, ``answer`` answer bytes and ``request`` request bytes in
    all (what the session reckons with; the blocks' bytes are placeholders)."""
    blocks = bytes(request)
    return Part(blocks, count, answer, 0, request_frame(blocks, count))


def session(max_blocks: int = 10) -> NativeSession[int]:
    s: NativeSession[int] = NativeSession(max_blocks)
    assert s.connected(KEY, VERSION, 8) == []
    return s


def submit(s: NativeSession[int], p: Part, deadline: float = INF) -> Job[int]:
    return s.submit(p, deadline, KEY, next(_tokens))


def answer(counts: list[int], tag: int = 0) -> bytes:
    """An answer frame of ``sum(counts)`` blocks, block i carrying ``(tag, i)``."""
    blocks = [ResponseBlock(1, 1, 0x15, 0, bytes((tag, i))) for i in range(sum(counts))]
    return encode_native_response(blocks, VERSION)


def frame_blocks(frame: bytes) -> int:
    return int.from_bytes(frame[10:12], "big")


# -- packing ---------------------------------------------------------------------------------


def greedy(parts: list[tuple[int, int, int]], max_blocks: int) -> list[int]:
    """The block counts of the frames the rule gives for ``parts`` (count, answer, request)."""
    frames: list[int] = []
    i = 0
    while i < len(parts):
        blocks, ans, req = parts[i]
        i += 1
        while i < len(parts):
            b, a, r = parts[i]
            if blocks + b > max_blocks or ans + a > LIMIT - 2 or req + r > LIMIT - 2:
                break
            blocks, ans, req = blocks + b, ans + a, req + r
            i += 1
        frames.append(blocks)
    return frames


#: Parts drawn from a few, so that runs of jobs of one part (one call made again) come up.
PARTS = st.lists(
    st.tuples(st.integers(1, 12), st.integers(16, 1500), st.integers(28, 1500)),
    min_size=1,
    max_size=4,
).flatmap(lambda pool: st.lists(st.sampled_from(pool), min_size=1, max_size=30))


@settings(max_examples=200)
@given(parts=PARTS, max_blocks=st.integers(1, 24))
def test_jobs_are_packed_greedily_in_call_order(
    parts: list[tuple[int, int, int]], max_blocks: int
) -> None:
    s = session(max_blocks)
    made = {spec: part(*spec) for spec in set(parts)}  # one part object per call, as a client
    jobs = [submit(s, made[spec]) for spec in parts]
    sent: list[int] = []
    for _ in range(len(jobs)):
        frame = s.next_frame()
        if frame is None:
            break
        assert s.next_frame() is None  # one frame in flight
        assert s.in_flight is not None
        counts = [job.part.count for job in s.in_flight]
        sent.append(frame_blocks(frame))
        assert sum(counts) == frame_blocks(frame)
        s.receive(answer(counts, len(sent)))
    assert sent == greedy(parts, max_blocks)
    assert all(job.ending is Ending.ANSWERED for job in jobs)
    assert [len(job.blocks) for job in jobs] == [c for c, _, _ in parts]
    assert s.frames_sent == len(sent) and s.blocks_sent == sum(sent)


def test_each_job_gets_its_own_blocks_in_order() -> None:
    s = session()
    jobs = [submit(s, part(n)) for n in (1, 3, 2)]
    assert s.next_frame() is not None
    ended = s.receive(answer([1, 3, 2]))
    assert ended == jobs
    assert [[b.data[1] for b in job.blocks] for job in jobs] == [[0], [1, 2, 3], [4, 5]]


def test_a_lone_job_goes_in_the_frame_its_part_keeps() -> None:
    s = session()
    call = cnc_rdmacro(KEY, 100)
    submit(s, call.parts[0])
    assert s.next_frame() == call.parts[0].frame == call.encode()[0]


@settings(max_examples=100)
@given(cuts=st.lists(st.integers(1, 60), max_size=10), trailing=st.booleans())
def test_an_answer_in_pieces_is_the_same_answer(cuts: list[int], trailing: bool) -> None:
    s = session()
    jobs = [submit(s, part(2)), submit(s, part(1))]
    s.next_frame()
    raw = answer([2, 1]) + (b"\xa0" if trailing else b"")
    pieces, pos = [], 0
    for cut in cuts:
        pieces.append(raw[pos : pos + cut])
        pos += cut
    pieces.append(raw[pos:])
    ended: list[Job[int]] = []
    for piece in pieces:
        ended += s.receive(piece)
    assert ended == jobs
    assert [len(j.blocks) for j in jobs] == [2, 1]
    if trailing:
        assert s.failure == "bytes no request asked for"
    else:
        assert s.failure is None and s.idle


def test_an_error_answer_refuses_every_job_of_its_frame_only() -> None:
    s = session()
    jobs = [submit(s, part(1)), submit(s, part(1))]
    s.next_frame()
    error = encode_native_frame(FrameType.DATA_ERROR, b"\x00\x00\x00\x05\x00\x00\x00\x00", 2)
    assert s.receive(error) == jobs
    assert [(j.ending, j.ew) for j in jobs] == [(Ending.REFUSED, 5)] * 2
    assert s.failure is None
    later = submit(s, part(1))
    assert s.next_frame() is not None
    assert s.receive(answer([1])) == [later]


@pytest.mark.parametrize(
    ("raw", "why"),
    [
        (b"\x00" * 12, "does not start with A0 A0 A0 A0"),
        (encode_native_frame(FrameType.OPEN_RESPONSE, b"", 2), "frame type 0x0102"),
        (encode_native_response([ResponseBlock(1, 1, 1)], 2), "RB count(1) differs"),
    ],
)
def test_an_answer_the_library_refuses_ends_the_connection(raw: bytes, why: str) -> None:
    s = session()
    jobs = [submit(s, part(2)), submit(s, part(1), 5.0)]
    s.next_frame()
    waiting = submit(s, part(1))
    assert s.receive(raw) == jobs
    assert all(j.ending is Ending.LOST and j.sent for j in jobs)
    assert s.failure is not None and why in s.failure
    assert s.next_frame() is None  # nothing more on this connection
    assert waiting.ending is None and s.lost(keep_queued=False) == [waiting]
    assert waiting.ending is Ending.LOST and not waiting.sent


def test_bytes_nobody_asked_for_end_the_connection() -> None:
    s = session()
    assert s.receive(answer([1])) == []
    assert s.failure == "bytes no request asked for"


# -- deadlines -------------------------------------------------------------------------------


def test_a_queued_job_times_out_unsent_and_a_sent_one_drops_its_blocks() -> None:
    s = session(max_blocks=1)
    sent = submit(s, part(1), 10.0)
    queued = submit(s, part(1), 5.0)
    patient = submit(s, part(1), 30.0)
    s.next_frame()
    assert s.wake_at == 5.0
    assert s.expire(4.9) == []
    assert s.expire(5.0) == [queued]
    assert queued.ending is Ending.TIMED_OUT and not queued.sent
    assert s.wake_at == 10.0
    assert s.expire(10.0) == [sent]
    assert sent.ending is Ending.TIMED_OUT and sent.sent
    assert s.failure is None and s.overdue  # its late answer is awaited
    assert s.next_frame() is None  # no frame leaves behind it
    assert patient.ending is None and s.wake_at == 30.0
    assert s.receive(answer([1], tag=1)) == []  # the late answer: matched to its frame, dropped
    assert not s.overdue and s.failure is None and s.idle
    assert s.next_frame() is not None and patient.sent
    assert s.receive(answer([1], tag=2)) == [patient]  # the next answer is the patient's
    assert patient.blocks == (ResponseBlock(1, 1, 0x15, 0, bytes((2, 0))),)


def test_a_late_answer_in_pieces_is_dropped_and_the_next_frame_gets_its_own() -> None:
    s = session(max_blocks=4)
    given_up = [submit(s, part(2), 1.0), submit(s, part(1), 2.0)]
    s.next_frame()
    assert s.expire(1.0) == given_up[:1]
    assert s.expire(2.0) == given_up[1:] and s.overdue
    assert s.wake_at == INF  # nothing waits: no time to be woken at
    behind = [submit(s, part(1), 20.0), submit(s, part(2), 20.0)]
    assert s.next_frame() is None
    late = answer([2, 1], tag=1)
    for i in range(len(late) - 1):
        assert s.receive(late[i : i + 1]) == []
        assert s.overdue and s.failure is None
    assert s.receive(late[-1:]) == []  # whole: dropped, the connection goes on
    assert s.failure is None and not s.overdue
    assert frame_blocks(s.next_frame() or b"") == 3 and all(j.sent for j in behind)
    assert s.receive(answer([1, 2], tag=2)) == behind
    assert [b.data for j in behind for b in j.blocks] == [bytes((2, i)) for i in range(3)]
    assert all(j.ending is Ending.TIMED_OUT for j in given_up)


def test_a_late_answer_that_never_comes_ends_the_connection_when_a_call_behind_gives_up() -> None:
    s = session(max_blocks=1)
    sent = submit(s, part(1), 10.0)
    s.next_frame()
    assert s.expire(10.0) == [sent] and s.overdue
    behind = submit(s, part(1), 15.0)
    patient = submit(s, part(1), 40.0)
    assert s.next_frame() is None and s.wake_at == 15.0
    assert s.expire(14.9) == [] and s.failure is None
    assert s.expire(15.0) == [behind]  # it waited its whole time behind the frame
    assert behind.ending is Ending.TIMED_OUT and not behind.sent
    assert s.failure == "no answer within the timeout"
    assert s.receive(answer([1])) == []  # nothing more on this connection
    assert patient.ending is None  # waits for the next connection
    assert s.lost(keep_queued=True) == [] and s.connected(KEY, VERSION, 8) == []
    assert s.next_frame() is not None and patient.sent


def test_a_call_that_gives_up_behind_a_frame_not_yet_overdue_keeps_the_connection() -> None:
    s = session(max_blocks=1)
    sent = submit(s, part(1), 10.0)
    s.next_frame()
    behind = submit(s, part(1), 5.0)
    assert s.expire(5.0) == [behind] and s.failure is None
    assert s.expire(10.0) == [sent] and s.failure is None and s.overdue


def test_a_frame_is_awaited_until_its_latest_deadline() -> None:
    s = session()
    early = submit(s, part(1), 1.0)
    late = submit(s, part(1), 9.0)
    s.next_frame()
    assert s.expire(1.0) == [early]
    assert s.failure is None and s.wake_at == 9.0
    assert s.receive(answer([1, 1])) == [late]  # the early one's blocks are dropped
    assert early.ending is Ending.TIMED_OUT and late.ending is Ending.ANSWERED


@settings(max_examples=200)
@given(
    steps=st.lists(
        st.one_of(
            st.tuples(st.just("call"), st.integers(1, 4), st.floats(0.5, 20)),
            st.tuples(st.just("time"), st.floats(0, 5), st.just(0.0)),
            st.tuples(st.just("answer"), st.just(0), st.just(0.0)),
            st.tuples(st.just("abandon"), st.integers(0, 50), st.just(0.0)),
        ),
        max_size=60,
    )
)
def test_every_job_ends_by_its_deadline(steps: list[tuple[str, int, float]]) -> None:
    s = session(max_blocks=4)
    now = 0.0
    jobs: list[Job[int]] = []
    ended_at: dict[int, float] = {}

    def settle(ended: list[Job[int]]) -> None:
        for job in ended:
            assert job.token not in ended_at  # a job ends once
            ended_at[job.token] = now

    for kind, a, b in steps:
        if kind == "call":
            jobs.append(submit(s, part(a), now + b))
        elif kind == "time":
            target = now + a
            # the shell's timer: woken at wake_at, never later than a deadline due
            while s.wake_at <= target:
                now = max(now, s.wake_at)
                settle(s.expire(now))
            now = target
        elif kind == "answer" and s.in_flight is not None:
            settle(s.receive(answer([j.part.count for j in s.in_flight])))
        elif kind == "abandon" and jobs:
            s.abandon(jobs[a % len(jobs)])
        if s.failure is not None:
            settle(s.lost(keep_queued=True))
            settle(s.connected(KEY, VERSION, 8))
        s.next_frame()
    while s.wake_at < INF:
        now = max(now, s.wake_at)
        settle(s.expire(now))
        s.next_frame()
    for job in jobs:
        assert job.ending is not None
        if job.ending is not Ending.ABANDONED:
            assert ended_at[job.token] <= job.deadline


# -- the connection ----------------------------------------------------------------------


@settings(max_examples=200)
@given(
    steps=st.lists(
        st.sampled_from(
            ["call", "answer", "garbage", "refused", "time", "lost", "connect", "close"]
        ),
        max_size=40,
    )
)
def test_idle_says_whether_a_frame_could_go(steps: list[str]) -> None:
    # idle is kept as the connection, the frame in flight and the failure change: it is
    # always what they say together, whatever came in between
    s = session(max_blocks=2)
    connected = True
    now = 0.0
    for step in steps:
        if step == "call":
            submit(s, part(1), now + 1.0)
        elif step == "answer" and s.in_flight is not None:
            s.receive(answer([j.part.count for j in s.in_flight]))
        elif step == "garbage":
            s.receive(b"\x00" * 12)
        elif step == "refused" and s.in_flight is not None:
            s.receive(encode_native_frame(FrameType.DATA_ERROR, b"\x00\x00\x00\x05" * 2, 2))
        elif step == "time":
            now += 0.6
            s.expire(now)
        elif step == "lost":
            s.lost(keep_queued=True)
            connected = False
        elif step == "connect":
            s.connected(KEY, VERSION, 8)
            connected = True
        elif step == "close":
            s.close()
            connected = False
        assert s.idle == (connected and s.in_flight is None and s.failure is None)
        if s.next_frame() is not None:
            assert not s.idle  # its frame in flight


def test_queued_jobs_wait_for_the_next_connection() -> None:
    s = session(max_blocks=1)
    first = submit(s, part(1))
    second = submit(s, part(1))
    s.next_frame()
    assert s.lost(keep_queued=True) == [first]
    assert first.ending is Ending.LOST and first.sent
    assert s.next_frame() is None  # no connection
    assert s.connected(KEY, VERSION, 8) == []
    assert s.next_frame() is not None
    assert s.receive(answer([1])) == [second]


def test_a_job_made_for_another_command_set_is_never_sent() -> None:
    s = session(max_blocks=1)
    submit(s, part(1))
    queued = submit(s, part(1))
    s.next_frame()
    s.lost(keep_queued=True)
    assert s.connected(CommandSet.FS30I, 3, 8) == [queued]
    assert queued.ending is Ending.STALE and not queued.sent
    late = s.submit(part(1), INF, KEY, 0)  # made before the reconnect, submitted after
    assert late.ending is Ending.STALE
    assert s.next_frame() is None


def test_a_job_whose_caller_gave_up_waits_no_more() -> None:
    gone: set[int] = set()
    s: NativeSession[int] = NativeSession(10, lambda token: token in gone)
    s.connected(KEY, VERSION, 8)
    first, second = submit(s, part(1)), submit(s, part(1))
    assert s.queued == 2
    gone.add(first.token)  # its caller cancelled its future
    assert s.queued == 1
    frame = s.next_frame()
    assert frame is not None and frame_blocks(frame) == 1
    assert first.ending is Ending.ABANDONED and not first.sent
    assert s.receive(answer([1])) == [second]


def test_an_abandoned_job_is_never_sent() -> None:
    s = session()
    gone = submit(s, part(1))
    kept = submit(s, part(1))
    s.abandon(gone)
    frame = s.next_frame()
    assert frame is not None and frame_blocks(frame) == 1
    assert s.receive(answer([1])) == [kept]
    assert gone.ending is Ending.ABANDONED and not gone.sent


def test_a_whole_status_frame_round_trips() -> None:
    s = session()
    call = cnc_statinfo(KEY)
    job = submit(s, call.parts[0])
    assert s.next_frame() == call.encode()[0]
    s.receive(answer([3]))
    assert job.ending is Ending.ANSWERED and len(job.blocks) == 3
