"""The packed-protocol adapter, driven through ``PackedAdapter.answer`` with payloads made by the
codecs."""

from __future__ import annotations

import struct
import weakref
from collections.abc import Iterator
from datetime import UTC, datetime, timedelta, timezone
from typing import Any

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from focas_net.adapters import PackedAdapter
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
    PmcArea,
    PmcData,
    PmcRange,
    RaiseAlarm,
    SetPanel,
    StatusInfo,
    SysInfo,
    VersaMaxReply,
    VersaMaxRequest,
)
from focas_net.protocol.codecs import (
    ActualValue,
    AxisPosition,
    PositionData,
    PositionRequest,
    ProgramNumbers,
)
from focas_net.sim import Machine, MachineError, MotionData, Session, default_machine
from focas_net.sim.default import mdd844_record
from focas_net.versamax import IOModuleRecord

MANUAL_REPLY = bytes.fromhex(
    "00 52 00 03 00 00 80 08 80 80 44 38 34 34 32 00"
    "00 00 00 00 00 00 00 00 00 00 00 00 00 00 34 00"
    "80 08 80 80 30 00 01 00 01 00 00 00 00 00 03 00"
    "00 00 02 00 00 00 00 00 01 10 11 00 02 00 2C 00"
    "02 12 08 00 02 00 2E 00 00 00 00 00 00 00 00 00"
    "00 00"
)


class FakeClock:
    """A settable UTC clock."""

    def __init__(self, start: datetime) -> None:
        self.now = start

    def __call__(self) -> datetime:
        return self.now

    def tick(self, seconds: float = 1) -> None:
        self.now += timedelta(seconds=seconds)


@pytest.fixture
def clock() -> FakeClock:
    return FakeClock(datetime(2024, 3, 9, 14, 30, 5, 750_000, tzinfo=UTC))


@pytest.fixture
def m(clock: FakeClock) -> Machine:
    return default_machine(clock=clock)


@pytest.fixture
def s(m: Machine) -> Session:
    return m.new_session()


_ADAPTERS: weakref.WeakKeyDictionary[Machine, PackedAdapter] = weakref.WeakKeyDictionary()


def answer(m: Machine, s: Session, command: int, payload: bytes) -> bytes:
    """The answer of ``m``'s adapter (one per machine, as a server has one per listener)."""
    adapter = _ADAPTERS.get(m)
    if adapter is None:
        adapter = _ADAPTERS[m] = PackedAdapter(m)
    return adapter.answer(s, command, payload)


def raw(m: Machine, s: Session, command: int, request: Any) -> bytes:
    payload = request if isinstance(request, bytes) else request.encode()
    return answer(m, s, command, payload)


def call(m: Machine, s: Session, command: int, request: Any = b"") -> Any:
    return COMMANDS[command].response.decode(raw(m, s, command, request))


def ew_of(m: Machine, s: Session, command: int, request: Any = b"") -> int:
    """The EW code of an answer (0 for success; counted lists: the code after count -1)."""
    answer = call(m, s, command, request)
    if isinstance(answer, EwReply | ActiveAlarmList | AlarmHistory):
        return answer.ew
    return 0


def ew(code: EW) -> int:
    return int(code)


def open_gate(m: Machine, s: Session) -> None:
    assert ew_of(m, s, Command.SIM_SET_PANEL, SetPanel(0, 1, 0)) == 0


def rd_param(m: Machine, s: Session, datano: int, axis: int) -> Any:
    return call(m, s, Command.RDPARAM, DataRequest(datano, axis))


def wr_param(m: Machine, s: Session, datano: int, axis: int, value: int, width: int) -> int:
    return ew_of(m, s, Command.WRPARAM, ParamValue(datano, axis, value, width))


def raise_alarm(m: Machine, s: Session, axis: int, typ: int, no: int, msg: bytes = b"") -> int:
    return ew_of(m, s, Command.SIM_RAISE_ALARM, RaiseAlarm(axis, typ, no, msg))


def history(m: Machine, s: Session, depth: int = 250) -> AlarmHistory:
    answer = call(m, s, Command.RDALMHISTRY, AlarmHistoryRequest(depth))
    assert isinstance(answer, AlarmHistory)
    return answer


# -- status and identity ----------------------------------------------------------------------


def test_status_of_default_machine(m: Machine, s: Session) -> None:
    st_ = call(m, s, Command.RDCNCSTAT)
    assert st_ == StatusInfo(0, 0, 1, 0, 0, 0, 0, 0, 0)


def test_status_follows_panel_and_alarms(m: Machine, s: Session) -> None:
    assert ew_of(m, s, Command.SIM_SET_PANEL, SetPanel(5, 1, 1)) == 0
    st_ = call(m, s, Command.RDCNCSTAT)
    assert (st_.aut, st_.emergency, st_.alarm) == (5, 1, 0)
    assert raise_alarm(m, s, 0, 0, 1000, b"EMERGENCY STOP") == 0
    assert call(m, s, Command.RDCNCSTAT).alarm == 1
    assert raise_alarm(m, s, 1, 4, 500, b"OVER TRAVEL +X") == 0
    assert ew_of(m, s, Command.SIM_CLEAR_ALARMS, ClearAlarms(0, -1)) == 0
    assert call(m, s, Command.RDCNCSTAT).alarm == 1
    assert ew_of(m, s, Command.SIM_CLEAR_ALARMS, ClearAlarms(-1, -1)) == 0
    st_ = call(m, s, Command.RDCNCSTAT)
    assert (st_.aut, st_.emergency, st_.alarm) == (5, 1, 0)
    assert ew_of(m, s, Command.SIM_SET_PANEL, SetPanel(0, 0, 0)) == 0
    st_ = call(m, s, Command.RDCNCSTAT)
    assert (st_.aut, st_.emergency) == (0, 0)


def test_status_and_sysinfo_reject_a_payload(m: Machine, s: Session) -> None:
    assert raw(m, s, Command.RDCNCSTAT, b"\x00") == b"\x02\x00"
    assert raw(m, s, Command.SYSINFO, b"\x00\x00") == b"\x02\x00"


def test_sysinfo(m: Machine, s: Session) -> None:
    info = call(m, s, Command.SYSINFO)
    assert isinstance(info, SysInfo)
    assert info.axes == b"03" and info.axes_count == 3
    assert len(raw(m, s, Command.SYSINFO, b"")) == 20


# -- parameters -------------------------------------------------------------------------------

SECTION7_PARAMS = [
    (1320, True, 4),
    (1420, True, 4),
    (1815, True, 1),
    (3216, False, 2),
    (6711, False, 4),
    (6712, False, 4),
    (20, False, 1),
]


@pytest.mark.parametrize(("datano", "is_axis", "width"), SECTION7_PARAMS)
def test_section7_parameters(
    m: Machine, s: Session, datano: int, is_axis: bool, width: int
) -> None:
    for axis in (1, 2, 3) if is_axis else (0,):
        pv = rd_param(m, s, datano, axis)
        assert (pv.datano, pv.axis, pv.width) == (datano, axis, width)
        assert len(raw(m, s, Command.RDPARAM, DataRequest(datano, axis))) == 6 + width


def test_axis_names_in_1020(m: Machine, s: Session) -> None:
    assert [chr(rd_param(m, s, 1020, a).value) for a in (1, 2, 3)] == ["X", "Y", "Z"]


