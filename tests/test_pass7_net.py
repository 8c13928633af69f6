"""Wrong and failing peers, seventh pass: what both transports and the command line say.

Each case here is one a user met: a refused connect with ``--tls``, a name of two addresses
refused on both (``localhost`` is ``::1`` and ``127.0.0.1`` on most systems), a connect that
never completes, a peer that sends the start of an answer and then closes or says no more,
a certificate that is trusted but names another host, a FOCAS/2 open one connection short of
a server's limit, a ``--host`` given as a URL, a ``serve --native-port`` already taken, and a
client still reconnecting when a call's time is up.

The peers are raw TCP servers of this test on 127.0.0.1 (ephemeral ports); ``focas-net`` runs
as a subprocess where its exit code is checked.
"""

from __future__ import annotations

import asyncio
import errno
import shutil
import socket
import ssl
import subprocess
import threading
from collections.abc import AsyncIterator, Iterator
from contextlib import asynccontextmanager, contextmanager
from http.server import SimpleHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path
from typing import Any, Final

import pytest
from cli_support import one_line, run_focas_net
from support import IO_TIMEOUT, LoopbackPeer, free_port, serving, wait_until

from focas_net.cli import EXIT_CONNECTION, EXIT_PROTOCOL, _diagnose, _run, main
from focas_net.cli._diagnose import Findings
from focas_net.client import ClientState, FocasClient, NativeClient, ReconnectPolicy
from focas_net.errors import FocasConnectionError, FocasError, FocasTimeoutError, ProtocolError
from focas_net.native.frame import MAGIC, NATIVE_HEADER, FrameType
from focas_net.protocol import FrameDecoder, encode_frame

PROTOCOLS: Final = ("packed", "native")
CLIENTS: Final = (FocasClient, NativeClient)
SHORT: Final = "0.5"


