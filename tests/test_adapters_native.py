"""The native adapter without sockets: the double-to-macro rounding rule, the size limit and
arbitrary request blocks (every answer well formed, the machine unchanged by reads)."""

from __future__ import annotations

import math
import struct
from decimal import Decimal

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from focas_net.adapters import NativeAdapter, macro_from_double
from focas_net.errors import EW
from focas_net.native import (
    REQUEST_TYPES,
    Device,
    FrameType,
    MacroDoubleWriteRequest,
    MacroReadRequest,
    NativeCommand,
    NativeFrameError,
    PmcReadRequest,
    RequestBlock,
    SysInfoRequest,
    decode_frame,
    decode_response_body,
    encode_request_body,
)
from focas_net.native import NativePmcArea as NativePmcArea
from focas_net.sim import default_machine


@pytest.mark.parametrize(
    ("value", "stored"),
    [
        (100.0, (100, 0)),
        (1.5, (15, 1)),
        (0.1, (1, 1)),
        (-0.001, (-1, 3)),
        (12.345, (12345, 3)),
        (-0.0, (0, 0)),
        (1e-300, (0, 0)),
        (1 / 3, (333333333, 9)),
        (2 / 3, (666666667, 9)),
        (0.0000000005, (0, 0)),  # half-even at the 9th decimal
        (0.0000000015, (2, 9)),
        (12345.678901234, (123456789, 4)),
        (2147483647.0, (2147483647, 0)),
        (-2147483648.0, (-2147483648, 0)),
        (2147483647.4, (2147483647, 0)),
    ],
)
def test_macro_from_double(value: float, stored: tuple[int, int]) -> None:
    assert macro_from_double(value) == stored


@pytest.mark.parametrize("value", [math.inf, -math.inf, math.nan, 2147483647.6, 3e9, 1e300])
def test_macro_from_double_refuses(value: float) -> None:
    assert macro_from_double(value) is None


@given(st.floats(allow_nan=False, allow_infinity=False, min_value=-1e9, max_value=1e9))
def test_macro_from_double_is_close(value: float) -> None:
    stored = macro_from_double(value)
    assert stored is not None
    mantissa, decimals = stored
    assert -(2**31) <= mantissa < 2**31
    assert 0 <= decimals <= 9
    assert decimals == 0 or mantissa % 10  # no trailing zero
    # within half a unit of the last decimal kept
    assert abs(mantissa / 10**decimals - value) <= 0.5 / 10**decimals * (1 + 1e-9) + 1e-12


def _answer(adapter: NativeAdapter, *blocks: RequestBlock) -> tuple[int, list[tuple[int, int]]]:
    frame = decode_frame(adapter.answer(encode_request_body(list(blocks))))
    assert frame.type == FrameType.DATA_RESPONSE
    answers = decode_response_body(frame.body)
    return len(frame.body), [(a.ew, len(a.data)) for a in answers]


def test_block_count_limit() -> None:
    adapter = NativeAdapter(default_machine(), version=2)
    assert adapter.limit == 1450
    # 89 heads leave 24 bytes of data: the first block gets its 18, the others EW_LENGTH
    size, answers = _answer(adapter, *[SysInfoRequest().to_block()] * 89)
    assert size <= 1450
    assert answers == [(0, 18)] + [(EW.LENGTH, 0)] * 88
    # 90 heads fill the body: every block answered, none with data
    size, answers = _answer(adapter, *[SysInfoRequest().to_block()] * 90)
    assert size == 2 + 16 * 90 <= 1450
    assert answers == [(EW.LENGTH, 0)] * 90
    with pytest.raises(NativeFrameError):
        adapter.answer(encode_request_body([SysInfoRequest().to_block()] * 91))


def test_version_raises_the_limit() -> None:
    adapter = NativeAdapter(default_machine(), version=4)
    assert adapter.limit == 3470
    _, answers = _answer(adapter, MacroReadRequest(500, 899).to_block())
    assert answers == [(0, 400 * 8)]
    frame = decode_frame(adapter.answer(encode_request_body([SysInfoRequest().to_block()])))
    assert frame.version == 4


def test_vacant_write_on_vacant_variable_changes_nothing() -> None:
    machine = default_machine()
    adapter = NativeAdapter(machine)
    before = machine.state_digest()
    _, answers = _answer(adapter, MacroDoubleWriteRequest(500, None).to_block())
    assert answers == [(0, 0)]
    assert machine.state_digest() == before


_SERVED = sorted(REQUEST_TYPES)
_WRITES = {key for key, cls in REQUEST_TYPES.items() if cls.WRITE}
_READS = [key for key in _SERVED if key not in _WRITES]
_i32 = st.integers(-(2**31), 2**31 - 1)
_small = st.integers(-3, 1100)
_args = st.tuples(
    st.one_of(_small, _i32), st.one_of(_small, _i32), st.one_of(_small, _i32), _small, _small
)


@st.composite
def _blocks(draw: st.DrawFn, keys: list[tuple[int, int]]) -> RequestBlock:
    if draw(st.booleans()):
        device, command = draw(st.sampled_from(keys))
    else:
        device = draw(st.integers(0, 3))
        command = draw(st.integers(0, 0xFFFF).filter(lambda c: (device, c) not in _WRITES))
    path = draw(st.sampled_from([1, 1, 1, 0, 2]))
    extra = draw(st.binary(max_size=12))
    return RequestBlock(device, path, command, draw(_args), extra)


