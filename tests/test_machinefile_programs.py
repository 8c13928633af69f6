"""``[[program]]`` entries of a machine file, and the built-in machine's demo program."""

from __future__ import annotations

from pathlib import Path

import pytest

from focas_net.sim import DEMO_PROGRAM, MachineFileError, default_machine, load_machine
from focas_net.sim.nc import CycleState, ManualClock

HEAD = """
[machine]
name = "with-programs"
axes = ["X", "Y", "Z"]
"""


def test_inline_and_file_programs_and_the_main(tmp_path: Path) -> None:
    (tmp_path / "parts").mkdir()
    (tmp_path / "parts" / "o2000.nc").write_text("%\nO2000 (FROM FILE)\nG1 X1. F100\nM30\n%\n")
    path = tmp_path / "m.toml"
    path.write_text(
        HEAD
        + """
[[program]]
text = "O1000 (INLINE)\\nG4 P100\\nM30\\n"

[[program]]
file = "parts/o2000.nc"
main = true
"""
    )
    clock = ManualClock()
    machine = load_machine(path, sim_clock=clock)
    assert [(p.number, p.name) for p in machine.programs.directory()] == [
        (1000, "INLINE"),
        (2000, "FROM FILE"),
    ]
    assert machine.programs.main == 2000
    machine.cycle_start()
    clock.advance(0.3)  # 1 mm at F100 takes 0.6 s
    assert machine.motion.absolute[0] == 500


def test_the_first_program_is_the_main_by_default(tmp_path: Path) -> None:
    path = tmp_path / "m.toml"
    path.write_text(HEAD + '[[program]]\ntext = "O7\\nM30"\n[[program]]\ntext = "O3\\nM30"\n')
    assert load_machine(path).programs.main == 7


@pytest.mark.parametrize(
    ("entries", "key", "problem"),
    [
        ('[[program]]\nmain = true\n', "program[0]", "either text"),
        ('[[program]]\ntext = "O1\\nM30"\nfile = "x.nc"\n', "program[0]", "either text"),
        ('[[program]]\nfile = "missing.nc"\n', "program[0].file", "cannot read"),
        ('[[program]]\ntext = "G1 X1."\n', "program[0].text", "O"),
        ('[[program]]\ntext = "O1\\nM30"\n[[program]]\ntext = "O1\\nM2"\n', "program[1].text",
         "given twice"),
        ('[[program]]\ntext = "O1\\nM30"\nmain = true\n[[program]]\ntext = "O2\\nM2"\nmain = 1\n',
         "program[1].main", "already the main"),
        ('[[program]]\ntext = "O1"\nspeed = 2\n', "program[0]", "speed"),
    ],
)  # fmt: skip
def test_bad_program_entries_name_the_key(
    tmp_path: Path, entries: str, key: str, problem: str
) -> None:
    path = tmp_path / "m.toml"
    path.write_text(HEAD + entries)
    with pytest.raises(MachineFileError) as failed:
        load_machine(path)
    assert failed.value.key.startswith(key) and problem in str(failed.value)


def test_the_built_in_machine_runs_its_demo_program() -> None:
    clock = ManualClock()
    machine = default_machine(sim_clock=clock)
    assert machine.programs.text(1).startswith(DEMO_PROGRAM.splitlines()[0])
    assert machine.programs.main == 1
    machine.cycle_start()
    clock.advance(12.0)
    first = machine.motion.absolute
    assert machine.motion.feed == 1200 and machine.motion.spindle_speed == 3000
    clock.advance(1.0)
    assert machine.motion.absolute != first
    clock.advance(120.0)
    assert machine.engine.state is CycleState.RESET and machine.read_param(6711, 0) == 1
