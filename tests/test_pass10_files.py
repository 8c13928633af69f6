"""A new user's pass over machine files, part programs and the examples (pass 10): each test
names a case that was wrong or unsettled, and the behaviour FANUC's practice asks for."""

from __future__ import annotations

import tomllib
from pathlib import Path

import pytest
from examples_support import port_args, run_example
from support import serving

from focas_net.sim import (
    LifeTool,
    Machine,
    MachineFileError,
    ToolGroup,
    ToolsSpec,
    machine_from_dict,
)
from focas_net.sim.nc import (
    CycleState,
    Engine,
    ManualClock,
    NcSettings,
    ProgramError,
    ProgramErrorReason,
    parse_program,
)


def _run(text: str, seconds: float = 30.0) -> Engine:
    """Run ``text`` (its first program) on an engine of its own for ``seconds``."""
    clock = ManualClock()
    engine = Engine(clock, NcSettings())
    main = engine.store.store(text)
    engine.store.select(main.number)
    engine.cycle_start()
    for _ in range(int(seconds)):
        if engine.state is not CycleState.START:
            break
        clock.advance(1.0)
    return engine


# -- several G codes of one group in a block: the last one is valid (FANUC's G code list) ----


@pytest.mark.parametrize(
    ("first", "x"),
    [("G90 G91", 20.0), ("G91 G90", 10.0)],
)
def test_of_two_g_codes_of_one_group_in_a_block_the_last_is_valid(first: str, x: float) -> None:
    engine = _run(f"O1\n{first} G0 X10.\nX10.\nM30\n")
    assert engine.alarm is None
    assert engine.state is CycleState.RESET
    assert engine.absolute_position()[0] == pytest.approx(x)


def test_of_two_motion_codes_in_a_block_the_last_is_the_modal_one() -> None:
    engine = _run("O1\nG1 G0 X10.\nM30\n")  # G0 last: a rapid, no feed rate needed
    assert engine.alarm is None
    assert engine.absolute_position()[0] == pytest.approx(10.0)


def _format_refusal(text: str) -> str:
    """Why ``text`` is no program a CNC stores (a format error, as FANUC's)."""
    with pytest.raises(ProgramError) as caught:
        parse_program(text)
    assert caught.value.reason is ProgramErrorReason.FORMAT
    return str(caught.value)


# -- a comment opened with ( and not closed in its line is refused, naming the line ---------


@pytest.mark.parametrize(
    ("text", "line", "shown"),
    [
        ("O1\nG1 X10. F100 (ROUGH X20.\nM30\n", 2, "'(ROUGH X20.'"),
        ("O1 (NAME\nG0 X1.\nM30\n", 1, "'(NAME'"),
        ("O1\nG0 X1. (A;B\nM30\n", 2, "'(A;B'"),
        ("O1\nG0 X1. (A(B\nM30\n", 2, "'(A(B'"),
        ("%\nO1\nG0 X1.\n(END\nM30\n%\n", 4, "'(END'"),
    ],
)
def test_an_unclosed_comment_is_refused_naming_its_line(text: str, line: int, shown: str) -> None:
    assert _format_refusal(text).startswith(f"line {line}: the comment {shown} has no ')'")


def test_a_closed_comment_and_a_semicolon_in_it_still_load() -> None:
    program = parse_program("O1 (NAME)\nG0 X1. (A;B)\nM30\n")
    assert program.name == "NAME"
    assert [b.comment for b in program.blocks] == ["A;B", ""]


def test_a_machine_file_program_with_an_unclosed_comment_names_the_entry() -> None:
    data = tomllib.loads(
        '[machine]\nname = "m"\naxes = ["X"]\n[[program]]\ntext = "O1\\nG0 X1. (OOPS\\nM30"\n'
    )
    with pytest.raises(MachineFileError) as caught:
        machine_from_dict(data)
    assert "program[0]" in str(caught.value)
    assert "line 2: the comment '(OOPS' has no ')'" in str(caught.value)


# -- a tool in two tool life groups ---------------------------------------------------------

_TOOLS = '[machine]\nname = "m"\naxes = ["X", "Y", "Z"]\n[[tools]]\n'


def _tools_file(body: str) -> Machine:
    return machine_from_dict(tomllib.loads(_TOOLS + body))


