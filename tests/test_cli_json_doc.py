"""The ``--json`` table of ``docs/cli.md`` is what the commands print: each row's object names
the top-level keys of its command's output, read from the page and compared with a run of the
command against the built-in machine (in-process, one server)."""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any, Final

import pytest
from cli_support import Cli
from support import Served

DOC: Final = Path(__file__).resolve().parent.parent / "docs" / "cli.md"

#: The command each row is checked with (by the row's first name), in the page's order; a row
#: whose output needs more than one run to show (``--follow``) or a changed machine is left out.
RUNS: Final[dict[str, tuple[str, ...]]] = {
    "status": ("status",),
    "sysinfo": ("sysinfo",),
    "program": ("program",),
    "position": ("position",),
    "param get": ("param", "get", "1320", "--axis", "1"),
    "macro get": ("macro", "get", "100"),
    "diag": ("diag", "300", "--axis", "1"),
    "pmc read": ("pmc", "read", "R", "0", "2"),
    "pmc write": ("pmc", "write", "R", "0", "1"),
    "pmc bit": ("pmc", "bit", "R", "0.1"),
    "alarms": ("alarms",),
    "watch": ("watch", "--count", "1"),
    "unlock": ("unlock", "0"),
    "versamax": ("versamax", "0", "1"),
    "sim panel": ("sim", "panel"),
    "sim alarm": ("sim", "alarm", "PS0123", "TEST"),
    "sim cycle start": ("sim", "cycle", "reset"),
    "sim override": ("sim", "override"),
    "program list": ("program", "list"),
    "program show": ("program", "show", "1"),
    "program load": ("program", "load", "{file}"),
    "program delete": ("program", "delete", "777"),
    "program select": ("program", "select", "1"),
    "sim clear": ("sim", "clear"),
    "sim fault": ("sim", "fault", "delay", "--arg", "1"),
    "sim faults": ("sim", "faults"),
}
#: Keys a row names that the run of :data:`RUNS` does not print (they come with other input).
OPTIONAL: Final[dict[str, set[str]]] = {
    "param get": {"type", "bits", "decimals", "bit", "bit_value"},
    "alarms": {"history"},
    "watch": {"paths"},
}
_CELL: Final = re.compile(r"(?<!\\)\|")
_CODE: Final = re.compile(r"`([^`]*)`")


def top_level_keys(obj: str) -> set[str]:
    """The keys of the outer object of a row's ``{"a", "b": {...}}``: each quoted name right
    after its ``{`` or a ``,`` at the outer depth."""
    keys: set[str] = set()
    depth, previous = 0, ""
    for m in re.finditer(r'"[^"]*"|[{}\[\],:]|\S', obj):
        token = m[0]
        if token in "{[":
            depth += 1
        elif token in "}]":
            depth -= 1
        elif token.startswith('"') and depth == 1 and previous in "{,":
            keys.add(token.strip('"'))
        previous = token
    return keys


def documented() -> dict[str, set[str]]:
    """The first name of each row of the JSON table, and the keys of its first object."""
    text = DOC.read_text()
    table = text[text.index("| Command | Object |") :].split("\n\n")[0]
    rows: dict[str, set[str]] = {}
    for line in table.splitlines()[2:]:
        cells = _CELL.split(line)
        names, objects = _CODE.findall(cells[1]), _CODE.findall(cells[2])
        first = next((o for o in objects if o.startswith("{")), None)
        if names and first is not None:
            rows[names[0]] = top_level_keys(first)
    return rows


def test_the_key_reader() -> None:
    assert top_level_keys('{"a", "b": {"c", "d"}, "e": [{"f"}], "g": "x" \\| "y"}') == {
        "a",
        "b",
        "e",
        "g",
    }


def test_every_row_is_checked() -> None:
    rows = documented()
    assert set(RUNS) <= set(rows)
    assert set(rows) - set(RUNS) == {"alarms --follow"}


async def test_every_command_prints_the_documented_keys(
    server: Served, capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    program = tmp_path / "o0777.nc"
    program.write_text("O0777\nG0 X1.\nM30\n")
    cli = Cli(server, capsys)
    rows = documented()
    for name, argv in RUNS.items():
        out = await cli.ok(*(a.format(file=program) for a in argv), "--json")
        data: Any = json.loads(out)
        assert isinstance(data, dict), (name, out)
        printed, doc = set(data), rows[name]
        assert printed <= doc, (name, printed - doc)
        assert doc - printed <= OPTIONAL.get(name, set()), (name, doc - printed)
