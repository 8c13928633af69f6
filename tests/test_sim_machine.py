"""The simulated machine through its protocol-neutral API (no wire types, no payload bytes)."""

from __future__ import annotations

import logging
from collections.abc import Callable
from datetime import UTC, datetime, timedelta, timezone
from decimal import Decimal

import pytest

from focas_net.errors import EW
from focas_net.sim import (
    AUT_MODES,
    DEFAULT_NAME,
    MAX_ALARM_NO,
    Alarm,
    DataItem,
    HistoryEntry,
    Identity,
    Machine,
    MachineError,
    MacroRange,
    Panel,
    PmcAreaSpec,
    Status,
    default_machine,
)
from focas_net.sim.default import gniu_record, mdd844_record
from focas_net.sim.nc import ManualClock


def fixed_clock(t: datetime) -> Callable[[], datetime]:
    return lambda: t


def ew_of(fn: Callable[[], object]) -> int:
    with pytest.raises(MachineError) as exc:
        fn()
    return exc.value.ew


@pytest.fixture
def m() -> Machine:
    return default_machine(clock=fixed_clock(datetime(2025, 6, 1, 8, 0, 0, tzinfo=UTC)))


# -- the default machine (docs/protocol.md section 7) -----------------------------------------


def test_default_identity_and_panel(m: Machine) -> None:
    assert m.name == DEFAULT_NAME
    assert m.axes == ["X", "Y", "Z"]
    assert m.identity() == Identity(2, 32, " 0", " M", "D4F1", "32.0", "03")
    assert m.status() == Status(0, 0, 1, 0, 0, 0, 0, 0, 0)
    assert (m.panel.mode, m.panel.pwe, m.panel.emergency) == (1, 0, 0)
    assert not m.has_password
    assert m.active_alarms() == [] and m.alarm_history(250) == ()
    assert m.history_capacity == 250
    assert m.control_enabled and not m.read_only


@pytest.mark.parametrize(
    ("number", "is_axis", "width"),
    [
        (1320, True, 4),
        (1420, True, 4),
        (1815, True, 1),
        (3216, False, 2),
        (6711, False, 4),
        (6712, False, 4),
        (20, False, 1),
        (1005, True, 1),
        (1006, True, 1),
        (1020, True, 1),
        (1321, True, 4),
        (1410, False, 4),
        (1422, False, 4),
    ],
)
def test_default_parameters(m: Machine, number: int, is_axis: bool, width: int) -> None:
    item = m.param_item(number)
    assert item is not None and (item.axis, item.width) == (is_axis, width)


def test_default_diagnostics(m: Machine) -> None:
    item = m.diag_item(300)
    assert item is not None and item.axis and item.width == 4
    assert m.read_diag(300, 2) == 0


