"""A seventh new-user pass over machine files, part programs and the examples: the cases it
found, each checked where the fix lives (the machine file's loader, the program store's
reasons, the command line's messages)."""

from __future__ import annotations

from collections.abc import AsyncIterator
from pathlib import Path

import pytest
from cli_support import Cli, run_focas_net
from examples_support import EXAMPLES, run_example
from support import serving

from focas_net.cli import EXIT_CNC, EXIT_USAGE
from focas_net.protocol import MotionState, field_label
from focas_net.sim import Machine, MachineFileError, default_machine, load_machine
from focas_net.sim.nc import ManualClock

HEAD = '[machine]\nname = "M"\naxes = ["X", "Y"]\n'


def _load(tmp_path: Path, body: str) -> Machine:
    path = tmp_path / "m.toml"
    path.write_text(HEAD + body, encoding="utf-8")
    return load_machine(path)


# -- machine files ---------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("body", "expected"),
    [
        ('type = "real"\ndecimals = 2', 0),
        ('type = "real"', 0),
        ('type = "real"\ndecimals = 1\nrange = [1.5, 3]', 15),
        ('type = "real"\ndecimals = 3\naxis = true\nrange = [-2, -1]', -2000),
    ],
)
def test_a_real_parameter_without_a_value_loads_with_its_default(
    tmp_path: Path, body: str, expected: int
) -> None:
    """A real parameter or diagnostic left without ``value`` takes the documented default (0,
    or the low end of its range), as every other type does."""
    machine = _load(tmp_path, f"[parameters.1430]\n{body}\n[diagnostics.1431]\n{body}\n")
    axis = 1 if "axis" in body else 0
    assert machine.read_param(1430, axis) == expected  # the mantissa
    assert machine.read_diag(1431, axis) == expected


def test_a_parts_count_of_type_real_is_refused_for_its_type(tmp_path: Path) -> None:
    with pytest.raises(MachineFileError) as refused:
        _load(tmp_path, '[parameters.6711]\ntype = "real"\ndecimals = 1\n')
    message = str(refused.value)
    assert "parameters.6711.type: the machine counts parts in it" in message
    assert "Decimal" not in message


# -- programs at the command line ------------------------------------------------------------


@pytest.fixture
async def cli(capsys: pytest.CaptureFixture[str]) -> AsyncIterator[Cli]:
    async with serving(default_machine()) as served:
        yield Cli(served, capsys)


@pytest.mark.parametrize(
    ("content", "words"),
    [
        (b"O1401 (\x07BELL)\nM30\n", "line 1: character '\\x07' (U+0007)"),
        (b"O1402\nG1 X1. F100\x1b\nM30\n", "line 2: character '\\x1b' (U+001B)"),
        (b"%\nO1404\nM30\n%\nO1405\nM30\n%\n", "line 5: 'O1405' starts a second program"),
        (b"%\n%\n", "the program text is empty"),
        (b"G1 X1. F100\nM30\n", "a program starts with O and its number"),
    ],
)
async def test_program_load_names_why_the_machine_refused_the_text(
    cli: Cli, tmp_path: Path, content: bytes, words: str
) -> None:
    """EW_DATA of ``cnc_download`` names the machine's reason: a control character on a line,
    a second program, no program at all, not just "not one part program"."""
    file = tmp_path / "part.nc"
    file.write_bytes(content)
    line = await cli.fails(EXIT_CNC, "program", "load", str(file))
    assert line.startswith("focas-net: EW_DATA (5)")
    assert f"{file}: {words}" in line


async def test_program_load_of_a_too_long_file_names_the_file(cli: Cli, tmp_path: Path) -> None:
    file = tmp_path / "huge.nc"
    file.write_bytes(b"O1\n" + b"G0 X1.\n" * 20_000)
    line = await cli.fails(EXIT_USAGE, "program", "load", str(file), prefix="focas-net")
    assert line.startswith(
        f"focas-net program: error: argument N|FILE: {str(file)!r}: a program of "
    )


# -- the examples' machines ------------------------------------------------------------------


