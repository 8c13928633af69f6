"""Property tests of every payload codec: encode -> decode gives the value back, and decoding
arbitrary bytes raises nothing but :class:`PayloadError` (the alarm lists raise nothing at all).
"""

from __future__ import annotations

from datetime import UTC, datetime
from typing import Any

import pytest
from hypothesis import given
from hypothesis import strategies as st

from focas_net.errors import PayloadError
from focas_net.protocol import (
    COMMANDS,
    ActiveAlarm,
    ActiveAlarmList,
    AlarmHistory,
    AlarmHistoryEntry,
    AlarmHistoryRequest,
    AlarmMsgRequest,
    ArmedFault,
    ClearAlarms,
    Command,
    DataRequest,
    EwReply,
    FaultList,
    FaultsCleared,
    FaultsRequest,
    FrameDecoder,
    InjectFault,
    MacroRequest,
    MacroValue,
    ParamAttributes,
    ParamAttributesRequest,
    ParamValue,
    Password,
    PathNumber,
    PathSelection,
    PmcData,
    PmcRange,
    RaiseAlarm,
    SetPanel,
    StatusInfo,
    SysInfo,
    VacateMacro,
    VersaMaxReply,
    VersaMaxRequest,
    encode_frame,
)
from focas_net.protocol.codecs import (
    ActualValue,
    AxisPosition,
    PositionData,
    PositionKind,
    PositionRequest,
    ProgramNumbers,
)
from focas_net.protocol.programs import (
    MAX_PROGRAM_CHUNK,
    MAX_PROGRAM_NAME,
    CycleControl,
    DirectoryRequest,
    LoadMeters,
    Overrides,
    ProgramChunk,
    ProgramChunkRequest,
    ProgramDirectory,
    ProgramEntry,
    ProgramNumber,
    ProgramText,
    RunInfo,
)
from focas_net.versamax import BoardId, IOModuleRecord, ModuleType, RefDesc, RefType

u8 = st.integers(0, 0xFF)
i8 = st.integers(-0x80, 0x7F)
u16 = st.integers(0, 0xFFFF)
i16 = st.integers(-0x8000, 0x7FFF)
i32 = st.integers(-0x8000_0000, 0x7FFF_FFFF)
nonzero_ew = st.one_of(st.integers(-0x8000, -1), st.integers(1, 0x7FFF))
latin1 = st.characters(max_codepoint=0xFF)

status = st.builds(StatusInfo, i16, i16, i16, i16, i16, i16, i16, i16, i16)
data_requests = st.builds(DataRequest, i16, i16)
param_values = st.one_of(
    st.builds(ParamValue, i16, i16, i8, st.just(1)),
    st.builds(ParamValue, i16, i16, i16, st.just(2)),
    st.builds(ParamValue, i16, i16, i32, st.just(4)),
    st.builds(ParamValue, i16, i16, i32, st.just(8), st.integers(0, 9)),
)
macro_values = st.builds(MacroValue, i16, i16, i32, i16)
sysinfos = st.builds(
    SysInfo,
    i16,
    i16,
    st.binary(min_size=2, max_size=2),
    st.binary(min_size=2, max_size=2),
    st.binary(min_size=4, max_size=4),
    st.binary(min_size=4, max_size=4),
    st.binary(min_size=2, max_size=2),
)
pmc_ranges = st.builds(PmcRange, i16, i16, u16, u16)
pmc_data = st.builds(PmcData, i16, i16, u16, u16, st.binary(max_size=40))
passwords = st.builds(Password, st.binary(min_size=4, max_size=4))
raise_alarms = st.builds(RaiseAlarm, i16, i16, i16, st.binary(max_size=48))
versamax_requests = st.builds(VersaMaxRequest, u8, u16, u8, u16)
versamax_replies = st.builds(VersaMaxReply, u8, u8, u16, st.binary(max_size=140))

program_numbers = st.builds(ProgramNumbers, i32, i32)
actual_values = st.builds(ActualValue, i32)
position_requests = st.builds(PositionRequest, i16, i16)
axis_names = st.text(st.characters(min_codepoint=1, max_codepoint=0xFF), max_size=4)
position_data = st.builds(
    PositionData, i16, st.lists(st.builds(AxisPosition, axis_names, i32), max_size=32).map(tuple)
)