@pytest.mark.parametrize("command", [Command.RDPARAM, Command.RDDIAG])
@pytest.mark.parametrize(
    ("datano", "axis", "code"),
    [
        (9999, 0, EW.NUMBER),
        (9999, -5, EW.NUMBER),  # the number is checked before the axis
        (300, 0, EW.ATTRIB),  # axis item read with axis 0 (300 is axis in both tables)
        (300, -1, EW.ATTRIB),  # no all-axes read
        (300, 4, EW.ATTRIB),
    ],
)
def test_data_read_errors(
    m: Machine, s: Session, command: int, datano: int, axis: int, code: EW
) -> None:
    if command == Command.RDPARAM and datano == 300:
        datano = 1320
    assert raw(m, s, command, DataRequest(datano, axis)) == struct.pack("<h", code)


def test_non_axis_item_with_an_axis(m: Machine, s: Session) -> None:
    assert ew_of(m, s, Command.RDPARAM, DataRequest(3216, 1)) == ew(EW.ATTRIB)
    assert ew_of(m, s, Command.RDDIAG, DataRequest(0, 1)) == ew(EW.ATTRIB)
    # a spindle diagnostic takes the spindle number (one spindle)
    assert ew_of(m, s, Command.RDDIAG, DataRequest(410, 2)) == ew(EW.ATTRIB)


@pytest.mark.parametrize("command", [Command.RDPARAM, Command.RDDIAG])
@pytest.mark.parametrize("payload", [b"", b"\x00", b"\x00\x00\x00", b"\x00" * 5])
def test_data_read_wrong_size(m: Machine, s: Session, command: int, payload: bytes) -> None:
    assert raw(m, s, command, payload) == b"\x02\x00"


def test_diagnostic_300(m: Machine, s: Session) -> None:
    for axis in (1, 2, 3):
        pv = call(m, s, Command.RDDIAG, DataRequest(300, axis))
        assert (pv.datano, pv.axis, pv.width) == (300, axis, 4)


def test_param_write_gate_pwe_and_mode(m: Machine, s: Session) -> None:
    before = m.state_digest()
    assert wr_param(m, s, 6711, 0, 5, 4) == ew(EW.PASSWD)  # MEM, PWE off
    assert ew_of(m, s, Command.SIM_SET_PANEL, SetPanel(1, 1, 0)) == 0
    assert wr_param(m, s, 6711, 0, 5, 4) == ew(EW.PASSWD)  # PWE on but MEM
    assert ew_of(m, s, Command.SIM_SET_PANEL, SetPanel(0, 0, 0)) == 0
    assert wr_param(m, s, 6711, 0, 5, 4) == ew(EW.PASSWD)  # MDI but PWE off
    assert rd_param(m, s, 6711, 0).value == 0
    assert ew_of(m, s, Command.SIM_SET_PANEL, SetPanel(0, 1, 0)) == 0
    assert m.state_digest() != before
    assert wr_param(m, s, 6711, 0, 5, 4) == 0
    assert rd_param(m, s, 6711, 0).value == 5


@pytest.mark.parametrize(
    ("datano", "axis", "value", "width"),
    [
        (1320, 2, -123_456_789, 4),
        (1420, 3, 30000, 4),
        (1815, 1, -1, 1),
        (1815, 3, 0x31, 1),
        (3216, 0, 9999, 2),
        (20, 0, 35, 1),
        (6712, 0, 999_999_999, 4),
    ],
)
def test_param_write_reads_back_byte_identical(
    m: Machine, s: Session, datano: int, axis: int, value: int, width: int
) -> None:
    open_gate(m, s)
    request = ParamValue(datano, axis, value, width).encode()
    assert raw(m, s, Command.WRPARAM, request) == b"\x00\x00"
    assert raw(m, s, Command.RDPARAM, DataRequest(datano, axis)) == b"\x00\x00" + request


def test_param_write_touches_only_its_axis(m: Machine, s: Session) -> None:
    open_gate(m, s)
    assert wr_param(m, s, 1420, 2, 1234, 4) == 0
    assert [rd_param(m, s, 1420, a).value for a in (1, 2, 3)] == [24000, 1234, 24000]


@pytest.mark.parametrize(
    ("payload", "gate", "code"),
    [
        (b"\x00" * 4, True, EW.LENGTH),
        (b"\x00" * 7, True, EW.LENGTH),
        (b"\x00" * 9, True, EW.LENGTH),
        (ParamValue(9999, 0, 1, 4).encode(), True, EW.NUMBER),
        (ParamValue(9999, 7, 1, 2).encode(), False, EW.NUMBER),
        (ParamValue(1320, 0, 1, 4).encode(), True, EW.ATTRIB),
        (ParamValue(1320, 4, 1, 2).encode(), False, EW.ATTRIB),
        (ParamValue(3216, 1, 1, 2).encode(), True, EW.ATTRIB),
        (ParamValue(1320, 1, 1, 2).encode(), True, EW.LENGTH),  # width differs
        (ParamValue(3216, 0, 1, 4).encode(), False, EW.LENGTH),  # width before the gate
        (ParamValue(3216, 0, 1, 2).encode(), False, EW.PASSWD),
        (ParamValue(3216, 0, 10000, 2).encode(), False, EW.PASSWD),  # gate before range
        (ParamValue(3216, 0, 10000, 2).encode(), True, EW.DATA),
        (ParamValue(3216, 0, -1, 2).encode(), True, EW.DATA),
        (ParamValue(1320, 1, 2_000_000_000, 4).encode(), True, EW.DATA),
        (ParamValue(20, 0, 36, 1).encode(), True, EW.DATA),
    ],
)
def test_param_write_errors_in_order(
    m: Machine, s: Session, payload: bytes, gate: bool, code: EW
) -> None:
    if gate:
        open_gate(m, s)
    before = m.state_digest()
    assert raw(m, s, Command.WRPARAM, payload) == struct.pack("<h", code)
    assert m.state_digest() == before


# -- password unlock --------------------------------------------------------------------------


@pytest.fixture
def locked(clock: FakeClock) -> Machine:
    return default_machine(param_password="secr", clock=clock)


def unlock(m: Machine, s: Session, text: str) -> int:
    return ew_of(m, s, Command.WRUNLOCKPARAM, Password.from_text(text))


def test_unlock_is_per_session(locked: Machine) -> None:
    a, b = locked.new_session(), locked.new_session()
    open_gate(locked, a)
    assert wr_param(locked, a, 6711, 0, 1, 4) == ew(EW.PASSWD)
    assert unlock(locked, a, "secr") == 0
    assert wr_param(locked, a, 6711, 0, 2, 4) == 0
    assert wr_param(locked, b, 6711, 0, 3, 4) == ew(EW.PASSWD)
    assert rd_param(locked, b, 6711, 0).value == 2
    assert ew_of(locked, b, Command.WRUNLOCKPARAM, b"secret") == ew(EW.PASSWD)  # never a prefix
    assert unlock(locked, b, "secr") == 0
    assert wr_param(locked, b, 6711, 0, 3, 4) == 0
    assert locked.new_session().unlocked is False


def test_failed_unlock_locks_again(locked: Machine) -> None:
    s = locked.new_session()
    open_gate(locked, s)
    assert unlock(locked, s, "secr") == 0
    assert unlock(locked, s, "nope") == ew(EW.PASSWD)
    assert wr_param(locked, s, 6711, 0, 1, 4) == ew(EW.PASSWD)
    assert ew_of(locked, s, Command.WRUNLOCKPARAM, b"\x00" * 4) == ew(EW.PASSWD)
    assert unlock(locked, s, "sec") == ew(EW.PASSWD)
    assert unlock(locked, s, "secr") == 0
    assert wr_param(locked, s, 6711, 0, 1, 4) == 0


