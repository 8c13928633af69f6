"""The declared records of the native codec: layouts, round trips of every record and request,
the binary macro record, the open answer, and garbage that only raises the codec's error."""

from __future__ import annotations

import dataclasses
import math
import struct
from decimal import Decimal
from typing import Any, cast

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from focas_net.errors import EW
from focas_net.native import (
    REQUEST_TYPES,
    VACANT,
    AlarmHistoryRecord,
    AlarmMessage,
    AlarmMessages,
    AxisDisplay,
    AxisName,
    AxisNameRequest,
    AxisNames,
    ClockValue,
    ClockWriteRequest,
    CncId,
    DiagType,
    ExecutingProgram,
    ItemHead,
    ItemRecord,
    ItemValues,
    MacroDoubles,
    MacroDoubleWriteRequest,
    MacroWriteRequest,
    NativeFrameError,
    NativePayloadError,
    NativePmcData,
    NativeProtocolError,
    NativeRecord,
    NativeRequest,
    NativeSysInfo,
    NoData,
    OffsetWrite,
    OpenHeadV2,
    OpenHeadV3,
    OpenRequest,
    ParamInfo,
    ParamInfo3,
    ParamInfoEntry,
    ParamType,
    ParamWrite3Request,
    ParamWriteRequest,
    PathDescription,
    PathRecordV2,
    PathRecordV3,
    PmcWriteRequest,
    PositionAxisName,
    PositionAxisNames,
    RecordArray,
    RequestBlock,
    ResponseBlock,
    ScaledItemRecord,
    ScaledItemValues,
    ScaledNumber,
    ToolOffsetWriteRequest,
    WorkOffsetWriteRequest,
    answer_refusal,
    axes,
    base,
    binary_to_decimal,
    blocks,
    build_open_answer,
    decimal_to_binary,
    decode_open_answer,
    decode_request,
    encode_response_body,
    frame,
    items,
    macros,
    max_response_body,
    open_answer_size,
    opening,
    pmc,
    records,
)

i8 = st.integers(-(2**7), 2**7 - 1)
u8 = st.integers(0, 2**8 - 1)
i16 = st.integers(-(2**15), 2**15 - 1)
u16 = st.integers(0, 2**16 - 1)
i32 = st.integers(-(2**31), 2**31 - 1)
u32 = st.integers(0, 2**32 - 1)
scaled = st.builds(ScaledNumber, i32, i16, i16)

_INTS: dict[str, st.SearchStrategy[int]] = {
    "b": i8,
    "B": u8,
    "h": i16,
    "H": u16,
    "i": i32,
    "I": u32,
}


#: The modules declaring the records checked here (part programs' are checked on their own).
RECORD_MODULES = (base, frame, opening, blocks, records, items, macros, pmc, axes)


def _all_records() -> list[type[NativeRecord]]:
    found: dict[str, type[NativeRecord]] = {}
    for module in RECORD_MODULES:
        for obj in vars(module).values():
            if isinstance(obj, type) and issubclass(obj, NativeRecord) and obj is not NativeRecord:
                found[obj.__name__] = obj
    return [found[name] for name in sorted(found)]


RECORDS = _all_records()


def _field_strategy(cls: type[NativeRecord], name: str, code: str) -> st.SearchStrategy[Any]:
    if code in _INTS:
        return _INTS[code]
    if code == "d":
        return st.floats(allow_nan=False)
    if code == "c":
        return st.binary(min_size=1, max_size=1)
    size = int(code[:-1] or 1)
    if name in cls.TEXT:
        return st.text(st.characters(max_codepoint=255), min_size=size, max_size=size)
    if name in cls.PADDED:
        return st.binary(max_size=size).map(lambda b: b.rstrip(b"\0"))
    return st.binary(min_size=size, max_size=size)


def record_strategy(cls: type[NativeRecord]) -> st.SearchStrategy[Any]:
    fields = {name: _field_strategy(cls, name, code) for name, code in cls.layout()}
    return st.builds(cls, **fields)


