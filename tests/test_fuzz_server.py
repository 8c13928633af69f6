"""Fuzzing the server over TCP with generated frames and raw byte streams.

A real :class:`FocasServer` runs in this process on 127.0.0.1 (port 0), so that the tests can
reach its machine and its counters. Each example sends many frames over one connection. The
properties:

* the server never crashes: no handler raises (nothing is logged at ERROR) and a fresh
  connection is still served afterwards;
* every well-framed request gets exactly one answer carrying its command and request id, and
  the answer decodes with the command's response codec (unknown ids answer ``EW_FUNC``);
* only a connection that breaks framing (a length prefix outside ``4..max_frame``) is closed,
  and it is closed after the answers to the frames before the violation;
* the machine's state (``Machine.state_digest``) changes only through a write or control
  command that answered ``EW_OK``. The machine's time stands still (a ``ManualClock`` nobody
  steps), so a program a cycle start set running does not move between two reads.

The frame oracle here is written from docs/protocol.md section 1, not taken from the decoder under
test. The default run fuzzes about 10,000 frames; the ``slow`` variants many more
(``pytest -m slow tests/test_fuzz_server.py``). With ``FOCAS_NET_FUZZ_STATS=<file>`` set, the
number of frames, streams and bytes sent is appended to that file as one JSON line per test.
"""

from __future__ import annotations

import asyncio
import json
import logging
import os
import struct
from collections import Counter
from collections.abc import AsyncIterator, Iterator
from typing import Any, Final

import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st
from support import IO_TIMEOUT, Served, Wire, ew_of, serving

from focas_net.errors import EW, PayloadError
from focas_net.protocol import COMMANDS, Command, encode_ew, encode_frame
from focas_net.sim import default_machine
from focas_net.sim.nc import ManualClock

MAX_FRAME: Final = 65_536
INJECT_FAULT: Final = int(Command.SIM_INJECT_FAULT)
#: Commands that change machine state: the writes, the program store and the simulator
#: control commands.
STATE_CHANGING: Final = frozenset(
    int(c)
    for c in (
        Command.WRPARAM,
        Command.WRMACRO,
        Command.WRPMCRNG,
        Command.WRPROGRAM,
        Command.DELPROGRAM,
        Command.SELPROGRAM,
        Command.SIM_SET_PANEL,
        Command.SIM_RAISE_ALARM,
        Command.SIM_CLEAR_ALARMS,
        Command.SIM_SET_PMC,
        Command.SIM_INJECT_FAULT,
        Command.SIM_VACATE_MACRO,
        Command.SIM_CYCLE,
        Command.SIM_SET_OVERRIDES,
    )
)
EW_FUNC_BYTES: Final = encode_ew(EW.FUNC)
MARKER_COMMAND: Final = int(Command.RDCNCSTAT)

_NO_FIXTURE_RESET = [HealthCheck.function_scoped_fixture, HealthCheck.too_slow]
CI = settings(max_examples=100, deadline=None, suppress_health_check=_NO_FIXTURE_RESET)
CI_SMALL = settings(max_examples=80, deadline=None, suppress_health_check=_NO_FIXTURE_RESET)
SLOW = settings(max_examples=2_500, deadline=None, suppress_health_check=_NO_FIXTURE_RESET)


# -- statistics (figures for the documentation) --------------------------------------------


@pytest.fixture
def stats(request: pytest.FixtureRequest) -> Iterator[Counter[str]]:
    counts: Counter[str] = Counter()
    yield counts
    path = os.environ.get("FOCAS_NET_FUZZ_STATS")
    if path:
        with open(path, "a", encoding="utf-8") as out:
            out.write(json.dumps({"test": request.node.name, **counts}) + "\n")


# -- the server and a watch on its error log ------------------------------------------------


class ErrorLog(logging.Handler):
    """Collects records at ERROR and above (a handler that raised logs one)."""

    def __init__(self) -> None:
        super().__init__(logging.ERROR)
        self.records: list[logging.LogRecord] = []

    def emit(self, record: logging.LogRecord) -> None:
        self.records.append(record)


@pytest.fixture
def errors() -> Iterator[ErrorLog]:
    handler = ErrorLog()
    logger = logging.getLogger("focas_net")
    logger.addHandler(handler)
    try:
        yield handler
    finally:
        logger.removeHandler(handler)


