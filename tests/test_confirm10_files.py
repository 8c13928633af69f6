"""A confirming new-user pass over machine files, part programs and the examples (tenth): a
dwell written in a block with a move, a tab in a program's name, an M98 P of too many digits,
the two-argument ATAN of the 30i, and the examples' number options read as the command line
reads numbers; each checked where the fix lives."""

from __future__ import annotations

import logging
from pathlib import Path

import pytest
from examples_support import port_args, run_example
from support import block_run, serving

from focas_net import FocasClient
from focas_net.protocol import alarm_text
from focas_net.sim import MachineFileError, default_machine, load_machine
from focas_net.sim.nc import (
    Engine,
    ManualClock,
    NcAlarm,
    ProgramError,
    ProgramStore,
    parse_program,
)
from focas_net.sim.nc.macro import Cursor, evaluate, parse_expression

# -- a dwell is a block of its own -------------------------------------------------------------


@pytest.mark.parametrize(
    ("block", "code", "words"),
    [
        ("G1 X10. F100 G4 P1000", "PS5074", "G4 X10. P1000: a dwell takes its time in X or P"),
        ("G4 P1000 X2.", "PS5074", "G4 X2. P1000: a dwell takes its time in X or P"),
        ("G1 Y10. F100 G4 P1000", "PS0009", "G4 with Y10.: a dwell moves no axis"),
        ("G4 X1. Z-5.", "PS0009", "G4 with Z-5.: a dwell moves no axis"),
        ("G0 X1. Y2. G4", "PS0009", "G4 with Y2.: a dwell moves no axis"),
    ],
)
def test_a_dwell_with_a_move_raises_an_alarm_naming_the_words(
    block: str, code: str, words: str
) -> None:
    """The block only dwelled: the move was dropped with no alarm."""
    engine = block_run(block)
    assert engine.alarm is not None
    assert engine.alarm.code == code
    assert words in str(engine.alarm)
    assert "in a block of its own" in str(engine.alarm)
    assert engine.absolute_position() == (0.0, 0.0, 0.0)


@pytest.mark.parametrize("block", ["G4 P1000 F100 S500 M3", "G4 X1.", "G1 X10. F100\nG4 P1000"])
def test_a_dwell_with_its_time_and_no_move_runs(block: str) -> None:
    engine = block_run(block)
    assert engine.alarm is None


# -- a tab in a program's name -------------------------------------------------------------------


@pytest.mark.parametrize(
    ("o_line", "name"),
    [("O13 (A\tTAB)", "ATAB"), ("O13 (\tLEAD)", "LEAD"), ("O13 (TWO\t\tTABS X)", "TWOTABS X")],
)
def test_a_tab_in_the_name_is_disregarded_as_fanuc_reads_iso_ht(o_line: str, name: str) -> None:
    """The tab was kept in the name, so ``program list`` printed it and its table lost its
    columns."""
    store = ProgramStore()
    program = store.store(f"{o_line}\nG0 X1.\nM30\n")
    assert program.name == name
    assert [info.name for info in store.directory()] == [name]
    assert program.text.startswith(f"O0013 ({name})\n")


def _alarm(engine: Engine, code: str) -> NcAlarm:
    """The alarm ``engine`` stopped in, which must be ``code``."""
    alarm = engine.alarm
    assert alarm is not None, "no alarm"
    assert alarm.code == code, str(alarm)
    return alarm


# -- M98 P of more digits than a repeat count and a program number ----------------------------


@pytest.mark.parametrize(
    ("block", "words"),
    [
        ("M98 P123456789", "M98 P123456789: P has at most 8 digits"),
        ("#1 = 100000000\nM98 P#1", "M98 P100000000: P has at most 8 digits"),
        ("M98 P2 L123456789", "L123456789: L has at most 4 digits"),
        ("M98 P2 L10000", "L10000: L has at most 4 digits"),
    ],
)
def test_an_m98_of_too_many_digits_is_ps0003(block: str, words: str) -> None:
    """``M98 P123456789`` ran O6789 12345 times."""
    engine = block_run(block)
    assert str(_alarm(engine, "PS0003")).endswith(words), str(engine.alarm)
    assert engine.absolute_position() == (0.0, 0.0, 0.0)


