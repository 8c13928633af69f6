"""A new user's ninth pass over the command line: ``serve --workers`` without a fleet naming
``--fleet``, ``sim clear`` naming the path it looked on (and where the alarm is), a path the
CNC has not named with the machine's real paths, every override refusal naming its option.

Each test runs ``focas-net`` as a user does (a subprocess) and checks its one line and its
exit code.
"""

from __future__ import annotations

import json
from collections.abc import AsyncIterator
from pathlib import Path
from typing import Final

import pytest
from cli_support import at, fails, ok
from support import Served, serving

from focas_net.cli import EXIT_CNC, EXIT_USAGE
from focas_net.sim import load_machine

PROTOCOLS: Final = (["--protocol", "packed"], ["--protocol", "native"])
#: The example machine of two paths.
LATHE: Final = Path(__file__).resolve().parent.parent / "examples" / "lathe_2path.toml"


@pytest.fixture
async def lathe() -> AsyncIterator[Served]:
    async with serving(load_machine(LATHE)) as served:
        yield served


# -- serve --workers without --fleet ------------------------------------------------------------


async def test_workers_without_a_fleet_asks_for_fleet() -> None:
    """``serve --workers 2`` alone said "no more than the 1 machine of --fleet", though no
    ``--fleet`` was given: it says that --workers spreads a fleet, and how to give one."""
    line = await fails(EXIT_USAGE, "serve", "--workers", "2", "--port", "0", prefix="focas-net")
    assert line == (
        "focas-net serve: error: argument --workers: 2 workers spread a fleet over processes, "
        "and the fleet is 1 machine (without --fleet): give --fleet N (at least 2 machines); "
        "see focas-net serve --help"
    ), line


async def test_workers_past_the_fleet_still_names_both() -> None:
    line = await fails(
        EXIT_USAGE, "serve", "--fleet", "2", "--workers", "3", "--port", "0", prefix="focas-net"
    )
    assert "--workers: at most 64, and no more than the 2 machines of --fleet, got 3" in line, line


# -- sim clear on a machine of several paths ---------------------------------------------------


async def test_sim_clear_without_path_names_the_path_it_looked_on_and_where_the_alarm_is(
    lathe: Served,
) -> None:
    """``sim clear SV0411`` looked on path 1 only and said "no active alarm matches" while
    SV0411 was active on path 2: it clears on the path of ``--path``, as ``sim alarm``
    raises there (a CNC's RESET clears the alarms of the path selected), and says so."""
    await ok("sim", "alarm", "SV0411", "--path", "2", *at(lathe))
    line = await fails(EXIT_CNC, "sim", "clear", "SV0411", *at(lathe))
    assert line == (
        "focas-net: no active alarm matches SV0411 on path 1; nothing cleared (SV0411 is "
        "active on path 2: focas-net sim clear SV0411 --path 2)"
    ), line
    assert lathe.machine.active_alarms(path=2), "the alarm of path 2 must stay"
    cleared = await ok("sim", "clear", "SV0411", "--path", "2", *at(lathe))
    assert cleared == "cleared SV0411 on path 2; 0 still active on path 2\n", cleared
    assert not lathe.machine.active_alarms(path=2)


async def test_sim_clear_all_on_a_machine_of_several_paths_names_the_path(
    lathe: Served,
) -> None:
    await ok("sim", "alarm", "EX1001", "--path", "2", *at(lathe))
    said = await ok("sim", "clear", *at(lathe))
    assert said == "no active alarms on path 1; nothing to clear (1 active on path 2)\n", said
    data = json.loads(await ok("sim", "clear", "--json", "--path", "2", *at(lathe)))
    assert [a["code"] for a in data["alarms"]] == ["EX1001"]
    assert data["active"] == []


async def test_sim_clear_on_a_machine_of_one_path_says_no_path(server: Served) -> None:
    """A machine of one path prints what it printed before: no path named."""
    line = await fails(EXIT_CNC, "sim", "clear", "SV0411", *at(server))
    assert line == "focas-net: no active alarm matches SV0411; nothing cleared", line
    await ok("sim", "alarm", "SV0411", *at(server))
    assert await ok("sim", "clear", "SV0411", *at(server)) == "cleared SV0411; 0 still active\n"


# -- a path the CNC has not: the machine's real paths -------------------------------------------


@pytest.mark.parametrize("protocol", PROTOCOLS)
@pytest.mark.parametrize(
    "command", [["status"], ["sysinfo"], ["param", "get", "1420", "--axis", "1"]]
)
async def test_a_path_past_a_two_path_machines_names_its_paths(
    lathe: Served, protocol: list[str], command: list[str]
) -> None:
    """``--path 3`` on a machine of two paths said "a CNC of one path has path 1"."""
    line = await fails(EXIT_CNC, *command, "--path", "3", *protocol, *at(lathe))
    assert line == (
        "focas-net: EW_PATH (11): path number error (cnc_setpath); the CNC has no path 3: "
        "it has paths 1..2 (give --path 1..2)"
    ), line


async def test_a_path_past_a_one_path_machine_says_it_has_one(server: Served) -> None:
    line = await fails(EXIT_CNC, "sim", "alarm", "SV0411", "--path", "2", *at(server))
    assert line == (
        "focas-net: EW_PATH (11): path number error (cnc_setpath); the CNC has no path 2: "
        "it has path 1 only (leave out --path)"
    ), line


# -- sim override: every refusal names its option -----------------------------------------------


@pytest.mark.parametrize(
    ("argv", "words"),
    [
        (["--feed", "255"], "argument --feed: feed override 255 outside 0..254 %"),
        (["--feed", "-1"], "argument --feed: feed override -1 outside 0..254 %"),
        (["--spindle", "300"], "argument --spindle: spindle override 300 outside 0..254 %"),
        (
            ["--rapid", "7"],
            "argument --rapid: rapid override 7 is not a step of FANUC's: 0 (F0), 25, 50 or 100 %",
        ),
        (["--feed", "abc"], "argument --feed: not a whole number: 'abc'"),
    ],
)
async def test_every_override_refusal_names_its_option(
    server: Served, argv: list[str], words: str
) -> None:
    before = server.machine.overrides()
    line = await fails(EXIT_USAGE, "sim", "override", *argv, *at(server), prefix="focas-net")
    assert line == (f"focas-net sim override: error: {words}; see focas-net sim override --help"), (
        line
    )
    assert server.machine.overrides() == before


# -- a program number refused says what one is ---------------------------------------------------


@pytest.mark.parametrize("typed", ["0", "O0", "-5", "O100000000"])
async def test_a_program_number_refused_gives_the_range(server: Served, typed: str) -> None:
    """``program show 0`` said "'0' is not a program number (e.g. O1000)", not why."""
    line = await fails(EXIT_USAGE, "program", "show", typed, *at(server), prefix="focas-net")
    assert line == (
        f"focas-net program: error: argument N|FILE: {typed!r} is not a program number "
        "(O1..O99999999, e.g. O1000); see focas-net program --help"
    ), line


# -- NUMBER.BIT without its number ----------------------------------------------------------------


@pytest.mark.parametrize("command", [["param", "get"], ["param", "set", "--axis", "1"]])
async def test_a_bit_without_its_number_says_so(server: Served, command: list[str]) -> None:
    """``param get .4`` said "got '.4' (nothing typed)", though '.4' was typed."""
    line = await fails(
        EXIT_USAGE,
        *command,
        ".4",
        *(["1"] if "set" in command else []),
        *at(server),
        prefix="focas-net",
    )
    assert "got '.4' (no number before the dot); see" in line, line
