"""An eighth new-user pass over machine files, part programs and the examples: the cases it
found, each checked where the fix lives (the machine's parameter types and axis names, the
program store's O line, production's part time, the command line's reasons, the examples)."""

from __future__ import annotations

import asyncio
import signal
import sys
from collections.abc import AsyncIterator
from pathlib import Path

import pytest
from cli_support import Cli, fails
from examples_support import EXAMPLES, RUN_TIMEOUT, port_args, run_example
from fwlib_support import LIBRARY
from support import serve_process, serving

from focas_net.cli import EXIT_CNC, EXIT_USAGE
from focas_net.errors import EW
from focas_net.sim import (
    AXIS_NAME_PARAM,
    KNOWN_DIAGS,
    KNOWN_PARAMS,
    DataItem,
    Machine,
    MachineError,
    MachineFileError,
    ParamKind,
    default_machine,
    load_machine,
)
from focas_net.sim.nc import ManualClock, ProgramError, Scenario, parse_program

HEAD = '[machine]\nname = "M"\naxes = ["X", "Y"]\n'


def _load(tmp_path: Path, body: str, head: str = HEAD) -> Machine:
    path = tmp_path / "m.toml"
    path.write_text(head + body, encoding="utf-8")
    return load_machine(path)


def _refused(tmp_path: Path, body: str, head: str = HEAD) -> str:
    with pytest.raises(MachineFileError) as refused:
        _load(tmp_path, body, head)
    return str(refused.value)


# -- the types of the parameters the machine reads ----------------------------------------


@pytest.mark.parametrize(
    ("number", "spec", "words"),
    [
        (8110, 'type = "real"\ndecimals = 2\nvalue = 1.5', "waiting M codes from it: it is a word"),
        (8111, 'type = "bit"', "(got a bit parameter)"),
        (8110, 'type = "two-word"\naxis = true', "not per axis (got an axis two-word parameter)"),
        (1020, 'type = "word"\naxis = true', "it is a byte parameter, one per axis"),
        (1020, 'type = "byte"\nvalue = 88', "one per axis (got a byte parameter)"),
        (
            1420,
            'type = "byte"\naxis = true',
            "rapid traverse rate from it: it is a two-word or real",
        ),
        (1422, 'type = "real"\naxis = true', "maximum cutting feed from it"),
        (1320, 'type = "word"\naxis = true', "stroke limit from it"),
        (1825, 'type = "real"\naxis = true', "servo loop gain from it: it is a word parameter"),
        (9968, 'type = "byte"', "FANUC's library reads its bits: it is a bit parameter"),
        (3115, 'type = "bit"', "one per axis (got a bit parameter)"),
        (6752, 'type = "real"', "keeps a timer in it: it is a two-word parameter"),
    ],
)
def test_a_parameter_the_machine_reads_must_have_fanucs_type(
    tmp_path: Path, number: int, spec: str, words: str
) -> None:
    """Each parameter the machine acts on is checked against the type the control gives it:
    8110/8111 declared real used to load and be read as their mantissas."""
    message = _refused(tmp_path, f"[parameters.{number}]\n{spec}\n")
    assert f"m.toml: parameters.{number}.type: " in message
    assert words in message


@pytest.mark.parametrize("number", sorted(KNOWN_PARAMS))
def test_every_type_the_file_can_give_is_checked_against_the_table(
    tmp_path: Path, number: int
) -> None:
    """Each of the five types, per axis and not, of every parameter the machine reads: loaded
    exactly when it is one of the types the table gives (the rest refused, naming the key)."""
    known = KNOWN_PARAMS[number]
    for kind in ParamKind:
        for axis in (False, True):
            name = kind.name.lower().replace("_", "-")
            spec = f'[parameters.{number}]\ntype = "{name}"\naxis = {str(axis).lower()}\n'
            if number == AXIS_NAME_PARAM:
                spec += "value = [88, 89]\n" if axis else "value = 88\n"
            if kind in known.kinds and axis == known.axis:
                assert _load(tmp_path, spec).param_item(number) is not None
            else:
                assert f"parameters.{number}.type: " in _refused(tmp_path, spec)


def test_a_machine_built_in_python_meets_the_same_types() -> None:
    with pytest.raises(ValueError, match="parameter 8110: the machine reads its waiting M codes"):
        Machine("M", axes=["X"], params=[DataItem(8110, kind=ParamKind.REAL, decimals=1)])