def test_an_m98_of_eight_digits_repeats_the_program() -> None:
    clock = ManualClock()
    engine = Engine(clock)
    engine.store.store("O1\nM98 P00030002\nM30\n")
    engine.store.store("O2\nG91 G0 X1.\nM99\n")
    engine.store.select(1)
    engine.cycle_start()
    clock.advance(5.0)
    assert engine.alarm is None
    assert engine.absolute_position()[0] == pytest.approx(3.0)


# -- ATAN[a,b], the two-argument form of the 30i ----------------------------------------------


@pytest.mark.parametrize(
    ("expression", "angle"),
    [
        ("ATAN[1,1]", 45.0),
        ("ATAN[1,-1]", 135.0),
        ("ATAN[-1,-1]", 225.0),
        ("ATAN[-1,1]", 315.0),
        ("ATAN[[2-1],[3-2]]", 45.0),
        ("ATAN[1,1]/[1]", 45.0),
    ],
)
def test_atan_of_two_arguments_is_atan_a_over_b(expression: str, angle: float) -> None:
    """FANUC's 30i writes ``ATAN[a,b]`` for ``ATAN[a]/[b]``; it raised PS0114."""
    cur = Cursor(expression)
    expr = parse_expression(cur)
    assert cur.done()
    assert evaluate(expr, lambda _: None) == pytest.approx(angle)


@pytest.mark.parametrize(
    ("expression", "code"),
    [("SIN[1,1]", "PS0114"), ("ATAN[1,1,1]", "PS0114"), ("ATAN[1,]", "PS0114")],
)
def test_a_comma_elsewhere_is_still_a_format_error(expression: str, code: str) -> None:
    engine = block_run(f"#1 = {expression}")
    assert engine.alarm is not None and engine.alarm.code == code


def test_parse_program_reads_atan_of_two_arguments() -> None:
    program = parse_program("O1\n#1 = ATAN[#2, #3]\nM30\n")
    assert [type(b.statement).__name__ for b in program.blocks] == ["Assign", "Words"]


# -- the examples read numbers as the command line does ----------------------------------------


@pytest.mark.parametrize(
    ("name", "args", "words"),
    [
        ("fleet_dashboard.py", ["--speed", "inf"], "--speed: not a number: 'inf'"),
        ("fleet_dashboard.py", ["--interval", "1e1"], "--interval: not a number: '1e1'"),
        ("fleet_dashboard.py", ["--timeout", "nan"], "--timeout: not a number: 'nan'"),
        ("run_program.py", ["--seconds", "1e3"], "--seconds: not a number: '1e3'"),
        ("run_program.py", ["--interval", "0"], "--interval: must be positive, got 0"),
        ("alarm_watch.py", ["--seconds", "1e1"], "--seconds: not a number: '1e1'"),
        ("fleet_poll.py", ["--timeout", "infinity"], "--timeout: not a number: 'infinity'"),
        ("read_status.py", ["--timeout", "2e0"], "--timeout: not a number: '2e0'"),
        ("pmc_bits.py", ["--timeout=-inf"], "--timeout: not a number: '-inf'"),
        ("versamax_config.py", ["--timeout", "1E1"], "--timeout: not a number: '1E1'"),
        ("write_param_with_unlock.py", ["--timeout", "NaN"], "--timeout: not a number: 'NaN'"),
        ("fleet_dashboard.py", ["--speed", "1" + "0" * 400], "--speed: not a number: '1000"),
        ("read_status.py", ["--port", "\u0661"], "--port: '\u0661' holds a digit beyond ASCII"),
        ("pmc_bits.py", ["--bytes", "1_0"], "--bytes: not a whole number: '1_0'"),
        (
            "fleet_poll.py",
            ["--ports", "8193,\u0662"],
            "--ports: not a list of ports: '8193,\u0662'",
        ),
        ("fleet_dashboard.py", ["--ports", "8193;8194"], "--ports: not a list of ports"),
        ("alarm_watch.py", ["--events", "0"], "--events must be at least 1, got 0"),
        ("versamax_config.py", ["--rack", "1.5"], "--rack: not a whole number: '1.5'"),
    ],
)
async def test_an_example_refuses_a_number_the_command_line_refuses(
    name: str, args: list[str], words: str
) -> None:
    """``float()`` took ``1e1``, and ``--speed inf`` ran into a traceback (exit 1)."""
    code, out, err = await run_example(name, *args)
    assert (code, out) == (2, ""), (code, out, err)
    assert "Traceback" not in err and words in err, err