@pytest.fixture
async def fuzz_server() -> AsyncIterator[Served]:
    async with serving(default_machine(sim_clock=ManualClock()), max_frame=MAX_FRAME) as served:
        yield served
        await assert_still_serving(served)


async def assert_still_serving(served: Served) -> None:
    """A fresh connection is accepted and answered."""
    async with await served.connect() as wire:
        answer = await wire.call(MARKER_COMMAND)
        assert ew_of(MARKER_COMMAND, answer) == 0


# -- strategies ------------------------------------------------------------------------------

i16 = st.integers(-0x8000, 0x7FFF)
u16 = st.integers(0, 0xFFFF)
i32 = st.integers(-(2**31), 2**31 - 1)

PARAM_NUMBERS = st.one_of(st.sampled_from([20, 1320, 1420, 1815, 3216, 6711, 6712, 300]), i16)
MACRO_NUMBERS = st.one_of(
    st.sampled_from([0, 1, 33, 34, 99, 100, 199, 200, 499, 500, 999, 1000, 3000]), i16
)
AXIS = st.integers(-2, 5)
PMC_AREA = st.integers(-1, 14)
PMC_ADDRESS = st.one_of(st.sampled_from([0, 31, 99, 127, 249, 399, 767, 7999, 9999]), u16)


def _pack(fmt: str) -> Any:
    def pack(*values: int) -> bytes:
        return struct.pack(fmt, *values)

    return pack


@st.composite
def pmc_header(draw: st.DrawFn, *, with_data: bool) -> bytes:
    type_a = draw(PMC_AREA)
    type_d = draw(st.sampled_from([0, 0, 0, 1, -1]))
    start = draw(PMC_ADDRESS)
    span = draw(st.one_of(st.integers(-2, 34), u16))
    end = (start + span) & 0xFFFF
    head = struct.pack("<hhHH", type_a, type_d, start, end)
    if not with_data:
        return head
    count = (end - start + 1) if end >= start else 0
    size = draw(st.sampled_from([count, count, max(count - 1, 0), count + 1, 0]))
    return head + draw(st.binary(min_size=min(size, 64), max_size=min(size, 64)))


@st.composite
def raise_alarm_payload(draw: st.DrawFn) -> bytes:
    msg = draw(st.binary(max_size=40))
    msg_len = draw(st.sampled_from([len(msg), len(msg), len(msg) + 1, max(len(msg) - 1, 0), -1]))
    head = struct.pack(
        "<hhhh", draw(st.integers(-1, 4)), draw(st.integers(-2, 33)), draw(i16), msg_len
    )
    return head + msg


#: Payloads shaped like each known command's request, valid or close to it.
STRUCTURED: Final[dict[int, st.SearchStrategy[bytes]]] = {
    Command.RDCNCSTAT: st.just(b""),
    Command.SYSINFO: st.just(b""),
    Command.RDPARAM: st.builds(_pack("<hh"), PARAM_NUMBERS, AXIS),
    Command.RDDIAG: st.builds(_pack("<hh"), PARAM_NUMBERS, AXIS),
    Command.RDMACRO: st.builds(_pack("<h"), MACRO_NUMBERS),
    Command.RDALMMSG: st.builds(_pack("<hh"), st.integers(-2, 33), st.integers(-1, 34)),
    Command.RDALMHISTRY: st.builds(_pack("<h"), st.one_of(st.integers(-1, 252), i16)),
    Command.RDPMCRNG: pmc_header(with_data=False),
    Command.VERSAMAX_RDCONFIG: st.builds(
        _pack("<BHBH"),
        st.integers(0, 9),
        st.one_of(st.integers(0, 130), u16),
        st.integers(0, 11),
        st.one_of(st.integers(0, 200), u16),
    ),
    Command.WRPARAM: st.one_of(
        st.builds(_pack("<hhb"), PARAM_NUMBERS, AXIS, st.integers(-128, 127)),
        st.builds(_pack("<hhh"), PARAM_NUMBERS, AXIS, i16),
        st.builds(_pack("<hhi"), PARAM_NUMBERS, AXIS, i32),
    ),
    Command.WRMACRO: st.builds(
        _pack("<hhih"),
        MACRO_NUMBERS,
        st.sampled_from([8, 8, 8, 0, 7, 9, -8]),
        i32,
        st.integers(-2, 12),
    ),
    Command.WRPMCRNG: pmc_header(with_data=True),
    Command.SIM_SET_PMC: pmc_header(with_data=True),
    Command.WRUNLOCKPARAM: st.binary(min_size=4, max_size=4),
    Command.SIM_SET_PANEL: st.builds(
        _pack("<hhh"), st.integers(-1, 11), st.integers(-1, 2), st.integers(-1, 2)
    ),
    Command.SIM_RAISE_ALARM: raise_alarm_payload(),
    Command.SIM_CLEAR_ALARMS: st.builds(_pack("<hh"), st.integers(-2, 33), i16),
}

