"""Machines at work on their own (scenarios) and the loads of cutting, with a hand-stepped
clock."""

from __future__ import annotations

import argparse
from dataclasses import replace
from typing import Any

import pytest

from focas_net.cli import _fleet, serve
from focas_net.sim import Machine, MachineError, MachineFileError, default_machine
from focas_net.sim.machinefile import machine_from_dict
from focas_net.sim.nc import (
    DEFAULT_SCENARIO,
    SCENARIO_ALARMS,
    CycleState,
    ManualClock,
    Scenario,
    ScenarioEvent,
    Schedule,
    fleet_seed,
)
from focas_net.sim.nc.scenario import noise

#: One part: the spindle on, 20 mm of cutting at F1200 (1 s), a rapid back (0.05 s), M30.
PART = "O0010\nN10 S3000 M3\nN20 G1 X20. F1200\nN30 G0 X0\nN40 M30\n"
#: No events at all: plain production.
CALM = Scenario(phase=0.0, pause_rate=0.0, tool_rate=0.0, alarm_rate=0.0)


def machine_with(clock: ManualClock, *programs: str) -> Machine:
    return default_machine(sim_clock=clock, programs=programs or (PART,))


def first(scenario: Scenario, kind: str, origin: float = 0.0) -> ScenarioEvent:
    """The first event of ``kind`` the scenario has, from its own schedule."""
    schedule = Schedule(scenario, origin, 3)
    for _ in range(10_000):
        event = schedule.pop()
        if event.kind == kind:
            return event
    pytest.fail(f"no {kind} event in 10000")


def trace(machine: Machine, clock: ManualClock, step: float, until: float) -> list[Any]:
    """What a collector sees at every ``step`` seconds up to ``until``."""
    seen: list[Any] = []
    for _ in range(round(until / step)):
        clock.advance(step)
        st = machine.status()
        m = machine.motion
        seen.append((clock.now(), st.run, st.alarm, m.machine, m.feed, machine.parts_counts()))
    return seen


# -- the schedule ---------------------------------------------------------------------------


def test_the_same_seed_gives_the_same_events_and_another_seed_others() -> None:
    scenario = replace(DEFAULT_SCENARIO, seed=11)
    one = Schedule(scenario, 0.0, 3).until(100 * 3600.0)
    again = Schedule(scenario, 0.0, 3).until(100 * 3600.0)
    other = Schedule(replace(scenario, seed=12), 0.0, 3).until(100 * 3600.0)
    assert one == again
    assert len(one) > 100
    assert [e.time for e in one] == sorted(e.time for e in one)
    assert one != other


def test_each_kind_keeps_its_rate_and_mean_time_over_many_hours() -> None:
    scenario = Scenario(seed=3, pause_rate=4.0, pause_time=60.0, tool_rate=1.0, alarm_rate=0.5)
    hours = 2000.0
    events = Schedule(scenario, 0.0, 3).until(hours * 3600.0)
    for kind, rate in (("pause", 4.0), ("tool", 1.0), ("alarm", 0.5)):
        count = sum(1 for e in events if e.kind == kind)
        assert 0.85 * rate * hours < count < 1.15 * rate * hours, kind
    pauses = [e.duration for e in events if e.kind == "pause"]
    assert 50.0 < sum(pauses) / len(pauses) < 70.0
    assert min(pauses) >= 5.0
    alarms = {e.alarm for e in events if e.kind == "alarm"}
    assert alarms == set(range(len(SCENARIO_ALARMS)))
    assert {e.axis for e in events if e.kind == "alarm" and SCENARIO_ALARMS[e.alarm].per_axis} == {
        1,
        2,
        3,
    }


def test_a_rate_of_zero_has_no_events_and_one_kind_does_not_move_another() -> None:
    assert Schedule(CALM, 0.0).until(1e9) == []
    alone = Schedule(replace(CALM, pause_rate=5.0, seed=4), 0.0).until(50 * 3600.0)
    mixed = Schedule(replace(DEFAULT_SCENARIO, pause_rate=5.0, seed=4), 0.0).until(50 * 3600.0)
    assert alone and [e for e in mixed if e.kind == "pause"] == alone