def test_unlock_without_a_password(m: Machine, s: Session) -> None:
    assert unlock(m, s, "any") == 0
    assert ew_of(m, s, Command.WRUNLOCKPARAM, b"\x00" * 4) == 0


@pytest.mark.parametrize("payload", [b"", b"abc"])
def test_unlock_short_payload(locked: Machine, payload: bytes) -> None:
    s = locked.new_session()
    assert raw(locked, s, Command.WRUNLOCKPARAM, payload) == b"\x02\x00"


@pytest.mark.parametrize("payload", [b"secrX", b"secret", b"secr\x00"])
def test_unlock_long_payload_is_a_wrong_password(locked: Machine, payload: bytes) -> None:
    s = locked.new_session()
    open_gate(locked, s)
    assert unlock(locked, s, "secr") == 0
    assert ew_of(locked, s, Command.WRUNLOCKPARAM, payload) == ew(EW.PASSWD)
    assert wr_param(locked, s, 6711, 0, 1, 4) == ew(EW.PASSWD)  # and the session is locked


def test_short_password_is_padded_with_nul(clock: FakeClock) -> None:
    m = default_machine(param_password="ab", clock=clock)
    s = m.new_session()
    assert raw(m, s, Command.WRUNLOCKPARAM, b"ab\x00\x00") == b"\x00\x00"
    assert raw(m, s, Command.WRUNLOCKPARAM, b"ab\x00x") == struct.pack("<h", EW.PASSWD)


# -- macro variables --------------------------------------------------------------------------


@pytest.mark.parametrize("number", [1, 33, 100, 199, 500, 999, 0])
def test_macros_vacant_at_start(m: Machine, s: Session, number: int) -> None:
    assert call(m, s, Command.RDMACRO, MacroRequest(number)) == MacroValue(number, 8, 0, -1)


@pytest.mark.parametrize("number", [-1, 34, 99, 200, 499, 1000, 4000, 32767])
def test_unknown_macro(m: Machine, s: Session, number: int) -> None:
    assert raw(m, s, Command.RDMACRO, MacroRequest(number)) == b"\x03\x00"
    assert ew_of(m, s, Command.WRMACRO, MacroValue(number, 8, 1, 0)) == ew(EW.NUMBER)


def test_system_macros_are_read_only(m: Machine, s: Session) -> None:
    assert call(m, s, Command.RDMACRO, MacroRequest(4003)) == MacroValue(4003, 8, 90, 0)
    assert call(m, s, Command.RDMACRO, MacroRequest(4018)) == MacroValue(4018, 8, 401, 1)
    before = m.state_digest()
    for number in (0, 4001, 4014, 4109, 5001, 5023):
        assert ew_of(m, s, Command.WRMACRO, MacroValue(number, 8, 1, 0)) == ew(EW.PROT)
        # read-only is checked before dec_val
        assert ew_of(m, s, Command.WRMACRO, MacroValue(number, 8, 1, 12)) == ew(EW.PROT)
    assert m.state_digest() == before


@pytest.mark.parametrize(
    ("mcr_val", "dec_val"),
    [(0, 0), (12345, 3), (-7, 1), (2**31 - 1, 9), (-(2**31), 0), (100, 2), (0, 9)],
)
def test_macro_write_reads_back_as_written(
    m: Machine, s: Session, mcr_val: int, dec_val: int
) -> None:
    for number in (1, 150, 999):
        assert ew_of(m, s, Command.WRMACRO, MacroValue(number, 8, mcr_val, dec_val)) == 0
        got = call(m, s, Command.RDMACRO, MacroRequest(number))
        assert got == MacroValue(number, 8, mcr_val, dec_val)


@pytest.mark.parametrize(
    ("payload", "code"),
    [
        (b"\x01\x00" * 4, EW.LENGTH),
        (b"\x01\x00" * 6, EW.LENGTH),
        (MacroValue(100, 4, 1, 0).encode(), EW.LENGTH),
        (MacroValue(100, 0, 1, 0).encode(), EW.LENGTH),
        (MacroValue(9999, 4, 1, 0).encode(), EW.LENGTH),  # length before the number
        (MacroValue(9999, 8, 1, 12).encode(), EW.NUMBER),  # number before dec_val
        (MacroValue(100, 8, 1, 10).encode(), EW.DATA),
        (MacroValue(100, 8, 1, -1).encode(), EW.DATA),  # vacant cannot be written
    ],
)
def test_macro_write_errors(m: Machine, s: Session, payload: bytes, code: EW) -> None:
    assert ew_of(m, s, Command.WRMACRO, MacroValue(100, 8, 42, 1)) == 0
    before = m.state_digest()
    assert raw(m, s, Command.WRMACRO, payload) == struct.pack("<h", code)
    assert m.state_digest() == before
    assert call(m, s, Command.RDMACRO, MacroRequest(100)) == MacroValue(100, 8, 42, 1)


@pytest.mark.parametrize("payload", [b"", b"\x01", b"\x01\x00\x00"])
def test_macro_read_wrong_size(m: Machine, s: Session, payload: bytes) -> None:
    assert raw(m, s, Command.RDMACRO, payload) == b"\x02\x00"


# -- PMC --------------------------------------------------------------------------------------

AREAS = {"X": 128, "Y": 128, "F": 768, "G": 768, "R": 8000, "D": 10000, "K": 100, "A": 250}
AREAS |= {"T": 500, "C": 400}


@pytest.mark.parametrize(("letter", "size"), AREAS.items())
def test_pmc_areas_read_to_their_last_byte(m: Machine, s: Session, letter: str, size: int) -> None:
    code = PmcArea[letter]
    got = call(m, s, Command.RDPMCRNG, PmcRange(code, 0, size - 32, size - 1))
    assert got == PmcData(code, 0, size - 32, size - 1, bytes(32))
    assert ew_of(m, s, Command.RDPMCRNG, PmcRange(code, 0, size - 1, size)) == ew(EW.NUMBER)
    assert ew_of(m, s, Command.RDPMCRNG, PmcRange(code, 0, size, size)) == ew(EW.NUMBER)


@pytest.mark.parametrize(
    ("header", "code"),
    [
        (PmcRange(9, 0, 0, 0), EW.ATTRIB),  # unknown type_a
        (PmcRange(0, 1, 0, 0), EW.ATTRIB),
        (PmcRange(-1, 0, 0, 0), EW.ATTRIB),
        (PmcRange(PmcArea.E, 0, 0, 0), EW.NOOPT),
        (PmcRange(PmcArea.E, 1, 0, 100), EW.NOOPT),  # no-area before type_d and count
        (PmcRange(PmcArea.R, 1, 0, 100), EW.ATTRIB),  # type_d before count
        (PmcRange(PmcArea.R, 0, 5, 4), EW.LENGTH),  # count 0
        (PmcRange(PmcArea.R, 0, 0, 32), EW.LENGTH),  # count 33
        (PmcRange(PmcArea.R, 0, 9000, 9100), EW.LENGTH),  # count before the address
        (PmcRange(PmcArea.R, 0, 7990, 8005), EW.NUMBER),
        (PmcRange(PmcArea.K, 0, 65535, 65535), EW.NUMBER),
    ],
)
def test_pmc_read_errors_in_order(m: Machine, s: Session, header: PmcRange, code: EW) -> None:
    assert raw(m, s, Command.RDPMCRNG, header) == struct.pack("<h", code)


