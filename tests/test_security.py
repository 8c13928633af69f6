"""Hardening: loopback by default, read-only machines, TLS on both sides, the parameter
password compared in constant time and kept out of the logs.

The TLS certificate is generated inside the test with the ``openssl`` command (skipped with a
message when it is missing). Servers run in this process on 127.0.0.1 (port 0), or as the
``focas-net serve`` command in a child process for the command-line options.
"""

from __future__ import annotations

import asyncio
import hmac
import inspect
import logging
import signal
import ssl
import subprocess
import sys
from collections.abc import AsyncIterator, Iterator
from contextlib import asynccontextmanager
from decimal import Decimal
from pathlib import Path
from typing import Any, Final

import pytest
from support import IO_TIMEOUT, Served, serving

from focas_net.cli import build_parser
from focas_net.client import FocasClient
from focas_net.errors import (
    EW,
    AccessDeniedError,
    ChunkedWriteError,
    CncError,
    FocasConnectionError,
    FocasTimeoutError,
)
from focas_net.protocol import FaultKind
from focas_net.server import FocasServer
from focas_net.sim import default_machine

PASSWORD: Final = "Pw9!"


# -- the command line in a child process ---------------------------------------------------------


class Serve:
    """``focas-net serve ARGS`` in a child process; stopped with SIGTERM."""

    def __init__(self, *args: str) -> None:
        self.proc = subprocess.Popen(
            [sys.executable, "-m", "focas_net", "serve", *args],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )

    async def address(self) -> tuple[str, int]:
        assert self.proc.stdout is not None
        line = await asyncio.wait_for(asyncio.to_thread(self.proc.stdout.readline), 20)
        if "listening on" not in line:
            self.proc.kill()
            _, err = self.proc.communicate(timeout=10)
            pytest.fail(f"focas-net serve did not start: {line!r} {err!r}")
        host, port = line.rsplit(" ", 1)[1].strip().rsplit(":", 1)
        return host, int(port)

    def stop(self) -> tuple[int, str]:
        """SIGTERM; the exit code and everything written to stderr."""
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGTERM)
        try:
            _, err = self.proc.communicate(timeout=20)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            _, err = self.proc.communicate(timeout=10)
        return self.proc.returncode, err


@pytest.fixture
def cli() -> Iterator[list[Serve]]:
    started: list[Serve] = []
    yield started
    for serve in started:
        if serve.proc.poll() is None:
            serve.proc.kill()
            serve.proc.communicate(timeout=10)


def start(cli: list[Serve], *args: str) -> Serve:
    serve = Serve(*args)
    cli.append(serve)
    return serve


# -- loopback by default ---------------------------------------------------------------------------


async def test_focas_server_binds_loopback_by_default() -> None:
    assert inspect.signature(FocasServer).parameters["host"].default == "127.0.0.1"
    async with FocasServer(default_machine(), port=0, grace_period=0.5) as server:
        assert [host for host, _ in server.addresses] == ["127.0.0.1"]


async def test_focas_net_serve_binds_loopback_by_default(cli: list[Serve]) -> None:
    assert build_parser().parse_args(["serve"]).host == "127.0.0.1"
    serve = start(cli, "--port", "0")
    host, port = await serve.address()
    assert host == "127.0.0.1"
    async with FocasClient(host, port, timeout=IO_TIMEOUT) as cnc:
        await cnc.read_status()
    code, _ = serve.stop()
    assert code == 0


# -- read-only ------------------------------------------------------------------------------------


async def assert_every_write_is_refused(cnc: FocasClient) -> None:
    async def refused(call: Any) -> None:
        with pytest.raises(CncError) as caught:
            await call
        assert caught.value.ew == EW.PROT, caught.value

    await refused(cnc.write_param(6711, 5, width=4))
    await refused(cnc.write_param(1320, 5, axis=1, width=4))
    await refused(cnc.write_param_bit(1815, 1, True, axis=1))
    await refused(cnc.write_macro(100, 1))
    await refused(cnc.write_macro(500, Decimal("1.5")))
    await refused(cnc.write_pmc("R", 0, b"\x01"))
    await refused(cnc.write_pmc("Y", 0, b"\x01"))
    await refused(cnc.write_pmc_bit("R", 10, 3, True))
    await refused(cnc.sim.set_panel(0, pwe=True))
    await refused(cnc.sim.raise_alarm(3, 100, "NO"))
    await refused(cnc.sim.clear_alarms())
    await refused(cnc.sim.set_pmc("X", 0, b"\x01"))
    await refused(cnc.sim.inject_fault(FaultKind.DROP))
    with pytest.raises(ChunkedWriteError) as chunked:
        await cnc.write_pmc("D", 0, bytes(100))
    assert chunked.value.written == []
    assert isinstance(chunked.value.cause, CncError) and chunked.value.cause.ew == EW.PROT


