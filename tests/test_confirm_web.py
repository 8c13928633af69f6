"""A confirming new-user pass over the web dashboard, machine files and part programs: the
cases it found, each checked where the fix lives."""

from __future__ import annotations

from collections.abc import AsyncIterator
from pathlib import Path
from typing import Any

import pytest
from cli_support import Cli
from examples_support import port_args, run_example
from support import serving

from focas_net.cli import EXIT_CNC
from focas_net.errors import EW
from focas_net.sim import MachineError, MachineFileError, default_machine, load_machine
from focas_net.web import Dashboard, Station, perform, stations_of
from focas_net.web.view import pmc_window

HEAD = '[machine]\nname = "M"\naxes = ["X", "Y"]\n'


@pytest.mark.parametrize(
    ("key", "value", "words"),
    [
        ("program_running", 10000, "motion.program_running: 10000 is outside 0..9999"),
        ("program_main", 123456789, "motion.program_main: 123456789 is outside 0..9999"),
        ("sequence", 123456, "motion.sequence: 123456 is outside 0..99999"),
    ],
)
def test_a_program_or_sequence_number_of_the_motion_table_has_fanucs_digits(
    tmp_path: Path, key: str, value: int, words: str
) -> None:
    """O1..O9999 and N1..N99999 (0: none), as a program's own O and N words are read: a
    machine file's ``[motion]`` shows no number a program could not have."""
    path = tmp_path / "m.toml"
    path.write_text(f"{HEAD}[motion]\n{key} = {value}\n", encoding="utf-8")
    with pytest.raises(MachineFileError) as refused:
        load_machine(path)
    assert words in str(refused.value)


@pytest.mark.parametrize(
    ("key", "value", "words"),
    [
        ("program_running", 10000, "program_running = 10000 outside 0..9999"),
        ("program_main", -1, "program_main = -1 outside 0..9999"),
        ("sequence", 100000, "sequence = 100000 outside 0..99999"),
    ],
)
def test_set_motion_refuses_the_same_numbers(key: str, value: int, words: str) -> None:
    machine = default_machine()
    before = machine.motion
    numbers: dict[str, Any] = {key: value}
    with pytest.raises(MachineError) as refused:
        machine.set_motion(**numbers)
    assert refused.value.ew == EW.DATA
    assert words in str(refused.value)
    assert machine.motion == before


def test_the_motion_tables_largest_numbers_load(tmp_path: Path) -> None:
    path = tmp_path / "m.toml"
    body = "[motion]\nprogram_running = 9999\nprogram_main = 9999\nsequence = 99999\n"
    path.write_text(HEAD + body, encoding="utf-8")
    motion = load_machine(path).motion
    assert (motion.program_running, motion.program_main, motion.sequence) == (9999, 9999, 99999)


@pytest.mark.parametrize(
    ("axis", "words"),
    [
        ("9", "parameter 1320 is an axis parameter: give --axis 1..3, got 9"),
        ("-1", "parameter 1320 is an axis parameter: give --axis 1..3, got -1"),
        ("0", "parameter 1320 is an axis parameter: give --axis 1..3, got 0"),
    ],
)
async def test_write_param_names_an_axis_the_cnc_has_not(axis: str, words: str) -> None:
    """``--axis 9`` of a three-axis machine was ``EW_ATTRIB (4): data attribute / data type
    error: cnc_rdparam``, naming neither the axis nor the axes there are."""
    async with serving() as server:
        argv = ["--param", "1320", "--axis", axis, "--value", "5000"]
        code, _out, err = await run_example("write_param_with_unlock.py", *port_args(server), *argv)
        assert code == 2 and "Traceback" not in err
        assert words in err
        assert (server.machine.panel.mode, server.machine.panel.pwe) == (1, 0)


@pytest.mark.parametrize(("start", "shown"), [(8000, "R8000"), (65535, "R65535")])
def test_a_pmc_address_beyond_its_area_is_refused_in_one_set_of_words(
    start: int, shown: str
) -> None:
    """The page's PMC window said ``R8000 is outside R0..R7999`` and a click on a bit of the
    same address ``R address 8000 outside 0..7999``: both are the machine's words now (an
    address no request carries, -1 or 65536, is refused before, as the command line refuses
    it: tests/test_pass9_web.py)."""
    station = Station(0, default_machine())
    words = f"{shown} goes past the end of PMC area R (R0..R7999)"
    with pytest.raises(MachineError) as read:
        pmc_window(station.machine, "R", start)
    with pytest.raises(MachineError) as clicked:
        perform(station, "pmc_bit", {"area": "R", "address": start, "bit": 0, "value": 1})
    with pytest.raises(MachineError) as direct:
        station.machine.read_pmc("R", start, 1)
    for refused in (read, clicked, direct):
        assert (refused.value.ew, refused.value.detail) == (EW.NUMBER, words)


