"""The native FOCAS/2 Ethernet codec: golden bytes, round trips, incremental decoding, fuzzing."""

from __future__ import annotations

import math
import struct

import pytest
from hypothesis import given
from hypothesis import strategies as st

from focas_net.errors import EW, FrameError, PayloadError, ProtocolError
from focas_net.native import (
    DEFAULT_MAX_BODY,
    REQUEST_TYPES,
    VACANT,
    ActualFeedRequest,
    ActualSpindleSpeedRequest,
    AlarmMessage,
    AlarmMessageRequest,
    AlarmMessages,
    Device,
    DiagnosticRequest,
    FrameType,
    ItemRecord,
    ItemValues,
    MacroDoubleReadRequest,
    MacroDoubles,
    MacroDoubleWriteRequest,
    MacroReadRequest,
    NativeCommand,
    NativeFrame,
    NativeFrameDecoder,
    NativeFrameError,
    NativePayloadError,
    NativePmcArea,
    NativePmcData,
    NativePositionKind,
    NativePositionRequest,
    NativeProgramNumbers,
    NativeProtocolError,
    NativeRequest,
    NativeSysInfo,
    OpenRequest,
    ParamRead3Request,
    ParamReadRequest,
    PmcDataType,
    PmcReadRequest,
    ProgramNumberRequest,
    RequestBlock,
    ResponseBlock,
    ScaledItemRecord,
    ScaledItemValues,
    ScaledNumber,
    ScaledValues,
    StatInfo,
    StatInfoRequest,
    SysInfoRequest,
    decode_frame,
    decode_request,
    decode_request_body,
    decode_response_body,
    encode_close_request,
    encode_close_response,
    encode_native_frame,
    encode_native_response,
    encode_open_request,
    encode_open_response,
    encode_request,
    max_response_body,
    resolve_position_kind,
)


def h(text: str) -> bytes:
    return bytes.fromhex(text)


ZERO20 = "00" * 20

# ---------------------------------------------------------------------------------------------
# Golden bytes: requests as pyfocas / pyfanuc / FANUC's library put them on the wire


def test_error_tree() -> None:
    assert issubclass(NativeProtocolError, ProtocolError)
    assert issubclass(NativeFrameError, NativeProtocolError)
    assert issubclass(NativeFrameError, FrameError)
    assert issubclass(NativePayloadError, NativeProtocolError)
    assert issubclass(NativePayloadError, PayloadError)
    assert NativePayloadError("x", EW.ATTRIB).ew == EW.ATTRIB


def test_open_request_golden() -> None:
    wire = h("a0a0a0a0 0001 0101 0002 0002")
    assert encode_open_request() == wire
    frame = decode_frame(wire)
    assert frame == NativeFrame(1, FrameType.OPEN_REQUEST, h("0002"))
    assert OpenRequest.decode(frame.body) == OpenRequest(2)
    # FANUC's library: counter 1 on its control connection
    assert encode_open_request(1) == h("a0a0a0a0 0001 0101 0002 0001")


def test_open_request_bad_body() -> None:
    with pytest.raises(NativeFrameError):
        OpenRequest.decode(b"\x00")


def test_close_golden() -> None:
    assert encode_close_request() == h("a0a0a0a0 0001 0201 0000")
    assert encode_close_response() == h("a0a0a0a0 0002 0202 0000")
    assert decode_frame(encode_close_response()) == NativeFrame(2, FrameType.CLOSE_RESPONSE, b"")


def test_open_response_default() -> None:
    wire = encode_open_response()
    assert wire == h("a0a0a0a0 0002 0102 0010") + bytes(16)
    assert decode_frame(wire).type == FrameType.OPEN_RESPONSE


