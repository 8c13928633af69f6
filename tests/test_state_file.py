"""The state file of ``serve --state``: what a power cycle keeps and resets, the format's
round trip, its version, a machine file that changed, and damaged files."""

from __future__ import annotations

import hashlib
import os
from datetime import UTC, datetime
from decimal import Decimal
from pathlib import Path

import pytest

from focas_net.sim import Machine, MachineError, MacroRange, default_machine, statefile
from focas_net.sim.machine import MDI
from focas_net.sim.statefile import (
    STATE_VERSION,
    StateError,
    StateFile,
    apply_state,
    decode_state,
    encode_body,
    encode_record,
    encode_state,
    save_all,
    state_path,
)

PROGRAM = "O0123\n(KEPT)\nG0X1.\nM30\n%"


def _written() -> Machine:
    m = default_machine()
    s = m.new_session()
    m.set_panel(mode=MDI, pwe=1)  # PWE on: parameter writes open
    m.write_param(s, 3216, 0, 77)
    m.write_macro(500, Decimal("1.25"))
    m.write_macro(999, -3)
    m.write_macro(100, 9)  # #100-#199: a power-off clears them
    m.write_pmc("K", 3, b"\x5a")
    m.write_pmc("D", 10, b"\x01\x02\x03")
    m.write_pmc("R", 0, b"\xff")  # volatile
    m.path_programs().store(PROGRAM)
    m.write_macro(3901, 42)  # the parts count
    m.raise_alarm(0, 2, 1001, "KEPT IN HISTORY")
    return m


def _power_cycle(m: Machine, tmp_path: Path) -> Machine:
    state = StateFile(state_path(tmp_path, m.name))
    assert state.save(m)
    return StateFile(state.path).load(default_machine)


def test_a_power_cycle_keeps_the_nonvolatile_memory(tmp_path: Path) -> None:
    m = _power_cycle(_written(), tmp_path)
    assert m.read_param(3216, 0) == 77
    assert m.read_macro(500) == Decimal("1.25")
    assert m.read_macro(999) == Decimal(-3)
    assert m.read_pmc("K", 3, 1) == b"\x5a"
    assert m.read_pmc("D", 10, 3) == b"\x01\x02\x03"
    assert m.path_programs().text(123) == _written().path_programs().text(123)
    assert m.read_macro(3901) == 42
    assert [(e.alm_no, e.msg) for e in m.alarm_history()][:1] == [(1001, "KEPT IN HISTORY")]


def test_a_power_cycle_resets_the_volatile_memory(tmp_path: Path) -> None:
    m = _power_cycle(_written(), tmp_path)
    assert m.read_macro(100) is None
    assert m.read_pmc("R", 0, 1) == b"\x00"
    assert m.active_alarms() == []
    assert m.status().run == 0  # reset: nothing runs
    assert m.path_programs().main == 1  # the main program kept, at its head


def test_the_round_trip_is_exact() -> None:
    m = _written()
    data = encode_state(m)
    again = default_machine()
    apply_state(again, decode_state(data))
    assert encode_state(again) == data


def test_an_unchanged_machine_writes_nothing(tmp_path: Path) -> None:
    m = default_machine()
    state = StateFile(tmp_path / "m.state")
    m = state.load(lambda: m)
    assert not state.save(m)
    assert not state.path.exists()
    m.write_macro(501, 1)
    assert state.save(m)
    assert not state.save(m)
    assert state.writes == 1


def test_read_only_reads_and_writes_nothing(tmp_path: Path) -> None:
    path = state_path(tmp_path, "M")
    m = default_machine()
    m.write_macro(502, 5)
    StateFile(path).save(m)
    before = path.read_bytes()
    ro = StateFile(path, read_only=True)
    m2 = ro.load(default_machine)
    assert m2.read_macro(502) == 5
    m2.write_macro(502, 6)
    assert not ro.save(m2)
    assert path.read_bytes() == before


