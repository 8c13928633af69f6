"""The simulated machine through its typed API (no wire encoding)."""

from __future__ import annotations

import logging
from collections.abc import Callable
from datetime import UTC, datetime, timedelta, timezone

import pytest

from focas_net.errors import EW
from focas_net.protocol import MacroValue, ParamValue, PmcArea, StatusInfo, SysInfo
from focas_net.sim import (
    AUT_MODES,
    DEFAULT_NAME,
    DataItem,
    Machine,
    MachineError,
    MacroRange,
    Panel,
    PmcAreaSpec,
    default_machine,
)
from focas_net.sim.default import gniu_record, mdd844_record


def fixed_clock(t: datetime) -> Callable[[], datetime]:
    return lambda: t


def ew_of(fn: Callable[[], object]) -> int:
    with pytest.raises(MachineError) as exc:
        fn()
    return exc.value.ew


@pytest.fixture
def m() -> Machine:
    return default_machine(clock=fixed_clock(datetime(2025, 6, 1, 8, 0, 0, tzinfo=UTC)))


# -- the default machine (PROTOCOL.md section 7) --------------------------------------------


def test_default_identity_and_panel(m: Machine) -> None:
    assert m.name == DEFAULT_NAME
    assert m.axes == ["X", "Y", "Z"]
    assert isinstance(m.sysinfo(), SysInfo) and m.sysinfo().axes == b"03"
    assert m.status() == StatusInfo(0, 0, 1, 0, 0, 0, 0, 0, 0)
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
    assert m.read_diag(300, 2) == ParamValue(300, 2, 0, 4)


