"""Transports and hints, eighth pass: what a new user meets with wrong peers, odd addresses,
``serve``'s options and Ctrl-C.

Ctrl-C twice: a terminal's user presses it again when the first seems slow. The second one,
a few milliseconds after the first, must change nothing: ``serve`` (one process or
``--workers``), ``watch`` and ``alarms --follow`` still exit 0 with nothing on stderr (the
second one used to kill the process by SIGINT once the interpreter finalized, to raise a
KeyboardInterrupt past the command, or, in ``serve --workers``' parent, to wait for ever on
a lock the first signal's handler held).

Servers here bind 127.0.0.1 on ephemeral ports; ``focas-net`` runs as a subprocess where its
exit code is checked.
"""

from __future__ import annotations

import asyncio
import os
import signal
import sys
from collections.abc import Iterator
from typing import Final

import pytest
from support import serve_process, serving

from focas_net.cli import _signals

#: Upper bound of a subprocess's start (an interpreter and the package imported) and end.
PROCESS_TIMEOUT: Final = 30.0


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


@pytest.mark.usefixtures("signals_restored")
def test_the_first_signal_stops_and_every_later_one_is_ignored_for_good() -> None:
    calls: list[str] = []

    def stop() -> None:
        calls.append("stop")
        signal.raise_signal(signal.SIGINT)  # a second Ctrl-C while the first is handled

    with _signals.on_first_signal(stop):
        signal.raise_signal(signal.SIGINT)
        signal.raise_signal(signal.SIGTERM)
    assert calls == ["stop"]
    # ignored after the block too: nothing is left for a late one to interrupt or kill
    assert signal.getsignal(signal.SIGINT) == signal.SIG_IGN
    assert signal.getsignal(signal.SIGTERM) == signal.SIG_IGN
    signal.raise_signal(signal.SIGINT)  # would raise KeyboardInterrupt were it not ignored


@pytest.mark.usefixtures("signals_restored")
def test_a_block_without_a_signal_puts_the_handlers_back() -> None:
    before = signal.getsignal(signal.SIGINT)
    with _signals.on_first_signal(lambda: None):
        assert signal.getsignal(signal.SIGINT) is not before
    assert signal.getsignal(signal.SIGINT) is before
    assert signal.getsignal(signal.SIGTERM) == signal.SIG_DFL


@pytest.mark.usefixtures("signals_restored")
def test_a_signal_stops_the_innermost_block() -> None:
    calls: list[str] = []
    with _signals.on_first_signal(lambda: calls.append("outer")):
        with _signals.on_first_signal(lambda: calls.append("inner")):
            signal.raise_signal(signal.SIGTERM)
    assert calls == ["inner"]


async def _ctrl_c_until_it_ends(proc: asyncio.subprocess.Process) -> tuple[int, str]:
    """Ctrl-C, then again every millisecond until the process is gone (a bounded number of
    times), so that a later one lands in every phase of its end; its exit code and stderr."""
    assert proc.stderr is not None
    errors = asyncio.ensure_future(proc.stderr.read())
    ended = asyncio.ensure_future(proc.wait())
    for _ in range(int(PROCESS_TIMEOUT * 1000)):
        if ended.done():
            break
        # os.kill, not send_signal: Popen's would reap the process behind asyncio's back
        # (whose wait then reports 255); a zombie not yet reaped takes the signal harmlessly.
        try:
            os.kill(proc.pid, signal.SIGINT)
        except ProcessLookupError:  # reaped, its end not yet reported to the loop
            break
        await asyncio.wait([ended], timeout=0.001)
    async with asyncio.timeout(PROCESS_TIMEOUT):
        code = await ended
        err = await errors
    return code, err.decode()


@pytest.mark.parametrize(
    "options", [(), ("--fleet", "2", "--workers", "2")], ids=["one-process", "workers"]
)
async def test_serve_exits_zero_on_ctrl_c_pressed_twice(options: tuple[str, ...]) -> None:
    lines = 2 if options else 1
    async with serve_process(*options, lines=lines, start_timeout=PROCESS_TIMEOUT) as (proc, _):
        assert await _ctrl_c_until_it_ends(proc) == (0, "")


async def _client(*argv: str) -> asyncio.subprocess.Process:
    return await asyncio.create_subprocess_exec(
        sys.executable, "-m", "focas_net", *argv,
        stdout=asyncio.subprocess.PIPE, stderr=asyncio.subprocess.PIPE,
    )  # fmt: skip


@pytest.mark.parametrize(
    "command",
    [("watch", "--json", "--interval", "0.1"), ("alarms", "--follow")],
    ids=["watch", "follow"],
)
async def test_until_told_commands_exit_zero_on_ctrl_c_pressed_twice(
    command: tuple[str, ...],
) -> None:
    async with serving() as served:
        served.machine.raise_alarm(0, 2, 1001, "SPINDLE ALARM")  # follow's first line
        proc = await _client(*command, "--host", "127.0.0.1", "--port", str(served.port))
        assert proc.stdout is not None
        async with asyncio.timeout(PROCESS_TIMEOUT):
            assert await proc.stdout.readline()  # it polls: its first line is out
        assert await _ctrl_c_until_it_ends(proc) == (0, "")
