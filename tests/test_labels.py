"""One value, one label, on every front end: the command line (``status``, ``watch``, ``sim
panel``, ``sim cycle``, ``alarms``, ``param get``) and the dashboard name a status field, an
alarm and a parameter's type from the same tables of :mod:`focas_net.protocol`."""

from __future__ import annotations

import json
from collections.abc import AsyncIterator
from pathlib import Path
from typing import Any

import pytest
from cli_support import Cli
from support import serving

from focas_net.protocol import ParamDataType, alarm_text
from focas_net.sim import Machine, default_machine, load_machine
from focas_net.web.view import machine_tile, machine_view, param_rows, status_fields

#: The alarms of the tests: an external alarm whose message starts with its code (as the
#: scenarios' alarms do), an axis's alarm, and one whose message does not carry its code.
ALARMS = (
    (0, 15, 1001, "EX1001 COOLANT LEVEL LOW"),
    (1, 6, 411, "SV0411 EXCESS ERROR IN MOVE"),
    (0, 3, 100, "PARAMETER WRITE ENABLE"),
)


def machine_of(tmp_path: Path, mt_type: str) -> Machine:
    """The default machine's kind of machine with ODBSYS ``mt_type``."""
    path = tmp_path / "machine.toml"
    path.write_text(
        f'[machine]\nname = "m"\naxes = ["X", "Y", "Z"]\n[sysinfo]\nmt_type = "{mt_type}"\n'
    )
    return load_machine(path)


@pytest.fixture(params=[" M", " T", "MT"], ids=["M", "T", "compound"])
async def cli(
    request: pytest.FixtureRequest, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> AsyncIterator[Cli]:
    async with serving(machine_of(tmp_path, request.param)) as served:
        yield Cli(served, capsys)


def _named(fields: dict[str, Any]) -> dict[str, tuple[str, str]]:
    return {f: (v["name"], v["meaning"]) for f, v in fields.items()}


async def test_every_front_end_names_the_status_alike(cli: Cli) -> None:
    machine = cli.served.machine
    web = {f["field"]: (f["name"], f["meaning"]) for f in status_fields(machine)}
    status = _named(await cli.json("status"))
    (frame,) = [json.loads(line) for line in (await cli.ok("watch", "--json", "--count", "1"))
                .splitlines()]  # fmt: skip
    watch = _named(frame["state"]["status"])
    panel = _named((await cli.json("sim", "panel"))["status"])
    cycle = _named((await cli.json("sim", "cycle", "reset"))["status"])
    assert status == watch == panel == cycle == web
    assert list(status) == list(web)  # in one order too
    series = machine.identity().mt_type.strip()
    label, meaning = status["tmmode"]
    if series == "MT":
        assert (label, meaning) == ("T", "T mode")  # tmmode 0 of a compound machine
    else:
        assert (label, meaning) == (series, f"{series} series machine (no T/M mode selection)")


async def test_every_front_end_writes_an_alarm_alike(cli: Cli) -> None:
    machine = cli.served.machine
    for alarm in ALARMS:
        machine.raise_alarm(*alarm)
    expected = [alarm_text(t, no, msg, axis) for axis, t, no, msg in ALARMS]
    assert expected == [
        "EX1001 COOLANT LEVEL LOW",  # the code once
        "SV0411 (axis 1) EXCESS ERROR IN MOVE",
        "PS0100 PARAMETER WRITE ENABLE",
    ]
    cli_lines = [line.strip() for line in (await cli.ok("alarms")).splitlines()]
    watch_lines = [line.strip() for line in (await cli.ok("watch", "--count", "1")).splitlines()]
    history = await cli.ok("alarms", "--history", "10")
    view = machine_view(0, machine, 8193)
    tile = machine_tile(0, machine, 8193)
    for text in expected:
        assert text in cli_lines and text in watch_lines
        assert text in history
    assert [a["text"] for a in view["alarms"]] == expected
    assert sorted(h["text"] for h in view["history"]) == sorted(expected)
    assert tile["alarm"] == expected[0]
    for shown in (*cli_lines, *watch_lines, *history.splitlines(), tile["alarm"]):
        assert shown.count("EX1001") <= 1 and shown.count("SV0411") <= 1


@pytest.mark.parametrize("number", [1815, 20, 1420, 3216])
async def test_a_parameter_type_has_one_name(
    number: int, capsys: pytest.CaptureFixture[str]
) -> None:
    machine = default_machine()
    async with serving(machine) as served:
        cli = Cli(served, capsys)
        item = machine.param_item(number)
        assert item is not None and item.kind is not None
        axis = ["--axis", "1"] * item.axis
        shown = await cli.json("param", "get", str(number), *axis)
        text = await cli.ok("param", "get", str(number), *axis)
    (row,) = [r for r in param_rows(machine, str(number)) if r["number"] == number]
    assert "kind" not in row  # the key is the attribute's name: ParamAttributes.type
    assert row["type"] == shown["type"] == ParamDataType(item.kind).label
    assert text.rstrip().endswith(f"{row['type']} parameter"), text


def test_the_docs_and_the_example_files_name_the_types_as_every_front_end() -> None:
    root = Path(__file__).parent.parent
    doc = (root / "docs" / "machine-file.md").read_text()
    for t in ParamDataType:
        assert f"| `{t.label}` |" in doc, t  # the table of the types, a row per type
    assert "2-word" not in doc.replace('`"2-word"`', "")  # named once, as an older spelling
    for example in sorted((root / "examples").glob("*.toml")):
        assert '"2-word"' not in example.read_text(), example


def test_the_dashboard_names_parameter_types_as_the_command_line() -> None:
    kinds = {row["type"] for row in param_rows(default_machine())}
    assert kinds == {"bit", "byte", "word", "two-word"}  # never the enumeration's two_word
    assert {t.label for t in ParamDataType} == {"bit", "byte", "word", "two-word", "real"}