async def test_a_path_waiting_at_a_waiting_m_code_shows_motion_wait(
    capsys: pytest.CaptureFixture[str],
) -> None:
    """examples/lathe_2path.toml: turret 1 at M100 waits for turret 2; its status shows motion
    3 as docs/machine-file.md names it (WAIT), never "unknown value"."""
    clock = ManualClock()
    machine = load_machine(EXAMPLES / "lathe_2path.toml", sim_clock=clock)
    machine.cycle_start(path=1)
    clock.advance(10.0)
    assert (machine.status(path=1).run, machine.status(path=1).motion) == (3, 3)
    assert field_label(MotionState, 3) == ("WAIT", "waiting for the other paths (waiting M code)")
    async with serving(machine) as served:
        cli = Cli(served, capsys)
        out = await cli.ok("status")
        assert out.startswith("mode=MEM run=STRT motion=WAIT ")
        assert "unknown value" not in out


@pytest.mark.parametrize(("name", "paths"), [("machine.toml", 1), ("lathe_2path.toml", 2)])
def test_the_example_machines_have_the_system_variables_watch_reads(name: str, paths: int) -> None:
    """``focas-net watch`` shows the sequence number from #4114 and the parts from #3901; the
    example machines have them on every path (they showed ``sequence -``)."""
    clock = ManualClock()
    machine = load_machine(EXAMPLES / name, sim_clock=clock)
    for path in range(1, paths + 1):
        if machine.status(path=path).run != 3:  # machine.toml's [run] has started already
            machine.cycle_start(path=path)
    clock.advance(3.0)
    for path in range(1, paths + 1):
        sequence = machine.read_macro(4114, path=path)
        assert sequence is not None and sequence > 0
        assert machine.read_macro(3901, path=path) == machine.read_param(6711, 0, path=path)


# -- serve --run -----------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("argv", "line"),
    [
        (
            ["--seed", "9223372036854775808"],
            "argument --seed: must be 0..9223372036854775807, got 9223372036854775808",
        ),
        (
            ["--run-parts", "2147483648"],
            "argument --run-parts: must be 0..2147483647, got 2147483648",
        ),
    ],
)
async def test_serve_run_refuses_what_a_run_section_refuses(argv: list[str], line: str) -> None:
    """``--seed`` and ``--run-parts`` take what a machine file's ``[run]`` seed and parts take;
    beyond it the start-up stops with a usage error naming the option."""
    code, out, err = await run_focas_net("serve", "--port", "0", "--run", *argv)
    assert (code, out) == (EXIT_USAGE, "")
    assert err == f"focas-net serve: error: {line}; see focas-net serve --help\n"


@pytest.mark.parametrize(("key", "value"), [("seed", 2**63), ("parts", 2**31)])
def test_a_run_section_refuses_the_same_bounds(tmp_path: Path, key: str, value: int) -> None:
    with pytest.raises(MachineFileError, match=rf"run\.{key}: {value} is outside 0\.\."):
        _load(tmp_path, f"[run]\n{key} = {value}\n")


def test_a_program_file_that_is_not_utf8_is_named_with_its_key(tmp_path: Path) -> None:
    (tmp_path / "latin.nc").write_bytes(b"O1308 (CAF\xe9)\nM30\n")
    with pytest.raises(MachineFileError) as refused:
        _load(tmp_path, '[[program]]\nfile = "latin.nc"\n')
    assert str(refused.value) == (
        f"{tmp_path / 'm.toml'}: program[0].file: {str(tmp_path / 'latin.nc')!r}: line 1: "
        "byte 0xE9 in 'O1308 (CAF\\xe9)' is not text: a program is printable ASCII text"
    )


async def test_program_load_reads_a_file_with_a_byte_order_mark(cli: Cli, tmp_path: Path) -> None:
    """A program saved by Windows Notepad as UTF-8 starts with a byte-order mark; a machine
    file's ``[[program]] file`` reads it, and so does ``program load``."""
    file = tmp_path / "o1306.nc"
    file.write_bytes(b"\xef\xbb\xbfO1306 (NOTEPAD)\r\nM30\r\n")
    assert await cli.ok("program", "load", str(file)) == f"stored O1306 from {file}\n"
    assert cli.served.machine.program_text(1306).startswith("O1306 (NOTEPAD)")


