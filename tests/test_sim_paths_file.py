"""Machine files of several paths: ``[[path]]`` tables load into a machine whose paths each
answer for themselves; bad tables name the key; the twin-turret example runs both paths in
step and counts parts per path."""

from __future__ import annotations

import asyncio
import signal
from pathlib import Path

import pytest
from support import Wire, serve_process

from focas_net.protocol import Command
from focas_net.sim import MachineFileError, PathInfo, load_machine
from focas_net.sim.nc import ManualClock, Scenario

ROOT = Path(__file__).resolve().parent.parent
LATHE = ROOT / "examples" / "lathe_2path.toml"

FOUR_PATHS = """
[machine]
name = "four"

[parameters.6711]
type = "2-word"

[parameters.8110]
type = "2-word"
value = 100

[parameters.8111]
type = "2-word"
value = 199

[parameters.1420]
type = "2-word"
axis = true
value = [11, 12, 21, 22, 31, 41, 42, 43]
"""


def four_path_file(tmp_path: Path) -> Path:
    """A machine of 4 paths: path n has axes Xn (and more), program O(n*100) moving Xn to
    n mm at 600 mm/min, panels in MEM except path 4's in EDIT."""
    axes = [["X1", "Z1"], ["X2", "Z2"], ["X3"], ["X4", "Y4", "Z4"]]
    text = FOUR_PATHS
    for n, names in enumerate(axes, 1):
        quoted = ", ".join(f'"{a}"' for a in names)
        text += f"""
[[path]]
axes = [{quoted}]
kind = "{"T" if n < 3 else "M"}"

[path.panel]
mode = "{"EDIT" if n == 4 else "MEM"}"

[[path.program]]
text = "O{n * 100}\\nG1 X{n}. F600\\nM30\\n%"
"""
    path = tmp_path / "four.toml"
    path.write_text(text, encoding="utf-8")
    return path


def test_a_four_path_machine_file_answers_per_path(tmp_path: Path) -> None:
    clock = ManualClock()
    m = load_machine(four_path_file(tmp_path), sim_clock=clock)
    assert m.path_count == 4
    assert m.path_info(3) == PathInfo(3, "PATH3", "M", ("X3",), 1)
    assert m.path_info(4).kind == "M"
    assert [m.status(path=n).aut for n in (1, 2, 3, 4)] == [1, 1, 1, 3]  # MEM, EDIT
    for n in (1, 2, 3, 4):
        assert [p.number for p in m.program_directory(path=n)] == [n * 100]
        assert m.path_motion(path=n).program_main == n * 100  # the selected program
        assert m.read_param(1420, 1, path=n) == [11, 21, 31, 41][n - 1]
    for n in (1, 2, 3):
        m.cycle_start(path=n)
    clock.set(0.05)
    assert [m.status(path=n).run for n in (1, 2, 3, 4)] == [3, 3, 3, 0]
    clock.set(1.0)  # path n needs n/10 s
    for n in (1, 2, 3):
        assert m.positions("absolute", 1, path=n) == [(f"X{n}", n * 1000)]
        assert m.parts_counts(path=n) == (1, 1)
        assert m.read_param(6711, 0, path=n) == 1
    assert m.parts_counts(path=4) == (0, 0)
    assert m.raise_alarm(0, 2, 3000, "ONLY PATH 3", path=3)
    assert [len(m.active_alarms(path=n)) for n in (1, 2, 3, 4)] == [0, 0, 1, 0]


def write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "machine.toml"
    path.write_text(text, encoding="utf-8")
    return path


ONE = """
[machine]
name = "m"
"""


@pytest.mark.parametrize(
    ("body", "key", "words"),
    [
        ('[[path]]\naxes = []\n', "path[0].axes", "at least one axis"),
        ('[[path]]\nname = "A"\n', "path[0].axes", "missing"),
        ('[[path]]\naxes = ["X"]\n[[path]]\naxes = ["Z", "X"]\n', "path[1].axes[1]",
         "axis 'X' is path[0]'s already"),
        ('[[path]]\naxes = ["X"]\nkind = "L"\n', "path[0].kind", 'must be "M"'),
        ('[[path]]\naxes = ["X"]\nspindles = 9\n', "path[0].spindles", "outside 1..8"),
        ('[[path]]\naxes = ["X"]\nname = "A"\n[[path]]\naxes = ["Y"]\nname = "A"\n',
         "path[1].name", "path[0]'s name already"),
        ('[[path]]\naxes = ["X"]\nturret = 1\n', "path[0].turret", "unknown key"),
        ('[[path]]\naxes = ["X"]\n[path.panel]\nmode = "FAST"\n', "path[0].panel.mode",
         "unknown mode"),
        ('[[path]]\naxes = ["X"]\n[[path.program]]\ntext = "nothing"\n',
         "path[0].program[0].text", ""),
        ('[panel]\nmode = "MEM"\n[[path]]\naxes = ["X"]\n', "panel", "in each [[path]]"),
        ('[[program]]\ntext = "O1\\nM30\\n%"\n[[path]]\naxes = ["X"]\n', "program",
         "in each [[path]]"),
        ('[path]\naxes = ["X"]\n', "path", "must be an array"),
    ],
)  # fmt: skip
def test_a_bad_path_table_names_the_key(tmp_path: Path, body: str, key: str, words: str) -> None:
    with pytest.raises(MachineFileError) as info:
        load_machine(write(tmp_path, ONE + body))
    assert info.value.key == key
    assert words in info.value.problem