@pytest.mark.parametrize(
    ("wire", "expected"),
    [
        (f"a0a0a0a0 0001 2101 001e 0001 001c 0001 0001 0019 {ZERO20}", StatInfoRequest()),
        (f"a0a0a0a0 0001 2101 001e 0001 001c 0001 0001 0018 {ZERO20}", SysInfoRequest()),
        (
            "a0a0a0a0 0001 2101 001e 0001 001c 0001 0001 0015 000001f6 000001f6" + "00" * 12,
            MacroReadRequest(502, 502),
        ),
        (
            "a0a0a0a0 0001 2101 001e 0001 001c 0001 0001 0030 00000396 00000396 00000001"
            + "00" * 8,
            DiagnosticRequest(918, 918, 1),
        ),
        (
            "a0a0a0a0 0001 2101 001e 0001 001c 0002 0001 8001 0000089c 0000089d 00000009"
            " 00000001 00000000",
            PmcReadRequest(2204, 2205, NativePmcArea.D, PmcDataType.WORD),
        ),
        (
            "a0a0a0a0 0001 2101 001e 0001 001c 0001 0001 0026 00000004 ffffffff" + "00" * 12,
            NativePositionRequest(4, -1),
        ),
        (
            "a0a0a0a0 0001 2101 001e 0001 001c 0001 0001 0023 ffffffff 0000000a 00000002"
            " 00000040 00000000",
            AlarmMessageRequest(-1, 10, 2, 64),
        ),
        (
            "a0a0a0a0 0001 2101 001e 0001 001c 0001 0001 008d 00000cd1 00000cd1" + "00" * 12,
            ParamRead3Request(3281, 3281, 0),
        ),
        (
            "a0a0a0a0 0001 2101 0026 0001 0024 0001 0001 00a8 000001f6" + "00" * 12 + "00000008"
            " 4059000000000000",
            MacroDoubleWriteRequest(502, 100.0),
        ),
    ],
)
def test_request_golden(wire: str, expected: NativeRequest) -> None:
    data = h(wire)
    assert encode_request([expected.to_block()]) == data
    frame = decode_frame(data)
    assert (frame.version, frame.type) == (1, FrameType.DATA_REQUEST)
    (block,) = decode_request_body(frame.body)
    assert decode_request(block) == expected


def test_multi_block_request_golden() -> None:
    # a pyfanuc-style position read: ABS, REL, machine, distance in one frame
    blocks = [NativePositionRequest(kind).to_block() for kind in (4, 6, 1, 7)]
    wire = encode_request(blocks)
    assert wire[:12] == h("a0a0a0a0 0001 2101 0072 0004")
    assert wire[12:40] == h("001c 0001 0001 0026 00000004 ffffffff" + "00" * 12)
    assert decode_request_body(decode_frame(wire).body) == tuple(blocks)


def test_position_kinds() -> None:
    assert NativePositionRequest(4).position_kind is NativePositionKind.ABSOLUTE
    assert resolve_position_kind(0) is NativePositionKind.ABSOLUTE
    assert resolve_position_kind(1) is NativePositionKind.MACHINE
    assert resolve_position_kind(6) is NativePositionKind.RELATIVE
    assert resolve_position_kind(7) is NativePositionKind.DISTANCE
    assert resolve_position_kind(8) is NativePositionKind.SKIP
    assert resolve_position_kind(5) is None


def test_unsupported_command_decodes_to_none() -> None:
    assert decode_request(RequestBlock(1, 1, 0x7FF0)) is None
    assert decode_request(RequestBlock(Device.PMC, 1, NativeCommand.SYSINFO)) is None


def test_macro_double_write_wrong_length_is_ew_length() -> None:
    block = RequestBlock(1, 1, NativeCommand.WRMACRO_DOUBLE, (502, 0, 0, 0, 4), b"\x00" * 4)
    with pytest.raises(NativePayloadError) as info:
        decode_request(block)
    assert info.value.ew == EW.LENGTH


def test_empty_data_request_has_no_blocks() -> None:
    frame = decode_frame(h("a0a0a0a0 0001 2101 0000"))
    assert decode_request_body(frame.body) == ()


# ---------------------------------------------------------------------------------------------
# Golden bytes: responses (public captures of real controls, trailing fill bytes zeroed)


def test_status_response_golden() -> None:
    reply = StatInfoRequest().to_block().reply(StatInfo(1, 0, 0, 0, 0, 0, 0).encode())
    wire = encode_native_response([reply])
    assert wire == h(
        "a0a0a0a0 0002 2102 0020 0001 001e 0001 0001 0019 0000 0000 0000 000e"
        " 0001 0000 0000 0000 0000 0000 0000"
    )
    (block,) = decode_response_body(decode_frame(wire).body)
    assert StatInfo.decode(block.data) == StatInfo(1, 0, 0, 0, 0, 0, 0)


