"""A confirming new-user pass over machine files, part programs and the examples: the cases it
found, each checked where the fix lives (the interpreter's M, S and T codes)."""

from __future__ import annotations

from pathlib import Path

import pytest
from examples_support import port_args, run_example
from support import block_run, serving

from focas_net.errors import EW
from focas_net.sim import (
    DataItem,
    Machine,
    MachineError,
    MachineFileError,
    ParamKind,
    Session,
    default_machine,
    load_machine,
)
from focas_net.sim.nc import ManualClock, ProgramError, parse_program

HEAD = '[machine]\nname = "M"\naxes = ["X", "Y"]\n[panel]\nmode = "MDI"\npwe = true\n'


def _load(tmp_path: Path, body: str, clock: ManualClock | None = None) -> Machine:
    path = tmp_path / "m.toml"
    path.write_text(HEAD + body, encoding="utf-8")
    return load_machine(path, sim_clock=clock)


def _refused(tmp_path: Path, body: str) -> str:
    with pytest.raises(MachineFileError) as refused:
        _load(tmp_path, body)
    return str(refused.value)


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
    engine = block_run(block)
    assert engine.alarm is not None
    assert words in str(engine.alarm)


# -- the ranges of the counts and timers a file gives without one --------------------------


@pytest.mark.parametrize(
    ("number", "value", "words"),
    [
        (6711, "-3", "parameters.6711.value: -3 is outside 0..999999999"),
        (6713, "-1", "parameters.6713.value: -1 is outside 0..999999999"),
        (6750, "1000000000", "parameters.6750.value: 1000000000 is outside 0..999999999"),
        (6751, "60000", "parameters.6751.value: 60000 is outside 0..59999"),
        (6758, "-5", "parameters.6758.value: -5 is outside 0..999999999"),
    ],
)
def test_a_count_or_timer_given_without_a_range_has_fanucs(
    tmp_path: Path, number: int, value: str, words: str
) -> None:
    """A file giving a parts count or a run-time parameter without a range took the whole
    two-word range: a parts count of -3, a timer of 60000 ms past the minute loaded."""
    body = f'[parameters.{number}]\ntype = "two-word"\nvalue = {value}\n'
    assert f"m.toml: {words}" in _refused(tmp_path, body)


def test_a_write_of_a_negative_count_or_timer_is_refused(tmp_path: Path) -> None:
    """Written through the wire, -100 minutes of operating time made the timer read -5800 s
    and -7 parts counted on from -7; now EW_DATA as on the built-in machine."""
    clock = ManualClock()
    body = "".join(f'[parameters.{n}]\ntype = "two-word"\n' for n in (6711, 6751, 6752))
    machine = _load(tmp_path, body, clock)
    session = Session()
    for number, value in ((6752, -100), (6751, 60000), (6711, -7)):
        with pytest.raises(MachineError) as refused:
            machine.write_param(session, number, 0, value)
        assert refused.value.ew == EW.DATA
    machine.write_param(session, 6711, 0, 12)
    assert machine.read_param(6711, 0) == 12
    assert machine.read_param(6752, 0) == 0 and machine.read_param(6751, 0) == 0


def test_a_file_may_still_give_a_count_another_range(tmp_path: Path) -> None:
    body = '[parameters.6711]\ntype = "word"\nrange = [-10, 100]\nvalue = -5\n'
    assert _load(tmp_path, body).read_param(6711, 0) == -5
    word = _load(tmp_path, '[parameters.6712]\ntype = "word"\n').param_item(6712)
    assert word is not None and (word.low, word.high) == (0, 32767)


def test_a_machine_built_in_python_takes_the_same_ranges() -> None:
    with pytest.raises(ValueError, match=r"parameter 6711: value -3 is outside 0\.\.999999999"):
        Machine("M", axes=["X"], params=[DataItem(6711, kind=ParamKind.TWO_WORD, values=[-3])])
    machine = Machine("M", axes=["X"], params=[DataItem(6757, kind=ParamKind.TWO_WORD)])
    item = machine.param_item(6757)
    assert item is not None and (item.low, item.high) == (0, 59999)


# -- parameter 1020 without a value ---------------------------------------------------------


def test_parameter_1020_without_a_value_holds_the_axes_letters(tmp_path: Path) -> None:
    """A file giving 1020 without a value was refused for a value it did not give
    (``value: axis X's letter 'X' is 88, not 0``); the value is each axis's letter."""
    machine = _load(tmp_path, '[parameters.1020]\ntype = "byte"\naxis = true\nname = "axis"\n')
    assert [machine.read_param(1020, axis) for axis in (1, 2)] == [88, 89]


def test_a_range_of_1020_that_leaves_out_a_letter_names_the_range(tmp_path: Path) -> None:
    body = '[parameters.1020]\ntype = "byte"\naxis = true\nrange = [65, 88]\n'
    assert "m.toml: parameters.1020.range: 65..88 leaves out axis Y's letter 89" in _refused(
        tmp_path, body
    )


@pytest.mark.parametrize(
    ("value", "words"), [("[88]", "1 value for 2 axes"), ("[88, 89, 90]", "3 values for 2 axes")]
)
def test_a_list_of_values_of_another_length_is_counted_in_words(
    tmp_path: Path, value: str, words: str
) -> None:
    body = f'[parameters.1825]\ntype = "word"\naxis = true\nvalue = {value}\n'
    assert f"parameters.1825.value: {words}" in _refused(tmp_path, body)


# -- the O line ---------------------------------------------------------------------------