active_alarms = st.builds(ActiveAlarm, i16, i16, i16, st.text(latin1, max_size=40))
active_lists = st.one_of(
    st.builds(ActiveAlarmList, st.lists(active_alarms, max_size=8).map(tuple), st.just(0)),
    st.builds(ActiveAlarmList, st.just(()), nonzero_ew),
)
whole_seconds_utc = st.datetimes(
    min_value=datetime(1, 1, 1),
    max_value=datetime(9999, 12, 31, 23, 59, 59),
    timezones=st.just(UTC),
).map(lambda d: d.replace(microsecond=0))
history_entries = st.builds(
    AlarmHistoryEntry, whole_seconds_utc, i16, i16, i16, st.text(latin1, max_size=40)
)
histories = st.one_of(
    st.builds(AlarmHistory, st.lists(history_entries, max_size=8).map(tuple), st.just(0)),
    st.builds(AlarmHistory, st.just(()), nonzero_ew),
)


def ew_or(inner: st.SearchStrategy[Any]) -> st.SearchStrategy[Any]:
    """A read/write answer: the data, or an EW code other than 0."""
    return st.one_of(inner, st.builds(EwReply, nonzero_ew))


OK_ONLY = ew_or(st.none())
armed_faults = st.builds(ArmedFault, i16, i16, i32)
fault_lists = st.builds(FaultList, st.lists(armed_faults, max_size=70).map(tuple))

ascii_text = st.text(st.characters(max_codepoint=0x7F))
i64 = st.integers(-(2**63), 2**63 - 1)
program_entries = st.builds(ProgramEntry, i32, i32, ascii_text.filter(lambda t: len(t) <= 60))
directories = st.builds(ProgramDirectory, st.lists(program_entries, max_size=8).map(tuple))
chunks = st.builds(
    ProgramChunk, i32, st.text(st.characters(max_codepoint=0x7F), max_size=MAX_PROGRAM_CHUNK)
)
program_texts = st.builds(
    ProgramText, i16, st.text(st.characters(max_codepoint=0x7F), max_size=600)
)
load_meters = st.builds(
    LoadMeters,
    st.lists(i16, max_size=255).map(tuple),
    st.lists(i16, max_size=255).map(tuple),
)
run_infos = st.builds(RunInfo, i16, i16, i16, i32, i32, i64, i64, i64, i64)
overrides = st.builds(Overrides, i16, i16, i16)
program_numbers_i32 = st.builds(ProgramNumber, i32)

REQUESTS: dict[Command, st.SearchStrategy[Any]] = {
    Command.RDCNCSTAT: st.none(),
    Command.RDPARAM: data_requests,
    Command.RDMACRO: st.builds(MacroRequest, i16),
    Command.RDDIAG: data_requests,
    Command.SYSINFO: st.none(),
    Command.RDALMMSG: st.builds(AlarmMsgRequest, i16, i16),
    Command.RDPRGNUM: st.none(),
    Command.ACTF: st.none(),
    Command.ACTS: st.none(),
    Command.RDPOSITION: position_requests,
    Command.RDPMCRNG: pmc_ranges,
    Command.WRPARAM: param_values,
    Command.WRMACRO: macro_values,
    Command.WRPMCRNG: pmc_data,
    Command.WRUNLOCKPARAM: passwords,
    Command.VERSAMAX_RDCONFIG: versamax_requests,
    Command.SIM_SET_PANEL: st.builds(SetPanel, i16, i16, i16),
    Command.SIM_RAISE_ALARM: raise_alarms,
    Command.SIM_CLEAR_ALARMS: st.builds(ClearAlarms, i16, i16),
    Command.SIM_SET_PMC: pmc_data,
    Command.SIM_INJECT_FAULT: st.builds(InjectFault, i16, i16, i16, i32),
    Command.SIM_LIST_FAULTS: st.builds(FaultsRequest, i16),
    Command.SIM_CLEAR_FAULTS: st.builds(FaultsRequest, i16),
    Command.RDALMHISTRY: st.builds(AlarmHistoryRequest, i16),
    Command.RDPARAINFO: st.builds(ParamAttributesRequest, i16),
    Command.SIM_READ_PANEL: st.none(),
    Command.SIM_VACATE_MACRO: st.builds(VacateMacro, i16),
    Command.RDPROGDIR: st.builds(DirectoryRequest, i32, i16),
    Command.RDPROGRAM: st.builds(ProgramChunkRequest, i32, i32),
    Command.RDRUNINFO: st.none(),
    Command.RDLOADS: st.none(),
    Command.GETPATH: st.none(),
    Command.SETPATH: st.builds(PathNumber, i16),
    Command.WRPROGRAM: program_texts,
    Command.DELPROGRAM: program_numbers_i32,
    Command.SELPROGRAM: program_numbers_i32,
    Command.SIM_CYCLE: st.builds(CycleControl, i16),
    Command.SIM_SET_OVERRIDES: overrides,
}