def test_sysinfo_golden() -> None:
    data = h("0662 0020 2030 204d 44344733 32382e30 3033")
    info = NativeSysInfo(0x0662, 32, " 0", " M", "D4G3", "28.0", "03")
    assert info.encode() == data
    assert NativeSysInfo.decode(data) == info
    wire = encode_native_response([SysInfoRequest().to_block().reply(data)])
    assert wire[:20] == h("a0a0a0a0 0002 2102 0024 0001 0022 0001 0001 0018")


def test_sysinfo_rejects_bad_widths() -> None:
    with pytest.raises(ValueError):
        NativeSysInfo(0, 8, "0", " M", "D4G3", "28.0", "03").encode()
    with pytest.raises(NativePayloadError):
        NativeSysInfo.decode(bytes(17))


def test_mixed_response_golden() -> None:
    # program numbers, feed, an EW_FUNC block and an EW_NOOPT block in one answer
    wire = h(
        "a0a0a0a0 0002 2102 0052 0004"
        " 0018 0001 0001 001c 0000 0000 0000 0008 00000bb8 00000bb8"
        " 0018 0001 0001 0024 0000 0000 0000 0008 00000000 000a 0004"
        " 0010 0001 0001 0025 0001 0000 0000 0000"
        " 0010 0001 0001 0026 0006 0000 0000 0000"
    )
    blocks = [
        ProgramNumberRequest().to_block().reply(NativeProgramNumbers(3000, 3000).encode()),
        ActualFeedRequest().to_block().reply(ScaledValues((ScaledNumber(0, 4),)).encode()),
        ActualSpindleSpeedRequest().to_block().reply(ew=EW.FUNC),
        NativePositionRequest(7).to_block().reply(ew=EW.NOOPT),
    ]
    assert encode_native_response(blocks) == wire
    decoded = decode_response_body(decode_frame(wire).body)
    assert decoded == tuple(blocks)
    assert NativeProgramNumbers.decode(decoded[0].data) == NativeProgramNumbers(3000, 3000)
    assert ScaledValues.decode(decoded[1].data).values[0].to_float() == 0.0
    assert [b.ew for b in decoded] == [0, 0, EW.FUNC, EW.NOOPT]


def test_scaled_number_golden() -> None:
    assert ScaledNumber.decode(h("0bc77120 000a 0006")).to_float() == pytest.approx(197.62)
    assert ScaledNumber.from_float(197.62, 6).encode() == h("0bc77120 000a 0006")
    assert VACANT.encode() == h("00000000 000a ffff")
    assert ScaledNumber.decode(h("00000000 000a ffff")).vacant
    assert VACANT.to_float() is None
    assert ScaledNumber.decode(h("fffe7a44 000a 0003")).to_float() == pytest.approx(-99.772)


def test_scaled_number_from_float_limits() -> None:
    with pytest.raises(ValueError):
        ScaledNumber.from_float(1e12, 3)
    with pytest.raises(ValueError):
        ScaledNumber.from_float(1.0, 10)
    with pytest.raises(ValueError):
        ScaledNumber.from_float(math.inf, 0)


def test_diag_item_values_golden() -> None:
    # 16i style: number 918, non-axis, two-word type, 8 slots
    data = h("00000396 0000 0002 001772a3") + bytes(28)
    values = ItemValues.decode(data, 8)
    assert values == ItemValues((ItemRecord(918, 0, 2, (1536675, 0, 0, 0, 0, 0, 0, 0)),))
    assert values.encode(8) == data


def test_param3_scaled_values_golden() -> None:
    # 30i style: number 308, all axes, 32 scaled slots of which 4 are used
    used = [0x1C, 0x1C, 0x2C, 0x1A]
    slots = "".join(f"{v:08x}000a0000" for v in used) + "00000000000a0000" * 28
    data = h("00000134 ffff 0000" + slots)
    values = ScaledItemValues.decode(data, 32)
    (record,) = values.records
    assert (record.number, record.axis, record.type) == (308, -1, 0)
    assert [v.to_float() for v in record.values[:4]] == [28.0, 28.0, 44.0, 26.0]
    assert values.encode(32) == data


