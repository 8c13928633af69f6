"""A new user's tenth pass over the command line: every number-range refusal naming the
number as it was typed (``0x0``, ``0b0``), not the value it was read as; the program
numbers read after the main program is deleted; ``alarms --count`` without ``--follow``;
a switch given a value (``--json=yes``); a PMC range past the last address; an axis
beyond the path's of an item the machine lacks, on both transports.

Each test runs ``focas-net`` as a user does (a subprocess) and checks its one line and its
exit code.
"""

from __future__ import annotations

import json
from typing import Final

import pytest
from cli_support import at, fails, ok
from support import serving

from focas_net.cli import EXIT_CNC, EXIT_USAGE

PROTOCOLS: Final = (["--protocol", "packed"], ["--protocol", "native"])

# -- a refused number named as typed ------------------------------------------------------------


@pytest.mark.parametrize(
    ("argv", "said"),
    [
        (("serve", "--fleet", "0x0"), "argument --fleet: must be 1..10000, got 0x0"),
        (("serve", "--workers", "0b0"), "argument --workers: must be 1..64, got 0b0"),
        (
            ("serve", "--max-connections", "0x0"),
            "argument --max-connections: must be at least 1, got 0x0",
        ),
        (("serve", "--seed", "-0x1"), "argument --seed: must not be negative, got -0x1"),
        (("serve", "--max-frame", "0"), "argument --max-frame: must be at least 4, got 0"),
        (("serve", "--max-frame", "0x2"), "argument --max-frame: must be at least 4, got 0x2"),
        (("watch", "--count", "0o0"), "argument --count: must be at least 1, got 0o0"),
        (("versamax", "0x8", "0"), "argument RACK: must be 0..7, got 0x8"),
    ],
)
async def test_a_range_refusal_names_the_number_as_typed(argv: tuple[str, ...], said: str) -> None:
    """``serve --fleet 0x0`` said ``got 0`` (the value read), which the user never typed:
    every range refusal names the text typed."""
    line = await fails(EXIT_USAGE, *argv, prefix="focas-net")
    assert f"{said}; see" in line, line


@pytest.mark.parametrize(
    ("argv", "said"),
    [
        (
            ("sim", "override", "--feed", "0x100"),
            "argument --feed: 0x100 reads as 256: feed override 256 outside 0..254 %",
        ),
        (
            ("alarms", "--history", "-0x1"),
            "argument --history: -0x1 reads as -1: history depth -1 is below 1",
        ),
        (
            ("param", "get", "1", "--axis", "0x8000"),
            "argument --axis: 0x8000 reads as 32768: axis 32768 is outside 0..32767",
        ),
    ],
)
async def test_a_machine_rule_names_the_value_and_the_text_typed(
    argv: tuple[str, ...], said: str
) -> None:
    """A refusal in the machine's words (an override, an item's axis) names the value it
    checked, and the text typed where the two differ."""
    line = await fails(EXIT_USAGE, *argv, prefix="focas-net")
    assert said in line, line


# -- deleting the selected program --------------------------------------------------------------


async def test_deleting_the_main_program_names_no_program() -> None:
    """``program delete O1`` on a fresh machine deleted its main program, yet ``program``
    still read O0001 as running and main, while ``sim cycle start`` said "no main program is
    selected": the figures name no program once it is deleted, as after a program search
    (on both transports)."""
    async with serving() as served:
        assert await ok("program", "delete", "O1", *at(served)) == "deleted O0001\n"
        shown = [json.loads(await ok("program", "--json", *at(served), *p)) for p in PROTOCOLS]
        line = await fails(EXIT_CNC, "sim", "cycle", "start", *at(served))
    assert [(s["program_running"], s["program_main"]) for s in shown] == [(0, 0), (0, 0)], shown
    assert "no main program is selected" in line, line


# -- alarms: an option of --follow without it ---------------------------------------------------


@pytest.mark.parametrize(
    ("given", "said"),
    [
        (("--count", "2"), "--count applies to --follow (focas-net alarms --follow --count 2)"),
        (
            ("--interval", "5"),
            "--interval applies to --follow (focas-net alarms --follow --interval 5)",
        ),
        (
            ("--count", "2", "--interval", "5"),
            "--count and --interval apply to --follow "
            "(focas-net alarms --follow --count 2 --interval 5)",
        ),
    ],
)
async def test_an_option_of_follow_alone_is_named_as_given(
    given: tuple[str, ...], said: str
) -> None:
    """``alarms --count 2`` said "--count and --interval apply to --follow", naming an
    option not given: the refusal names the options given, and the command that takes them."""
    async with serving() as served:
        line = await fails(EXIT_USAGE, "alarms", *given, *at(served), prefix="focas-net")
    assert line == f"focas-net alarms: error: {said}; see focas-net alarms --help", line


# -- a switch given a value ---------------------------------------------------------------------


@pytest.mark.parametrize(
    ("argv", "said"),
    [
        (("status", "--json=yes"), "argument --json: --json takes no value, got 'yes'"),
        (("sim", "faults", "--clear=1"), "argument --clear: --clear takes no value, got '1'"),
        (("status", "--tls=on"), "argument --tls: --tls takes no value, got 'on'"),
    ],
)
async def test_a_switch_given_a_value_says_it_takes_none(argv: tuple[str, ...], said: str) -> None:
    """``status --json=yes`` said "ignored explicit argument 'yes'", argparse's words for a
    switch written with a value: it says the switch takes no value."""
    line = await fails(EXIT_USAGE, *argv, "--port", "1", prefix="focas-net")
    assert f": error: {said}; see" in line, line


# -- a PMC range past the last address ----------------------------------------------------------


@pytest.mark.parametrize(
    "argv", [("pmc", "read", "R", "65535", "2"), ("pmc", "write", "R", "65534", "1", "2", "3")]
)
async def test_a_pmc_range_past_the_last_address_names_where_it_ends(
    argv: tuple[str, ...],
) -> None:
    """``pmc read R 65535 2`` said "2 PMC bytes from 65535 do not end by 65535", a riddle:
    the refusal names the address the range runs to and the last one there is."""
    async with serving() as served:
        line = await fails(EXIT_USAGE, *argv, *at(served), prefix="focas-net")
    count = len(argv) - 4 if argv[1] == "write" else int(argv[4])
    last = int(argv[3]) + count - 1
    command = f"focas-net pmc {argv[1]}"
    assert line == (
        f"{command}: error: {count} PMC bytes from {argv[3]} run to {last}, "
        f"past 65535 (the last PMC address); see {command} --help"
    ), line


# -- an axis beyond the path's, of an item the machine lacks -------------------------------------


@pytest.mark.parametrize(("command", "number"), [("param", "9999"), ("diag", "9999")])
async def test_an_axis_beyond_the_path_is_refused_alike_on_both_transports(
    command: str, number: str
) -> None:
    """``param get 9999 --axis 9`` on a machine of 3 axes answered EW_NUMBER over the
    packed protocol and EW_ATTRIB (``axis 9 is outside 1..3``) over FOCAS/2, whose client checks the
    axis before sending: the machine checks an axis beyond the path's first too."""
    argv = (command, "get", number) if command == "param" else (command, number)
    async with serving() as served:
        lines = [await fails(EXIT_CNC, *argv, "--axis", "9", *at(served), *p) for p in PROTOCOLS]
    for line in lines:  # (both name the diagnostic read cnc_diagnoss)
        assert line.startswith("focas-net: EW_ATTRIB (4)"), lines
        assert line.endswith(": axis 9 is outside 1..3: the path has 3 axes); give --axis 1..3")