def test_a_pmc_range_running_past_its_area_names_the_area() -> None:
    with pytest.raises(MachineError) as refused:
        default_machine().write_pmc("R", 7999, b"\0\0")
    assert refused.value.detail == "R7999..R8000 goes past the end of PMC area R (R0..R7999)"


@pytest.fixture
async def cli(capsys: pytest.CaptureFixture[str]) -> AsyncIterator[Cli]:
    async with serving(default_machine()) as served:
        yield Cli(served, capsys)


@pytest.mark.parametrize(
    ("content", "words"),
    [
        (b"O0\nM30\n", "program number O0 is outside O1..O9999"),
        (b"%\nO12345678 (BIG)\nM30\n%\n", "program number O12345678 is outside O1..O9999"),
    ],
)
async def test_program_load_of_a_number_beyond_the_store_names_its_range(
    cli: Cli, tmp_path: Path, content: bytes, words: str
) -> None:
    """EW_NUMBER of ``cnc_download`` said ``the number of O0000 is outside the program store's
    range``: it names the number as written and the range, as a machine file's entry does."""
    file = tmp_path / "part.nc"
    file.write_bytes(content)
    line = await cli.fails(EXIT_CNC, "program", "load", str(file))
    assert line.startswith("focas-net: EW_NUMBER (3)")
    assert f"{file}: {words}" in line
    machine_file = tmp_path / "m.toml"
    machine_file.write_text(f"{HEAD}[[program]]\nfile = 'part.nc'\n", encoding="utf-8")
    with pytest.raises(MachineFileError) as refused:
        load_machine(machine_file)
    assert words in str(refused.value)


@pytest.mark.parametrize(
    ("query", "words"),
    [
        (
            "clear_alarms?alm_type=3",
            "/api/machines/0/actions/clear_alarms takes no query key 'alm_type' "
            "(an action's arguments are the keys of its JSON body)",
        ),
        (
            "clear_alarms?path=1",
            "/api/machines/0/actions/clear_alarms takes no query key 'path' "
            "(an action's arguments are the keys of its JSON body)",
        ),
    ],
)
async def test_an_action_refuses_a_query_rather_than_leave_it_unread(
    query: str, words: str
) -> None:
    """``POST .../actions/clear_alarms?alm_type=3`` with no body cleared every alarm: the
    query was never read. An action takes its arguments in its body only."""
    aiohttp = pytest.importorskip("aiohttp", reason="the web dashboard needs aiohttp")
    async with serving() as served:
        served.machine.raise_alarm(0, 0, 100, "kept")
        served.machine.raise_alarm(0, 3, 100, "kept too")
        web = Dashboard(stations_of(served.server), port=0)
        async with web, aiohttp.ClientSession() as session:
            url = f"{web.url}api/machines/0/actions/{query}"
            async with session.post(url, data=b"") as answer:
                assert answer.status == 400
                assert await answer.json() == {"ok": False, "error": words}
        assert len(served.machine.active_alarms()) == 2


async def test_a_machine_the_dashboard_has_not_is_named_alike_by_each_of_its_ends() -> None:
    """The page said ``no machine '5' (this dashboard shows machine 0)``, a read ``no machine
    '5'`` and a subscription ``no machine 5 (the machines are 0..0)``."""
    aiohttp = pytest.importorskip("aiohttp", reason="the web dashboard needs aiohttp")
    async with serving() as served:
        web = Dashboard(stations_of(served.server), port=0)
        async with web, aiohttp.ClientSession() as session:
            async with session.get(f"{web.url}api/machines/5") as answer:
                assert answer.status == 404
                assert await answer.json() == {
                    "ok": False,
                    "error": "no machine '5' (this dashboard shows machine 0)",
                }
            async with session.ws_connect(f"{web.url}ws") as ws:
                await ws.send_str('{"subscribe": "machine", "index": 5}')
                frame = await ws.receive_json(timeout=5)
                assert frame == {
                    "type": "error",
                    "error": "no machine 5 (this dashboard shows machine 0)",
                }
