"""The client side of a FOCAS/2 connection, without I/O: :class:`NativeSession`.

It is what :class:`~focas_net.client.NativeClient` does between its calls and the bytes of
connection B, written as a plain object, as h11's ``Connection`` is for HTTP: no socket, no
event loop, no clock of its own. The asyncio shell (``focas_net/client/_native_link.py``) hands
it the calls, the bytes read and the time, and does what it says: write a frame, complete a
call, close the connection.

FOCAS/2 carries no request id, so the answer to a data request is the next data answer on the
connection, and a connection carries **one request frame in flight**. What the session keeps:

* **a queue of jobs** in call order. A job is one frame's worth of blocks of one call: a
  :class:`Part`, encoded when the call was made, and the call's deadline;
* **greedy packing**: :meth:`NativeSession.next_frame` takes jobs from the head of the queue
  while they fit (at most ``max_blocks`` blocks, an answer within the limit of the open
  answer's version, a request body within 1450 bytes, as FANUC's library sends) and at least
  one, whatever its size, so no call is overtaken;
* **matching**: the answer's blocks are handed out in order, each job its own ``count``;
* **deadlines**: :meth:`NativeSession.expire` ends every job whose deadline passed (a queued
  one was never sent; a sent one's blocks are dropped when the answer comes);
* **late answers**: a frame unanswered past the latest deadline of its jobs stays in flight
  (:attr:`NativeSession.overdue`) and no frame leaves after it, so the next data answer on the
  connection is still its answer: when it comes it is matched to the frame, dropped, and the
  queued jobs go. A job queued behind the overdue frame that reaches its own deadline unsent
  ends the wait: the CNC is taken as no longer answering and the connection is done for
  (:attr:`NativeSession.failure`). Nothing but the answer in order tells an answer's frame
  (FOCAS/2 has no request id), so a frame is never sent while another may still be answered.

A job ends once, with an :class:`Ending`; the shell turns that into the call's result or
exception (it knows the address the messages name). Nothing here raises because of a call's
arguments: they were checked and encoded (:func:`encode_part`) in the caller's frame.
"""

from __future__ import annotations

import enum
import struct
from collections import deque
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from typing import Final, Generic, TypeVar

from focas_net._memo import Memo
from focas_net._typed import field_unfit
from focas_net.errors import ProtocolError

from .blocks import (
    RESPONSE_BLOCK_SIZE,
    ResponseBlock,
    answer_refusal,
    decode_response_body,
)
from .frame import (
    CLIENT_VERSION,
    LIBRARY_MAX_REQUEST_BODY,
    MAGIC,
    NATIVE_HEADER,
    NATIVE_HEADER_SIZE,
    FrameType,
    max_response_body,
)
from .macros import MacroReadRequest
from .pmc import PmcReadRequest
from .requests import AlarmMessageRequest, NativeAlarmHistoryRequest, NativeRequest

__all__ = [
    "NOT_A_FRAME",
    "AnswerRefused",
    "Ending",
    "Job",
    "NativeSession",
    "Part",
    "answer_blocks",
    "encode_part",
    "request_frame",
]

T = TypeVar("T")

#: Why an answer is no FOCAS/2 frame, at the connect and after it alike.
NOT_A_FRAME: Final = "its answer does not start with A0 A0 A0 A0"

#: No deadline.
_NEVER: Final = float("inf")
#: The deadline of a frame past it with no answer (:attr:`NativeSession.overdue`).
_OVERDUE: Final = float("-inf")
_MAGIC: Final = int.from_bytes(MAGIC, "big")
#: A data request frame's header and its block count.
_REQUEST_HEAD: Final = struct.Struct(">IHHHH")
_DATA_REQUEST: Final = int(FrameType.DATA_REQUEST)
_DATA_ANSWER: Final = FrameType.DATA_RESPONSE >> 8
_ERROR_WORDS: Final = struct.Struct(">hhhh")
#: The bytes of each axis in an answer of one record per axis (a position, a parameter).
_AXIS_RECORD: Final = 16
#: The room of a request's blocks after the block count: FANUC's library keeps a request
#: body within 1450 bytes whatever the answer version, and servers may refuse more.
_SEND_LIMIT: Final = LIBRARY_MAX_REQUEST_BODY - 2