def test_a_newer_format_is_refused_clearly() -> None:
    data = encode_state(default_machine())
    newer = data.replace(
        f"focas-net-state {STATE_VERSION}\n".encode(),
        f"focas-net-state {STATE_VERSION + 1}\n".encode(),
    )
    with pytest.raises(StateError, match=rf"newer focas-net \(state format {STATE_VERSION + 1}"):
        decode_state(newer, "m.state")


@pytest.mark.parametrize("cut", [1, 10, 100, 1000])
def test_a_truncated_file_is_refused_clearly(cut: int) -> None:
    data = encode_state(_written())
    with pytest.raises(StateError, match=r"^m\.state: (truncated|not a focas-net)"):
        decode_state(data[:-cut] if cut < len(data) else b"", "m.state")


def test_a_corrupted_file_is_refused_clearly() -> None:
    data = bytearray(encode_state(_written()))
    data[-20] ^= 0x01
    with pytest.raises(StateError, match="checksum"):
        decode_state(bytes(data), "m.state")
    with pytest.raises(StateError, match="not a focas-net state file"):
        decode_state(b"\x00" * 50, "m.state")


def test_a_changed_machine_file_is_named(tmp_path: Path) -> None:
    path = state_path(tmp_path, "M")
    StateFile(path).save(_written())
    with pytest.raises(StateError) as caught:
        StateFile(path).load(lambda: Machine("M", axes=["X", "Z"]))
    text = str(caught.value)
    assert "machine file changed" in text and "the paths (kind, axes)" in text
    assert "XYZ" in text and "XZ" in text


def test_a_file_left_by_a_crash_mid_write_is_ignored(tmp_path: Path) -> None:
    path = state_path(tmp_path, "M")
    m = default_machine()
    m.write_macro(503, 3)
    StateFile(path).save(m)
    temp = path.with_name(path.name + ".tmp")
    temp.write_bytes(b"focas-net-state 1 99 half")
    m2 = StateFile(path).load(default_machine)
    assert m2.read_macro(503) == 3
    assert not temp.exists()


def test_the_alarm_history_keeps_its_stamps(tmp_path: Path) -> None:
    when = datetime(2026, 1, 2, 3, 4, 5, tzinfo=UTC)
    m = default_machine(clock=lambda: when)
    m.raise_alarm(0, 2, 7, "A")
    m2 = _power_cycle(m, tmp_path)
    assert m2.alarm_history()[0].occurred_at == when


def test_a_malformed_state_is_refused_whole(tmp_path: Path) -> None:
    m = default_machine()
    body = encode_body(m).replace(b'"macros":{}', b'"macros":{"100":"1"}')
    header = f"focas-net-state 1 {len(body)} {hashlib.sha256(body).hexdigest()}\n".encode()
    path = tmp_path / "m.state"
    path.write_bytes(header + body)
    with pytest.raises(StateError, match="#100: not kept"):
        StateFile(path).load(default_machine)
    with pytest.raises(MachineError):
        default_machine().write_pmc("X", 0, b"\x01")  # the machine's own checks stay


@pytest.mark.parametrize(
    ("body", "match"),
    [
        (b'{"machine":"m","shape":[],"kept":{}}', "malformed"),
        (b'{"machine":"m","shape":{},"kept":[]}', "malformed"),
        (b'{"machine":"m","shape":{},"kept":{}}', "the control class: not in the state"),
    ],
)
def test_a_state_of_no_shape_is_refused_in_one_short_line(
    tmp_path: Path, body: bytes, match: str
) -> None:
    path = tmp_path / "m.state"
    path.write_bytes(b"focas-net-state 2\n" + encode_record(body))
    with pytest.raises(StateError, match=match) as raised:
        StateFile(path).load(default_machine)
    assert "\n" not in str(raised.value) and len(str(raised.value)) < 600


def _format1(m: Machine) -> bytes:
    """``m``'s state as format 1 wrote it: one header line with the body's length and
    checksum, then the body."""
    body = encode_body(m)
    return f"focas-net-state 1 {len(body)} {hashlib.sha256(body).hexdigest()}\n".encode() + body


