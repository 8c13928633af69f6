"""A new user's pass over machine files, part programs and the examples (pass 9): each test
names a case that was wrong, and the behaviour FANUC's practice asks for."""

from __future__ import annotations

from pathlib import Path

import pytest
from cli_support import fails
from examples_support import port_args, run_example
from support import serving

from focas_net.adapters._native_cnc import path_sysinfo
from focas_net.cli import EXIT_USAGE
from focas_net.sim import (
    Identity,
    Machine,
    MachineError,
    MachineFileError,
    PathSpec,
    default_machine,
    load_machine,
)
from focas_net.sim.nc import CycleState, Engine, ManualClock, NcSettings, parse_program


def _alarm_of(block: str) -> tuple[str, str, int | None]:
    """Run ``block`` as N20 of a program and answer the alarm's code, its text and block."""
    clock = ManualClock()
    engine = Engine(clock, NcSettings())
    main = engine.store.store(f"O12\nN10 G90\nN20 {block}\nN30 G1 X50. F100\nM30\n")
    engine.store.store("O1\nM99\n")
    engine.store.select(main.number)
    engine.cycle_start()
    clock.advance(1.0)
    alarm = engine.alarm
    assert alarm is not None, block
    assert engine.state is CycleState.STOP
    return alarm.code, str(alarm), alarm.sequence


# -- a decimal point on an address that takes none is PS0007 ---------------------------------


@pytest.mark.parametrize(
    ("block", "shown"),
    [
        ("T1.", "T1."),
        ("M3.", "M3."),
        ("S1000.", "S1000."),
        ("M98 P1.", "P1."),
        ("G4 P100.", "P100."),
        ("G43 H1. Z10.", "H1."),
        ("M98 P1 L2.", "L2."),
        ("M3 S-.5", "S-.5"),
        ("T.1", "T.1"),
        ("G41 D1. X1.", "D1."),
    ],
)
def test_a_decimal_point_on_an_address_that_takes_none_is_ps0007(block: str, shown: str) -> None:
    code, text, sequence = _alarm_of(block)
    assert code == "PS0007", text
    assert sequence == 20
    assert shown in text and "decimal point" in text


@pytest.mark.parametrize(
    "block",
    ["G1 X1. F100.", "G4 X1.5", "G2 X10. I5. F100", "G4 P100", "M3 S1000 T1", "#1 = 3.\nN25 M#1"],
)
def test_addresses_that_take_a_decimal_point_or_whole_numbers_run(block: str) -> None:
    clock = ManualClock()
    engine = Engine(clock, NcSettings())
    main = engine.store.store(f"O12\nN10 G90\nN20 {block}\nM30\n")
    engine.store.select(main.number)
    engine.cycle_start()
    for _ in range(100):
        if engine.state is not CycleState.START:
            break
        clock.advance(1.0)
    assert engine.alarm is None, block
    assert engine.state is CycleState.RESET


# -- the comment after the O number is the program's name, not a part of its first block ----


def test_the_o_line_comment_names_the_program_and_is_not_the_first_blocks() -> None:
    program = parse_program("O1234 (DEMO) G0 X1.\nM30\n")
    assert program.name == "DEMO"
    first = program.blocks[0]
    assert (first.text, first.comment) == ("G0 X1.", "")
    # the stored text keeps the comment on the O line, once
    assert program.text == "O1234 (DEMO)\nG0 X1.\nM30\n"
    again = parse_program(program.text)
    assert again.name == "DEMO"
    assert [(b.text, b.comment) for b in again.blocks] == [("G0 X1.", ""), ("M30", "")]


def test_a_comment_later_on_the_o_line_is_its_blocks_not_the_name() -> None:
    program = parse_program("O1234 G0 (FIRST MOVE) X1.\nM30\n")
    assert program.name == ""
    first = program.blocks[0]
    assert (first.text, first.comment) == ("G0 (FIRST MOVE) X1.", "FIRST MOVE")
    again = parse_program(program.text)
    assert [(b.text, b.comment) for b in again.blocks] == [(first.text, first.comment), ("M30", "")]


def test_an_alarm_of_a_block_without_a_sequence_number_shows_no_none() -> None:
    clock = ManualClock()
    engine = Engine(clock, NcSettings())
    engine.store.store("O1\nT1.\nM30\n")
    engine.store.select(1)
    engine.cycle_start()
    clock.advance(1.0)
    assert str(engine.alarm) == (
        "PS0007 ILLEGAL USE OF DECIMAL POINT (O0001): T1.: a T code takes no decimal point"
    )