@pytest.mark.parametrize("payload", [b"", b"\x05\x00" * 3, b"\x05\x00" * 4 + b"\x00"])
def test_pmc_read_wrong_size(m: Machine, s: Session, payload: bytes) -> None:
    assert raw(m, s, Command.RDPMCRNG, payload) == b"\x02\x00"


def test_pmc_write_reads_back_and_echoes_header(m: Machine, s: Session) -> None:
    data = bytes(range(1, 33))
    request = PmcData(PmcArea.R, 0, 100, 131, data)
    assert raw(m, s, Command.WRPMCRNG, request) == b"\x00\x00"
    header = PmcRange(PmcArea.R, 0, 100, 131).encode()
    assert raw(m, s, Command.RDPMCRNG, header) == b"\x00\x00" + header + data
    assert call(m, s, Command.RDPMCRNG, PmcRange(PmcArea.R, 0, 99, 101)).data == b"\x00\x01\x02"


@pytest.mark.parametrize(
    ("request_", "code"),
    [
        (b"\x05\x00\x00\x00\x00\x00", EW.LENGTH),
        (PmcData(13, 0, 0, 0, b"\x01"), EW.ATTRIB),
        (PmcData(PmcArea.E, 0, 0, 0, b"\x01"), EW.NOOPT),
        (PmcData(PmcArea.G, 2, 0, 0, b"\x01"), EW.ATTRIB),
        (PmcData(PmcArea.G, 0, 0, 32, bytes(33)), EW.LENGTH),
        (PmcData(PmcArea.G, 0, 0, 3, b"\x01\x02"), EW.LENGTH),  # data length != count
        (PmcData(PmcArea.G, 0, 0, 1, b"\x01\x02\x03"), EW.LENGTH),
        (PmcData(PmcArea.G, 0, 767, 768, b"\x01\x02"), EW.NUMBER),
        (PmcData(PmcArea.G, 0, 767, 768, b"\x01"), EW.LENGTH),  # data length before address
        (PmcData(PmcArea.X, 0, 0, 1, b"\x01\x02"), EW.PROT),
        (PmcData(PmcArea.F, 0, 767, 767, b"\x01"), EW.PROT),
        (PmcData(PmcArea.F, 0, 768, 768, b"\x01"), EW.NUMBER),  # address before protection
    ],
)
def test_pmc_write_errors_change_nothing(m: Machine, s: Session, request_: Any, code: EW) -> None:
    before = m.state_digest()
    assert raw(m, s, Command.WRPMCRNG, request_) == struct.pack("<h", code)
    assert m.state_digest() == before


def test_set_pmc_ignores_write_protection(m: Machine, s: Session) -> None:
    assert ew_of(m, s, Command.SIM_SET_PMC, PmcData(PmcArea.X, 0, 8, 9, b"\xa5\x5a")) == 0
    assert call(m, s, Command.RDPMCRNG, PmcRange(PmcArea.X, 0, 8, 9)).data == b"\xa5\x5a"
    assert ew_of(m, s, Command.SIM_SET_PMC, PmcData(PmcArea.F, 0, 0, 0, b"\x80")) == 0
    before = m.state_digest()
    assert ew_of(m, s, Command.SIM_SET_PMC, PmcData(PmcArea.X, 0, 127, 128, b"\x01\x01")) == ew(
        EW.NUMBER
    )
    assert ew_of(m, s, Command.SIM_SET_PMC, PmcData(PmcArea.E, 0, 0, 0, b"\x01")) == ew(EW.NOOPT)
    assert ew_of(m, s, Command.SIM_SET_PMC, PmcData(PmcArea.X, 0, 0, 1, b"\x01")) == ew(EW.LENGTH)
    assert raw(m, s, Command.SIM_SET_PMC, b"\x01\x00") == b"\x02\x00"
    assert m.state_digest() == before


# -- alarms -----------------------------------------------------------------------------------


def alarms(m: Machine, s: Session, typ: int = -1, max_: int = 32) -> ActiveAlarmList:
    answer = call(m, s, Command.RDALMMSG, AlarmMsgRequest(typ, max_))
    assert isinstance(answer, ActiveAlarmList)
    return answer


def test_rdalmmsg_oldest_first_filtered_and_limited(m: Machine, s: Session) -> None:
    assert alarms(m, s) == ActiveAlarmList(())
    assert raise_alarm(m, s, 1, 6, 401, b"SV0401 IMPROPER V_READY OFF") == 0
    assert raise_alarm(m, s, 0, 3, 10, b"PS0010 IMPROPER G-CODE") == 0
    assert raise_alarm(m, s, 2, 6, 411, b"SV0411 EXCESS ERROR") == 0
    got = alarms(m, s)
    assert [a.key for a in got.entries] == [(1, 6, 401), (0, 3, 10), (2, 6, 411)]
    assert got.entries[1].msg == "PS0010 IMPROPER G-CODE"
    assert [a.key for a in alarms(m, s, 6).entries] == [(1, 6, 401), (2, 6, 411)]
    assert [a.key for a in alarms(m, s, -1, 2).entries] == [(1, 6, 401), (0, 3, 10)]
    assert [a.key for a in alarms(m, s, 6, 1).entries] == [(1, 6, 401)]
    assert alarms(m, s, 19).entries == ()
    assert alarms(m, s, -7).entries == ()


@pytest.mark.parametrize("max_", [0, 33, -1, 32767])
def test_rdalmmsg_bad_max(m: Machine, s: Session, max_: int) -> None:
    assert raw(m, s, Command.RDALMMSG, AlarmMsgRequest(-1, max_)) == b"\xff\xff\x02\x00"


@pytest.mark.parametrize("payload", [b"", b"\xff\xff", b"\xff\xff\x01\x00\x00"])
def test_rdalmmsg_wrong_size(m: Machine, s: Session, payload: bytes) -> None:
    assert raw(m, s, Command.RDALMMSG, payload) == b"\xff\xff\x02\x00"


def test_alarm_history_newest_first_in_utc(m: Machine, s: Session, clock: FakeClock) -> None:
    assert history(m, s) == AlarmHistory(())
    assert raise_alarm(m, s, 1, 6, 401, b"SERVO") == 0
    clock.tick(61)
    assert raise_alarm(m, s, 0, 3, 10, b"PROGRAM") == 0
    clock.now = datetime(2024, 3, 9, 17, 0, 0, 999_999, tzinfo=timezone(timedelta(hours=2)))
    assert raise_alarm(m, s, 0, 2, 1, b"") == 0
    got = history(m, s)
    assert [(e.alm_type, e.alm_no) for e in got.entries] == [(2, 1), (3, 10), (6, 401)]
    assert [e.occurred_at for e in got.entries] == [
        datetime(2024, 3, 9, 15, 0, 0, tzinfo=UTC),
        datetime(2024, 3, 9, 14, 31, 6, tzinfo=UTC),
        datetime(2024, 3, 9, 14, 30, 5, tzinfo=UTC),
    ]
    assert got.entries[2].msg == "SERVO" and got.entries[0].msg == ""
    assert [e.alm_no for e in history(m, s, 2).entries] == [1, 10]


