"""A confirming new-user pass over machine files, part programs and the examples: the cases it
found, each checked where the fix lives (the program parser's words of a block)."""

from __future__ import annotations

from pathlib import Path

import pytest
from cli_support import fails
from support import block_run

from focas_net.cli import EXIT_USAGE
from focas_net.sim import MachineFileError, default_machine, load_machine
from focas_net.sim.nc import Engine, ManualClock
from focas_net.sim.nc.actions import Step

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
    engine = block_run(block)
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


# -- an offset value of the other machine type -----------------------------------------------


@pytest.mark.parametrize(
    ("kind", "name", "words"),
    [
        (
            "M",
            "x_wear",
            "tool offset 1: x_wear is a lathe's offset, not a machining centre's (kind M): "
            "radius_wear, radius_geometry, length_wear, length_geometry",
        ),
        (
            "T",
            "radius_wear",
            "tool offset 1: radius_wear is a machining centre's offset, not a lathe's (kind T): "
            "x_wear, x_geometry, z_wear, z_geometry, nose_wear, nose_geometry, tip",
        ),
        (
            "M",
            "tip",
            "tool offset 1: tip is a lathe's offset, not a machining centre's (kind M): "
            "radius_wear, radius_geometry, length_wear, length_geometry",
        ),
    ],
)
def test_an_offset_of_the_other_machine_type_names_the_ones_it_has(
    tmp_path: Path, kind: str, name: str, words: str
) -> None:
    """It said `M offsets have no 'x_wear'`: a letter for the machine and no word of the
    offsets a machining centre has."""
    path = tmp_path / "m.toml"
    path.write_text(
        f'[machine]\nname = "M"\n[[path]]\nkind = "{kind}"\n'
        f'axes = ["X", "Z"]\n[[tools]]\n[[tools.offset]]\nnumber = 1\n{name} = 1\n',
        encoding="utf-8",
    )
    with pytest.raises(MachineFileError) as refused:
        load_machine(path)
    assert str(refused.value).endswith(f"m.toml: tools[0].offset[0].{name}: {words}")


# -- a loop of dwells of no time -------------------------------------------------------------


@pytest.mark.parametrize("dwell", ["G4 P0", "G4 X0", "G4 X0.", "G4 P0\nG4 X0"])
def test_a_loop_of_zero_dwells_takes_the_busy_block_time(dwell: str) -> None:
    """`G4 P0` then `M99` looped in no machine time: each dwell of 0 s restarted the count of
    blocks of no time, so the busy block time (1 ms a block after 10,000 of them) never
    applied, and one read of the machine stepped the program millions of times (20 s of CPU,
    the server's answers held meanwhile)."""
    clock = ManualClock()
    engine = Engine(clock)
    engine.store.store(f"O1\n{dwell}\nM99\n")
    engine.store.select(1)
    steps = 0
    step = engine.interpreter.step

    def counted() -> Step:
        nonlocal steps
        steps += 1
        if steps > 100_000:
            raise AssertionError("the loop of no time ran on")
        return step()

    engine.interpreter.step = counted  # type: ignore[method-assign]
    engine.cycle_start()
    clock.advance(1.0)
    assert engine.alarm is None
    settings = engine.settings
    bound = 2 * settings.zero_time_blocks + 2 * round(1.0 / settings.busy_block_time)
    assert steps <= bound


# -- what an alarm's detail names -------------------------------------------------------------


@pytest.mark.parametrize(
    ("block", "words"),
    [
        # the repetitions in front of four digits: the detail names P as written
        ("M98 P12345678", "M98 P12345678: no program O5678 (1234 times)"),
        ("M98 P20003", "M98 P20003: no program O0003 (2 times)"),
        ("M98 P3", "M98 P3: no program O0003"),
        # a canned cycle is PS0010 (its G code), as docs/machine-file.md says, not its Q
        ("G83 X1. Y1. Z-1. R1. Q1. F100", "PS0010 IMPROPER G-CODE (O0001): G83"),
        ("G73 X1. Z-1. Q0.5 F100", "PS0010 IMPROPER G-CODE (O0001): G73"),
        # Q names no axis: the detail does not offer the axes in its place
        (
            "G0 X1. Q1.",
            "PS0009 ILLEGAL ADDRESS INPUT (O0001): address Q: the interpreter reads no Q",
        ),
        ("G0 A1.", "PS0009 ILLEGAL ADDRESS INPUT (O0001): address A (axes are XYZ)"),
    ],
)
def test_an_alarm_names_the_word_as_written_and_the_code_refused(block: str, words: str) -> None:
    """`M98 P12345678` was named `M98 P5678`; `G83 ... Q1.` raised PS0009 `address Q (axes
    are XYZ)` as if Q were a missing axis, where the docs say a canned cycle raises PS0010."""
    engine = block_run(block)
    assert str(engine.alarm).endswith(words)


# -- an option of the command before an action not given --------------------------------------


@pytest.mark.parametrize(
    ("argv", "words"),
    [
        (
            ("macro", "--port", "1234", "500"),
            "focas-net macro: error: --port is an option of the command: give it after the "
            "command (focas-net macro get|set|clear --port ...)",
        ),
        (
            ("param", "--port=1234", "6711"),
            "focas-net param: error: --port is an option of the command: give it after the "
            "command (focas-net param get|set --port ...)",
        ),
        (
            ("--host", "cnc7"),
            "focas-net: error: --host is an option of the command: give it after the command "
            "(focas-net COMMAND --host ...)",
        ),
        # an option no command has is left to argparse's own words
        (("macro", "--bogus", "500"), "focas-net macro: error: argument ACTION: invalid choice"),
    ],
)
async def test_an_option_before_a_missing_action_is_named(
    argv: tuple[str, ...], words: str
) -> None:
    """`focas-net macro --port 1234 500` (the action forgotten) said `argument ACTION:
    invalid choice: '1234'`: the port's value named as the action the user never typed."""
    line = await fails(EXIT_USAGE, *argv, prefix="focas-net")
    assert line.startswith(words), line