@pytest.mark.parametrize(("first", "last"), [(1, 33), (100, 199), (500, 999)])
def test_default_writable_macros(m: Machine, first: int, last: int) -> None:
    for number in (first, (first + last) // 2, last):
        assert m.macro_writable(number) is True
        assert m.read_macro(number).vacant
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
    assert ew_of(lambda: m.read_pmc(PmcArea.E, 0, 0, 0)) == EW.NOOPT


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
    a.write_param(a.new_session(), 1420, 1, 1, 4)
    a.write_pmc(PmcArea.R, 0, 0, 0, b"\x01")
    a.write_macro(100, 1, 0)
    assert b.read_param(1420, 1).value == 24000
    assert b.read_pmc(PmcArea.R, 0, 0, 0) == b"\x00"
    assert b.read_macro(100).vacant
    assert b.status().aut == 1


def test_default_machine_name_and_password() -> None:
    m = default_machine("cell-7", param_password="abc")
    assert m.name == "cell-7" and m.has_password


# -- errors, caches and digests ---------------------------------------------------------------


def test_machine_error_carries_the_code() -> None:
    err = MachineError(EW.PASSWD, "locked")
    assert err.ew == 17 and "EW_PASSWD" in str(err) and "locked" in str(err)
    assert MachineError(-1).ew == -1 and "EW_BUSY" in str(MachineError(-1))
    assert "1234" in str(MachineError(1234))


def test_status_payload_is_cached_until_panel_or_alarm_change(m: Machine) -> None:
    first = m.status_payload()
    assert first == b"\x00\x00" + m.status().encode()
    assert m.status_payload() is first
    m.write_macro(100, 1, 0)
    assert m.status_payload() is first
    m.set_panel(0, 1, 1)
    second = m.status_payload()
    assert second != first and StatusInfo.decode(second[2:]).emergency == 1
    m.raise_alarm(0, 3, 10, b"")
    third = m.status_payload()
    assert StatusInfo.decode(third[2:]).alarm == 1
    m.clear_alarms()
    assert StatusInfo.decode(m.status_payload()[2:]).alarm == 0
    m.set_run(3, 1)
    st = StatusInfo.decode(m.status_payload()[2:])
    assert (st.run, st.motion) == (3, 1)


def test_version_counts_changes_only(m: Machine) -> None:
    v = m.version
    m.read_param(1320, 1)
    m.read_pmc(PmcArea.R, 0, 0, 3)
    m.status_payload()
    assert m.version == v
    with pytest.raises(MachineError):
        m.write_macro(4001, 1, 0)
    assert m.version == v
    m.write_macro(100, 1, 0)
    assert m.version == v + 1


def test_state_digest_is_stable_and_sees_every_change() -> None:
    a, b = default_machine(), default_machine()
    assert a.state_digest() == b.state_digest()
    seen = {a.state_digest()}
    s = a.new_session()
    changes: list[Callable[[], object]] = [
        lambda: a.set_panel(0, 1, 0),
        lambda: a.write_param(s, 20, 0, 5, 1),
        lambda: a.write_macro(1, 5, 1),
        lambda: a.write_pmc(PmcArea.G, 0, 4, 4, b"\x01"),
        lambda: a.write_pmc(PmcArea.X, 0, 4, 4, b"\x01", force=True),
        lambda: a.raise_alarm(1, 6, 401, b"SV"),
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
        a.write_param(s, 20, 0, 99, 1)
    assert a.state_digest() == digest


def test_unlock_per_session_and_constant_time_compare(caplog: pytest.LogCaptureFixture) -> None:
    caplog.set_level(logging.DEBUG)
    m = default_machine(param_password="Q7#z")
    m.set_panel(0, 1, 0)
    a, b = m.new_session(), m.new_session()
    assert ew_of(lambda: m.write_param(a, 6711, 0, 1, 4)) == EW.PASSWD
    m.unlock(a, b"Q7#z")
    assert a.unlocked and not b.unlocked
    m.write_param(a, 6711, 0, 1, 4)
    assert ew_of(lambda: m.write_param(b, 6711, 0, 2, 4)) == EW.PASSWD
    assert ew_of(lambda: m.unlock(a, b"Q7#")) == EW.PASSWD
    assert not a.unlocked
    assert "Q7#z" not in caplog.text and "Q7#z" not in repr(m)


def test_password_longer_than_four_is_cut() -> None:
    m = default_machine(param_password="secret")
    s = m.new_session()
    m.unlock(s, b"secrXXXX")  # only 4 bytes count, on both sides
    assert s.unlocked


def test_write_param_order(m: Machine) -> None:
    s = m.new_session()
    assert ew_of(lambda: m.write_param(s, 9, 0, 1, 1)) == EW.NUMBER
    assert ew_of(lambda: m.write_param(s, 1320, 0, 1, 4)) == EW.ATTRIB
    assert ew_of(lambda: m.write_param(s, 1320, 1, 1, 2)) == EW.LENGTH
    assert ew_of(lambda: m.write_param(s, 1320, 1, 1, 4)) == EW.PASSWD
    m.set_panel(0, 1, 0)
    assert ew_of(lambda: m.write_param(s, 3216, 0, -5, 2)) == EW.DATA
    m.write_param(s, 3216, 0, 0, 2)
    assert m.read_param(3216, 0) == ParamValue(3216, 0, 0, 2)
    assert m.param_gate_open(s)
    m.set_panel(3, 1, 0)
    assert not m.param_gate_open(s)


def test_read_only_machine_typed_ops() -> None:
    m = default_machine(read_only=True)
    s = m.new_session()
    for op in (
        lambda: m.write_param(s, 9, 0, 1, 1),
        lambda: m.write_macro(9999, 1, 0),
        lambda: m.write_pmc(99, 0, 0, 0, b""),
        lambda: m.write_pmc(PmcArea.R, 0, 0, 0, b"\x00", force=True),
        lambda: m.set_panel(2, 2, 2),
        lambda: m.raise_alarm(0, 1, 1, b""),
        lambda: m.clear_alarms(),
    ):
        assert ew_of(op) == EW.PROT


def test_macro_values(m: Machine) -> None:
    m.write_macro(33, -123456, 3)
    assert m.read_macro(33) == MacroValue(33, 8, -123456, 3)
    assert ew_of(lambda: m.write_macro(33, 1, 10)) == EW.DATA
    assert m.read_macro(33) == MacroValue(33, 8, -123456, 3)
    assert ew_of(lambda: m.read_macro(34)) == EW.NUMBER
    assert m.read_macro(4014) == MacroValue(4014, 8, 54, 0)


# -- alarms -------------------------------------------------------------------------------------


def test_alarm_clock_is_utc_whole_seconds() -> None:
    local = timezone(timedelta(hours=-5))
    m = default_machine(clock=fixed_clock(datetime(2025, 1, 1, 22, 15, 30, 999_000, local)))
    m.raise_alarm(0, 2, 1, b"IO")
    assert m.alarm_history(1)[0].occurred_at == datetime(2025, 1, 2, 3, 15, 30, tzinfo=UTC)


def test_alarm_history_cache_follows_new_alarms(m: Machine) -> None:
    assert m.alarm_history(5) == ()
    before = m.alarm_history_payload(5)
    m.raise_alarm(0, 3, 1, b"a")
    assert len(m.alarm_history(5)) == 1
    assert m.alarm_history_payload(5) != before
    assert ew_of(lambda: m.alarm_history(0)) == EW.LENGTH
    assert ew_of(lambda: m.alarm_history_payload(251)) == EW.LENGTH


def test_custom_history_capacity() -> None:
    m = default_machine(history_capacity=5)
    for no in range(8):
        m.raise_alarm(0, 3, no, b"")
    assert [e.alm_no for e in m.alarm_history(250)] == [7, 6, 5, 4, 3]


def test_active_alarm_limits(m: Machine) -> None:
    for no in range(40):
        m.raise_alarm(0, 3, no, b"")
    assert len(m.active_alarms(-1, 32)) == 32
    assert [a.alm_no for a in m.active_alarms(3, 3)] == [0, 1, 2]
    assert ew_of(lambda: m.active_alarms(-1, 0)) == EW.LENGTH
    assert ew_of(lambda: m.active_alarms(-1, 33)) == EW.LENGTH
    assert m.clear_alarms(3, 5) == 1
    assert m.clear_alarms(3, 5) == 0
    assert m.clear_alarms() == 39


def test_raise_alarm_check_order(m: Machine) -> None:
    assert ew_of(lambda: m.raise_alarm(99, 99, 1, b"")) == EW.DATA
    assert ew_of(lambda: m.raise_alarm(99, 0, -2, b"")) == EW.DATA
    assert ew_of(lambda: m.raise_alarm(99, 0, 1, b"")) == EW.ATTRIB
    assert m.active_alarms() == []


def test_set_panel_values(m: Machine) -> None:
    assert AUT_MODES == frozenset({0, 1, 3, 4, 5, 6, 7, 8, 9, 10})
    assert ew_of(lambda: m.set_panel(2, 0, 0)) == EW.DATA
    m.set_panel(10, 1, 1)
    assert m.status().aut == 10 and m.status().emergency == 1


def test_set_run_and_set_diag_validate(m: Machine) -> None:
    assert ew_of(lambda: m.set_run(5)) == EW.DATA
    assert ew_of(lambda: m.set_diag(308, 1, 500)) == EW.DATA
    m.set_diag(308, 1, 40)
    assert m.read_diag(308, 1).value == 40


def test_motion_state(m: Machine) -> None:
    mo = m.motion
    assert len(mo.absolute) == len(mo.machine) == len(mo.relative) == len(mo.distance_to_go) == 3
    assert mo.program_main == 1


# -- constructor validation ---------------------------------------------------------------------


@pytest.mark.parametrize(
    ("kwargs", "words"),
    [
        ({"axes": []}, "1..32 axes"),
        ({"params": [DataItem(1, 3)]}, "width"),
        ({"params": [DataItem(1, 1, low=5, high=1)]}, "range"),
        ({"params": [DataItem(1, 1, low=0, high=300)]}, "range"),
        ({"params": [DataItem(1, 1, values=[200])]}, "outside"),
        ({"params": [DataItem(1, 1, True, values=[1, 2])]}, "values given"),
        ({"params": [DataItem(1, 1), DataItem(1, 2)]}, "twice"),
        ({"diags": [DataItem(40000, 1)]}, "outside i16"),
        ({"macro_ranges": [MacroRange(1, 10), MacroRange(5, 20)]}, "overlap"),
        ({"macro_ranges": [MacroRange(10, 1)]}, "empty"),
        ({"macro_ranges": [MacroRange(1, 10)], "macro_values": {11: (1, 0)}}, "not in any"),
        ({"macro_ranges": [MacroRange(1, 10)], "macro_values": {1: (1, 10)}}, "invalid"),
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
    assert [m.read_param(7, a).value for a in (1, 2)] == [9, 9]
    assert ew_of(lambda: m.read_param(7, 3)) == EW.ATTRIB


def test_set_param_password_locks_open_sessions() -> None:
    m = default_machine()
    m.set_panel(0, 1, 0)
    s = m.new_session()
    m.write_param(s, 6711, 0, 1, 4)  # no password: the gate is PWE and MDI only
    m.set_param_password("ab")
    assert m.has_password
    assert ew_of(lambda: m.write_param(s, 6711, 0, 2, 4)) == EW.PASSWD
    m.unlock(s, b"ab")
    m.write_param(s, 6711, 0, 2, 4)
    m.set_param_password("cd")
    assert ew_of(lambda: m.write_param(s, 6711, 0, 3, 4)) == EW.PASSWD
    late = m.new_session()
    m.unlock(late, b"cd")
    m.write_param(late, 6711, 0, 3, 4)
    m.set_param_password(None)
    assert not m.has_password
    m.write_param(s, 6711, 0, 4, 4)
    assert m.read_param(6711, 0).value == 4


def test_numbers_and_clear_macro(m: Machine) -> None:
    assert m.param_numbers()[:3] == (20, 1001, 1005)
    assert {1320, 1420, 1815, 3216, 6711, 6712} <= set(m.param_numbers())
    assert m.diag_numbers() == (0, 300, 301, 308, 309, 403, 410)
    m.write_macro(7, 1, 0)
    v = m.version
    m.clear_macro(7)
    assert m.read_macro(7).vacant and m.version == v + 1
    m.clear_macro(7)  # already vacant: nothing changes
    assert m.version == v + 1
    assert ew_of(lambda: m.clear_macro(34)) == EW.NUMBER
    assert ew_of(lambda: m.clear_macro(4001)) == EW.PROT
    assert ew_of(lambda: default_machine(read_only=True).clear_macro(1)) == EW.PROT