def test_a_real_maximum_cutting_feed_is_read_as_its_value() -> None:
    """1422 of type real (as the 30i class has it) clamps the feed at its value in mm/min, not
    at its mantissa."""
    clock = ManualClock()
    params = [DataItem(1422, kind=ParamKind.REAL, decimals=3, values=[600_000])]  # 600 mm/min
    machine = Machine(
        "M", axes=["X"], params=params, sim_clock=clock, programs=("O1\nG1 X60. F6000\nM30\n",)
    )
    machine.cycle_start()
    clock.advance(1.0)
    assert machine.motion.feed == 600
    clock.advance(4.5)  # 60 mm at 600 mm/min: 6 s
    assert machine.status().run == 3
    clock.advance(1.0)
    assert machine.status().run == 0


# -- parameter 1020 and the axes ----------------------------------------------------------


@pytest.mark.parametrize(
    ("value", "key", "words"),
    [
        ("[88, 90]", "value[1]", "axis Y's letter 'Y' is 89, not 90 ('Z')"),
        ("[65, 89]", "value[0]", "axis X's letter 'X' is 88, not 65 ('A')"),
        ("88", "value", "axis Y's letter 'Y' is 89, not 88 ('X')"),
        ("[88, 0]", "value[1]", "axis Y's letter 'Y' is 89, not 0"),
    ],
)
def test_parameter_1020_must_name_the_axes_the_file_declares(
    tmp_path: Path, value: str, key: str, words: str
) -> None:
    body = f'[parameters.1020]\ntype = "byte"\naxis = true\nvalue = {value}\n'
    assert f"m.toml: parameters.1020.{key}: {words}" in _refused(tmp_path, body)


def test_parameter_1020_names_each_paths_axes_by_their_letter(tmp_path: Path) -> None:
    head = '[machine]\nname = "L"\n[[path]]\naxes = ["X1", "Z1"]\n[[path]]\naxes = ["X2", "Z2"]\n'
    body = '[parameters.1020]\ntype = "byte"\naxis = true\nvalue = [88, 90, 88, 90]\n'
    machine = _load(tmp_path, body, head)
    assert machine.read_param(1020, 2, path=2) == 90
    wrong = '[parameters.1020]\ntype = "byte"\naxis = true\nvalue = [88, 90, 90, 88]\n'
    assert "parameters.1020.value[2]: axis X2's letter 'X' is 88, not 90 ('Z')" in _refused(
        tmp_path, wrong, head
    )


def test_a_write_of_1020_that_renames_an_axis_is_refused_with_why() -> None:
    machine = default_machine()
    machine.set_panel(mode=0, pwe=1)  # MDI, PWE on
    session = machine.new_session()
    with pytest.raises(MachineError) as refused:
        machine.write_param(session, 1020, 1, 65)
    assert refused.value.ew == EW.DATA
    assert "axis X's letter 'X' is 88, not 65 ('A')" in str(refused.value)
    assert "next power-on" in str(refused.value)
    machine.write_param(session, 1020, 2, 89)  # its own letter: nothing changes
    assert [machine.read_param(1020, a) for a in (1, 2, 3)] == [88, 89, 90]


@pytest.fixture
async def cli(capsys: pytest.CaptureFixture[str]) -> AsyncIterator[Cli]:
    machine = default_machine()
    machine.set_panel(mode=0, pwe=1)  # MDI, PWE on
    async with serving(machine) as served:
        yield Cli(served, capsys)


@pytest.mark.parametrize("protocol", ["packed", "native"])
async def test_the_command_line_says_a_refused_1020_may_be_a_new_letter(
    cli: Cli, protocol: str
) -> None:
    line = await cli.fails(
        EXIT_CNC, "param", "set", "1020", "65", "--axis", "1", "--protocol", protocol
    )
    assert "the CNC refused 65 for parameter 1020 axis 1" in line
    assert "a letter other than the axis's own" in line


# -- the O line -----------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("o_line", "words"),
    [
        ("O1.5", "'O1.5': a program number is O and 1..4 digits, no decimal point (O1..O9999)"),
        ("O12.", "'O12.': a program number is O and 1..4 digits, no decimal point"),
        ("O1 .5", "'O1 .5': a program number is O and 1..4 digits, no decimal point"),
        ("O1,5", "'O1,5': a program number is O and 1..4 digits, no decimal point"),
        ("O1-2", "'O1-2': a program number is O and 1..4 digits, no '-' after its digits"),
        ("O00001", "'O00001': a program number is O and 1..4 digits, not 5 (O1..O9999)"),
        (":7.0", "':7.0': a program number is O and 1..4 digits, no decimal point"),
    ],
)
def test_a_program_number_that_is_no_whole_number_is_refused_when_loaded(
    tmp_path: Path, o_line: str, words: str
) -> None:
    """``O1.5`` used to load as O0001 with a block ``.5`` that alarmed only when run."""
    with pytest.raises(ProgramError, match=r"a program number is O and 1\.\.4 digits"):
        parse_program(f"{o_line}\nG0 X1.\nM30\n")
    message = _refused(tmp_path, f'[[program]]\ntext = "{o_line}\\nM30"\n')
    assert f"program[0].text: {words}" in message