@pytest.mark.parametrize("o_line", ["O1O2", "O1 O2", ":1 O2", "O1 (NAME) O2"])
def test_an_o_line_holding_a_second_o_number_is_refused(tmp_path: Path, o_line: str) -> None:
    """``O1O2`` loaded as O1 with a block ``O2``, stored as ``O0001`` / ``O2`` / ...: a text
    the program store itself refuses as two programs, so the machine's own text could not be
    loaded again (a download of the upload, a state file)."""
    with pytest.raises(ProgramError, match="starts a second program: one program per text"):
        parse_program(f"{o_line}\nM30\n")
    message = _refused(tmp_path, f'[[program]]\ntext = "{o_line}\\nM30\\n"\n')
    assert "m.toml: program[0].text: line 1: " in message and "starts a second program" in message


def test_an_o_line_with_a_block_is_stored_as_a_text_that_loads_again() -> None:
    program = parse_program("O1 G90 (O2 IN A COMMENT)\nM30\n")
    assert program.number == 1 and program.blocks[0].text == "G90 (O2 IN A COMMENT)"
    assert parse_program(program.text).text == program.text


# -- a path's kind from mt_type -----------------------------------------------------------


@pytest.mark.parametrize(
    ("mt_type", "kind"),
    [("MT", "T"), ("mt", "T"), ("T ", "T"), (" W", "M"), (" P", "M"), ("  ", "M")],
)
def test_a_t_series_code_makes_a_lathe(tmp_path: Path, mt_type: str, kind: str) -> None:
    """FANUC's ODBSYS codes: " T" a lathe, "TT" a lathe of 2/3 paths, "MT" a T series control
    with the compound machining function; "MT" made machining centres."""
    head = f'[machine]\nname = "L"\naxes = ["X", "Z"]\n[sysinfo]\nmt_type = "{mt_type}"\n'
    path = tmp_path / "l.toml"
    path.write_text(head, encoding="utf-8")
    assert load_machine(path).path_info(1).kind == kind


# -- the examples -------------------------------------------------------------------------


async def test_run_program_names_a_program_stopped_in_its_middle() -> None:
    """A machine stopped in the middle of its program (M0; a scenario's tool-change wait)
    made run_program end with ``EW_BUSY (-1): busy, retry: cnc_search``: a retry never helps
    until a reset; it says so, before storing anything."""
    clock = ManualClock()
    machine = default_machine(sim_clock=clock, programs=("O0400\nM0\nM30\n",))
    machine.select_program(400)
    machine.cycle_start()
    clock.advance(5.0)
    assert machine.status().run == 1
    async with serving(machine) as served:
        code, out, err = await run_example("run_program.py", *port_args(served))
    assert (code, out) == (1, "")
    assert err == (
        "run_program: the CNC stopped in the middle of a program (run STOP): reset it first "
        "(focas-net sim cycle reset)\n"
    )


async def test_write_param_with_unlock_names_a_wrong_password() -> None:
    """A wrong ``--password`` ended with ``EW_PASSWD (17): protection / password error:
    cnc_wrunlockparam``, where ``focas-net unlock`` says the password is not the CNC's; the
    example names the password typed, and puts the panel back."""
    machine = default_machine(param_password="5810")
    async with serving(machine) as served:
        code, out, err = await run_example(
            "write_param_with_unlock.py", *port_args(served), "--password", "0000"
        )
    assert code == 1
    assert err.endswith("; --password '0000' is not the CNC's parameter password\n")
    assert out.endswith("panel: mode restored, PWE off\n")
    assert machine.read_param(1320, 1) != 500_000


@pytest.mark.parametrize(
    ("block", "alarm"),
    [
        ("G91 G1 X99999999. F100", 3),
        ("#1 = 1000000\nG0 X#1", 3),
        ("G20 G0 X100000.", 3),
        ("G1 X999999.999 F100000", None),
        ("G20 G0 X99999.9999", None),
    ],
)
def test_an_axis_word_has_at_most_nine_digits(block: str, alarm: int | None) -> None:
    """``X99999999.`` (99999999 mm) ran a move of two years at F100; an axis word beyond the
    9 digits of a number in least input increments is PS0003, as its literal of 10 digits
    already was."""
    engine = block_run(block, 0.01)
    if alarm is None:
        assert engine.alarm is None
    else:
        assert engine.alarm is not None and engine.alarm.code == "PS0003"
        assert "an axis word has at most 9 digits" in str(engine.alarm)


# -- operator messages --------------------------------------------------------------------

_A_AREA = "[pmc.A]\nsize = 4\n"


@pytest.mark.parametrize(
    ("messages", "words"),
    [
        (
            [("A4.0", 2000, "X")],
            "operator_messages[0]: A4.0 is outside the A area (A0.0..A3.7)",
        ),
        (
            [("A0.1", 2000, "X"), ("A0.2", 2000, "Y")],
            "operator_messages[1]: ",
        ),
        (
            [("A0.1", 2000, "X"), ("A0.1", 2001, "Y")],
            "operator_messages[1]: ",
        ),
        (
            [("A0.1", 2000, "TAB\\tHERE")],
            "operator_messages[0].text: a message is printable ASCII, got 'TAB\\tHERE'",
        ),
        ([("A0.1", 2000, "")], "operator_messages[0].text: a message is 1..255 characters"),
    ],
)
def test_an_operator_message_refused_is_named_by_its_entry(
    tmp_path: Path, messages: list[tuple[str, int, str]], words: str
) -> None:
    """The machine's checks of the messages (the A area, a number or a bit twice, the text)
    named only ``operator_messages``, not which entry nor its key."""
    body = _A_AREA + "".join(
        f'[[operator_messages]]\naddress = "{a}"\nnumber = {n}\ntext = "{t}"\n'
        for a, n, t in messages
    )
    assert f"m.toml: {words}" in _refused(tmp_path, body)
