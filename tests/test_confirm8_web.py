"""A confirming new-user pass over the web dashboard: the page's refusals and values compared
with the command line's for the same machine, each case checked where the fix lives."""

from __future__ import annotations

from collections.abc import AsyncIterator
from typing import Any

import pytest
from cli_support import Cli, fails
from support import serving
from web_support import page_refusal

from focas_net.cli import EXIT_CNC, EXIT_USAGE
from focas_net.sim import default_machine
from focas_net.web import Station, machine_view


@pytest.fixture
async def cli(capsys: pytest.CaptureFixture[str]) -> AsyncIterator[Cli]:
    async with serving(default_machine()) as served:
        yield Cli(served, capsys)


def _page_refusal(action: str, args: dict[str, Any]) -> str:
    """What the page says of ``action`` refused (the machine's reason or the argument's)."""
    station = Station(0, default_machine())
    station.machine.set_panel(1, 1, None)  # MDI, PWE on: only the refusal under test is left
    return page_refusal(station, action, args)


@pytest.mark.parametrize(
    ("argv", "action", "args", "words"),
    [
        (
            ("program", "select", "10000"),
            "select_program",
            {"number": 10000},
            "program number 10000 outside 1..9999",
        ),
        (
            ("program", "select", "O1234"),
            "select_program",
            {"number": "O1234"},
            "no program O1234",
        ),
    ],
)
async def test_a_program_search_is_refused_in_the_stores_words_on_both(
    cli: Cli, argv: tuple[str, ...], action: str, args: dict[str, Any], words: str
) -> None:
    """``program select 10000`` said ``no program O10000`` where the page said ``program
    number 10000 outside 1..9999``: both say the store's words now."""
    line = await cli.fails(EXIT_CNC, *argv)
    assert line.startswith("focas-net: EW_NUMBER (3)") and words in line
    assert _page_refusal(action, args) == words


@pytest.mark.parametrize(
    ("argv", "action", "args", "words"),
    [
        (
            ("param", "set", "99999", "1"),
            "write_param",
            {"number": 99999, "value": "1"},
            "parameter number 99999 is outside 0..32767",
        ),
        (
            ("param", "set", "--", "-5", "1"),
            "write_param",
            {"number": -5, "value": "1"},
            "parameter number -5 is outside 0..32767",
        ),
        (
            ("macro", "set", "99999", "1"),
            "write_macro",
            {"number": 99999, "value": "1"},
            "macro variable number 99999 is outside -32768..32767",
        ),
        (
            ("macro", "set", "--", "-40000", "1"),
            "write_macro",
            {"number": "-40000", "value": "1"},
            "macro variable number -40000 is outside -32768..32767",
        ),
    ],
)
async def test_a_number_no_cnc_field_holds_is_refused_in_one_set_of_words(
    cli: Cli, argv: tuple[str, ...], action: str, args: dict[str, Any], words: str
) -> None:
    """The page said ``no parameter 99999`` / ``no macro variable #99999`` where the command
    line says the number is outside what the CNC's field holds."""
    line = await cli.fails(EXIT_USAGE, *argv, prefix="focas-net")
    assert f": {words}; see focas-net " in line, line
    assert _page_refusal(action, args) == f"number: {words}"


@pytest.mark.parametrize("which", ["feed", "spindle"])
async def test_a_negative_override_is_refused_in_the_machines_words(which: str) -> None:
    """``sim override --feed -1`` said ``must not be negative, got -1`` where the page (and
    ``--feed 300``) say the override's range; the parser refuses it, naming the option."""
    words = f"{which} override -1 outside 0..254 %"
    line = await fails(EXIT_USAGE, "sim", "override", f"--{which}", "-1", prefix="focas-net")
    assert line == (
        f"focas-net sim override: error: argument --{which}: {words}; "
        "see focas-net sim override --help"
    )
    assert _page_refusal("overrides", {which: -1}) == words


async def test_the_pages_status_names_each_label_as_status_json_does(cli: Cli) -> None:
    """Each ODBST field's screen label is ``name`` in ``status --json`` and was ``label`` in
    the page's view: one key now, with the same value and meaning."""
    data = await cli.json("status")
    rows = machine_view(0, cli.served.machine, 0)["status"]
    assert {r["field"]: (r["value"], r["name"], r["meaning"]) for r in rows} == {
        f: (d["value"], d["name"], d["meaning"]) for f, d in data.items()
    }
    assert all("label" not in r for r in rows)
