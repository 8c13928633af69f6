"""Every command of docs/protocol.md sections 3-5 over real TCP, and every error path with its EW.

The machine logic is tested through the packed adapter elsewhere; here the same paths go through the
server: frames on a socket, answers matched by command and request id.
"""

from __future__ import annotations

import struct
from datetime import UTC, datetime, timedelta

import pytest
from support import Served, Wire, ew_of, serving

from focas_net.errors import EW
from focas_net.protocol import (
    COMMANDS,
    ActiveAlarmList,
    AlarmHistory,
    AlarmHistoryRequest,
    AlarmMsgRequest,
    ClearAlarms,
    Command,
    DataRequest,
    EwReply,
    MacroRequest,
    MacroValue,
    ParamValue,
    Password,
    PmcData,
    PmcRange,
    RaiseAlarm,
    SetPanel,
    StatusInfo,
    SysInfo,
    VersaMaxReply,
    VersaMaxRequest,
    encode_frame,
)
from focas_net.sim import default_machine

MDI, MEM, EDIT = 0, 1, 3
R, X, F, E = 5, 1, 3, 12

# The reply datagram of rack 0 slot 3 read from offset 0 (docs/protocol.md section 5).
MDD844_REPLY = bytes.fromhex(
    "00 52 00 03 00 00 80 08 80 80 44 38 34 34 32 00"
    "00 00 00 00 00 00 00 00 00 00 00 00 00 00 34 00"
    "80 08 80 80 30 00 01 00 01 00 00 00 00 00 03 00"
    "00 00 02 00 00 00 00 00 01 10 11 00 02 00 2C 00"
    "02 12 08 00 02 00 2E 00 00 00 00 00 00 00 00 00"
    "00 00"
)


async def set_panel(wire: Wire, mode: int, pwe: int, emergency: int = 0) -> None:
    assert await wire.ew(Command.SIM_SET_PANEL, SetPanel(mode, pwe, emergency).encode()) == 0


async def raise_alarm(wire: Wire, axis: int, alm_type: int, alm_no: int, msg: bytes) -> int:
    return await wire.ew(Command.SIM_RAISE_ALARM, RaiseAlarm(axis, alm_type, alm_no, msg).encode())


def param_payload(datano: int, axis: int, value: int, width: int) -> bytes:
    return ParamValue(datano, axis, value, width).encode()


# -- reads ---------------------------------------------------------------------------------


async def test_rdcncstat_default_and_derived(wire: Wire) -> None:
    st = await wire.request(Command.RDCNCSTAT)
    assert st == StatusInfo(0, 0, MEM, 0, 0, 0, 0, 0, 0)
    await set_panel(wire, MDI, 1, 1)
    assert await raise_alarm(wire, 0, 3, 10, b"PROGRAM ERROR") == 0
    st = await wire.request(Command.RDCNCSTAT)
    assert (st.aut, st.emergency, st.alarm) == (MDI, 1, 1)
    assert await wire.ew(Command.SIM_CLEAR_ALARMS, ClearAlarms(-1, -1).encode()) == 0
    await set_panel(wire, EDIT, 0, 0)
    st = await wire.request(Command.RDCNCSTAT)
    assert (st.aut, st.emergency, st.alarm) == (EDIT, 0, 0)


async def test_sysinfo(wire: Wire) -> None:
    answer = await wire.call(Command.SYSINFO)
    assert len(answer) == 2 + 18
    info = await wire.request(Command.SYSINFO)
    assert isinstance(info, SysInfo)
    assert info.axes == b"03"
    assert info.axes_count == 3


@pytest.mark.parametrize(
    ("datano", "axis", "width"),
    [
        (1320, 1, 4),
        (1420, 3, 4),
        (1815, 2, 1),
        (3216, 0, 2),
        (6711, 0, 4),
        (6712, 0, 4),
        (20, 0, 1),
    ],
)
async def test_rdparam_widths(wire: Wire, datano: int, axis: int, width: int) -> None:
    pv = await wire.request(Command.RDPARAM, DataRequest(datano, axis))
    assert isinstance(pv, ParamValue)
    assert (pv.datano, pv.axis, pv.width) == (datano, axis, width)


async def test_rddiag(wire: Wire) -> None:
    pv = await wire.request(Command.RDDIAG, DataRequest(300, 1))
    assert (pv.datano, pv.axis, pv.width) == (300, 1, 4)