def test_every_machine_of_a_fleet_has_a_seed_and_a_phase_of_its_own() -> None:
    seeds = [fleet_seed(0, i) for i in range(200)]
    assert len(set(seeds)) == 200
    assert seeds == [fleet_seed(0, i) for i in range(200)]
    assert fleet_seed(1, 0) != fleet_seed(0, 0)
    phases = [replace(DEFAULT_SCENARIO, seed=s).start_phase() for s in seeds]
    assert len(set(phases)) == 200
    assert all(0.0 <= p < DEFAULT_SCENARIO.phase_span for p in phases)
    assert replace(DEFAULT_SCENARIO, phase=7.5).start_phase() == 7.5


@pytest.mark.parametrize(
    ("given", "message"),
    [
        ({"parts": -1}, "parts is a count >= 0 or 'required', got -1"),
        ({"parts": "some"}, "parts is a count >= 0 or 'required', got 'some'"),
        ({"seed": -2}, "seed is an integer 0..9223372036854775807, got -2"),
        ({"pause_rate": -1.0}, "pause_rate is a finite number >= 0, got -1.0"),
        ({"alarm_time": float("nan")}, "alarm_time is a finite number >= 0, got nan"),
        ({"phase": float("inf")}, "phase is a finite number >= 0, got inf"),
    ],
)
def test_a_scenario_refuses_bad_values_naming_them(given: dict[str, Any], message: str) -> None:
    with pytest.raises(ValueError, match=message):
        Scenario(**given)


# -- a machine running its scenario ---------------------------------------------------------


def test_the_same_seed_runs_the_same_way_however_often_the_machine_is_read() -> None:
    scenario = Scenario(
        seed=5,
        phase=3.0,
        pause_rate=20.0,
        pause_time=30.0,
        tool_rate=10.0,
        tool_time=40.0,
        alarm_rate=6.0,
        alarm_time=60.0,
    )
    often, seldom = ManualClock(), ManualClock()
    a, b = machine_with(often), machine_with(seldom)
    a.start_scenario(scenario)
    b.start_scenario(scenario)
    seen_often = trace(a, often, 0.5, 1800.0)[11::12]  # every 6 s, read every 0.5 s
    seen_seldom = trace(b, seldom, 6.0, 1800.0)
    assert [s[:3] + s[4:] for s in seen_often] == [s[:3] + s[4:] for s in seen_seldom]
    for x, y in zip(seen_often, seen_seldom, strict=True):  # positions to the micrometre
        assert all(abs(p - q) <= 1 for p, q in zip(x[3], y[3], strict=True))
    assert [e for e in a.scenario_log] == [e for e in b.scenario_log]
    runs = {s[1] for s in seen_seldom}
    assert runs == {1, 2, 3}  # STOP (tool changes, alarms), HOLD (pauses), STRT
    clock = ManualClock()
    other = machine_with(clock)
    other.start_scenario(replace(scenario, seed=6))
    assert trace(other, clock, 6.0, 1800.0) != seen_seldom
    assert list(other.scenario_log) != list(a.scenario_log)


def test_an_operator_pause_holds_the_feed_and_cycle_start_follows_it() -> None:
    scenario = replace(CALM, seed=2, pause_rate=30.0)
    pause = first(scenario, "pause")
    clock = ManualClock()
    machine = machine_with(clock)
    machine.start_scenario(scenario)
    clock.set(pause.time + 0.01)
    assert machine.status().run == 2  # HOLD
    held = machine.motion.machine
    assert machine.motion.feed == 0
    clock.set(pause.end - 0.01)
    assert machine.status().run == 2
    assert machine.motion.machine == held
    clock.set(pause.end + 0.01)
    assert machine.status().run == 3
    assert (pause, "begin") in machine.scenario_log
    assert (pause, "end") in machine.scenario_log


def test_a_tool_change_wait_stops_the_cycle_until_the_operator_is_done() -> None:
    scenario = replace(CALM, seed=8, tool_rate=30.0)
    wait = first(scenario, "tool")
    clock = ManualClock()
    machine = machine_with(clock)
    machine.start_scenario(scenario)
    clock.set(wait.time + 0.01)
    parts = machine.parts_counts()
    assert machine.status().run == 1  # STOP, no alarm
    assert machine.status().alarm == 0
    clock.set(wait.end - 0.01)
    assert machine.parts_counts() == parts
    clock.set(wait.end + 5.0)
    assert machine.status().run == 3
    assert machine.parts_counts()[0] > parts[0]