def test_every_record_is_declared_big_endian_and_sized() -> None:
    assert len(RECORDS) > 30
    for cls in RECORDS:
        assert cls.FORMAT.startswith(">"), cls
        assert cls.SIZE == struct.calcsize(cls.FORMAT), cls
        fields = {f.name for f in dataclasses.fields(cast(Any, cls))}
        assert fields == {name for name, _ in cls.layout()}, cls


@pytest.mark.parametrize("cls", RECORDS, ids=lambda c: c.__name__)
@settings(max_examples=40, deadline=None)
@given(data=st.data())
def test_record_round_trip(cls: type[NativeRecord], data: st.DataObject) -> None:
    record = data.draw(record_strategy(cls))
    wire = record.encode()
    assert len(wire) == cls.SIZE
    assert cls.decode(wire) == record
    assert cls.decode_from(b"\x01" + wire + b"\x02", 1) == record
    if cls.SIZE:
        assert cls.decode_many(wire * 3) == (record,) * 3


@pytest.mark.parametrize("cls", RECORDS, ids=lambda c: c.__name__)
@settings(max_examples=40, deadline=None)
@given(data=st.data())
def test_record_bytes_round_trip(cls: type[NativeRecord], data: st.DataObject) -> None:
    wire = data.draw(st.binary(min_size=cls.SIZE, max_size=cls.SIZE))
    record = cls.decode(wire)
    if any(isinstance(v, float) and math.isnan(v) for v in dataclasses.astuple(cast(Any, record))):
        return
    assert record.encode() == wire


@pytest.mark.parametrize("cls", RECORDS, ids=lambda c: c.__name__)
@settings(max_examples=30, deadline=None)
@given(data=st.binary(max_size=80), offset=st.integers(-3, 90))
def test_record_garbage_raises_only_the_codec_error(
    cls: type[NativeRecord], data: bytes, offset: int
) -> None:
    for call in (
        lambda: cls.decode(data),
        lambda: cls.decode_from(data, offset),
        lambda: cls.decode_many(data),
    ):
        try:
            call()
        except NativeProtocolError:
            pass


def test_decode_errors_are_the_codec_errors() -> None:
    with pytest.raises(NativePayloadError) as info:
        NativeSysInfo.decode(bytes(17))
    assert info.value.ew == EW.LENGTH
    with pytest.raises(NativeFrameError):
        OpenRequest.decode(bytes(3))
    with pytest.raises(NativePayloadError):
        CncId.decode_many(bytes(17))
    assert NoData.decode(b"") == NoData()
    assert NoData.decode_many(b"") == ()
    with pytest.raises(NativePayloadError):
        NoData.decode_many(b"x")


def test_encode_errors_are_value_errors() -> None:
    with pytest.raises(ValueError, match=r"CncId\.id1"):
        CncId(-1, 0, 0, 0).encode()
    with pytest.raises(ValueError, match="exactly 2"):
        PathRecordV2("M", 0, 3, 1).encode()
    with pytest.raises(ValueError, match="at most 36"):
        ExecutingProgram(1, bytes(37)).encode()
    with pytest.raises(ValueError):
        AxisName(b"XY").encode()


