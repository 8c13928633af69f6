"""What a new user runs into, fifth pass: the command line as a child process against a real
server (127.0.0.1, ephemeral port), its exit codes and its one-line messages.

Each test names what a user typed and what the command must say.
"""

from __future__ import annotations

import re
from functools import partial
from pathlib import Path

import pytest
from cli_support import at, ok
from cli_support import fails as cli_fails
from support import Served

from focas_net.cli import EXIT_CNC, EXIT_USAGE
from focas_net.protocol import FaultKind, FaultScope
from focas_net.server.faults import fault_refusal
from focas_net.sim import default_machine
from focas_net.web.operations import ActionError, Station, perform

#: A refusal of this pass, a usage error (``focas-net watch: error: ...``) among them.
fails = partial(cli_fails, prefix="focas-net")


# -- a poll interval: 0.05 s .. one hour, and each refusal with its own reason -------------------


@pytest.mark.parametrize("command", [["watch", "--count", "1"], ["alarms", "--follow"]])
@pytest.mark.parametrize(
    ("value", "reason"),
    [
        ("inf", "not a number: 'inf' (no NaN or infinity: write the digits)"),
        ("1e9", "not a number: '1e9' (no exponent: write the digits)"),
        ("3600.5", "must be 0.05..3600 seconds, got 3600.5"),
        ("0.01", "must be 0.05..3600 seconds, got 0.01"),
        ("-1", "must be 0.05..3600 seconds, got -1"),
        ("nan", "not a number: 'nan' (no NaN or infinity: write the digits)"),
    ],
)
async def test_a_poll_interval_out_of_range_says_why(
    server: Served, command: list[str], value: str, reason: str
) -> None:
    line = await fails(EXIT_USAGE, *command, "--interval", value, *at(server))
    assert f"argument --interval: {reason};" in line, line


@pytest.mark.parametrize(
    ("value", "reason"),
    [
        ("inf", "not a number: 'inf' (no NaN or infinity: write the digits)"),
        ("0", "must be positive, got 0"),
    ],
)
async def test_a_timeout_out_of_range_says_why(server: Served, value: str, reason: str) -> None:
    line = await fails(EXIT_USAGE, "status", "--timeout", value, *at(server))
    assert f"argument --timeout: {reason};" in line, line


async def test_an_hour_is_the_longest_poll_interval(server: Served) -> None:
    assert "frame 1" in await ok("watch", "--count", "1", "--interval", "3600", *at(server))


# -- an alarm's message: optional (the alarm is named by its code), at most 32 characters kept ---


@pytest.mark.parametrize("message", [[], [""]])
async def test_an_alarm_without_a_message_is_named_by_its_code(
    server: Served, message: list[str]
) -> None:
    assert await ok("sim", "alarm", "EX1003", *message, *at(server)) == "raised EX1003\n"
    (alarm,) = server.machine.active_alarms()
    assert (alarm.alm_no, alarm.msg) == (1003, "")
    assert "  EX1003\n" in await ok("alarms", *at(server))


async def test_a_long_alarm_message_is_kept_as_the_machine_keeps_it(server: Served) -> None:
    typed = "SPINDLE OVERHEAT ON THE LEFT SIDE OF THE HEAD"
    out = await ok("sim", "alarm", "EX1001", typed, *at(server))
    assert out == f"raised EX1001 {typed[:32]}\n"
    assert [a.msg for a in server.machine.active_alarms()] == [typed[:32]]


def test_the_docs_say_why_an_alarm_may_have_no_message() -> None:
    doc = (Path(__file__).parent.parent / "docs" / "cli.md").read_text()
    assert "The message may be left out" in doc and "not checked on a control" in doc


# -- a fault's arguments are refused in the server's words (server.faults.fault_refusal) --------


@pytest.mark.parametrize(
    ("argv", "numbers"),
    [
        (["delay", "--arg", "99999"], (FaultKind.DELAY, 1, 99999)),
        (["delay", "--arg", "-1"], (FaultKind.DELAY, 1, -1)),
        (["error", "--arg", "0"], (FaultKind.ERROR, 1, 0)),
        (["error", "--arg", "40000"], (FaultKind.ERROR, 1, 40000)),
        (["drop", "--count", "100000"], (FaultKind.DROP, 100000, 0)),
        (["drop", "--count", "0"], (FaultKind.DROP, 0, 0)),
    ],
)
async def test_a_faults_arguments_are_refused_in_the_servers_words(
    server: Served, argv: list[str], numbers: tuple[FaultKind, int, int]
) -> None:
    kind, count, arg = numbers
    reason = fault_refusal(int(kind), int(FaultScope.MACHINE), count, arg)
    assert reason is not None
    line = await fails(EXIT_USAGE, "sim", "fault", *argv, *at(server), prefix="focas-net")
    assert line.endswith(reason) or f"{reason};" in line, line
    assert await ok("sim", "faults", *at(server)) == "no pending faults of this machine\n"


