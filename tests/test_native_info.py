"""The CNC's information over the native protocol: the frames FANUC's library sends (golden
bytes from libfwlib32 1.0.5, both command sets), the answers' layouts (golden bytes the library
was seen to decode, hypothesis round trips), the adapter's answers from the machine (idle and
running, both command sets, refusals) and :class:`NativeClient`'s typed results against a
served machine."""

from __future__ import annotations

from collections.abc import AsyncIterator, Callable

import pytest
from hypothesis import given
from hypothesis import strategies as st
from support import IO_TIMEOUT, serving, two_path_lathe

from focas_net.adapters import NativeAdapter
from focas_net.client import (
    EthernetInfo,
    ItemAttributes,
    ItemRange,
    NativeClient,
    PmcAreaSpan,
    SoftwareSlot,
)
from focas_net.errors import EW, CncError
from focas_net.native import (
    AxisFigure,
    CommandSet,
    EtherInfo,
    Figures,
    ItemNumbers,
    LibraryCall,
    NativePositionRequest,
    PmcAreaInfo,
    PmcAreaInfos,
    PmcTitle,
    RequestBlock,
    ResponseBlock,
    RestartValues,
    SoftwareEdition,
    StatInfo2,
    SystemSoftware,
    decode_frame,
    decode_response_body,
    encode_request_body,
    info,
)
from focas_net.sim import (
    POSITION_DECIMALS,
    SETTING_NUMBERS,
    VALID_FIGURES,
    Machine,
    MachineError,
    default_machine,
    load_machine,
)
from focas_net.sim.nc import ManualClock

MACHINE_16I = "tests/data/fwlib_16i_machine.toml"
CS = (CommandSet.FS16I, CommandSet.FS30I)


# --------------------------------------------------------------------------------------------
# What FANUC's library sends: logged from libfwlib32 1.0.5 against the simulator, both sets


#: (call, the frame the library sent: the same in both sets unless given per set)
GOLDEN_REQUESTS: dict[str, tuple[Callable[[CommandSet], LibraryCall], str]] = {
    "cnc_getfigure": (
        lambda cs: info.cnc_getfigure(cs, 0),
        "a0a0a0a000012101001e0001001c00010001001b0000000000000000000000000000000000000000",
    ),
    "cnc_statinfo2": (
        info.cnc_statinfo2,
        "a0a0a0a0000121010056000300"
        "1c0001000100e20000000000000000000000000000000000000000"
        "001c0001000100e10000000000000000000000000000000000000000"
        "001c0001000100980000000000000000000000000000000000000000",
    ),
    "cnc_rdsyssoft": (
        info.cnc_rdsyssoft,
        "a0a0a0a000012101001e0001001c0001000100410000000000000000000000000000000000000000",
    ),
    "cnc_rddiaginfo": (
        lambda cs: info.cnc_rddiaginfo(cs, 0, 10),
        "a0a0a0a000012101001e0001001c000100010031000000000000000a000000000000000000000000",
    ),
    "cnc_rddiagnum": (
        info.cnc_rddiagnum,
        "a0a0a0a000012101001e0001001c0001000100320000000000000000000000000000000000000000",
    ),
    "cnc_rdparanum": (
        info.cnc_rdparanum,
        "a0a0a0a000012101001e0001001c0001000100110000000000000000000000000000000000000000",
    ),
    "pmc_rdpmcinfo": (
        lambda cs: info.pmc_rdpmcinfo(cs, -1),
        "a0a0a0a000012101001e0001001c000200018003ffffffff00000000000000000000000000000000",
    ),
    "pmc_rdpmctitle": (
        info.pmc_rdpmctitle,
        "a0a0a0a000012101001e0001001c00020001800b0000000000000000000000000000000000000000",
    ),
    "cnc_rdetherinfo": (
        info.cnc_rdetherinfo,
        "a0a0a0a000012101001e0001001c0001000101590000000000000000000000000000000000000000",
    ),
    "cnc_rdsetinfo": (
        lambda cs: info.cnc_rdsetinfo(cs, 0, 10),
        "a0a0a0a000012101001e0001001c00010001002b000000000000000a000000000000000000000000",
    ),
    "cnc_rdprstrinfo": (
        info.cnc_rdprstrinfo,
        "a0a0a0a00001210100c60007001c0001000100430000000000000000000000000000000000000000"
        "001c0001000100430000000100000000000000000000000000000000"
        "001c0001000100430000000200000000000000000000000000000000"
        "001c0001000100430000000300000000000000000000000000000000"
        "001c0001000100430000000400000000000000000000000000000000"
        "001c0001000100260000000dffffffff000000000000000000000000"
        "001c0001000100260000000effffffff000000000000000000000000",
    ),
}