# -- a lathe of several paths reports "TT", as FANUC's T series of 2/3 paths does -----------

EXAMPLE = Path(__file__).parent.parent / "examples" / "lathe_2path.toml"


def test_the_twin_turret_example_is_a_t_series_of_two_paths() -> None:
    machine = load_machine(EXAMPLE)
    assert machine.identity().mt_type == "TT"
    for path in (1, 2):
        i = machine.path_identity(path)
        assert (i.mt_type, i.axes) == ("TT", "02")
        assert machine.path_info(path).kind == "T"
    # the wire's 0x18 answer of each path is the same identity
    assert path_sysinfo(machine, 2) == machine.path_identity(2)


def test_a_path_of_another_kind_than_the_machines_code_reports_its_own() -> None:
    machine = Machine(
        "mill-turn",
        paths=[PathSpec(("X", "Z"), kind="T"), PathSpec(("X2", "Y2", "Z2"), kind="M")],
        identity=Identity(2, 32, " 0", "TT", "D6F1", "32.0", "05"),
    )
    assert machine.path_identity(1).mt_type == "TT"
    assert (machine.path_identity(2).mt_type, machine.path_identity(2).axes) == (" M", "03")
    with pytest.raises(MachineError):
        machine.path_identity(3)


def test_one_path_reports_the_identity_as_it_is() -> None:
    machine = Machine(
        "lathe", axes=["X", "Z"], identity=Identity(2, 8, " 0", " T", "D6F1", "32.0", "02")
    )
    assert machine.path_identity(1) == machine.identity()


# -- a bit parameter given more than eight bits is told so, not shown another value ---------


@pytest.mark.parametrize("text", ["101100001", "0b101100001", "1_0110_0001"])
def test_more_than_eight_bits_are_named_without_a_made_up_value(tmp_path: Path, text: str) -> None:
    path = tmp_path / "m.toml"
    path.write_text(
        f'[machine]\nname = "m"\naxes = ["X"]\n[parameters.1815]\ntype = "bit"\nvalue = "{text}"\n',
        encoding="utf-8",
    )
    with pytest.raises(MachineFileError) as e:
        load_machine(path)
    message = str(e.value)
    assert f"parameters.1815.value: {text!r} has 9 bits" in message
    # no example made of another value (it said "00001011" and "0b1011" for any of these)
    assert '"00001011"' not in message and '"0b1011"' not in message


# -- a word of too many digits or none names its address ------------------------------------


@pytest.mark.parametrize(
    ("block", "code", "detail"),
    [
        ("G4 P99999999999", "PS0003", "P99999999999: a number has at most 9 digits"),
        ("G00000000001 X1.", "PS0003", "G00000000001: a number has at most 9 digits"),
        ("X" + "9" * 40, "PS0003", "X9999999999999999999...: a number has at most 9 digits"),
        ("G0 X.", "PS0005", "X.: no digits after X"),
        ("G0 Y-.", "PS0005", "Y-.: no digits after Y"),
    ],
)
def test_a_word_of_too_many_digits_or_none_names_its_address(
    block: str, code: str, detail: str
) -> None:
    got, text, _ = _alarm_of(block)
    assert got == code
    assert text.endswith(f"(O0012 N20): {detail}")


# -- the examples check what was typed before they change anything -------------------------


@pytest.mark.parametrize(("count", "shown"), [("0", "0"), ("-3", "-3"), ("100000", "100000")])
async def test_pmc_bits_names_the_byte_count_as_typed_and_writes_nothing(
    count: str, shown: str
) -> None:
    """``--bytes -3`` said ``PMC byte count 0``; ``--bytes 0`` was refused in other words
    (``--bytes must be at least 1``) than ``--bytes 100000``."""
    machine = default_machine()
    before = machine.read_pmc("R", 100, 4)
    async with serving(machine) as served:
        code, out, err = await run_example(
            "pmc_bits.py", *port_args(served), "--area", "R", "--bytes", count
        )
    assert (code, out) == (2, "")
    least = " (a PMC range holds one byte at least)" if int(shown) < 1 else ""
    assert err == f"pmc_bits: PMC byte count {shown} is outside 1..65536{least}\n"
    assert machine.read_pmc("R", 100, 4) == before


async def test_write_param_with_unlock_refuses_a_bad_password_before_touching_the_panel() -> None:
    machine = default_machine()
    async with serving(machine) as served:
        code, out, err = await run_example(
            "write_param_with_unlock.py", *port_args(served), "--password", "12345"
        )
    assert (code, out) == (2, "")
    assert err == (
        "write_param_with_unlock: parameter password '12345': must be 1..4 ASCII characters\n"
    )


