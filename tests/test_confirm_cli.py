"""A confirming new-user pass over the command line: the advice about ``--axis`` counts the
axes of the path a command reads (a lathe's turret, not the whole machine) on both
transports, ``pmc bit`` on FOCAS/2 does not suggest a ``--force`` it has not, and a program
file that is not ASCII is refused naming its line and character, as the machine names them,
a host of digits of another script is refused, and output that cannot be written is one
line.

Each test runs ``focas-net`` as a user does (a subprocess) and checks its one line and its
exit code."""

from __future__ import annotations

import asyncio
import json
import os
import sys
from collections.abc import AsyncIterator
from pathlib import Path

import pytest
from cli_support import SUBPROCESS_TIMEOUT, at, fails, ok
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


# -- --axis advice: the path's axes ------------------------------------------------------------

#: An axis past a path of 2: the machine's reason, carried by the client, then the advice.
PAST = "axis 3 is outside 1..2: the path has 2 axes); give --axis 1..2"


@pytest.mark.parametrize("protocol", PROTOCOLS)
@pytest.mark.parametrize(
    ("argv", "hint"),
    [
        (("param", "get", "1420", "--axis", "3"), PAST),
        (("param", "get", "1420"), "; parameter 1420 is an axis parameter: give --axis 1..2"),
        (("position", "--axis", "3"), PAST),
        (("position", "--axis", "3", "--path", "2"), PAST),
    ],
)
async def test_the_axis_advice_counts_the_axes_of_the_path(
    lathe: Served, protocol: str, argv: tuple[str, ...], hint: str
) -> None:
    line = await fails(EXIT_CNC, *argv, *at(lathe), "--protocol", protocol)
    assert line.startswith("focas-net: EW_ATTRIB (4)"), line
    assert line.endswith(hint), line


# -- pmc bit on FOCAS/2: no --force to suggest -------------------------------------------------


async def test_pmc_bit_on_native_does_not_suggest_a_force_it_has_not(server: Served) -> None:
    line = await fails(EXIT_CNC, "pmc", "bit", "X", "0.1", "1", *at(server), "--protocol", "native")
    assert "(--force) needs" not in line, line
    assert line.endswith(
        "; pmc bit has no --force: focas-net pmc write X 0 VALUE --force (with --protocol "
        "packed) writes the whole byte as the simulator"
    ), line


# -- program load: a file that is not ASCII ---------------------------------------------------


@pytest.mark.parametrize(
    ("content", "said"),
    [
        (
            "O1235\nG0 X1 (\u00e9)\nM30\n".encode(),
            "line 2: character '\u00e9' (U+00E9) in 'G0 X1 (\u00e9)': a program is printable "
            "ASCII text",
        ),
        (
            b"O1236\nM30 \xff\n",
            "line 2: byte 0xFF in 'M30 \\xff' is not text: a program is printable ASCII text",
        ),
    ],
)
async def test_a_program_file_not_in_ascii_names_its_line_and_character(
    server: Served, tmp_path: Path, content: bytes, said: str
) -> None:
    program = tmp_path / "o1235.nc"
    program.write_bytes(content)
    line = await fails(EXIT_USAGE, "program", "load", str(program), *at(server), prefix="focas-net")
    assert line == (
        f"focas-net program: error: argument N|FILE: {str(program)!r}: {said}; "
        "see focas-net program --help"
    ), line


# -- --host: digits of another script ----------------------------------------------------------


@pytest.mark.parametrize("protocol", PROTOCOLS)
async def test_a_host_of_digits_beyond_ascii_is_refused_not_read_as_an_address(
    server: Served, protocol: str
) -> None:
    # the name service reads "\uff11\uff12\uff17.0.0.1" as 127.0.0.1 and connected to it
    line = await fails(
        EXIT_USAGE,
        "status",
        "--host",
        "\uff11\uff12\uff17.0.0.1",
        "--port",
        str(server.port),
        "--protocol",
        protocol,
        prefix="focas-net status: error: ",
    )
    assert (
        "argument --host: not an IPv4 address: host '\uff11\uff12\uff17.0.0.1' holds a digit "
        "beyond ASCII ('\uff11', U+FF11): write 0-9" in line
    ), line


# -- output that cannot be written --------------------------------------------------------------


@pytest.mark.skipif(not Path("/dev/full").exists(), reason="needs /dev/full (Linux)")
async def test_output_that_cannot_be_written_is_one_line_not_a_traceback(server: Served) -> None:
    full = os.open("/dev/full", os.O_WRONLY)
    try:
        proc = await asyncio.create_subprocess_exec(
            sys.executable, "-m", "focas_net", "status", *at(server),
            stdout=full, stderr=asyncio.subprocess.PIPE,
        )  # fmt: skip
        async with asyncio.timeout(SUBPROCESS_TIMEOUT):
            _, err = await proc.communicate()
    finally:
        os.close(full)
    assert proc.returncode == EXIT_CNC
    assert err.decode() == "focas-net: cannot write the output: no space left on device\n"


# -- sim clear all -------------------------------------------------------------------------------


async def test_sim_clear_all_is_what_leaving_the_alarm_out_means(server: Served) -> None:
    assert await ok("sim", "alarm", "PS0100", *at(server)) != ""
    out = json.loads(await ok("sim", "clear", "ALL", "--json", *at(server)))
    assert out["cleared"] == "all"
    assert [a["code"] for a in out["alarms"]] == ["PS0100"] and out["active"] == []
    # with nothing active it says so, exit 0, as the bare command does
    assert await ok("sim", "clear", "all", *at(server)) == "no active alarms; nothing to clear\n"
