"""Shared fixtures: a real server on 127.0.0.1 (port 0), a raw wire to it, a scripted peer,
leak checks.

The helpers they are built on are in ``support.py`` and ``peers.py``, which test modules
import; this file is never imported.
"""

from __future__ import annotations

import asyncio
import shutil
import signal
import subprocess
from collections.abc import AsyncIterator, Iterator
from pathlib import Path
from typing import Any

import pytest
from fwlib_support import Recorder, record_requests
from hypothesis import settings
from peers import ScriptedPeer
from support import Served, Wire, serving, with_both_clients

from focas_net.cli import _signals
from focas_net.client import FocasClient, NativeClient
from focas_net.sim import Machine, default_machine
from focas_net.sim.nc import ManualClock

# No wall-clock deadline on a hypothesis example: speed is the benchmarks' to measure, and a
# busy machine made single examples of pure codec tests run past hypothesis's 200 ms.
settings.register_profile("focas_net", deadline=None)
settings.load_profile("focas_net")


@pytest.fixture(autouse=True)
async def _no_leaked_tasks() -> AsyncIterator[None]:
    """Fail a test that leaves asyncio tasks running behind it."""
    before = asyncio.all_tasks()
    yield
    current = asyncio.current_task()
    leaked: set[asyncio.Task[Any]] = set()
    for _ in range(20):  # let tasks that are finishing finish
        leaked = {t for t in asyncio.all_tasks() - before if t is not current and not t.done()}
        if not leaked:
            break
        await asyncio.sleep(0.01)
    if leaked:
        for task in leaked:
            task.cancel()
        await asyncio.gather(*leaked, return_exceptions=True)
        pytest.fail(f"test left {len(leaked)} task(s) behind: {sorted(map(repr, leaked))}")


@pytest.fixture
async def server() -> AsyncIterator[Served]:
    """The default machine served on 127.0.0.1, an ephemeral port."""
    async with serving() as served:
        yield served


@pytest.fixture
async def both_clients() -> AsyncIterator[tuple[Machine, FocasClient, NativeClient]]:
    """The default machine on a manual clock, served on 127.0.0.1, with a packed and a
    FOCAS/2 client connected to it."""
    machine = default_machine(sim_clock=ManualClock())
    async with with_both_clients(machine) as both:
        yield both


@pytest.fixture
async def wire(server: Served) -> AsyncIterator[Wire]:
    """One connection to the ``server`` fixture."""
    w = await server.connect()
    async with w:
        yield w


@pytest.fixture
async def peer() -> AsyncIterator[ScriptedPeer]:
    """A :class:`ScriptedPeer` listening on 127.0.0.1 (an ephemeral port)."""
    async with ScriptedPeer() as p:
        yield p


@pytest.fixture(scope="session")
def certificate(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path]:
    """A self-signed certificate for 127.0.0.1 and localhost, and its key (PEM files), made
    with the ``openssl`` command; tests that need it are skipped without it."""
    openssl = shutil.which("openssl")
    if openssl is None:
        pytest.skip("TLS tests need the openssl command to generate a certificate")
    folder = tmp_path_factory.mktemp("tls")
    cert, key = folder / "cert.pem", folder / "key.pem"
    subprocess.run(
        [openssl, "req", "-x509", "-newkey", "ec", "-pkeyopt", "ec_paramgen_curve:prime256v1",
         "-nodes", "-keyout", str(key), "-out", str(cert), "-days", "1", "-subj", "/CN=localhost",
         "-addext", "subjectAltName=IP:127.0.0.1,DNS:localhost"],
        check=True, capture_output=True, timeout=60,
    )  # fmt: skip
    return cert, key


@pytest.fixture
def recorder(monkeypatch: pytest.MonkeyPatch) -> Recorder:
    """The request bodies the native adapters answer during the test, in order."""
    return record_requests(monkeypatch)


@pytest.fixture
def signals_restored() -> Iterator[None]:
    """The test process's handlers as they were, and the module's record of a signal
    cleared, whatever the test did to them."""
    saved = {n: signal.getsignal(n) for n in _signals.SIGNALS}
    try:
        yield
    finally:
        _signals._told.clear()
        _signals._stops.clear()
        for number, handler in saved.items():
            signal.signal(number, handler)