@pytest.mark.parametrize("command", [Command.RDPARAM, Command.RDDIAG])
@pytest.mark.parametrize(
    ("datano", "axis", "ew"),
    [
        (9999, 1, EW.NUMBER),  # unknown number
        (9999, -1, EW.NUMBER),  # the number is checked before the axis
        (300, 0, EW.ATTRIB),  # axis 0 for an axis item (param 300 does not exist: see below)
        (-5, 0, EW.NUMBER),
    ],
)
async def test_rdparam_rddiag_number(
    wire: Wire, command: Command, datano: int, axis: int, ew: int
) -> None:
    if datano == 300 and command == Command.RDPARAM:
        ew = EW.NUMBER
    assert await wire.ew(command, DataRequest(datano, axis).encode()) == ew


@pytest.mark.parametrize(
    ("command", "datano", "axis"),
    [
        (Command.RDPARAM, 1320, 0),  # axis 0 for an axis item
        (Command.RDPARAM, 3216, 1),  # an axis for a non-axis item
        (Command.RDPARAM, 1320, -1),  # no all-axes read
        (Command.RDPARAM, 1320, 4),  # beyond the 3 axes
        (Command.RDDIAG, 300, 0),
        (Command.RDDIAG, 300, 4),
        (Command.RDDIAG, 300, -1),
    ],
)
async def test_rdparam_rddiag_attrib(wire: Wire, command: Command, datano: int, axis: int) -> None:
    assert await wire.ew(command, DataRequest(datano, axis).encode()) == EW.ATTRIB


async def test_rdmacro_vacant_and_unknown(wire: Wire) -> None:
    for number in (1, 33, 100, 199, 500, 999):
        mv = await wire.request(Command.RDMACRO, MacroRequest(number))
        assert mv == MacroValue(number, 8, 0, -1)
        assert mv.vacant
    for number in (34, 99, 200, 1000, -1):
        assert await wire.ew(Command.RDMACRO, MacroRequest(number).encode()) == EW.NUMBER


# -- wrong payload sizes -------------------------------------------------------------------


@pytest.mark.parametrize(
    ("command", "payload"),
    [
        (Command.RDCNCSTAT, b"\x00"),
        (Command.SYSINFO, b"\x00\x00"),
        (Command.RDPARAM, b"\x00\x00\x00"),
        (Command.RDPARAM, b"\x00" * 5),
        (Command.RDDIAG, b""),
        (Command.RDMACRO, b"\x01"),
        (Command.RDMACRO, b"\x01\x00\x00"),
        (Command.RDALMMSG, b"\xff\xff"),
        (Command.RDALMHISTRY, b"\x01\x00\x00"),
        (Command.RDALMHISTRY, b""),
        (Command.RDPMCRNG, b"\x05\x00" * 3 + b"\x00"),
        (Command.RDPMCRNG, b"\x05\x00" + b"\x00" * 8),
        (Command.WRPARAM, b"\x14\x00\x00\x00"),
        (Command.WRPARAM, b"\x14\x00\x00\x00\x00\x00\x00"),
        (Command.WRPARAM, b"\x00" * 9),
        (Command.WRMACRO, b"\x00" * 9),
        (Command.WRMACRO, b"\x00" * 11),
        (Command.WRPMCRNG, b"\x05\x00\x00\x00\x00\x00\x00"),
        (Command.WRUNLOCKPARAM, b"abc"),
        (Command.WRUNLOCKPARAM, b"abcde"),
        (Command.VERSAMAX_RDCONFIG, b"\x00" * 5),
        (Command.VERSAMAX_RDCONFIG, b"\x00" * 7),
        (Command.SIM_SET_PANEL, b"\x00" * 4),
        (Command.SIM_RAISE_ALARM, b"\x00" * 6),
        (Command.SIM_CLEAR_ALARMS, b"\xff\xff"),
        (Command.SIM_SET_PMC, b"\x05\x00"),
        (Command.SIM_INJECT_FAULT, b"\x01\x00\x00\x00\x01\x00"),
        (Command.SIM_INJECT_FAULT, b"\x00" * 12),
    ],
)
async def test_wrong_size_is_ew_length(wire: Wire, command: Command, payload: bytes) -> None:
    answer = await wire.call(command, payload)
    if command in (Command.RDALMMSG, Command.RDALMHISTRY):
        assert answer == struct.pack("<hh", -1, EW.LENGTH)
    else:
        assert answer == struct.pack("<h", EW.LENGTH)


