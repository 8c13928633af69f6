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
import threading
from collections.abc import Iterator
from typing import Final

import pytest

from focas_net.cli import _run, _signals

#: Seconds a woken loop has to call the block's stop (it takes a few milliseconds).
WAKE_BOUND: Final = 5.0


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