def test_layouts_of_the_fact_sheet() -> None:
    assert NativeSysInfo.SIZE == 18
    assert ScaledNumber.layout() == (("mantissa", "i"), ("base", "h"), ("decimals", "h"))
    assert ScaledNumber(-2500, 3).encode() == bytes.fromhex("fffff63c 000a 0003")
    assert VACANT.encode() == bytes.fromhex("00000000 000a ffff")
    assert ItemHead.SIZE == 8
    assert AlarmHistoryRecord.SIZE == 60
    assert ExecutingProgram(1234, b"O1234").encode()[:9] == bytes.fromhex("000004d2") + b"O1234"
    assert ParamInfo(0, 0, (ParamInfoEntry(1320, 3),)).encode() == bytes.fromhex(
        "00000000 00000000 00000528 00000003"
    )
    info3 = ParamInfo3(0, 0, 1320, 3, 2).encode()
    assert len(info3) == 28
    assert info3[12:16] == bytes.fromhex("0003 0002")
    assert AxisDisplay(bytes(3), 0x0F).encode() == bytes.fromhex("0000000f")
    entry = PositionAxisName.of(AxisName(b"X", b"1"), AxisName(b"X", b"M"), AxisName(b"X", b"R"))
    assert entry.encode() == bytes(4) + b"X1\0\0" + b"XM\0\0" + b"XR\0\0"
    assert entry.names()[1] == AxisName(b"X", b"1")
    history = AlarmHistoryRecord(500, 4, 1, 2024, 5, 6, 7, 8, 9, 5, b"HELLO")
    assert history.message == b"HELLO"
    assert AlarmHistoryRecord.decode(history.encode()) == history


def test_param_and_diag_type_numbering() -> None:
    assert [t.value for t in ParamType] == [0, 1, 2, 3, 4]
    assert ParamType.for_width(1) is ParamType.BYTE
    assert ParamType.for_width(2) is ParamType.WORD
    assert ParamType.for_width(4) is ParamType.TWO_WORD
    assert [t.value for t in DiagType] == [0, 1, 2, 5]
    assert DiagType.for_width(4) is DiagType.TWO_WORD
    entry = ParamInfoEntry(1320, 0x103)
    assert (entry.type, entry.axis) == (3, True)


def test_real_values_in_16i_slots() -> None:
    # a REAL value takes two 4-byte slots: the mantissa, then base and decimals
    record = ItemRecord.real(1420, -1, [ScaledNumber(7, 1), ScaledNumber(-25, 3)], 8)
    assert record.values[:4] == (7, 0x000A0001, -25, 0x000A0003)
    assert record.values[4:] == (0, 0, 0, 0)
    assert record.reals()[:2] == (ScaledNumber(7, 1), ScaledNumber(-25, 3))
    with pytest.raises(ValueError):
        ItemRecord.real(1, 0, [ScaledNumber(1, 1)] * 5, 8)


# ---------------------------------------------------------------------------------------------
# The binary macro record (fact sheet examples)


@pytest.mark.parametrize(
    ("mcr_val", "dec_val", "wire"),
    [
        (12345, 3, "62C28F5C 0002 001B"),
        (-25, 1, "B0000000 0002 001D"),
        (100, 0, "64000000 0002 0018"),
        (0, 0, "00000000 0002 0000"),
        (0, 3, "00000000 0002 0003"),
    ],
)
def test_wrmacro_binary_record(mcr_val: int, dec_val: int, wire: str) -> None:
    record = ScaledNumber.from_macro(mcr_val, dec_val, binary=True)
    assert record.encode() == bytes.fromhex(wire)
    assert ScaledNumber.decode(bytes.fromhex(wire)) == record
    assert decimal_to_binary(mcr_val, dec_val) == (record.mantissa, record.decimals)


def test_wrmacro_decimal_record() -> None:
    assert ScaledNumber.from_macro(12345, 3).encode() == bytes.fromhex("00003039 000a 0003")
    assert ScaledNumber.from_macro(5, -1).encode() == bytes.fromhex("00000005 000a ffff")


@pytest.mark.parametrize(
    ("wire", "macro"),
    [
        ("62C28F5C 0002 001B", (123450000, 7)),
        ("40000000 0002 001E", (100000000, 8)),
        ("40000000 0002 0000", (107374182, -1)),
        ("40000000 0002 0028", (976563000, 12)),  # the library's truncating arithmetic
        ("00003039 000a 0003", (12345, 3)),  # base 10 as it is
        ("00000000 000a ffff", (0, -1)),  # vacant
        ("00000000 0000 ffff", (0, -1)),  # vacant, base 0
        ("00000005 0010 0002", (125000000, 8)),  # any base but 10 is binary
    ],
)
def test_rdmacro_record(wire: str, macro: tuple[int, int]) -> None:
    assert ScaledNumber.decode(bytes.fromhex(wire)).to_macro() == macro