@pytest.mark.parametrize(("first", "last"), [(1, 33), (100, 199), (500, 999)])
def test_default_writable_macros(m: Machine, first: int, last: int) -> None:
    for number in (first, (first + last) // 2, last):
        assert m.macro_writable(number) is True
        assert m.read_macro(number) is None
    assert m.macro_writable(first - 1) is not True
    assert m.macro_writable(last + 1) is not True


@pytest.mark.parametrize(
    ("letter", "size", "protected"),
    [
        ("X", 128, True),
        ("F", 768, True),
        ("Y", 128, False),
        ("G", 768, False),
        ("R", 8000, False),
        ("D", 10000, False),
        ("K", 100, False),
        ("A", 250, False),
        ("T", 500, False),
        ("C", 400, False),
    ],
)
def test_default_pmc_areas(m: Machine, letter: str, size: int, protected: bool) -> None:
    assert m.pmc_area(letter) == (size, protected)


def test_default_has_no_e_area(m: Machine) -> None:
    assert m.pmc_area("E") is None
    assert ew_of(lambda: m.read_pmc("E", 0, 1)) == EW.NOOPT


def test_default_versamax_station(m: Machine) -> None:
    occupied = {
        (rack, slot)
        for rack in range(8)
        for slot in range(10)
        if m.module_record(rack, slot) is not None
    }
    assert occupied == {(0, 1), (0, 3)}
    assert m.module_record(0, 3) == mdd844_record()
    assert m.module_record(0, 1) == gniu_record()
    assert len(mdd844_record().encode()) == 76


def test_default_machines_are_independent() -> None:
    a, b = default_machine(), default_machine()
    a.set_panel(0, 1, 0)
    a.write_param(a.new_session(), 1420, 1, 1)
    a.write_pmc("R", 0, b"\x01")
    a.write_macro(100, 1)
    assert b.read_param(1420, 1) == 24000
    assert b.read_pmc("R", 0, 1) == b"\x00"
    assert b.read_macro(100) is None
    assert b.status().aut == 1


def test_default_machine_name_and_password() -> None:
    m = default_machine("cell-7", param_password="abc")
    assert m.name == "cell-7" and m.has_password


# -- errors, counters and digests ---------------------------------------------------------------


def test_machine_error_carries_the_code() -> None:
    err = MachineError(EW.PASSWD, "locked")
    assert err.ew == 17 and "EW_PASSWD" in str(err) and "locked" in str(err)
    assert MachineError(-1).ew == -1 and "EW_BUSY" in str(MachineError(-1))
    assert "1234" in str(MachineError(1234))


def test_status_version_moves_with_panel_run_and_alarms(m: Machine) -> None:
    v = m.status_version
    m.write_macro(100, 1)
    m.write_pmc("R", 0, b"\x01")
    assert m.status_version == v
    m.set_panel(0, 1, 1)
    assert m.status_version == v + 1 and m.status().emergency == 1
    m.raise_alarm(0, 3, 10)
    assert m.status_version == v + 2 and m.status().alarm == 1
    m.raise_alarm(0, 3, 10)  # already active: nothing changes
    assert m.status_version == v + 2
    m.clear_alarms()
    assert m.status_version == v + 3 and m.status().alarm == 0
    m.set_run(3, 1)
    st = m.status()
    assert (st.run, st.motion) == (3, 1) and m.status_version == v + 4


def test_version_counts_changes_only(m: Machine) -> None:
    v = m.version
    m.read_param(1320, 1)
    m.read_pmc("R", 0, 4)
    m.status()
    assert m.version == v
    with pytest.raises(MachineError):
        m.write_macro(4001, 1)
    assert m.version == v
    m.write_macro(100, 1)
    assert m.version == v + 1


def test_state_digest_is_stable_and_sees_every_change() -> None:
    a, b = default_machine(), default_machine()
    assert a.state_digest() == b.state_digest()
    seen = {a.state_digest()}
    s = a.new_session()
    changes: list[Callable[[], object]] = [
        lambda: a.set_panel(0, 1, 0),
        lambda: a.write_param(s, 20, 0, 5),
        lambda: a.write_macro(1, Decimal("0.5")),
        lambda: a.write_pmc("G", 4, b"\x01"),
        lambda: a.write_pmc("X", 4, b"\x01", force=True),
        lambda: a.raise_alarm(1, 6, 401, "SV"),
        lambda: a.clear_alarms(6, 401),
        lambda: a.set_diag(410, 0, 55),
        lambda: a.set_run(3),
    ]
    for change in changes:
        change()
        digest = a.state_digest()
        assert digest not in seen
        seen.add(digest)
    # reads and failed writes leave it alone
    a.read_macro(1)
    a.alarm_history(10)
    with pytest.raises(MachineError):
        a.write_param(s, 20, 0, 99)
    assert a.state_digest() == digest


def test_unlock_per_session_and_constant_time_compare(caplog: pytest.LogCaptureFixture) -> None:
    caplog.set_level(logging.DEBUG)
    m = default_machine(param_password="Q7#z")
    m.set_panel(0, 1, 0)
    a, b = m.new_session(), m.new_session()
    assert ew_of(lambda: m.write_param(a, 6711, 0, 1)) == EW.PASSWD
    m.unlock(a, "Q7#z")
    assert a.unlocked and not b.unlocked
    m.write_param(a, 6711, 0, 1)
    assert ew_of(lambda: m.write_param(b, 6711, 0, 2)) == EW.PASSWD
    assert ew_of(lambda: m.unlock(a, b"Q7#")) == EW.PASSWD
    assert not a.unlocked
    assert "Q7#z" not in caplog.text and "Q7#z" not in repr(m)


def test_password_longer_than_four_is_refused_never_cut() -> None:
    with pytest.raises(ValueError, match="'secret'"):
        default_machine(param_password="secret")
    m = default_machine(param_password="secr")
    s = m.new_session()
    assert ew_of(lambda: m.unlock(s, b"secrXXXX")) == EW.PASSWD
    assert not s.unlocked


def test_write_param_order(m: Machine) -> None:
    s = m.new_session()
    assert ew_of(lambda: m.write_param(s, 9, 0, 1, width=1)) == EW.NUMBER
    assert ew_of(lambda: m.write_param(s, 1320, 0, 1, width=4)) == EW.ATTRIB
    assert ew_of(lambda: m.write_param(s, 1320, 1, 1, width=2)) == EW.LENGTH
    assert ew_of(lambda: m.write_param(s, 1320, 1, 1, width=4)) == EW.PASSWD
    assert ew_of(lambda: m.write_param(s, 1320, 1, 1)) == EW.PASSWD  # no width: not checked
    m.set_panel(0, 1, 0)
    assert ew_of(lambda: m.write_param(s, 3216, 0, -5, width=2)) == EW.DATA
    m.write_param(s, 3216, 0, 0, width=2)
    assert m.read_param(3216, 0) == 0
    assert m.param_gate_open(s)
    m.set_panel(3, 1, 0)
    assert not m.param_gate_open(s)


def test_write_param_refusal_names_the_closed_gate(m: Machine) -> None:
    s = m.new_session()

    def detail() -> str:
        with pytest.raises(MachineError) as info:
            m.write_param(s, 3216, 0, 0, width=2)
        assert info.value.ew == EW.PASSWD
        return str(info.value)

    m.set_panel(3, 0, 0)  # EDIT, PWE off: PWE is named first
    assert "parameter write enable (PWE) is off" in detail()
    m.set_panel(3, 1, 0)
    assert "the mode is EDIT, not MDI" in detail()
    m.set_param_password("1234")
    m.set_panel(0, 1, 0)
    assert "the parameter password is not unlocked on this connection" in detail()
    m.unlock(s, "1234")
    m.write_param(s, 3216, 0, 0, width=2)
    assert m.param_gate_closed(s) is None


def test_read_only_machine_typed_ops() -> None:
    m = default_machine(read_only=True)
    s = m.new_session()
    for op in (
        lambda: m.write_param(s, 9, 0, 1, width=1),
        lambda: m.write_macro(9999, 1),
        lambda: m.write_macro(9999, None),
        lambda: m.write_pmc("Q", 0, b""),
        lambda: m.write_pmc("R", 0, b"\x00", force=True),
        lambda: m.set_panel(2, 2, 2),
        lambda: m.raise_alarm(0, 1, 1),
        lambda: m.clear_alarms(),
        m.check_writable,
    ):
        assert ew_of(op) == EW.PROT


def test_macro_values(m: Machine) -> None:
    m.write_macro(33, Decimal("-123.456"))
    assert m.read_macro(33) == Decimal("-123.456")
    assert ew_of(lambda: m.write_macro(33, Decimal("1E-10"))) == EW.DATA
    assert m.read_macro(33) == Decimal("-123.456")
    assert ew_of(lambda: m.read_macro(34)) == EW.NUMBER
    assert m.read_macro(4014) == Decimal(54)


# -- alarms -------------------------------------------------------------------------------------


def test_alarm_clock_is_utc_whole_seconds() -> None:
    local = timezone(timedelta(hours=-5))
    m = default_machine(clock=fixed_clock(datetime(2025, 1, 1, 22, 15, 30, 999_000, local)))
    m.raise_alarm(0, 2, 1, "IO")
    assert m.alarm_history(1)[0].occurred_at == datetime(2025, 1, 2, 3, 15, 30, tzinfo=UTC)


def test_alarm_history_follows_new_alarms(m: Machine) -> None:
    assert m.alarm_history(5) == ()
    v = m.alarm_version
    m.raise_alarm(0, 3, 1, "a")
    assert m.alarm_version == v + 1
    assert m.alarm_history(5) == (
        HistoryEntry(datetime(2025, 6, 1, 8, 0, 0, tzinfo=UTC), 0, 3, 1, "a"),
    )
    assert m.alarm_history(0) == ()
    assert len(m.alarm_history(251)) == len(m.alarm_history()) == 1


def test_custom_history_capacity() -> None:
    m = default_machine(history_capacity=5)
    for no in range(8):
        m.raise_alarm(0, 3, no)
    assert [e.alm_no for e in m.alarm_history(250)] == [7, 6, 5, 4, 3]


def test_active_alarms_to_any_depth(m: Machine) -> None:
    for no in range(40):
        m.raise_alarm(0, 3, no)
    assert len(m.active_alarms(-1, 32)) == 32
    assert [a.alm_no for a in m.active_alarms(3, 3)] == [0, 1, 2]
    assert m.active_alarms(-1, 0) == []
    assert len(m.active_alarms(-1, 33)) == 33
    assert len(m.active_alarms()) == 40
    assert m.active_alarms(4) == []
    assert m.clear_alarms(3, 5) == 1
    assert m.clear_alarms(3, 5) == 0
    assert m.clear_alarms() == 39


def test_raise_alarm_check_order(m: Machine) -> None:
    assert ew_of(lambda: m.raise_alarm(99, 99, 1)) == EW.DATA
    assert ew_of(lambda: m.raise_alarm(99, 0, -2)) == EW.DATA
    assert ew_of(lambda: m.raise_alarm(99, 0, 1, "\u20ac")) == EW.ATTRIB
    assert ew_of(lambda: m.raise_alarm(0, 0, 1, "\u20ac")) == EW.DATA  # not single-byte text
    assert m.active_alarms() == []


@pytest.mark.parametrize(
    ("msg", "control"),
    [
        ("TWO\nLINES", "\n"),
        ("BELL\x07", "\x07"),
        ("NUL\x00", "\x00"),
        ("TAB\tBED", "\t"),
        ("C1\x85", "\x85"),
    ],
)
def test_an_alarm_message_with_a_control_character_is_refused(
    m: Machine, msg: str, control: str
) -> None:
    """The message is one line of text on every front end (the web page, the command line,
    both protocols, a machine file): the machine refuses a control character, naming it."""
    with pytest.raises(MachineError) as info:
        m.raise_alarm(0, 15, 100, msg)
    assert info.value.ew == EW.DATA
    assert f"control character {control!r} (U+{ord(control):04X})" in str(info.value)
    assert m.active_alarms() == [] and m.alarm_history() == ()
    assert m.raise_alarm(0, 15, 100, "caf\u00e9 OK")  # Latin-1 text is kept


@pytest.mark.parametrize("alm_no", [MAX_ALARM_NO + 1, 40000, 99999999999])
def test_an_alarm_number_the_cnc_cannot_hold_is_refused(m: Machine, alm_no: int) -> None:
    assert ew_of(lambda: m.raise_alarm(0, 15, alm_no, "TOO BIG")) == EW.DATA
    assert m.active_alarms() == [] and m.alarm_history() == ()
    assert m.raise_alarm(0, 15, MAX_ALARM_NO, "THE LAST ONE")
    assert [a.alm_no for a in m.active_alarms()] == [MAX_ALARM_NO]


def test_set_panel_values(m: Machine) -> None:
    assert AUT_MODES == frozenset({0, 1, 3, 4, 5, 6, 7, 8, 9, 10})
    assert ew_of(lambda: m.set_panel(2, 0, 0)) == EW.DATA
    m.set_panel(10, 1, 1)
    assert m.status().aut == 10 and m.status().emergency == 1


def test_set_run_and_set_diag_validate(m: Machine) -> None:
    assert ew_of(lambda: m.set_run(5)) == EW.DATA
    assert ew_of(lambda: m.set_diag(308, 1, 500)) == EW.DATA
    m.set_diag(308, 1, 40)
    assert m.read_diag(308, 1) == 40


def test_motion_state(m: Machine) -> None:
    mo = m.motion
    assert len(mo.absolute) == len(mo.machine) == len(mo.relative) == len(mo.distance_to_go) == 3
    assert mo.program_main == 1


# -- constructor validation ---------------------------------------------------------------------


#: The rule an axis name is refused by, as a pattern.
AXIS_RULE = (
    r"an axis name is a capital letter A\.\.Z \(FANUC's parameter 1020\) and up to 3 capital "
    r"letters or digits"
)


@pytest.mark.parametrize(
    ("kwargs", "words"),
    [
        ({"axes": []}, "1..20 axes"),
        ({"axes": [f"A{i}" for i in range(1, 22)]}, "a path has 1..20 axes, got 21$"),
        ({"axes": ["X", "X"]}, "axis 'X' is named twice"),
        ({"axes": ["X", "Ä"]}, "got 'Ä'"),
        ({"axes": ["x"]}, AXIS_RULE + ", got 'x'"),
        ({"axes": ["1"]}, AXIS_RULE + ", got '1'"),
        ({"axes": ["Xa"]}, "got 'Xa'"),
        ({"axes": ["X12345"]}, "got 'X12345'"),
        ({"params": [DataItem(1, 3)]}, "width"),
        ({"params": [DataItem(1, 1, low=5, high=1)]}, "range"),
        ({"params": [DataItem(1, 1, low=0, high=300)]}, "range"),
        ({"params": [DataItem(1, 1, values=[200])]}, "outside"),
        ({"params": [DataItem(1, 1, True, values=[1, 2])]}, "values given"),
        ({"params": [DataItem(1, 1), DataItem(1, 2)]}, "twice"),
        ({"diags": [DataItem(40000, 1)]}, r"outside 0\.\.32767"),
        ({"params": [DataItem(-5, 1)]}, r"number -5 is outside 0\.\.32767"),
        ({"macro_ranges": [MacroRange(-5, 10)]}, r"outside 0\.\.32767"),
        ({"macro_ranges": [MacroRange(1, 10), MacroRange(5, 20)]}, "overlap"),
        ({"macro_ranges": [MacroRange(10, 1)]}, "empty"),
        ({"macro_ranges": [MacroRange(1, 10)], "macro_values": {11: 1}}, "not in any"),
        (
            {"macro_ranges": [MacroRange(1, 10)], "macro_values": {1: Decimal("1E-10")}},
            "does not fit a macro variable",
        ),
        (
            {"macro_ranges": [MacroRange(1, 10)], "macro_values": {1: 2**31}},
            "does not fit a macro variable",
        ),
        ({"pmc": [PmcAreaSpec("Q", 10)]}, "unknown PMC area"),
        ({"identity": Identity(2, 8, "0", " M", "D4F1", "32.0", "03")}, "cnc_type"),
        ({"pmc": [PmcAreaSpec("R", 10), PmcAreaSpec("R", 20)]}, "twice"),
        ({"pmc": [PmcAreaSpec("R", 4, initial={3: b"\x01\x02"})]}, "run past"),
        ({"panel": Panel(mode=2)}, "aut"),
        ({"station": {(8, 1): gniu_record()}}, "out of range"),
        ({"history_capacity": 0}, "capacity"),
    ],
)
def test_constructor_rejects(kwargs: dict[str, object], words: str) -> None:
    with pytest.raises(ValueError, match=words):
        Machine("bad", **kwargs)  # type: ignore[arg-type]


def test_axis_item_single_value_applies_to_every_axis() -> None:
    m = Machine("m", axes=["X", "Y"], params=[DataItem(7, 2, True, values=[9])])
    assert [m.read_param(7, a) for a in (1, 2)] == [9, 9]
    assert ew_of(lambda: m.read_param(7, 3)) == EW.ATTRIB


def test_set_param_password_locks_open_sessions() -> None:
    m = default_machine()
    m.set_panel(0, 1, 0)
    s = m.new_session()
    m.write_param(s, 6711, 0, 1)  # no password: the gate is PWE and MDI only
    m.set_param_password("ab")
    assert m.has_password
    assert ew_of(lambda: m.write_param(s, 6711, 0, 2)) == EW.PASSWD
    m.unlock(s, b"ab")
    m.write_param(s, 6711, 0, 2)
    m.set_param_password("cd")
    assert ew_of(lambda: m.write_param(s, 6711, 0, 3)) == EW.PASSWD
    late = m.new_session()
    m.unlock(late, "cd")
    m.write_param(late, 6711, 0, 3)
    m.set_param_password(None)
    assert not m.has_password
    m.write_param(s, 6711, 0, 4)
    assert m.read_param(6711, 0) == 4


def test_numbers_and_vacant_macro(m: Machine) -> None:
    assert m.param_numbers()[:3] == (20, 1001, 1005)
    assert {1320, 1420, 1815, 3216, 6711, 6712} <= set(m.param_numbers())
    assert m.diag_numbers() == (0, 300, 301, 308, 309, 403, 410, 4901, 4902)
    m.write_macro(7, 1)
    v = m.version
    m.write_macro(7, None)
    assert m.read_macro(7) is None and m.version == v + 1
    m.write_macro(7, None)  # already vacant: nothing changes
    assert m.version == v + 1
    assert ew_of(lambda: m.write_macro(34, None)) == EW.NUMBER
    assert ew_of(lambda: m.write_macro(4001, None)) == EW.PROT
    assert ew_of(lambda: default_machine(read_only=True).write_macro(1, None)) == EW.PROT


# -- the neutral API: any length, decimals, vacant, check orders ----------------------------


def test_pmc_reads_and_writes_of_any_length(m: Machine) -> None:
    data = bytes(i % 251 for i in range(5000))
    m.write_pmc("D", 3000, data)
    assert m.read_pmc("D", 3000, 5000) == data
    assert m.read_pmc("d", 2999, 2) == b"\x00\x00"  # any case
    assert m.read_pmc("D", 9990, 10) == bytes(10)
    assert m.read_pmc("D", 9999, 1) == b"\x00"  # a range holds one byte at least
    m.write_pmc("R", 0, bytes(8000))  # the whole area at once
    assert m.read_pmc("R", 0, 8000) == bytes(8000)


@pytest.mark.parametrize(
    ("op", "code"),
    [
        (lambda m: m.read_pmc("E", -5, 99999), EW.NOOPT),  # the area before the range
        (lambda m: m.read_pmc("Q", 0, 1), EW.NOOPT),  # a letter no machine has
        (lambda m: m.read_pmc("D", 9999, 2), EW.NUMBER),
        (lambda m: m.read_pmc("D", -1, 1), EW.NUMBER),
        (lambda m: m.write_pmc("E", 0, b"\x01"), EW.NOOPT),
        (lambda m: m.write_pmc("X", 127, b"\x01\x02"), EW.NUMBER),  # range before protection
        (lambda m: m.write_pmc("X", 0, b"\x01"), EW.PROT),
        (lambda m: m.write_pmc("G", 767, b"\x01\x02"), EW.NUMBER),
        (lambda m: m.check_pmc_area("E"), EW.NOOPT),
    ],
)
def test_pmc_check_order(m: Machine, op: Callable[[Machine], object], code: EW) -> None:
    before = m.state_digest()
    assert ew_of(lambda: op(m)) == code
    assert m.state_digest() == before


def test_pmc_write_protection_and_force(m: Machine) -> None:
    m.write_pmc("X", 126, b"\x01\x02", force=True)
    assert m.read_pmc("X", 126, 2) == b"\x01\x02"
    m.check_pmc_area("X")
    assert ew_of(lambda: m.read_pmc("D", 0, -1)) == EW.LENGTH
    with pytest.raises(ValueError):
        m.pmc_area("Q")


@pytest.mark.parametrize(
    "value",
    [
        Decimal("1.50"),
        Decimal("-0.000000001"),
        Decimal("2147483.647"),
        Decimal("-2147483648"),
        Decimal("0.000"),
        7,
        -(2**31),
        Decimal("1E+0"),
    ],
)
def test_a_macro_holds_up_to_nine_decimals_as_given(m: Machine, value: Decimal | int) -> None:
    m.write_macro(500, value)
    got = m.read_macro(500)
    assert isinstance(got, Decimal) and got == value
    assert str(got) == str(Decimal(value))  # the decimals written are the decimals read


@pytest.mark.parametrize(("value", "shown"), [("-0", "0"), ("-0.000", "0.000"), ("-0E+0", "0")])
def test_a_negative_zero_is_held_as_zero(m: Machine, value: str, shown: str) -> None:
    """The wire has no -0: the machine holds it as 0, so the page shows what FOCAS reads."""
    m.write_macro(500, Decimal(value))
    assert str(m.read_macro(500)) == shown


@pytest.mark.parametrize(
    "value",
    [
        Decimal("1E-10"),  # ten decimals
        Decimal("5E+1"),  # negative decimals
        Decimal("2147483648"),  # digits beyond 32 bits
        Decimal("214748364.80"),
        Decimal("1" * 5000),  # more digits than an int is made of text
        Decimal("1" * 5000 + "E-5000"),
        Decimal("NaN"),
        Decimal("Infinity"),
        2**31,
    ],
)
def test_a_macro_refuses_what_it_cannot_hold(m: Machine, value: Decimal | int) -> None:
    m.write_macro(500, 3)
    before = m.state_digest()
    assert ew_of(lambda: m.write_macro(500, value)) == EW.DATA
    assert m.state_digest() == before and m.read_macro(500) == 3


def test_macro_write_check_order() -> None:
    m = default_machine()
    bad = Decimal("1E-12")
    assert ew_of(lambda: m.write_macro(9999, bad)) == EW.NUMBER  # the number before the value
    assert ew_of(lambda: m.write_macro(4001, bad)) == EW.PROT  # read-only before the value
    assert ew_of(lambda: m.write_macro(4001, None)) == EW.PROT
    assert ew_of(lambda: m.write_macro(1, bad)) == EW.DATA
    ro = default_machine(read_only=True)
    assert ew_of(lambda: ro.write_macro(9999, bad)) == EW.PROT  # read-only machine first
    with pytest.raises(TypeError):
        m.write_macro(1, 1.5)  # type: ignore[arg-type]
    with pytest.raises(TypeError):
        m.write_macro(1, True)


def test_macro_counters(m: Machine) -> None:
    v, mv = m.version, m.macro_version
    m.write_macro(1, Decimal("2.5"))
    assert (m.version, m.macro_version) == (v + 1, mv + 1)
    m.write_macro(1, None)
    m.write_macro(1, None)
    assert (m.version, m.macro_version) == (v + 2, mv + 2)


def test_the_default_system_variables_keep_their_decimals(m: Machine) -> None:
    assert str(m.read_macro(5001)) == "0.000"
    assert m.read_macro(4018) == Decimal("40.1")
    assert m.read_macro(0) is None


def test_positions_by_kind_and_axis(m: Machine) -> None:
    m.set_motion(absolute=[1, 2, 3], distance_to_go=[-1, 0, 1])
    assert m.positions("absolute") == [("X", 1), ("Y", 2), ("Z", 3)]
    assert m.positions("distance_to_go", 3) == [("Z", 1)]
    assert ew_of(lambda: m.positions("skip", 9)) == EW.NOOPT  # the kind before the axis
    assert ew_of(lambda: m.positions("sideways")) == EW.ATTRIB
    for axis in (0, -1, 4):
        with pytest.raises(MachineError) as exc:
            m.positions("machine", axis)
        assert exc.value.ew == EW.ATTRIB


def test_versamax_station_reads(m: Machine) -> None:
    record = m.config_record(0, 3)
    assert record == mdd844_record().encode()
    assert m.read_config(0, 3, 70, 128) == record[70:]
    assert m.read_config(0, 3, 0, 1000) == record  # any length: what the record has
    assert ew_of(lambda: m.config_record(0, 2)) == EW.NUMBER
    assert ew_of(lambda: m.read_config(0, 2, 99, 1)) == EW.NUMBER
    assert ew_of(lambda: m.read_config(0, 3, 76, 1)) == EW.NUMBER
    assert ew_of(lambda: m.read_config(0, 3, -1, 1)) == EW.NUMBER


def test_active_alarms_and_history_are_neutral_records(m: Machine) -> None:
    m.raise_alarm(1, 4, 500, "OVER TRAVEL +X" + "." * 40)
    (alarm,) = m.active_alarms()
    assert alarm == Alarm(1, 4, 500, "OVER TRAVEL +X" + "." * 18)  # 32 characters kept
    assert alarm.key == (1, 4, 500)
    (entry,) = m.alarm_history()
    assert entry.occurred_at.tzinfo is UTC and entry.msg == alarm.msg


def test_identity_and_status_are_plain_values(m: Machine) -> None:
    identity = m.identity()
    assert (identity.series, identity.version, identity.axes) == ("D4F1", "32.0", "03")
    m.set_panel(0, 1, 1)
    assert m.status() == Status(0, 0, 0, 0, 0, 0, 1, 0, 0)
    custom = Machine("one", axes=["X"])
    assert custom.identity() == Identity(2, 32, " 0", " M", "D4F1", "32.0", "01")


def test_parameter_width_is_checked_only_when_given(m: Machine) -> None:
    s = m.new_session()
    m.set_panel(0, 1, 0)
    assert ew_of(lambda: m.write_param(s, 3216, 0, 5, width=4)) == EW.LENGTH
    m.write_param(s, 3216, 0, 5)
    m.write_param(s, 3216, 0, 6, width=2)
    assert m.read_param(3216, 0) == 6


def test_raising_an_active_alarm_again_keeps_the_first_message() -> None:
    """A CNC shows one entry per alarm: raised again while active, even with another message,
    the alarm stays as it was and the history gets no second entry; raise_alarm says so."""
    m = default_machine()
    assert m.raise_alarm(0, 3, 100, "FIRST") is True
    version = m.version
    assert m.raise_alarm(0, 3, 100, "SECOND MESSAGE") is False
    assert [a.msg for a in m.active_alarms()] == ["FIRST"]
    assert [e.msg for e in m.alarm_history()] == ["FIRST"]
    assert m.version == version
    m.clear_alarms(3, 100)
    assert m.raise_alarm(0, 3, 100, "SECOND MESSAGE") is True  # cleared, then raised anew
    assert [e.msg for e in m.alarm_history()] == ["SECOND MESSAGE", "FIRST"]


@pytest.mark.parametrize(
    ("call", "words"),
    [
        (lambda m: m.select_program(-1), "program number -1 outside 1..9999"),
        (lambda m: m.select_program(10000), "program number 10000 outside 1..9999"),
        (lambda m: m.delete_program(0), "program number 0 outside 1..9999"),
        (lambda m: m.select_program(1234), "no program O1234"),
        (lambda m: m.read_pmc("R", -1, 1), "R-1 is outside PMC area R (R0..R7999)"),
        (
            lambda m: m.read_pmc("R", 10**20, 1),
            f"R{10**20} goes past the end of PMC area R (R0..R7999)",
        ),
        (
            lambda m: m.write_pmc("R", 7999, b"\0\0"),
            "R7999..R8000 goes past the end of PMC area R (R0..R7999)",
        ),
    ],
)
def test_a_refused_number_is_named_as_given(call: Callable[[Machine], object], words: str) -> None:
    """No ``O-001`` or ``R-1..-1``: a number outside the machine's range is named with it."""
    m = default_machine()
    with pytest.raises(MachineError) as exc:
        call(m)
    assert exc.value.ew == EW.NUMBER and words in str(exc.value)


def test_a_clock_behind_the_machine_is_refused_with_what_to_give() -> None:
    m = default_machine(sim_clock=ManualClock(5.0))
    with pytest.raises(ValueError) as exc:
        m.set_clock(ManualClock())
    assert "5.0 s behind the machine's time 5.0" in str(exc.value)
    assert "ManualClock(5.0)" in str(exc.value) and "sim_clock=" in str(exc.value)
    later = ManualClock(m.sim_clock.now())
    m.set_clock(later)
    later.advance(1.0)
    assert m.sim_clock.now() == 6.0


@pytest.mark.parametrize(
    ("mode", "pwe", "emergency", "words"),
    [
        (2, None, None, "unknown mode 2 (one of MDI, MEM, EDIT,"),
        (None, 2, None, "pwe must be True, False or None (unchanged), got 2"),
        (None, None, -1, "emergency must be True, False or None (unchanged), got -1"),
    ],
)
def test_a_panel_refusal_gives_the_values_it_takes(
    mode: int | None, pwe: int | None, emergency: int | None, words: str
) -> None:
    m = default_machine()
    with pytest.raises(MachineError) as info:
        m.set_panel(mode, pwe, emergency)
    assert info.value.ew == EW.DATA
    assert words in str(info.value)
    assert (m.panel.mode, m.panel.pwe, m.panel.emergency) == (1, 0, 0)  # nothing changed