def test_alarm_history_naive_clock_is_utc(clock: FakeClock) -> None:
    clock.now = datetime(2023, 12, 31, 23, 59, 59, 500_000)
    m = default_machine(clock=clock)
    s = m.new_session()
    assert raise_alarm(m, s, 0, 1, 1, b"X") == 0
    assert history(m, s).entries[0].occurred_at == datetime(2023, 12, 31, 23, 59, 59, tzinfo=UTC)


def test_active_alarm_raised_again_changes_nothing(
    m: Machine, s: Session, clock: FakeClock
) -> None:
    assert raise_alarm(m, s, 1, 4, 500, b"OT0500 +X") == 0
    before = m.state_digest()
    clock.tick(5)
    assert raise_alarm(m, s, 1, 4, 500, b"another text") == 0
    assert m.state_digest() == before
    assert len(history(m, s).entries) == 1
    assert alarms(m, s).entries[0].msg == "OT0500 +X"
    # same number on another axis is another alarm
    assert raise_alarm(m, s, 2, 4, 500, b"OT0500 +Y") == 0
    assert len(alarms(m, s).entries) == 2
    # cleared, it can be raised again and is recorded again
    assert ew_of(m, s, Command.SIM_CLEAR_ALARMS, ClearAlarms(4, 500)) == 0
    assert alarms(m, s).entries == ()
    assert raise_alarm(m, s, 1, 4, 500, b"OT0500 +X") == 0
    assert len(history(m, s).entries) == 3


def test_alarm_message_cut_at_32(m: Machine, s: Session) -> None:
    msg = bytes(range(0x41, 0x41 + 40))
    assert raise_alarm(m, s, 0, 15, 1, msg) == 0
    assert alarms(m, s).entries[0].msg.encode("latin-1") == msg[:32]
    assert history(m, s).entries[0].msg.encode("latin-1") == msg[:32]


def test_alarm_message_bytes_come_back_identical(m: Machine, s: Session) -> None:
    msg = bytes([0x20, 0x7E, 0xA0, 0xFF])
    assert raise_alarm(m, s, 0, 12, 7, msg) == 0
    assert alarms(m, s).entries[0].msg.encode("latin-1") == msg


@pytest.mark.parametrize("control", [0x00, 0x01, 0x0A, 0x1F, 0x7F, 0x80, 0x9F])
def test_an_alarm_message_with_a_control_byte_is_ew_data(
    m: Machine, s: Session, control: int
) -> None:
    assert raise_alarm(m, s, 0, 12, 7, b"AB" + bytes([control])) == 5
    assert alarms(m, s).entries == ()


def test_alarm_history_ring_of_250(m: Machine, s: Session, clock: FakeClock) -> None:
    for no in range(260):
        assert raise_alarm(m, s, 0, 3, no, b"PS") == 0
        clock.tick(1)
    got = history(m, s, 250).entries
    assert [e.alm_no for e in got] == list(range(259, 9, -1))
    assert got[0].occurred_at - got[-1].occurred_at == timedelta(seconds=249)
    assert [e.alm_no for e in history(m, s, 1).entries] == [259]


@pytest.mark.parametrize("depth", [0, 251, -1, -32768])
def test_alarm_history_bad_depth(m: Machine, s: Session, depth: int) -> None:
    assert raw(m, s, Command.RDALMHISTRY, AlarmHistoryRequest(depth)) == b"\xff\xff\x02\x00"


@pytest.mark.parametrize("payload", [b"", b"\x01", b"\x01\x00\x00"])
def test_alarm_history_wrong_size(m: Machine, s: Session, payload: bytes) -> None:
    assert raw(m, s, Command.RDALMHISTRY, payload) == b"\xff\xff\x02\x00"


@pytest.mark.parametrize(
    ("payload", "code"),
    [
        (b"\x00" * 7, EW.LENGTH),
        (struct.pack("<4h", 0, 1, 1, 3) + b"ab", EW.LENGTH),  # msg_len does not match
        (struct.pack("<4h", 0, 1, 1, 1) + b"ab", EW.LENGTH),
        (struct.pack("<4h", 0, 1, 1, -1), EW.LENGTH),
        (RaiseAlarm(0, 32, 1, b"").encode(), EW.DATA),
        (RaiseAlarm(0, -1, 1, b"").encode(), EW.DATA),
        (RaiseAlarm(9, 40, 1, b"").encode(), EW.DATA),  # alm_type before axis_no
        (RaiseAlarm(0, 3, -1, b"").encode(), EW.DATA),
        (RaiseAlarm(4, 3, 1, b"").encode(), EW.ATTRIB),
        (RaiseAlarm(-1, 3, 1, b"").encode(), EW.ATTRIB),
    ],
)
def test_raise_alarm_errors(m: Machine, s: Session, payload: bytes, code: EW) -> None:
    before = m.state_digest()
    assert raw(m, s, Command.SIM_RAISE_ALARM, payload) == struct.pack("<h", code)
    assert m.state_digest() == before


def test_raise_alarm_limits(m: Machine, s: Session) -> None:
    assert raise_alarm(m, s, 3, 31, 0) == 0
    assert raise_alarm(m, s, 0, 0, 32767) == 0
    assert len(alarms(m, s).entries) == 2


def test_clear_alarms_matching(m: Machine, s: Session) -> None:
    for axis, typ, no in [(0, 3, 10), (0, 3, 11), (1, 6, 10), (2, 6, 411)]:
        assert raise_alarm(m, s, axis, typ, no) == 0
    assert ew_of(m, s, Command.SIM_CLEAR_ALARMS, ClearAlarms(-1, 10)) == 0
    assert [a.key for a in alarms(m, s).entries] == [(0, 3, 11), (2, 6, 411)]
    assert ew_of(m, s, Command.SIM_CLEAR_ALARMS, ClearAlarms(6, -1)) == 0
    assert [a.key for a in alarms(m, s).entries] == [(0, 3, 11)]
    assert ew_of(m, s, Command.SIM_CLEAR_ALARMS, ClearAlarms(9, 9)) == 0
    assert len(alarms(m, s).entries) == 1
    assert len(history(m, s).entries) == 4
    assert raw(m, s, Command.SIM_CLEAR_ALARMS, b"\xff\xff") == b"\x02\x00"


# -- operator panel ---------------------------------------------------------------------------


@pytest.mark.parametrize(
    "panel", [(2, 0, 0), (11, 0, 0), (-2, 0, 0), (0, 2, 0), (0, -2, 0), (0, 0, 2), (1, 1, -2)]
)
def test_set_panel_bad_values(m: Machine, s: Session, panel: tuple[int, int, int]) -> None:
    before = m.state_digest()
    assert raw(m, s, Command.SIM_SET_PANEL, SetPanel(*panel)) == b"\x05\x00"
    assert m.state_digest() == before


def test_set_panel_minus_one_leaves_a_switch_unchanged(m: Machine, s: Session) -> None:
    assert ew_of(m, s, Command.SIM_SET_PANEL, SetPanel(0, 1, 0)) == 0
    assert ew_of(m, s, Command.SIM_SET_PANEL, SetPanel(-1, -1, 1)) == 0
    assert (m.panel.mode, m.panel.pwe, m.panel.emergency) == (0, 1, 1)
    assert ew_of(m, s, Command.SIM_SET_PANEL, SetPanel(5, -1, -1)) == 0
    assert (m.panel.mode, m.panel.pwe, m.panel.emergency) == (5, 1, 1)
    assert call(m, s, Command.SIM_READ_PANEL) == SetPanel(5, 1, 1)


