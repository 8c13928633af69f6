"""What a new user meets in the first hour: the command line as a child process, its exit
codes and its one-line messages, against real servers, a peer that is not a FOCAS server, TLS
on one side only, and options that cannot work.

Servers and peers run on this test's loop (127.0.0.1, ephemeral ports); ``focas-net`` runs as
a subprocess, each bounded by :data:`CLI_TIMEOUT`.
"""

from __future__ import annotations

import argparse
import asyncio
import json
import ssl
import sys
from collections.abc import AsyncIterator
from contextlib import asynccontextmanager
from pathlib import Path
from typing import Any

import pytest
from cli_support import at, one_line, run_focas_net
from peers import ScriptedPeer, turns
from support import IO_TIMEOUT, Served, serving

from focas_net import __version__ as focas_net_version
from focas_net.cli import (
    EXIT_CNC,
    EXIT_CONNECTION,
    EXIT_OK,
    EXIT_PROTOCOL,
    EXIT_USAGE,
    main,
    serve,
)
from focas_net.client import AlarmProjection, ClientState, FocasClient, ReconnectPolicy
from focas_net.errors import EW, CncError, FocasConnectionError, ProtocolError
from focas_net.protocol import Frame

CLI_TIMEOUT = 6 * IO_TIMEOUT
FLEET_POLL = Path(__file__).resolve().parent.parent / "examples" / "fleet_poll.py"
HTTP_ANSWER = b"HTTP/1.1 400 Bad Request\r\nContent-Length: 0\r\n\r\n"


@pytest.fixture
async def http_peer() -> AsyncIterator[ScriptedPeer]:
    """A peer that answers every request as an HTTP server would: not a FOCAS server."""

    def http(frame: Frame, peer: ScriptedPeer) -> bytes | None:
        peer.send_raw(HTTP_ANSWER)
        return None

    async with ScriptedPeer() as p:
        p.answer = http
        yield p


# -- 4. a peer that is not a FOCAS server ------------------------------------------------------


async def test_a_command_against_a_non_focas_peer_exits_4(http_peer: ScriptedPeer) -> None:
    code, out, err = await run_focas_net("status", *at(http_peer))
    assert code == EXIT_PROTOCOL, err
    assert out == ""
    line = one_line(err)
    assert "does not speak the FOCAS protocol" in line
    assert "HTTP/1.1" in line


async def test_follow_against_a_non_focas_peer_gives_up(http_peer: ScriptedPeer) -> None:
    code, out, err = await run_focas_net("alarms", "--follow", "--count", "2", *at(http_peer))
    assert code == EXIT_PROTOCOL, err
    assert out == ""
    line = one_line(err)  # no "reconnecting" line: it failed at its first read
    # its first read failed: it fails as a one-shot command does (the same words), at once
    one_shot = one_line((await run_focas_net("status", *at(http_peer)))[2])
    assert line == one_shot and "does not speak the FOCAS protocol" in line


async def test_a_protocol_violation_is_not_retried_as_a_lost_connection(
    http_peer: ScriptedPeer,
) -> None:
    policy = ReconnectPolicy(initial_delay=0, jitter=0)
    async with FocasClient("127.0.0.1", http_peer.port, timeout=IO_TIMEOUT, reconnect=policy) as c:
        with pytest.raises(ProtocolError, match="does not speak the FOCAS protocol"):
            await c.read_status()
        await turns(20)
        assert c.state is ClientState.DISCONNECTED
        assert http_peer.connections == 1
        with pytest.raises(ProtocolError, match="does not speak the FOCAS protocol"):
            await c.read_status()  # later calls say why, too


async def test_a_projection_raises_when_it_cannot_make_progress(http_peer: ScriptedPeer) -> None:
    policy = ReconnectPolicy(initial_delay=0, jitter=0)
    async with FocasClient("127.0.0.1", http_peer.port, timeout=IO_TIMEOUT, reconnect=policy) as c:
        projection = AlarmProjection(c, interval=0.01)
        with pytest.raises(ProtocolError):
            async with asyncio.timeout(IO_TIMEOUT):
                async for _event in projection:
                    pytest.fail("no event can come from a peer that is not a FOCAS server")
        assert projection.polls == 0 and projection.failed_polls >= 1


