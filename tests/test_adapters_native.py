"""The native adapter without sockets: the double-to-macro rounding rule, the size limit and
arbitrary request blocks (every answer well formed, the machine unchanged by reads)."""

from __future__ import annotations

import logging
import math
import struct
from datetime import UTC, datetime
from decimal import Decimal

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from focas_net.adapters import NativeAdapter, PackedAdapter, command_set_of, macro_from_double
from focas_net.errors import EW
from focas_net.native import (
    REQUEST_TYPES,
    VACANT,
    AlarmMessageRequest,
    CommandSet,
    Device,
    FrameType,
    ItemHead,
    ItemRecord,
    MacroDoubleWriteRequest,
    MacroReadRequest,
    MacroWriteRequest,
    NativeAlarmHistory,
    NativeAlarmHistoryRequest,
    NativeCommand,
    NativeFrameError,
    NativePmcData,
    ParamInfo3,
    ParamInfo3Request,
    ParamInfoRequest,
    ParamRead3Request,
    ParamReadRequest,
    ParamType,
    ParamWrite3Request,
    ParamWriteRequest,
    PathDescription,
    PmcReadRequest,
    PmcWriteRequest,
    RequestBlock,
    ResponseBlock,
    ScaledItemRecord,
    ScaledNumber,
    SysInfoRequest,
    TimerRequest,
    decode_frame,
    decode_open_answer,
    decode_response_body,
    encode_request_body,
)
from focas_net.native import NativePmcArea as NativePmcArea
from focas_net.protocol import (
    COMMANDS,
    AlarmHistoryRequest,
    AlarmMsgRequest,
    Command,
    DataRequest,
    ParamValue,
)
from focas_net.sim import (
    CLASS_MAX_AXES,
    Alarm,
    HistoryEntry,
    Machine,
    MachineFileError,
    default_machine,
    machine_from_dict,
)
from focas_net.sim.nc import ManualClock


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


# -- the control class, the open answer and the library's own reads -------------------------


@pytest.mark.parametrize(
    ("control_class", "command_set", "version"),
    [("16i", CommandSet.FS16I, 2), ("0i-C", CommandSet.FS16I, 2), ("0i-F", CommandSet.FS30I, 3)],
)
def test_the_control_class_picks_the_command_set(
    control_class: str, command_set: CommandSet, version: int
) -> None:
    machine = Machine("m", control_class=control_class)
    adapter = NativeAdapter(machine)
    assert command_set_of(machine) is adapter.command_set is command_set
    assert adapter.version == version
    frame = decode_frame(adapter.open_response())
    assert (frame.type, frame.version) == (FrameType.OPEN_RESPONSE, version)
    opened = decode_open_answer(frame.body, version)
    assert opened.present() == (PathDescription(" M", 3, 1),)
    # what a CNC of the class reports: 8 axes at most for the 16i family, 32 for the 30i's
    assert opened.max_axes == CLASS_MAX_AXES[control_class] == adapter.max_axis
    assert opened.max_axes == machine.identity().max_axis
    assert opened.option_bits == (None if version == 2 else 1)


def test_an_unknown_control_class_is_named() -> None:
    with pytest.raises(ValueError, match="'15i'"):
        Machine("m", control_class="15i")
    with pytest.raises(MachineFileError, match=r"machine\.control_class: .*'FS15'"):
        machine_from_dict({"machine": {"name": "m", "axes": ["X"], "control_class": "FS15"}})
    loaded = machine_from_dict({"machine": {"name": "m", "axes": ["X"], "control_class": "0I-c"}})
    assert loaded.control_class == "0i-C"


def _packed_param(machine: Machine, number: int, axis: int) -> tuple[int, int]:
    """``(ew, value)`` of the packed protocol's cnc_rdparam of the same machine."""
    raw = PackedAdapter(machine).answer(
        machine.new_session(), Command.RDPARAM, DataRequest(number, axis).encode()
    )
    ew = struct.unpack_from("<h", raw)[0]
    if ew:
        return ew, 0
    value: ParamValue = COMMANDS[Command.RDPARAM].response.decode(raw)
    return 0, value.bits