def test_an_older_format_loads_and_the_next_save_writes_the_current_one(tmp_path: Path) -> None:
    m = default_machine()
    m.write_macro(504, 4)
    path = tmp_path / "m.state"
    path.write_bytes(_format1(m))
    state = StateFile(path)
    again = state.load(default_machine)
    assert again.read_macro(504) == 4
    again.write_macro(504, 5)
    assert state.save(again)
    assert path.read_bytes().startswith(f"focas-net-state {STATE_VERSION}\n".encode())
    assert StateFile(path).load(default_machine).read_macro(504) == 5


def test_saves_append_records_and_the_last_whole_one_is_the_state(tmp_path: Path) -> None:
    path = tmp_path / "m.state"
    state = StateFile(path)
    m = state.load(default_machine)
    for n in range(3):
        m.write_macro(505, n)
        assert state.save(m)
    data = path.read_bytes()
    assert data.count(b"\n{") == 3  # three records
    assert decode_state(data)["kept"]["macros"]["505"] == "2"


@pytest.mark.parametrize("cut", [1, 30, 200])
def test_a_torn_last_record_is_ignored_and_replaced(tmp_path: Path, cut: int) -> None:
    path = tmp_path / "m.state"
    state = StateFile(path)
    m = state.load(default_machine)
    m.write_macro(506, 1)
    state.save(m)
    m.write_macro(506, 2)
    state.save(m)
    path.write_bytes(path.read_bytes()[:-cut])  # the second append cut short by a crash
    state = StateFile(path)
    again = state.load(default_machine)
    assert again.read_macro(506) == 1
    again.write_macro(506, 3)
    state.save(again)  # replaces the file: nothing is appended after the torn record
    assert StateFile(path).load(default_machine).read_macro(506) == 3


def test_a_damaged_record_before_the_last_is_corruption(tmp_path: Path) -> None:
    m = default_machine()
    first = encode_record(encode_body(m))
    m.write_macro(507, 1)
    second = encode_record(encode_body(m))
    damaged = bytearray(first)
    damaged[-10] ^= 0x01
    data = f"focas-net-state {STATE_VERSION}\n".encode() + bytes(damaged) + second
    with pytest.raises(StateError, match="records follow it"):
        decode_state(data, "m.state")


def test_a_long_journal_is_compacted_into_one_record(tmp_path: Path) -> None:
    path = tmp_path / "m.state"
    state = StateFile(path)
    m = state.load(default_machine)
    sizes = []
    for n in range(60):  # 60 records of about 24 KB pass the 1 MiB bound once
        m.write_macro(508, n)
        state.save(m)
        sizes.append(path.stat().st_size)
    assert max(sizes) <= 1 << 20 and sizes[-1] < max(sizes)
    assert StateFile(path).load(default_machine).read_macro(508) == 59


