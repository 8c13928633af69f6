"""Transports and hints, a confirming pass: what a new user meets with passwords, wrong
peers, odd addresses and ``serve``'s options, in cases the earlier passes did not try.

Servers here bind 127.0.0.1 on ephemeral ports; ``focas-net`` runs as a subprocess where its
exit code is checked.
"""

from __future__ import annotations

import asyncio
import errno
import shutil
import socket
import ssl
import struct
import subprocess
from pathlib import Path

import pytest
from cli_support import INTERRUPTED_IMPORT, one_line, run_entry, run_focas_net
from support import IO_TIMEOUT, LoopbackPeer, serving

from focas_net.client import NativeClient
from focas_net.client._failures import connect_error
from focas_net.errors import ProtocolError


def _closed_port() -> int:
    """A port of 127.0.0.1 nothing listens on (bound, then closed)."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port: int = s.getsockname()[1]
    return port


@pytest.mark.parametrize(
    ("argv", "named"),
    [
        (("unlock", ""), "PASSWORD"),
        (("unlock", "ABCDE"), "PASSWORD"),
        (("param", "set", "1020", "5", "--password", "ABCDE"), "--password"),
        (("macro", "set", "100", "5", "--password", "é"), "--password"),
    ],
)
async def test_a_bad_password_is_a_usage_error_naming_its_argument_before_any_connect(
    argv: tuple[str, ...], named: str
) -> None:
    """``unlock ''`` connected first (exit 3 when the CNC was away, as if the password were
    good), and both refusals read `parameter password '': ...`, naming no argument, in words
    other than ``serve --param-password``'s."""
    typed = argv[argv.index("--password") + 1] if "--password" in argv else argv[1]
    command = " ".join(argv[:2]) if argv[0] != "unlock" else "unlock"
    code, out, err = await run_focas_net(*argv, "--port", str(_closed_port()))
    assert (code, out) == (2, "")
    assert one_line(err, f"focas-net {command}: error:") == (
        f"focas-net {command}: error: argument {named}: parameter password {typed!r}: must be "
        f"1..4 ASCII characters; see focas-net {command} --help"
    )


class _ResettingPeer(LoopbackPeer):
    """Accepts each connection and resets it at once (a close with SO_LINGER 0), as a
    server at its limit may close one: the client's connect may meet the reset."""

    async def _serve(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        sock = writer.get_extra_info("socket")
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, struct.pack("ii", 1, 0))
        writer.transport.abort()


@pytest.mark.parametrize("protocol", ["packed", "native"])
async def test_a_peer_that_resets_each_connection_at_once_reads_as_closed_before_any_answer(
    protocol: str,
) -> None:
    """It read `cannot connect to 127.0.0.1:P: connection reset by peer`, where docs/cli.md
    says a reset reads as a close, and without the probe's advice a close at once gets."""
    async with _ResettingPeer() as peer:
        code, out, err = await run_focas_net(
            "status", "--port", str(peer.port), "--timeout", "1", "--protocol", protocol
        )
    assert (code, out) == (3, "")
    assert one_line(err) == (
        f"focas-net: connection closed by 127.0.0.1:{peer.port} before any answer; the server "
        "refused the connection: it closes new ones at once, as a server at its connection "
        "limit does (focas-net serve --max-connections)"
    )


def test_a_connect_the_peer_resets_is_a_close_before_any_answer() -> None:
    """Whether the reset of a peer that closes at once meets the connect or the request is
    a race: both read the same, without TLS (with TLS it ended the handshake)."""
    exc = ConnectionResetError(errno.ECONNRESET, "Connection reset by peer")
    plain = connect_error("127.0.0.1", 8193, exc, None)
    assert str(plain) == "connection closed by 127.0.0.1:8193 before any answer"
    assert plain.__cause__ is exc
    tls = connect_error("127.0.0.1", 8193, exc, ssl.create_default_context())
    assert str(tls) == (
        "cannot connect to 127.0.0.1:8193: TLS handshake failed (the peer closed it): the peer "
        "may not speak TLS"
    )
    refused = connect_error("::1", 8193, ConnectionRefusedError(errno.ECONNREFUSED, "x"), None)
    assert str(refused) == "cannot connect to [::1]:8193: connection refused"