def test_alarm_messages_golden() -> None:
    data = h("0000004b 00000003 00000000 00000004 b1a3bba4") + bytes(60)
    alarms = AlarmMessages.decode(data, 64)
    assert alarms == AlarmMessages((AlarmMessage(75, 3, 0, h("b1a3bba4")),))
    assert alarms.encode(64) == data
    assert AlarmMessages.decode(b"", 64) == AlarmMessages(())
    # no text asked: a 16-byte head per entry
    assert AlarmMessages((AlarmMessage(75, 3, 0, b""),)).encode(0) == data[:12] + bytes(4)


def test_alarm_message_bad_length() -> None:
    data = h("0000004b 00000003 00000000 00000041") + bytes(64)
    with pytest.raises(NativePayloadError):
        AlarmMessages.decode(data, 64)


def test_pmc_data_golden() -> None:
    data = NativePmcData.from_values(PmcDataType.WORD, [0x1234, 0xFFFF])
    assert data.raw == h("1234 ffff")
    assert data.values(PmcDataType.WORD) == (0x1234, 0xFFFF)
    assert data.values(PmcDataType.BYTE) == (0x12, 0x34, 0xFF, 0xFF)
    with pytest.raises(NativePayloadError):
        data.values(7)
    with pytest.raises(NativePayloadError):
        NativePmcData(b"\x00").values(PmcDataType.WORD)


def test_macro_doubles_golden() -> None:
    data = h("4059000000000000 7ff8000000000000")
    assert MacroDoubles.decode(data) == MacroDoubles((100.0, None))
    assert MacroDoubles((100.0, None)).encode() == data
    with pytest.raises(ValueError):
        MacroDoubles((math.nan,)).encode()


def test_response_version_limit() -> None:
    assert max_response_body(2) == 1450
    assert max_response_body(3) == 2910
    assert max_response_body(4) == 3470
    block = ResponseBlock(1, 1, 0x15, data=bytes(1432))  # body: 2 + 16 + 1432 = 1450
    assert len(encode_native_response([block])) == 1460
    with pytest.raises(ValueError):
        encode_native_response([ResponseBlock(1, 1, 0x15, data=bytes(1433))])
    assert (
        len(encode_native_response([ResponseBlock(1, 1, 0x15, data=bytes(1433))], version=3))
        == 1461
    )


# ---------------------------------------------------------------------------------------------
# The independent client's own parser reads our replies


def test_pyfocas_parses_our_replies() -> None:
    packet = pytest.importorskip("pyfocas.protocol.packet")
    wire = encode_native_response(
        [
            SysInfoRequest()
            .to_block()
            .reply(NativeSysInfo(0, 8, " 0", " M", "D4G3", "28.0", "03").encode())
        ]
    )
    parsed = packet.extract_focas_packet(wire)
    assert parsed.packet_type == FrameType.DATA_RESPONSE
    (content,) = parsed.data
    assert content.startswith(struct.pack(">HHH", 1, 1, 0x18) + bytes(6))
    info = packet.FOCASSysInfo.from_bytes(content[14:])
    assert (info.max_axis, info.series, info.version, info.axes) == (8, "D4G3", "28.0", "03")

    scaled = ScaledValues((ScaledNumber.from_float(12.5, 3),)).encode()
    assert packet.decode_scaled_integer(scaled) == 12.5
    with pytest.raises(packet.DecodingError):
        packet.decode_scaled_integer(VACANT.encode())

    opened = packet.extract_focas_packet(encode_open_response())
    assert opened.packet_type == FrameType.OPEN_RESPONSE


# ---------------------------------------------------------------------------------------------
# Round trips

i16 = st.integers(-(2**15), 2**15 - 1)
u16 = st.integers(0, 2**16 - 1)
i32 = st.integers(-(2**31), 2**31 - 1)
args5 = st.tuples(i32, i32, i32, i32, i32)
scaled = st.builds(ScaledNumber, i32, i16, i16)
doubles = st.one_of(st.none(), st.floats(allow_nan=False))
request_blocks = st.builds(RequestBlock, u16, u16, u16, args5, st.binary(max_size=64))
response_blocks = st.builds(ResponseBlock, u16, u16, u16, i16, st.binary(max_size=64), i16, i16)