#: cnc_rdset(20, 0): 0x29 in the 16i set, 0x90 in the 30i set.
GOLDEN_RDSET = {
    CommandSet.FS16I: "a0a0a0a000012101001e0001001c0001000100290000001400000014"
    "000000000000000000000000",
    CommandSet.FS30I: "a0a0a0a000012101001e0001001c0001000100900000001400000014"
    "000000000000000000000000",
}


@pytest.mark.parametrize("cs", CS)
@pytest.mark.parametrize("name", sorted(GOLDEN_REQUESTS))
def test_each_call_sends_what_the_library_sends(name: str, cs: CommandSet) -> None:
    build, golden = GOLDEN_REQUESTS[name]
    call = build(cs)
    assert call.function == name
    assert call.encode() == (bytes.fromhex(golden),)


@pytest.mark.parametrize("cs", CS)
def test_rdset_is_0x29_in_the_16i_set_and_0x90_in_the_30i_set(cs: CommandSet) -> None:
    assert info.cnc_rdset(cs, 20, 0).encode() == (bytes.fromhex(GOLDEN_RDSET[cs]),)


def test_getfigure_sends_the_librarys_argument_of_each_data_type() -> None:
    sent = [info.cnc_getfigure(CommandSet.FS30I, t).frames[0][0].args()[0] for t in range(7)]
    assert sent == [0, 1, 2, 5, 6, 3, 4]


@pytest.mark.parametrize("cs", CS)
@pytest.mark.parametrize("name", sorted(GOLDEN_REQUESTS))
def test_each_request_reads_back_from_its_block(name: str, cs: CommandSet) -> None:
    for request in GOLDEN_REQUESTS[name][0](cs).frames[0]:
        assert type(request).from_block(request.to_block()) == request


@given(
    st.integers(0, 6),
    st.integers(-(2**31), 2**31 - 1),
    st.integers(1, 10),
    st.integers(-(2**15), 2**15 - 1),
)
def test_requests_with_arguments_round_trip(kind: int, first: int, count: int, axis: int) -> None:
    for call in (
        info.cnc_getfigure(CommandSet.FS16I, kind),
        info.cnc_rddiaginfo(CommandSet.FS16I, first, count),
        info.cnc_rdsetinfo(CommandSet.FS30I, first, count),
        info.cnc_rdset(CommandSet.FS30I, first, axis),
        info.pmc_rdpmcinfo(CommandSet.FS30I, kind),
    ):
        for request in call.frames[0]:
            assert type(request).from_block(request.to_block()) == request


# --------------------------------------------------------------------------------------------
# The answers: golden bytes the library decoded (see tests/test_fwlib_info.py), round trips


def test_figures_golden() -> None:
    data = bytes.fromhex("00000009000300030003000300030003")
    figures = Figures(9, (AxisFigure(3, 3),) * 3)
    assert figures.encode() == data
    assert Figures.decode(data) == figures


def test_statinfo2_golden() -> None:
    s = StatInfo2(1, 3, 1, 0, 0, 0, 0)
    assert s.encode() == bytes.fromhex("0001 0003 0001 0000 0000 0000 0000 0000 0000 0000 0000")