async def test_run_program_names_a_program_file_that_is_not_text(tmp_path: Path) -> None:
    """A program file of Latin-1 bytes ended run_program in a UnicodeDecodeError traceback."""
    path = tmp_path / "cafe.nc"
    path.write_bytes(b"O3005 (CAF\xe9)\nM30\n")
    code, out, err = await run_example("run_program.py", "--port", "1", "--program", str(path))
    assert (code, out) == (2, "")
    assert err == (
        f"run_program: {str(path)!r}: line 1: byte 0xE9 is not text: a program is printable "
        "ASCII text\n"
    )


async def test_run_program_says_a_missing_file_as_the_command_line_does(tmp_path: Path) -> None:
    path = tmp_path / "none.nc"
    code, out, err = await run_example("run_program.py", "--port", "1", "--program", str(path))
    assert (code, out) == (2, "")
    assert err == f"run_program: cannot read {str(path)!r}: no such file or directory\n"


def test_one_lathe_path_of_a_machining_centres_code_reports_a_lathe(tmp_path: Path) -> None:
    """A file of one ``[[path]]`` of ``kind = "T"`` (mt_type left " M") answered
    ``cnc_sysinfo`` with " M" where its open answer's path record says " T"."""
    path = tmp_path / "l.toml"
    path.write_text(
        '[machine]\nname = "l"\n[[path]]\naxes = ["X", "Z"]\nkind = "T"\n', encoding="utf-8"
    )
    machine = load_machine(path)
    assert machine.path_info(1).kind == "T"
    assert (machine.path_identity(1).mt_type, machine.path_identity(1).axes) == (" T", "02")
    assert path_sysinfo(machine, 1).mt_type == " T"


# -- a program file is refused in the same words by the machine file and the command line ---


def _program_file_refusal(tmp_path: Path, raw: bytes, name: str = "p.nc") -> str:
    (tmp_path / name).write_bytes(raw)
    path = tmp_path / "m.toml"
    path.write_text(
        f'[machine]\nname = "m"\naxes = ["X"]\n[[program]]\nfile = "{name}"\n', encoding="utf-8"
    )
    with pytest.raises(MachineFileError) as e:
        load_machine(path)
    return str(e.value)


@pytest.mark.parametrize(
    ("raw", "why"),
    [
        (
            b"O5 (CAF\xe9)\nM30\n",
            "line 1: byte 0xE9 in 'O5 (CAF\\xe9)' is not text: a program is printable ASCII text",
        ),
        (
            "O5\n(CAFÉ)\nM30\n".encode(),
            "line 2: character 'É' (U+00C9) in '(CAFÉ)': a program is printable ASCII text",
        ),
    ],
)
async def test_a_program_file_that_is_not_ascii_is_named_alike_everywhere(
    tmp_path: Path, raw: bytes, why: str
) -> None:
    """The machine file said ``not UTF-8 text: ... (save the file as UTF-8)`` of a Latin-1
    file, which saved as UTF-8 is still refused; ``program load`` named the line."""
    message = _program_file_refusal(tmp_path, raw)
    assert message.endswith(f"program[0].file: {str(tmp_path / 'p.nc')!r}: {why}")
    line = await fails(
        EXIT_USAGE, "program", "load", str(tmp_path / "p.nc"), "--port", "1", prefix="focas-net"
    )
    assert line == (
        f"focas-net program: error: argument N|FILE: {str(tmp_path / 'p.nc')!r}: {why}; "
        "see focas-net program --help"
    )


def test_an_empty_program_file_name_is_named_as_empty(tmp_path: Path) -> None:
    """``file = ""`` said ``cannot read '<the folder>': is a directory``."""
    path = tmp_path / "m.toml"
    path.write_text(
        '[machine]\nname = "m"\naxes = ["X"]\n[[program]]\nfile = " "\n', encoding="utf-8"
    )
    with pytest.raises(MachineFileError) as e:
        load_machine(path)
    assert str(e.value).endswith(
        "program[0].file: ' ' names no file: give the path of the program's text"
    )


def test_the_comment_after_the_number_names_the_program_over_one_before_the_o() -> None:
    program = parse_program("(PRE)O1 (NAME)\nM30\n")
    assert program.name == "NAME"
    assert program.text == "O0001 (NAME)\nM30\n"
    assert parse_program("(12)O12\nM30\n").name == "12"  # none after: the one before