async def assert_reads_work(cnc: FocasClient) -> None:
    status = await cnc.read_status()
    assert status.aut == 1  # MEM
    assert (await cnc.read_sysinfo()).axes == b"03"
    await cnc.read_param(1320, axis=1)
    await cnc.read_diag(300, axis=1)
    assert await cnc.read_macro(100) is None
    assert await cnc.read_pmc("D", 0, 100) == bytes(100)
    assert await cnc.read_alarms() == ()
    assert (await cnc.read_alarm_history()).entries == ()
    assert (await cnc.read_module_config(0, 3)).label == "D844"


async def test_read_only_machine_refuses_every_write_and_serves_reads() -> None:
    machine = default_machine(read_only=True)
    before = machine.state_digest()
    async with serving(machine) as served:
        async with FocasClient(served.host, served.port, timeout=IO_TIMEOUT) as cnc:
            await assert_every_write_is_refused(cnc)
            await assert_reads_work(cnc)
            await cnc.unlock("any")  # connection state, not machine state: allowed
    assert machine.state_digest() == before


async def test_focas_server_read_only_argument_covers_a_fleet() -> None:
    machines = [default_machine(), default_machine()]
    async with FocasServer(machines, port=0, read_only=True, control=True) as server:
        assert all(m.read_only and m.control_enabled for m in machines)
        befores = [m.state_digest() for m in machines]
        for host, port in server.addresses:
            async with FocasClient(host, port, timeout=IO_TIMEOUT) as cnc:
                await assert_every_write_is_refused(cnc)
                await assert_reads_work(cnc)
    assert [m.state_digest() for m in machines] == befores


async def test_focas_net_serve_read_only(cli: list[Serve]) -> None:
    serve = start(cli, "--port", "0", "--read-only")
    host, port = await serve.address()
    async with FocasClient(host, port, timeout=IO_TIMEOUT) as cnc:
        await assert_every_write_is_refused(cnc)
        await assert_reads_work(cnc)
    code, _ = serve.stop()
    assert code == 0


# -- TLS ------------------------------------------------------------------------------------------


def server_context(cert: Path, key: Path) -> ssl.SSLContext:
    ctx = ssl.SSLContext(ssl.PROTOCOL_TLS_SERVER)
    ctx.load_cert_chain(cert, key)
    return ctx


def client_context(cert: Path) -> ssl.SSLContext:
    return ssl.create_default_context(cafile=str(cert))


@asynccontextmanager
async def tls_served(certificate: tuple[Path, Path]) -> AsyncIterator[Served]:
    async with serving(ssl=server_context(*certificate)) as served:
        yield served


async def exercise(cnc: FocasClient) -> None:
    await cnc.read_status()
    await cnc.write_macro(100, Decimal("12.5"))
    assert await cnc.read_macro(100) == Decimal("12.5")
    await cnc.write_pmc("D", 0, bytes(range(100)))
    assert await cnc.read_pmc("D", 0, 100) == bytes(range(100))


async def test_tls_on_both_sides(certificate: tuple[Path, Path]) -> None:
    cert, _ = certificate
    async with tls_served(certificate) as served:
        async with FocasClient(
            served.host, served.port, timeout=IO_TIMEOUT, ssl=client_context(cert)
        ) as cnc:
            await exercise(cnc)
        # the name in the certificate works too
        async with FocasClient(
            served.host,
            served.port,
            timeout=IO_TIMEOUT,
            ssl=client_context(cert),
            server_hostname="localhost",
        ) as cnc:
            await cnc.read_status()


async def test_tls_server_refuses_plain_and_untrusting_clients(
    certificate: tuple[Path, Path],
) -> None:
    cert, _ = certificate
    async with tls_served(certificate) as served:
        plain = FocasClient(served.host, served.port, timeout=1.0)
        try:
            with pytest.raises((FocasConnectionError, FocasTimeoutError)):
                await plain.connect()
                await plain.read_status()
        finally:
            await plain.aclose()
        untrusting = FocasClient(
            served.host, served.port, timeout=IO_TIMEOUT, ssl=ssl.create_default_context()
        )
        with pytest.raises(FocasConnectionError):
            await untrusting.connect()
        await untrusting.aclose()
        # the server is unharmed
        async with FocasClient(
            served.host, served.port, timeout=IO_TIMEOUT, ssl=client_context(cert)
        ) as cnc:
            await cnc.read_status()


async def test_plain_client_against_tls_server_does_not_hang_the_server(
    certificate: tuple[Path, Path],
) -> None:
    async with tls_served(certificate) as served:
        wire = await served.connect()
        async with wire:
            wire.send_raw(b"\x04\x00\x00\x00\x01\x00\x01\x00")
            assert await wire.closed_by_peer()