RESPONSES: dict[Command, st.SearchStrategy[Any]] = {
    Command.RDCNCSTAT: ew_or(status),
    Command.RDPARAM: ew_or(param_values),
    Command.RDMACRO: ew_or(macro_values),
    Command.RDDIAG: ew_or(param_values),
    Command.SYSINFO: ew_or(sysinfos),
    Command.RDALMMSG: active_lists,
    Command.RDPRGNUM: ew_or(program_numbers),
    Command.ACTF: ew_or(actual_values),
    Command.ACTS: ew_or(actual_values),
    Command.RDPOSITION: ew_or(position_data),
    Command.RDPMCRNG: ew_or(pmc_data),
    Command.WRPARAM: OK_ONLY,
    Command.WRMACRO: OK_ONLY,
    Command.WRPMCRNG: OK_ONLY,
    Command.WRUNLOCKPARAM: OK_ONLY,
    Command.VERSAMAX_RDCONFIG: ew_or(versamax_replies),
    Command.SIM_SET_PANEL: OK_ONLY,
    Command.SIM_RAISE_ALARM: OK_ONLY,
    Command.SIM_CLEAR_ALARMS: OK_ONLY,
    Command.SIM_SET_PMC: OK_ONLY,
    Command.SIM_INJECT_FAULT: OK_ONLY,
    Command.SIM_LIST_FAULTS: ew_or(fault_lists),
    Command.SIM_CLEAR_FAULTS: ew_or(st.builds(FaultsCleared, i16)),
    Command.RDALMHISTRY: histories,
    Command.RDPARAINFO: ew_or(st.builds(ParamAttributes, i16, i16, i16, i16, i32, i32)),
    Command.SIM_READ_PANEL: ew_or(st.builds(SetPanel, i16, i16, i16)),
    Command.SIM_VACATE_MACRO: OK_ONLY,
    Command.RDPROGDIR: ew_or(directories),
    Command.RDPROGRAM: ew_or(chunks),
    Command.RDRUNINFO: ew_or(run_infos),
    Command.RDLOADS: ew_or(load_meters),
    Command.GETPATH: ew_or(st.builds(PathSelection, i16, i16)),
    Command.SETPATH: OK_ONLY,
    Command.WRPROGRAM: ew_or(program_numbers_i32),
    Command.DELPROGRAM: OK_ONLY,
    Command.SELPROGRAM: OK_ONLY,
    Command.SIM_CYCLE: OK_ONLY,
    Command.SIM_SET_OVERRIDES: OK_ONLY,
}


@st.composite
def module_records(draw: st.DrawFn) -> IOModuleRecord:
    refs = draw(
        st.lists(
            st.builds(
                RefDesc, u8, st.sampled_from([int(t) for t in RefType]), u16, st.integers(0, 8), u16
            ),
            max_size=6,
        )
    )
    setup = draw(u16)
    ins = sum(r.byte_length for r in refs if RefType(r.ref_type).is_input) if setup & 1 else 0
    outs = sum(r.byte_length for r in refs if not RefType(r.ref_type).is_input) if setup & 1 else 0
    return IOModuleRecord(
        BoardId(draw(u16)),
        BoardId(draw(u16)),
        draw(st.text(latin1, min_size=4, max_size=4)),
        tuple(refs),
        setup,
        draw(u16),
        draw(u16),
        draw(st.binary(min_size=ins, max_size=ins)),
        draw(st.binary(min_size=outs, max_size=outs)),
        draw(st.binary(max_size=40)),
    )


