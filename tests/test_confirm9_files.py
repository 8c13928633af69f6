"""A confirming new-user pass over machine files, part programs and the examples: the cases it
found, each checked where the fix lives (the program parser's words of a block)."""

from __future__ import annotations

import pytest

from focas_net.sim import default_machine
from focas_net.sim.nc import Engine, ManualClock

# -- one address given twice in a block ------------------------------------------------------


@pytest.mark.parametrize(
    ("block", "words"),
    [
        ("G0 X1. X2.", "X given twice in one block (X1. and X2.)"),
        ("M3 M4", "M given twice in one block (M3 and M4)"),
        ("M5 M9", "M given twice in one block (M5 and M9)"),
        ("G1 X1. F100 F200", "F given twice in one block (F100 and F200)"),
        ("S100 S200", "S given twice in one block (S100 and S200)"),
        ("T1 T2", "T given twice in one block (T1 and T2)"),
        ("#1 = 5\nG0 Y#1 Y[#1 + 1]", "Y given twice in one block (Y#1 and Y[#1+1])"),
    ],
)
def test_an_address_given_twice_in_a_block_is_ps5074(block: str, words: str) -> None:
    """FANUC's alarm table: PS5074 ADDRESS DUPLICATION ERROR, the same address specified two
    or more times in one block. The interpreter ran such a block (the last X won; M3 M4 ran
    both M codes) with no alarm."""
    clock = ManualClock()
    engine = Engine(clock)
    engine.store.store(f"O1\n{block}\nM30\n")
    engine.store.select(1)
    engine.cycle_start()
    clock.advance(5.0)
    assert engine.alarm is not None
    shown = str(engine.alarm)
    assert shown.startswith("PS5074 ADDRESS DUPLICATION ERROR (O0001")
    assert shown.endswith(words)


@pytest.mark.parametrize("block", ["G90 G0 G54 X1. Y1.", "G1 X1. Y1. F100 M8", "M98 P2 L1"])
def test_g_codes_and_distinct_addresses_in_one_block_run(block: str) -> None:
    clock = ManualClock()
    programs = (f"O0001\n{block}\nM30\n", "O0002\nM99\n")
    machine = default_machine(sim_clock=clock, programs=programs)
    machine.select_program(1)
    machine.cycle_start()
    clock.advance(60.0)
    assert machine.active_alarms() == []


def test_the_panel_alarm_of_a_duplicated_address_is_ps_5074() -> None:
    clock = ManualClock()
    machine = default_machine(sim_clock=clock, programs=("O0001\nN10 G0 X1. X2.\nM30\n",))
    machine.select_program(1)
    machine.cycle_start()
    clock.advance(5.0)
    [alarm] = machine.active_alarms()
    assert (alarm.alm_type, alarm.alm_no) == (3, 5074)
    assert "ADDRESS DUPLICATION ERROR" in alarm.msg