def test_an_alarm_stops_the_cycle_a_repair_clears_it_and_parts_keep_counting() -> None:
    scenario = replace(CALM, seed=9, alarm_rate=3.0, alarm_time=60.0)
    schedule = Schedule(scenario, 0.0, 3)
    alarm, following = schedule.pop(), schedule.pop()
    assert following.time > alarm.end + 10.0  # the repair is over before the next alarm
    spec = SCENARIO_ALARMS[alarm.alarm]
    clock = ManualClock()
    machine = machine_with(clock)
    machine.start_scenario(scenario)
    clock.set(alarm.time + 0.01)
    status = machine.status()
    assert (status.run, status.alarm) == (1, 1)
    active = machine.active_alarms()
    assert [(a.axis_no, a.alm_type, a.alm_no, a.msg) for a in active] == [
        (alarm.axis, spec.alm_type, spec.alm_no, spec.message)
    ]
    with pytest.raises(MachineError, match="alarm"):
        machine.cycle_start()  # an operator cannot go on before the repair
    parts = machine.parts_counts()[0]
    clock.set(alarm.end - 0.01)
    assert machine.status().alarm == 1
    assert machine.parts_counts()[0] == parts
    clock.set(alarm.end + 10.0)
    status = machine.status()
    assert (status.run, status.alarm) == (3, 0)
    assert machine.parts_counts()[0] > parts
    assert machine.alarm_history()[0].alm_no == spec.alm_no


def test_n_parts_then_the_machine_stops_in_reset() -> None:
    clock = ManualClock()
    machine = machine_with(clock)
    machine.start_scenario(replace(CALM, parts=3))
    clock.advance(600.0)
    assert machine.parts_counts() == (3, 3)
    assert machine.status().run == 0
    assert not machine.scenario_running
    clock.advance(600.0)
    assert machine.parts_counts() == (3, 3)


def test_parts_required_stops_production_at_parameter_6713() -> None:
    clock = ManualClock()
    machine = machine_with(clock)
    item = machine.param_item(6713)
    assert item is not None
    item.values[0] = 4
    machine.start_scenario(replace(CALM, parts="required"))
    clock.advance(600.0)
    assert machine.parts_counts()[0] == 4
    assert machine.engine.state is CycleState.RESET


def test_a_phase_puts_the_machine_that_far_into_its_production() -> None:
    clock = ManualClock()
    early, late = machine_with(clock), machine_with(clock)
    early.start_scenario(replace(CALM, phase=0.0))
    late.start_scenario(replace(CALM, phase=5.5))
    assert early.parts_counts()[0] == 0
    clock.advance(5.5)  # the early one is where the late one was when it started
    assert early.parts_counts()[0] > 0
    ahead = ManualClock()
    reference = machine_with(ahead)
    reference.start_scenario(replace(CALM, phase=11.0))
    assert late.parts_counts() == reference.parts_counts()
    assert late.motion.machine == reference.motion.machine
    assert late.timer(1) == pytest.approx(11.0)
    assert late.timer(0) == pytest.approx(11.0)  # powered on since then


def test_a_scenario_starts_only_where_cycle_start_would() -> None:
    machine = machine_with(ManualClock())
    machine.set_panel(mode=0)
    with pytest.raises(MachineError, match="the mode is MDI, not MEM"):
        machine.start_scenario(CALM)
    machine.set_panel(mode=1, emergency=1)
    with pytest.raises(MachineError, match="emergency stop"):
        machine.start_scenario(CALM)


def test_a_hand_reset_stops_production_and_cycle_start_resumes_it() -> None:
    clock = ManualClock()
    machine = machine_with(clock)
    machine.start_scenario(CALM)
    clock.advance(5.0)
    machine.reset()
    parts = machine.parts_counts()
    clock.advance(5.0)
    assert machine.parts_counts() == parts
    machine.cycle_start()
    clock.advance(5.0)
    assert machine.parts_counts()[0] > parts[0]
    machine.stop_scenario()
    assert not machine.scenario_running


def test_an_idle_machine_without_a_scenario_reads_no_clock() -> None:
    class Counting(ManualClock):
        calls = 0

        def now(self) -> float:
            Counting.calls += 1
            return super().now()

    clock = Counting()
    machine = machine_with(clock)
    before = Counting.calls
    for _ in range(10):
        machine.status()
        machine.motion_version  # noqa: B018 - the counter read is the point
    assert Counting.calls == before


# -- loads ----------------------------------------------------------------------------------