# -- words of program alarms ---------------------------------------------------------------


@pytest.mark.parametrize(
    ("block", "words"),
    [
        ("G4 X-1.", "PS0006 ILLEGAL USE OF NEGATIVE SIGN (O0001): G4 X-1."),
        ("G4 X-500", "PS0006 ILLEGAL USE OF NEGATIVE SIGN (O0001): G4 X-500"),
        ("M98 P10000", "PS0078 NUMBER NOT FOUND (O0001): M98 P10000: no program O0000 (1 time)"),
    ],
)
def test_a_program_alarm_names_the_word_as_written(block: str, words: str) -> None:
    """``G4 X-1.`` was named ``G4 X-1`` (the point lost: a time in increments), and a call of
    one repetition said ``(1 times)``."""
    engine = block_run(block)
    assert str(engine.alarm) == words


@pytest.mark.parametrize(
    ("block", "detail"),
    [
        ("G1 X10. F100 ,C1.", ",C1.: chamfering and corner R (,C and ,R) are not modelled"),
        ("G1 X10. F100 ,R2. Y1.", ",R2.: chamfering and corner R (,C and ,R) are not modelled"),
        ("G0 X1. N10", "N10: a sequence number opens its block"),
        ("G0 X1. $", "'$' is no address (A..Z but N and O)"),
    ],
)
def test_a_character_that_starts_no_word_is_named_with_why(block: str, detail: str) -> None:
    """PS0009's detail was the character alone (``','``, ``'N'``)."""
    assert _alarm(block_run(block), "PS0009").detail == detail


# -- the [[tools]] table of a machine file ------------------------------------------------------


@pytest.mark.parametrize(
    ("tools", "words"),
    [
        (
            "offsets = 10\n[[tools.offset]]\nnumber = 11\n",
            "tools[0].offset[0].number: 11 is outside 1..10",
        ),
        (
            "offsets = 10\n[[tools.offset]]\nnumber = 11\nlength_wear = 1\n",
            "tools[0].offset[0].number: 11 is outside 1..10",
        ),
        (
            "work = { G54 = [inf, 0, 0] }\n",
            "tools[0].work.G54[0]: must be a finite number of millimetres, got inf",
        ),
        (
            "work = { EXT = [0, nan, 0] }\n",
            "tools[0].work.EXT[1]: must be a finite number of millimetres, got nan",
        ),
        (
            "[[tools.offset]]\nnumber = 1\nlength_wear = -inf\n",
            "tools[0].offset[0].length_wear: must be a finite number of millimetres, got -inf",
        ),
    ],
)
def test_a_tools_table_names_the_key_of_a_number_it_cannot_hold(
    tmp_path: Path, tools: str, words: str
) -> None:
    """An offset number past ``offsets`` with no values loaded; ``inf`` raised an
    OverflowError's traceback and ``nan`` was said to have more than 3 decimals."""
    path = tmp_path / "m.toml"
    path.write_text(f'[machine]\nname = "m"\naxes = ["X", "Y", "Z"]\n\n[[tools]]\n{tools}')
    with pytest.raises(MachineFileError) as caught:
        load_machine(path)
    assert str(caught.value) == f"{path}: {words}"