typed_requests = st.one_of(
    st.just(SysInfoRequest()),
    st.just(StatInfoRequest()),
    st.just(ProgramNumberRequest()),
    st.just(ActualFeedRequest()),
    st.just(ActualSpindleSpeedRequest()),
    st.builds(MacroReadRequest, i32, i32),
    st.builds(MacroDoubleReadRequest, i32, i32),
    st.builds(MacroDoubleWriteRequest, i32, doubles),
    st.builds(ParamReadRequest, i32, i32, i32),
    st.builds(ParamRead3Request, i32, i32, i32),
    st.builds(DiagnosticRequest, i32, i32, i32),
    st.builds(PmcReadRequest, i32, i32, i32, i32),
    st.builds(AlarmMessageRequest, i32, i32, i32, i32),
    st.builds(NativePositionRequest, i32, i32),
)


def test_every_supported_command_has_a_typed_request() -> None:
    commands = {command for _, command in REQUEST_TYPES}
    assert commands == set(NativeCommand)


@given(typed_requests, u16)
def test_typed_request_round_trip(request: NativeRequest, path: int) -> None:
    block = request.to_block(path)
    wire = encode_request([block])
    (decoded,) = decode_request_body(decode_frame(wire).body)
    assert decoded == block
    assert decode_request(decoded) == request


@given(st.lists(request_blocks, max_size=8), u16)
def test_request_body_round_trip(blocks: list[RequestBlock], version: int) -> None:
    frame = decode_frame(encode_request(blocks, version))
    assert frame.version == version
    assert decode_request_body(frame.body) == tuple(blocks)


@given(st.lists(response_blocks, max_size=8))
def test_response_body_round_trip(blocks: list[ResponseBlock]) -> None:
    frame = decode_frame(encode_native_response(blocks))
    assert decode_response_body(frame.body) == tuple(blocks)


@given(
    i16,
    i16,
    st.text(st.characters(max_codepoint=255), min_size=2, max_size=2),
    st.text(st.characters(max_codepoint=255), min_size=2, max_size=2),
    st.text(st.characters(max_codepoint=255), min_size=4, max_size=4),
    st.text(st.characters(max_codepoint=255), min_size=4, max_size=4),
    st.text(st.characters(max_codepoint=255), min_size=2, max_size=2),
)
def test_sysinfo_round_trip(
    addinfo: int, max_axis: int, cnc: str, mt: str, series: str, version: str, axes: str
) -> None:
    info = NativeSysInfo(addinfo, max_axis, cnc, mt, series, version, axes)
    assert NativeSysInfo.decode(info.encode()) == info


@given(st.builds(StatInfo, i16, i16, i16, i16, i16, i16, i16))
def test_statinfo_round_trip(info: StatInfo) -> None:
    assert StatInfo.decode(info.encode()) == info


@given(st.builds(NativeProgramNumbers, i32, i32))
def test_program_numbers_round_trip(numbers: NativeProgramNumbers) -> None:
    assert NativeProgramNumbers.decode(numbers.encode()) == numbers


@given(st.lists(scaled, max_size=40))
def test_scaled_values_round_trip(values: list[ScaledNumber]) -> None:
    reply = ScaledValues(tuple(values))
    assert ScaledValues.decode(reply.encode()) == reply


@given(st.floats(-2000.0, 2000.0, allow_nan=False), st.integers(0, 6))
def test_scaled_number_from_float_is_close(value: float, decimals: int) -> None:
    number = ScaledNumber.from_float(value, decimals)
    restored = ScaledNumber.decode(number.encode()).to_float()
    assert restored is not None
    assert abs(restored - value) <= 0.5 * 10**-decimals + 1e-9


@given(st.lists(doubles, max_size=20))
def test_macro_doubles_round_trip(values: list[float | None]) -> None:
    reply = MacroDoubles(tuple(values))
    assert MacroDoubles.decode(reply.encode()) == reply


@given(
    st.integers(1, 8).flatmap(
        lambda n: st.tuples(
            st.just(n),
            st.lists(st.builds(ItemRecord, i32, i16, i16, st.tuples(*[i32] * n)), max_size=5),
        )
    )
)
def test_item_values_round_trip(case: tuple[int, list[ItemRecord]]) -> None:
    max_axis, records = case
    reply = ItemValues(tuple(records))
    assert ItemValues.decode(reply.encode(max_axis), max_axis) == reply