def test_pmc_title_fields_sit_where_the_library_copies_them() -> None:
    title = PmcTitle(b"MTB", b"MILL", b"PMC", b"0001", b"01", date=b"2026", remarks=b"R")
    data = title.encode()
    assert len(data) == 246
    for offset, text in ((0, b"MTB"), (32, b"MILL"), (64, b"PMC"), (96, b"0001"), (100, b"01")):
        assert data[offset : offset + len(text)] == text
    assert data[134:138] == b"2026"
    assert data[214:215] == b"R"
    assert PmcTitle.decode(data) == title


def test_system_software_places() -> None:
    software = SystemSoftware(
        slots=(0, 0x81),
        module_ids=(0x1234, 0x5678),
        soft_ids=(7, 8),
        editions=(SoftwareEdition(b"D4F1", b"32.0"), SoftwareEdition(b"ABCD", b"0001")),
        installed=2,
        servo=SoftwareEdition(b"90D0", b"0030"),
        others=(("eth_boot", SoftwareEdition(b"E1E1", b"0002")),),
    )
    data = software.encode()
    assert len(data) == 664
    assert data[0:3] == bytes([0, 0x81, 0xFF])
    assert data[0x10:0x12] == b"\x12\x34"  # module ID of slot 0
    assert data[0x32:0x34] == b"\x56\x78"  # module ID of slot 0x81
    assert data[0x90:0x94] == bytes([0, 0, 0x81, 0])  # logical places
    assert data[0xD0:0xD8] == b"D4F132.0"
    assert data[0xD8:0xE0] == b"ABCD0001"
    assert data[0x158:0x160] == b"90D00030"
    assert data[0x1D1] == 2
    assert data[0x1D8 + 8 * 20 : 0x1D8 + 8 * 21] == b"E1E10002"
    assert SystemSoftware.decode(data) == software


def test_pmc_area_count_is_the_records_sent() -> None:
    areas = PmcAreaInfos((PmcAreaInfo(ord("G"), 0, 0, 767), PmcAreaInfo(ord("R"), 0, 0, 7999)))
    data = areas.encode()
    assert data == bytes.fromhex("00000002 0047 0000 00000000 000002ff 0052 0000 00000000 00001f3f")
    assert PmcAreaInfos.decode(data) == areas
    with pytest.raises(ValueError, match="at most 64"):
        PmcAreaInfos((PmcAreaInfo(71, 0, 0, 1),) * 65).encode()


_i32 = st.integers(-(2**31), 2**31 - 1)
_i16 = st.integers(-(2**15), 2**15 - 1)
_text4 = st.binary(min_size=0, max_size=4).map(lambda b: b.replace(b"\0", b"x"))


@given(_i32, st.lists(st.tuples(_i16, _i16), max_size=32))
def test_figures_round_trip(valid: int, axes: list[tuple[int, int]]) -> None:
    f = Figures(valid, tuple(AxisFigure(*a) for a in axes))
    assert Figures.decode(f.encode()) == f


@given(st.lists(_i16, min_size=11, max_size=11))
def test_statinfo2_round_trip(words: list[int]) -> None:
    s = StatInfo2(*words)
    assert StatInfo2.decode(s.encode()) == s


@given(_i32, _i32, _i32, _i16, _i16)
def test_numbers_and_ether_round_trip(a: int, b: int, c: int, t: int, d: int) -> None:
    assert ItemNumbers.decode(ItemNumbers(a, b, c).encode()) == ItemNumbers(a, b, c)
    assert EtherInfo.decode(EtherInfo(t, d).encode()) == EtherInfo(t, d)


@given(st.lists(st.tuples(st.integers(0, 0xFFFF), st.integers(0, 0xFFFF), _i32, _i32), max_size=64))
def test_pmc_areas_round_trip(areas: list[tuple[int, int, int, int]]) -> None:
    a = PmcAreaInfos(tuple(PmcAreaInfo(*x) for x in areas))
    assert PmcAreaInfos.decode(a.encode()) == a


