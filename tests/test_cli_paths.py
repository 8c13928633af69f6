"""``--path`` and ``watch`` on a machine of two paths, through ``focas-net`` as a process."""

from __future__ import annotations

import json
from collections.abc import AsyncIterator

import pytest
from cli_support import run_focas_net
from support import Served, serving, two_path_lathe

from focas_net.cli import EXIT_CNC, EXIT_OK, EXIT_USAGE


@pytest.fixture
async def lathe() -> AsyncIterator[Served]:
    async with serving(two_path_lathe()) as served:
        yield served


def _at(served: Served) -> tuple[str, ...]:
    return ("--host", served.host, "--port", str(served.port))


async def test_path_chooses_the_path_read(lathe: Served) -> None:
    base = ("program", "--json", *_at(lathe))
    code, out, err = await run_focas_net(*base)
    assert (code, err) == (EXIT_OK, "")
    one = json.loads(out)
    code, out, err = await run_focas_net(*base, "--path", "2")
    assert (code, err) == (EXIT_OK, "")
    two = json.loads(out)
    assert (one["program_running"], two["program_running"]) == (1, 2)
    assert (one["feed"], two["feed"]) == (1500, 700)


async def test_path_positions_name_the_path_axes(lathe: Served) -> None:
    code, out, _ = await run_focas_net("position", "--json", "--path", "2", *_at(lathe))
    assert code == EXIT_OK
    assert "X2" in out and "C2" in out and "X1" not in out


async def test_a_path_the_machine_lacks_is_a_cnc_error(lathe: Served) -> None:
    code, out, err = await run_focas_net("status", "--path", "3", *_at(lathe))
    assert code == EXIT_CNC
    assert out == "" and "EW_PATH" in err


@pytest.mark.parametrize(
    ("given", "why"),
    [
        ("11", "path 11 is outside 1..10"),
        ("0", "path 0 is outside 1..10"),
        ("two", "not a path number: 'two'"),
    ],
)
async def test_a_bad_path_is_a_usage_error(given: str, why: str) -> None:
    code, out, err = await run_focas_net("status", "--path", given)
    assert code == EXIT_USAGE and out == ""
    assert f"argument --path: {why}" in err


async def test_watch_shows_every_path(lathe: Served) -> None:
    code, out, err = await run_focas_net("watch", "--count", "1", *_at(lathe))
    assert (code, err) == (EXIT_OK, "")
    lines = out.splitlines()
    assert lines[0].endswith("frame 1  2 paths")
    assert "path 1" in lines and "path 2" in lines
    second = lines.index("path 2")
    assert any("O0001" in line for line in lines[:second])
    assert any("O0002" in line for line in lines[second:])


async def test_watch_json_has_an_entry_per_path(lathe: Served) -> None:
    code, out, err = await run_focas_net("watch", "--json", "--count", "1", *_at(lathe))
    assert (code, err) == (EXIT_OK, "")
    frame = json.loads(out)
    assert [p["path"] for p in frame["paths"]] == [1, 2]
    assert frame["state"] == frame["paths"][0]["state"]
    assert [p["state"]["program_running"] for p in frame["paths"]] == [1, 2]
    assert list(frame["paths"][1]["state"]["positions"]["absolute"]) == ["X2", "Z2", "C2"]


async def test_watch_of_one_path_has_no_path_entries() -> None:
    async with serving() as served:
        code, out, _ = await run_focas_net("watch", "--json", "--count", "1", *_at(served))
    assert code == EXIT_OK
    assert "paths" not in json.loads(out)
