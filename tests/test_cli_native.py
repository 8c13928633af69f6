"""``focas-net ... --protocol native``: the client commands over FOCAS/2 Ethernet.

The server answers both protocols on one port, so every read command runs on both transports
against the same machine and must print the same thing; the commands FOCAS/2 cannot carry fail
with one line naming the command and the transport, before anything is sent.
"""

from __future__ import annotations

import asyncio
import json
import os
import re
import socket
import sys
from collections.abc import AsyncIterator

import pytest
from cli_support import SUBPROCESS_TIMEOUT, Cli, run_focas_net
from support import IO_TIMEOUT, serving

from focas_net.cli import EXIT_CONNECTION, EXIT_OK, EXIT_USAGE
from focas_net.client import CncClient, FocasClient, NativeClient
from focas_net.protocol import ParamDataType
from focas_net.sim import default_machine

NATIVE = ("--protocol", "native")


@pytest.fixture
async def cli(capsys: pytest.CaptureFixture[str]) -> AsyncIterator[Cli]:
    """A CLI against a machine with an alarm, a macro value and PMC bytes set (through the
    packed transport), so that the reads have something to show."""
    async with serving() as served:
        c = Cli(served, capsys)
        await c.ok("sim", "alarm", "PS0100", "parameter", "write")
        await c.ok("sim", "alarm", "OT0500", "overtravel", "--axis", "2")
        await c.ok("sim", "panel", "--mode", "MDI", "--pwe", "on")
        await c.ok("macro", "set", "100", "12.5")
        await c.ok("pmc", "write", "R", "10", "1", "2", "0xff")
        yield c


def test_both_clients_are_cnc_clients() -> None:
    """Statically (mypy --strict checks this assignment) and at run time, both clients have
    every call the shared type lists."""
    clients: list[CncClient] = [FocasClient("127.0.0.1"), NativeClient("127.0.0.1")]
    listed = {n for n in dir(CncClient) if not n.startswith("_")}
    for client in clients:
        assert {n for n in listed if not hasattr(client, n)} == set()
    assert "read_dynamic" not in listed and "sim" not in listed


READS = [
    ("status",),
    ("sysinfo",),
    ("program",),
    ("position",),
    ("position", "--kind", "machine"),
    ("position", "--kind", "relative", "--axis", "2"),
    ("position", "--kind", "distance"),
    ("param", "get", "1320", "--axis", "1"),
    ("param", "get", "1815", "--axis", "1"),
    ("param", "get", "1815.4", "--axis", "1"),
    ("param", "get", "3401"),
    ("macro", "get", "100"),
    ("macro", "get", "101"),
    ("diag", "300", "--axis", "1"),
    ("pmc", "read", "R", "8", "8"),
    ("pmc", "read", "R", "0", "600"),
    ("pmc", "bit", "R", "12.7"),
    ("alarms",),
    ("alarms", "--history", "5"),
    ("param", "get", "1320"),  # an EW code with its hint: the same line, the same exit code
    ("param", "get", "3401", "--axis", "1"),
]


@pytest.mark.parametrize("argv", READS, ids=" ".join)
@pytest.mark.parametrize("as_json", [False, True], ids=["text", "json"])
async def test_reads_print_the_same_on_both_transports(
    cli: Cli, argv: tuple[str, ...], as_json: bool
) -> None:
    extra = ("--json",) if as_json else ()
    packed = await cli.run(*argv, *extra)
    native = await cli.run(*argv, *extra, *NATIVE)
    assert native == packed
    code, out, _ = native
    if code == EXIT_OK and as_json:
        assert json.loads(out)  # a document with something in it


async def test_param_get_of_a_bit_parameter_shows_its_bits_natively(cli: Cli) -> None:
    data = await cli.json("param", "get", "1815", "--axis", "1", *NATIVE)
    assert data["type"] == "bit"
    assert data["bits"] == f"{data['value']:08b}"


@pytest.mark.parametrize(("number", "axis"), [(1320, 1), (1815, 1), (3401, 0), (1020, 1)])
async def test_read_param_type_names_the_type_read_param_attributes_gives(
    number: int, axis: int
) -> None:
    async with (
        serving() as served,
        FocasClient(served.host, served.port, timeout=IO_TIMEOUT) as packed,
        NativeClient(served.host, served.port, timeout=IO_TIMEOUT) as native,
    ):
        attributes = await packed.read_param_attributes(number)
        kind = await native.read_param_type(number, axis=axis)
    assert isinstance(kind, ParamDataType)
    assert kind == attributes.type


async def test_writes_on_native_read_back_what_they_wrote(cli: Cli) -> None:
    out = await cli.ok("macro", "set", "500", "-3.25", *NATIVE)
    assert out == "#500 = -3.25 (written)\n"
    assert await cli.ok("macro", "get", "500") == "#500 = -3.25\n"
    out = await cli.ok("pmc", "write", "R", "20", "7", "8", *NATIVE)
    assert out.startswith("wrote 2 bytes to R20..R21")
    assert (await cli.json("pmc", "read", "R", "20", "2"))["data"] == [7, 8]
    assert await cli.ok("pmc", "bit", "R", "20.7", "1", *NATIVE) == "R20.7 = 1 (written)\n"
    assert (await cli.json("pmc", "read", "R", "20", "1"))["data"] == [0x87]
    out = await cli.ok("param", "set", "1320", "123456", "--axis", "1", *NATIVE)
    assert out.startswith("1320 axis 1 = 123456") and out.endswith("(written)\n")
    assert (await cli.json("param", "get", "1320", "--axis", "1"))["value"] == 123456