KNOWN_SAFE: Final = sorted(c for c in COMMANDS if c != INJECT_FAULT)
UNKNOWN_IDS = u16.filter(lambda c: c not in COMMANDS)


def payload_for(command: int) -> st.SearchStrategy[bytes]:
    """Any payload for ``command``: random bytes of any small size, or a request shape."""
    choices: list[st.SearchStrategy[bytes]] = [st.binary(max_size=48)]
    shaped = STRUCTURED.get(command)
    if shaped is not None:
        choices += [shaped, shaped]
    return st.one_of(*choices)


#: A request that may be any known command (0x0E05 only with a payload that cannot arm a
#: fault: arming a drop would close the connection by design) or an unknown id.
inject_fault_request = st.tuples(
    st.just(INJECT_FAULT), st.binary(max_size=24).filter(lambda p: len(p) != 10)
)
known_request = st.one_of(*[st.tuples(st.just(c), payload_for(c)) for c in KNOWN_SAFE])
unknown_request = st.tuples(UNKNOWN_IDS, st.binary(max_size=48))
big_request = st.tuples(
    st.one_of(st.sampled_from(KNOWN_SAFE), UNKNOWN_IDS), st.binary(min_size=64, max_size=4_096)
)
request = st.one_of(
    known_request, known_request, known_request, unknown_request, inject_fault_request, big_request
)
batches = st.lists(request, min_size=48, max_size=160)

write_commands = sorted(STATE_CHANGING - {INJECT_FAULT})
write_request = st.one_of(*[st.tuples(st.just(c), payload_for(c)) for c in write_commands])


# -- the frame oracle (docs/protocol.md section 1) ----------------------------------------------


def split_frames(
    stream: bytes, max_frame: int = MAX_FRAME
) -> tuple[list[tuple[int, int, bytes]], int, bool]:
    """Frames complete in ``stream``, where the first incomplete one starts, and whether a
    length prefix outside ``4..max_frame`` ends the stream (a framing violation)."""
    frames: list[tuple[int, int, bytes]] = []
    pos = 0
    while len(stream) - pos >= 4:
        (length,) = struct.unpack_from("<I", stream, pos)
        if not 4 <= length <= max_frame:
            return frames, pos, True
        end = pos + 4 + length
        if end > len(stream):
            break
        command, request_id = struct.unpack_from("<HH", stream, pos + 4)
        frames.append((command, request_id, stream[pos + 8 : end]))
        pos = end
    return frames, pos, False


def completion(rest: bytes) -> bytes:
    """Bytes that finish the partial frame ``rest`` (zeros); may make a bad length prefix,
    which the oracle then reports as a violation."""
    if not rest:
        return b""
    head = rest[:4].ljust(4, b"\x00")
    (length,) = struct.unpack("<I", head)
    if not 4 <= length <= MAX_FRAME:
        return head[len(rest) :]
    return bytes(4 + length - len(rest))


def arms_fault(frames: list[tuple[int, int, bytes]]) -> bool:
    return any(c == INJECT_FAULT and len(p) == 10 for c, _, p in frames)


# -- helpers -------------------------------------------------------------------------------


def cuts_of(data: bytes, cuts: list[int]) -> list[bytes]:
    """``data`` split at the given offsets (taken modulo its length)."""
    if not data:
        return []
    points = sorted({c % len(data) for c in cuts} - {0})
    pieces = []
    last = 0
    for p in [*points, len(data)]:
        pieces.append(data[last:p])
        last = p
    return pieces


async def send_pieces(wire: Wire, pieces: list[bytes]) -> None:
    for piece in pieces:
        wire.send_raw(piece)
        await wire.writer.drain()
        await asyncio.sleep(0)