# -- a served machine's program alarm is logged with its detail --------------------------------


def test_a_program_alarm_is_logged_with_what_the_program_said(
    caplog: pytest.LogCaptureFixture,
) -> None:
    """The alarm's detail (the words of the block) reached no front end: the alarm screen,
    the history and the page show FANUC's message alone, so a served machine's user never saw
    why ``G1 X10. F100 G4 P1000`` stopped."""
    clock = ManualClock()
    machine = default_machine(
        sim_clock=clock, programs=("O0001\nN20 G1 X10. F100 G4 P1000\nM30\n",)
    )
    machine.select_program(1)
    with caplog.at_level(logging.WARNING, logger="focas_net"):
        machine.cycle_start()
        clock.advance(5.0)
        assert len(machine.active_alarms()) == 1
    warned = [r.getMessage() for r in caplog.records if r.levelno == logging.WARNING]
    assert warned == [
        f"{machine.name}: PS5074 ADDRESS DUPLICATION ERROR (O0001 N20): G4 X10. P1000: a dwell "
        "takes its time in X or P (program the move in a block of its own)"
    ]


@pytest.mark.parametrize(
    ("block", "detail"),
    [
        ("IF [1 EQ 1] THEN G0 X1.", "THEN takes one assignment (#i = ...), not 'G0X1.'"),
        ("IF [1 EQ 1] THEN", "THEN takes one assignment (#i = ...), not nothing"),
    ],
)
def test_then_with_no_assignment_says_what_then_takes(block: str, detail: str) -> None:
    """FANUC's IF ... THEN runs one macro statement; an NC block after it said only
    ``expected '#' at 'G0X1.'``."""
    engine = block_run(block)
    assert engine.alarm is not None and engine.alarm.code == "PS0114"
    assert engine.alarm.detail == detail


@pytest.mark.parametrize("typed", [" ", "\t", "  \t "])
def test_a_path_name_of_spaces_is_named_as_typed(tmp_path: Path, typed: str) -> None:
    """It was named after its spaces were dropped: ``''``."""
    path = tmp_path / "m.toml"
    name = typed.replace("\t", "\\t")
    path.write_text(f'[machine]\nname = "m"\n[[path]]\naxes = ["X"]\nname = "{name}"\n')
    with pytest.raises(MachineFileError) as caught:
        load_machine(path)
    assert str(caught.value) == (
        f"{path}: path[0].name: a path's name is 1..32 printable ASCII characters: {typed!r}"
    )


@pytest.mark.parametrize(
    ("second", "words"),
    [
        (
            'address = "A0.1"\nnumber = 2001',
            "message 2001 of A0.1: A0.1 shows message 2000 already",
        ),
        ('address = "A0.2"\nnumber = 2000', "message 2000 of A0.2: message 2000 is given twice"),
    ],
)
def test_an_operator_message_given_twice_says_whether_its_bit_or_its_number(
    tmp_path: Path, second: str, words: str
) -> None:
    """Both said ``number or bit given twice``."""
    path = tmp_path / "m.toml"
    path.write_text(
        '[machine]\nname = "m"\naxes = ["X"]\n\n[pmc.A]\nsize = 1\n\n'
        '[[operator_messages]]\naddress = "A0.1"\nnumber = 2000\ntext = "ONE"\n\n'
        f'[[operator_messages]]\n{second}\ntext = "TWO"\n'
    )
    with pytest.raises(MachineFileError) as caught:
        load_machine(path)
    assert str(caught.value) == f"{path}: operator_messages[1]: {words}"


# -- a program of a character beyond ASCII, written through the client ------------------------