def test_loads_are_near_zero_idle_and_rise_while_cutting() -> None:
    clock = ManualClock()
    machine = machine_with(clock)
    assert machine.spindle_loads() == (0,)
    assert machine.servo_loads() == (0, 0, 0)
    machine.cycle_start()
    clock.advance(0.5 + 0.5)  # the spindle's M3, then half way through the G1 along X
    cutting = machine.spindle_loads()[0]
    x, y, z = machine.servo_loads()
    assert cutting > 20
    assert x > 10 and y == z == 0
    clock.advance(0.52)  # the rapid back: the spindle turns, nothing cuts
    assert machine.engine.motion.value == "motion" and not machine.engine.cutting
    assert machine.spindle_loads()[0] <= 5
    assert machine.servo_loads()[0] > 0
    clock.advance(0.5)  # the end, spindle stopped by M30
    assert machine.spindle_loads() == (0,)
    assert machine.servo_loads() == (0, 0, 0)


def test_loads_grow_with_the_feed() -> None:
    slow_part = PART.replace("F1200", "F400")
    fast_part = PART.replace("F1200", "F3000")
    clock = ManualClock()
    slow, fast = machine_with(clock, slow_part), machine_with(clock, fast_part)
    slow.cycle_start()
    fast.cycle_start()
    clock.advance(0.7)  # both cutting (the fast one takes 0.4 s)
    assert fast.spindle_loads()[0] > slow.spindle_loads()[0] + 20
    assert fast.servo_loads()[0] > slow.servo_loads()[0]


def test_loads_are_the_same_at_the_same_machine_time_and_wiggle_over_time() -> None:
    clock = ManualClock()
    long_cut = "O0011\nS2000 M3\nG1 X80. F600\nM30\n"  # 8 s of cutting
    a, b = machine_with(clock, long_cut), machine_with(clock, long_cut)
    a.seed = b.seed = 77
    a.cycle_start()
    b.cycle_start()
    clock.advance(1.0)  # past the spindle's start: cutting from here
    seen = []
    for _ in range(20):
        clock.advance(0.3)
        assert a.spindle_loads() == a.spindle_loads() == b.spindle_loads()
        assert a.servo_loads() == b.servo_loads()
        seen.append(a.spindle_loads()[0])
    assert len(set(seen)) > 1
    assert max(seen) - min(seen) <= 10  # a noise, not a jump
    assert noise(77, 1.0, 0) == noise(77, 1.1, 0) != noise(78, 1.0, 0)


# -- the machine file and serve ---------------------------------------------------------------


def _file(run: dict[str, Any]) -> dict[str, Any]:
    return {"machine": {"name": "m", "axes": ["X", "Y", "Z"]}, "run": run}


def test_a_machine_file_run_section_gives_the_machine_its_scenario() -> None:
    machine = machine_from_dict(
        _file({"parts": 12, "seed": 4, "phase": 0, "pause_rate": 2, "alarm_time": 600.5}),
        sim_clock=ManualClock(),
    )
    assert machine.scenario == replace(
        DEFAULT_SCENARIO, parts=12, seed=4, phase=0.0, pause_rate=2.0, alarm_time=600.5
    )
    required = machine_from_dict(_file({"parts": "required"}), sim_clock=ManualClock())
    assert required.scenario is not None and required.scenario.parts == "required"


@pytest.mark.parametrize(
    ("run", "message"),
    [
        ({"parts": -1}, r"run\.parts: -1 is outside 0\.\.2147483647"),
        ({"parts": "all"}, r"run\.parts: must be a count >= 0 or \"required\", got 'all'"),
        ({"seed": "x"}, r"run\.seed: must be an integer, got a string \('x'\)"),
        ({"pause_rate": -0.5}, r"run\.pause_rate: -0\.5 is outside 0\.\.31536000"),
        ({"tool_time": True}, r"run\.tool_time: must be a number, got a boolean \(true\)"),
        ({"alarms": 1}, r"run\.alarms: unknown key \(expected one of: parts, seed, phase"),
    ],
)
def test_a_bad_run_section_names_the_key(run: dict[str, Any], message: str) -> None:
    with pytest.raises(MachineFileError, match=message):
        machine_from_dict(_file(run))


def _parse(*argv: str) -> argparse.Namespace:
    parser = argparse.ArgumentParser()
    serve.register(parser.add_subparsers())
    return parser.parse_args(["serve", *argv])