@settings(max_examples=300, deadline=None)
@given(st.lists(_blocks(_READS), min_size=1, max_size=12))
def test_arbitrary_reads_answer_every_block_and_change_nothing(blocks: list[RequestBlock]) -> None:
    machine = default_machine()
    machine.raise_alarm(1, 2, 300, "ALARM")
    adapter = NativeAdapter(machine)
    before = machine.state_digest()
    raw = adapter.answer(encode_request_body(blocks))
    frame = decode_frame(raw)
    assert len(frame.body) <= adapter.limit
    answers = decode_response_body(frame.body)
    assert len(answers) == len(blocks)
    for req, resp in zip(blocks, answers, strict=True):
        assert (resp.device, resp.path, resp.command) == (req.device, req.path, req.command)
        if (req.device, req.command) not in REQUEST_TYPES:
            assert resp.ew == EW.FUNC
        if resp.ew:
            assert resp.data == b""
        if resp.ew != EW.NUMBER:
            assert resp.detail1 == resp.detail2 == 0
    assert machine.state_digest() == before


@settings(max_examples=200, deadline=None)
@given(st.integers(-5, 1100), st.floats(allow_nan=True, width=64), st.binary(max_size=16))
def test_arbitrary_macro_writes(number: int, value: float, extra: bytes) -> None:
    machine = default_machine()
    adapter = NativeAdapter(machine)
    good = RequestBlock(
        Device.CNC, 1, NativeCommand.WRMACRO_DOUBLE, (number, 0, 0, 0, 8), struct.pack(">d", value)
    )
    odd = RequestBlock(Device.CNC, 1, NativeCommand.WRMACRO_DOUBLE, (number, 0, 0, 0, 8), extra)
    _, answers = _answer(adapter, odd, good)
    writable = machine.macro_writable(number)
    ew = answers[1][0]
    if writable is None:
        assert ew == EW.NUMBER
    elif not writable:
        assert ew == EW.PROT
    elif math.isnan(value):
        assert ew == 0
    elif macro_from_double(value) is None:
        assert ew == EW.DATA
    else:
        assert ew == 0
        stored = macro_from_double(value)
        assert stored is not None
        assert machine.read_macro(number) == Decimal(stored[0]).scaleb(-stored[1])
    if len(extra) != 8:
        assert answers[0] == (EW.LENGTH, 0)


def test_forced_answer_carries_the_code_in_every_block_and_runs_nothing() -> None:
    machine = default_machine()
    adapter = NativeAdapter(machine)
    before = machine.state_digest()
    blocks = [
        SysInfoRequest().to_block(),
        MacroDoubleWriteRequest(500, 1.5).to_block(),
        RequestBlock(Device.CNC, 2, 0x7777, (0, 0, 0, 0, 0), b""),
    ]
    frame = decode_frame(adapter.forced_answer(encode_request_body(blocks), EW.BUSY))
    assert frame.type == FrameType.DATA_RESPONSE and frame.version == adapter.version
    answers = decode_response_body(frame.body)
    assert [(a.device, a.path, a.command) for a in answers] == [
        (b.device, b.path, b.command) for b in blocks
    ]
    assert all(a.ew == EW.BUSY and a.data == b"" for a in answers)
    assert machine.state_digest() == before and machine.read_macro(500) is None
    with pytest.raises(NativeFrameError):
        adapter.forced_answer(encode_request_body([SysInfoRequest().to_block()] * 182), EW.BUSY)


def test_double_writes_go_through_the_machine_write() -> None:
    machine = default_machine(read_only=True)
    adapter = NativeAdapter(machine)
    # the machine's order: read-only first, whatever the number or the value
    for number, value in ((9999, math.inf), (4001, 1.0), (500, None)):
        block = MacroDoubleWriteRequest(number, value).to_block()
        assert _answer(adapter, block)[1] == [(EW.PROT, 0)]
    machine = default_machine()
    adapter = NativeAdapter(machine)
    assert _answer(adapter, MacroDoubleWriteRequest(500, 12.5).to_block())[1] == [(0, 0)]
    assert str(machine.read_macro(500)) == "12.5"
    assert _answer(adapter, MacroDoubleWriteRequest(500, None).to_block())[1] == [(0, 0)]
    assert machine.read_macro(500) is None


def test_pmc_reads_are_bounded_by_the_answer_only() -> None:
    machine = default_machine()
    data = bytes(i % 256 for i in range(1400))
    machine.write_pmc("D", 100, data)
    adapter = NativeAdapter(machine)
    block = PmcReadRequest(100, 1499, NativePmcArea.D, 0).to_block()
    frame = decode_frame(adapter.answer(encode_request_body([block])))
    (reply,) = decode_response_body(frame.body)
    assert (reply.ew, reply.data) == (0, data)  # one read of the machine, no 32-byte pieces
    words = PmcReadRequest(100, 1499, NativePmcArea.D, 1).to_block()
    frame = decode_frame(adapter.answer(encode_request_body([words])))
    (reply,) = decode_response_body(frame.body)
    assert reply.data[:4] == bytes([1, 0, 3, 2])  # little-endian PMC words, big-endian answer
    assert adapter.limit == 2910
    too_long = PmcReadRequest(0, 2910, NativePmcArea.D, 0).to_block()
    assert _answer(adapter, too_long)[1] == [(EW.LENGTH, 0)]
    past_the_end = PmcReadRequest(9990, 10009, NativePmcArea.D, 0).to_block()
    assert _answer(adapter, past_the_end)[1] == [(EW.NUMBER, 0)]