def test_binary_record_exact_value() -> None:
    record = ScaledNumber.decode(bytes.fromhex("62C28F5C 0002 001B"))
    value = record.to_decimal()
    assert value is not None
    assert value == Decimal(0x62C28F5C) / 2**27
    assert abs(value - Decimal("12.345")) < Decimal("1e-8")
    assert ScaledNumber(-25, 1).to_decimal() == Decimal("-2.5")
    assert VACANT.to_decimal() is None


@settings(max_examples=200)
@given(i32, st.integers(-9, 9))
def test_binary_round_trip_keeps_nine_digits(mcr_val: int, dec_val: int) -> None:
    mantissa, exponent = decimal_to_binary(mcr_val, dec_val)
    if mcr_val:
        assert 2**30 <= abs(mantissa) <= 2**31
    back_mcr, back_dec = binary_to_decimal(mantissa, exponent)
    original = mcr_val * 10.0**-dec_val
    back = back_mcr * 10.0**-back_dec
    assert math.isclose(original, back, rel_tol=2e-8, abs_tol=1e-300)


@settings(max_examples=200)
@given(i32, st.integers(-300, 300))
def test_binary_to_decimal_fits_a_macro(mantissa: int, exponent: int) -> None:
    # nine digits, or ten for very small values (the library's rounding, see fwlib_float.json)
    mcr_val, _ = binary_to_decimal(mantissa, exponent)
    assert -(2**31) <= mcr_val < 2**31


# ---------------------------------------------------------------------------------------------
# The open answer


def test_open_answer_v2_example_of_the_fact_sheet() -> None:
    """The fact sheet's example, but for the path count ``cnc_getpath`` reports (u16 at 10)."""
    body = build_open_answer([PathDescription(" M", 3, 1)], 8, version=2)
    assert body == bytes.fromhex("0000 0000 0008 0000 0001 0001 0000 0000 204d 0000 0003 0001")
    assert open_answer_size(body, 2) == 24
    answer = decode_open_answer(body, 2)
    assert isinstance(answer.head, OpenHeadV2)
    assert answer.present() == (PathDescription(" M", 3, 1),)
    assert build_open_answer([PathDescription()], 8, version=2, kind=3)[2:4] == b"\0\3"


def test_open_answer_v3_offsets() -> None:
    paths = [PathDescription(" M", 3, 1), PathDescription(" T", 2, 2)]
    body = build_open_answer(paths, 8, option_bits=0x0101, version=3)
    assert len(body) == 40 + 32 * 2 == open_answer_size(body, 3)
    assert body[6:8] == b"\0\x08"  # max axes
    assert body[8:10] == b"\0\x02"  # max spindles
    assert body[10:12] == b"\0\x02"  # paths
    assert body[22:24] == b"\0\x02"  # the path count cnc_getpath reports
    assert body[28:30] == b"\x01\x01"  # option bits
    first, second = body[40:72], body[72:104]
    assert first[:2] == b" M" and first[2:4] == b"\0\1" and first[6:8] == b"\0\3"
    assert first[10:12] == b"\0\1"
    assert second[:2] == b" T" and second[2:4] == b"\0\2" and second[10:12] == b"\0\2"
    answer = decode_open_answer(body, 4)
    assert isinstance(answer.head, OpenHeadV3)
    assert answer.option_bits == 0x0101
    assert answer.present() == tuple(paths)
    assert answer.encode() == body