def test_read_panel_changes_nothing(m: Machine, s: Session) -> None:
    before = m.state_digest()
    assert raw(m, s, Command.SIM_READ_PANEL, b"") == bytes.fromhex("0000 0100 0000 0000")
    assert m.state_digest() == before
    assert raw(m, s, Command.SIM_READ_PANEL, b"\x00") == b"\x02\x00"
    m.control_enabled = False
    assert raw(m, s, Command.SIM_READ_PANEL, b"") == b"\x01\x00"


@pytest.mark.parametrize("mode", [0, 1, 3, 4, 5, 6, 7, 8, 9, 10])
def test_set_panel_every_mode(m: Machine, s: Session, mode: int) -> None:
    assert ew_of(m, s, Command.SIM_SET_PANEL, SetPanel(mode, 1, 0)) == 0
    assert call(m, s, Command.RDCNCSTAT).aut == mode


def test_set_panel_wrong_size(m: Machine, s: Session) -> None:
    assert raw(m, s, Command.SIM_SET_PANEL, b"\x00\x00\x00\x00") == b"\x02\x00"


# -- VersaMax ---------------------------------------------------------------------------------


def test_versamax_mdd844_is_the_manual_example(m: Machine, s: Session) -> None:
    answer = raw(m, s, Command.VERSAMAX_RDCONFIG, VersaMaxRequest(0, 128, 3, 0))
    assert answer == b"\x00\x00" + MANUAL_REPLY
    reply = call(m, s, Command.VERSAMAX_RDCONFIG, VersaMaxRequest(0, 128, 3, 0))
    assert IOModuleRecord.decode(reply.data) == mdd844_record()


def test_versamax_read_by_offset_reassembles(m: Machine, s: Session) -> None:
    parts: list[bytes] = []
    offset = 0
    for _ in range(20):
        reply = call(m, s, Command.VERSAMAX_RDCONFIG, VersaMaxRequest(0, 10, 3, offset))
        assert isinstance(reply, VersaMaxReply) and reply.offset == offset
        parts.append(reply.data)
        offset += len(reply.data)
        if offset >= 76:
            break
    assert b"".join(parts) == MANUAL_REPLY[6:]


def test_versamax_gniu_record(m: Machine, s: Session) -> None:
    reply = call(m, s, Command.VERSAMAX_RDCONFIG, VersaMaxRequest(0, 128, 1, 0))
    record = IOModuleRecord.decode(reply.data)
    assert record.label == "GBI1" and record.references == ()
    assert record.primary_id.valid


@pytest.mark.parametrize(
    ("request_", "code"),
    [
        (VersaMaxRequest(0, 10, 0, 0), EW.NUMBER),  # power supply slot empty
        (VersaMaxRequest(0, 10, 2, 0), EW.NUMBER),
        (VersaMaxRequest(0, 10, 10, 0), EW.NUMBER),
        (VersaMaxRequest(1, 10, 3, 0), EW.NUMBER),
        (VersaMaxRequest(8, 10, 3, 0), EW.NUMBER),
        (VersaMaxRequest(255, 0, 3, 0), EW.NUMBER),  # rack/slot before length
        (VersaMaxRequest(0, 0, 3, 0), EW.LENGTH),
        (VersaMaxRequest(0, 129, 3, 0), EW.LENGTH),
        (VersaMaxRequest(0, 129, 3, 500), EW.LENGTH),  # length before offset
        (VersaMaxRequest(0, 1, 3, 76), EW.NUMBER),
        (VersaMaxRequest(0, 1, 3, 65535), EW.NUMBER),
    ],
)
def test_versamax_errors(m: Machine, s: Session, request_: VersaMaxRequest, code: EW) -> None:
    assert raw(m, s, Command.VERSAMAX_RDCONFIG, request_) == struct.pack("<h", code)


def test_versamax_last_byte(m: Machine, s: Session) -> None:
    reply = call(m, s, Command.VERSAMAX_RDCONFIG, VersaMaxRequest(0, 128, 3, 75))
    assert reply.data == MANUAL_REPLY[-1:]


@pytest.mark.parametrize("payload", [b"", b"\x00" * 5, b"\x00" * 7])
def test_versamax_wrong_size(m: Machine, s: Session, payload: bytes) -> None:
    assert raw(m, s, Command.VERSAMAX_RDCONFIG, payload) == b"\x02\x00"


# -- control off, read-only machine, unknown commands -----------------------------------------

CONTROL_REQUESTS = [
    (Command.SIM_SET_PANEL, SetPanel(0, 1, 0).encode()),
    (Command.SIM_RAISE_ALARM, RaiseAlarm(0, 1, 1, b"x").encode()),
    (Command.SIM_CLEAR_ALARMS, ClearAlarms(-1, -1).encode()),
    (Command.SIM_SET_PMC, PmcData(PmcArea.X, 0, 0, 0, b"\x01").encode()),
]


@pytest.mark.parametrize(("command", "payload"), CONTROL_REQUESTS)
def test_control_disabled_answers_func(clock: FakeClock, command: int, payload: bytes) -> None:
    m = default_machine(clock=clock, control_enabled=False)
    s = m.new_session()
    before = m.state_digest()
    assert answer(m, s, command, payload) == b"\x01\x00"
    assert answer(m, s, command, b"\x00") == b"\x01\x00"  # before the payload size
    assert m.state_digest() == before


def test_control_can_be_switched_off_at_run_time(m: Machine, s: Session) -> None:
    assert ew_of(m, s, Command.SIM_SET_PANEL, SetPanel(0, 1, 0)) == 0
    m.control_enabled = False
    assert raw(m, s, Command.SIM_SET_PANEL, SetPanel(1, 0, 0)) == b"\x01\x00"
    assert call(m, s, Command.RDCNCSTAT).aut == 0


WRITE_REQUESTS = [
    (Command.WRPARAM, ParamValue(3216, 0, 5, 2).encode()),
    (Command.WRPARAM, ParamValue(9999, 0, 5, 2).encode()),  # before the number check
    (Command.WRMACRO, MacroValue(100, 8, 1, 0).encode()),
    (Command.WRMACRO, MacroValue(9999, 8, 1, 0).encode()),
    (Command.WRPMCRNG, PmcData(PmcArea.R, 0, 0, 0, b"\x01").encode()),
    (Command.WRPMCRNG, PmcData(PmcArea.E, 0, 0, 0, b"\x01").encode()),
    *CONTROL_REQUESTS,
    (Command.SIM_SET_PANEL, SetPanel(2, 0, 0).encode()),
    (Command.SIM_RAISE_ALARM, RaiseAlarm(9, 99, 1, b"").encode()),
]


@pytest.mark.parametrize(("command", "payload"), WRITE_REQUESTS)
def test_read_only_machine_protects_every_write(
    clock: FakeClock, command: int, payload: bytes
) -> None:
    m = default_machine(clock=clock, read_only=True)
    s = m.new_session()
    before = m.state_digest()
    assert answer(m, s, command, payload) == b"\x07\x00"
    assert m.state_digest() == before


def test_read_only_machine_still_reads(clock: FakeClock) -> None:
    m = default_machine(clock=clock, read_only=True, param_password="pw")
    s = m.new_session()
    assert call(m, s, Command.RDCNCSTAT).aut == 1
    assert rd_param(m, s, 1320, 1).width == 4
    assert unlock(m, s, "pw") == 0
    assert raw(m, s, Command.WRPARAM, b"\x00" * 7) == b"\x02\x00"  # size before protection