@pytest.mark.parametrize("control_class", ["16i", "0i-F"])
def test_the_parameters_the_library_reads_at_connect_are_the_machines(control_class: str) -> None:
    adapter = NativeAdapter(Machine("m", control_class=control_class))
    scaled = adapter.command_set is CommandSet.FS30I
    read = ParamRead3Request if scaled else ParamReadRequest
    # 9968 (option bits, bit 0 set) and 3115 (display bits of each axis, 0): bit parameters of
    # every machine, read the same through both protocols
    for number, axis, want in ((9968, 0, 1), (3115, 2, 0)):
        (reply,) = _replies(adapter, read(number, number, axis).to_block())
        head = ItemHead.decode_from(reply.data)
        first = struct.unpack_from(">i", reply.data, ItemHead.SIZE)[0]
        assert (reply.ew, head.number, head.type, first) == (0, number, ParamType.BIT, want)
        assert _packed_param(adapter.machine, number, axis) == (0, want)
    # 3115 alone, outside cnc_rdposition's frame, is answered like any parameter
    (reply,) = _replies(adapter, read(3115, 3115, -1).to_block())
    assert reply.ew == 0 and ItemHead.decode_from(reply.data).axis == -1


def test_the_option_bits_are_parameter_9968() -> None:
    loaded = machine_from_dict(
        {
            "machine": {"name": "m", "axes": ["X"]},
            "parameters": {"9968": {"type": "bit", "value": "00000000"}},
        }
    )
    adapter = NativeAdapter(loaded)
    assert decode_open_answer(adapter.open_answer(), adapter.version).option_bits == 0
    assert _packed_param(loaded, 9968, 0) == (0, 0)
    assert (
        NativeAdapter(default_machine()).open_answer()
        == NativeAdapter(default_machine()).open_answer()
    )
    assert decode_open_answer(NativeAdapter(default_machine()).open_answer(), 3).option_bits == 1


def _kinds_machine(control_class: str) -> Machine:
    machine = machine_from_dict(
        {
            "machine": {"name": "m", "axes": ["X", "Y", "Z"], "control_class": control_class},
            "panel": {"mode": "MDI", "pwe": True},
            "parameters": {
                "1815": {"type": "bit", "axis": True, "value": ["10110000", 1, 0xFF]},
                "3216": {"type": "byte", "value": -5},
                "3202": {"type": "word", "value": -300},
                "6711": {"type": "2-word", "value": 123456789},
                "1451": {"type": "real", "decimals": 3, "value": 12.345},
                "1420": {"type": "real", "decimals": 1, "axis": True, "value": [1.5, -2, 3.1]},
            },
        }
    )
    return machine