@dataclass(frozen=True, slots=True)
class Part:
    """The blocks of one frame of one call, encoded: what a job carries.

    ``answer_fixed + answer_axes * 16 * max_axes`` is the most answer bytes (block heads
    included) the blocks can get: a request whose answer has one record per axis counts in
    ``answer_axes``.
    """

    blocks: bytes
    count: int
    answer_fixed: int
    answer_axes: int
    #: The data request frame that carries these blocks alone.
    frame: bytes
    #: The FOCAS function whose frame this is (``cnc_rdparam``), as a failure names it.
    function: str = field(default="", compare=False)

    @property
    def request_size(self) -> int:
        """The bytes of the blocks in a request body."""
        return len(self.blocks)


def _answer_size(request: NativeRequest) -> tuple[int, int]:
    """The most answer bytes of ``request``'s block: (fixed bytes, records of one per axis)."""
    if isinstance(request, MacroReadRequest):
        size = 8 * max(request.last - request.first + 1, 1)
    elif isinstance(request, PmcReadRequest):
        size = max(request.last - request.first + 1, 0)
    elif isinstance(request, AlarmMessageRequest):
        size = request.count * (16 + request.text_length)
    elif isinstance(request, NativeAlarmHistoryRequest):
        size = 60 * max(request.last - request.first + 1, 1)
    else:
        fixed = getattr(request.ANSWER, "SIZE", None)
        if not isinstance(fixed, int):
            return RESPONSE_BLOCK_SIZE + 8, 1
        size = fixed
    return RESPONSE_BLOCK_SIZE + size, 0


def request_frame(blocks: bytes, count: int) -> bytes:
    """The data request frame of ``count`` encoded ``blocks``."""
    head = _REQUEST_HEAD.pack(_MAGIC, CLIENT_VERSION, _DATA_REQUEST, 2 + len(blocks), count)
    return head + blocks


def encode_part(requests: Sequence[NativeRequest], path: int = 1, function: str = "") -> Part:
    """The :class:`Part` of ``requests`` (one frame's worth of one call) on ``path`` (of
    ``function``, the FOCAS function, named in a failure).

    :raises ValueError: a request whose fields do not fit its block, naming the function (or
        the request's kind) and the field and value that do not fit, never the request's
        repr.
    """
    encoded: list[bytes] = []
    fixed = axes = 0
    for request in requests:
        try:
            encoded.append(request.to_block(path).encode())
        except ValueError as exc:
            raise ValueError(f"{function or type(request).__name__}: {exc}") from None
        size, per_axis = _answer_size(request)
        fixed += size
        axes += per_axis
    blocks = b"".join(encoded)
    return Part(blocks, len(encoded), fixed, axes, request_frame(blocks, len(encoded)), function)


class Ending(enum.Enum):
    """How a job ended."""

    #: Its answer blocks came (``Job.blocks``; an EW code in a block is the call's to raise).
    ANSWERED = "answered"
    #: Its deadline passed (``Job.sent`` tells whether its frame had left).
    TIMED_OUT = "timed out"
    #: The connection ended (``Job.sent`` tells whether its frame had left).
    LOST = "lost"
    #: Its frame was answered with an error frame (0x2103) carrying ``Job.ew``.
    REFUSED = "refused"
    #: Encoded for a command set the connection it would go on does not have.
    STALE = "stale"
    #: Given up by its caller (cancelled).
    ABANDONED = "abandoned"


#: The ending of every answered job, looked up once: on Python 3.11 an enumeration's
#: ``EnumType.__getattr__`` keeps each ``Ending.ANSWERED`` in a function from being a cached
#: look-up (about five times the cost of a global's), and it is asked once per call.
_ANSWERED: Final = Ending.ANSWERED


class Job(Generic[T]):
    """One frame's worth of one call, queued, in flight or ended."""

    __slots__ = ("blocks", "deadline", "ending", "ew", "key", "part", "sent", "token")

    def __init__(self, part: Part, deadline: float, key: object, token: T) -> None:
        self.part = part
        #: When the call gives up (``inf``: never).
        self.deadline = deadline
        #: What the blocks were encoded for (the command set): see :meth:`NativeSession.connected`.
        self.key = key
        #: The shell's handle of the call (its future).
        self.token = token
        #: Whether a frame carrying it was sent.
        self.sent = False
        self.ending: Ending | None = None
        self.blocks: tuple[ResponseBlock, ...] = ()
        self.ew = 0

    def __repr__(self) -> str:
        state = self.ending.value if self.ending else ("sent" if self.sent else "queued")
        return f"<Job of {self.part.count} block(s), {state}>"


def _time_out(jobs: Iterable[Job[T]], now: float) -> tuple[list[Job[T]], float]:
    """End TIMED_OUT the jobs of ``jobs`` due by ``now``; those, and the earliest deadline of
    the others still waiting (``inf``: none)."""
    ended: list[Job[T]] = []
    earliest = _NEVER
    for job in jobs:
        if job.ending is not None:
            continue
        if job.deadline <= now:
            job.ending = Ending.TIMED_OUT
            ended.append(job)
        elif job.deadline < earliest:
            earliest = job.deadline
    return ended, earliest