@pytest.mark.parametrize("command", [0x0000, 0x000B, 0x0101, 0x0E00, 0x0E08, 0x0F19, 0xFFFF])
async def test_unknown_command_is_ew_func(wire: Wire, command: int) -> None:
    rid = wire.send(command, b"\x01\x02\x03")
    frame = await wire.recv()
    assert (frame.command, frame.request_id, frame.payload) == (command, rid, b"\x01\x00")
    # the connection is still usable
    assert isinstance(await wire.request(Command.RDCNCSTAT), StatusInfo)


# -- parameter writes and their gates ------------------------------------------------------


async def test_wrparam_gate_pwe_and_mode(wire: Wire) -> None:
    payload = param_payload(3216, 0, 25, 2)
    assert await wire.ew(Command.WRPARAM, payload) == EW.PASSWD  # PWE off, MEM
    await set_panel(wire, MDI, 0)
    assert await wire.ew(Command.WRPARAM, payload) == EW.PASSWD  # PWE off
    await set_panel(wire, MEM, 1)
    assert await wire.ew(Command.WRPARAM, payload) == EW.PASSWD  # not MDI
    pv = await wire.request(Command.RDPARAM, DataRequest(3216, 0))
    assert pv.value == 10  # nothing changed
    await set_panel(wire, MDI, 1)
    assert await wire.ew(Command.WRPARAM, payload) == 0
    pv = await wire.request(Command.RDPARAM, DataRequest(3216, 0))
    assert pv.value == 25


@pytest.mark.parametrize(
    ("datano", "axis", "value", "width"),
    [(1320, 2, -123_456, 4), (3216, 0, 9999, 2), (20, 0, 35, 1), (1815, 3, -128, 1)],
)
async def test_wrparam_reads_back_byte_identical(
    wire: Wire, datano: int, axis: int, value: int, width: int
) -> None:
    await set_panel(wire, MDI, 1)
    sent = param_payload(datano, axis, value, width)
    assert await wire.ew(Command.WRPARAM, sent) == 0
    answer = await wire.call(Command.RDPARAM, DataRequest(datano, axis).encode())
    assert answer == b"\x00\x00" + sent


@pytest.mark.parametrize(
    ("payload", "ew"),
    [
        (b"\x0c\x00\x00\x00\x00\x00\x00", EW.LENGTH),  # 7 bytes: not 5/6/8
        (param_payload(9999, 0, 1, 2), EW.NUMBER),
        (param_payload(9999, 9, 1, 1), EW.NUMBER),  # number before axis
        (param_payload(1320, 0, 1, 4), EW.ATTRIB),
        (param_payload(3216, 1, 1, 2), EW.ATTRIB),
        (param_payload(1320, 4, 1, 4), EW.ATTRIB),
        (param_payload(1320, 1, 1, 2), EW.LENGTH),  # width != the parameter's type
        (param_payload(3216, 0, 1, 4), EW.LENGTH),
        (param_payload(20, 0, 36, 1), EW.DATA),  # outside 0..35
        (param_payload(3216, 0, -1, 2), EW.DATA),
    ],
)
async def test_wrparam_errors_with_gate_open(wire: Wire, payload: bytes, ew: int) -> None:
    await set_panel(wire, MDI, 1)
    assert await wire.ew(Command.WRPARAM, payload) == ew


async def test_wrparam_width_checked_before_gate_and_range_after(wire: Wire) -> None:
    # gate closed: width error still wins over EW_PASSWD; EW_PASSWD wins over the range
    assert await wire.ew(Command.WRPARAM, param_payload(1320, 1, 1, 2)) == EW.LENGTH
    assert await wire.ew(Command.WRPARAM, param_payload(20, 0, 99, 1)) == EW.PASSWD