def test_open_answer_refusals() -> None:
    with pytest.raises(ValueError):
        build_open_answer([], 8)
    with pytest.raises(ValueError):
        build_open_answer([PathDescription(axes=9)], 8)
    assert open_answer_size(bytes(9), 2) is None
    assert open_answer_size(bytes(16), 2) == 16
    with pytest.raises(NativePayloadError):
        decode_open_answer(bytes(17), 2)
    with pytest.raises(NativePayloadError):
        decode_open_answer(bytes(40), 2)
    empty = decode_open_answer(bytes(16), 2)
    assert empty.present() == ()
    blank = PathRecordV3("\0\0", 0, 0, 0, 0, 0)
    body = OpenHeadV3(0, 0, 1, 8, 1, 1).encode() + blank.encode()
    assert decode_open_answer(body, 3).present() == ()


@given(
    st.lists(
        st.builds(
            PathDescription, st.sampled_from([" M", " T"]), st.integers(0, 8), st.integers(0, 4)
        ),
        min_size=1,
        max_size=10,
    ),
    st.integers(2, 5),
    u16,
)
def test_open_answer_round_trip(paths: list[PathDescription], version: int, bits: int) -> None:
    body = build_open_answer(paths, 8, option_bits=bits, version=version)
    assert open_answer_size(body, version) == len(body)
    answer = decode_open_answer(body, version)
    assert answer.present() == tuple(paths)
    assert answer.encode() == body


@given(st.binary(max_size=120), st.integers(0, 6))
def test_open_answer_garbage(body: bytes, version: int) -> None:
    open_answer_size(body, version)
    try:
        decode_open_answer(body, version)
    except NativeProtocolError:
        pass


# ---------------------------------------------------------------------------------------------
# Variable answers


slot_counts = st.integers(1, 8)


@given(
    slot_counts.flatmap(
        lambda n: st.lists(st.tuples(i32, i16, i16, st.tuples(*[i32] * n)), max_size=4)
    )
)
def test_item_values_without_slot_count(rows: list[tuple[int, int, int, tuple[int, ...]]]) -> None:
    values = ItemValues(tuple(ItemRecord(*row) for row in rows))
    wire = values.encode()
    if rows:
        assert ItemValues.decode(wire, len(rows[0][3])) == values
        assert ItemRecord.decode(wire[: 8 + 4 * len(rows[0][3])]) == values.records[0]


@given(
    slot_counts.flatmap(
        lambda n: st.lists(st.tuples(i32, i16, i16, st.tuples(*[scaled] * n)), max_size=4)
    )
)
def test_scaled_item_values(rows: list[tuple[int, int, int, tuple[ScaledNumber, ...]]]) -> None:
    values = ScaledItemValues(tuple(ScaledItemRecord(*row) for row in rows))
    wire = values.encode()
    if rows:
        assert ScaledItemValues.decode(wire, len(rows[0][3])) == values
        assert ScaledItemRecord.decode(wire[: 8 + 8 * len(rows[0][3])]) == values.records[0]


@given(i32, i32, st.lists(st.builds(ParamInfoEntry, i32, i32), max_size=6))
def test_param_info_round_trip(prev: int, nxt: int, entries: list[ParamInfoEntry]) -> None:
    info = ParamInfo(prev, nxt, tuple(entries))
    assert ParamInfo.decode(info.encode()) == info


def _array_types() -> list[type[RecordArray[Any]]]:
    found = {
        obj
        for module in RECORD_MODULES
        for obj in vars(module).values()
        if isinstance(obj, type) and issubclass(obj, RecordArray) and obj is not RecordArray
    }
    return sorted(found, key=lambda cls: cls.__name__)


@pytest.mark.parametrize("cls", _array_types(), ids=lambda c: c.__name__)
@settings(max_examples=30, deadline=None)
@given(data=st.data())
def test_record_arrays(cls: type[RecordArray[Any]], data: st.DataObject) -> None:
    items = data.draw(st.lists(record_strategy(cls.ITEM), max_size=6))
    array = cls(tuple(items))
    wire = array.encode()
    assert cls.decode(wire) == array
    assert len(array) == len(items)
    raw = data.draw(st.binary(max_size=cls.ITEM.SIZE * 4))
    try:
        decoded = cls.decode(raw)
    except NativePayloadError:
        assert len(raw) % cls.ITEM.SIZE
    else:
        assert decoded.encode() == raw


