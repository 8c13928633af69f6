"""A confirming new-user pass over machine files, part programs and the examples: the cases it
found, each checked where the fix lives (the interpreter's M, S and T codes)."""

from __future__ import annotations

import pytest

from focas_net.sim import default_machine
from focas_net.sim.nc import Engine, ManualClock


@pytest.mark.parametrize(
    ("block", "alarm", "words"),
    [
        ("M123456789", 3, "M123456789: an M code has 1..8 digits"),
        ("T123456789", 3, "T123456789: a T code has 1..8 digits"),
        ("S123456", 3, "S123456: an S code has 1..5 digits"),
        ("#1 = 123456789\nM#1", 3, "M123456789: an M code has 1..8 digits"),
        ("M12345678 T12345678 S99999", None, ""),
    ],
)
def test_an_m_s_or_t_code_has_fanucs_default_digits(
    block: str, alarm: int | None, words: str
) -> None:
    """FANUC's controls allow 8 digits of an M and a T code and 5 of an S code by default
    (parameters 3030, 3032, 3031 left 0); more raised no alarm and ran the code. Now it is
    PS0003 (too many digits) naming the code, a literal or a macro's value alike."""
    clock = ManualClock()
    programs = (f"O0300\n{block}\nM30\n", "O0301\nG4 P5000\nM30\n")
    machine = default_machine(sim_clock=clock, programs=programs)
    machine.select_program(300)
    machine.cycle_start()
    clock.advance(5.0)
    active = machine.active_alarms()
    assert [(a.alm_type, a.alm_no) for a in active] == ([] if alarm is None else [(3, alarm)])
    if alarm is not None:
        assert machine.status().run == 1
    machine.reset()
    machine.select_program(301)
    machine.cycle_start()
    assert machine.active_alarms() == [] and machine.status().run == 3


@pytest.mark.parametrize(
    ("block", "words"),
    [
        ("M123456789", "PS0003 TOO MANY DIGITS"),
        ("M123456789", "M123456789: an M code has 1..8 digits"),
        ("T123456789", "T123456789: a T code has 1..8 digits"),
        ("S123456", "S123456: an S code has 1..5 digits"),
        ("#1 = 123456789\nM#1", "M123456789: an M code has 1..8 digits"),
    ],
)
def test_the_alarm_of_too_many_digits_names_the_code(block: str, words: str) -> None:
    clock = ManualClock()
    engine = Engine(clock)
    engine.store.store(f"O1\n{block}\nM30\n")
    engine.store.select(1)
    engine.cycle_start()
    clock.advance(5.0)
    assert engine.alarm is not None
    assert words in str(engine.alarm)