@st.composite
def built_records(draw: st.DrawFn) -> IOModuleRecord:
    refs = draw(
        st.lists(st.tuples(st.sampled_from(list(RefType)), u16, st.integers(0, 8)), max_size=6)
    )
    setup = draw(u16)
    ins = sum(n for t, _, n in refs if t.is_input) if setup & 1 else 0
    outs = sum(n for t, _, n in refs if not t.is_input) if setup & 1 else 0
    kind = draw(st.sampled_from([ModuleType.DISCRETE_DC, ModuleType.DISCRETE_AC]))
    return IOModuleRecord.build(
        BoardId.make(kind, outputs=2 * draw(st.integers(0, 15))),
        BoardId.make(kind, inputs=2 * draw(st.integers(0, 15))),
        draw(
            st.text(st.characters(min_codepoint=0x20, max_codepoint=0x7E), min_size=4, max_size=4)
        ),
        refs,
        setup=setup,
        default_inputs=draw(st.binary(min_size=ins, max_size=ins)),
        default_outputs=draw(st.binary(min_size=outs, max_size=outs)),
        module_data=draw(st.binary(max_size=40)),
        input_segment_mode=draw(u16),
        output_segment_mode=draw(u16),
    )


PAYLOAD_CLASSES: dict[type[Any], st.SearchStrategy[Any]] = {
    StatusInfo: status,
    DataRequest: data_requests,
    MacroRequest: st.builds(MacroRequest, i16),
    MacroValue: macro_values,
    SysInfo: sysinfos,
    AlarmMsgRequest: st.builds(AlarmMsgRequest, i16, i16),
    AlarmHistoryRequest: st.builds(AlarmHistoryRequest, i16),
    PmcRange: pmc_ranges,
    Password: passwords,
    SetPanel: st.builds(SetPanel, i16, i16, i16),
    ClearAlarms: st.builds(ClearAlarms, i16, i16),
    InjectFault: st.builds(InjectFault, i16, i16, i16, i32),
    FaultsRequest: st.builds(FaultsRequest, i16),
    ArmedFault: armed_faults,
    FaultList: fault_lists,
    FaultsCleared: st.builds(FaultsCleared, i16),
    ParamValue: param_values,
    PmcData: pmc_data,
    RaiseAlarm: raise_alarms,
    VersaMaxRequest: versamax_requests,
    VersaMaxReply: versamax_replies,
    ActiveAlarmList: active_lists,
    AlarmHistory: histories,
    IOModuleRecord: st.one_of(module_records(), built_records()),
    ProgramNumbers: program_numbers,
    ActualValue: actual_values,
    PositionRequest: position_requests,
    PositionData: position_data,
    DirectoryRequest: st.builds(DirectoryRequest, i32, i16),
    ProgramDirectory: directories,
    ProgramChunkRequest: st.builds(ProgramChunkRequest, i32, i32),
    ProgramChunk: chunks,
    ProgramText: program_texts,
    ProgramNumber: program_numbers_i32,
    CycleControl: st.builds(CycleControl, i16),
    Overrides: overrides,
    RunInfo: run_infos,
    LoadMeters: load_meters,
}

NUMBERS = sorted(COMMANDS)
IDS = [COMMANDS[n].focas_name for n in NUMBERS]


def test_every_command_has_strategies() -> None:
    assert set(REQUESTS) == set(Command) == set(RESPONSES)


# -- round trips ----------------------------------------------------------------------------


@pytest.mark.parametrize("number", NUMBERS, ids=IDS)
@given(data=st.data())
def test_request_round_trip(number: int, data: st.DataObject) -> None:
    codec = COMMANDS[number].request
    value = data.draw(REQUESTS[Command(number)], label="request")
    assert codec.decode(codec.encode(value)) == value