async def test_a_projection_ends_when_the_reconnect_policy_gives_up() -> None:
    policy = ReconnectPolicy(initial_delay=0, jitter=0, max_attempts=2)
    async with serving() as served:
        c = FocasClient(served.host, served.port, timeout=IO_TIMEOUT, reconnect=policy)
        await c.connect()
        projection = AlarmProjection(c, interval=0.01)
        assert await projection.poll() == []
    try:  # the server has stopped: every reconnect attempt fails
        with pytest.raises(FocasConnectionError):
            async with asyncio.timeout(IO_TIMEOUT):
                async for _event in projection:
                    pytest.fail("no event comes without a connection")
        assert c.state is ClientState.DISCONNECTED
    finally:
        await c.aclose()


async def test_a_projection_gives_up_after_max_failures(server: Served) -> None:
    async with FocasClient(server.host, server.port, timeout=IO_TIMEOUT) as c:
        await c.sim.inject_fault(2, count=100, arg=-1, scope=1)  # EW_BUSY for 100 answers
        projection = AlarmProjection(c, interval=0.01, max_failures=3)
        with pytest.raises(CncError) as failure:
            async with asyncio.timeout(IO_TIMEOUT):
                async for _event in projection:
                    pytest.fail("every poll fails")
        assert failure.value.ew == EW.BUSY
        assert (projection.polls, projection.failed_polls) == (0, 3)


# -- 5. TLS --------------------------------------------------------------------------------


@asynccontextmanager
async def tls_served(certificate: tuple[Path, Path]) -> AsyncIterator[Served]:
    ctx = ssl.SSLContext(ssl.PROTOCOL_TLS_SERVER)
    ctx.load_cert_chain(*certificate)
    async with serving(ssl=ctx) as served:
        yield served


async def test_cli_tls_options(certificate: tuple[Path, Path]) -> None:
    cert, _key = certificate
    async with tls_served(certificate) as served:
        code, out, err = await run_focas_net("status", "--tls-ca", str(cert), *at(served))
        assert (code, err) == (EXIT_OK, "")
        assert out.startswith("mode=MEM ")
        code, out, err = await run_focas_net("sysinfo", "--tls-insecure", "--json", *at(served))
        assert (code, err) == (EXIT_OK, "")
        assert json.loads(out)["mt_type"]["value"] == "M"
        code, out, err = await run_focas_net("status", "--tls", *at(served))  # self-signed
        assert code == EXIT_CONNECTION
        line = one_line(err)
        assert "certificate not trusted" in line and "--tls-ca" in line


async def test_plain_client_against_a_tls_server_says_why(
    certificate: tuple[Path, Path],
) -> None:
    async with tls_served(certificate) as served:
        code, out, err = await run_focas_net("status", *at(served))
    assert code == EXIT_CONNECTION and out == ""
    line = one_line(err)
    assert "before any answer" in line and "give --tls" in line


async def test_tls_client_against_a_plain_server_says_why(
    server: Served, certificate: tuple[Path, Path]
) -> None:
    cert, _key = certificate
    code, out, err = await run_focas_net("status", "--tls-ca", str(cert), *at(server))
    assert code == EXIT_CONNECTION and out == ""
    line = one_line(err)
    assert line.startswith(f"focas-net: cannot connect to 127.0.0.1:{server.port}: TLS handshake")
    assert "drop --tls" in line
    assert not line.endswith(": ")


async def test_tls_option_errors_are_usage_errors(tmp_path: Path) -> None:
    code, _out, err = await run_focas_net("status", "--tls-ca", str(tmp_path / "missing.pem"))
    assert code == EXIT_USAGE and "missing.pem" in one_line(err, "focas-net status: error: ")
    code, _out, err = await run_focas_net("status", "--tls-ca", "x.pem", "--tls-insecure")
    line = one_line(err, "focas-net status: error: ")
    assert code == EXIT_USAGE and "argument --tls-insecure: not allowed with --tls-ca" in line


async def test_serve_ready_line_says_tls_and_read_only(certificate: tuple[Path, Path]) -> None:
    cert, key = certificate
    proc = await asyncio.create_subprocess_exec(
        sys.executable, "-m", "focas_net", "serve", "--port", "0", "--read-only",
        "--tls-cert", str(cert), "--tls-key", str(key),
        stdout=asyncio.subprocess.PIPE, stderr=asyncio.subprocess.PIPE,
    )  # fmt: skip
    assert proc.stdout is not None
    try:
        async with asyncio.timeout(CLI_TIMEOUT):
            line = (await proc.stdout.readline()).decode()
        assert line.startswith("focas-net: focas-sim-0i (TLS, read-only) listening on 127.0.0.1:")
    finally:
        proc.kill()
        await proc.wait()


