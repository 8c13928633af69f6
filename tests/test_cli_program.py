"""``focas-net program list|show|load|delete|select`` and ``sim cycle``/``sim override``
against a real server whose machine runs on a hand-stepped clock."""

from __future__ import annotations

from collections.abc import AsyncIterator
from pathlib import Path

import pytest
from cli_support import Cli
from support import serving

from focas_net.cli._args import EXIT_CNC, EXIT_USAGE
from focas_net.sim import default_machine
from focas_net.sim.nc import ManualClock

PROGRAM = "O0300 (FACE)\nN10 G90 G21 S800 M3\nN20 G1 X20. F1200\nN30 M30\n"


@pytest.fixture
def clock() -> ManualClock:
    return ManualClock()


@pytest.fixture
async def cli(capsys: pytest.CaptureFixture[str], clock: ManualClock) -> AsyncIterator[Cli]:
    async with serving(default_machine(sim_clock=clock)) as served:
        yield Cli(served, capsys)


async def test_load_list_show_select_and_run(cli: Cli, clock: ManualClock, tmp_path: Path) -> None:
    path = tmp_path / "o300.nc"
    path.write_text(PROGRAM)
    out = await cli.ok("program", "load", str(path))
    assert out.strip() == f"stored O0300 from {path}"
    listing = await cli.json("program", "list")
    assert listing == {"programs": [
        {"number": 1, "name": "DEMO CONTOUR", "size": len(cli.served.machine.programs.text(1)),
         "main": True},
        {"number": 300, "name": "FACE", "size": len(PROGRAM), "main": False},
    ]}  # fmt: skip
    assert (await cli.ok("program", "show", "O300")) == PROGRAM
    assert (await cli.ok("program", "select", "300")).strip() == "O0300 is the main program"
    out = await cli.ok("sim", "cycle", "start")
    assert out.startswith("start: ")
    clock.advance(0.5 + 0.5)  # M3, then 10 mm at F1200
    data = await cli.json("program")
    assert data == {"program_running": 300, "program_main": 300, "feed": 1200, "spindle_speed": 800}
    assert (await cli.json("sim", "override", "--feed", "50"))["feed"] == 50
    assert (await cli.json("program"))["feed"] == 600
    await cli.ok("sim", "cycle", "hold")
    assert (await cli.json("status"))["run"]["value"] == 2
    await cli.ok("sim", "cycle", "reset")
    assert (await cli.json("status"))["run"]["value"] == 0
    assert (await cli.ok("program", "delete", "300")).strip() == "deleted O0300"


async def test_program_refusals_and_bad_input(cli: Cli, tmp_path: Path) -> None:
    err = await cli.fails(EXIT_CNC, "program", "show", "4321")
    assert "EW_NUMBER" in err
    err = await cli.fails(EXIT_USAGE, "program", "show", "O12X", prefix="focas-net")
    assert "'O12X' is not a program number" in err
    err = await cli.fails(
        EXIT_USAGE, "program", "load", str(tmp_path / "missing.nc"), prefix="focas-net"
    )
    assert "cannot read" in err and "missing.nc" in err
    err = await cli.fails(EXIT_USAGE, "program", "list", "--replace", prefix="focas-net")
    assert "argument --replace: goes with program load only" in err
    path = tmp_path / "o1.nc"
    path.write_text("O0001\nM30\n")
    err = await cli.fails(EXIT_CNC, "program", "load", str(path))
    assert "EW_REJECT" in err
    out = await cli.ok("program", "load", str(path), "--replace")
    assert out.strip() == f"stored or replaced O0001 from {path}"