class AnswerRefused(ProtocolError):
    """A data answer FANUC's library refuses: the connection cannot go on after it."""


#: (a whole answer frame, header included; its request's block count) -> its blocks.
_ANSWERS: Final = Memo(512)


def answer_blocks(raw: bytes, count: int) -> tuple[ResponseBlock, ...] | int:
    """The blocks of the data answer ``raw`` to a request of ``count`` blocks, checked as
    FANUC's library checks them, or the EW code of an error answer (0x2103).

    :raises AnswerRefused: an answer the library refuses (the connection must end).
    """
    known: tuple[ResponseBlock, ...] | None = _ANSWERS.get((raw, count))
    if known is not None:
        return known
    _, version, frame_type, _ = NATIVE_HEADER.unpack_from(raw)
    body = raw[NATIVE_HEADER_SIZE:]
    if frame_type >> 8 != _DATA_ANSWER:
        raise AnswerRefused(f"answer of frame type 0x{frame_type:04X} to a data request")
    if frame_type == FrameType.DATA_ERROR:
        if len(body) < _ERROR_WORDS.size:
            raise AnswerRefused(f"error answer of {len(body)} bytes")
        return int(_ERROR_WORDS.unpack_from(body)[1])
    refusal = answer_refusal(body, count, version)
    if refusal is not None:
        raise AnswerRefused(f"data answer refused: {refusal}")
    try:
        blocks = decode_response_body(body)
    except ProtocolError as exc:
        raise AnswerRefused(str(exc)) from None
    _ANSWERS.put((raw, count), blocks)
    return blocks