# -- 6. serve options are checked before anything is allocated -----------------------------


@pytest.mark.parametrize(
    ("argv", "words"),
    [
        (("--fleet", "100000", "--port", "1000"), "must be 1..10000"),
        (("--fleet", "500", "--port", "65300"), "run past 65535"),
        (("--fleet", "3", "--port", "0", "--native-port", "65534"), "run past 65535"),
        (("--fleet", "3", "--port", "9000", "--native-port", "9002"), "overlaps"),
    ],
)
async def test_serve_checks_options_first(argv: tuple[str, ...], words: str) -> None:
    code, out, err = await run_focas_net("serve", *argv)
    assert code == EXIT_USAGE and out == ""
    assert err.count("\n") == 1 and words in err, err


def test_serve_builds_no_machine_for_bad_options(monkeypatch: pytest.MonkeyPatch) -> None:
    def build(args: argparse.Namespace) -> Any:
        pytest.fail("machines were built before the options were checked")

    monkeypatch.setattr(serve, "build_machines", build)
    parser = argparse.ArgumentParser()
    serve.register(parser.add_subparsers())
    args = parser.parse_args(["serve", "--fleet", "500", "--port", "65300"])
    assert serve.run(args) == EXIT_USAGE


# -- 11. hints and bounds ------------------------------------------------------------------


async def test_a_long_host_is_a_clear_usage_error() -> None:
    code, _out, err = await run_focas_net("status", "--host", "a" * 300)
    assert code == EXIT_USAGE
    assert "host name too long" in err and "idna" not in err
    code, _out, err = await run_focas_net("status", "--host", "a" * 64 + ".example")
    assert code == EXIT_USAGE and "1..63" in err


async def test_ipv6_addresses_print_in_brackets() -> None:
    blocker = await asyncio.start_server(lambda r, w: None, "127.0.0.1", 0)
    port = blocker.sockets[0].getsockname()[1]
    blocker.close()
    await blocker.wait_closed()
    code, _out, err = await run_focas_net("status", "--host", "::1", "--port", str(port))
    assert code == EXIT_CONNECTION
    assert f"[::1]:{port}" in one_line(err)


async def test_follow_interval_is_bounded_below() -> None:
    code, _out, err = await run_focas_net("alarms", "--follow", "--interval", "0.000000001")
    assert code == EXIT_USAGE and "0.05..3600 seconds" in err


# -- 13. small things ----------------------------------------------------------------------


async def test_version() -> None:
    code, out, err = await run_focas_net("--version")
    assert (code, err) == (EXIT_OK, "")
    assert out.strip() == f"focas-net {focas_net_version}"


async def test_status_names_tmmode_by_the_machine_series(server: Served) -> None:
    code, out, err = await run_focas_net("status", *at(server))
    assert (code, err) == (EXIT_OK, "")
    (row,) = [line.split() for line in out.splitlines() if line.startswith("tmmode")]
    assert row[:3] == ["tmmode", "0", "M"] and "T mode" not in out
    code, out, _err = await run_focas_net("status", "--json", *at(server))
    assert json.loads(out)["tmmode"] == {
        "value": 0,
        "name": "M",
        "meaning": "M series machine (no T/M mode selection)",
    }


async def test_fleet_poll_error_rows_do_not_widen_the_columns(server: Served) -> None:
    async with serving() as gone:
        dead = gone.port
    proc = await asyncio.create_subprocess_exec(
        sys.executable, str(FLEET_POLL), "--ports", f"{server.port},{dead}", "--rounds", "1",
        stdout=asyncio.subprocess.PIPE, stderr=asyncio.subprocess.PIPE,
    )  # fmt: skip
    async with asyncio.timeout(CLI_TIMEOUT):
        out, _err = await proc.communicate()
    header, good, bad, *_ = out.decode().splitlines()
    assert header.index("alarm") - header.index("run") == len("**** ") + 1  # as wide as ****
    assert good.split()[3:5] == ["MEM", "****"]
    assert bad.split()[2:4] == ["ERROR", "unreachable:"] and len(bad) <= len(header) + 60