async def test_a_state_folder_of_the_machine_file_is_named_as_the_file_names_it(
    tmp_path: Path,
) -> None:
    """``state = "x.toml"`` in ``[machine]`` (a file, not a folder) is refused naming the
    machine file's key, not a ``--state`` option the command line did not have."""
    (tmp_path / "x.toml").write_text("")
    machine = tmp_path / "m.toml"
    machine.write_text(HEAD + 'state = "x.toml"\n')
    code, out, err = await run_focas_net("serve", "--port", "0", "--machine", str(machine))
    assert (code, out) == (EXIT_USAGE, "")
    assert err.startswith(
        f"focas-net serve: error: {machine}: machine.state {tmp_path / 'x.toml'}: "
    )
    assert err.endswith("not a directory\n") and "--state" not in err


@pytest.mark.parametrize(
    ("value", "words"),
    [
        (
            '"1.5"',
            "must be an integer or [mcr_val, dec_val] (1.5 is [15, 1]), got a string ('1.5')",
        ),
        ('"abc"', "must be an integer or [mcr_val, dec_val], got a string ('abc')"),
    ],
)
def test_a_macro_value_in_quotes_is_refused_with_the_pair(
    tmp_path: Path, value: str, words: str
) -> None:
    with pytest.raises(MachineFileError) as refused:
        _load(
            tmp_path,
            f"[macros]\nranges = [{{ first = 1, last = 3 }}]\nvalues = {{ 1 = {value} }}\n",
        )
    assert str(refused.value).endswith(f"macros.values.1: {words}")


@pytest.mark.parametrize(
    ("value", "kind"), [("true", "a boolean (true)"), ("{ a = 1 }", "a table")]
)
def test_a_real_value_of_another_type_is_refused_as_not_a_number(
    tmp_path: Path, value: str, kind: str
) -> None:
    with pytest.raises(MachineFileError) as refused:
        _load(tmp_path, f'[parameters.1430]\ntype = "real"\ndecimals = 1\nvalue = {value}\n')
    assert str(refused.value).endswith(
        f"parameters.1430.value: must be a number such as 12.345, got {kind}"
    )


def test_tools_of_a_path_the_machine_has_not_are_named_by_their_key(tmp_path: Path) -> None:
    with pytest.raises(MachineFileError) as refused:
        _load(tmp_path, "[[tools]]\npath = 3\n")
    assert str(refused.value).endswith("tools[0].path: the machine has no path 3 (its paths: 1..1)")


def test_versamax_module_and_reference_type_names_in_either_case(tmp_path: Path) -> None:
    """As a control class, a mode, a type or a PMC letter, a built-in module's name and a
    reference type are read in either case."""
    body = (
        '[[versamax]]\nrack = 0\nslot = 1\nmodule = "ic200gbi001"\n'
        '[[versamax]]\nrack = 0\nslot = 4\nlabel = "MDL6"\nprimary_id = 0x8008\n'
        'references = [{ type = "i", offset = 3, length = 2 },\n'
        '  { type = "aq", offset = 0, length = 2 }]\n'
    )
    lower = _load(tmp_path, body)
    upper = _load(
        tmp_path,
        body.replace('"ic200gbi001"', '"IC200GBI001"')
        .replace('"i"', '"I"')
        .replace('"aq"', '"AQ"'),
    )
    for slot in (1, 4):
        assert lower.config_record(0, slot) == upper.config_record(0, slot)
    with pytest.raises(MachineFileError, match=r"versamax\[0\]\.module: unknown module 'IC200XYZ'"):
        _load(tmp_path, '[[versamax]]\nrack = 0\nslot = 1\nmodule = "IC200XYZ"\n')


@pytest.mark.parametrize("control_class", ["30i", "0i-F", "16i"])
def test_program_numbers_are_four_digits_on_every_control_class(
    tmp_path: Path, control_class: str
) -> None:
    """docs/machine-file.md: O1..O9999 on every class; the 30i's 8-digit option is not
    modelled, and a machine file saying O12345678 is told so."""
    head = f'control_class = "{control_class}"\n'
    with pytest.raises(MachineFileError) as refused:
        _load(tmp_path, head + '[[program]]\ntext = "O12345678\\nM30\\n"\n')
    assert str(refused.value).endswith(
        "program[0].text: program number O12345678 is outside O1..O9999"
    )
    machine = _load(tmp_path, head + '[[program]]\ntext = ":9999\\nM30\\n"\n')
    assert [p.number for p in machine.program_directory()] == [9999]


# -- part programs in the machine --------------------------------------------------------------