def test_axis_name_answers_by_argument() -> None:
    names = AxisNames((AxisName(b"X", b"1"), AxisName(b"Y", b"2")))
    assert AxisNameRequest(0).decode_answer(names.encode()) == names
    wide = PositionAxisNames((PositionAxisName(bytes(4), b"X\0\0\0", b"X\0\0\0", b"X\0\0\0"),))
    assert AxisNameRequest(-1).decode_answer(wide.encode()) == wide


# ---------------------------------------------------------------------------------------------
# Typed requests


#: A name carried in extra bytes (the program folders' requests): fits the shortest, 12 bytes.
_NAME = st.text(st.characters(min_codepoint=0x20, max_codepoint=0x7E), max_size=11)


def _ints(cls: type[NativeRequest]) -> dict[str, st.SearchStrategy[Any]]:
    fields = dataclasses.fields(cls)  # type: ignore[arg-type]
    return {f.name: _NAME if f.name == "name" else i32 for f in fields}


def _offset_write(values: list[int]) -> OffsetWrite:
    return OffsetWrite(tuple(values))


_SPECIAL: dict[type[NativeRequest], st.SearchStrategy[Any]] = {
    MacroWriteRequest: st.builds(MacroWriteRequest, i32, scaled),
    ClockWriteRequest: st.builds(
        ClockWriteRequest, i32, st.builds(ClockValue, *[st.integers(-0x8000, 0x7FFF)] * 6)
    ),
    MacroDoubleWriteRequest: st.builds(
        MacroDoubleWriteRequest, i32, st.one_of(st.none(), st.floats(allow_nan=False))
    ),
    ParamWriteRequest: st.builds(
        ParamWriteRequest,
        st.builds(ItemRecord, i32, i16, i16, st.lists(i32, max_size=10).map(tuple)),
    ),
    ParamWrite3Request: st.builds(
        ParamWrite3Request,
        st.builds(ScaledItemRecord, i32, i16, i16, st.lists(scaled, max_size=10).map(tuple)),
    ),
    PmcWriteRequest: st.builds(
        PmcWriteRequest, i32, i32, i32, i32, st.binary(max_size=20).map(NativePmcData)
    ),
    ToolOffsetWriteRequest: st.builds(
        ToolOffsetWriteRequest, i32, i32, i32, st.lists(i32, max_size=8).map(_offset_write)
    ),
    WorkOffsetWriteRequest: st.builds(
        WorkOffsetWriteRequest, i32, i32, i32, st.lists(i32, max_size=8).map(_offset_write)
    ),
}


REQUESTS = sorted(REQUEST_TYPES.values(), key=lambda c: int(c.COMMAND))


def request_strategy(cls: type[NativeRequest]) -> st.SearchStrategy[Any]:
    if cls in _SPECIAL:
        return _SPECIAL[cls]
    return st.builds(cls, **_ints(cls))


@pytest.mark.parametrize("cls", REQUESTS)
@settings(max_examples=30, deadline=None)
@given(data=st.data(), path=u16)
def test_typed_request_round_trip(cls: type[NativeRequest], data: st.DataObject, path: int) -> None:
    request = data.draw(request_strategy(cls))
    block = request.to_block(path)
    assert (block.device, block.command) == (cls.DEVICE, cls.COMMAND)
    assert decode_request(block) == request
    assert len(block.extra) == len(request.extra())
    if block.extra:
        assert block.args[4] == len(block.extra)