@pytest.mark.parametrize("number", NUMBERS, ids=IDS)
@given(data=st.data())
def test_response_round_trip(number: int, data: st.DataObject) -> None:
    spec = COMMANDS[number]
    value = data.draw(RESPONSES[Command(number)], label="response")
    wire = spec.response.encode(value)
    assert spec.response.decode(wire) == value
    if spec.counted:
        if value.ew:
            assert wire == spec.error_payload(value.ew)
    elif isinstance(value, EwReply):
        assert wire == spec.error_payload(value.ew)
        assert len(wire) == 2
    else:
        assert wire[:2] == b"\x00\x00"


@pytest.mark.parametrize("number", NUMBERS, ids=IDS)
@given(data=st.data())
def test_round_trip_through_frames(number: int, data: st.DataObject) -> None:
    spec = COMMANDS[number]
    request = data.draw(REQUESTS[Command(number)], label="request")
    response = data.draw(RESPONSES[Command(number)], label="response")
    request_id = data.draw(u16, label="request_id")
    stream = encode_frame(number, request_id, spec.request.encode(request)) + encode_frame(
        number, request_id, spec.response.encode(response)
    )
    cut = data.draw(st.integers(0, len(stream)), label="cut")
    decoder = FrameDecoder()
    frames = decoder.feed(stream[:cut]) + decoder.feed(stream[cut:])
    assert [(f.command, f.request_id) for f in frames] == [(number, request_id)] * 2
    assert spec.request.decode(frames[0].payload) == request
    assert spec.response.decode(frames[1].payload) == response


@pytest.mark.parametrize("cls", list(PAYLOAD_CLASSES), ids=lambda c: c.__name__)
@given(data=st.data())
def test_payload_class_round_trip(cls: type[Any], data: st.DataObject) -> None:
    value = data.draw(PAYLOAD_CLASSES[cls], label=cls.__name__)
    assert type(value) is cls
    assert cls.decode(value.encode()) == value


@pytest.mark.parametrize(
    "cls",
    [
        StatusInfo,
        DataRequest,
        MacroRequest,
        MacroValue,
        SysInfo,
        AlarmMsgRequest,
        PmcRange,
        ProgramNumbers,
        ActualValue,
        PositionRequest,
    ],
    ids=lambda c: c.__name__,
)
def test_fixed_payload_codec_is_the_class(cls: type[Any]) -> None:
    codec = cls.codec()
    assert codec.encode is not None and codec.decode is not None
    assert cls.__name__ in repr(codec)
    assert codec.decode(bytes(cls.STRUCT.size)) == cls.decode(bytes(cls.STRUCT.size))
    with pytest.raises(PayloadError):
        codec.decode(bytes(cls.STRUCT.size + 1))


# -- encode rejects what cannot go on the wire -----------------------------------------------

