"""Fuzzing the native FOCAS/2 front end over TCP with generated frames and raw byte streams.

A real :class:`FocasServer` runs in this process on 127.0.0.1 (port 0); a connection whose
first four bytes are ``A0 A0 A0 A0`` is a native one. Two machines are served: the built-in
one (a 0i-F, answering version 3, the 30i command set) and the same machine as a 16i-class
control (version 2, the 16i set, 1450-byte answers). The properties:

* the server never crashes: nothing is logged at ERROR and a fresh native connection is still
  opened and answered afterwards;
* every well-formed request frame gets exactly one answer frame, in order: an open request an
  open answer of the size its version announces, a data request a data answer with one block
  per request block (one block for an empty request), each echoing its block's device, path
  and command, ``EW_FUNC`` for a command not served, ``EW_PATH`` for a path the machine has not
  (other than 0; the CNC ID, the alarm history, the parameter information and the PMC answer
  whatever the path), no
  data with any other refusal, and the body within the answer version's limit;
* only a framing violation closes a connection (bad magic, a body over the limit, a frame type
  not served, an open body that is not one word, a block list that does not walk to the end of
  its body, a data request before the open request); a close request is answered, then the
  server closes;
* the machine's state (``Machine.state_digest``) changes only through a write block
  (``0x16``, ``0xA8``, ``0x0F``, ``0x8E``, PMC ``0x8002``) that answered ``EW_OK``.

The frame and block oracle here is written from docs/native-protocol.md, not taken from the
decoder under test. The default run sends a few thousand frames; the ``slow`` variants many
more (``pytest -m slow tests/test_native_fuzz.py``).
"""

from __future__ import annotations

import asyncio
import logging
import struct
from collections.abc import AsyncIterator, Iterator
from dataclasses import dataclass
from typing import Final

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from support import IO_TIMEOUT, serving

from focas_net.errors import EW
from focas_net.native import DEFAULT_MAX_BODY, Device, NativeCommand
from focas_net.server import FocasServer
from focas_net.sim import Machine, default_machine

MAGIC: Final = b"\xa0\xa0\xa0\xa0"
HEADER: Final = struct.Struct(">IHHH")
REQUEST_HEAD: Final = struct.Struct(">HHHH5i")
ANSWER_HEAD: Final = struct.Struct(">HHHHhhhH")
OPEN, CLOSE, DATA = 0x0101, 0x0201, 0x2101
OPEN_ANSWER, CLOSE_ANSWER, DATA_ANSWER = 0x0102, 0x0202, 0x2102
#: Program transfer requests (docs/native-protocol.md, "Programs"): served after the open.
UPLOAD, DOWNLOAD, DOWNLOAD_DATA, DOWNLOAD_END = 0x1501, 0x1101, 0x1204, 0x1301
UPLOAD_END_ANSWER, UPLOAD_ABORT = 0x1702, 0x1804
TRANSFERS: Final = frozenset(
    {UPLOAD, DOWNLOAD, DOWNLOAD_DATA, DOWNLOAD_END, UPLOAD_END_ANSWER, UPLOAD_ABORT}
)
SERVED_TYPES: Final = frozenset({OPEN, CLOSE, DATA}) | TRANSFERS
#: The control classes fuzzed, by the version word they answer.
CLASSES: Final = {"0i-F": 3, "16i": 2}
MAX_AXES: Final = 8

PMC_COMMANDS: Final = frozenset(c for c in NativeCommand if c.name.startswith("PMC_"))
#: ``(device, command)`` of every block the native front end serves (docs/native-protocol.md).
SERVED: Final = frozenset(
    (Device.PMC if c in PMC_COMMANDS else Device.CNC, int(c)) for c in NativeCommand
)
WRITES: Final = frozenset(
    {
        (Device.CNC, NativeCommand.WRMACRO),
        (Device.CNC, NativeCommand.WRMACRO_DOUBLE),
        (Device.CNC, NativeCommand.WRPARAM),
        (Device.CNC, NativeCommand.WRPARAM3),
        (Device.PMC, NativeCommand.PMC_WRPMCRNG),
        (Device.CNC, NativeCommand.DELETE),
        (Device.CNC, NativeCommand.SEARCH),
        (Device.CNC, NativeCommand.SETTIMER),
    }
)
EW_CODES: Final = frozenset(int(e) for e in EW)
#: ``(device, command)`` of the blocks that ignore the path word (docs/native-protocol.md).
PATH_INDEPENDENT: Final = frozenset(
    {
        (Device.CNC, NativeCommand.RDCNCID),
        (Device.CNC, NativeCommand.RDALMHISTRY),
        (Device.CNC, NativeCommand.RDPARAINFO),
        (Device.CNC, NativeCommand.RDPARAINFO3),
        (Device.CNC, NativeCommand.RDPDF_DRIVE),
        (Device.CNC, NativeCommand.RDPDF_INF),
        (Device.PMC, NativeCommand.PMC_RDPMCRNG),
        (Device.PMC, NativeCommand.PMC_WRPMCRNG),
        (Device.PMC, NativeCommand.PMC_RDPMCINFO),
        (Device.PMC, NativeCommand.PMC_RDPMCTITLE),
        (Device.CNC, NativeCommand.RDSYSSOFT),
        (Device.CNC, NativeCommand.RDETHERINFO),
        (Device.CNC, NativeCommand.RDPARANUM),
        (Device.CNC, NativeCommand.RDDIAGNUM),
        (Device.CNC, NativeCommand.RDDIAGINFO),
        (Device.CNC, NativeCommand.RDSETINFO),
    }
)