class NativeSession(Generic[T]):
    """The jobs of one client and the frame in flight on its connection B.

    The session outlives a connection: :meth:`connected` starts one (frames may go),
    :meth:`lost` ends it (jobs in flight end, queued ones wait for the next connection or end
    too). ``T`` is the type of the shell's token of a job.
    """

    def __init__(
        self, max_blocks: int, given_up: Callable[[T], bool] = lambda token: False
    ) -> None:
        if isinstance(max_blocks, bool) or not isinstance(max_blocks, int):
            raise TypeError(f"max_blocks must be an integer, got {max_blocks!r}")
        why = field_unfit("max_blocks", max_blocks, 1, 0xFFFF)
        if why is not None:
            raise ValueError(why)
        self.max_blocks = max_blocks
        #: Whether the caller of a job's token gave up (cancelled) without saying so: such a
        #: job queued is never sent, as one :meth:`abandon` ended.
        self._given_up = given_up
        #: Jobs not sent, in call order (ended ones are dropped when met).
        self.queue: deque[Job[T]] = deque()
        #: The jobs of the frame in flight, or None.
        self.in_flight: list[Job[T]] | None = None
        #: The latest deadline of the jobs of the frame in flight (``-inf`` once past with no
        #: answer: :attr:`overdue`).
        self.frame_deadline = _NEVER
        #: Why the connection can carry no further frame (None: it can, or there is none).
        self.failure: str | None = None
        #: Whether :attr:`failure` is the peer breaking FOCAS/2 (bytes no frame starts with,
        #: an answer the library refuses), not a stray answer or a timeout.
        self.broken = False
        #: Whether a frame could be sent now: connected, nothing in flight, no failure (kept
        #: as each of those changes, so that asking costs nothing).
        self.idle = False
        #: A time no later than the earliest deadline of a job waiting (``inf``: none): the
        #: shell calls :meth:`expire` then.
        self.wake_at = _NEVER
        self.frames_sent = 0
        self.blocks_sent = 0
        self._open = False
        self._key: object = None
        self._limit = 0
        self._axis_bytes = 0
        self._rx = bytearray()
        self._in_flight_blocks = 0

    # -- the connection ----------------------------------------------------------------------
    @property
    def queued(self) -> int:
        """Jobs waiting to be sent whose caller still waits for them."""
        given_up = self._given_up
        return sum(1 for job in self.queue if job.ending is None and not given_up(job.token))

    def connected(self, key: object, version: int, max_axes: int) -> list[Job[T]]:
        """A connection is open whose open answer gave ``version`` and ``max_axes``: frames
        go on it. ``key`` names what a job's blocks depend on (the command set): the queued
        jobs made for another key end :attr:`Ending.STALE` (returned), never sent."""
        self._open = True
        self.idle = True
        self._key = key
        self._limit = max_response_body(version) - 2  # the bodies' room after the block count
        self._axis_bytes = _AXIS_RECORD * max_axes
        self.failure = None
        self.broken = False
        self.in_flight = None
        self.frame_deadline = _NEVER
        self._rx.clear()
        stale = [job for job in self.queue if job.ending is None and job.key != key]
        for job in stale:
            job.ending = Ending.STALE
        return stale

    def lost(self, keep_queued: bool) -> list[Job[T]]:
        """The connection ended: the jobs that end with it (those in flight, and the queued
        ones unless ``keep_queued``: they go on the next connection)."""
        self._open = self.idle = False
        self._rx.clear()
        ended = self._end_in_flight(Ending.LOST)
        if not keep_queued:
            ended += self._end_queue(Ending.LOST)
        return ended

    # -- calls -------------------------------------------------------------------------------
    def submit(self, part: Part, deadline: float, key: object, token: T) -> Job[T]:
        """Queue one frame's worth of a call (``deadline`` in the shell's clock, ``inf`` for
        none; ``key`` what ``part`` was encoded for). A job made for another key than the
        open connection's is ended :attr:`Ending.STALE` at once (``job.ending`` says so)."""
        job = Job(part, deadline, key, token)
        if self._open and key != self._key:
            job.ending = Ending.STALE
            return job
        self.queue.append(job)
        if deadline < self.wake_at:
            self.wake_at = deadline
        return job

    def abandon(self, job: Job[T]) -> None:
        """The caller of ``job`` gave up: queued, it is never sent; sent, its blocks are
        dropped when the answer comes."""
        if job.ending is None:
            job.ending = Ending.ABANDONED

    def next_frame(self) -> bytes | None:
        """The next frame to write, when the session is :attr:`idle` and jobs wait: the jobs
        at the head of the queue that fit in one frame (at least one) are in flight from now.
        None when there is nothing to send (or no frame may go)."""
        if not self.idle:
            return None
        queue = self.queue
        job = queue[0] if len(queue) == 1 else None
        if job is not None and job.ending is None and not self._given_up(job.token):
            # one job waiting (a sequential caller): the frame its part keeps
            queue.popleft()
            batch = [job]
            count = job.part.count
            latest = job.deadline
            frame = job.part.frame
        else:
            batch, count, latest, frame = self._pack()
            if not batch:
                return None
        for job in batch:
            job.sent = True
        self.in_flight = batch
        self.idle = False
        self._in_flight_blocks = count
        self.frame_deadline = latest
        self.frames_sent += 1
        self.blocks_sent += count
        return frame

    def _pack(self) -> tuple[list[Job[T]], int, float, bytes]:
        """The jobs at the head of the queue that fit in one frame (at least one, whatever its
        size), taken from the queue: those jobs, their block count, their latest deadline and
        their frame (no jobs: none waits)."""
        queue = self.queue
        batch: list[Job[T]] = []
        blocks: list[bytes] = []
        blocks_left = self.max_blocks
        answer_left = self._limit
        send_left = min(self._limit, _SEND_LIMIT)
        given_up = self._given_up
        latest = 0.0
        # Jobs of one call in a row share their part: how many of them the frame still takes
        # (``room``) is reckoned once a run, from what is left of its blocks and bodies.
        run: Part | None = None
        room = answer = size = 0
        while queue:
            job = queue[0]
            if job.ending is not None or given_up(job.token):
                queue.popleft()
                job.ending = job.ending or Ending.ABANDONED
                continue
            part = job.part
            if part is not run:
                run = part
                answer = part.answer_fixed + part.answer_axes * self._axis_bytes
                size = len(part.blocks)
                room = min(
                    blocks_left // max(part.count, 1),
                    answer_left // max(answer, 1),
                    send_left // max(size, 1),
                )
                if not batch:
                    room = max(room, 1)  # a frame takes at least one job, whatever its size
            if room <= 0:
                break
            room -= 1
            queue.popleft()
            batch.append(job)
            blocks.append(part.blocks)
            blocks_left -= part.count
            answer_left -= answer
            send_left -= size
            if job.deadline > latest:
                latest = job.deadline
        count = self.max_blocks - blocks_left
        if len(batch) > 1:
            return batch, count, latest, request_frame(b"".join(blocks), count)
        return batch, count, latest, batch[0].part.frame if batch else b""

    # -- bytes and time --------------------------------------------------------------------
    def receive(self, data: bytes) -> list[Job[T]]:
        """Bytes of B: the jobs they end (the answer of the frame in flight, when whole). On
        bytes no frame asked for, or an answer the library refuses, :attr:`failure` says why
        and the jobs in flight end LOST."""
        if self.failure is not None:
            return []
        rx = self._rx
        if not rx and len(data) >= NATIVE_HEADER_SIZE:
            magic, _, _, length = NATIVE_HEADER.unpack_from(data)
            if magic == _MAGIC and len(data) == NATIVE_HEADER_SIZE + length:
                return self._answered(data)  # the usual read: one whole answer
        rx += data
        ended: list[Job[T]] = []
        while len(rx) >= NATIVE_HEADER_SIZE:
            magic, _, _, length = NATIVE_HEADER.unpack_from(rx)
            if magic != _MAGIC:
                return ended + self._fail(NOT_A_FRAME, True)
            end = NATIVE_HEADER_SIZE + length
            if len(rx) < end:
                break
            raw = bytes(rx[:end])
            del rx[:end]
            ended += self._answered(raw)
            if self.failure is not None:
                return ended
        if rx and self.in_flight is None:
            ended += self._fail("bytes no request asked for")
        return ended

    def _answered(self, raw: bytes) -> list[Job[T]]:
        """The whole frame ``raw`` came: the answer to the frame in flight."""
        jobs = self.in_flight
        if jobs is None:
            return self._fail("bytes no request asked for")
        try:
            blocks = answer_blocks(raw, self._in_flight_blocks)
        except AnswerRefused as exc:
            return self._fail(str(exc), True)
        self.in_flight = None
        self.idle = self._open
        self.frame_deadline = _NEVER
        if isinstance(blocks, int):
            ended = [job for job in jobs if job.ending is None]
            for job in ended:
                job.ending = Ending.REFUSED
                job.ew = blocks
            return ended
        if len(jobs) == 1:  # a lone job: the whole answer is its own
            job = jobs[0]
            if job.ending is not None:
                return []
            job.ending = _ANSWERED
            job.blocks = blocks
            return jobs
        # each job of the frame its own ``count`` blocks, in order
        ended = []
        pos = 0
        for job in jobs:
            end = pos + job.part.count
            if job.ending is None:
                job.ending = _ANSWERED
                job.blocks = blocks[pos:end]
                ended.append(job)
            pos = end
        return ended

    @property
    def overdue(self) -> bool:
        """Whether the frame in flight is past the latest deadline of its jobs: its late
        answer is awaited (to be dropped) before the next frame leaves."""
        return self.in_flight is not None and self.frame_deadline == _OVERDUE

    def expire(self, now: float) -> list[Job[T]]:
        """The jobs whose deadline is ``now`` or earlier, ended TIMED_OUT. A frame past its
        own deadline with no answer is :attr:`overdue`: its late answer is awaited, until a
        job queued behind it reaches its deadline unsent; then the connection fails."""
        ended, earliest = _time_out(self.queue, now)
        gave_up = bool(ended)
        if gave_up:
            self.queue = deque(job for job in self.queue if job.ending is None)
        jobs = self.in_flight
        if jobs is not None:
            sent, due = _time_out(jobs, now)
            ended += sent
            earliest = min(earliest, due)
            if self.frame_deadline <= now:
                if gave_up:  # a call waited its whole time behind the frame
                    ended += self._fail("no answer within the timeout")
                else:
                    self.frame_deadline = _OVERDUE
            elif self.frame_deadline < earliest:
                earliest = self.frame_deadline
        self.wake_at = earliest
        return ended

    def close(self) -> list[Job[T]]:
        """The client is closing: every job not ended ends LOST."""
        self._open = self.idle = False
        return self._end_in_flight(Ending.LOST) + self._end_queue(Ending.LOST)

    # -- helpers -----------------------------------------------------------------------------
    def _fail(self, why: str, broken: bool = False) -> list[Job[T]]:
        """The connection can carry no further frame (``broken``: the peer broke FOCAS/2):
        the jobs in flight end LOST."""
        self.failure = why
        self.broken = broken
        self.idle = False
        self._rx.clear()
        return self._end_in_flight(Ending.LOST)

    def _end_in_flight(self, ending: Ending) -> list[Job[T]]:
        jobs, self.in_flight = self.in_flight or [], None
        self.frame_deadline = _NEVER
        ended = [job for job in jobs if job.ending is None]
        for job in ended:
            job.ending = ending
        return ended

    def _end_queue(self, ending: Ending) -> list[Job[T]]:
        queue, self.queue = self.queue, deque()
        ended = [job for job in queue if job.ending is None]
        for job in ended:
            job.ending = ending
        return ended
