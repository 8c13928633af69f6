"""SIGINT and SIGTERM for the commands that run until told (``serve``, ``watch``, ``alarms
--follow``, ``gateway``): the first one tells the command to stop, and every later one is
ignored for the rest of the process.

A stopping command ends by itself, within its own bounds (``serve``'s ``--grace-period``,
the workers' kill timer), with exit 0, so a second Ctrl-C has nothing left to do. Were the
default handler back once the command's block ended, a second Ctrl-C a few milliseconds
after the first would land in what is left of the run as a KeyboardInterrupt (exit 130,
where docs/cli.md says 0), or, once the interpreter has begun to finalize and put SIG_DFL
back, kill the process by the signal. So the handler itself swaps both signals to SIG_IGN
before it does anything else: from the first signal on, no moment is left where a second
one lands anywhere, and the interpreter's finalization leaves SIG_IGN alone.

The handler runs in the main thread between two bytecodes of whatever runs there, so
``stop`` must neither block nor take a lock that code may hold (``threading.Event.set``,
``queue.Queue.put``): an event loop's ``call_soon_threadsafe``, a flag, ``os.kill``.

It runs only once the main thread is back in the interpreter. An event loop asleep in
``select`` with no timer due wakes only for a byte on a socket it watches; when the kernel
hands the signal to another thread of the process (any thread may take a ``kill``), or the
signal comes between the loop's last look and its ``select``, nothing else wakes it (``serve``
slept on until its next idle sweep, 75 s by default). So a block given its ``loop`` has the
signal write a byte (``signal.set_wakeup_fd``) to a socket that loop watches.
"""

from __future__ import annotations

import asyncio
import contextlib
import signal
import socket
from collections.abc import Callable, Iterator
from types import FrameType
from typing import Final

__all__ = ["SIGNALS", "on_first_signal"]

#: The signals that tell a command to stop.
SIGNALS: Final = (signal.SIGINT, signal.SIGTERM)

#: The stop of each block that is open, innermost last (blocks nest: ``alarms --follow``'s
#: polling inside the command's own run).
_stops: list[Callable[[], object]] = []
#: A signal came: both are ignored from then on, for the rest of the process.
_told: list[bool] = []


def _handler(signum: int, frame: FrameType | None) -> None:
    for number in SIGNALS:
        signal.signal(number, signal.SIG_IGN)
    if _told:  # a second run of this handler, for a signal that came before the swap
        return
    _told.append(True)
    if _stops:
        _stops[-1]()


def _drain(sock: socket.socket) -> None:
    """Read what the signals wrote (the signal's handler itself has run, or runs next)."""
    with contextlib.suppress(OSError):
        while sock.recv(4096):
            pass


@contextlib.contextmanager
def _waking(loop: asyncio.AbstractEventLoop) -> Iterator[None]:
    """A signal wakes ``loop`` at once while the block runs: it writes a byte to a socket the
    loop watches. Nothing is changed where a wakeup file is set already (asyncio's own signal
    handlers, uvloop: they wake the loop) or off the main thread."""
    reader, writer = socket.socketpair()
    try:
        for sock in (reader, writer):
            sock.setblocking(False)
        try:
            previous = signal.set_wakeup_fd(writer.fileno(), warn_on_full_buffer=False)
        except ValueError:  # not the main thread
            yield
            return
        if previous != -1:  # someone wakes the loop already: theirs stays
            signal.set_wakeup_fd(previous)
            yield
            return
        loop.add_reader(reader.fileno(), _drain, reader)
        try:
            yield
        finally:
            loop.remove_reader(reader.fileno())
            signal.set_wakeup_fd(-1)
    finally:
        reader.close()
        writer.close()


@contextlib.contextmanager
def on_first_signal(
    stop: Callable[[], object], loop: asyncio.AbstractEventLoop | None = None
) -> Iterator[None]:
    """``stop()`` on the first SIGINT or SIGTERM while the block runs (the innermost open
    block's); from that signal on both are ignored, after the block too. Off the main thread
    no handler can be set, and Ctrl-C acts as it would without the block. A block that ends
    without a signal puts back what was there. With ``loop`` (the event loop the block runs
    in), a signal wakes that loop at once, whichever thread takes it."""
    _stops.append(stop)
    previous: dict[int, Callable[[int, FrameType | None], object] | int | None] = {}
    try:
        if len(_stops) == 1 and not _told:
            for number in SIGNALS:
                previous[int(number)] = signal.signal(number, _handler)
    except ValueError:  # not the main thread
        pass
    try:
        with contextlib.nullcontext() if loop is None else _waking(loop):
            yield
    finally:
        _stops.remove(stop)
        if not _told:
            for signum, handler in previous.items():
                signal.signal(signum, handler)
