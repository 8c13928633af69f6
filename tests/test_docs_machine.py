"""What the docs say of machines is what the machines are: the built-in machine of
``docs/machine-file.md`` (its parameters and diagnostics with their types, the demo contour),
and ``examples/machine.toml``, which holds every key of the machine-file schema and loads into
a machine whose program numbers are programs it has."""

from __future__ import annotations

import re
import tomllib
from pathlib import Path
from typing import Any

import pytest
from cli_support import Cli
from support import serving

from focas_net.protocol import ParamDataType
from focas_net.sim import Machine, default_machine, load_machine
from focas_net.sim.nc import ManualClock

ROOT = Path(__file__).resolve().parent.parent
MACHINE_FILE_DOC = ROOT / "docs" / "machine-file.md"
EXAMPLE = ROOT / "examples" / "machine.toml"
#: A type's name in a machine file, for each type: the name every front end gives it.
FILE_TYPES = {t: t.label for t in ParamDataType}


def _section(doc: str, heading: str) -> str:
    """The text of the section of ``doc`` whose heading starts with ``heading``."""
    start = doc.index(f"\n{heading}")
    end = doc.find("\n## ", start + 1)
    return doc[start : end if end >= 0 else len(doc)]


def _items_listed(section: str, bullet: str) -> dict[int, tuple[str, bool]]:
    """``{number: (type, axis)}`` of a bullet of the built-in machine's list, written as
    ``20 byte (0..35), 1005/1006 axis bit, ...``."""
    start = section.index(f"- {bullet}")
    text = section[section.index(": ", start) + 2 : section.index("\n- ", start)]
    text = re.sub(r"\([^)]*\)", "", " ".join(text.split())).rstrip(". ")
    text = text.split("; and ")[0]  # what follows names items listed elsewhere
    listed: dict[int, tuple[str, bool]] = {}
    for entry in text.split(","):
        words = entry.split()
        numbers, type_name = words[0], words[-1]
        for number in numbers.split("/"):
            listed[int(number)] = (type_name, "axis" in words[1:-1])
    return listed


def _items_of(machine: Machine, diagnostics: bool) -> dict[int, tuple[str, bool]]:
    numbers = machine.diag_numbers() if diagnostics else machine.param_numbers()
    found = {}
    for number in numbers:
        item = machine.diag_item(number) if diagnostics else machine.param_item(number)
        assert item is not None and item.kind is not None
        found[number] = (FILE_TYPES[ParamDataType(item.kind)], item.axis)
    return found


def test_the_built_in_machine_is_as_listed() -> None:
    section = _section(MACHINE_FILE_DOC.read_text(), "## The built-in default machine")
    machine = default_machine()
    params = _items_of(machine, diagnostics=False)
    # 9968, 3115, 3106, 3107, 9936 and 6750-6758, which every machine has, are listed in
    # their own section
    every = (9968, 3115, 3106, 3107, 9936)
    assert _items_listed(section, "Parameters") == {
        n: v for n, v in params.items() if n not in every and not 6750 <= n <= 6758
    }
    assert _items_listed(section, "Diagnostics") == _items_of(machine, diagnostics=True)


def test_the_demo_contour_is_the_size_the_docs_give() -> None:
    clock = ManualClock()
    machine = default_machine(sim_clock=clock)
    machine.cycle_start()
    xs, ys = [], []
    for _ in range(2000):  # 0.05 s steps: about 100 s of machine time, the part takes 25
        clock.advance(0.05)
        x, y, _z = machine.motion.absolute
        xs.append(x)
        ys.append(y)
        if machine.status().run == 0:
            break
    assert machine.parts_counts()[0] == 1  # the part was made
    size = f"{(max(xs) - min(xs)) // 1000} x {(max(ys) - min(ys)) // 1000} mm"
    assert size == "80 x 60 mm"
    for doc in (ROOT / "README.md", MACHINE_FILE_DOC):
        assert re.findall(r"\d+ x \d+ mm contour", doc.read_text()) == [f"{size} contour"], doc


def _keys_documented() -> dict[str, set[str]]:
    """For each section of the schema (``machine``, ``parameters``, ``versamax`` ...), the keys
    the first column of its tables names."""
    doc = MACHINE_FILE_DOC.read_text()
    sections = {}
    for match in re.finditer(r"^## `\[\[?([a-z_]+)", doc, re.M):
        body = _section(doc, match.group(0))
        cells = re.findall(r"^\| ([^|]+) \|", body, re.M)
        keys = {k for cell in cells for k in re.findall(r"`([a-z_]+)`", cell)}
        sections[match.group(1)] = keys - {"bit", "byte", "word", "real"}  # the types' table
    return sections


def _keys_given(value: Any, nested: bool) -> set[str]:
    """The keys of a table, or of every table of an array or, when ``nested``, of every
    table of a table (``[parameters.<number>]``)."""
    if isinstance(value, list):
        return {k for entry in value for k in entry}
    if nested:
        return {k for entry in value.values() for k in entry}
    return set(value)


def test_the_example_machine_file_has_every_key_and_every_type() -> None:
    example = tomllib.loads(EXAMPLE.read_text())
    documented = _keys_documented()
    assert set(documented) == set(example) - {"diagnostics"}  # every section, no other
    for section, keys in documented.items():
        nested = section in ("parameters", "pmc")
        given = _keys_given(example[section], nested)
        if section == "parameters":
            given |= _keys_given(example["diagnostics"], nested)
        assert keys <= given, (section, keys - given)
    types = {spec["type"] for spec in example["parameters"].values()}
    assert types == set(FILE_TYPES.values())  # FANUC's names, never the old i16 and i32
    load_machine(EXAMPLE)


async def test_the_example_machine_runs_the_programs_it_has(
    capsys: pytest.CaptureFixture[str],
) -> None:
    async with serving(load_machine(EXAMPLE)) as served:
        cli = Cli(served, capsys)
        numbers = await cli.json("program")
        listed = await cli.json("program", "list")
    stored = {p["number"] for p in (listed if isinstance(listed, list) else listed["programs"])}
    assert numbers["program_main"] in stored
    assert numbers["program_running"] in stored | {0}