class SaysThenActs(LoopbackPeer):
    """On each connection: reads what comes first, sends ``said``, then closes (``then``
    ``close``) or keeps the connection open, saying nothing more (``hang``)."""

    def __init__(self, said: bytes, then: str) -> None:
        self.said = said
        self.then = then
        self.open: list[asyncio.StreamWriter] = []

    async def _serve(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        await reader.read(64)
        writer.write(self.said)
        await writer.drain()
        if self.then == "hang":
            self.open.append(writer)  # closed at the end of the test, by the server's close
            return
        writer.close()

    async def stop(self) -> None:
        for writer in self.open:
            writer.close()
        await super().stop()


@asynccontextmanager
async def says(said: bytes, then: str) -> AsyncIterator[SaysThenActs]:
    async with SaysThenActs(said, then) as peer:
        yield peer


async def cli(port: int, protocol: str, *argv: str) -> tuple[int, str, str]:
    return await run_focas_net(
        *(argv or ("status",)), "--port", str(port), "--protocol", protocol, "--timeout", SHORT
    )


async def failure(
    cls: type[FocasClient] | type[NativeClient], port: int, host: str = "127.0.0.1"
) -> FocasError:
    with pytest.raises(FocasError) as caught:
        async with cls(host, port, timeout=float(SHORT)) as client:
            await client.read_status()
    return caught.value


# -- a connect refused, or never completed ---------------------------------------------------


@pytest.mark.parametrize("tls", ["--tls", "--tls-insecure"])
async def test_a_refused_connect_with_tls_is_refused_not_a_handshake_that_failed(tls: str) -> None:
    """It never reached a handshake: no "TLS handshake failed", no "drop --tls"."""
    port = free_port()
    code, out, err = await run_focas_net("status", "--port", str(port), tls)
    assert (code, out) == (EXIT_CONNECTION, ""), err
    assert one_line(err) == f"focas-net: cannot connect to 127.0.0.1:{port}: connection refused"


def _two_addresses(monkeypatch: pytest.MonkeyPatch) -> None:
    """``dual.test`` resolves to ``::1`` then ``127.0.0.1``, as ``localhost`` does on most
    systems."""
    loop = asyncio.get_running_loop()

    async def resolve(host: str, port: int, **kwargs: Any) -> list[Any]:
        assert host == "dual.test"
        return [
            (socket.AF_INET6, socket.SOCK_STREAM, 6, "", ("::1", port, 0, 0)),
            (socket.AF_INET, socket.SOCK_STREAM, 6, "", ("127.0.0.1", port)),
        ]

    monkeypatch.setattr(loop, "getaddrinfo", resolve)


@pytest.mark.parametrize("cls", CLIENTS)
async def test_a_name_refused_on_each_of_its_addresses_is_refused(
    cls: type[FocasClient] | type[NativeClient], monkeypatch: pytest.MonkeyPatch
) -> None:
    _two_addresses(monkeypatch)
    port = free_port()
    err = await failure(cls, port, "dual.test")
    assert type(err) is FocasConnectionError
    assert str(err) == f"cannot connect to dual.test:{port}: connection refused"


@pytest.mark.parametrize("cls", CLIENTS)
async def test_a_name_failing_differently_on_its_addresses_says_each(
    cls: type[FocasClient] | type[NativeClient], monkeypatch: pytest.MonkeyPatch
) -> None:
    """Per address, why, in words: never Python's ``[Errno 111] Connect call failed (...)``."""

    class NoIPv6(socket.socket):
        def __init__(self, family: int = -1, *args: Any, **kwargs: Any) -> None:
            if family == socket.AF_INET6:
                raise OSError(errno.EAFNOSUPPORT, "Address family not supported by protocol")
            super().__init__(family, *args, **kwargs)

    _two_addresses(monkeypatch)
    monkeypatch.setattr(socket, "socket", NoIPv6)
    port = free_port()
    err = await failure(cls, port, "dual.test")
    assert type(err) is FocasConnectionError
    assert str(err) == (
        f"cannot connect to dual.test:{port}: [::1]:{port}: address family not supported by "
        f"protocol; 127.0.0.1:{port}: connection refused"
    )


@contextmanager
def never_accepting() -> Iterator[int]:
    """A port whose accept queue is full: a connect to it never completes (the kernel drops
    its SYN); its port."""
    with socket.socket() as server:
        server.bind(("127.0.0.1", 0))
        server.listen(0)
        port: int = server.getsockname()[1]
        fills = [socket.socket() for _ in range(3)]
        try:
            for sock in fills:
                sock.setblocking(False)
                try:
                    sock.connect(("127.0.0.1", port))
                except BlockingIOError:
                    pass
            yield port
        finally:
            for sock in fills:
                sock.close()


@pytest.mark.parametrize("cls", CLIENTS)
async def test_a_connect_that_never_completes_says_so_on_both_clients(
    cls: type[FocasClient] | type[NativeClient],
) -> None:
    """Not "no answer to the open request: nothing received since connecting" on FOCAS/2:
    it never connected."""
    with never_accepting() as port:
        err = await failure(cls, port)
    assert type(err) is FocasTimeoutError
    assert str(err) == f"connecting to 127.0.0.1:{port} timed out"


# -- a peer that says a little, then closes or says no more ---------------------------------

#: The first 12 bytes of an open answer: its header (of 42 bytes to come) and two of them.
CUT_OPEN_ANSWER: Final = NATIVE_HEADER.pack(0xA0A0A0A0, 2, FrameType.OPEN_RESPONSE, 42) + b"\0\0"


@pytest.mark.parametrize("said", [MAGIC, CUT_OPEN_ANSWER], ids=["magic", "cut open answer"])
async def test_an_answer_cut_short_by_a_close_is_a_close_not_before_any_answer(
    said: bytes,
) -> None:
    """The start of an answer is an answer: "connection closed by", no probe, and so no hint
    of a server limited to one connection (which the probes found in the cut answers)."""
    async with says(said, "close") as peer:
        code, out, err = await cli(peer.port, "native")
    assert (code, out) == (EXIT_CONNECTION, ""), err
    assert one_line(err) == f"focas-net: connection closed by 127.0.0.1:{peer.port}"


@pytest.mark.parametrize("said", [MAGIC, CUT_OPEN_ANSWER], ids=["magic", "cut open answer"])
async def test_an_answer_cut_short_then_silence_is_not_nothing_received(said: bytes) -> None:
    async with says(said, "hang") as peer:
        err = await failure(NativeClient, peer.port)
    assert type(err) is FocasTimeoutError
    assert str(err) == "no answer to the open request"


@pytest.mark.parametrize("protocol", PROTOCOLS)
async def test_four_bytes_of_no_frame_then_silence_do_not_speak_focas_on_both(
    protocol: str,
) -> None:
    """FOCAS/2 knows from its first bytes what the packed transport knows from a length:
    no frame starts so, and no timeout is waited for."""
    async with says(b"\x00\x00\x00\x10", "hang") as peer:
        code, out, err = await cli(peer.port, protocol)
    assert (code, out) == (EXIT_PROTOCOL, ""), err
    line = one_line(err)
    assert f"127.0.0.1:{peer.port} does not speak the FOCAS protocol (" in line
    assert line.endswith(r"it sent 00 00 00 10)")


async def test_a_frame_that_does_not_start_so_is_refused_by_the_native_client() -> None:
    async with says(b"\x00\x00\x00\x10", "hang") as peer:
        err = await failure(NativeClient, peer.port)
    assert type(err) is ProtocolError
    assert "its answer does not start with A0 A0 A0 A0" in str(err)


# -- hints that follow from what was given ----------------------------------------------------


@pytest.mark.parametrize(
    ("host", "advice"),
    [
        ("tcp://127.0.0.1:8193", "give --host 127.0.0.1 --port 8193, without a scheme"),
        ("http://[::1]:9400/", "give --host ::1 --port 9400, without a scheme"),
        ("focas://cnc1", "give --host cnc1, without a scheme"),
    ],
)
@pytest.mark.parametrize("command", ["status", "serve"])
async def test_a_url_as_host_names_its_host_and_port(command: str, host: str, advice: str) -> None:
    """Not "not an IPv6 address" (the colons of a URL), on the client's commands and serve."""
    code, out, err = await run_focas_net(command, "--host", host)
    assert (code, out) == (2, ""), err
    line = one_line(err, "focas-net")
    assert f"argument --host: {host!r} is a URL: {advice}; see focas-net {command} --help" in line


@pytest.mark.parametrize("cls", CLIENTS)
def test_a_url_given_to_a_client_names_its_host_and_port(
    cls: type[FocasClient] | type[NativeClient],
) -> None:
    with pytest.raises(ValueError) as caught:
        cls("tcp://127.0.0.1:8193", 8193)
    assert str(caught.value) == (
        "host 'tcp://127.0.0.1:8193' is a URL: give the host '127.0.0.1' and the port 8193 "
        "apart, without a scheme"
    )


@pytest.fixture(scope="module")
def other_name_certificate(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path]:
    """A self-signed certificate for ``cnc.example`` alone, and its key."""
    openssl = shutil.which("openssl")
    if openssl is None:
        pytest.skip("TLS tests need the openssl command to generate a certificate")
    folder = tmp_path_factory.mktemp("tls-other-name")
    cert, key = folder / "cert.pem", folder / "key.pem"
    subprocess.run(
        [openssl, "req", "-x509", "-newkey", "ec", "-pkeyopt", "ec_paramgen_curve:prime256v1",
         "-nodes", "-keyout", str(key), "-out", str(cert), "-days", "1", "-subj", "/CN=cnc",
         "-addext", "subjectAltName=DNS:cnc.example"],
        check=True, capture_output=True, timeout=60,
    )  # fmt: skip
    return cert, key


async def test_a_trusted_certificate_of_another_name_does_not_ask_for_tls_ca(
    other_name_certificate: tuple[Path, Path],
) -> None:
    """``--tls-ca`` was given, and trusts it: the host is what does not match."""
    cert, key = other_name_certificate
    context = ssl.SSLContext(ssl.PROTOCOL_TLS_SERVER)
    context.load_cert_chain(cert, key)
    async with serving(ssl=context) as served:
        code, out, err = await run_focas_net(
            "status", "--port", str(served.port), "--tls-ca", str(cert)
        )
    assert (code, out) == (EXIT_CONNECTION, ""), err
    line = one_line(err)
    assert "certificate is not valid for '127.0.0.1';" in line  # (no "'.;")
    assert line.endswith(
        "the certificate does not name 127.0.0.1: connect by a name it holds (--host NAME), "
        "or give --tls-insecure"
    )
    assert "--tls-ca" not in line


async def test_a_focas2_open_one_connection_short_of_the_limit_blames_no_limit_of_one() -> None:
    """A server of ``--max-connections 2`` with one taken by another client: the hint says
    either may be so, and asks for no limit the server does not have."""
    async with serving(max_connections=2) as served, await served.connect():
        code, out, err = await cli(served.port, "native")
    assert (code, out) == (EXIT_CONNECTION, ""), err
    line = one_line(err)
    assert "FOCAS/2's open, which takes two: a server with one connection free" in line
    assert "or other clients holding the others" in line
    assert "a server limited to one connection" not in line


# -- serve's ports ---------------------------------------------------------------------------


async def test_a_native_port_in_use_is_the_port_named() -> None:
    """Not the first port (``--port 0``), which was free: the one taken."""
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen(1)
        port = taken.getsockname()[1]
        code, out, err = await run_focas_net("serve", "--port", "0", "--native-port", str(port))
    assert (code, out) == (1, ""), err
    assert one_line(err, "focas-net") == (
        f"focas-net serve: error: cannot listen on 127.0.0.1:{port} (--native-port): "
        "address already in use"
    )


def _free(port: int) -> bool:
    with socket.socket() as probe:
        try:
            probe.bind(("127.0.0.1", port))
        except OSError:
            return False
    return True


async def test_a_fleet_port_in_use_is_the_port_named() -> None:
    """The third machine's port is taken: the refusal names it, not the fleet's first. (The
    two ports below it are other programs' to take meanwhile: a run that met one of them
    taken is tried again, three runs at most.)"""
    for _ in range(3):
        with socket.socket() as taken:
            taken.bind(("127.0.0.1", 0))
            taken.listen(1)
            port = taken.getsockname()[1]
            if not (_free(port - 2) and _free(port - 1)):
                continue
            code, out, err = await run_focas_net("serve", "--port", str(port - 2), "--fleet", "3")
        assert (code, out) == (1, ""), err
        line = one_line(err, "focas-net")
        if f"127.0.0.1:{port - 2}:" in line or f"127.0.0.1:{port - 1}:" in line:
            continue  # (taken by another program between the probe and the run)
        assert f"cannot listen on 127.0.0.1:{port}: address already in use" in line
        return
    pytest.skip("the ports below an ephemeral one were taken by other programs in 3 runs")


# -- a call whose time is up while reconnecting ----------------------------------------------


@pytest.mark.parametrize("cls", CLIENTS)
async def test_still_reconnecting_says_why_it_was_lost_and_why_the_attempt_failed(
    cls: type[FocasClient] | type[NativeClient],
) -> None:
    """What ``watch`` shows under its frame while the server is down: the causes, not only
    that it is still reconnecting."""
    policy = ReconnectPolicy(initial_delay=0.01, max_delay=0.05, jitter=0)
    async with serving() as served:
        port = served.port
        client = cls("127.0.0.1", port, timeout=IO_TIMEOUT, reconnect=policy)
        await client.connect()
        await client.read_status()  # (answered: a close now is no close "before any answer")
    try:
        await wait_until(lambda: client._attempt_error is not None)
        with pytest.raises(FocasConnectionError) as caught:
            await client.read_status(timeout=0.2)
    finally:
        await client.aclose()
    assert str(caught.value) == (
        f"still reconnecting to 127.0.0.1:{port} when the call timed out (connection closed by "
        f"127.0.0.1:{port}; the last reconnect attempt failed: cannot connect to "
        f"127.0.0.1:{port}: connection refused)"
    )


@pytest.mark.parametrize("cls", CLIENTS)
async def test_lost_reason_is_why_while_reconnecting_and_none_once_back(
    cls: type[FocasClient] | type[NativeClient],
) -> None:
    """What ``alarms --follow`` prints when its connection is lost (``lost: <why>;
    reconnecting``), as ``watch`` does."""
    policy = ReconnectPolicy(initial_delay=0.01, max_delay=0.05, jitter=0)
    seen: list[str] = []

    def record(state: ClientState) -> None:
        if state is ClientState.RECONNECTING:
            seen.append(str(client.lost_reason))

    async with serving() as served:
        client = cls("127.0.0.1", served.port, timeout=IO_TIMEOUT, reconnect=policy)
        client.add_state_callback(record)
        await client.connect()
        try:
            await client.read_status()
            assert client.lost_reason is None
            for conn in list(served.listener.all_connections()):
                conn.abort()
            await wait_until(lambda: bool(seen))
            await client.read_status()  # reconnected
            assert client.lost_reason is None
        finally:
            await client.aclose()
    assert seen == [f"connection closed by 127.0.0.1:{served.port}"]


@pytest.mark.skipif(not socket.has_ipv6, reason="needs IPv6")
@pytest.mark.parametrize("cls", CLIENTS)
async def test_a_link_local_address_without_its_interface_says_it_needs_one(
    cls: type[FocasClient] | type[NativeClient],
) -> None:
    """Linux refuses the connect with EINVAL, which alone says nothing of the cause."""
    err = await failure(cls, 8193, "fe80::1")
    assert type(err) is FocasConnectionError
    assert str(err) == (
        "cannot connect to [fe80::1]:8193: invalid argument: fe80::1 is a link-local address, "
        "which needs its interface (fe80::1%eth0, the interface's name or number after %)"
    )


# -- a packed answer that does not decode -----------------------------------------------------


class AnswersWith(LoopbackPeer):
    """A packed peer answering every request with its own command and id and ``payload`` (an
    echo peer answers so with an empty one)."""

    def __init__(self, payload: bytes) -> None:
        self.payload = payload

    async def _serve(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        decoder = FrameDecoder()
        try:
            for _ in range(100):  # bounded: a command sends a few requests
                data = await reader.read(4096)
                if not data:
                    break
                for frame in decoder.feed(data):
                    writer.write(encode_frame(frame.command, frame.request_id, self.payload))
        finally:
            writer.close()


@pytest.mark.parametrize(
    ("payload", "argv", "call", "why"),
    [
        # (an empty answer to an empty request, status's, is its request sent back: an echo)
        (b"", ("diag", "300"), "cnc_rddiag (0x0004)", "answer of 0 bytes has no EW code"),
        (b"\0\0", ("macro", "get", "100"), "cnc_rdmacro (0x0003)", "0 bytes, expected 10"),
        (b"\0", ("pmc", "read", "R", "0", "3"), "pmc_rdpmcrng (0x0010)", "answer of 1 bytes"),
    ],
)
async def test_an_answer_that_does_not_decode_names_the_peer_and_the_call(
    payload: bytes, argv: tuple[str, ...], call: str, why: str
) -> None:
    async with AnswersWith(payload) as peer:
        code, out, err = await cli(peer.port, "packed", *argv)
    assert (code, out) == (EXIT_PROTOCOL, ""), err
    line = one_line(err)
    assert line.startswith(
        f"focas-net: 127.0.0.1:{peer.port} sent an answer to {call} that does not decode: {why}"
    )


# -- a FOCAS/2-only port and a command FOCAS/2 cannot carry -----------------------------------


@pytest.mark.parametrize(
    ("argv", "needs"),
    [
        (("unlock", "1234"), "unlock"),
        (("sim", "panel", "--mode", "MDI"), "sim panel"),
        (("param", "set", "1420", "5000", "--axis", "1", "--password", "1234"), "--password"),
        (("watch", "--count", "1"), "watch"),
    ],
)
async def test_a_native_only_port_does_not_send_a_packed_only_command_to_protocol_native(
    argv: tuple[str, ...], needs: str
) -> None:
    """``give --protocol native`` would be refused there (exit 2): the main port serves it."""
    async with serving(native_port=0) as served:
        native = served.listener.native
        assert native is not None
        code, out, err = await cli(native.address[1], "packed", *argv)
    assert (code, out) == (EXIT_CONNECTION, ""), err
    line = one_line(err)
    assert line.endswith(
        f"the port speaks FOCAS/2 only (serve --native-port), which cannot carry {needs}: "
        "connect to the server's main port, which speaks both"
    )
    assert "give --protocol native" not in line


def test_the_advice_for_a_packed_only_command_on_a_native_port_with_tls() -> None:
    said = _diagnose.advice(Findings(False, False, False, True), "packed", True, "unlock")
    assert said == (
        "the port speaks FOCAS/2 only (serve --native-port), without TLS, which cannot carry "
        "unlock: connect to the server's main port, which speaks both"
    )


# -- alarms --follow when an HTTP server takes the CNC's place --------------------------------


@contextmanager
def http_server_on(port: int) -> Iterator[None]:
    """Python's own ``http.server`` on ``port`` of 127.0.0.1, in a thread."""
    httpd = ThreadingHTTPServer(("127.0.0.1", port), SimpleHTTPRequestHandler)
    httpd.daemon_threads = True
    thread = threading.Thread(target=httpd.serve_forever, daemon=True)
    thread.start()
    try:
        yield
    finally:
        httpd.shutdown()
        httpd.server_close()
        thread.join(IO_TIMEOUT)


@pytest.mark.parametrize("protocol", PROTOCOLS)
async def test_follow_finds_an_http_server_in_the_cncs_place_on_both_transports(
    protocol: str, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """FOCAS/2's reconnect attempts time out on it (its open has no end of line), so the
    follower gives up still reconnecting: the last attempt's failure is what is diagnosed,
    and the line is the packed transport's (exit 4), not a timeout (exit 3)."""
    monkeypatch.setattr(_run, "FOLLOW_MAX_FAILURES", 2)
    printed: list[str] = []

    def followed() -> bool:
        printed.append(capsys.readouterr().out)
        return "raised" in "".join(printed)

    async with serving() as served:
        port = served.port
        served.machine.raise_alarm(0, 3, 100, "ACTIVE")
        argv = ["alarms", "--follow", "--interval", "0.05", "--timeout", SHORT]
        argv += ["--port", str(port), "--protocol", protocol]
        follow = asyncio.create_task(asyncio.to_thread(main, argv))
        await wait_until(followed)
    with http_server_on(port):
        async with asyncio.timeout(8 * IO_TIMEOUT):
            code = await follow
    err = capsys.readouterr().err.splitlines()
    assert code == EXIT_PROTOCOL, err
    last = err[-1]
    assert last.startswith(
        f"focas-net: 127.0.0.1:{port} does not speak the FOCAS protocol (it answers "
        "'HTTP/1.0 200' to an HTTP request and no FOCAS frame: an HTTP server); "
        "alarms --follow gave up after "
    ), last


# -- a peer that sends garbage after the connect ---------------------------------------------


class GarblingProxy(LoopbackPeer):
    """Passes each connection on to ``upstream`` (a port of 127.0.0.1); once ``garble`` is
    set, what comes back is replaced with bytes no frame of either protocol starts with."""

    GARBAGE: Final = b"\xde\xad\xbe\xef" * 4

    def __init__(self, upstream: int) -> None:
        self.upstream = upstream
        self.garble = False

    async def _serve(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        up_reader, up_writer = await asyncio.open_connection("127.0.0.1", self.upstream)

        async def pump(src: asyncio.StreamReader, dst: asyncio.StreamWriter, back: bool) -> None:
            for _ in range(100_000):  # bounded: a test's few calls
                data = await src.read(65536)
                if not data:
                    break
                dst.write(self.GARBAGE if back and self.garble else data)
                await dst.drain()
            dst.close()

        try:
            await asyncio.gather(
                pump(reader, up_writer, False),
                pump(up_reader, writer, True),
                return_exceptions=True,
            )
        finally:
            writer.close()
            up_writer.close()


@pytest.mark.parametrize("cls", CLIENTS)
async def test_garbage_after_the_connect_is_a_peer_that_does_not_speak_focas_on_both(
    cls: type[FocasClient] | type[NativeClient],
) -> None:
    """Not a bare ``closed`` (FOCAS/2 gave its calls the text of no loss yet), and no
    reconnect to a peer that would send it again: later calls raise the same error."""
    policy = ReconnectPolicy(initial_delay=0.01, max_delay=0.05, jitter=0)
    async with serving() as served, GarblingProxy(served.port) as proxy:
        async with cls("127.0.0.1", proxy.port, timeout=IO_TIMEOUT, reconnect=policy) as client:
            await client.read_status()
            proxy.garble = True
            with pytest.raises(ProtocolError) as caught:
                await client.read_status()
            with pytest.raises(ProtocolError) as again:
                await client.read_status()
            assert client.state is ClientState.DISCONNECTED
    text = str(caught.value)
    assert text.startswith(f"127.0.0.1:{proxy.port} does not speak the FOCAS protocol (")
    assert text.endswith(r"it sent DE AD BE EF DE AD BE EF)")
    assert str(again.value) == text


async def test_a_native_port_limited_to_one_connection_is_refused_at_start() -> None:
    """It speaks FOCAS/2 alone, whose open takes two: no client could use it."""
    code, out, err = await run_focas_net(
        "serve", "--port", "0", "--native-port", "0", "--max-connections", "1"
    )
    assert (code, out) == (2, ""), err
    assert one_line(err, "focas-net") == (
        "focas-net serve: error: argument --max-connections: 1 leaves --native-port unusable: "
        "it speaks FOCAS/2 alone, whose open takes two connections (give 2 or more); see "
        "focas-net serve --help"
    )


class AnswersAnotherCommand(LoopbackPeer):
    """A packed peer answering every request with command 0x0099 and the request's id."""

    async def _serve(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        decoder = FrameDecoder()
        try:
            for _ in range(100):  # bounded: a command sends a few requests
                data = await reader.read(4096)
                if not data:
                    break
                for frame in decoder.feed(data):
                    writer.write(encode_frame(0x0099, frame.request_id, b"\0\0"))
        finally:
            writer.close()


async def test_an_answer_of_another_command_names_the_peer_and_both_calls() -> None:
    """Not ``answer to request 0 carries command 0x0099, expected 0x0001``: the peer, the
    call asked by its FOCAS name, what came instead."""
    async with AnswersAnotherCommand() as peer:
        code, out, err = await cli(peer.port, "packed")
    assert (code, out) == (EXIT_PROTOCOL, ""), err
    assert one_line(err) == (
        f"focas-net: 127.0.0.1:{peer.port} answered cnc_rdcncstat (0x0001) with an answer of "
        "0x0099 (request 0)"
    )