@pytest.mark.parametrize(("o_line", "number"), [("O12X1.", 12), ("O0012(X)", 12), ("o7", 7)])
def test_an_o_line_of_a_whole_number_still_loads(o_line: str, number: int) -> None:
    assert parse_program(f"{o_line}\nM30\n").number == number


async def test_program_load_of_o1_5_names_it(cli: Cli, tmp_path: Path) -> None:
    target = tmp_path / "o15.nc"
    target.write_text("O1.5\nG0 X1.\nM30\n", encoding="ascii")
    line = await cli.fails(EXIT_CNC, "program", "load", str(target))
    assert line.endswith(
        f"{target}: 'O1.5': a program number is O and 1..4 digits, no decimal point (O1..O9999)"
    )


# -- production of a part of no machine time --------------------------------------------


@pytest.mark.parametrize(
    ("text", "per_10_s"),
    [
        ("O1\nM30\n", 20),  # no time at all: one part per M30's FIN (0.5 s)
        ("O1\n#1 = 1\nM30\n", 20),
        ("O1\nG4 X0.1\nM30\n", 20),  # shorter than the FIN: 0.5 s a part
        ("O1\nG4 X1.\nM30\n", 10),  # longer: its own time
    ],
)
def test_production_of_a_part_of_no_time_counts_as_time_goes(text: str, per_10_s: int) -> None:
    """``[run]`` of a main program that takes (almost) no machine time used to hang the
    machine's start (``serve`` printed no ready line): each part now takes at least M30's FIN."""
    clock = ManualClock()
    machine = default_machine(sim_clock=clock, programs=(text,))
    machine.select_program(1)
    machine.scenario = Scenario(phase=0.0, pause_rate=0, tool_rate=0, alarm_rate=0)
    machine.start_scenario()
    first = machine.read_param(6711, 0)
    clock.advance(10.0)
    assert machine.read_param(6711, 0) - first == per_10_s


async def test_serve_starts_a_run_of_a_program_of_no_motion(tmp_path: Path) -> None:
    path = tmp_path / "m.toml"
    path.write_text(
        '[machine]\nname = "m"\naxes = ["X"]\n[[program]]\ntext = "O1\\nG1 X1. F100\\nM30"\n'
        '[run]\nparts = "required"\n',
        encoding="utf-8",
    )
    async with serve_process(
        "--machine", str(path), "--fleet", "2", lines=2, start_timeout=30.0
    ) as (
        _,
        ready,
    ):
        assert [m["name"] for m in ready] == ["m-1", "m-2"]


# -- the examples -------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("args", "line"),
    [
        (["--rack", "8"], "versamax_config: rack 8 is outside 0..7"),
        (["--slot", "10"], "versamax_config: slot 10 is outside 0..9"),
    ],
)
async def test_versamax_config_refuses_a_rack_or_slot_its_help_does_not_have(
    args: list[str], line: str
) -> None:
    code, out, err = await run_example("versamax_config.py", "--port", "1", *args)
    assert (code, out, err) == (2, "", line + "\n")


@pytest.mark.parametrize(
    ("ports", "words"),
    [
        (",", "argument --ports: no port in ','"),
        (" ", "argument --ports: no port in ' '"),
        ("8193,70000", "argument --ports: ports are 1..65535, got '8193,70000'"),
    ],
)
async def test_fleet_poll_refuses_ports_that_are_none(ports: str, words: str) -> None:
    """``--ports ,`` used to end in ``unsupported operand type(s) for +``."""
    code, out, err = await run_example("fleet_poll.py", "--ports", ports)
    assert code == EXIT_USAGE and out == ""
    assert err.splitlines()[-1].startswith(f"fleet_poll.py: error: {words}")
    assert "NoneType" not in err