async def test_password_unlock_per_connection() -> None:
    async with serving(default_machine(param_password="AB12")) as served:
        a = await served.connect()
        b = await served.connect()
        async with a, b:
            await set_panel(a, MDI, 1)
            write = param_payload(6711, 0, 42, 4)
            assert await a.ew(Command.WRPARAM, write) == EW.PASSWD
            assert await a.ew(Command.WRUNLOCKPARAM, Password.from_text("nope").encode()) == (
                EW.PASSWD
            )
            assert await a.ew(Command.WRPARAM, write) == EW.PASSWD
            # a longer password is wrong, never cut to a prefix
            assert await a.ew(Command.WRUNLOCKPARAM, b"AB12XYZ") == EW.PASSWD
            assert await a.ew(Command.WRUNLOCKPARAM, Password.from_text("AB12").encode()) == 0
            assert await a.ew(Command.WRPARAM, write) == 0
            # the unlock does not leak to another connection
            assert await b.ew(Command.WRPARAM, param_payload(6711, 0, 7, 4)) == EW.PASSWD
            assert (await b.request(Command.RDPARAM, DataRequest(6711, 0))).value == 42
            # a failed unlock locks the connection again
            assert await a.ew(Command.WRUNLOCKPARAM, b"AB13") == EW.PASSWD
            assert await a.ew(Command.WRPARAM, write) == EW.PASSWD
        # a new connection starts locked
        c = await served.connect()
        async with c:
            assert await c.ew(Command.WRPARAM, write) == EW.PASSWD
            assert await c.ew(Command.WRUNLOCKPARAM, b"AB12") == 0
            assert await c.ew(Command.WRPARAM, param_payload(6711, 0, 43, 4)) == 0


async def test_unlock_without_password_succeeds(wire: Wire) -> None:
    assert await wire.ew(Command.WRUNLOCKPARAM, b"\x00\x00\x00\x00") == 0
    assert await wire.ew(Command.WRUNLOCKPARAM, b"anyx") == 0


# -- macros --------------------------------------------------------------------------------


async def test_wrmacro_round_trip(wire: Wire) -> None:
    for number, mcr_val, dec_val in [(1, 12345, 3), (100, -7, 0), (999, 2_147_483_647, 9)]:
        sent = MacroValue(number, 8, mcr_val, dec_val).encode()
        assert await wire.ew(Command.WRMACRO, sent) == 0
        answer = await wire.call(Command.RDMACRO, MacroRequest(number).encode())
        assert answer == b"\x00\x00" + sent


@pytest.mark.parametrize(
    ("value", "ew"),
    [
        (MacroValue(100, 7, 1, 0), EW.LENGTH),  # length field must be 8
        (MacroValue(34, 8, 1, 0), EW.NUMBER),
        (MacroValue(34, 8, 1, 10), EW.NUMBER),  # number before dec_val
        (MacroValue(4001, 8, 1, 0), EW.PROT),  # read-only variable
        (MacroValue(100, 8, 1, 10), EW.DATA),
        (MacroValue(100, 8, 1, -1), EW.DATA),
    ],
)
async def test_wrmacro_errors(wire: Wire, value: MacroValue, ew: int) -> None:
    assert await wire.ew(Command.WRMACRO, value.encode()) == ew
    if value.number == 100:
        assert (await wire.request(Command.RDMACRO, MacroRequest(100))).vacant


# -- PMC -----------------------------------------------------------------------------------


async def test_pmc_round_trip_and_set_pmc(wire: Wire) -> None:
    data = bytes(range(1, 33))
    assert await wire.ew(Command.WRPMCRNG, PmcData(R, 0, 7968, 7999, data).encode()) == 0
    answer = await wire.request(Command.RDPMCRNG, PmcRange(R, 0, 7968, 7999))
    assert answer == PmcData(R, 0, 7968, 7999, data)
    # X is write-protected for pmc_wrpmcrng but set_pmc drives it
    assert await wire.ew(Command.WRPMCRNG, PmcData(X, 0, 0, 1, b"\x01\x02").encode()) == EW.PROT
    assert await wire.ew(Command.SIM_SET_PMC, PmcData(X, 0, 0, 1, b"\x01\x02").encode()) == 0
    assert (await wire.request(Command.RDPMCRNG, PmcRange(X, 0, 0, 1))).data == b"\x01\x02"
    assert await wire.ew(Command.WRPMCRNG, PmcData(F, 0, 767, 767, b"\x01").encode()) == EW.PROT