@pytest.mark.parametrize(
    ("text", "words"),
    [
        (
            "O7004 (CAF\u00c9)\nM30\n",
            "line 1: character '\u00c9' (U+00C9) in 'O7004 (CAF\u00c9)': a program is printable "
            "ASCII text",
        ),
        (
            "O7005\nG0 X1. (\u2013)\nM30\n",
            "line 2: character '\u2013' (U+2013) in 'G0 X1. (\u2013)': a program is printable "
            "ASCII text",
        ),
    ],
)
async def test_write_program_refuses_a_character_beyond_ascii_in_the_store_s_words(
    text: str, words: str
) -> None:
    """The client said ``program text must be ASCII text: 'O7004 (CAF\u00c9)\\nM30\\n'``
    where ``program load`` and the machine name the line and the character."""
    async with serving() as served, FocasClient(served.host, served.port, timeout=5) as cnc:
        with pytest.raises(ValueError) as caught:
            await cnc.write_program(text)
    assert str(caught.value) == words
    with pytest.raises(ProgramError) as stored:
        served.machine.path_programs().store(text)  # the machine's own words
    assert str(stored.value) == words


# -- a machine file's value of a macro variable the machine computes ---------------------------


@pytest.mark.parametrize(
    ("number", "words"),
    [
        (3901, "#3901 is the parts count, parameter 6711's value: give it there"),
        (3902, "#3902 is the total parts, parameter 6712's value: give it there"),
        (3011, "#3011 is the CNC's clock (the date): the machine keeps it, no file gives it"),
        (3012, "#3012 is the CNC's clock (the time): the machine keeps it, no file gives it"),
    ],
)
def test_a_value_of_a_variable_the_machine_computes_is_refused(
    tmp_path: Path, number: int, words: str
) -> None:
    """``values = { 3901 = 5 }`` loaded and was never seen: #3901 reads the parts count."""
    path = tmp_path / "m.toml"
    path.write_text(
        '[machine]\nname = "m"\naxes = ["X"]\n\n[macros]\n'
        f"ranges = [{{ first = {number}, last = {number} }}]\nvalues = {{ {number} = 5 }}\n"
    )
    with pytest.raises(MachineFileError) as caught:
        load_machine(path)
    assert str(caught.value) == f"{path}: macros.values.{number}: {words}"


# -- alarm_watch writes an alarm as every front end writes it ----------------------------------


async def test_alarm_watch_writes_an_axis_alarm_as_every_front_end_does() -> None:
    """It wrote ``OT0500 axis 1 OVER TRAVEL ( +1 )`` where the command line and the page write
    ``alarm_text``'s ``OT0500 (axis 1) ...``, with the message a control gives OT0500."""
    async with serving() as served:
        code, out, err = await run_example(
            "alarm_watch.py", *port_args(served), "--interval", "0.05", "--events", "6"
        )
    assert (code, err) == (0, "")
    raised = alarm_text(4, 500, "+ OVERTRAVEL ( SOFT 1 )", 1)
    assert raised == "OT0500 (axis 1) + OVERTRAVEL ( SOFT 1 )"
    assert any(line.endswith(f"raised   {raised}") for line in out.splitlines()), out
    assert any(line.endswith(f"UTC {raised}") for line in out.splitlines()), out


# -- a machine file's name that names no file ---------------------------------------------------
@pytest.mark.parametrize(
    ("name", "said"),
    [
        ("", "an empty name is no file or folder, got ''"),
        ("  ", "an empty name is no file or folder, got '  '"),
        ("mill\0.toml", "a file name holds no NUL character, got 'mill\\x00.toml'"),
    ],
)
def test_load_machine_refuses_a_name_that_names_no_file_as_the_cli_does(
    name: str, said: str
) -> None:
    """``load_machine("")`` said ``: cannot read: is a directory`` and a NUL raised Python's
    ``embedded null byte``: the command line's words, from the rule ``load_config`` uses."""
    with pytest.raises(MachineFileError) as refused:
        load_machine(name)
    assert str(refused.value) == said