@pytest.mark.parametrize("control_class", ["16i", "0i-F"])
def test_parameter_records_carry_the_machines_kind(control_class: str) -> None:
    adapter = NativeAdapter(_kinds_machine(control_class))
    scaled = adapter.command_set is CommandSet.FS30I
    read = ParamRead3Request if scaled else ParamReadRequest
    slot = 8 if scaled else 4

    def record(number: int, axis: int) -> tuple[int, int, bytes]:
        (reply,) = _replies(adapter, read(number, number, axis).to_block())
        assert reply.ew == 0 and len(reply.data) == ItemHead.SIZE + slot * adapter.max_axis
        head = ItemHead.decode_from(reply.data)
        assert head.number == number
        return head.axis, head.type, reply.data[ItemHead.SIZE :]

    # a bit parameter: its byte of bits in the slot's low byte (0xB0 for 10110000)
    axis, kind, slots = record(1815, -1)
    assert (axis, kind) == (-1, ParamType.BIT)
    values = struct.unpack_from(">iii" if not scaled else ">ixxxxixxxxi", slots)
    assert [v & 0xFF for v in values] == [0xB0, 1, 0xFF]
    for number, ptype, want in (
        (3216, ParamType.BYTE, -5),
        (3202, ParamType.WORD, -300),
        (6711, ParamType.TWO_WORD, 123456789),
    ):
        axis, kind, slots = record(number, 0)
        assert (axis, kind, struct.unpack_from(">i", slots)[0]) == (0, ptype, want)
    # a real parameter: REALPRM (mantissa, 10, decimals), two 4-byte slots or one 8-byte slot
    axis, kind, slots = record(1451, 0)
    assert (kind, ScaledNumber.decode(slots[:8])) == (ParamType.REAL, ScaledNumber(12345, 3))
    axis, kind, slots = record(1420, -1)
    reals = [ScaledNumber.decode(slots[i : i + 8]) for i in (0, 8, 16)]
    assert reals == [ScaledNumber(15, 1), ScaledNumber(-20, 1), ScaledNumber(31, 1)]
    empty = ScaledNumber(0, 0).encode() if scaled else bytes(4)  # (0, 10, 0) or a zero i32
    assert slots[24:] == empty * ((len(slots) - 24) // len(empty))


def test_bit_and_real_parameters_written_in_either_set() -> None:
    machine = _kinds_machine("0i-F")
    adapter = NativeAdapter(machine)
    zeros = (ScaledNumber(0, 0),) * 7
    # a bit parameter: the library sends the signed byte of the bits (-80 for 0xB0)
    bit = ScaledItemRecord(1815, 2, ParamType.BIT, (ScaledNumber(-80, -1, 0), *zeros))
    assert _replies(adapter, ParamWrite3Request(bit).to_block())[0].ew == 0
    assert machine.read_param(1815, 2) == 0xB0
    # a real parameter: (value, 10, decimals), rescaled to the parameter's decimals
    real = ScaledItemRecord(1451, 0, ParamType.REAL, (ScaledNumber(-15, 1), *zeros))
    assert _replies(adapter, ParamWrite3Request(real).to_block())[0].ew == 0
    assert machine.read_param(1451, 0) == -1500
    inexact = ScaledItemRecord(1451, 0, ParamType.REAL, (ScaledNumber(12345, 4), *zeros))
    assert _replies(adapter, ParamWrite3Request(inexact).to_block())[0].ew == EW.DATA
    info3 = ParamInfo3.decode(_replies(adapter, ParamInfo3Request(1451).to_block())[0].data)
    assert (info3.type, info3.axis_kind) == (ParamType.REAL, 0)
    # a refused all-axes real write (the last axis inexact at 1 decimal) changes no axis
    before = machine.state_digest()
    reals = (ScaledNumber(1, 0), ScaledNumber(2, 0), ScaledNumber(305, 2))
    bad = ScaledItemRecord(1420, -1, ParamType.REAL, (*reals, *zeros[:5]))
    assert _replies(adapter, ParamWrite3Request(bad).to_block())[0].ew == EW.DATA
    assert machine.state_digest() == before
    # the 16i set: a bit byte is written as 0..255; a real parameter cannot be written
    machine = _kinds_machine("16i")
    adapter = NativeAdapter(machine)
    record = ItemRecord(1815, -1, ParamType.BIT, (-1, 0x7F, -128, 0, 0, 0, 0, 0))
    assert _replies(adapter, ParamWriteRequest(record).to_block())[0].ew == 0
    assert [machine.read_param(1815, a) for a in (1, 2, 3)] == [0xFF, 0x7F, 0x80]
    info = _replies(adapter, ParamInfoRequest(1451, 1).to_block())[0].data
    assert struct.unpack(">iiii", info)[2:] == (1451, ParamType.BIT)  # bits 0-1 of REAL
    before = machine.state_digest()
    for rec in (
        ItemRecord(1451, 0, ParamType.BIT, (5,) + (0,) * 7),  # what the library sends
        ItemRecord.real(1451, 0, (ScaledNumber(1, 0),), 8),
    ):
        assert _replies(adapter, ParamWriteRequest(rec).to_block())[0].ew == EW.LENGTH
    assert machine.state_digest() == before


def test_parameter_writes_of_both_sets_reach_the_machine() -> None:
    machine = default_machine()
    machine.set_panel(0, 1, 0)
    adapter = NativeAdapter(machine)
    info = _replies(adapter, ParamInfoRequest(1320, 1).to_block())[0].data
    assert struct.unpack(">iiii", info)[2:] == (1320, ParamType.TWO_WORD)
    record = ItemRecord(1320, -1, ParamType.TWO_WORD, (1, -2, 3, 0x5555, 0, 0, 0, 0))
    assert _replies(adapter, ParamWriteRequest(record).to_block())[0].ew == 0
    assert [machine.read_param(1320, a) for a in (1, 2, 3)] == [1, -2, 3]
    info3 = ParamInfo3.decode(_replies(adapter, ParamInfo3Request(1825).to_block())[0].data)
    assert (info3.number, info3.type, info3.axis_kind) == (1825, ParamType.WORD, 2)
    slots = (ScaledNumber(77, -1, 0),) + (ScaledNumber(0, 0),) * 7
    write3 = ParamWrite3Request(ScaledItemRecord(1825, 2, ParamType.WORD, slots))
    assert _replies(adapter, write3.to_block())[0].ew == 0
    assert machine.read_param(1825, 2) == 77
    # a refused all-axes write changes no axis
    before = machine.state_digest()
    bad = ItemRecord(1320, -1, ParamType.TWO_WORD, (5, 6, 2_000_000_000, 0, 0, 0, 0, 0))
    assert _replies(adapter, ParamWriteRequest(bad).to_block())[0].ew == EW.DATA
    assert machine.state_digest() == before
    machine.set_panel(1, 0, 0)
    assert _replies(adapter, ParamWriteRequest(record).to_block())[0].ew == EW.PASSWD


def test_macro_writes_of_both_sets() -> None:
    machine = default_machine()
    adapter = NativeAdapter(machine)
    binary = ScaledNumber.from_macro(12345, 3, binary=True)  # what a 16i-class handle sends
    assert _replies(adapter, MacroWriteRequest(500, binary).to_block())[0].ew == 0
    assert machine.read_macro(500) == Decimal("12.345")
    decimal = ScaledNumber.from_macro(-25, 1)  # what a 30i-class handle sends
    assert _replies(adapter, MacroWriteRequest(501, decimal).to_block())[0].ew == 0
    assert machine.read_macro(501) == Decimal("-2.5")
    assert _replies(adapter, MacroWriteRequest(501, VACANT).to_block())[0].ew == 0
    assert machine.read_macro(501) is None
    reply = _replies(adapter, MacroWriteRequest(9999, decimal).to_block())[0]
    assert (reply.ew, reply.detail1, reply.detail2) == (EW.NUMBER, 1, 9999)


def test_pmc_writes_are_big_endian_and_bounded_by_the_request_only() -> None:
    machine = default_machine()
    adapter = NativeAdapter(machine)
    words = NativePmcData.from_values(1, [0x1234, 0xFFFE])
    write = PmcWriteRequest(20, 23, NativePmcArea.D, 1, words)
    assert _replies(adapter, write.to_block())[0].ew == 0
    assert machine.read_pmc("D", 20, 4) == bytes([0x34, 0x12, 0xFE, 0xFF])
    many = PmcWriteRequest(100, 1099, NativePmcArea.D, 0, NativePmcData(bytes(range(250)) * 4))
    assert _replies(adapter, many.to_block())[0].ew == 0
    assert machine.read_pmc("D", 100, 1000) == bytes(range(250)) * 4
    odd = PmcWriteRequest(20, 22, NativePmcArea.D, 1, NativePmcData(b"\x01\x02\x03"))
    assert _replies(adapter, odd.to_block())[0].ew == EW.LENGTH
    protected = PmcWriteRequest(0, 0, NativePmcArea.X, 0, NativePmcData(b"\x01"))
    assert _replies(adapter, protected.to_block())[0].ew == EW.PROT


def test_alarm_bits_and_history() -> None:
    machine = default_machine()
    machine.raise_alarm(0, 2, 100, "A")
    machine.raise_alarm(1, 4, 500, "B")
    adapter = NativeAdapter(machine)
    bits = _replies(adapter, RequestBlock(Device.CNC, 1, NativeCommand.ALARM))[0].data
    assert struct.unpack(">i", bits) == (0b10100,)
    reply = _replies(adapter, NativeAlarmHistoryRequest(1, 23).to_block())[0]
    records = NativeAlarmHistory.decode(reply.data).records
    assert [(r.alarm_no, r.group, r.axis, r.message) for r in records] == [
        (500, 4, 1, b"B"),
        (100, 2, 0, b"A"),
    ]
    assert _replies(adapter, NativeAlarmHistoryRequest(3, 25).to_block())[0].ew == EW.NUMBER


def test_an_empty_request_is_answered_with_one_refused_block() -> None:
    frame = decode_frame(NativeAdapter(default_machine()).answer(b""))
    (reply,) = decode_response_body(frame.body)
    assert reply.ew == EW.FUNC


class BeyondTheWire(Machine):
    """A machine that reports an alarm number no wire carries, as a machine with a bug would
    (a machine refuses to raise it: EW_DATA)."""

    def active_alarms(
        self, alm_type: int = -1, limit: int | None = None, *, path: int = 1
    ) -> list[Alarm]:
        return [Alarm(0, 15, 99999999999, "BEYOND")]

    def alarm_history(self, depth: int | None = None) -> tuple[HistoryEntry, ...]:
        return (HistoryEntry(datetime(2026, 1, 2, tzinfo=UTC), 0, 15, 99999999999, "BEYOND"),)


def test_an_answer_no_wire_carries_is_ew_data_not_an_exception(
    caplog: pytest.LogCaptureFixture,
) -> None:
    caplog.set_level(logging.WARNING, logger="focas_net")
    machine = BeyondTheWire("beyond")
    packed, session = PackedAdapter(machine), machine.new_session()
    for command, request in (
        (Command.RDALMMSG, AlarmMsgRequest(-1, 32)),
        (Command.RDALMHISTRY, AlarmHistoryRequest(10)),
    ):
        answer = packed.answer(session, command, request.encode())
        assert COMMANDS[command].response.decode(answer).ew == EW.DATA
    assert packed.answer(session, Command.RDCNCSTAT, b"") != b""  # the next request is answered
    native = NativeAdapter(machine)
    replies = _replies(
        native,
        AlarmMessageRequest(-1, 10, 2, 32).to_block(),
        NativeAlarmHistoryRequest(1, 10).to_block(),
        RequestBlock(Device.CNC, 1, NativeCommand.STATINFO),
    )
    assert [r.ew for r in replies] == [EW.DATA, EW.DATA, 0]
    warned = [r.getMessage() for r in caplog.records if r.levelno == logging.WARNING]
    assert len(warned) == 4
    assert all(w.startswith("beyond: ") and "does not fit the wire" in w for w in warned)


def test_a_timer_beyond_the_native_minutes_is_ew_data(caplog: pytest.LogCaptureFixture) -> None:
    """Power-on time of more minutes than an i32 holds (4,000 years of machine time): the
    packed wire carries its milliseconds, the native one answers EW_DATA and goes on."""
    caplog.set_level(logging.WARNING, logger="focas_net")
    clock = ManualClock()
    machine = default_machine(sim_clock=clock)
    clock.advance(60.0 * 2**31)
    replies = _replies(
        NativeAdapter(machine),
        TimerRequest(0).to_block(),
        RequestBlock(Device.CNC, 1, NativeCommand.STATINFO),
    )
    assert [r.ew for r in replies] == [EW.DATA, 0]
    assert machine.timer_ms(0) == 60_000 * 2**31
    assert "TimerValue.minute" in caplog.records[-1].getMessage()


def _replies(adapter: NativeAdapter, *blocks: RequestBlock) -> tuple[ResponseBlock, ...]:
    return decode_response_body(decode_frame(adapter.answer(encode_request_body(blocks))).body)