OUT_OF_RANGE = [
    pytest.param(lambda: StatusInfo(0, 0, 0, 0, 0, 0, 0, 0, 40000).encode(), id="status"),
    pytest.param(lambda: DataRequest(-40000, 0).encode(), id="datarequest"),
    pytest.param(lambda: MacroValue(1, 8, 2**31, 0).encode(), id="macro"),
    pytest.param(lambda: ParamValue(1, 0, 128, 1).encode(), id="param-byte"),
    pytest.param(lambda: ParamValue(1, 0, 40000, 2).encode(), id="param-i16"),
    pytest.param(lambda: ParamValue(1, 0, 0, 3).encode(), id="param-width"),
    pytest.param(lambda: PmcRange(5, 0, -1, 0).encode(), id="pmc-range"),
    pytest.param(lambda: PmcData(5, 0, 70000, 0, b"").encode(), id="pmc-data"),
    pytest.param(lambda: InjectFault(1, 0, 1, 2**31).encode(), id="inject"),
    pytest.param(lambda: RaiseAlarm(40000, 0, 0, b"").encode(), id="raise"),
    pytest.param(lambda: VersaMaxRequest(0, 70000, 3, 0).encode(), id="vm-request"),
    pytest.param(lambda: VersaMaxReply(0, 3, 0, bytes(65530)).encode(), id="vm-reply-too-long"),
    pytest.param(
        lambda: ActiveAlarmList((ActiveAlarm(0, 0, 40000, ""),)).encode(), id="active-alarm"
    ),
    pytest.param(lambda: ProgramNumbers(2**31, 0).encode(), id="program-numbers"),
    pytest.param(lambda: ActualValue(-(2**31) - 1).encode(), id="actual-value"),
    pytest.param(lambda: PositionRequest(0, 40000).encode(), id="position-request"),
    pytest.param(lambda: PositionData(40000, ()).encode(), id="position-dec"),
    pytest.param(
        lambda: PositionData(3, (AxisPosition("X", 2**31),)).encode(), id="position-value"
    ),
    pytest.param(
        lambda: PositionData(3, (AxisPosition("XAXIS", 0),)).encode(), id="position-long-name"
    ),
    pytest.param(
        lambda: PositionData(3, (AxisPosition("X\x00", 0),)).encode(), id="position-nul-name"
    ),
    pytest.param(
        lambda: PositionData(3, (AxisPosition("\u0394", 0),)).encode(), id="position-non-latin1"
    ),
    pytest.param(
        lambda: AlarmHistory(
            (AlarmHistoryEntry(datetime(2024, 1, 1, tzinfo=UTC), 40000, 0, 0, ""),)
        ).encode(),
        id="history",
    ),
]


@pytest.mark.parametrize("encode", OUT_OF_RANGE)
def test_encode_out_of_range_raises_value_error(encode: Any) -> None:
    with pytest.raises(ValueError):
        encode()


# -- decoding arbitrary bytes -------------------------------------------------------------------


def _decode_or_payload_error(codec: Any, data: bytes, never_raises: bool) -> None:
    if never_raises:
        codec.decode(data)
        return
    try:
        codec.decode(data)
    except PayloadError:
        pass


@pytest.mark.parametrize("number", NUMBERS, ids=IDS)
@given(blob=st.binary(max_size=300))
def test_arbitrary_bytes_raise_only_payload_error(number: int, blob: bytes) -> None:
    spec = COMMANDS[number]
    _decode_or_payload_error(spec.request, blob, never_raises=False)
    _decode_or_payload_error(spec.response, blob, never_raises=spec.counted)


@st.composite
def mutated(draw: st.DrawFn, valid: st.SearchStrategy[bytes]) -> bytes:
    """A valid encoding with bytes changed, cut or added: reaches deeper decoder paths."""
    data = bytearray(draw(valid))
    for _ in range(draw(st.integers(0, 4))):
        if data and draw(st.booleans()):
            data[draw(st.integers(0, len(data) - 1))] = draw(u8)
    if draw(st.booleans()):
        data = data[: draw(st.integers(0, len(data)))]
    data += draw(st.binary(max_size=6))
    return bytes(data)


@pytest.mark.parametrize("number", NUMBERS, ids=IDS)
@given(data=st.data())
def test_mutated_encodings_raise_only_payload_error(number: int, data: st.DataObject) -> None:
    spec = COMMANDS[number]
    command = Command(number)
    request = data.draw(mutated(REQUESTS[command].map(spec.request.encode)), label="request")
    response = data.draw(mutated(RESPONSES[command].map(spec.response.encode)), label="response")
    _decode_or_payload_error(spec.request, request, never_raises=False)
    _decode_or_payload_error(spec.response, response, never_raises=spec.counted)


def _outcome(decode: Any, data: bytes | bytearray) -> Any:
    """What ``decode(data)`` gives: its value, or the type and text of the PayloadError."""
    try:
        return decode(data)
    except PayloadError as exc:
        return (type(exc), str(exc))