_TWO_GROUPS = (
    "[[tools.group]]\nnumber = 1\nlife = 9\ntools = [5, 6]\n"
    "[[tools.group]]\nnumber = 2\nlife = 9\ntools = [7, 5]\n"
)


def test_a_tool_in_two_groups_without_an_ignore_number_is_refused_naming_the_key() -> None:
    with pytest.raises(MachineFileError) as caught:
        _tools_file(_TWO_GROUPS)
    message = str(caught.value)
    assert "tools[0].group[1].tools[1]: T5 is in tool group 1 too" in message
    assert "ignore number" in message


def test_a_tool_in_two_groups_is_refused_by_the_machine_too() -> None:
    groups = [ToolGroup(1, 9, tools=[LifeTool(5)]), ToolGroup(2, 9, tools=[LifeTool(5)])]
    with pytest.raises(ValueError, match="tool group 2: T5 is in tool group 1 too"):
        Machine("m", axes=["X"], tools={1: ToolsSpec(groups=groups)})
    Machine("m", axes=["X"], tools={1: ToolsSpec(groups=groups, ignore=100)})  # named by T


def _changed_to(machine: Machine, clock: ManualClock, t_code: int) -> int:
    machine.store_program(f"O0001\nT{t_code} M6\nM30\n")
    machine.set_panel(1)
    machine.select_program(1)
    machine.cycle_start()
    clock.advance(60)
    return machine.tool_life_info().selected


def test_with_an_ignore_number_a_tool_may_be_in_several_groups() -> None:
    clock = ManualClock()
    data = tomllib.loads(_TOOLS + "ignore_number = 100\n" + _TWO_GROUPS)
    machine = machine_from_dict(data, sim_clock=clock)
    assert _changed_to(machine, clock, 102) == 2  # T102: group 2, which lists T5 too
    assert machine.tool_group(2).count == 1
    assert machine.tool_group(1).count == 0


def test_a_t_code_at_or_below_the_ignore_number_names_no_group() -> None:
    clock = ManualClock()
    data = tomllib.loads(_TOOLS + "ignore_number = 100\n" + _TWO_GROUPS)
    machine = machine_from_dict(data, sim_clock=clock)
    assert _changed_to(machine, clock, 5) == 0  # FANUC: an ordinary tool, no life counted
    assert (machine.tool_group(1).count, machine.tool_group(2).count) == (0, 0)


# -- a tool offset out of range is named in the millimetres the file gives ------------------


@pytest.mark.parametrize(
    ("value", "shown"),
    [("1000.0", "1000.000 mm"), ("-999.9995", None), ("-1000", "-1000.000 mm")],
)
def test_a_tool_offset_beyond_its_range_is_named_in_millimetres(
    value: str, shown: str | None
) -> None:
    body = f"[[tools.offset]]\nnumber = 1\nradius_wear = {value}\n"
    with pytest.raises(MachineFileError) as caught:
        _tools_file(body)
    message = str(caught.value)
    if shown is None:  # a fourth decimal is named first, as typed
        assert "has more than 3 decimals" in message
    else:
        assert f"tool offset 1 radius_wear: {shown} is beyond 999.999 mm" in message
        assert "1000000" not in message


# -- a second sign is PS0006 naming the word, not "no value" -------------------------------


@pytest.mark.parametrize(
    ("block", "shown"),
    [("G0 X--1.", "X--1."), ("G0 X+-1.", "X+-1."), ("G1 X1. F--100", "F--100"), ("M--3", "M--3")],
)
def test_a_second_sign_is_ps0006_naming_the_word(block: str, shown: str) -> None:
    engine = _run(f"O1\nN10 {block}\nM30\n")
    assert engine.alarm is not None
    assert engine.alarm.code == "PS0006"
    assert f"{shown}: a value takes one sign" in str(engine.alarm)


def test_a_sign_with_nothing_after_it_is_still_no_data() -> None:
    engine = _run("O1\nN10 G0 X-\nM30\n")
    assert engine.alarm is not None and engine.alarm.code == "PS0005"


# -- the examples refuse a NaN, infinite or negative number of seconds ----------------------