_NO_FIXTURE_RESET = [HealthCheck.function_scoped_fixture, HealthCheck.too_slow]
CI = settings(
    max_examples=40, deadline=None, derandomize=True, suppress_health_check=_NO_FIXTURE_RESET
)
SLOW = settings(
    max_examples=1_500, deadline=None, derandomize=True, suppress_health_check=_NO_FIXTURE_RESET
)


def max_answer_body(version: int) -> int:
    """The largest answer body FANUC's library accepts at ``version``."""
    return {0: 1450, 1: 1450, 2: 1450, 3: 2910, 4: 3470}.get(version, 4950)


# -- the server, the error log and a raw native wire -------------------------------------------


@pytest.fixture
def errors(caplog: pytest.LogCaptureFixture) -> Iterator[pytest.LogCaptureFixture]:
    caplog.set_level(logging.WARNING, logger="focas_net")
    yield caplog
    assert_no_errors(caplog)


def assert_no_errors(caplog: pytest.LogCaptureFixture) -> None:
    bad = [r.getMessage() for r in caplog.records if r.levelno >= logging.ERROR]
    assert not bad, bad


@dataclass
class Native:
    """A served machine, its version word and a way to open native connections to it."""

    server: FocasServer
    host: str
    port: int
    machine: Machine
    version: int

    @property
    def violations(self) -> int:
        return self.server.listeners[0].native_violations

    async def connect(self) -> NativeWire:
        async with asyncio.timeout(IO_TIMEOUT):
            reader, writer = await asyncio.open_connection(self.host, self.port)
        return NativeWire(reader, writer)

    async def opened(self) -> NativeWire:
        wire = await self.connect()
        wire.send(frame(OPEN, struct.pack(">H", 2)))
        kind, version, body = await wire.recv()
        assert kind == OPEN_ANSWER and version == self.version
        check_open_answer(version, body)
        return wire