_TITLE_WIDTHS = (32, 32, 32, 4, 2, 32, 16, 32, 32, 32)


@given(
    st.tuples(*[st.binary(max_size=w).map(lambda b: b.replace(b"\0", b"A")) for w in _TITLE_WIDTHS])
)
def test_pmc_title_round_trip(texts: tuple[bytes, ...]) -> None:
    title = PmcTitle(*texts)
    assert len(title.encode()) == sum(_TITLE_WIDTHS)
    assert PmcTitle.decode(title.encode()) == title


@given(st.lists(_i32, max_size=40))
def test_restart_values_round_trip(values: list[int]) -> None:
    r = RestartValues(tuple(values))
    assert RestartValues.decode(r.encode()) == r


@given(
    st.lists(
        st.sampled_from([*range(16), *range(0x80, 0x90)]), unique=True, min_size=0, max_size=16
    ),
    st.data(),
)
def test_system_software_round_trip(slots: list[int], data: st.DataObject) -> None:
    n = len(slots)
    ids = st.lists(st.integers(0, 0xFFFF), min_size=n, max_size=n)
    editions = st.lists(st.builds(SoftwareEdition, _text4, _text4), min_size=n, max_size=n)
    software = SystemSoftware(
        tuple(slots),
        tuple(data.draw(ids)),
        tuple(data.draw(ids)),
        tuple(data.draw(editions)),
        data.draw(st.integers(0, 255)),
        data.draw(st.builds(SoftwareEdition, _text4, _text4)),
    )
    assert SystemSoftware.decode(software.encode()) == software


# --------------------------------------------------------------------------------------------
# The adapter answers from the machine


def _replies(adapter: NativeAdapter, *blocks: RequestBlock) -> tuple[ResponseBlock, ...]:
    return decode_response_body(decode_frame(adapter.answer(encode_request_body(blocks))).body)


def _answer(adapter: NativeAdapter, request: object, path: int = 1) -> ResponseBlock:
    (reply,) = _replies(adapter, request.to_block(path))  # type: ignore[attr-defined]
    return reply


def _machines() -> list[Machine]:
    return [default_machine(), load_machine(MACHINE_16I)]


@pytest.mark.parametrize("machine", _machines(), ids=["30i", "16i"])
def test_the_adapter_answers_from_the_machine(machine: Machine) -> None:
    adapter = NativeAdapter(machine)
    cs = adapter.command_set

    def answer(call: object, index: int = 0) -> object:
        request = call.frames[0][index]  # type: ignore[attr-defined]
        reply = _answer(adapter, request)
        assert reply.ew == 0, (request, reply.ew)
        return request.decode_answer(reply.data, adapter.max_axis)

    axes = len(machine.axes)
    assert answer(info.cnc_getfigure(cs, 0)) == Figures(
        VALID_FIGURES, (AxisFigure(POSITION_DECIMALS, POSITION_DECIMALS),) * axes
    )
    status = adapter.status_info()
    assert answer(info.cnc_statinfo2(cs)) == StatInfo2.of(status)
    identity = machine.identity()
    software = answer(info.cnc_rdsyssoft(cs))
    assert isinstance(software, SystemSoftware)
    assert software.slots == (0,)
    assert software.editions == (
        SoftwareEdition(identity.series.encode(), identity.version.encode()),
    )
    params, diags = machine.param_numbers(), machine.diag_numbers()
    assert answer(info.cnc_rdparanum(cs)) == ItemNumbers(params[0], params[-1], len(params))
    assert answer(info.cnc_rddiagnum(cs)) == ItemNumbers(diags[0], diags[-1], len(diags))
    diag_info = answer(info.cnc_rddiaginfo(cs, 0, 10))
    assert [e.number for e in diag_info.entries] == list(diags[:10])  # type: ignore[attr-defined]
    setting_info = answer(info.cnc_rdsetinfo(cs, 0, 10))
    assert [e.number for e in setting_info.entries] == [20]  # type: ignore[attr-defined]
    (record,) = answer(info.cnc_rdset(cs, 20, 0)).records  # type: ignore[attr-defined]
    value = record.values[0]
    assert (getattr(value, "mantissa", value), record.number) == (machine.read_param(20, 0), 20)
    areas = answer(info.pmc_rdpmcinfo(cs, -1))
    assert isinstance(areas, PmcAreaInfos)
    for area in areas.areas:
        size, _ = machine.pmc_area(chr(area.letter)) or (0, False)
        assert (area.first, area.last) == (0, size - 1)
        machine.read_pmc(chr(area.letter), area.last, 1)  # the last address reads
    title = answer(info.pmc_rdpmctitle(cs))
    assert title.machine == machine.name.encode()  # type: ignore[attr-defined]
    assert answer(info.cnc_rdetherinfo(cs)) == EtherInfo(1, 0)