async def test_serve_of_a_file_of_a_wrong_parameter_type_is_one_line(tmp_path: Path) -> None:
    path = tmp_path / "m.toml"
    path.write_text(HEAD + '[parameters.8110]\ntype = "real"\n', encoding="utf-8")
    line = await fails(
        EXIT_USAGE, "serve", "--port", "0", "--machine", str(path), prefix="focas-net"
    )
    assert "parameters.8110.type: the machine reads its waiting M codes from it" in line


def test_a_comment_before_the_o_number_leaves_no_stray_block() -> None:
    """``(12)O12`` used to add a block ``)O12`` (the number was looked for in the comment),
    which alarmed when run."""
    program = parse_program("(12)O12\nG4 X0.1\nM30\n")
    assert (program.number, program.name) == (12, "12")
    assert [b.text for b in program.blocks] == ["G4 X0.1", "M30"]
    clock = ManualClock()
    machine = default_machine(sim_clock=clock, programs=("(12)O12\nG4 X0.1\nM30\n",))
    machine.select_program(12)
    machine.cycle_start()
    clock.advance(1.0)
    assert machine.active_alarms() == [] and machine.read_param(6711, 0) == 1


def test_a_program_in_a_literal_toml_string_is_told_how_to_write_it(tmp_path: Path) -> None:
    message = _refused(tmp_path, "[[program]]\ntext = 'O1\\nG0 X1.\\nM30'\n")
    assert "m.toml: program[0].text: " in message
    assert "a TOML string in '...' keeps \\n as written" in message


# -- the examples against a machine without what they use -------------------------------


@pytest.fixture
async def lathe() -> AsyncIterator[tuple[Machine, list[str]]]:
    """The two-path lathe of examples/lathe_2path.toml: no parameter 1320, no PMC area D."""
    machine = load_machine(EXAMPLES / "lathe_2path.toml")
    async with serving(machine) as served:
        yield machine, port_args(served)


async def test_alarm_watch_stopped_early_leaves_none_of_its_alarms(
    lathe: tuple[Machine, list[str]],
) -> None:
    """``--events 1`` used to stop with the demonstration's PS0100 still active, so the next
    cycle start was refused with EW_ALARM. The one event is PS0100's, raised or (when the
    raise falls between a poll's active list and its history) its history entry."""
    machine, address = lathe
    code, out, _ = await run_example("alarm_watch.py", *address, "--events", "1")
    assert code == 0 and "  1  " in out and " PS0100" in out
    assert machine.active_alarms() == []


@pytest.mark.parametrize(
    ("name", "args", "words"),
    [
        (
            "write_param_with_unlock.py",
            [],
            "cnc_rdparainfo; the CNC has no parameter 1320 (give --param N)",
        ),
        (
            "pmc_bits.py",
            ["--area", "D"],
            "pmc_rdpmcrng: the CNC has no PMC area D; give --area of one it has",
        ),
        (
            "pmc_bits.py",
            ["--area", "G", "--start", "1999", "--bytes", "2"],
            "G1999..G2000 goes past the end of PMC area G; give --start and --bytes within it",
        ),
    ],
)
async def test_an_example_names_what_the_cnc_has_not(
    lathe: tuple[Machine, list[str]], name: str, args: list[str], words: str
) -> None:
    code, out, err = await run_example(name, *lathe[1], *args)
    assert (code, out) == (1, "")
    assert err.count("\n") == 1 and words in err


async def test_run_program_names_why_the_cnc_refused_the_program(
    lathe: tuple[Machine, list[str]], tmp_path: Path
) -> None:
    target = tmp_path / "o15.nc"
    target.write_text("O1.5\nG0 X1.\nM30\n", encoding="ascii")
    code, out, err = await run_example("run_program.py", *lathe[1], "--program", str(target))
    assert (code, out) == (1, "")
    assert err.endswith(
        f"; {target}: 'O1.5': a program number is O and 1..4 digits, no decimal point (O1..O9999)\n"
    )


async def test_run_program_names_the_alarm_that_refuses_cycle_start(
    lathe: tuple[Machine, list[str]],
) -> None:
    machine, address = lathe
    machine.raise_alarm(0, 3, 10, "IMPROPER G-CODE")
    code, out, err = await run_example("run_program.py", *address)
    assert (code, out) == (1, "")
    assert err == (
        "run_program: an alarm is active: PS0010 IMPROPER G-CODE (focas-net sim clear clears "
        "alarms)\n"
    )