async def test_axis_hints(server: Served) -> None:
    code, _out, err = await run_focas_net("param", "get", "1420", *at(server))
    assert code == EXIT_CNC
    assert one_line(err).endswith("parameter 1420 is an axis parameter: give --axis 1..3")
    code, _out, err = await run_focas_net("param", "get", "1420", "--axis", "7", *at(server))
    assert one_line(err).endswith("axis 7 is outside 1..3: the path has 3 axes); give --axis 1..3")
    code, _out, err = await run_focas_net("diag", "300", *at(server))
    assert one_line(err).endswith("diagnostic 300 is an axis diagnostic: give --axis 1..3")


async def test_pmc_write_of_many_bytes_is_summarised(server: Served) -> None:
    values = " ".join(str(i % 256) for i in range(300))
    code, out, err = await run_focas_net("pmc", "write", "R", "0", values, *at(server))
    assert (code, err) == (EXIT_OK, "")
    assert out.strip() == (
        "wrote 300 bytes to R0..R299: 00 01 02 03 04 05 06 07 08 09 0a 0b 0c 0d 0e 0f "
        "... (300 bytes)"
    )
    assert server.machine.read_pmc("R", 0, 300) == bytes(i % 256 for i in range(300))


# -- 12. one JSON shape per thing ----------------------------------------------------------

ALARM_KEYS = {"code", "axis_no", "alm_type", "alm_no", "msg"}


async def json_of(capsys: pytest.CaptureFixture[str], served: Served, *argv: str) -> Any:
    capsys.readouterr()
    args = [*argv, "--json", "--port", str(served.port)]
    code = await asyncio.wait_for(asyncio.to_thread(main, args), CLI_TIMEOUT)
    out, err = capsys.readouterr()
    assert (code, err) == (EXIT_OK, ""), argv
    lines = out.splitlines()
    return json.loads(out) if argv[:2] != ("alarms", "--follow") else [json.loads(x) for x in lines]


def assert_plain_or_object(value: Any, where: str) -> None:
    """Every value is a number, a string, a bool, null, an object or a list of such."""
    if isinstance(value, dict):
        for key, inner in value.items():
            assert isinstance(key, str)
            assert_plain_or_object(inner, f"{where}.{key}")
    elif isinstance(value, list):
        for i, inner in enumerate(value):
            assert_plain_or_object(inner, f"{where}[{i}]")
    else:
        assert value is None or isinstance(value, str | int | float | bool), where


async def test_json_shapes_are_consistent(
    server: Served, capsys: pytest.CaptureFixture[str]
) -> None:
    server.machine.raise_alarm(0, 3, 100, "PARAMETER WRITE ENABLE")
    server.machine.raise_alarm(2, 6, 401, "SERVO V-READY OFF")
    status = await json_of(capsys, server, "status")
    sysinfo = await json_of(capsys, server, "sysinfo")
    alarms = await json_of(capsys, server, "alarms", "--history", "2")
    raised = await json_of(capsys, server, "sim", "alarm", "OT0500")
    follow = await json_of(capsys, server, "alarms", "--follow", "--count", "3")
    cleared = await json_of(capsys, server, "sim", "clear", "SV")
    panel = await json_of(capsys, server, "sim", "panel", "--mode", "MEM")
    everything = [status, sysinfo, alarms, raised, cleared, panel]
    for argv in (("program",), ("position",), ("macro", "get", "100"), ("pmc", "read", "R", "0")):
        everything.append(await json_of(capsys, server, *argv))
    for i, data in enumerate(everything):
        assert isinstance(data, dict)
        assert_plain_or_object(data, f"document {i}")
    # a coded field is {value, name, meaning} in status, {value, meaning} in sysinfo
    assert all(set(v) == {"value", "name", "meaning"} for v in status.values())
    assert set(sysinfo["cnc_type"]) == set(sysinfo["mt_type"]) == {"value", "meaning"}
    assert isinstance(sysinfo["series"], str) and isinstance(sysinfo["max_axis"], int)
    # an alarm has one shape wherever it appears; a history entry adds occurred_at
    alarm_objects = [
        *alarms["active"],
        raised["raised"],
        *cleared["alarms"],
        *cleared["active"],
        *(e["alarm"] for e in follow),
    ]
    assert len(alarm_objects) >= 8
    assert all(set(a) == ALARM_KEYS for a in alarm_objects)
    assert all(set(h) == ALARM_KEYS | {"occurred_at"} for h in alarms["history"])
    # a status inside another command is the status object
    assert set(panel["status"]) == set(status)
    assert all(set(v) == {"value", "name", "meaning"} for v in panel["status"].values())
