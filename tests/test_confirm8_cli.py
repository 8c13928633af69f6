"""A confirming new-user pass over the command line (eighth): an alarm code of a type with no
name, as the command prints it (``T31:0005``), is taken back; an ``--axis`` past the path's
axes is told in the machine's words (``the path has 2 axes``) by every command, ``sim alarm``
too; ``serve --machine`` of a file that cannot be read names the option.

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

PROTOCOLS = ("packed", "native")
#: The example machine of two paths: two axes per turret, four in all.
LATHE = Path(__file__).resolve().parent.parent / "examples" / "lathe_2path.toml"


@pytest.fixture
async def lathe() -> AsyncIterator[Served]:
    async with serving(load_machine(LATHE)) as served:
        yield served


# -- an alarm code as the command prints it ----------------------------------------------------


async def test_an_alarm_of_a_type_with_no_name_is_taken_as_printed(server: Served) -> None:
    """``sim alarm T31:0005`` was "not an alarm code", though ``alarms`` prints it so."""
    raised = json.loads(await ok("sim", "alarm", "T31:0005", "X", "--json", *at(server)))
    assert raised["raised"]["code"] == "T31:0005"
    assert (raised["raised"]["alm_type"], raised["raised"]["alm_no"]) == (31, 5)
    listed = json.loads(await ok("alarms", "--json", *at(server)))
    code = listed["active"][0]["code"]
    assert code == "T31:0005"
    again = await ok("sim", "alarm", code.lower(), *at(server))
    assert again.startswith("T31:0005 is already active: X"), again
    cleared = json.loads(await ok("sim", "clear", code, "--json", *at(server)))
    assert [a["code"] for a in cleared["alarms"]] == ["T31:0005"]


@pytest.mark.parametrize("given", ["T:5", "TT3:1", "T3:"])
async def test_a_bad_code_of_that_form_is_still_refused_naming_it(
    server: Served, given: str
) -> None:
    line = await fails(EXIT_USAGE, "sim", "alarm", given, *at(server), prefix="focas-net")
    assert repr(given) in line or given in line, line


# -- --axis past the path's axes: the machine's words -------------------------------------------


async def test_sim_alarm_past_the_paths_axes_agrees_with_the_machine(lathe: Served) -> None:
    """It said "... the path has 2 axes); the machine has no axis 3" on a machine of 4."""
    line = await fails(EXIT_CNC, "sim", "alarm", "SV0411", "x", "--axis", "3", "--path", "2",
                       *at(lathe))  # fmt: skip
    assert line.startswith("focas-net: EW_ATTRIB (4)"), line
    assert "the machine has" not in line, line
    assert line.endswith(
        "the path has 2 axes); give --axis 1..2 (or --axis 0: an alarm of no axis)"
    ), line


@pytest.mark.parametrize("protocol", PROTOCOLS)
@pytest.mark.parametrize(
    "argv",
    [
        ("param", "get", "1420", "--axis", "3", "--path", "2"),
        ("param", "get", "1020", "--axis", "5"),
        ("position", "--axis", "3", "--path", "2", "--kind", "machine"),
    ],
)
async def test_an_axis_past_the_path_is_the_paths_on_both_transports(
    lathe: Served, protocol: str, argv: tuple[str, ...]
) -> None:
    line = await fails(EXIT_CNC, *argv, *at(lathe), "--protocol", protocol)
    assert line.endswith("is outside 1..2: the path has 2 axes); give --axis 1..2"), line


# -- serve --machine of a file that cannot be read ---------------------------------------------


@pytest.mark.parametrize("given", ["/nonexistent/lathe.toml", "/"])
async def test_serve_names_the_machine_option_of_a_file_it_cannot_read(given: str) -> None:
    line = await fails(EXIT_USAGE, "serve", "--port", "0", "--machine", given, prefix="focas-net")
    assert line.startswith(f"focas-net serve: error: --machine {given}: "), line
    assert line.endswith(("no such file or directory", "is a directory")), line


@pytest.mark.parametrize(("command", "given"), [("alarm", "T32:0005"), ("clear", "32:5")])
async def test_a_type_past_31_is_refused_in_the_range_a_code_can_have(
    server: Served, command: str, given: str
) -> None:
    """It said "outside -1..31": -1 (every type) is no type a code can name."""
    line = await fails(EXIT_USAGE, "sim", command, given, *at(server), prefix="focas-net")
    assert line == (
        f"focas-net sim {command}: error: argument ALARM: alarm type 32 is outside 0..31; "
        f"see focas-net sim {command} --help"
    ), line


# -- the advice of a refusal on path 2 acts on path 2 --------------------------------------------


async def test_the_advice_of_a_refusal_names_the_path_it_was_refused_on(lathe: Served) -> None:
    """The advice said ``focas-net sim panel --mode MDI --pwe on``, which sets path 1's panel:
    followed as printed, path 2's write was refused again."""
    two = ("--path", "2", *at(lathe))
    line = await fails(EXIT_CNC, "param", "set", "6711", "3", *two)
    assert "(focas-net sim panel --mode MDI --pwe on --path 2)" in line, line
    await ok("sim", "panel", "--mode", "MDI", "--pwe", "on", *two)
    assert "(written)" in await ok("param", "set", "6711", "3", *two)
    line = await fails(EXIT_CNC, "sim", "cycle", "start", *two)
    assert line.endswith("(focas-net sim panel --mode MEM --path 2)"), line
    line = await fails(EXIT_CNC, "program", "select", "2001", *two)
    assert line.endswith("(focas-net sim panel --mode MEM --path 2)"), line
    await ok("sim", "panel", "--mode", "MEM", *two)
    line = await fails(EXIT_CNC, "program", "select", "1001", *two)
    assert line.endswith(
        "no program O1001 on path 2 (O1001 is on path 1: focas-net program select O1001)"
    ), line
    # path 1 (given or not): the advice acts on the path that holds it
    line = await fails(EXIT_CNC, "program", "select", "2001", *at(lathe))
    assert line.endswith(
        "no program O2001 on path 1 (O2001 is on path 2: focas-net program select O2001 --path 2)"
    ), line
    line = await fails(EXIT_CNC, "program", "select", "3001", *at(lathe))
    assert line.endswith("no program O3001 (focas-net program list)"), line


# -- sim clear: the alarm cleared named by its code --------------------------------------------


@pytest.mark.parametrize(
    ("typed", "named"), [(" ps100 ", "PS0100"), ("3:100", "PS0100"), ("ps", "PS")]
)
async def test_sim_clear_names_what_it_cleared_by_its_code(
    server: Served, typed: str, named: str
) -> None:
    """``--json`` said ``"cleared": " ps100 "``, the text as typed, where docs/cli.md gives
    the code (``"PS0100" | "PS" | "all"``)."""
    await ok("sim", "alarm", "PS0100", *at(server))
    cleared = json.loads(await ok("sim", "clear", typed, "--json", *at(server)))
    assert cleared["cleared"] == named
    assert [a["code"] for a in cleared["alarms"]] == ["PS0100"]
    line = await fails(1, "sim", "clear", typed, *at(server))
    assert line == f"focas-net: no active alarm matches {named}; nothing cleared", line