@pytest.mark.skipif(
    LIBRARY is None, reason="set FOCAS_NET_FWLIB to FANUC's libfwlib32 to run fwlib_client.py"
)
async def test_fwlib_client_names_the_pmc_range_the_cnc_refused(
    lathe: tuple[Machine, list[str]],
) -> None:
    assert LIBRARY is not None
    code, out, err = await run_example("fwlib_client.py", "--library", LIBRARY, *lathe[1])
    assert code == 6 and "cnc: type 0T" in out  # EW_NOOPT as the exit status
    assert err == "fwlib_client: pmc_rdpmcrng of D0..D3 returned EW 6\n"


@pytest.mark.parametrize(
    ("path2", "words"),
    [
        ("", "a scenario cannot start on path 2: no main program is selected"),
        (
            '[path.panel]\nmode = "EDIT"\n[[path.program]]\ntext = "O2\\nM30"\n',
            "a scenario cannot start on path 2: the mode is EDIT, not MEM",
        ),
    ],
)
async def test_serve_run_names_the_path_that_cannot_start(
    tmp_path: Path, path2: str, words: str
) -> None:
    """A path of several without a main program was refused as if the machine had none."""
    path = tmp_path / "m.toml"
    path.write_text(
        '[machine]\nname = "tp"\n[[path]]\naxes = ["X1", "Z1"]\n[[path.program]]\n'
        'text = "O1\\nG4 X1.\\nM30"\n[[path]]\naxes = ["X2", "Z2"]\n' + path2 + "[run]\n",
        encoding="utf-8",
    )
    line = await fails(
        EXIT_USAGE, "serve", "--port", "0", "--machine", str(path), prefix="focas-net"
    )
    assert line.endswith(
        f"m.toml: [run]: tp: {'EW_DATA' if 'program' in words else 'EW_MODE'}: {words}"
    )


@pytest.mark.parametrize("number", sorted(KNOWN_DIAGS))
@pytest.mark.parametrize("kind", list(ParamKind))
def test_a_diagnostic_the_machine_computes_has_a_whole_number_type(
    tmp_path: Path, number: int, kind: ParamKind
) -> None:
    """410, 4901 and 4902 follow the loads: a bit or byte one read a load of 555 W past its
    type (4901 of type byte), a real one counted in its mantissa."""
    name = kind.name.lower().replace("_", "-")
    for axis in ("true", "false"):
        body = f'[diagnostics.{number}]\ntype = "{name}"\naxis = {axis}\n'
        if kind in (ParamKind.WORD, ParamKind.TWO_WORD):
            assert _load(tmp_path, body).read_diag(number, 1 if axis == "true" else 0) == 0
        else:
            message = _refused(tmp_path, body)
            assert f"diagnostics.{number}.type: the machine shows" in message
            got = f"(got an axis {name} diagnostic)" if axis == "true" else f"(got a {name} "
            assert f"it is a word or two-word diagnostic {got}" in message


def test_a_servo_power_is_held_within_its_range() -> None:
    clock = ManualClock()
    diags = [DataItem(4901, kind=ParamKind.WORD, axis=True, low=0, high=100)]
    machine = Machine(
        "M", axes=["X"], diags=diags, sim_clock=clock, programs=("O1\nG0 X500.\nM30\n",)
    )
    machine.cycle_start()
    clock.advance(0.5)
    assert machine.status().run == 3
    assert machine.read_diag(4901, 1) == 100  # a rapid's load times 15 W, held at its high


@pytest.mark.parametrize(
    ("name", "args"),
    [
        ("alarm_watch.py", ["--events", "100", "--seconds", "60", "--interval", "0.05"]),
        ("run_program.py", ["--interval", "0.05"]),
    ],
)
async def test_an_example_interrupted_by_ctrl_c_exits_130_without_a_traceback(
    name: str, args: list[str]
) -> None:
    """Ctrl-C printed asyncio's traceback of KeyboardInterrupt; the examples now end as the
    command line does (exit 130), and alarm_watch clears the alarms it raised."""
    machine = default_machine()
    async with serving(machine) as served:
        proc = await asyncio.create_subprocess_exec(
            sys.executable, str(EXAMPLES / name), *port_args(served), *args,
            stdout=asyncio.subprocess.PIPE, stderr=asyncio.subprocess.PIPE,
        )  # fmt: skip
        assert proc.stdout is not None
        try:
            async with asyncio.timeout(RUN_TIMEOUT):
                assert await proc.stdout.readline()  # at work: it printed its first line
                proc.send_signal(signal.SIGINT)
                _, err = await proc.communicate()
        finally:
            if proc.returncode is None:
                proc.kill()
                await proc.wait()
    assert proc.returncode == 130
    assert err == b""  # no traceback
    if name == "alarm_watch.py":
        assert machine.active_alarms() == []