@pytest.mark.parametrize(
    ("header", "ew"),
    [
        (PmcRange(9, 0, 0, 0), EW.ATTRIB),  # unknown type_a
        (PmcRange(0, 0, 0, 0), EW.ATTRIB),
        (PmcRange(E, 0, 0, 0), EW.NOOPT),  # no E area
        (PmcRange(E, 1, 0, 40), EW.NOOPT),  # area before type_d and count
        (PmcRange(R, 1, 0, 0), EW.ATTRIB),  # type_d
        (PmcRange(R, 0, 0, 32), EW.LENGTH),  # 33 bytes
        (PmcRange(R, 0, 5, 4), EW.LENGTH),  # count 0
        (PmcRange(R, 0, 7999, 8000), EW.NUMBER),
        (PmcRange(X, 0, 127, 128), EW.NUMBER),
        (PmcRange(8, 0, 9999, 10_000), EW.NUMBER),  # D
    ],
)
async def test_rdpmcrng_errors(wire: Wire, header: PmcRange, ew: int) -> None:
    assert await wire.ew(Command.RDPMCRNG, header.encode()) == ew


@pytest.mark.parametrize(
    ("value", "ew"),
    [
        (PmcData(9, 0, 0, 0, b"\x01"), EW.ATTRIB),
        (PmcData(E, 0, 0, 0, b"\x01"), EW.NOOPT),
        (PmcData(R, 1, 0, 0, b"\x01"), EW.ATTRIB),
        (PmcData(R, 0, 0, 32, b"\x01" * 33), EW.LENGTH),
        (PmcData(R, 0, 0, 3, b"\x01\x02"), EW.LENGTH),  # data length != count
        (PmcData(R, 0, 0, 1, b"\x01\x02\x03"), EW.LENGTH),
        (PmcData(R, 0, 7998, 8001, b"\x01" * 4), EW.NUMBER),
        (PmcData(X, 0, 127, 128, b"\x01\x01"), EW.NUMBER),  # number before protection
        (PmcData(X, 0, 0, 3, b"\x01" * 4), EW.PROT),
    ],
)
async def test_wrpmcrng_errors_change_nothing(wire: Wire, value: PmcData, ew: int) -> None:
    before = await wire.call(Command.RDPMCRNG, PmcRange(R, 0, 0, 31).encode())
    assert await wire.ew(Command.WRPMCRNG, value.encode()) == ew
    assert await wire.call(Command.RDPMCRNG, PmcRange(R, 0, 0, 31).encode()) == before
    assert (await wire.request(Command.RDPMCRNG, PmcRange(X, 0, 0, 3))).data == b"\x00" * 4


# -- alarms --------------------------------------------------------------------------------


async def test_rdalmmsg(wire: Wire) -> None:
    assert await wire.request(Command.RDALMMSG, AlarmMsgRequest(-1, 32)) == ActiveAlarmList(())
    assert await raise_alarm(wire, 0, 3, 10, b"PROGRAM ERROR") == 0
    assert await raise_alarm(wire, 2, 4, 500, b"OVER TRAVEL +") == 0
    assert await raise_alarm(wire, 0, 3, 11, b"X" * 40) == 0  # cut at 32
    alarms = (await wire.request(Command.RDALMMSG, AlarmMsgRequest(-1, 32))).entries
    assert [(a.axis_no, a.alm_type, a.alm_no, a.msg) for a in alarms] == [
        (0, 3, 10, "PROGRAM ERROR"),
        (2, 4, 500, "OVER TRAVEL +"),
        (0, 3, 11, "X" * 32),
    ]
    only_ot = (await wire.request(Command.RDALMMSG, AlarmMsgRequest(4, 32))).entries
    assert [a.alm_no for a in only_ot] == [500]
    first = (await wire.request(Command.RDALMMSG, AlarmMsgRequest(-1, 1))).entries
    assert [a.alm_no for a in first] == [10]
    for bad_max in (0, 33, -1):
        answer = await wire.call(Command.RDALMMSG, AlarmMsgRequest(-1, bad_max).encode())
        assert answer == struct.pack("<hh", -1, EW.LENGTH)
    # clearing selectively; the history keeps everything
    assert await wire.ew(Command.SIM_CLEAR_ALARMS, ClearAlarms(3, 10).encode()) == 0
    left = (await wire.request(Command.RDALMMSG, AlarmMsgRequest(-1, 32))).entries
    assert [a.alm_no for a in left] == [500, 11]
    assert await wire.ew(Command.SIM_CLEAR_ALARMS, ClearAlarms(-1, -1).encode()) == 0
    assert (await wire.request(Command.RDALMMSG, AlarmMsgRequest(-1, 32))).entries == ()
    assert (await wire.request(Command.RDCNCSTAT)).alarm == 0
    history = (await wire.request(Command.RDALMHISTRY, AlarmHistoryRequest(250))).entries
    assert len(history) == 3