@given(
    st.integers(1, 8).flatmap(
        lambda n: st.tuples(
            st.just(n),
            st.lists(
                st.builds(ScaledItemRecord, i32, i16, i16, st.tuples(*[scaled] * n)), max_size=5
            ),
        )
    )
)
def test_scaled_item_values_round_trip(case: tuple[int, list[ScaledItemRecord]]) -> None:
    max_axis, records = case
    reply = ScaledItemValues(tuple(records))
    assert ScaledItemValues.decode(reply.encode(max_axis), max_axis) == reply


@given(
    st.integers(0, 80).flatmap(
        lambda n: st.tuples(
            st.just(n),
            st.lists(st.builds(AlarmMessage, i32, i32, i32, st.binary(max_size=n)), max_size=5),
        )
    )
)
def test_alarm_messages_round_trip(case: tuple[int, list[AlarmMessage]]) -> None:
    text_length, alarms = case
    reply = AlarmMessages(tuple(alarms))
    assert AlarmMessages.decode(reply.encode(text_length), text_length) == reply


@given(st.sampled_from(list(PmcDataType)), st.data())
def test_pmc_data_round_trip(kind: PmcDataType, data: st.DataObject) -> None:
    top = (1 << (8 * kind.width)) - 1
    values = data.draw(st.lists(st.integers(0, top), max_size=32))
    reply = NativePmcData.from_values(kind, values)
    assert NativePmcData.decode(reply.encode()).values(kind) == tuple(values)


# ---------------------------------------------------------------------------------------------
# Incremental decoder


def _sample_stream() -> tuple[bytes, list[NativeFrame]]:
    frames = [
        encode_open_request(),
        encode_request([StatInfoRequest().to_block(), MacroReadRequest(100, 105).to_block()]),
        encode_request([MacroDoubleWriteRequest(500, -1.5).to_block()]),
        encode_native_frame(FrameType.DATA_REQUEST, b""),
        encode_close_request(),
    ]
    return b"".join(frames), [decode_frame(f) for f in frames]


def test_decoder_byte_by_byte() -> None:
    stream, expected = _sample_stream()
    decoder = NativeFrameDecoder()
    got: list[NativeFrame] = []
    for i in range(len(stream)):
        got.extend(decoder.feed(stream[i : i + 1]))
    assert got == expected
    assert decoder.buffered == 0


def test_decoder_merged_frames_in_one_chunk() -> None:
    stream, expected = _sample_stream()
    decoder = NativeFrameDecoder()
    assert decoder.feed(stream) == expected
    assert decoder.buffered == 0


@given(st.lists(st.integers(1, 40), max_size=60))
def test_decoder_any_chunking(cuts: list[int]) -> None:
    stream, expected = _sample_stream()
    decoder = NativeFrameDecoder()
    got: list[NativeFrame] = []
    pos = 0
    for size in cuts:
        got.extend(decoder.feed(memoryview(stream)[pos : pos + size]))
        pos += size
    got.extend(decoder.feed(stream[pos:]))
    assert got == expected


def test_decoder_keeps_partial_frame() -> None:
    stream, expected = _sample_stream()
    decoder = NativeFrameDecoder()
    assert decoder.feed(stream[:15]) == [expected[0]]
    assert decoder.buffered == 3
    assert decoder.feed(stream[15:]) == expected[1:]


def test_decoder_rejects_oversize_before_buffering() -> None:
    decoder = NativeFrameDecoder(max_body=64)
    with pytest.raises(NativeFrameError):
        decoder.feed(h("a0a0a0a0 0001 2101 0041"))
    assert decoder.buffered == 0
    with pytest.raises(NativeFrameError):
        decoder.feed(b"\x00")


def test_decoder_rejects_oversize_header_split_across_feeds() -> None:
    decoder = NativeFrameDecoder(max_body=64)
    assert decoder.feed(h("a0a0a0a0 0001 2101")) == []
    with pytest.raises(NativeFrameError):
        decoder.feed(h("ffff") + bytes(100))
    assert decoder.buffered == 0


def test_decoder_accepts_exactly_the_maximum() -> None:
    decoder = NativeFrameDecoder(max_body=64)
    wire = encode_native_frame(FrameType.DATA_REQUEST, bytes(64))
    assert decoder.feed(wire) == [NativeFrame(1, FrameType.DATA_REQUEST, bytes(64))]


def test_decoder_rejects_bad_magic_on_first_byte() -> None:
    decoder = NativeFrameDecoder()
    with pytest.raises(NativeFrameError):
        decoder.feed(b"\xa0\x00")
    assert decoder.buffered == 0


