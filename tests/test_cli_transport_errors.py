"""The transports' failures at the command line: the same words and exit codes on both
(``--protocol packed`` and ``native``), whatever the peer did: sent something that is no
FOCAS frame, closed or reset the connection, never answered, refused the connect; and
``alarms --follow`` giving up with the reason of its last reconnect attempt.

The peers are raw TCP servers of this test on 127.0.0.1 (ephemeral ports); ``focas-net`` runs
as a subprocess, except where a module constant must be made small (in-process, in a thread).
"""

from __future__ import annotations

import asyncio
import socket
import ssl
import struct
import threading
from collections.abc import AsyncIterator, Iterator
from contextlib import asynccontextmanager, contextmanager
from http.server import SimpleHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path
from typing import Final

import pytest
from cli_support import one_line, run_focas_net
from support import IO_TIMEOUT, LoopbackPeer, serving, wait_until

from focas_net.cli import EXIT_CONNECTION, EXIT_PROTOCOL, _diagnose, _run, main
from focas_net.cli._diagnose import Findings
from focas_net.client import FocasClient
from focas_net.protocol import FaultKind, FaultScope

PROTOCOLS: Final = ("packed", "native")
HTTP_ANSWER: Final = b"HTTP/1.1 400 Bad Request\r\nContent-Length: 0\r\n\r\n"
#: A short per-call timeout for a peer that never answers (the command's own option).
SHORT: Final = "0.5"


class RawPeer(LoopbackPeer):
    """A TCP peer that is not a FOCAS server: on each connection it reads what comes first,
    then does what it was made for (``answer``: an HTTP error; ``close``; ``reset``), or
    closes it at once, before reading anything (``at_once``: whether the client's request
    meets a reset or an end of stream is then a race)."""

    def __init__(self, action: str) -> None:
        self.action = action

    async def _serve(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        try:
            if self.action == "at_once":
                return
            await reader.read(64)
            if self.action == "answer":
                writer.write(HTTP_ANSWER)
                await writer.drain()
            elif self.action == "reset":
                sock = writer.get_extra_info("socket")
                sock.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, struct.pack("ii", 1, 0))
        finally:
            writer.close()


@asynccontextmanager
async def raw_peer(action: str) -> AsyncIterator[RawPeer]:
    async with RawPeer(action) as peer:
        yield peer


@contextmanager
def http_server() -> Iterator[int]:
    """Python's own ``http.server`` (as ``python3 -m http.server`` runs it) on an ephemeral
    port, in a thread: its port."""
    httpd = ThreadingHTTPServer(("127.0.0.1", 0), SimpleHTTPRequestHandler)
    httpd.daemon_threads = True
    thread = threading.Thread(target=httpd.serve_forever, daemon=True)
    thread.start()
    try:
        yield httpd.server_address[1]
    finally:
        httpd.shutdown()
        httpd.server_close()
        thread.join(IO_TIMEOUT)


def _closed_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port: int = s.getsockname()[1]
    return port


def no_python_text(line: str) -> None:
    """A line meant for a user: no exception repr, errno or address tuple of Python's."""
    for mark in ("Error(", "[Errno", "('127.0.0.1'", "bytes read on a total"):
        assert mark not in line, line


async def cli(port: int, protocol: str, *argv: str) -> tuple[int, str, str]:
    return await run_focas_net(
        *(argv or ("status",)), "--port", str(port), "--protocol", protocol, "--timeout", SHORT
    )


# -- item: a peer that is not a FOCAS server ----------------------------------------------------


@pytest.mark.parametrize("protocol", PROTOCOLS)
async def test_a_peer_answering_http_does_not_speak_focas_on_either_transport(
    protocol: str,
) -> None:
    async with raw_peer("answer") as peer:
        code, out, err = await cli(peer.port, protocol)
    assert (code, out) == (EXIT_PROTOCOL, ""), err
    line = one_line(err)
    assert f"127.0.0.1:{peer.port} does not speak the FOCAS protocol (" in line
    # what it answers, probed on a new connection, names it
    assert line.endswith(
        "it answers 'HTTP/1.1 400' to an HTTP request and no FOCAS frame: an HTTP server)"
    )