PACKED_ONLY = [
    (("unlock", "1234"), "unlock", "cnc_wrunlockparam"),
    (("versamax", "0", "1"), "versamax", "versamax_rdconfig"),
    (("program", "list"), "program list", "program store"),
    (("program", "show", "O1"), "program show", "program store"),
    (("macro", "clear", "100"), "macro clear", "simulator control"),
    (("pmc", "write", "R", "0", "1", "--force"), "pmc write", "--force"),
    (("sim", "panel"), "sim panel", "simulator controls"),
    (("sim", "cycle", "start"), "sim cycle start", "packed-protocol"),
    (("sim", "override"), "sim override", "packed-protocol"),
    (("sim", "fault", "drop"), "sim fault", "simulator controls"),
    (("sim", "faults"), "sim faults", "simulator controls"),
    (("watch", "--count", "1"), "watch", "run info"),
    (("param", "set", "1320", "1", "--axis", "1", "--password", "x"), "param set", "--password"),
]


@pytest.fixture
async def dead_port() -> AsyncIterator[int]:
    """A port bound on 127.0.0.1 where nothing listens: connecting there is refused."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        yield s.getsockname()[1]


@pytest.mark.parametrize(("argv", "name", "why"), PACKED_ONLY, ids=lambda v: str(v))
async def test_what_native_cannot_carry_is_one_line_naming_command_and_transport(
    cli: Cli, dead_port: int, argv: tuple[str, ...], name: str, why: str
) -> None:
    """Refused before connecting: against a port where nothing listens the exit is 2 (a
    usage error), not 3 (connection refused)."""
    code, out, err = await cli.run(*argv, *NATIVE, port=dead_port)
    assert (code, out) == (EXIT_USAGE, "")
    assert err.startswith(f"focas-net {name.split()[0]}") and err.count("\n") == 1
    assert f": error: {name} " in err
    assert "--protocol native (FOCAS/2 Ethernet)" in err
    assert why in err


@pytest.mark.parametrize("flag", [("--tls",), ("--tls-insecure",), ("--tls-ca", "ca.pem")])
async def test_tls_with_native_is_a_usage_error_naming_both(
    cli: Cli, flag: tuple[str, ...]
) -> None:
    line = await cli.fails(EXIT_USAGE, "status", *flag, *NATIVE, prefix="focas-net")
    assert f"{flag[0]} does not apply with --protocol native" in line
    assert "FOCAS/2 has no TLS" in line


async def test_native_connection_refused_is_exit_3(cli: Cli, dead_port: int) -> None:
    code, out, err = await cli.run("status", *NATIVE, port=dead_port)
    assert (code, out) == (EXIT_CONNECTION, "")
    assert err.startswith("focas-net: ") and err.count("\n") == 1


async def test_native_timeout_names_the_address(capsys: pytest.CaptureFixture[str]) -> None:
    """A peer that accepts and never answers: the open request times out, one line, exit 3."""
    held: list[asyncio.StreamWriter] = []

    async def accept(_: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        held.append(writer)

    silent = await asyncio.start_server(accept, "127.0.0.1", 0)
    port = silent.sockets[0].getsockname()[1]
    try:
        async with serving() as served:
            cli = Cli(served, capsys)
            code, out, err = await cli.run("status", "--timeout", "0.3", *NATIVE, port=port)
    finally:
        for w in held:
            w.close()
        silent.close()
        await silent.wait_closed()
    assert (code, out) == (EXIT_CONNECTION, "")
    assert err == (
        "focas-net: timed out after 0.3 s: no answer to the open request: nothing received "
        f"since connecting to 127.0.0.1:{port}\n"
    )


async def test_alarms_follow_on_native(capsys: pytest.CaptureFixture[str]) -> None:
    machine = default_machine()
    machine.raise_alarm(0, 0, 100, "follow me")
    async with serving(machine) as served:
        cli = Cli(served, capsys)
        out = await cli.ok("alarms", "--follow", "--count", "1", "--interval", "0.05", *NATIVE)
    assert out.startswith("raised")
    assert "follow me" in out


_READY = re.compile(r"listening on 127\.0\.0\.1:(\d+)$")


async def test_read_commands_against_focas_net_serve_match() -> None:
    """``focas-net serve`` in its own process; each command as its own process on each
    transport."""
    proc = await asyncio.create_subprocess_exec(
        sys.executable, "-m", "focas_net", "serve", "--port", "0",
        stdout=asyncio.subprocess.PIPE, stderr=asyncio.subprocess.DEVNULL,
        env={**os.environ, "PYTHONUNBUFFERED": "1"},
    )  # fmt: skip
    assert proc.stdout is not None
    try:
        async with asyncio.timeout(SUBPROCESS_TIMEOUT):
            line = (await proc.stdout.readline()).decode().strip()
        ready = _READY.search(line)
        assert ready is not None, line
        port = ready[1]
        for argv in (("status",), ("sysinfo", "--json"), ("position",), ("alarms",)):
            packed = await run_focas_net(*argv, "--port", port)
            native = await run_focas_net(*argv, "--port", port, *NATIVE)
            assert packed[0] == EXIT_OK, packed
            assert native == packed, argv
    finally:
        proc.kill()
        await proc.wait()