def check_answer(command: int, payload: bytes) -> None:
    """The answer is what its command's response codec accepts."""
    spec = COMMANDS.get(command)
    if spec is None:
        assert payload == EW_FUNC_BYTES, f"unknown id 0x{command:04X} answered {payload.hex()}"
        return
    try:
        spec.response.decode(payload)
    except PayloadError as exc:  # pragma: no cover - a failure report
        pytest.fail(f"answer to 0x{command:04X} does not decode: {exc} ({payload.hex()})")


async def collect_until(
    wire: Wire, marker: tuple[int, int], limit: int
) -> list[tuple[int, int, bytes]]:
    """Answers up to and including the one to ``marker`` (at most ``limit`` frames)."""
    got: list[tuple[int, int, bytes]] = []
    async with asyncio.timeout(IO_TIMEOUT * 2):
        for _ in range(limit):
            frame = await wire.recv()
            got.append((frame.command, frame.request_id, frame.payload))
            if (frame.command, frame.request_id) == marker:
                return got
    pytest.fail(f"no answer to the marker {marker} within {limit} frames")


# -- property: batches of well-framed requests ---------------------------------------------


async def batch_property(
    served: Served,
    errors: ErrorLog,
    stats: Counter[str],
    requests: list[tuple[int, bytes]],
    base_id: int,
    cuts: list[int],
) -> None:
    machine = served.machine
    before = machine.state_digest()
    ids = [(base_id + i) & 0xFFFF for i in range(len(requests))]
    marker = (MARKER_COMMAND, (base_id + len(requests)) & 0xFFFF)
    data = b"".join(encode_frame(c, r, p) for (c, p), r in zip(requests, ids, strict=True))
    data += encode_frame(*marker)
    violations = served.listener.violations
    async with await served.connect() as wire:
        await send_pieces(wire, cuts_of(data, cuts))
        answers = await collect_until(wire, marker, len(requests) + 1)
        # the connection is still open: one more request is answered
        assert await wire.call(MARKER_COMMAND)
    stats["frames"] += len(requests) + 1
    stats["bytes"] += len(data)
    assert served.listener.violations == violations
    expected = Counter((c, r) for (c, _), r in zip(requests, ids, strict=True))
    expected[marker] += 1
    got = Counter((c, r) for c, r, _ in answers)
    assert got == expected, "every request answered exactly once, with its command and id"
    changed = False
    for command, _, payload in answers:
        check_answer(command, payload)
        if command in STATE_CHANGING and ew_of(command, payload) == 0:
            changed = True
    if not changed:
        assert machine.state_digest() == before, "state changed without a successful write"
    assert not errors.records, [r.getMessage() for r in errors.records]


@CI
@given(requests=batches, base_id=u16, cuts=st.lists(st.integers(0, 2**20), max_size=6))
async def test_every_well_framed_request_is_answered_once(
    fuzz_server: Served,
    errors: ErrorLog,
    stats: Counter[str],
    requests: list[tuple[int, bytes]],
    base_id: int,
    cuts: list[int],
) -> None:
    await batch_property(fuzz_server, errors, stats, requests, base_id, cuts)


@pytest.mark.slow
@SLOW
@given(requests=batches, base_id=u16, cuts=st.lists(st.integers(0, 2**20), max_size=6))
async def test_every_well_framed_request_is_answered_once_long(
    fuzz_server: Served,
    errors: ErrorLog,
    stats: Counter[str],
    requests: list[tuple[int, bytes]],
    base_id: int,
    cuts: list[int],
) -> None:
    await batch_property(fuzz_server, errors, stats, requests, base_id, cuts)


# -- property: raw byte streams --------------------------------------------------------------

frame_segment = st.builds(
    lambda cp, rid: encode_frame(cp[0], rid, cp[1]), st.one_of(known_request, unknown_request), u16
)
length_segment = st.builds(
    lambda n, body: struct.pack("<I", n) + body,
    st.one_of(
        st.integers(0, 2**32 - 1), st.integers(0, 8), st.integers(MAX_FRAME - 2, MAX_FRAME + 2)
    ),
    st.binary(max_size=16),
)
segments = st.one_of(st.binary(min_size=1, max_size=32), length_segment, *[frame_segment] * 6)
#: Raw streams: arbitrary bytes, or well-formed frames followed by arbitrary segments.
raw_streams = st.one_of(
    st.binary(min_size=1, max_size=512),
    st.builds(
        lambda head, tail: b"".join(head + tail),
        st.lists(frame_segment, min_size=8, max_size=40),
        st.lists(segments, min_size=1, max_size=8),
    ),
)