@pytest.mark.parametrize("protocol", PROTOCOLS)
@pytest.mark.parametrize(
    ("action", "words"),
    [
        ("close", "connection closed by {peer} before any answer"),
        ("reset", "connection closed by {peer} before any answer"),
        ("at_once", "connection closed by {peer} before any answer"),
    ],
)
async def test_a_peer_that_ends_the_connection_reads_the_same_on_both_transports(
    protocol: str, action: str, words: str
) -> None:
    async with raw_peer(action) as peer:
        code, out, err = await cli(peer.port, protocol)
    assert (code, out) == (EXIT_CONNECTION, ""), err
    line = one_line(err)
    assert words.format(peer=f"127.0.0.1:{peer.port}") in line
    no_python_text(line)


@pytest.mark.parametrize("action", ["close", "reset", "at_once"])
async def test_a_peer_that_ends_the_connection_prints_one_line_on_both_transports(
    action: str,
) -> None:
    """The whole line, not only its words: no request number on one transport alone, and a
    reset reads as the close it is (which of the two a peer closing at once gives is a race)."""
    lines = set()
    async with raw_peer(action) as peer:
        for protocol in PROTOCOLS * 2:
            code, out, err = await cli(peer.port, protocol)
            assert (code, out) == (EXIT_CONNECTION, ""), err
            lines.add(one_line(err))
    assert len(lines) == 1, lines


@pytest.mark.parametrize("protocol", PROTOCOLS)
async def test_a_refused_connect_reads_as_its_reason(protocol: str) -> None:
    port = _closed_port()
    code, out, err = await cli(port, protocol)
    assert (code, out) == (EXIT_CONNECTION, ""), err
    line = one_line(err)
    assert line == f"focas-net: cannot connect to 127.0.0.1:{port}: connection refused"


# -- item: alarms --follow says why it gave up --------------------------------------------------