@pytest.mark.parametrize("command", [0x0000, 0x000B, 0x0101, 0x0E00, 0x0E05, 0x0E06, 0xFFFF])
def test_unknown_command(m: Machine, s: Session, command: int) -> None:
    assert answer(m, s, command, b"") == b"\x01\x00"
    assert answer(m, s, command, b"\x00" * 10) == b"\x01\x00"


def test_handled_commands_are_all_but_the_fault_queues_and_the_path_selection() -> None:
    # the connection answers those two groups from what it holds (fault queues, selection)
    assert PackedAdapter.handled == frozenset(COMMANDS) - {
        Command.SIM_INJECT_FAULT,
        Command.SIM_LIST_FAULTS,
        Command.SIM_CLEAR_FAULTS,
        Command.GETPATH,
        Command.SETPATH,
    }


# -- robustness -------------------------------------------------------------------------------


def _all_commands() -> Iterator[int]:
    yield from COMMANDS
    yield 0x0E05
    yield 0x1234


@settings(max_examples=400, deadline=None)
@given(
    command=st.sampled_from(sorted(set(_all_commands()))),
    payload=st.binary(max_size=48),
    read_only=st.booleans(),
    control=st.booleans(),
)
def test_answer_never_raises(command: int, payload: bytes, read_only: bool, control: bool) -> None:
    m = default_machine(read_only=read_only, control_enabled=control)
    s = m.new_session()
    if control and not read_only:
        open_gate(m, s)
    before = m.state_digest()
    reply = answer(m, s, command, payload)
    assert isinstance(reply, bytes) and len(reply) >= 2
    spec = COMMANDS.get(command)
    if spec is None or command == 0x0E05:
        assert reply == b"\x01\x00"
        return
    decoded = spec.response.decode(reply)
    failed = isinstance(decoded, EwReply) or getattr(decoded, "ew", 0) != 0
    if failed:
        assert m.state_digest() == before  # all-or-nothing


def test_cached_reads_follow_writes(m: Machine, s: Session) -> None:
    open_gate(m, s)
    assert rd_param(m, s, 6711, 0).value == 0
    assert wr_param(m, s, 6711, 0, 77, 4) == 0
    assert rd_param(m, s, 6711, 0).value == 77
    assert call(m, s, Command.RDDIAG, DataRequest(403, 0)).value == 33
    m.set_diag(403, 0, 12)
    assert call(m, s, Command.RDDIAG, DataRequest(403, 0)).value == 12
    assert call(m, s, Command.RDMACRO, MacroRequest(500)).vacant
    assert ew_of(m, s, Command.WRMACRO, MacroValue(500, 8, 5, 2)) == 0
    assert call(m, s, Command.RDMACRO, MacroRequest(500)) == MacroValue(500, 8, 5, 2)
    assert alarms(m, s).entries == ()
    assert raise_alarm(m, s, 0, 3, 10) == 0
    assert len(alarms(m, s).entries) == 1
    assert ew_of(m, s, Command.SIM_CLEAR_ALARMS, ClearAlarms(-1, -1)) == 0
    assert alarms(m, s).entries == ()
    assert len(history(m, s, 10).entries) == 1
    assert raise_alarm(m, s, 0, 3, 11) == 0
    assert len(history(m, s, 10).entries) == 2


def test_machines_do_not_share_answers(clock: FakeClock) -> None:
    a, b = default_machine(clock=clock), default_machine(clock=clock)
    sa, sb = a.new_session(), b.new_session()
    open_gate(a, sa)
    assert wr_param(a, sa, 3216, 0, 99, 2) == 0
    assert rd_param(a, sa, 3216, 0).value == 99
    assert rd_param(b, sb, 3216, 0).value == 10
    assert raise_alarm(a, sa, 0, 3, 1) == 0
    assert alarms(b, sb).entries == () and call(b, sb, Command.RDCNCSTAT).alarm == 0


@pytest.mark.parametrize("wrap", [bytearray, memoryview])
def test_payload_of_another_bytes_type(m: Machine, s: Session, wrap: Any) -> None:
    payload = wrap(DataRequest(1320, 1).encode())
    assert answer(m, s, Command.RDPARAM, payload) == raw(
        m, s, Command.RDPARAM, DataRequest(1320, 1)
    )
    assert answer(m, s, Command.RDPARAM, wrap(b"\x00")) == b"\x02\x00"


def test_changes_made_outside_the_adapter_are_seen(m: Machine, s: Session) -> None:
    """Another front end (native FOCAS/2) changes the same machine through its typed API."""
    assert ew_of(m, s, Command.WRMACRO, MacroValue(120, 8, 3, 0)) == 0
    assert not call(m, s, Command.RDMACRO, MacroRequest(120)).vacant
    m.write_macro(120, None)
    assert call(m, s, Command.RDMACRO, MacroRequest(120)).vacant
    assert rd_param(m, s, 3216, 0).value == 10
    m.set_panel(0, 1, 0)
    m.write_param(s, 3216, 0, 20, width=2)
    assert rd_param(m, s, 3216, 0).value == 20
    assert alarms(m, s).entries == ()
    m.raise_alarm(2, 6, 411, "SV0411")
    assert [a.key for a in alarms(m, s).entries] == [(2, 6, 411)]
    assert call(m, s, Command.RDCNCSTAT).alarm == 1
    assert call(m, s, Command.RDPMCRNG, PmcRange(PmcArea.R, 0, 0, 1)).data == b"\x00\x00"
    m.write_pmc("R", 1, b"\x07")
    assert call(m, s, Command.RDPMCRNG, PmcRange(PmcArea.R, 0, 0, 1)).data == b"\x00\x07"
    assert call(m, s, Command.RDPOSITION, PositionRequest(1, 2)).axes[0].value == 0
    m.set_motion(machine=[0, -9, 0])
    assert call(m, s, Command.RDPOSITION, PositionRequest(1, 2)).axes[0].value == -9
    m.set_run(3, 1)
    assert call(m, s, Command.RDCNCSTAT).run == 3


_REQUESTS = st.one_of(
    st.tuples(st.just(int(Command.WRPARAM)), st.sampled_from([
        ParamValue(3216, 0, 5, 2).encode(), ParamValue(1320, 2, -1, 4).encode(),
        ParamValue(20, 0, 99, 1).encode(), ParamValue(1815, 1, 7, 1).encode(),
    ])),
    st.tuples(st.just(int(Command.WRMACRO)), st.builds(
        lambda n, v, d: MacroValue(n, 8, v, d).encode(),
        st.sampled_from([1, 33, 34, 100, 999, 4001]), st.integers(-5, 5), st.integers(-1, 10),
    )),
    st.tuples(st.sampled_from([int(Command.WRPMCRNG), int(Command.SIM_SET_PMC)]), st.builds(
        lambda a, start, n: PmcData(a, 0, start, start + n - 1, bytes(range(n))).encode(),
        st.sampled_from([1, 3, 5, 12]), st.integers(0, 800), st.integers(1, 4),
    )),
    st.tuples(st.just(int(Command.SIM_SET_PANEL)), st.builds(
        lambda *v: SetPanel(*v).encode(), st.integers(-1, 3), st.integers(0, 2), st.integers(0, 1)
    )),
    st.tuples(st.just(int(Command.SIM_RAISE_ALARM)), st.builds(
        lambda ax, t, n: RaiseAlarm(ax, t, n, b"A").encode(),
        st.integers(-1, 4), st.integers(-1, 33), st.integers(0, 3),
    )),
    st.tuples(st.just(int(Command.SIM_CLEAR_ALARMS)), st.builds(
        lambda t, n: ClearAlarms(t, n).encode(), st.integers(-1, 4), st.integers(-1, 3)
    )),
    st.tuples(st.just(int(Command.WRUNLOCKPARAM)), st.sampled_from([b"pw\x00\x00", b"xx\x00\x00"])),
)  # fmt: skip