async def stream_property(
    served: Served, errors: ErrorLog, stats: Counter[str], stream: bytes, cuts: list[int]
) -> None:
    # a stream opening with A0 A0 A0 A0 is a native connection (tests/test_native_fuzz.py)
    assume(not stream.startswith(b"\xa0\xa0\xa0\xa0"))
    frames, rest_at, violated = split_frames(stream)
    if not violated:
        stream += completion(stream[rest_at:])
        frames, rest_at, violated = split_frames(stream)
    assume(not arms_fault(frames))
    marker = (MARKER_COMMAND, 0xFEED)
    if violated:
        # nothing after the bad length prefix: bytes the server never reads would make its
        # close a reset, which may discard answers still in flight
        stream = stream[: rest_at + 4]
    else:
        assert rest_at == len(stream)
        stream += encode_frame(*marker)
        frames.append((*marker, b""))
    machine = served.machine
    before = machine.state_digest()
    violations = served.listener.violations
    async with await served.connect() as wire:
        await send_pieces(wire, cuts_of(stream, cuts))
        answers = []
        async with asyncio.timeout(IO_TIMEOUT * 2):
            for _ in range(len(frames)):
                frame = await wire.recv()
                answers.append((frame.command, frame.request_id, frame.payload))
        if violated:
            assert await wire.closed_by_peer(), "a framing violation closes the connection"
        else:
            # not closed: one more request is answered
            assert await wire.call(MARKER_COMMAND)
    stats["streams"] += 1
    stats["frames"] += len(frames)
    stats["bytes"] += len(stream)
    if violated:
        stats["violations"] += 1
    assert sorted((c, r) for c, r, _ in answers) == sorted((c, r) for c, r, _ in frames)
    changed = False
    for command, _, payload in answers:
        check_answer(command, payload)
        if command in STATE_CHANGING and ew_of(command, payload) == 0:
            changed = True
    if not changed:
        assert machine.state_digest() == before
    if violated:
        await _wait_for(lambda: served.listener.violations == violations + 1)
    assert served.listener.violations == violations + int(violated)
    assert not errors.records, [r.getMessage() for r in errors.records]


async def _wait_for(predicate: Any) -> None:
    for _ in range(200):
        if predicate():
            return
        await asyncio.sleep(0.005)


@CI
@given(stream=raw_streams, cuts=st.lists(st.integers(0, 2**20), max_size=4))
async def test_raw_streams_close_only_on_framing_violations(
    fuzz_server: Served, errors: ErrorLog, stats: Counter[str], stream: bytes, cuts: list[int]
) -> None:
    await stream_property(fuzz_server, errors, stats, stream, cuts)


@pytest.mark.slow
@SLOW
@given(stream=raw_streams, cuts=st.lists(st.integers(0, 2**20), max_size=4))
async def test_raw_streams_close_only_on_framing_violations_long(
    fuzz_server: Served, errors: ErrorLog, stats: Counter[str], stream: bytes, cuts: list[int]
) -> None:
    await stream_property(fuzz_server, errors, stats, stream, cuts)


# -- property: invalid writes leave the machine as it was ------------------------------------


async def writes_property(
    served: Served, errors: ErrorLog, stats: Counter[str], writes: list[tuple[int, bytes]]
) -> None:
    machine = served.machine
    async with await served.connect() as wire:
        for command, payload in writes:
            before = machine.state_digest()
            answer = await wire.call(command, payload)
            check_answer(command, payload=answer)
            ew = ew_of(command, answer)
            after = machine.state_digest()
            stats["frames"] += 1
            if ew:
                stats["refused_writes"] += 1
                assert after == before, (
                    f"0x{command:04X} {payload.hex()} answered EW {ew} but changed the machine"
                )
            else:
                stats["accepted_writes"] += 1
    assert not errors.records, [r.getMessage() for r in errors.records]


@CI_SMALL
@given(writes=st.lists(write_request, min_size=10, max_size=60))
async def test_refused_writes_change_nothing(
    fuzz_server: Served, errors: ErrorLog, stats: Counter[str], writes: list[tuple[int, bytes]]
) -> None:
    await writes_property(fuzz_server, errors, stats, writes)


