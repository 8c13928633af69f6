"""A confirming new-user pass over the command line (ninth): ``serve --fleet`` is bounded by
its parser, both ends in one wording; ``gateway --shard`` is checked before the file is read;
``sim alarm`` names the path on a machine of several paths, as ``sim clear`` does; an
``--axis`` past the path's is told once; ``sim clear`` of spaces shows the spaces typed.

Each test runs ``focas-net`` as a user does (a subprocess) and checks its one line and its
exit code."""

from __future__ import annotations

import json
from collections.abc import AsyncIterator
from pathlib import Path

import pytest
from cli_support import at, fails, ok
from support import Served, serving

from focas_net.cli import EXIT_CNC, EXIT_USAGE
from focas_net.sim import load_machine

#: The example machine of two paths.
LATHE = Path(__file__).resolve().parent.parent / "examples" / "lathe_2path.toml"
SERVE_ERROR = "focas-net serve: error: "
GATEWAY_ERROR = "focas-net gateway: error: "


@pytest.fixture
async def lathe() -> AsyncIterator[Served]:
    async with serving(load_machine(LATHE)) as served:
        yield served


# -- serve --fleet: one check, at parse time ---------------------------------------------------


@pytest.mark.parametrize("given", ["0", "10001", "-3"])
async def test_serve_fleet_out_of_range_is_the_parsers_one_wording(given: str) -> None:
    """``--fleet 0`` was the parser's "must be at least 1", ``--fleet 10001`` a later check's
    "at most 10000 machines"."""
    line = await fails(EXIT_USAGE, "serve", "--port", "0", "--fleet", given, prefix=SERVE_ERROR)
    assert line == (
        f"{SERVE_ERROR}argument --fleet: must be 1..10000, got {int(given)}; "
        "see focas-net serve --help"
    ), line


@pytest.mark.parametrize("given", ["0", "65"])
async def test_serve_workers_out_of_range_is_the_parsers_one_wording(given: str) -> None:
    """``--workers 0`` was the parser's "must be at least 1", ``--workers 65`` (with a fleet of
    100) a later check's "at most 64, and no more than the 100 machines of --fleet"."""
    line = await fails(
        EXIT_USAGE, "serve", "--port", "0", "--fleet", "100", "--workers", given,
        prefix=SERVE_ERROR,
    )  # fmt: skip
    assert line == (
        f"{SERVE_ERROR}argument --workers: must be 1..64, got {given}; see focas-net serve --help"
    ), line


# -- gateway: --shard before the file ----------------------------------------------------------


@pytest.mark.parametrize(
    ("given", "words"),
    [
        ("0/2", "the shard must be within 1..2, got '0/2'"),
        ("3/2", "the shard must be within 1..2, got '3/2'"),
        ("1/0", "the number of shards must be 1 or more, got '1/0'"),
    ],
)
async def test_gateway_checks_the_shard_before_reading_the_file(
    tmp_path: Path, given: str, words: str
) -> None:
    """A missing file was reported before the bad ``--shard`` typed with it."""
    missing = str(tmp_path / "none.toml")
    line = await fails(EXIT_USAGE, "gateway", missing, "--shard", given, prefix=GATEWAY_ERROR)
    assert line == f"{GATEWAY_ERROR}argument --shard: {words}; see focas-net gateway --help", line


# -- sim alarm on path 2 names the path ----------------------------------------------------------


async def test_sim_alarm_names_the_path_on_a_machine_of_several(lathe: Served) -> None:
    """``sim alarm EX1001 COOLANT --path 2`` printed ``raised EX1001 COOLANT``, while ``sim
    clear`` names the path there."""
    two = ("--path", "2", *at(lathe))
    line = await ok("sim", "alarm", "EX1001", "COOLANT", *two)
    assert line == "raised EX1001 COOLANT on path 2\n", line
    line = await ok("sim", "alarm", "EX1001", "OTHER", *two)
    assert line.startswith("EX1001 is already active on path 2: COOLANT ("), line
    line = await ok("sim", "alarm", "EX1002", *("--path", "1"), *at(lathe))
    assert line.startswith("raised EX1002 ") and line.endswith(" on path 1\n"), line
    cleared = await ok("sim", "clear", "EX1001", *two)
    assert cleared == "cleared EX1001 on path 2; 0 still active on path 2\n", cleared
    raised = json.loads(await ok("sim", "alarm", "EX1001", "COOLANT", "--json", *two))
    assert raised["raised"]["code"] == "EX1001"