@pytest.mark.parametrize("number", NUMBERS, ids=IDS)
@given(data=st.data())
def test_decode_bytes_agrees_with_decode(number: int, data: st.DataObject) -> None:
    """``decode_bytes`` (the client's path, a memo's own look-up where the codec keeps one)
    gives what ``decode`` gives, the first time and again, and ``decode`` still takes a
    bytearray (which no memo can key on)."""
    codec = COMMANDS[number].response
    wire = data.draw(mutated(RESPONSES[Command(number)].map(codec.encode)), label="response")
    expected = _outcome(codec.decode, wire)
    assert _outcome(codec.decode_bytes, wire) == expected
    assert _outcome(codec.decode_bytes, bytes(wire)) == expected  # a hit, where kept
    assert _outcome(codec.decode, bytearray(wire)) == expected


@given(blob=st.binary(max_size=300))
def test_module_record_arbitrary_bytes_raise_only_payload_error(blob: bytes) -> None:
    _decode_or_payload_error(IOModuleRecord, blob, never_raises=False)


@given(
    blob=mutated(st.one_of(module_records(), built_records()).map(IOModuleRecord.encode)),
)
def test_module_record_mutations_raise_only_payload_error(blob: bytes) -> None:
    _decode_or_payload_error(IOModuleRecord, blob, never_raises=False)


@given(body=st.binary(min_size=24, max_size=200), label=st.binary(min_size=4, max_size=4))
def test_module_record_with_a_consistent_length_raises_only_payload_error(
    body: bytes, label: bytes
) -> None:
    """Random additional data behind a header whose length field matches it."""
    header = (
        b"\x80\x08\x80\x80"
        + label
        + len(body).to_bytes(2, "little")
        + bytes(14)
        + (len(body) + -len(body) % 26).to_bytes(2, "little")
    )
    _decode_or_payload_error(IOModuleRecord, header + body, never_raises=False)


def test_encode_errors_name_the_field_and_its_range() -> None:
    with pytest.raises(ValueError, match=r"value 99999 does not fit a 2-byte parameter"):
        ParamValue(3216, 0, 99999, 2).encode()
    with pytest.raises(ValueError, match=r"value 200 does not fit a 1-byte parameter \(-128"):
        ParamValue(20, 0, 200, 1).encode()
    with pytest.raises(
        ValueError, match=r"^mcr_val 2147483648 is outside -2147483648..2147483647$"
    ):
        MacroValue(1, 8, 2**31, 0).encode()
    with pytest.raises(ValueError, match=r"^mode 70000 is outside -32768..32767$"):
        SetPanel(70000, 0, 0).encode()


@pytest.mark.parametrize(
    ("given", "kind"),
    [
        ("absolute", PositionKind.ABSOLUTE),
        (" Machine ", PositionKind.MACHINE),
        ("RELATIVE", PositionKind.RELATIVE),
        ("distance", PositionKind.DISTANCE),
        ("distance-to-go", PositionKind.DISTANCE),
        ("distance_to_go", PositionKind.DISTANCE),
        (3, PositionKind.DISTANCE),
        (PositionKind.MACHINE, PositionKind.MACHINE),
    ],
)
def test_position_kind_parse(given: str | int | PositionKind, kind: PositionKind) -> None:
    assert PositionKind.parse(given) is kind


@pytest.mark.parametrize("given", ["skip", "", 4, -1])
def test_position_kind_parse_rejects(given: str | int) -> None:
    with pytest.raises(ValueError):
        PositionKind.parse(given)


# -- program payloads: what cannot go on the wire ----------------------------------------------


def test_program_payloads_refuse_what_the_wire_cannot_carry() -> None:
    with pytest.raises(ValueError, match="ASCII"):
        ProgramText(0, "O1 (\u00e9)").encode()
    with pytest.raises(ValueError, match="at most"):
        ProgramChunk(1, "x" * (MAX_PROGRAM_CHUNK + 1)).encode()
    with pytest.raises(ValueError, match="at most"):
        ProgramDirectory((ProgramEntry(1, 1, "n" * (MAX_PROGRAM_NAME + 1)),)).encode()


@given(st.binary(max_size=40))
def test_program_decoders_raise_only_payload_errors(data: bytes) -> None:
    for cls in (ProgramDirectory, ProgramChunk, ProgramText):
        try:
            value = cls.decode(data)
        except PayloadError:
            continue
        assert value.encode() == data  # what decodes is exactly what encodes to these bytes