@pytest.mark.parametrize(
    ("name", "args", "words"),
    [
        ("alarm_watch.py", ["--seconds", "nan"], "--seconds: not a number: 'nan' (no NaN"),
        ("alarm_watch.py", ["--interval", "inf"], "--interval: not a number: 'inf' (no NaN"),
        ("fleet_poll.py", ["--interval", "-1"], "--interval must be 0 or more seconds, got -1"),
        ("fleet_poll.py", ["--interval", "nan"], "--interval: not a number: 'nan' (no NaN"),
    ],
)
async def test_an_example_refuses_seconds_that_are_no_time(
    name: str, args: list[str], words: str
) -> None:
    code, out, err = await run_example(name, "--port", "1", *args)
    assert code == 2
    assert out == ""
    assert words in err and "Traceback" not in err


# -- run_program says a program that ends without M30 ended, not that it stopped early -------


async def test_run_program_says_a_program_without_m30_ended_with_no_part(tmp_path: Path) -> None:
    path = tmp_path / "o17.nc"
    path.write_text("O17 (NO END)\nG0 X1.\n")
    async with serving() as served:
        code, out, err = await run_example(
            "run_program.py", *port_args(served), "--program", str(path), "--seconds", "20"
        )
    assert code == 1, err
    assert "O0017 stored and selected" in out
    assert "O0017 ended in reset at N0 with no part counted: it has no M02 or M30" in err
    assert "before its end" not in err


# -- a program number on the % line is not lost in silence -----------------------------------


@pytest.mark.parametrize(
    ("text", "line", "shown"),
    [
        ("%O1\nM30\n%\n", 1, "'%O1'"),
        ("%O1\nO2\nM30\n%\n", 1, "'%O1'"),
        ("O1\nM30\n%O2\n", 3, "'%O2'"),
    ],
)
def test_a_program_number_on_the_percent_line_is_refused(text: str, line: int, shown: str) -> None:
    assert _format_refusal(text).startswith(
        f"line {line}: {shown}: the rest of a % line is not read"
    )


def test_a_percent_line_with_a_comment_or_spaces_still_loads() -> None:
    assert parse_program("% \nO1\nM30\n%\n").number == 1
    assert parse_program("%(HEADER)\nO1\nM30\n%\n").number == 1


# -- an alarm writes a number as the screen does: no exponent, no digits lost ----------------


@pytest.mark.parametrize(
    ("block", "shown"),
    [
        ("G0 X99999999.", "X99999999: an axis word has at most 9 digits"),
        ("G4 X-1234.5678", "G4 X-1234.5678"),
        ("#1=TAN[90]", "TAN[90]"),
        ("#1=SQRT[-2.5]", "SQRT[-2.5]"),
        ("G1 X1. F-1234.5678", "F-1234.5678"),
    ],
)
def test_an_alarm_writes_the_number_as_the_screen_does(block: str, shown: str) -> None:
    engine = _run(f"O1\nN10 {block}\nM30\n")
    assert engine.alarm is not None
    text = str(engine.alarm)
    assert shown in text
    assert "e+" not in text and ".0]" not in text


def test_an_overtravel_names_the_stroke_limit_with_every_digit() -> None:
    clock = ManualClock()
    limits = ((-10.0, 1234.567), None, None)
    engine = Engine(clock, NcSettings(stroke_limits=limits))
    engine.store.store("O1\nG90 G1 X2000. F60000\nM30\n")
    engine.store.select(1)
    engine.cycle_start()
    clock.advance(10.0)
    assert engine.alarm is not None and engine.alarm.code == "OT0500"
    assert "would pass its stroke limit 1234.567" in str(engine.alarm)


# -- a macro value of the machine file that does not fit is refused in the clients' words ----


@pytest.mark.parametrize(
    ("value", "key", "shown"),
    [
        ("99999999999", "macros.values.500", "99999999999"),
        ("[-2147483649, 2]", "macros.values.500[0]", "-2147483649"),
    ],
)
def test_a_macro_value_that_does_not_fit_is_named_as_the_clients_name_it(
    value: str, key: str, shown: str
) -> None:
    text = (
        '[machine]\nname = "m"\naxes = ["X"]\n[macros]\n'
        f"ranges = [{{ first = 500, last = 999 }}]\nvalues = {{ 500 = {value} }}\n"
    )
    with pytest.raises(MachineFileError) as caught:
        machine_from_dict(tomllib.loads(text))
    assert f"{key}: {shown} does not fit a macro variable" in str(caught.value)
