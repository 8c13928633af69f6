"""Shutdown within a bound: the commands that run until told wake at once on SIGINT or SIGTERM,
and a server's shutdown ends by its own deadline whatever its peers do.

A signal's Python handler runs in the main thread, once that thread is back in the
interpreter. An event loop asleep in ``select`` with no timer due is woken only by a byte on a
socket it watches: when the kernel hands the signal to another thread (any thread of the
process may take a ``kill``), or the signal lands between the loop's last look and its
``select``, nothing else wakes it, and ``serve`` slept on until its next idle sweep (75 s by
default), past any supervisor's patience. Here the signal is sent to a thread of the test's
own, which is how the kernel's choice of another thread looks, every time.
"""

from __future__ import annotations

import asyncio
import signal
import socket
import ssl
import threading
from collections.abc import Iterator
from pathlib import Path
from typing import Final

import pytest

from focas_net.cli import _run, _signals
from focas_net.server import FocasServer, Listener
from focas_net.server._native import NativeConnection
from focas_net.server._packed import PackedConnection
from focas_net.sim import default_machine

#: Seconds a woken loop has to call the block's stop (it takes a few milliseconds).
WAKE_BOUND: Final = 5.0
#: Seconds a shutdown with a grace period of 0.5 s has, with its bounds (it takes 1.5 s at
#: the most: 0.5 s for delayed answers, 0.5 s for output, 0.5 s more after aborting, well
#: below the TLS handshake's 60 s).
SHUTDOWN_BOUND: Final = 10.0


@pytest.fixture
def other_thread() -> Iterator[int]:
    """The id of a thread of this process that waits (for the signal the test sends it)."""
    done = threading.Event()
    thread = threading.Thread(target=done.wait, name="bystander", daemon=True)
    thread.start()
    try:
        assert thread.ident is not None
        yield thread.ident
    finally:
        done.set()
        thread.join()


@pytest.mark.usefixtures("signals_restored")
@pytest.mark.parametrize("signum", _signals.SIGNALS, ids=lambda s: signal.Signals(s).name)
async def test_a_signal_another_thread_takes_wakes_the_loop(
    other_thread: int, signum: signal.Signals
) -> None:
    told = asyncio.Event()
    with _run.stopping_on_signals(told.set):
        signal.pthread_kill(other_thread, signum)
        async with asyncio.timeout(WAKE_BOUND):
            await told.wait()
    assert told.is_set()
    assert signal.set_wakeup_fd(-1) == -1  # the block's wakeup socket is gone with it


def _tls(certificate: tuple[Path, Path]) -> ssl.SSLContext:
    context = ssl.SSLContext(ssl.PROTOCOL_TLS_SERVER)
    context.load_cert_chain(*certificate)
    return context


@pytest.mark.parametrize("shutdown", ["before its handshake is set up", "before it begins"])
async def test_a_tls_client_accepted_as_the_shutdown_begins_does_not_hold_it(
    certificate: tuple[Path, Path], monkeypatch: pytest.MonkeyPatch, shutdown: str
) -> None:
    """A client that connects to a TLS port as the server shuts down and sends nothing: its
    socket was left open (the handshake set up after the shutdown began waited up to its
    60 s timeout; one cancelled before it began, for ever), and from Python 3.12 on asyncio's
    server waits for it: the shutdown ends by its bound all the same."""
    accepted = asyncio.Event()
    make = Listener._new_connection

    def accepting(listener: Listener) -> PackedConnection | NativeConnection:
        accepted.set()  # the socket is accepted; its connection is made a loop turn later
        return make(listener)

    monkeypatch.setattr(Listener, "_new_connection", accepting)
    server = FocasServer(
        default_machine(), host="127.0.0.1", port=0, ssl=_tls(certificate), grace_period=0.5
    )
    await server.start()
    with socket.create_connection(server.listeners[0].address):  # it sends nothing
        async with asyncio.timeout(SHUTDOWN_BOUND):
            await accepted.wait()
        if shutdown == "before its handshake is set up":  # this very turn
            async with asyncio.timeout(SHUTDOWN_BOUND):
                await server.aclose()
        else:  # the next turn, with the handshake's first step
            closing = asyncio.ensure_future(server.aclose())
            done, _ = await asyncio.wait({closing}, timeout=SHUTDOWN_BOUND)
            assert done == {closing}
    assert not server.listeners[0]._handshakes