def _self_signed(folder: Path, name: str) -> tuple[Path, Path]:
    """A self-signed certificate for ``name`` and 127.0.0.1, and its key, in ``folder``."""
    openssl = shutil.which("openssl")
    if openssl is None:
        pytest.skip("TLS tests need the openssl command to generate a certificate")
    cert, key = folder / f"{name}.pem", folder / f"{name}-key.pem"
    subprocess.run(
        [openssl, "req", "-x509", "-newkey", "ec", "-pkeyopt", "ec_paramgen_curve:prime256v1",
         "-nodes", "-keyout", str(key), "-out", str(cert), "-days", "1", "-subj", f"/CN={name}",
         "-addext", "subjectAltName=IP:127.0.0.1"],
        check=True, capture_output=True, timeout=60,
    )  # fmt: skip
    return cert, key


async def test_a_certificate_the_tls_ca_file_given_does_not_trust_names_that_file(
    tmp_path: Path,
) -> None:
    """With ``--tls-ca`` given, the advice was `give --tls-ca FILE (the server's certificate
    or its CA) or --tls-insecure`, as if no file had been given."""
    cert, key = _self_signed(tmp_path, "cnc")
    other, _ = _self_signed(tmp_path, "other")
    context = ssl.SSLContext(ssl.PROTOCOL_TLS_SERVER)
    context.load_cert_chain(cert, key)
    async with serving(ssl=context) as served:
        code, out, err = await run_focas_net(
            "status", "--port", str(served.port), "--tls-ca", str(other)
        )
    assert (code, out) == (3, "")
    line = one_line(err)
    assert line.startswith(f"focas-net: cannot connect to 127.0.0.1:{served.port}: TLS ")
    assert line.endswith(
        f"; the server's certificate is neither in --tls-ca {other} nor signed by a "
        "certificate there: give its own certificate or its CA's, or --tls-insecure"
    )


class _OneByteThenSilent(LoopbackPeer):
    """Answers each connection with one byte that starts no frame, then says nothing."""

    async def _serve(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        writer.write(b"\x00")
        await reader.read()  # until the client closes
        writer.close()


async def test_a_native_answer_that_cannot_start_a_frame_is_refused_as_it_comes() -> None:
    """docs/cli.md: bytes that cannot start a frame make the peer one that does not speak
    FOCAS `at once`; FOCAS/2's open waited for the call's whole time first (a client of a
    long timeout sat there for all of it)."""
    async with _OneByteThenSilent() as peer:
        client = NativeClient("127.0.0.1", peer.port, timeout=3600)
        async with asyncio.timeout(IO_TIMEOUT):  # (not the client's hour)
            with pytest.raises(ProtocolError) as refusal:
                await client.connect()
    assert str(refusal.value) == (
        f"127.0.0.1:{peer.port} does not speak the FOCAS protocol (its answer does not start "
        "with A0 A0 A0 A0; it sent 00)"
    )


async def test_a_native_port_equal_to_the_port_names_no_fleet_not_typed() -> None:
    """It said `overlaps the ports 40111..40111 of --fleet 1`, an option not typed."""
    port = _closed_port()
    code, out, err = await run_focas_net("serve", "--port", str(port), "--native-port", str(port))
    assert (code, out) == (2, "")
    assert one_line(err, "focas-net serve: error:") == (
        f"focas-net serve: error: argument --native-port: {port} is the port of --port {port}, "
        "which speaks FOCAS/2 too: leave --native-port out, or give it another port; see "
        "focas-net serve --help"
    )


@pytest.mark.parametrize(
    ("argv", "code"),
    [
        (["watch", "--port", "1"], 0),
        (["alarms", "--port", "1", "--follow"], 0),
        (["alarms", "--fol", "--port", "1"], 0),
        (["serve", "--port", "0"], 0),
        (["status", "--port", "1"], 130),
        (["alarms", "--port", "1"], 130),
    ],
)
def test_ctrl_c_while_importing_ends_a_command_that_runs_until_told_with_0(
    argv: list[str], code: int
) -> None:
    """docs/cli.md: ``watch`` and ``alarms --follow`` end with 0 on Ctrl-C `at any moment`, as
    ``serve`` and ``gateway`` do; while the package was imported they ended with 130."""
    program = INTERRUPTED_IMPORT.replace('["focas-net", "--version"]', repr(["focas-net", *argv]))
    done = run_entry(program)
    assert (done.returncode, done.stdout, done.stderr) == (code, "", "")