@pytest.mark.parametrize("machine", _machines(), ids=["30i", "16i"])
def test_program_restart_answers_no_data_and_zero_points(machine: Machine) -> None:
    adapter = NativeAdapter(machine)
    call = info.cnc_rdprstrinfo(adapter.command_set)
    replies = _replies(adapter, *call.blocks()[0])
    assert [r.ew for r in replies] == [0] * 7
    assert [r.data for r in replies[:5]] == [b""] * 5
    zero = bytes.fromhex("00000000 000a 0003")
    assert replies[5].data == replies[6].data == zero * adapter.max_axis
    # the other position kinds are the position reads they were
    (absolute,) = _replies(adapter, NativePositionRequest(4, 1).to_block())
    assert absolute.ew == 0 and len(absolute.data) == 8


def test_the_adapter_refuses_what_the_machine_has_not() -> None:
    adapter = NativeAdapter(default_machine())
    cases = [
        (info.FigureRequest(1), EW.ATTRIB),
        (info.SettingRead3Request(1001, 1001, 0), EW.NUMBER),
        (info.SettingReadRequest(5, 5, 0), EW.NUMBER),
        (info.SettingInfoRequest(21, 10), EW.NUMBER),
        (info.DiagInfoRequest(0, 0), EW.LENGTH),
        (info.PmcInfoRequest(3), EW.ATTRIB),
        (info.RestartInfoRequest(5), EW.ATTRIB),
        (NativePositionRequest(13, 9), EW.ATTRIB),
    ]
    for request, ew in cases:
        assert _answer(adapter, request).ew == ew, request


def test_path_words_are_checked_where_the_answer_is_a_paths() -> None:
    adapter = NativeAdapter(default_machine())
    per_path = (info.FigureRequest(0), info.StatInfo2Request(), info.RestartInfoRequest(0))
    for request in per_path:
        assert _answer(adapter, request, path=2).ew == EW.PATH
    machines = (info.PmcTitleRequest(), info.PmcInfoRequest(0), info.EtherInfoRequest())
    for other in machines:
        assert _answer(adapter, other, path=2).ew == 0


def test_figures_and_status2_are_the_block_paths() -> None:
    machine = two_path_lathe()
    adapter = NativeAdapter(machine)
    for path, axes in ((1, 2), (2, 3)):
        figures = Figures.decode(_answer(adapter, info.FigureRequest(0), path).data)
        assert len(figures.axes) == axes == len(machine.path_info(path).axes)
        status = StatInfo2.decode(_answer(adapter, info.StatInfo2Request(), path).data)
        assert status == StatInfo2.of(adapter.status_info(path))
    assert _answer(adapter, info.FigureRequest(0), 3).ew == EW.PATH


def test_status2_follows_a_running_program() -> None:
    clock = ManualClock()
    machine = default_machine(sim_clock=clock)
    adapter = NativeAdapter(machine)
    idle = StatInfo2.decode(_answer(adapter, info.StatInfo2Request()).data)
    machine.cycle_start()
    clock.advance(1.0)
    running = StatInfo2.decode(_answer(adapter, info.StatInfo2Request()).data)
    assert (idle.run, running.run) == (0, machine.status().run)
    assert running.run != 0
    assert StatInfo2.decode(_answer(adapter, info.StatInfo2Request()).data) == StatInfo2.of(
        adapter.status_info()
    )