@pytest.mark.parametrize("protocol", PROTOCOLS)
async def test_follow_gives_up_with_the_last_reconnect_attempts_reason(
    protocol: str, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.setattr(_run, "FOLLOW_RECONNECT_ATTEMPTS", 1)
    printed: list[str] = []

    def followed() -> bool:  # the follower is connected: it printed the alarm active
        printed.append(capsys.readouterr().out)
        return "raised" in "".join(printed)

    async with serving() as served:
        served.machine.raise_alarm(0, 3, 100, "ACTIVE")
        argv = ["alarms", "--follow", "--interval", "0.05", "--timeout", "1"]
        argv += ["--port", str(served.port), "--protocol", protocol]
        follow = asyncio.create_task(asyncio.to_thread(main, argv))
        await wait_until(followed)
    # the server has stopped: the one reconnect attempt is refused
    async with asyncio.timeout(4 * IO_TIMEOUT):
        code = await follow
    err = capsys.readouterr().err.splitlines()
    assert code == EXIT_CONNECTION, err
    assert err[0] == (
        f"focas-net: connection to 127.0.0.1:{served.port} lost: connection closed by "
        f"127.0.0.1:{served.port}; reconnecting"
    )
    last = err[-1]
    assert "alarms --follow gave up" in last
    assert f"cannot connect to 127.0.0.1:{served.port}: connection refused" in last
    no_python_text(last)


# -- item: a peer that says nothing ---------------------------------------------------------------


@pytest.mark.parametrize("protocol", PROTOCOLS)
async def test_an_http_server_that_waits_is_named_as_one(protocol: str) -> None:
    """``python3 -m http.server`` waits for the end of a request line, which no FOCAS frame
    sends: the command times out with nothing received, then finds an HTTP server."""
    with http_server() as port:
        code, out, err = await cli(port, protocol)
    assert (code, out) == (EXIT_PROTOCOL, ""), err
    line = one_line(err)
    assert f"127.0.0.1:{port} does not speak the FOCAS protocol (" in line
    assert "an HTTP server" in line and "--tls" not in line


# -- item: hints that say what the probes found ---------------------------------------------------


async def test_a_native_only_port_points_to_protocol_native() -> None:
    async with serving(native_port=0) as served:
        native = served.listener.native
        assert native is not None
        port = native.address[1]
        code, out, err = await cli(port, "packed")
        assert (code, out) == (EXIT_CONNECTION, ""), err
        line = one_line(err)
        assert line.endswith("give --protocol native") and "--tls" not in line
        code, out, err = await cli(port, "native")
        assert (code, err) == (0, "")


@pytest.mark.parametrize("protocol", PROTOCOLS)
async def test_a_connection_over_the_limit_says_the_server_refused_it(protocol: str) -> None:
    async with serving(max_connections=1) as served, await served.connect():
        code, out, err = await cli(served.port, protocol)
    assert (code, out) == (EXIT_CONNECTION, ""), err
    line = one_line(err)
    assert "the server refused the connection" in line and "--max-connections" in line
    assert "--tls" not in line


async def test_a_limit_of_one_connection_is_named_to_a_focas2_client() -> None:
    async with serving(max_connections=1) as served:
        code, out, err = await cli(served.port, "native")
    assert (code, out) == (EXIT_CONNECTION, ""), err
    line = one_line(err)
    assert "FOCAS/2's open, which takes two" in line and "--max-connections 1" in line


async def test_a_dropped_answer_gives_no_tls_hint() -> None:
    async with serving() as served:
        async with FocasClient(served.host, served.port, timeout=IO_TIMEOUT) as c:
            await c.sim.inject_fault(FaultKind.DROP, scope=FaultScope.MACHINE)
        code, out, err = await cli(served.port, "packed")
    assert (code, out) == (EXIT_CONNECTION, ""), err
    line = one_line(err)
    assert "before any answer" in line and "drop fault" in line and "--tls" not in line


async def test_tls_on_one_side_only_is_found_on_either_side(
    certificate: tuple[Path, Path],
) -> None:
    context = ssl.SSLContext(ssl.PROTOCOL_TLS_SERVER)
    context.load_cert_chain(*certificate)
    async with serving(ssl=context) as served:
        lines = [one_line((await cli(served.port, p))[2]) for p in PROTOCOLS]
    assert lines[0].endswith(
        "the server uses TLS: give --tls (with --tls-ca FILE or --tls-insecure)"
    )
    assert lines[1].endswith("FOCAS/2 does not have: give --protocol packed --tls")
    async with serving(native_port=0) as served:
        native = served.listener.native
        assert native is not None
        code, _, err = await cli(native.address[1], "packed", "status", "--tls-insecure")
    assert code == EXIT_CONNECTION
    assert one_line(err).endswith("drop --tls, give --protocol native")


@pytest.mark.parametrize(
    ("found", "protocol", "tls", "advice"),
    [
        (Findings(True, False, False, False), "packed", False, "the server refused"),
        (Findings(True, False, True, False), "packed", False, "on purpose"),
        (Findings(False, True, False, False), "packed", True, None),
        (Findings(False, False, True, True), "packed", True, "plain TCP: drop --tls"),
        (Findings(False, False, False, True), "native", False, "on purpose"),
        (Findings(False, False, True, False), "native", False, "FOCAS/2's open, which takes two"),
        (Findings(False, False, False, False), "packed", False, None),
    ],
)
def test_the_advice_follows_from_what_the_probes_found(
    found: Findings, protocol: str, tls: bool, advice: str | None
) -> None:
    said = _diagnose.advice(found, protocol, tls)
    assert said == advice if advice is None else (said is not None and advice in said)
