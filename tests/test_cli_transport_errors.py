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
import struct
import threading
from collections.abc import AsyncIterator, Iterator
from contextlib import asynccontextmanager, contextmanager
from http.server import SimpleHTTPRequestHandler, ThreadingHTTPServer
from typing import Final

import pytest
from cli_support import run_focas_net
from support import IO_TIMEOUT, LoopbackPeer, serving, wait_until

from focas_net.cli import EXIT_CONNECTION, EXIT_PROTOCOL, _run, main

PROTOCOLS: Final = ("packed", "native")
HTTP_ANSWER: Final = b"HTTP/1.1 400 Bad Request\r\nContent-Length: 0\r\n\r\n"
#: A short per-call timeout for a peer that never answers (the command's own option).
SHORT: Final = "0.5"

class RawPeer(LoopbackPeer):
    """A TCP peer that is not a FOCAS server: on each connection it reads what comes first,
    then does what it was made for (``answer``: an HTTP error; ``close``; ``reset``)."""

    def __init__(self, action: str) -> None:
        self.action = action

    async def _serve(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        try:
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


def one_line(err: str) -> str:
    assert err.startswith("focas-net: ") and err.count("\n") == 1, err
    return err.strip()


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
    assert "it sent b'HTTP/1.1'" in line


@pytest.mark.parametrize("protocol", PROTOCOLS)
async def test_a_peer_that_closes_reads_the_same_on_both_transports(protocol: str) -> None:
    async with raw_peer("close") as peer:
        code, out, err = await cli(peer.port, protocol)
    assert (code, out) == (EXIT_CONNECTION, ""), err
    line = one_line(err)
    assert f"connection closed by 127.0.0.1:{peer.port} before any answer" in line
    no_python_text(line)


@pytest.mark.parametrize("protocol", PROTOCOLS)
async def test_a_peer_that_resets_reads_the_same_on_both_transports(protocol: str) -> None:
    async with raw_peer("reset") as peer:
        code, out, err = await cli(peer.port, protocol)
    assert (code, out) == (EXIT_CONNECTION, ""), err
    line = one_line(err)
    assert f"connection to 127.0.0.1:{peer.port} lost before any answer" in line
    no_python_text(line)


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
    async with serving() as served:
        argv = ["alarms", "--follow", "--interval", "0.05", "--timeout", "1"]
        argv += ["--port", str(served.port), "--protocol", protocol]
        follow = asyncio.create_task(asyncio.to_thread(main, argv))
        listener = served.listener
        await wait_until(lambda: listener.connections or listener.native_connections)
    # the server has stopped: the one reconnect attempt is refused
    async with asyncio.timeout(4 * IO_TIMEOUT):
        code = await follow
    err = capsys.readouterr().err.splitlines()
    assert code == EXIT_CONNECTION, err
    assert err[0] == f"focas-net: connection to 127.0.0.1:{served.port} lost; reconnecting"
    last = err[-1]
    assert "alarms --follow gave up" in last
    assert f"cannot connect to 127.0.0.1:{served.port}: connection refused" in last
    no_python_text(last)