@pytest.mark.parametrize("cls", REQUESTS)
@settings(max_examples=30, deadline=None)
@given(
    data=st.binary(max_size=120),
    args=st.tuples(i32, i32, i32, i32, i32),
    extra=st.binary(max_size=40),
)
def test_typed_request_garbage(
    cls: type[NativeRequest], data: bytes, args: tuple[int, int, int, int, int], extra: bytes
) -> None:
    block = RequestBlock(cls.DEVICE, 1, cls.COMMAND, args, extra)
    try:
        request = decode_request(block)
    except NativeProtocolError:
        request = data_request = None
    if request is None:
        return
    data_request = request
    try:
        answer = data_request.decode_answer(data, max_axes=3)
    except NativeProtocolError:
        return
    # what decodes encodes (a text field's bytes after the message length may differ)
    if not isinstance(answer, AlarmMessages | MacroDoubles):
        assert data_request.encode_answer(answer) == data


def test_write_requests_are_marked() -> None:
    writes = {cls.__name__ for cls in REQUEST_TYPES.values() if cls.WRITE}
    assert writes == {
        "ProgramDeleteRequest",
        "ProgramSearchRequest",
        "MacroWriteRequest",
        "MacroDoubleWriteRequest",
        "ParamWriteRequest",
        "ParamWrite3Request",
        "PmcWriteRequest",
        "ClockWriteRequest",
        "CurrentFolderWriteRequest",
        "FileDeleteRequest",
        "MainSelectRequest",
        "ToolOffsetWriteRequest",
        "WorkOffsetWriteRequest",
    }


def test_multi_record_items_need_the_slot_count() -> None:
    from focas_net.native import ParamReadRequest

    data = ItemValues((ItemRecord(1, 0, 3, (1, 2)), ItemRecord(2, 0, 3, (3, 4)))).encode()
    with pytest.raises(ValueError):
        ParamReadRequest(1, 2, 0).decode_answer(data)
    assert len(ParamReadRequest(1, 2, 0).decode_answer(data, 2).records) == 2
    assert len(ParamReadRequest(1, 1, 0).decode_answer(data[:16]).records) == 1


def test_alarm_messages_answer_uses_the_request_text_length() -> None:
    from focas_net.native import AlarmMessageRequest

    alarms = AlarmMessages((AlarmMessage(500, 4, 1, b"OVER TRAVEL"),))
    request = AlarmMessageRequest(-1, 10, 2, 32)
    wire = request.encode_answer(alarms)
    assert len(wire) == 16 + 32
    assert request.decode_answer(wire) == alarms


# ---------------------------------------------------------------------------------------------
# The library's checks on an answer body


def test_answer_refusal() -> None:
    good = encode_response_body([ResponseBlock(1, 1, 0x19, data=bytes(14))])
    assert answer_refusal(good, 1, 2) is None
    assert answer_refusal(good, 2, 2) is not None
    assert answer_refusal(b"\0\0", 0, 2) == "RB count(0) incorrect"
    assert answer_refusal(b"\0", 1, 2) is not None
    assert "larger than total" in str(answer_refusal(good[:-1], 1, 2))
    assert "smaller than total" in str(answer_refusal(good + b"\0", 1, 2))
    big = encode_response_body([ResponseBlock(1, 1, 0x15, data=bytes(1433))])
    assert answer_refusal(big, 1, 2) == "PDU data size(1451) is larger than MTU(1450)"
    assert answer_refusal(big, 1, 3) is None


def test_body_limits_by_version() -> None:
    assert [max_response_body(v) for v in (1, 2, 3, 4, 5, 6)] == [
        1450,
        1450,
        2910,
        3470,
        4950,
        4950,
    ]


@given(st.binary(max_size=33 * 8), st.integers(0, 40))
def test_the_mantissas_of_scaled_values_are_those_of_their_records(data: bytes, count: int) -> None:
    from focas_net.native import ScaledValues

    whole = data[: len(data) // 8 * 8]
    expected = tuple(v.mantissa for v in ScaledValues.decode(whole).values[:count])
    assert ScaledValues.mantissas(whole, count) == expected
    if len(data) % 8:
        with pytest.raises(NativePayloadError):
            ScaledValues.mantissas(data, count)