@pytest.mark.parametrize(
    ("block", "alarm"), [("N123456 G1 X1. F100", 3), ("N99999 G1 X1. F100", None)]
)
def test_a_sequence_number_has_five_digits(block: str, alarm: int | None) -> None:
    """N1..N99999 as on FANUC's 0i and 16i; N123456 raises PS0003 (too many digits) with its
    history entry, and a reset leaves no alarm for the next run."""
    clock = ManualClock()
    programs = (f"O0300\n{block}\nM30\n", "O0301\nG4 P5000\nM30\n")
    machine = default_machine(sim_clock=clock, programs=programs)
    machine.select_program(300)
    machine.cycle_start()
    clock.advance(5.0)
    expected = [] if alarm is None else [(3, alarm)]
    assert [(a.alm_type, a.alm_no) for a in machine.active_alarms()] == expected
    assert [(e.alm_type, e.alm_no) for e in machine.alarm_history()] == expected
    machine.reset()
    machine.select_program(301)
    machine.cycle_start()
    assert machine.active_alarms() == [] and machine.status().run == 3


async def test_a_program_of_a_long_name_leaves_the_directory_readable(
    cli: Cli, tmp_path: Path
) -> None:
    """A 300-character O-line comment was stored whole and made every ``program list`` answer
    EW_DATA (the name did not fit the wire); the directory names the program by the first 61
    characters, as FANUC's directory read does, and the text keeps the whole comment."""
    name = "N" * 300
    file = tmp_path / "o1701.nc"
    file.write_text(f"O1701 ({name})\nM30\n")
    await cli.ok("program", "load", str(file))
    listed = await cli.json("program", "list")
    entry = next(p for p in listed["programs"] if p["number"] == 1701)
    assert entry["name"] == name[:61]
    assert (await cli.json("program", "show", "1701"))["text"].startswith(f"O1701 ({name})")


async def test_fleet_poll_counts_each_poll_of_an_unreachable_machine_as_failed() -> None:
    """examples/fleet_poll.py: with one machine of two unreachable, 3 rounds are 6 polls of
    which 3 failed (it printed "6 polls ..., 1 failed")."""
    async with serving() as gone:
        dead = gone.port
    async with serving() as live:
        code, out, err = await run_example(
            "fleet_poll.py", "--ports", f"{live.port},{dead}", "--rounds", "3", "--interval", "0"
        )
    assert (code, err) == (1, "")
    assert "3 round(s): 6 polls of 3 calls each, 3 failed" in out.splitlines()[-1]


def test_a_machine_file_of_more_programs_than_the_store_holds_names_the_entry(
    tmp_path: Path,
) -> None:
    entries = "".join(f'[[program]]\ntext = "O{n}\\nM30\\n"\n' for n in range(1, 402))
    with pytest.raises(MachineFileError) as refused:
        _load(tmp_path, entries)
    assert str(refused.value).endswith(
        "m.toml: program[400]: the store holds its maximum of 400 programs"
    )


@pytest.mark.parametrize(
    ("text", "run", "parts"),
    [
        ("O0400\n(ONLY A COMMENT)\n", 0, 0),
        ("O0400\nG1 X1. F600\n%\n", 0, 0),
        ("O0400\nG1 X1. F600\nM99\n", 3, 0),
        ("O0400\nG1 X1. F600\nM02\n", 0, 1),
    ],
)
def test_how_a_main_program_ends_as_docs_machine_file_says(text: str, run: int, parts: int) -> None:
    clock = ManualClock()
    machine = default_machine(sim_clock=clock, programs=(text,))
    machine.select_program(400)
    machine.cycle_start()
    clock.advance(20.0)
    assert (machine.status().run, machine.read_param(6711, 0)) == (run, parts)
    assert machine.active_alarms() == [] and list(machine.alarm_history()) == []


@pytest.mark.parametrize(
    ("body", "words"),
    [
        ('state = "a\\u0000b"\n', "machine.state: 'a\\x00b': a folder name has no NUL character"),
        (
            '[[program]]\nfile = "a\\u0000b"\n',
            "program[0].file: 'a\\x00b': a file name has no NUL character",
        ),
    ],
)
def test_a_nul_in_a_file_or_folder_name_is_refused_with_its_key(
    tmp_path: Path, body: str, words: str
) -> None:
    """Both read as Python's bare "embedded null byte", naming neither file nor key."""
    with pytest.raises(MachineFileError) as refused:
        _load(tmp_path, body)
    assert str(refused.value).endswith(f"m.toml: {words}")