@pytest.mark.slow
@SLOW
@given(writes=st.lists(write_request, min_size=10, max_size=60))
async def test_refused_writes_change_nothing_long(
    fuzz_server: Served, errors: ErrorLog, stats: Counter[str], writes: list[tuple[int, bytes]]
) -> None:
    await writes_property(fuzz_server, errors, stats, writes)


async def test_a_run_of_invalid_writes_keeps_the_digest(fuzz_server: Served) -> None:
    """Hand-picked refusals of every write and control command, one connection, one digest
    before and after the whole run."""
    machine = fuzz_server.machine
    before = machine.state_digest()
    refused: list[tuple[int, bytes, int]] = [
        (Command.WRPARAM, struct.pack("<hhi", 6711, 0, 5), EW.PASSWD),  # PWE off
        (Command.WRPARAM, struct.pack("<hhh", 6711, 0, 5), EW.LENGTH),  # wrong width
        (Command.WRPARAM, struct.pack("<hhi", 1320, 0, 5), EW.ATTRIB),  # axis item, axis 0
        (Command.WRPARAM, struct.pack("<hhi", 9999, 0, 5), EW.NUMBER),
        (Command.WRPARAM, b"\x01\x02\x03", EW.LENGTH),
        (Command.WRMACRO, struct.pack("<hhih", 1, 8, 5, 10), EW.DATA),
        (Command.WRMACRO, struct.pack("<hhih", 1, 7, 5, 0), EW.LENGTH),
        (Command.WRMACRO, struct.pack("<hhih", 5000, 8, 5, 0), EW.NUMBER),
        (Command.WRPMCRNG, struct.pack("<hhHH", 1, 0, 0, 0) + b"\x01", EW.PROT),  # X protected
        (Command.WRPMCRNG, struct.pack("<hhHH", 5, 0, 7999, 8000) + b"\x01\x02", EW.NUMBER),
        (Command.WRPMCRNG, struct.pack("<hhHH", 5, 0, 0, 1) + b"\x01", EW.LENGTH),
        (Command.WRPMCRNG, struct.pack("<hhHH", 5, 0, 0, 32) + bytes(33), EW.LENGTH),
        (Command.WRPMCRNG, struct.pack("<hhHH", 12, 0, 0, 0) + b"\x01", EW.NOOPT),  # no E
        (Command.WRPMCRNG, struct.pack("<hhHH", 5, 1, 0, 0) + b"\x01", EW.ATTRIB),
        (Command.SIM_SET_PANEL, struct.pack("<hhh", 2, 1, 0), EW.DATA),
        (Command.SIM_SET_PANEL, struct.pack("<hhh", 0, 2, 0), EW.DATA),
        (Command.SIM_RAISE_ALARM, struct.pack("<hhhh", 0, 32, 1, 0), EW.DATA),
        (Command.SIM_RAISE_ALARM, struct.pack("<hhhh", 4, 3, 1, 0), EW.ATTRIB),
        (Command.SIM_RAISE_ALARM, struct.pack("<hhhh", 0, 3, 1, 5) + b"abc", EW.LENGTH),
        (Command.SIM_SET_PMC, struct.pack("<hhHH", 5, 0, 7999, 8000) + b"\x01\x02", EW.NUMBER),
        (Command.SIM_INJECT_FAULT, struct.pack("<hhhi", 9, 0, 1, 0), EW.DATA),
    ]
    async with await fuzz_server.connect() as wire:
        for command, payload, want in refused:
            assert await wire.ew(command, payload) == want, f"0x{command:04X} {payload.hex()}"
    assert machine.state_digest() == before


async def test_frames_before_a_violation_are_answered(fuzz_server: Served) -> None:
    """Well-framed requests and a bad length prefix in one write: the requests are answered,
    then the connection is closed, whatever the segmentation."""
    data = encode_frame(MARKER_COMMAND, 1) + encode_frame(MARKER_COMMAND, 2)
    data += struct.pack("<I", MAX_FRAME + 1) + b"\x00" * 4
    async with await fuzz_server.connect() as wire:
        wire.send_raw(data)
        await wire.writer.drain()
        answers = []
        with pytest.raises(EOFError):
            for _ in range(3):
                frame = await wire.recv()
                answers.append((frame.command, frame.request_id))
    assert answers == [(MARKER_COMMAND, 1), (MARKER_COMMAND, 2)]