class NativeWire:
    """A raw TCP connection; answers are split by this module's own reading of the header."""

    def __init__(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        self.reader = reader
        self.writer = writer

    def send(self, data: bytes) -> None:
        self.writer.write(data)

    async def recv(self) -> tuple[int, int, bytes]:
        """One answer frame: its type word, its version word and its body."""
        async with asyncio.timeout(IO_TIMEOUT):
            head = await self.reader.readexactly(HEADER.size)
            magic, version, kind, length = HEADER.unpack(head)
            assert magic == 0xA0A0A0A0, head.hex()
            body = await self.reader.readexactly(length)
        return kind, version, body

    async def closed_by_peer(self) -> bool:
        """True when the server closes the connection with nothing more to read."""
        try:
            async with asyncio.timeout(IO_TIMEOUT):
                rest = await self.reader.read(1)
        except ConnectionError:
            return True
        return rest == b""

    async def close(self) -> None:
        self.writer.close()
        try:
            await self.writer.wait_closed()
        except ConnectionError:
            pass

    async def __aenter__(self) -> NativeWire:
        return self

    async def __aexit__(self, *exc: object) -> None:
        await self.close()


@pytest.fixture(params=sorted(CLASSES))
async def native(request: pytest.FixtureRequest) -> AsyncIterator[Native]:
    machine = default_machine()
    machine.control_class = request.param
    async with serving(machine) as served:
        native = Native(served.server, served.host, served.port, machine, CLASSES[request.param])
        yield native
        await assert_still_serving(native)


async def assert_still_serving(native: Native) -> None:
    """A fresh native connection is opened and a status read answered."""
    async with await native.opened() as wire:
        wire.send(frame(DATA, request_body([Block(1, 1, NativeCommand.STATINFO)])))
        kind, _, body = await wire.recv()
        assert kind == DATA_ANSWER
        assert answer_blocks(body)[0].ew == 0


# -- frames and blocks, as docs/native-protocol.md describes them -----------------------------


def frame(kind: int, body: bytes = b"", version: int = 1) -> bytes:
    return HEADER.pack(0xA0A0A0A0, version, kind, len(body)) + body


@dataclass(frozen=True)
class Block:
    device: int
    path: int
    command: int
    args: tuple[int, int, int, int, int] = (0, 0, 0, 0, 0)
    extra: bytes = b""

    def encode(self) -> bytes:
        head = REQUEST_HEAD.pack(
            REQUEST_HEAD.size + len(self.extra), self.device, self.path, self.command, *self.args
        )
        return head + self.extra


def request_body(blocks: list[Block]) -> bytes:
    return struct.pack(">H", len(blocks)) + b"".join(b.encode() for b in blocks)


@dataclass(frozen=True)
class Answer:
    device: int
    path: int
    command: int
    ew: int
    detail1: int
    data: bytes


def answer_blocks(body: bytes) -> list[Answer]:
    """The blocks of a data answer; fails the test unless they walk to exactly its end."""
    assert len(body) >= 2, body.hex()
    (count,) = struct.unpack_from(">H", body)
    pos = 2
    blocks = []
    for index in range(count):
        assert len(body) - pos >= ANSWER_HEAD.size, f"answer block {index} truncated"
        length, device, path, command, ew, d1, _, size = ANSWER_HEAD.unpack_from(body, pos)
        assert length == ANSWER_HEAD.size + size, f"block {index}: length {length}, data {size}"
        data = body[pos + ANSWER_HEAD.size : pos + length]
        assert len(data) == size, f"answer block {index} data truncated"
        blocks.append(Answer(device, path, command, ew, d1, data))
        pos += length
    assert pos == len(body), f"{len(body) - pos} bytes after the last answer block"
    return blocks


def check_open_answer(version: int, body: bytes) -> None:
    """The size rule FANUC's library applies to an open answer."""
    if version <= 2:
        (paths,) = struct.unpack_from(">H", body, 8)
        assert len(body) == 16 + 8 * paths
    else:
        (paths,) = struct.unpack_from(">H", body, 10)
        assert len(body) == 40 + 32 * paths
    assert paths >= 1, "an open answer without a path makes FANUC's library fail"


def check_data_answer(version: int, request: list[Block], body: bytes) -> list[Answer]:
    """One answer block per request block, echoed, with a plausible EW code."""
    assert len(body) <= max_answer_body(version), f"answer body of {len(body)} bytes"
    answers = answer_blocks(body)
    if not request:
        assert len(answers) == 1, "an empty request is answered with one block"
        assert answers[0].ew != 0
        return answers
    assert len(answers) == len(request)
    for block, got in zip(request, answers, strict=True):
        assert (got.device, got.path, got.command) == (block.device, block.path, block.command)
        assert got.ew in EW_CODES, f"EW {got.ew} for 0x{block.command:04X}"
        if (block.device, block.command) not in SERVED:
            assert got.ew == EW.FUNC, f"unserved 0x{block.command:04X} answered {got.ew}"
        elif block.path not in (0, 1) and (block.device, block.command) not in PATH_INDEPENDENT:
            assert got.ew == EW.PATH, f"path {block.path} answered {got.ew}"
        if got.ew != 0:
            assert got.data == b"", f"a refusal with data: 0x{block.command:04X}"
        if got.ew == EW.NUMBER:
            assert got.detail1 == 1
    return answers


def wrote(request: list[Block], answers: list[Answer]) -> bool:
    """Whether a write block of ``request`` answered EW_OK."""
    return any(
        (b.device, b.command) in WRITES and a.ew == 0
        for b, a in zip(request, answers, strict=False)
    )


# -- strategies -----------------------------------------------------------------------------

i16 = st.integers(-0x8000, 0x7FFF)
u16 = st.integers(0, 0xFFFF)
i32 = st.integers(-(2**31), 2**31 - 1)

PARAM_NUMBERS = st.one_of(
    st.sampled_from([20, 1320, 1420, 1815, 3115, 3216, 6711, 8130, 9968, 300, 403]), i16
)
MACRO_NUMBERS = st.one_of(
    st.sampled_from([0, 1, 33, 34, 99, 100, 199, 500, 999, 1000, 4001, 5021]), i16
)
AXIS = st.integers(-2, 9)
PMC_ADDRESS = st.one_of(st.sampled_from([0, 31, 99, 127, 249, 767, 1449, 7999, 9999]), u16)
SMALL = st.one_of(st.integers(-3, 12), i32)
Args = tuple[int, int, int, int, int]
#: The five arguments of a request block and its extra bytes.
Shape = tuple[Args, bytes]


@st.composite
def args5(draw: st.DrawFn, *heads: st.SearchStrategy[int]) -> Args:
    """Five arguments: the first ones from ``heads``, the rest small or any."""
    values = [draw(h) for h in heads]
    values += [draw(SMALL) for _ in range(5 - len(values))]
    return (values[0], values[1], values[2], values[3], values[4])


def _same_twice(numbers: st.SearchStrategy[int]) -> st.SearchStrategy[tuple[int, int, int]]:
    return st.tuples(numbers, AXIS).flatmap(
        lambda t: st.tuples(
            st.just(t[0]), st.sampled_from([t[0], t[0], t[0] + 1, t[0] - 1]), st.just(t[1])
        )
    )


@st.composite
def item_read(draw: st.DrawFn) -> Shape:
    first, last, axis = draw(_same_twice(PARAM_NUMBERS))
    return (first, last, axis, 0, 0), b""


@st.composite
def macro_write(draw: st.DrawFn) -> Shape:
    n = draw(MACRO_NUMBERS)
    record = struct.pack(
        ">ihh", draw(i32), draw(st.sampled_from([10, 10, 2, 0, 16])), draw(st.integers(-2, 31))
    )
    record = draw(st.sampled_from([record, record, record[:7], record + b"\x00"]))
    return (n, n, 0, 0, draw(st.sampled_from([len(record), 8, 0]))), record


@st.composite
def double_write(draw: st.DrawFn) -> Shape:
    value = struct.pack(">d", draw(st.floats(allow_nan=True, allow_infinity=True)))
    value = draw(st.sampled_from([value, value, value[:4], bytes(8)]))
    return (draw(MACRO_NUMBERS), 0, 0, 0, len(value)), value


@st.composite
def param_write(draw: st.DrawFn, slot: int) -> Shape:
    slots = draw(st.sampled_from([MAX_AXES, MAX_AXES, 3, 0, MAX_AXES + 1]))
    head = struct.pack(">ihh", draw(PARAM_NUMBERS), draw(AXIS), draw(st.integers(-1, 5)))
    if slot == 4:
        body = b"".join(struct.pack(">i", draw(SMALL)) for _ in range(slots))
    else:
        body = b"".join(
            struct.pack(">ihh", draw(SMALL), draw(st.sampled_from([0, 10])), draw(AXIS))
            for _ in range(slots)
        )
    extra = head + body
    return (0, 0, 0, 0, len(extra)), extra


@st.composite
def pmc_range(draw: st.DrawFn, *, write: bool) -> Shape:
    start = draw(PMC_ADDRESS)
    end = start + draw(st.one_of(st.integers(-2, 40), st.integers(0, 3_000)))
    area = draw(st.one_of(st.integers(-1, 14), i16))
    data_type = draw(st.sampled_from([0, 0, 1, 2, 3, -1]))
    if not write:
        return (start, end, area, data_type, 0), b""
    count = max(end - start + 1, 0)
    size = draw(st.sampled_from([count, count, count, max(count - 1, 0), count + 1, 0]))
    data = bytes(draw(st.integers(0, 255)) for _ in range(min(size, 48))) + bytes(
        max(min(size, 1_200) - 48, 0)
    )
    return (start, end, area, data_type, len(data)), data


def plain(*heads: st.SearchStrategy[int]) -> st.SearchStrategy[Shape]:
    return st.tuples(args5(*heads), st.just(b""))


C = NativeCommand
#: Arguments and extra bytes shaped like each served command's request, valid or close to it.
SHAPED: Final[dict[int, st.SearchStrategy[Shape]]] = {
    C.RDPARAM: item_read(),
    C.RDPARAM3: item_read(),
    C.RDDIAG: item_read(),
    C.RDDIAG3: item_read(),
    C.RDPARAINFO: plain(PARAM_NUMBERS, st.integers(-1, 3)),
    C.RDPARAINFO3: plain(PARAM_NUMBERS, st.integers(-1, 3)),
    C.WRPARAM: param_write(4),
    C.WRPARAM3: param_write(8),
    C.RDMACRO: st.tuples(
        _same_twice(MACRO_NUMBERS).map(lambda t: (t[0], t[1], 0, 0, 0)), st.just(b"")
    ),
    C.WRMACRO: macro_write(),
    C.RDMACRO_DOUBLE: plain(MACRO_NUMBERS, st.integers(-1, 40)),
    C.WRMACRO_DOUBLE: double_write(),
    C.RDALMMSG: plain(
        st.integers(-2, 33), st.integers(-1, 34), st.just(2), st.sampled_from([32, 64, 0, 7])
    ),
    C.RDALMHISTRY: plain(st.integers(-1, 60), st.integers(-1, 60), st.integers(0, 2)),
    C.POSITION: plain(st.integers(-1, 8), AXIS),
    C.AXIS_NAME: plain(st.integers(-2, 2)),
    C.AXIS_UNIT: plain(st.integers(-1, 3)),
    C.AXIS_COUNT: plain(st.integers(-1, 4)),
    C.AXIS_DISPLAY: plain(st.integers(-1, 2), AXIS),
    C.RDSPLOAD: plain(st.integers(-1, 2), st.integers(-2, 3)),
    C.RDSVMETER: plain(st.integers(-1, 2)),
    C.RDTIMER: plain(st.integers(-1, 5)),
    C.RDPROGDIR: plain(st.integers(-1, 10), st.integers(-1, 60), st.integers(0, 2)),
    C.DELETE: plain(st.sampled_from([0, 1, 2, 9999, -1])),
    C.RDEXECPROG: plain(st.integers(-1, 3000)),
    C.SEARCH: plain(st.sampled_from([0, 1, 2, 9999, -1])),
    C.PMC_RDPMCRNG: pmc_range(write=False),
    C.PMC_WRPMCRNG: pmc_range(write=True),
}


def shaped_block(command: int) -> st.SearchStrategy[Block]:
    device = Device.PMC if command in PMC_COMMANDS else Device.CNC
    shape = SHAPED.get(command, plain())
    random = st.tuples(args5(), st.binary(max_size=40))

    def build(path: int, body: Shape) -> Block:
        return Block(device, path, command, body[0], body[1])

    return st.builds(
        build, st.sampled_from([1, 1, 1, 1, 0, 2]), st.one_of(shape, shape, shape, random)
    )


known_block = st.one_of(*[shaped_block(int(c)) for c in NativeCommand])
unknown_block = st.builds(
    Block,
    st.one_of(st.sampled_from([1, 2]), u16),
    st.one_of(st.sampled_from([1, 0]), u16),
    st.one_of(st.integers(0, 0x130), u16),
    args5(),
    st.binary(max_size=40),
)
block = st.one_of(known_block, known_block, known_block, unknown_block)
#: A data request of up to 12 blocks, rarely none (FANUC's library sends none only when the
#: open answer announces no path).
blocks = st.one_of(st.lists(block, min_size=1, max_size=12), st.just([]))
#: A frame a well-behaved client may send: a data request, sometimes a repeated open request.
request = st.one_of(
    blocks.map(lambda b: (DATA, b)), blocks.map(lambda b: (DATA, b)), st.just((OPEN, None))
)


def request_frame(kind: int, content: list[Block] | None) -> bytes:
    if kind == OPEN:
        return frame(OPEN, struct.pack(">H", 2))
    assert content is not None
    return frame(DATA, request_body(content))


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


async def send_pieces(wire: NativeWire, pieces: list[bytes]) -> None:
    for piece in pieces:
        wire.send(piece)
        await wire.writer.drain()
        await asyncio.sleep(0)


# -- property: well-formed request frames ---------------------------------------------------


async def requests_property(
    native: Native, requests: list[tuple[int, list[Block] | None]], cuts: list[int]
) -> None:
    machine = native.machine
    violations = native.violations
    async with await native.opened() as wire:
        data = b"".join(request_frame(kind, content) for kind, content in requests)
        before = machine.state_digest()
        await send_pieces(wire, cuts_of(data, cuts))
        changed = False
        for kind, content in requests:
            got_kind, version, body = await wire.recv()
            assert version == native.version
            if kind == OPEN:
                assert got_kind == OPEN_ANSWER
                check_open_answer(version, body)
                continue
            assert content is not None
            assert got_kind == DATA_ANSWER, f"0x{got_kind:04X}"
            changed |= wrote(content, check_data_answer(version, content, body))
        if not changed:
            assert machine.state_digest() == before, "state changed without a successful write"
        # Nothing more was answered, and the connection is still open: a close is answered.
        wire.send(frame(CLOSE))
        got_kind, _, body = await wire.recv()
        assert (got_kind, body) == (CLOSE_ANSWER, b"")
        assert await wire.closed_by_peer()
    assert native.violations == violations


request_lists = st.lists(request, min_size=1, max_size=24)


@CI
@given(requests=request_lists, cuts=st.lists(st.integers(0, 2**20), max_size=6))
async def test_every_well_formed_request_is_answered_once(
    native: Native,
    errors: pytest.LogCaptureFixture,
    requests: list[tuple[int, list[Block] | None]],
    cuts: list[int],
) -> None:
    await requests_property(native, requests, cuts)
    assert_no_errors(errors)


@pytest.mark.slow
@SLOW
@given(requests=request_lists, cuts=st.lists(st.integers(0, 2**20), max_size=6))
async def test_every_well_formed_request_is_answered_once_long(
    native: Native,
    errors: pytest.LogCaptureFixture,
    requests: list[tuple[int, list[Block] | None]],
    cuts: list[int],
) -> None:
    await requests_property(native, requests, cuts)
    assert_no_errors(errors)


# -- property: refused writes change nothing ----------------------------------------------------

write_block = st.one_of(
    *[shaped_block(int(c)) for _, c in sorted(WRITES)],
    # a write through an unserved path or to a write-protected PMC area (X, F)
    st.builds(
        lambda a, area: Block(Device.PMC, 1, C.PMC_WRPMCRNG, (a, a + 3, area, 0, 4), bytes(4)),
        st.integers(0, 120),
        st.sampled_from([1, 3]),
    ),
)


async def refused_writes_property(native: Native, writes: list[list[Block]]) -> None:
    machine = native.machine
    async with await native.opened() as wire:
        for content in writes:
            before = machine.state_digest()
            wire.send(frame(DATA, request_body(content)))
            kind, version, body = await wire.recv()
            assert kind == DATA_ANSWER
            answers = check_data_answer(version, content, body)
            if not wrote(content, answers):
                assert machine.state_digest() == before, [hex(a.ew) for a in answers]


@CI
@given(writes=st.lists(st.lists(write_block, min_size=1, max_size=6), min_size=1, max_size=8))
async def test_refused_writes_change_nothing(
    native: Native, errors: pytest.LogCaptureFixture, writes: list[list[Block]]
) -> None:
    await refused_writes_property(native, writes)
    assert_no_errors(errors)


@pytest.mark.slow
@SLOW
@given(writes=st.lists(st.lists(write_block, min_size=1, max_size=6), min_size=1, max_size=8))
async def test_refused_writes_change_nothing_long(
    native: Native, errors: pytest.LogCaptureFixture, writes: list[list[Block]]
) -> None:
    await refused_writes_property(native, writes)
    assert_no_errors(errors)


# -- property: raw streams --------------------------------------------------------------------


@dataclass
class Expected:
    """What the server must do with a stream: the answers (type word, request blocks), and
    whether it closes after them for a violation or for a close request."""

    answers: list[tuple[int, list[Block] | None]]
    violation: bool
    closed: bool
    tail: bytes
    #: Bytes follow the violating frame or the close request: the server may close with some
    #: of them unread, and the peer may then see a reset and lose answers not yet read.
    lossy: bool = False


def walk_blocks(body: bytes) -> list[Block] | None:
    """The blocks of a data-request body, or None when they do not walk to its end."""
    if not body:
        return []
    if len(body) < 2:
        return None
    (count,) = struct.unpack_from(">H", body)
    pos = 2
    out = []
    for _ in range(count):
        if len(body) - pos < REQUEST_HEAD.size:
            return None
        length, device, path, command, *args = REQUEST_HEAD.unpack_from(body, pos)
        if length < REQUEST_HEAD.size or pos + length > len(body):
            return None
        extra = body[pos + REQUEST_HEAD.size : pos + length]
        out.append(
            Block(device, path, command, (args[0], args[1], args[2], args[3], args[4]), extra)
        )
        pos += length
    return out if pos == len(body) else None


def expect(stream: bytes, version: int, max_body: int = DEFAULT_MAX_BODY) -> Expected:
    """The oracle: how a fresh native connection must treat ``stream``."""
    answers: list[tuple[int, list[Block] | None]] = []
    opened = False
    pos = 0
    max_blocks = (max_answer_body(version) - 2) // ANSWER_HEAD.size
    while pos < len(stream):
        rest = stream[pos:]
        if not MAGIC.startswith(rest[:4]):
            return Expected(answers, True, True, b"", True)
        if len(rest) < HEADER.size:
            return Expected(answers, False, False, rest)
        _, _, kind, length = HEADER.unpack_from(rest)
        if length > max_body:
            return Expected(answers, True, True, b"", True)
        if len(rest) < HEADER.size + length:
            return Expected(answers, False, False, rest)
        body = rest[HEADER.size : HEADER.size + length]
        pos += HEADER.size + length
        if kind not in SERVED_TYPES:
            return Expected(answers, True, True, b"", True)
        if kind == OPEN:
            if len(body) != 2:
                return Expected(answers, True, True, b"", True)
            opened = True
            answers.append((OPEN, None))
        elif kind == CLOSE:
            answers.append((CLOSE, None))
            return Expected(answers, False, True, b"", pos < len(stream))
        elif kind in TRANSFERS:
            if not opened:
                return Expected(answers, True, True, b"", True)
            if kind in (UPLOAD, DOWNLOAD, DOWNLOAD_END):
                answers.append((kind, None))  # answered; the others answer nothing
        else:
            content = walk_blocks(body)
            if not opened or content is None or len(content) > max_blocks:
                return Expected(answers, True, True, b"", True)
            answers.append((DATA, content))
    return Expected(answers, False, False, b"")


def completion(tail: bytes) -> bytes:
    """Bytes that finish the partial frame ``tail`` (the header of an empty data request,
    then zeros); the finished frame may still be a violation, which the oracle then says."""
    template = frame(DATA)
    if len(tail) < HEADER.size:
        tail_head = tail + template[len(tail) :]
        (length,) = struct.unpack_from(">H", tail_head, 8)
        return template[len(tail) :] + bytes(length)
    (length,) = struct.unpack_from(">H", tail, 8)
    return bytes(HEADER.size + length - len(tail))


segment = st.one_of(
    st.just(frame(OPEN, b"\x00\x02")),
    request.map(lambda r: request_frame(*r)),
    request.map(lambda r: request_frame(*r)),
    st.just(frame(CLOSE)),
    st.builds(
        frame,
        st.one_of(st.sampled_from([0x0102, 0x2102, 0x2103, 0x0202, 0x2401]), u16),
        st.binary(max_size=40),
    ),
    st.builds(lambda body: frame(DATA, body), st.binary(max_size=80)),
    st.builds(
        frame,
        st.sampled_from(sorted(TRANSFERS)),
        st.one_of(
            st.binary(max_size=16),
            st.sampled_from(
                [
                    b"\x00\x00\x00\x01O1-O1".ljust(516, b"\x00"),
                    b"\x00\x00\x00\x01O7-O9".ljust(516, b"\x00"),
                    b"\x00\x00\x00\x01".ljust(516, b"\x00"),
                    b"\nO0777 (FUZZ)\nM30\n%",
                ]
            ),
        ),
    ),
    st.builds(lambda body: frame(OPEN, body), st.binary(max_size=4)),
    st.builds(lambda n: frame(DATA, b"")[:8] + struct.pack(">H", n), st.integers(4000, 0xFFFF)),
    st.binary(min_size=1, max_size=24),
)
streams = st.tuples(
    st.sampled_from([[frame(OPEN, b"\x00\x02")], [frame(OPEN, b"\x00\x02")], [MAGIC], []]),
    st.lists(segment, max_size=10),
).map(lambda t: b"".join(t[0] + t[1]))


async def check_transfer(wire: NativeWire, kind: int, got_kind: int, body: bytes) -> bool:
    """Check the answer of a transfer request (the first frame received, then the rest of an
    upload): the request's kind with direction 2, or direction 3 and 8 bytes; True when a
    download was stored."""
    refused = (kind & 0xFF00) | 0x03
    if got_kind == refused:
        assert len(body) == 8
        return False
    assert got_kind == kind + 1, f"0x{kind:04X} answered 0x{got_kind:04X}"
    if kind == UPLOAD:
        for _ in range(200):
            got_kind, _, body = await wire.recv()
            if got_kind == 0x1701:
                break
            assert got_kind == 0x1604 and 0 < len(body) <= 1280
        else:
            pytest.fail("an upload without its end")
    return kind == DOWNLOAD_END


async def stream_property(native: Native, stream: bytes, cuts: list[int]) -> None:
    machine = native.machine
    if not stream.startswith(MAGIC):
        stream = MAGIC + stream  # a native connection (any other start is a packed one)
    expected = expect(stream, native.version)
    if expected.tail:
        stream += completion(expected.tail)
        expected = expect(stream, native.version)
    assert not expected.tail
    violations = native.violations
    before = machine.state_digest()
    async with await native.connect() as wire:
        changed = False
        got = 0
        try:
            await send_pieces(wire, cuts_of(stream, cuts))
            for kind, content in expected.answers:
                got_kind, version, body = await wire.recv()
                got += 1
                assert version == native.version
                if kind == OPEN:
                    assert got_kind == OPEN_ANSWER
                    check_open_answer(version, body)
                elif kind == CLOSE:
                    assert (got_kind, body) == (CLOSE_ANSWER, b"")
                elif kind in TRANSFERS:
                    changed |= await check_transfer(wire, kind, got_kind, body)
                else:
                    assert content is not None
                    assert got_kind == DATA_ANSWER
                    changed |= wrote(content, check_data_answer(version, content, body))
        except (asyncio.IncompleteReadError, ConnectionError):
            # The server answers every frame before a violation or a close request, then
            # closes; bytes it has not read by then make the close a reset, which may cost
            # this end answers it has not read yet.
            assert expected.lossy, f"closed after {got} of {len(expected.answers)} answers"
            # a write whose answer was lost may have been made (a deleted program stays gone)
            changed |= any(
                kind == DOWNLOAD_END or any((b.device, b.command) in WRITES for b in content or ())
                for kind, content in expected.answers[max(got - 1, 0) :]
            )
        if expected.closed:
            assert await wire.closed_by_peer()
        else:
            wire.send(frame(DATA, request_body([Block(1, 1, NativeCommand.STATINFO)])))
            kind, _, body = await wire.recv()
            assert kind == DATA_ANSWER and answer_blocks(body)[0].ew == 0
    if not changed:
        assert machine.state_digest() == before
    await asyncio.sleep(0)
    assert native.violations == violations + (1 if expected.violation else 0)


@CI
@given(stream=streams, cuts=st.lists(st.integers(0, 2**16), max_size=4))
async def test_raw_streams_close_only_on_framing_violations(
    native: Native, errors: pytest.LogCaptureFixture, stream: bytes, cuts: list[int]
) -> None:
    await stream_property(native, stream, cuts)
    assert_no_errors(errors)


@pytest.mark.slow
@SLOW
@given(stream=streams, cuts=st.lists(st.integers(0, 2**16), max_size=4))
async def test_raw_streams_close_only_on_framing_violations_long(
    native: Native, errors: pytest.LogCaptureFixture, stream: bytes, cuts: list[int]
) -> None:
    await stream_property(native, stream, cuts)
    assert_no_errors(errors)


# -- the oracle itself ------------------------------------------------------------------------


def test_the_oracle_reads_the_documented_cases() -> None:
    opened = frame(OPEN, b"\x00\x02")
    status = frame(DATA, request_body([Block(1, 1, NativeCommand.STATINFO)]))
    assert expect(opened + status, 3).answers == [
        (OPEN, None),
        (DATA, [Block(1, 1, NativeCommand.STATINFO)]),
    ]
    assert expect(status, 3).violation  # a data request before the open
    assert expect(opened + b"\xa0\xa0\x00", 3).violation  # bad magic
    assert expect(opened + frame(0x2103), 3).violation  # a type not served
    assert expect(opened + frame(DATA, b"\x00"), 3).violation  # no block count
    assert expect(opened + frame(DATA, b"\x00\x01"), 3).violation  # a missing block
    assert expect(opened + frame(DATA, bytes(4097)), 3).violation  # over the body limit
    assert expect(opened + frame(DATA), 3).answers[-1] == (DATA, [])
    closed = expect(opened + frame(CLOSE) + b"junk", 3)
    assert closed.closed and not closed.violation and len(closed.answers) == 2
    tail = expect(opened + status[:7], 3).tail
    assert tail == status[:7]
    assert expect(opened + tail + completion(tail), 3).answers[-1] == (DATA, [])
    many = frame(DATA, request_body([Block(1, 1, 0x19)] * 91))
    assert expect(opened + many, 2).violation and not expect(opened + many, 3).violation


# -- frames before a violation in the same read --------------------------------------------


async def test_frames_before_a_violation_in_one_write_are_answered(
    native: Native, errors: pytest.LogCaptureFixture
) -> None:
    status = frame(DATA, request_body([Block(1, 1, NativeCommand.STATINFO)]))
    violations = native.violations
    async with await native.connect() as wire:
        wire.send(frame(OPEN, b"\x00\x02") + status + b"\xa0\xa0\x00\x00")
        kinds = [(await wire.recv())[0] for _ in range(2)]
        assert kinds == [OPEN_ANSWER, DATA_ANSWER]
        assert await wire.closed_by_peer()
    assert native.violations == violations + 1


async def test_nothing_after_a_close_request_is_read(
    native: Native, errors: pytest.LogCaptureFixture
) -> None:
    violations = native.violations
    async with await native.connect() as wire:
        oversize = frame(DATA)[:8] + struct.pack(">H", DEFAULT_MAX_BODY + 1)
        wire.send(frame(OPEN, b"\x00\x02") + frame(CLOSE) + oversize)
        kinds = [(await wire.recv())[0] for _ in range(2)]
        assert kinds == [OPEN_ANSWER, CLOSE_ANSWER]
        assert await wire.closed_by_peer()
    assert native.violations == violations