@settings(max_examples=150, deadline=None)
@given(st.lists(_REQUESTS, max_size=25))
def test_write_sequences_are_all_or_nothing(requests: list[tuple[int, bytes]]) -> None:
    m = default_machine(param_password="pw")
    s = m.new_session()
    for command, payload in requests:
        before = m.state_digest()
        reply = answer(m, s, command, payload)
        assert len(reply) == 2
        if reply != b"\x00\x00":
            assert m.state_digest() == before
    # the status always matches the panel and the alarms
    st_ = call(m, s, Command.RDCNCSTAT)
    assert st_.aut == m.panel.mode and st_.alarm == (1 if alarms(m, s).entries else 0)


# -- motion figures (0x0007..0x000A) ------------------------------------------------------------


def test_program_numbers_feed_and_spindle_of_the_default_machine(m: Machine, s: Session) -> None:
    assert call(m, s, Command.RDPRGNUM) == ProgramNumbers(1, 1)
    assert call(m, s, Command.ACTF) == ActualValue(0)
    assert call(m, s, Command.ACTS) == ActualValue(0)


def test_set_motion_feeds_the_reads(m: Machine, s: Session) -> None:
    m.set_motion(feed=1500, spindle_speed=3000, program_running=1234, program_main=1000)
    assert raw(m, s, Command.RDPRGNUM, b"") == bytes.fromhex("0000 d2040000 e8030000")
    assert raw(m, s, Command.ACTF, b"") == bytes.fromhex("0000 dc050000")
    assert raw(m, s, Command.ACTS, b"") == bytes.fromhex("0000 b80b0000")
    m.set_motion(feed=0)  # only what is given changes
    assert call(m, s, Command.ACTF) == ActualValue(0)
    assert call(m, s, Command.ACTS) == ActualValue(3000)


@pytest.mark.parametrize("command", [Command.RDPRGNUM, Command.ACTF, Command.ACTS])
def test_motion_reads_reject_a_payload(m: Machine, s: Session, command: Command) -> None:
    assert raw(m, s, command, b"\x00") == b"\x02\x00"
    assert raw(m, s, command, b"\x00\x00\x00\x00") == b"\x02\x00"


@pytest.mark.parametrize(
    ("kind", "field"),
    [(0, "absolute"), (1, "machine"), (2, "relative"), (3, "distance_to_go")],
)
def test_positions_of_every_kind(m: Machine, s: Session, kind: int, field: str) -> None:
    values = {
        "absolute": [12345, -2, 100_000],
        "machine": [1, 2, 3],
        "relative": [-7, 0, 7],
        "distance_to_go": [0, 50, -50],
    }
    m.set_motion(**values)  # type: ignore[arg-type]
    want = values[field]
    answer = call(m, s, Command.RDPOSITION, PositionRequest(kind, -1))
    assert answer == PositionData(
        3, tuple(AxisPosition(n, v) for n, v in zip("XYZ", want, strict=True))
    )
    for axis in (1, 2, 3):
        one = call(m, s, Command.RDPOSITION, PositionRequest(kind, axis))
        assert one == PositionData(3, (AxisPosition("XYZ"[axis - 1], want[axis - 1]),))


def test_position_answer_bytes(m: Machine, s: Session) -> None:
    m.set_motion(absolute=[12345, -2, 100_000])
    assert raw(m, s, Command.RDPOSITION, PositionRequest(0, -1)) == bytes.fromhex(
        "0000 0300 0300 39300000 58000000 feffffff 59000000 a0860100 5a000000"
    )
    assert raw(m, s, Command.RDPOSITION, PositionRequest(0, 2)) == bytes.fromhex(
        "0000 0300 0100 feffffff 59000000"
    )


def test_positions_carry_long_axis_names() -> None:
    m = Machine("long", axes=("X1", "B2AX"))
    s = m.new_session()
    m.set_motion(machine=[5, -5])
    answer = call(m, s, Command.RDPOSITION, PositionRequest(1, -1))
    assert answer == PositionData(3, (AxisPosition("X1", 5), AxisPosition("B2AX", -5)))


@pytest.mark.parametrize(
    ("payload", "code"),
    [
        (b"", EW.LENGTH),
        (b"\x00\x00", EW.LENGTH),
        (b"\x00\x00\xff\xff\x00", EW.LENGTH),
        (b"\x04\x00\x00\x00\x00\x00", EW.LENGTH),  # size first: type 4 never looked at
        (PositionRequest(4, -1).encode(), EW.ATTRIB),
        (PositionRequest(-1, 1).encode(), EW.ATTRIB),
        (PositionRequest(4, 0).encode(), EW.ATTRIB),  # bad type and bad axis: EW_ATTRIB
        (PositionRequest(0, 0).encode(), EW.ATTRIB),
        (PositionRequest(0, -2).encode(), EW.ATTRIB),
        (PositionRequest(3, 4).encode(), EW.ATTRIB),
        (PositionRequest(0, 32767).encode(), EW.ATTRIB),
    ],
)
def test_position_read_errors(m: Machine, s: Session, payload: bytes, code: EW) -> None:
    assert raw(m, s, Command.RDPOSITION, payload) == struct.pack("<h", code)


def test_position_reads_work_on_a_read_only_machine_without_control(clock: FakeClock) -> None:
    m = default_machine(clock=clock, read_only=True, control_enabled=False)
    s = m.new_session()
    m.set_motion(relative=[1, 2, 3], feed=10)
    assert call(m, s, Command.RDPOSITION, PositionRequest(2, 3)) == PositionData(
        3, (AxisPosition("Z", 3),)
    )
    assert call(m, s, Command.ACTF) == ActualValue(10)


@pytest.mark.parametrize(
    "kwargs",
    [
        {"absolute": [1, 2]},
        {"machine": [1, 2, 3, 4]},
        {"relative": [0, 0, 2**31]},
        {"distance_to_go": [0, 0, -(2**31) - 1]},
        {"feed": -1},
        {"spindle_speed": 2**31},
        {"program_running": 1, "program_main": -5},
        {"absolute": [9, 9, 9], "sequence": 100_000},
    ],
)
def test_set_motion_is_all_or_nothing(m: Machine, kwargs: dict[str, Any]) -> None:
    before = m.state_digest()
    with pytest.raises(MachineError) as info:
        m.set_motion(**kwargs)
    assert info.value.ew == EW.DATA
    assert m.state_digest() == before


def test_set_motion_changes_the_state_digest(m: Machine) -> None:
    before, version = m.state_digest(), m.version
    m.set_motion(sequence=10)
    assert m.state_digest() != before
    assert m.version == version + 1
    assert m.motion.sequence == 10


def test_machine_rejects_motion_for_other_axes() -> None:
    with pytest.raises(ValueError, match="2 values for 3 axes"):
        Machine("m", motion=MotionData([0, 0], [0, 0, 0], [0, 0, 0], [0, 0, 0]))