async def test_sim_alarm_on_a_machine_of_one_path_names_none(server: Served) -> None:
    assert await ok("sim", "alarm", "EX1001", "COOLANT", *at(server)) == "raised EX1001 COOLANT\n"


# -- an --axis past the path's: told once ------------------------------------------------------


async def test_sim_alarm_axis_past_the_path_tells_the_count_once(server: Served) -> None:
    line = await fails(EXIT_CNC, "sim", "alarm", "PS0100", "--axis", "33", *at(server))
    assert line.count("the path has 3 axes") == 1, line
    assert line.endswith(
        "the path has 3 axes); give --axis 1..3 (or --axis 0: an alarm of no axis)"
    ), line


# -- sim clear of spaces -----------------------------------------------------------------------


@pytest.mark.parametrize("given", ["   ", "\t"])
async def test_sim_clear_of_spaces_shows_what_was_typed(server: Served, given: str) -> None:
    line = await fails(EXIT_USAGE, "sim", "clear", given, *at(server), prefix="focas-net")
    assert line.startswith(
        f"focas-net sim clear: error: argument ALARM: not an alarm code: {given!r} "
    ), line


# -- pmc: a count refused alike at both ends ---------------------------------------------------


@pytest.mark.parametrize(
    ("given", "words"),
    [
        ("0", "PMC byte count 0 is outside 1..65536 (a PMC range holds one byte at least)"),
        ("100000", "PMC byte count 100000 is outside 1..65536"),
    ],
)
async def test_pmc_count_is_refused_alike_at_both_ends(
    server: Served, given: str, words: str
) -> None:
    """``pmc read R 0 0`` was the parser's "must be at least 1", ``pmc read R 0 100000`` the
    clients' "PMC byte count 100000 is outside 1..65536"."""
    line = await fails(EXIT_USAGE, "pmc", "read", "R", "0", given, *at(server), prefix="focas-net")
    assert line == (
        f"focas-net pmc read: error: argument COUNT: {words}; see focas-net pmc read --help"
    ), line


# -- pmc write --hex: a separator parts whole bytes --------------------------------------------


@pytest.mark.parametrize("given", ["0 1", "1:2", "01 2", "1-02"])
async def test_pmc_write_hex_groups_of_half_a_byte_are_refused(server: Served, given: str) -> None:
    """``--hex "0 1"`` wrote the one byte 01, ``--hex 1:2`` the byte 12: a separator glued two
    halves of bytes together."""
    argv = ("pmc", "write", "R", "0", "--hex", given)
    line = await fails(EXIT_USAGE, *argv, *at(server), prefix="focas-net")
    assert line.startswith(f"focas-net pmc write: error: argument --hex: not hex bytes: {given!r}")
    assert "two digits" in line, line
    assert await ok("pmc", "read", "R", "0", "2", *at(server)) == "R0000  00 00\n"


@pytest.mark.parametrize(("given", "shown"), [("01 ff", "01 ff"), ("0x0102", "01 02")])
async def test_pmc_write_hex_of_whole_bytes_is_written(
    server: Served, given: str, shown: str
) -> None:
    line = await ok("pmc", "write", "R", "0", "--hex", given, *at(server))
    assert line.endswith(f": {shown}\n"), line


# -- gateway "": an empty file name ------------------------------------------------------------


@pytest.mark.parametrize("given", ["", "  "])
async def test_gateway_of_an_empty_file_name_names_it(given: str) -> None:
    """``gateway ""`` said ``: is a directory``, as ``serve --machine ""`` no longer does."""
    line = await fails(EXIT_USAGE, "gateway", given, prefix=GATEWAY_ERROR)
    assert line == (
        f"{GATEWAY_ERROR}argument CONFIG.toml: an empty name is no file or folder, got "
        f"{given!r}; see focas-net gateway --help"
    ), line