# -- a macro value refused names the variable, on both transports --------------------------------


@pytest.mark.parametrize("protocol", ["packed", "native"])
@pytest.mark.parametrize(
    ("value", "words"),
    [
        ("abc", "#100: not a number: 'abc'"),
        ("1e999", "#100: not a number: '1e999' (no exponent: write the digits)"),
        ("nan", "#100: not a number: 'nan' (no NaN or infinity: write the digits)"),
    ],
)
async def test_a_macro_value_refused_names_the_variable(
    server: Served, protocol: str, value: str, words: str
) -> None:
    line = await fails(
        EXIT_USAGE,
        "macro",
        "set",
        "100",
        value,
        "--protocol",
        protocol,
        *at(server),
        prefix="focas-net",
    )
    assert line == (
        f"focas-net macro set: error: argument VALUE: {words}; see focas-net macro set --help"
    ), line


# -- digits are ASCII everywhere a number is typed (the page's rule, the machine file's) ---------


@pytest.mark.parametrize(
    ("argv", "words"),
    [
        (["pmc", "write", "R", "0", "\u0661"], "'\u0661' holds a digit beyond ASCII"),
        (["pmc", "read", "R", "0", "\u0662"], "'\u0662' holds a digit beyond ASCII"),
        (
            ["macro", "set", "100", "\u0661\u0662"],
            "#100: '\u0661\u0662' holds a digit beyond ASCII ('\u0661', U+0661): write 0-9",
        ),
        (
            ["macro", "set", "100", "\u0661\u0662", "--protocol", "native"],
            "#100: '\u0661\u0662' holds a digit beyond ASCII ('\u0661', U+0661): write 0-9",
        ),
        (["param", "set", "3216", "\u0661"], "'\u0661' holds a digit beyond ASCII"),
    ],
)
async def test_digits_of_other_scripts_are_refused(
    server: Served, argv: list[str], words: str
) -> None:
    before = server.machine.read_pmc("R", 0, 1), server.machine.read_macro(100)
    line = await fails(EXIT_USAGE, *argv, *at(server), prefix="focas-net")
    assert words in line, line
    assert (server.machine.read_pmc("R", 0, 1), server.machine.read_macro(100)) == before


# -- a path the CNC has not is named, whatever the command -----------------------------------------


@pytest.mark.parametrize("protocol", ["packed", "native"])
@pytest.mark.parametrize("command", [["status"], ["macro", "get", "100"], ["program"]])
async def test_a_path_the_cnc_has_not_is_named(
    server: Served, protocol: str, command: list[str]
) -> None:
    line = await fails(EXIT_CNC, *command, "--path", "2", "--protocol", protocol, *at(server))
    assert "EW_PATH" in line and line.endswith(
        "; the CNC has no path 2: it has path 1 only (leave out --path)"
    ), line


# -- a program number is read alike by the command line and the page (O1000, 1000; ASCII) --------


@pytest.mark.parametrize("typed", ["\u0661", "O\u0661", "O", "0", "O123456789"])
async def test_a_program_number_typed_wrong_is_refused(server: Served, typed: str) -> None:
    line = await fails(EXIT_USAGE, "program", "select", typed, *at(server), prefix="focas-net")
    assert line == (
        f"focas-net program: error: argument N|FILE: {typed!r} is not a program number "
        "(O1..O99999999, e.g. O1000); see focas-net program --help"
    ), line


def test_the_page_reads_a_program_number_as_the_command_line() -> None:
    station = Station(0, default_machine())
    assert perform(station, "select_program", {"number": "O0001"}) == {"ok": True}
    assert perform(station, "select_program", {"number": 1}) == {"ok": True}
    with pytest.raises(ActionError, match=re.escape("number: '\u0661' is not a program number")):
        perform(station, "select_program", {"number": "\u0661"})
