"""A running machine's status between the ends of its actions: read without advancing the
engine, yet changing at the exact machine time an action ends, after a command, and at a
scenario event. Hand-stepped clock throughout."""

from __future__ import annotations

import math
from typing import Any

import pytest

from focas_net.adapters import PackedAdapter
from focas_net.protocol import COMMANDS, Command
from focas_net.sim import Machine, default_machine
from focas_net.sim.nc import CycleState, Engine, ManualClock, ProgramStore
from focas_net.sim.nc.scenario import Scenario, Schedule

#: An M3's 0.5 s, then X 0 -> 60 at F1200 (3.0 s), a one-second dwell, the end.
PROGRAM = """O0100
N10 G90 G21 G54 S1000 M3
N20 G1 X60. F1200
N30 G4 P1000
N40 M30
"""

#: Machine times of the ends of N10's M3, N20's motion and N30's dwell (at 100 %).
M3_END, MOVE_END, DWELL_END = 0.5, 3.5, 4.5

# run, motion of ODBST
STRT, HOLD = 3, 2
MOTION, DWELL, NONE = 1, 2, 0


def engine(clock: ManualClock) -> Engine:
    store = ProgramStore()
    store.select(store.store(PROGRAM).number)
    return Engine(clock, store=store)


def test_steady_until_is_the_end_of_the_current_action() -> None:
    clock = ManualClock()
    e = engine(clock)
    assert e.steady_until() == math.inf  # reset: time changes nothing
    e.cycle_start()
    assert e.steady_until() == pytest.approx(M3_END)
    clock.advance(1.0)
    assert e.steady_until() == pytest.approx(MOVE_END)
    clock.advance(3.0)
    assert e.steady_until() == pytest.approx(DWELL_END)


def test_the_overrides_and_the_commands_move_it_and_the_revision() -> None:
    clock = ManualClock()
    e = engine(clock)
    e.cycle_start()
    clock.advance(2.0)  # X half way: 30 mm left at 1200 mm/min
    revision = e.revision
    e.feed_override = 50  # 30 mm at 600 mm/min: 3 s more
    assert e.revision > revision
    assert e.steady_until() == pytest.approx(5.0)
    e.set_feed_override(0)
    assert e.steady_until() == math.inf  # held by the override: only a command ends it
    e.set_feed_override(100)
    assert e.steady_until() == pytest.approx(MOVE_END)
    revision = e.revision
    e.feed_hold()
    assert e.revision > revision and e.steady_until() == math.inf
    with pytest.raises(ValueError, match=r"feed override is 0\.\.254 %, got 300"):
        e.feed_override = 300
    assert e.feed_override == 100


def status(adapter: PackedAdapter, m: Machine) -> Any:
    """ODBST as the packed protocol answers it (through the adapter's memo)."""
    raw = adapter.answer(m.new_session(), Command.RDCNCSTAT, b"")
    return COMMANDS[Command.RDCNCSTAT].response.decode(raw)


def running(clock: ManualClock) -> tuple[Machine, PackedAdapter]:
    m = default_machine(sim_clock=clock, programs=(PROGRAM,))
    m.cycle_start()
    clock.advance(1.0)
    return m, PackedAdapter(m)


def test_status_reads_between_action_ends_leave_the_engine_alone(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    clock = ManualClock()
    m, adapter = running(clock)
    assert status(adapter, m).motion == MOTION
    advances = 0
    advance = Engine.advance

    def counting(self: Engine) -> None:
        nonlocal advances
        advances += 1
        advance(self)

    monkeypatch.setattr(Engine, "advance", counting)
    version = m.status_version
    for _ in range(20):  # 1.0 .. 3.0 s: X still moving
        clock.advance(0.1)
        assert status(adapter, m).motion == MOTION
    assert advances == 0
    assert m.status_version == version


def test_the_status_changes_at_the_exact_time_an_action_ends() -> None:
    clock = ManualClock()
    m, adapter = running(clock)
    clock.advance(MOVE_END - 1.0 - 1e-6)
    assert (status(adapter, m).run, status(adapter, m).motion) == (STRT, MOTION)
    clock.advance(1e-6)
    assert status(adapter, m).motion == DWELL
    clock.advance(DWELL_END - MOVE_END)
    assert status(adapter, m).motion == NONE  # M30: the cycle ended


def test_an_override_set_on_the_engine_itself_moves_the_change() -> None:
    clock = ManualClock()
    m, adapter = running(clock)
    clock.advance(1.0)  # t = 2.0, X half way
    assert status(adapter, m).motion == MOTION
    m.engine.feed_override = 50  # not through the machine: 3 s more
    clock.advance(MOVE_END - 2.0)
    assert status(adapter, m).motion == MOTION  # the old end went by: still moving
    clock.advance(5.0 - MOVE_END)
    assert status(adapter, m).motion == DWELL


def test_a_command_between_action_ends_shows_at_once() -> None:
    clock = ManualClock()
    m, adapter = running(clock)
    assert status(adapter, m).run == STRT
    m.feed_hold()
    assert (status(adapter, m).run, status(adapter, m).motion) == (HOLD, NONE)
    clock.advance(10.0)
    assert status(adapter, m).run == HOLD
    m.cycle_start()
    assert (status(adapter, m).run, status(adapter, m).motion) == (STRT, MOTION)
    clock.advance(MOVE_END - 1.0)  # the hold took no time off the motion: 2.5 s were left
    assert status(adapter, m).motion == DWELL


def test_a_scenario_event_between_action_ends_changes_the_status_at_its_time() -> None:
    clock = ManualClock()
    long_move = "O0100\nN10 G1 X500. F100\nN20 M30\n"  # 300 s of motion
    m = default_machine(sim_clock=clock, programs=(long_move,))
    scenario = Scenario(
        seed=3, phase=0.0, pause_rate=600.0, pause_time=5.0, tool_rate=0, alarm_rate=0
    )
    m.start_scenario(scenario)
    adapter = PackedAdapter(m)
    assert status(adapter, m).run == STRT
    due = Schedule(scenario, 0.0, len(m.axes)).next_time  # the same seed draws the same pause
    assert 0 < due < 300
    clock.advance(due - 1e-6)
    assert status(adapter, m).run == STRT
    clock.advance(2e-6)
    assert status(adapter, m).run == HOLD
    assert m.engine.state is CycleState.HOLD