async def test_focas_net_serve_with_tls(cli: list[Serve], certificate: tuple[Path, Path]) -> None:
    cert, key = certificate
    serve = start(cli, "--port", "0", "--tls-cert", str(cert), "--tls-key", str(key))
    host, port = await serve.address()
    async with FocasClient(host, port, timeout=IO_TIMEOUT, ssl=client_context(cert)) as cnc:
        await exercise(cnc)
    plain = FocasClient(host, port, timeout=1.0)
    try:
        with pytest.raises((FocasConnectionError, FocasTimeoutError)):
            await plain.connect()
            await plain.read_status()
    finally:
        await plain.aclose()
    code, _ = serve.stop()
    assert code == 0


def test_focas_net_serve_tls_key_without_certificate(certificate: tuple[Path, Path]) -> None:
    _, key = certificate
    done = subprocess.run(
        [sys.executable, "-m", "focas_net", "serve", "--port", "0", "--tls-key", str(key)],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert done.returncode == 2
    assert "--tls-cert" in done.stderr


# -- the parameter password -----------------------------------------------------------------------


async def test_password_is_compared_with_compare_digest(monkeypatch: pytest.MonkeyPatch) -> None:
    seen: list[tuple[bytes, bytes]] = []
    original = hmac.compare_digest

    def spy(a: Any, b: Any) -> bool:
        seen.append((bytes(a), bytes(b)))
        return original(a, b)

    monkeypatch.setattr(hmac, "compare_digest", spy)
    async with serving(default_machine(param_password=PASSWORD)) as served:
        async with FocasClient(served.host, served.port, timeout=IO_TIMEOUT) as cnc:
            with pytest.raises(AccessDeniedError):
                await cnc.unlock("nope")
            assert seen, "the password was not compared with hmac.compare_digest"
            assert {PASSWORD.encode(), b"nope"} == set(seen[-1])
            count = len(seen)
            await cnc.unlock(PASSWORD)
            assert len(seen) == count + 1
            assert set(seen[-1]) == {PASSWORD.encode()}


def _password_forms() -> list[str]:
    raw = PASSWORD.encode()
    return [PASSWORD, repr(raw), raw.hex(), raw.hex(" "), raw.hex(" ").upper(), raw.hex().upper()]


async def _unlock_failed_then_succeeded(served: Served) -> None:
    async with FocasClient(served.host, served.port, timeout=IO_TIMEOUT) as wrong:
        with pytest.raises(AccessDeniedError):
            await wrong.unlock("nope")
        await wrong.sim.set_panel(0, pwe=True)
        with pytest.raises(AccessDeniedError):
            await wrong.write_param(6711, 1, width=4)
    async with FocasClient(
        served.host, served.port, timeout=IO_TIMEOUT, password=PASSWORD
    ) as right:
        await right.write_param(6711, 1, width=4)
        assert await right.read_param(6711) == 1
    # a client whose password is refused at connect time
    refused = FocasClient(served.host, served.port, timeout=IO_TIMEOUT, password="bad!")
    with pytest.raises(AccessDeniedError):
        await refused.connect()
    await refused.aclose()


async def test_password_text_is_never_logged(caplog: pytest.LogCaptureFixture) -> None:
    caplog.set_level(logging.DEBUG)
    machine = default_machine(param_password=PASSWORD)
    async with serving(machine) as served:
        await _unlock_failed_then_succeeded(served)
        shown = [repr(machine), repr(served.server), str(served.server.stats())]
    text = "\n".join([*(r.getMessage() for r in caplog.records), *shown])
    assert caplog.records, "nothing was logged at DEBUG: the check would prove nothing"
    assert PASSWORD not in text
    assert repr(PASSWORD.encode()) not in text


async def test_password_is_not_logged_in_hex_dumps(caplog: pytest.LogCaptureFixture) -> None:
    caplog.set_level(logging.DEBUG)
    async with serving(default_machine(param_password=PASSWORD)) as served:
        await _unlock_failed_then_succeeded(served)
    text = "\n".join(r.getMessage() for r in caplog.records)
    assert any("from" in r.getMessage() for r in caplog.records)
    for form in _password_forms():
        assert form not in text, f"the password appears in the log as {form!r}"


async def test_focas_net_serve_never_prints_the_password(cli: list[Serve]) -> None:
    serve = start(cli, "--port", "0", "--param-password", PASSWORD, "--log-level", "INFO")
    host, port = await serve.address()
    async with FocasClient(host, port, timeout=IO_TIMEOUT) as cnc:
        with pytest.raises(AccessDeniedError):
            await cnc.unlock("nope")
        await cnc.unlock(PASSWORD)
    code, err = serve.stop()
    assert code == 0
    assert "listening" in err  # the log did reach stderr
    for form in _password_forms():
        assert form not in err