async def test_alarm_history_newest_first_with_utc_times() -> None:
    start = datetime(2026, 3, 1, 23, 59, 58, 700_000, tzinfo=UTC)
    ticks = iter(range(100))

    def clock() -> datetime:
        return start + timedelta(seconds=next(ticks))

    async with serving(default_machine(clock=clock)) as served:
        wire = await served.connect()
        async with wire:
            for i, msg in enumerate([b"FIRST", b"SECOND", b"THIRD"]):
                assert await raise_alarm(wire, i, 3, 100 + i, msg) == 0
            # raising an alarm that is already active adds nothing
            assert await raise_alarm(wire, 0, 3, 100, b"FIRST") == 0
            history = await wire.request(Command.RDALMHISTRY, AlarmHistoryRequest(10))
            assert isinstance(history, AlarmHistory)
            assert [(e.alm_no, e.msg, e.axis_no) for e in history.entries] == [
                (102, "THIRD", 2),
                (101, "SECOND", 1),
                (100, "FIRST", 0),
            ]
            times = [e.occurred_at for e in history.entries]
            assert times == [
                datetime(2026, 3, 2, 0, 0, 0, tzinfo=UTC),
                datetime(2026, 3, 1, 23, 59, 59, tzinfo=UTC),
                datetime(2026, 3, 1, 23, 59, 58, tzinfo=UTC),
            ]
            assert all(t.tzinfo is UTC for t in times)
            newest = await wire.request(Command.RDALMHISTRY, AlarmHistoryRequest(1))
            assert [e.alm_no for e in newest.entries] == [102]
            for depth in (0, 251, -1):
                answer = await wire.call(Command.RDALMHISTRY, AlarmHistoryRequest(depth).encode())
                assert answer == struct.pack("<hh", -1, EW.LENGTH)


async def test_alarm_history_wall_clock_is_utc(wire: Wire) -> None:
    before = datetime.now(UTC).replace(microsecond=0)
    assert await raise_alarm(wire, 1, 6, 401, b"SERVO ALARM") == 0
    after = datetime.now(UTC)
    (entry,) = (await wire.request(Command.RDALMHISTRY, AlarmHistoryRequest(5))).entries
    assert before <= entry.occurred_at <= after
    assert entry.occurred_at.utcoffset() == timedelta(0)


@pytest.mark.parametrize(
    ("payload", "ew"),
    [
        (struct.pack("<hhhh", 0, 3, 1, 5) + b"ABC", EW.LENGTH),  # msg_len != bytes sent
        (struct.pack("<hhhh", 0, 3, 1, 0) + b"ABC", EW.LENGTH),
        (RaiseAlarm(0, 32, 1, b"X").encode(), EW.DATA),  # alm_type outside 0..31
        (RaiseAlarm(0, -1, 1, b"X").encode(), EW.DATA),
        (RaiseAlarm(4, 3, 1, b"X").encode(), EW.ATTRIB),  # axis_no outside 0..3
        (RaiseAlarm(-1, 3, 1, b"X").encode(), EW.ATTRIB),
    ],
)
async def test_raise_alarm_errors(wire: Wire, payload: bytes, ew: int) -> None:
    assert await wire.ew(Command.SIM_RAISE_ALARM, payload) == ew
    assert (await wire.request(Command.RDALMMSG, AlarmMsgRequest(-1, 32))).entries == ()
    assert (await wire.request(Command.RDALMHISTRY, AlarmHistoryRequest(250))).entries == ()