def test_decoder_rejects_garbage_after_a_good_frame() -> None:
    decoder = NativeFrameDecoder()
    with pytest.raises(NativeFrameError):
        decoder.feed(encode_close_request() + b"GET / HTTP/1.1\r\n")


def test_decoder_max_body_validated() -> None:
    assert NativeFrameDecoder().max_body == DEFAULT_MAX_BODY
    with pytest.raises(ValueError):
        NativeFrameDecoder(max_body=70_000)


@pytest.mark.parametrize(
    "body",
    [
        h("00"),  # shorter than the count
        h("0001"),  # one block announced, none present
        h("0001 001b") + bytes(25),  # block length below the 28-byte minimum
        h("0001 0030") + bytes(26),  # block length past the end
        h("0001 001c") + bytes(26) + h("00"),  # trailing byte
    ],
)
def test_bad_request_bodies(body: bytes) -> None:
    with pytest.raises(NativeFrameError):
        decode_request_body(body)


@pytest.mark.parametrize(
    "body",
    [
        h(""),
        h("0001 0010") + bytes(10),
        h("0001 0011 0001 0001 0019 0000 0000 0000 0000") + h("00"),  # length != 16 + data
        h("0001 0010 0001 0001 0019 0000 0000 0000 0000 00"),  # trailing byte
    ],
)
def test_bad_response_bodies(body: bytes) -> None:
    with pytest.raises(NativeFrameError):
        decode_response_body(body)


def test_decode_frame_rejects_mismatched_length() -> None:
    with pytest.raises(NativeFrameError):
        decode_frame(h("a0a0a0a0 0001 0201 0001"))
    with pytest.raises(NativeFrameError):
        decode_frame(h("a0a0a0a0 0001 0201 0000 00"))
    with pytest.raises(NativeFrameError):
        decode_frame(h("a0a0a0a1 0001 0201 0000"))
    with pytest.raises(NativeFrameError):
        decode_frame(h("a0a0"))


# ---------------------------------------------------------------------------------------------
# Arbitrary bytes raise nothing but the documented error


def _only_native_errors(call: object) -> None:
    assert callable(call)
    try:
        call()
    except NativeProtocolError:
        pass


@given(st.lists(st.binary(max_size=64), max_size=10), st.booleans())
def test_fuzz_decoder(chunks: list[bytes], with_magic: bool) -> None:
    decoder = NativeFrameDecoder(max_body=256)
    for i, chunk in enumerate(chunks):
        data = b"\xa0\xa0\xa0\xa0" + chunk if with_magic and i == 0 else chunk
        try:
            frames = decoder.feed(data)
        except NativeProtocolError:
            break
        for frame in frames:
            assert len(frame.body) <= 256
    assert decoder.buffered <= 256 + 10


@given(st.binary(max_size=200))
def test_fuzz_bodies(data: bytes) -> None:
    _only_native_errors(lambda: decode_frame(data))
    _only_native_errors(lambda: decode_request_body(data))
    _only_native_errors(lambda: decode_response_body(data))
    _only_native_errors(lambda: OpenRequest.decode(data))
    _only_native_errors(lambda: NativeSysInfo.decode(data))
    _only_native_errors(lambda: StatInfo.decode(data))
    _only_native_errors(lambda: NativeProgramNumbers.decode(data))
    _only_native_errors(lambda: ScaledNumber.decode(data))
    _only_native_errors(lambda: ScaledValues.decode(data))
    _only_native_errors(lambda: MacroDoubles.decode(data))
    _only_native_errors(lambda: ItemValues.decode(data, 3))
    _only_native_errors(lambda: ScaledItemValues.decode(data, 3))
    _only_native_errors(lambda: AlarmMessages.decode(data, 32))
    _only_native_errors(lambda: NativePmcData.decode(data).values(data[0] if data else 0))


@given(st.lists(request_blocks, min_size=1, max_size=3), st.sampled_from(sorted(REQUEST_TYPES)))
def test_fuzz_typed_requests(blocks: list[RequestBlock], key: tuple[int, int]) -> None:
    for block in blocks:
        retargeted = RequestBlock(key[0], block.path, key[1], block.args, block.extra)
        _only_native_errors(lambda b=retargeted: decode_request(b))
        _only_native_errors(lambda b=block: decode_request(b))