def test_serve_run_gives_every_machine_of_the_fleet_its_own_seed() -> None:
    machines = _fleet.build_machines(_parse("--fleet", "4", "--run", "--seed", "9"))
    assert all(m.scenario_running for m in machines)
    assert [m.seed for m in machines] == [fleet_seed(9, i) for i in range(4)]
    again = _fleet.build_machines(_parse("--fleet", "4", "--run", "--seed", "9"))
    assert [m.seed for m in again] == [m.seed for m in machines]
    default = _fleet.build_machines(_parse("--fleet", "2", "--run"))
    assert [m.seed for m in default] == [fleet_seed(serve.DEFAULT_SEED, i) for i in range(2)]


def test_serve_run_parts_and_downtime_shape_the_scenario() -> None:
    (machine,) = _fleet.build_machines(_parse("--run", "--run-parts", "2", "--downtime", "0"))
    scenario = machine.active_scenario
    assert scenario is not None
    assert scenario.parts == 2
    assert (scenario.pause_rate, scenario.tool_rate, scenario.alarm_rate) == (0.0, 0.0, 0.0)


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (("--seed", "3"), "argument --seed: the machines do not run"),
        (("--run-parts", "5"), "argument --run-parts: the machines do not run"),
        (("--downtime", "2"), "argument --downtime: the machines do not run"),
    ],
)
def test_run_options_without_a_running_machine_are_refused(
    argv: tuple[str, ...], message: str
) -> None:
    with pytest.raises(_fleet.ConfigError, match=message):
        _fleet.build_machines(_parse(*argv))


@pytest.mark.parametrize(
    ("argv", "option"),
    [
        (("--seed", "-1"), "--seed"),
        (("--run-parts", "x"), "--run-parts"),
        (("--downtime", "101"), "--downtime"),
        (("--downtime", "nan"), "--downtime"),
    ],
)
def test_bad_run_option_values_are_usage_errors(
    argv: tuple[str, ...], option: str, capsys: pytest.CaptureFixture[str]
) -> None:
    with pytest.raises(SystemExit) as exc:
        _parse("--run", *argv)
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert option in err and argv[1] in err


def test_a_machine_started_with_a_phase_is_where_one_started_that_long_before_is() -> None:
    scenario = Scenario(
        seed=21, phase=0.0, pause_rate=30.0, pause_time=20.0, tool_rate=15.0, tool_time=20.0
    )
    clock = ManualClock()
    before = machine_with(clock)
    before.start_scenario(scenario)
    clock.advance(600.0)
    now = machine_with(clock)
    now.start_scenario(replace(scenario, phase=600.0))  # the same schedule: from machine time 0
    for _ in range(60):
        assert (now.status(), now.motion.machine, now.parts_counts()) == (
            before.status(),
            before.motion.machine,
            before.parts_counts(),
        )
        clock.advance(7.0)
    assert list(now.scenario_log) == list(before.scenario_log)
    assert len(before.scenario_log) > 10


RUN_FILE = """
[machine]
name = "cell"
axes = ["X", "Y", "Z"]

[panel]
mode = "{mode}"

[[program]]
text = "O0010\\nN10 S3000 M3\\nN20 G1 X20. F1200\\nN30 G0 X0\\nN40 M30\\n"

[run]
seed = 31
parts = 7
phase = 0
"""


def test_a_machine_file_with_run_runs_when_served_without_the_run_option(
    tmp_path: Any,
) -> None:
    path = tmp_path / "cell.toml"
    path.write_text(RUN_FILE.format(mode="MEM"), encoding="utf-8")
    machines = _fleet.build_machines(_parse("--machine", str(path), "--fleet", "2"))
    assert [m.seed for m in machines] == [fleet_seed(31, 0), fleet_seed(31, 1)]
    for m in machines:
        scenario = m.active_scenario
        assert scenario is not None and scenario.parts == 7
    (other,) = _fleet.build_machines(_parse("--machine", str(path), "--seed", "2"))
    assert other.seed == fleet_seed(2, 0)


def test_a_run_section_the_machine_cannot_start_names_the_file_and_the_machine(
    tmp_path: Any,
) -> None:
    path = tmp_path / "cell.toml"
    path.write_text(RUN_FILE.format(mode="EDIT"), encoding="utf-8")
    with pytest.raises(
        _fleet.ConfigError, match=r"cell\.toml: \[run\]: cell: .*the mode is EDIT, not MEM"
    ):
        _fleet.build_machines(_parse("--machine", str(path)))