@pytest.mark.parametrize(
    "panel", [SetPanel(2, 0, 0), SetPanel(11, 0, 0), SetPanel(-2, 0, 0), SetPanel(0, 2, 0),
              SetPanel(0, 0, 2), SetPanel(0, -2, 0)]
)  # fmt: skip
async def test_set_panel_bad_values(wire: Wire, panel: SetPanel) -> None:
    assert await wire.ew(Command.SIM_SET_PANEL, panel.encode()) == EW.DATA
    st = await wire.request(Command.RDCNCSTAT)
    assert (st.aut, st.emergency) == (MEM, 0)


async def test_set_panel_every_mode(wire: Wire) -> None:
    for mode in (0, 1, 3, 4, 5, 6, 7, 8, 9, 10):
        await set_panel(wire, mode, 0)
        assert (await wire.request(Command.RDCNCSTAT)).aut == mode


# -- VersaMax --------------------------------------------------------------------------------


async def test_versamax_mdd844_record_is_the_manual_example(wire: Wire) -> None:
    answer = await wire.call(Command.VERSAMAX_RDCONFIG, VersaMaxRequest(0, 128, 3, 0).encode())
    assert answer == b"\x00\x00" + MDD844_REPLY
    # read by offset and reassembled
    parts = []
    for offset in range(0, 76, 30):
        reply = await wire.request(Command.VERSAMAX_RDCONFIG, VersaMaxRequest(0, 30, 3, offset))
        assert isinstance(reply, VersaMaxReply)
        assert reply.offset == offset
        parts.append(reply.data)
    assert b"".join(parts) == MDD844_REPLY[6:]


async def test_versamax_gniu(wire: Wire) -> None:
    reply = await wire.request(Command.VERSAMAX_RDCONFIG, VersaMaxRequest(0, 128, 1, 0))
    assert isinstance(reply, VersaMaxReply)
    assert (reply.rack, reply.slot) == (0, 1)
    assert len(reply.data) > 0


@pytest.mark.parametrize(
    ("request_", "ew"),
    [
        (VersaMaxRequest(1, 16, 3, 0), EW.NUMBER),  # empty rack
        (VersaMaxRequest(8, 16, 3, 0), EW.NUMBER),  # rack out of range
        (VersaMaxRequest(0, 16, 2, 0), EW.NUMBER),  # empty slot
        (VersaMaxRequest(0, 16, 10, 0), EW.NUMBER),  # slot out of range
        (VersaMaxRequest(0, 0, 2, 0), EW.NUMBER),  # slot before length
        (VersaMaxRequest(0, 0, 3, 0), EW.LENGTH),
        (VersaMaxRequest(0, 129, 3, 0), EW.LENGTH),
        (VersaMaxRequest(0, 129, 3, 500), EW.LENGTH),  # length before offset
        (VersaMaxRequest(0, 16, 3, 76), EW.NUMBER),  # offset at the end of the record
    ],
)
async def test_versamax_errors(wire: Wire, request_: VersaMaxRequest, ew: int) -> None:
    answer = await wire.call(Command.VERSAMAX_RDCONFIG, request_.encode())
    assert answer == struct.pack("<h", ew)
    assert COMMANDS[Command.VERSAMAX_RDCONFIG].response.decode(answer) == EwReply(ew)


# -- pipelining ----------------------------------------------------------------------------


async def test_pipelined_requests_all_answered_with_their_ids(server: Served, wire: Wire) -> None:
    n = 500
    chunk = b"".join(
        encode_frame(Command.RDMACRO, rid, MacroRequest(1 + rid % 33).encode()) for rid in range(n)
    )
    wire.send_raw(chunk)
    await wire.writer.drain()
    frames = await wire.recv_many(n)
    assert sorted(f.request_id for f in frames) == list(range(n))
    for f in frames:
        assert f.command == Command.RDMACRO
        assert MacroValue.decode(f.payload[2:]).number == 1 + f.request_id % 33


async def test_frames_split_and_merged_across_writes(wire: Wire) -> None:
    data = encode_frame(Command.RDPARAM, 7, DataRequest(1320, 1).encode()) + encode_frame(
        Command.SYSINFO, 8
    )
    for i in range(len(data)):  # one byte per write
        wire.send_raw(data[i : i + 1])
        await wire.writer.drain()
    a, b = await wire.recv_many(2)
    assert (a.request_id, b.request_id) == (7, 8)
    assert ew_of(a.command, a.payload) == 0 and ew_of(b.command, b.payload) == 0