def test_a_failed_save_is_tried_again(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    path = tmp_path / "m.state"
    state = StateFile(path)
    m = state.load(default_machine)
    m.write_macro(509, 1)
    assert state.save(m)
    m.write_macro(509, 2)

    def full(fd: int) -> None:
        raise OSError(28, "No space left on device")

    with monkeypatch.context() as patched:
        patched.setattr(os, "fdatasync", full)
        with pytest.raises(OSError):
            state.save(m)
    assert state.save(m)  # not taken as saved: written now (the file replaced, whole)
    assert StateFile(path).load(default_machine).read_macro(509) == 2


def test_a_file_whose_folder_was_not_flushed_is_replaced_at_the_next_save(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    files = [StateFile(tmp_path / f"m{i}.state") for i in range(2)]
    states = [(state, state.load(default_machine)) for state in files]
    for i, (_, m) in enumerate(states):
        m.write_macro(510, i + 1)

    def cannot(folder: Path) -> None:
        raise OSError(5, "Input/output error")

    with monkeypatch.context() as patched:
        patched.setattr(statefile, "sync_folder", cannot)
        with pytest.raises(OSError):
            save_all(states)
    writes = [state.writes for state, _ in states]
    assert save_all(states) == 2  # unchanged since, but the renames were not durable
    assert [state.writes for state, _ in states] == [w + 1 for w in writes]
    for i, (state, _) in enumerate(states):
        assert StateFile(state.path).load(default_machine).read_macro(510) == i + 1


def test_a_tool_life_count_set_is_saved(tmp_path: Path) -> None:
    state = StateFile(tmp_path / "m.state")
    m = state.load(default_machine)
    state.save(m)
    count = m.tool_group(1).count
    m.set_tool_life_count(1, count + 2)
    assert state.save(m)  # the change is seen, not taken for none
    assert StateFile(state.path).load(default_machine).tool_group(1).count == count + 2


def test_a_two_path_machine_keeps_each_paths_offsets_and_programs(tmp_path: Path) -> None:
    from focas_net.sim import LifeTool, PathSpec, ToolGroup, ToolsSpec

    def build() -> Machine:
        return Machine(
            "lathe",
            paths=[PathSpec(("X1", "Z1"), kind="T"), PathSpec(("X2", "Z2", "C2"), kind="T")],
            tools={2: ToolsSpec(groups=[ToolGroup(1, 5, tools=[LifeTool(11), LifeTool(12)])])},
        )

    m = build()
    m.write_tool_offset(3, 1, 1234, path=1)
    m.write_tool_offset(4, 6, 3, path=2)
    m.write_work_offset(1, None, [10, 20, 30], path=2)
    m.set_tool_life_count(1, 4, path=2)
    m.path_programs(2).store("O0777\nG0X1.\nM30\n")
    path = tmp_path / "lathe.state"
    StateFile(path).save(m)
    again = StateFile(path).load(build)
    assert any(1234 in row for row in again.tool_offsets(1, 5, None, path=1))
    assert again.tool_offsets(1, 5, None, path=1) == m.tool_offsets(1, 5, None, path=1)
    assert again.tool_offsets(1, 5, None, path=2) == m.tool_offsets(1, 5, None, path=2)
    assert again.work_offsets(0, 6, None, path=2) == m.work_offsets(0, 6, None, path=2)
    assert again.tool_group(1, path=2) == m.tool_group(1, path=2)
    assert again.tool_group(1, path=2) != build().tool_group(1, path=2)
    assert 777 in [p.number for p in again.path_programs(2).directory()]
    assert 777 not in [p.number for p in again.path_programs(1).directory()]
    assert encode_state(again) == encode_state(m)


def test_the_timers_and_the_integrating_meter_are_kept(tmp_path: Path) -> None:
    from focas_net.sim.nc import ManualClock

    clock = ManualClock()
    m = default_machine(sim_clock=clock)
    m.set_panel(mode=MDI, pwe=1)
    s = m.new_session()
    m.write_param(s, 6752, 0, 90)  # operating time: 90 minutes
    m.write_param(s, 6756, 0, 7)  # the integrating meter: 7 minutes
    clock.advance(125.0)  # the power-on time runs
    path = tmp_path / "m.state"
    StateFile(path).save(m)
    again = StateFile(path).load(lambda: default_machine(sim_clock=ManualClock()))
    assert again.timer_ms(1) == m.timer_ms(1) // 1000 * 1000
    assert again.timer_ms(4) == 7 * 60_000
    assert again.timer_ms(0) == 125_000  # the power-on time integrates over power cycles


def test_a_variable_vacated_stays_vacant_whatever_the_machine_file_gives(tmp_path: Path) -> None:
    def build() -> Machine:
        return Machine(
            "M",
            macro_ranges=[MacroRange(500, 999)],
            macro_values={500: 5, 501: 6},
        )

    m = build()
    m.write_macro(500, None)
    path = tmp_path / "m.state"
    StateFile(path).save(m)
    again = StateFile(path).load(build)
    assert again.read_macro(500) is None and again.read_macro(501) == 6