def test_more_than_ten_paths_are_refused(tmp_path: Path) -> None:
    body = "".join(f'[[path]]\naxes = ["X{n}"]\n' for n in range(11))
    with pytest.raises(MachineFileError) as info:
        load_machine(write(tmp_path, ONE + body))
    assert (info.value.key, info.value.problem) == ("path", "a machine has 1..10 paths, got 11")


def test_machine_axes_with_paths_is_refused(tmp_path: Path) -> None:
    text = '[machine]\nname = "m"\naxes = ["X"]\n[[path]]\naxes = ["Z"]\n'
    with pytest.raises(MachineFileError) as info:
        load_machine(write(tmp_path, text))
    assert info.value.key == "machine.axes"


def test_a_file_without_paths_and_without_axes_says_where_axes_go(tmp_path: Path) -> None:
    with pytest.raises(MachineFileError) as info:
        load_machine(write(tmp_path, ONE))
    assert info.value.key == "machine.axes"
    assert "[[path]]" in info.value.problem


def test_the_twin_turret_lathe_runs_both_paths_in_step() -> None:
    clock = ManualClock()
    m = load_machine(LATHE, sim_clock=clock)
    assert [m.path_info(n).axes for n in (1, 2)] == [("X1", "Z1"), ("X2", "Z2")]
    m.cycle_start(path=1)
    m.cycle_start(path=2)
    waited = {1: False, 2: False}
    for _ in range(2000):  # 0.05 s steps, 100 s of machine time: a part takes about 30
        clock.advance(0.05)
        for n in (1, 2):
            waited[n] = waited[n] or m.status(path=n).motion == 3
        if m.status(path=1).run == 0 and m.status(path=2).run == 0:
            break
    assert waited == {1: True, 2: True}  # each path waited for the other somewhere
    assert [m.parts_counts(path=n) for n in (1, 2)] == [(1, 1), (1, 1)]
    # both end at the last waiting M code together: the same cycle time
    assert m.timer(3, path=1) == pytest.approx(m.timer(3, path=2))


def test_the_twin_turret_lathe_produces_on_both_paths() -> None:
    clock = ManualClock()
    m = load_machine(LATHE, sim_clock=clock)
    m.start_scenario(Scenario(seed=5, alarm_rate=0.0, pause_rate=0.0, tool_rate=0.0))
    clock.advance(600.0)
    one, two = m.parts_counts(path=1), m.parts_counts(path=2)
    assert one[0] > 10
    assert one == two  # one part on each path per cycle, in step
    cycle = m.timer(3, path=1)
    assert 0 < cycle < 60


async def test_serve_runs_the_twin_turret_lathe() -> None:
    """``focas-net serve --machine examples/lathe_2path.toml --run`` serves it (the ready
    line names it) and stops on SIGTERM with exit code 0."""
    async with serve_process("--machine", str(LATHE), "--run", lines=1, start_timeout=30.0) as (
        proc,
        ready,
    ):
        assert ready[0]["name"] == "twin-turret-lathe"
        async with await Wire.open("127.0.0.1", int(ready[0]["port"])) as wire:
            assert await wire.ew(Command.RDCNCSTAT, b"") == 0
        proc.send_signal(signal.SIGTERM)
        async with asyncio.timeout(30.0):
            assert await proc.wait() == 0


def test_a_scenario_s_part_count_holds_for_every_path() -> None:
    clock = ManualClock()
    m = load_machine(LATHE, sim_clock=clock)
    quiet = {"alarm_rate": 0.0, "pause_rate": 0.0, "tool_rate": 0.0, "phase": 0.0}
    m.start_scenario(Scenario(seed=5, parts=2, **quiet))
    clock.advance(600.0)
    assert [m.parts_counts(path=n)[0] for n in (1, 2)] == [2, 2]
    assert [m.status(path=n).run for n in (1, 2)] == [0, 0]
    m.start_scenario(Scenario(seed=5, parts=1, **quiet))
    m.stop_scenario()  # production goes on without the limit, on every path
    clock.advance(600.0)
    assert [m.parts_counts(path=n)[0] > 4 for n in (1, 2)] == [True, True]
    assert [m.status(path=n).run for n in (1, 2)] == [3, 3]