def test_settings_are_parameters_below_100() -> None:
    machine = default_machine()
    assert machine.setting_numbers() == tuple(n for n in machine.param_numbers() if n < 100)
    assert SETTING_NUMBERS == range(100)
    machine.check_setting(20)
    with pytest.raises(MachineError, match="no setting data 1001") as raised:
        machine.check_setting(1001)
    assert raised.value.ew == EW.NUMBER
    with pytest.raises(TypeError, match="setting number must be an integer, got '20'"):
        machine.check_setting("20")  # type: ignore[arg-type]


# --------------------------------------------------------------------------------------------
# NativeClient


@pytest.fixture(params=["30i", "16i"])
async def client(request: pytest.FixtureRequest) -> AsyncIterator[NativeClient]:
    machine = default_machine() if request.param == "30i" else load_machine(MACHINE_16I)
    async with serving(machine) as served:
        async with NativeClient(served.host, served.port, timeout=IO_TIMEOUT) as native:
            native.machine = machine  # type: ignore[attr-defined]
            yield native


async def test_the_client_reads_the_machines_information(client: NativeClient) -> None:
    machine: Machine = client.machine  # type: ignore[attr-defined]
    axes = len(machine.axes)
    figures = await client.read_figures()
    assert (figures.valid, figures.input_decimals) == (VALID_FIGURES, (POSITION_DECIMALS,) * axes)
    status = machine.status()
    s2 = await client.read_status2()
    assert (s2.aut, s2.run, s2.tmmode, s2.warning) == (status.aut, status.run, status.tmmode, 0)
    identity = machine.identity()
    software = await client.read_system_software()
    assert software.software == (SoftwareSlot(0, 0, 0, identity.series, identity.version),)
    pmc = next(s for s in machine.system_software() if s.name == "pmc")
    assert software.pmc == (pmc.series, pmc.version)
    params, diags = machine.param_numbers(), machine.diag_numbers()
    assert await client.read_param_numbers() == ItemRange(params[0], params[-1], len(params))
    assert await client.read_diag_numbers() == ItemRange(diags[0], diags[-1], len(diags))
    attributes = await client.read_diag_attributes(diags[0], 2)
    assert [n for n, _ in attributes.items] == list(diags[:2])
    assert await client.read_setting_attributes() == ItemAttributes(0, 0, ((20, 1),))
    setting = await client.read_setting(20)
    assert setting.value == machine.read_param(20, 0) == await client.read_param(20)
    spans = await client.read_pmc_areas()
    assert {s.letter for s in spans} == {r.letter for r in machine.pmc_ranges()}
    assert PmcAreaSpan("R", 0, 0, 7999) in spans
    title = await client.read_pmc_title()
    assert (title.machine, title.prgno) == (machine.name, "0001")
    assert await client.read_ethernet_info() == EthernetInfo(1, 0)
    restart = await client.read_restart_info()
    assert restart.block_counter == () and restart.point == (0,) * axes


async def test_the_client_checks_arguments_before_sending(client: NativeClient) -> None:
    with pytest.raises(ValueError, match="figure data type 7"):
        await client.read_figures(7)
    with pytest.raises(TypeError):
        await client.read_figures("0")  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="count 11"):
        await client.read_diag_attributes(0, 11)
    with pytest.raises(ValueError, match="PMC data type 3"):
        await client.read_pmc_areas(3)
    with pytest.raises(ValueError):
        await client.read_setting(-1)


async def test_the_client_raises_the_cncs_refusals(client: NativeClient) -> None:
    with pytest.raises(CncError) as refused:
        await client.read_setting(1001)
    assert refused.value.ew == EW.NUMBER
    with pytest.raises(CncError) as refused:
        await client.read_figures(1)
    assert refused.value.ew == EW.ATTRIB
