"""``serve --state``: a server killed with SIGKILL at random moments keeps every write it
acknowledged, and its clients, reconnecting, carry on.

Three clients write through both protocols (packed: macros, a parameter, programs and the
PMC's K area; native: macros, the PMC's D area and the total parts parameter) while the
server subprocess is killed and restarted on the same port. Each client keeps, per key, the
last value acknowledged and the values sent after it whose answer never came (those may or
may not be kept). At the end a fresh server on the same state must hold, for every key, the
acknowledged value or one of the unanswered ones sent after it.
"""

from __future__ import annotations

import asyncio
import random
import signal
import sys
from collections.abc import Awaitable, Callable, Coroutine
from decimal import Decimal
from pathlib import Path
from typing import Any

import pytest
from support import IO_TIMEOUT, free_port

from focas_net.client import FocasClient, NativeClient
from focas_net.errors import FocasError

#: Kill and restart cycles of one storm.
KILLS = 4
#: Writes of one client per connection at most (the kill usually comes first).
WRITES_PER_LIFE = 400
START_TIMEOUT = 15 * IO_TIMEOUT


#: The values of the built-in machine (None: vacant, no program) by the key's letter.
_INITIAL: dict[str, object] = {"K": b"\0", "D": b"\0\0", "#": None, "O": None}


async def _start(port: int, state: Path) -> asyncio.subprocess.Process:
    proc = await asyncio.create_subprocess_exec(
        sys.executable, "-m", "focas_net", "serve", "--host", "127.0.0.1",
        "--port", str(port), "--state", str(state),
        stdout=asyncio.subprocess.PIPE, stderr=asyncio.subprocess.PIPE,
    )  # fmt: skip
    assert proc.stdout is not None
    async with asyncio.timeout(START_TIMEOUT):
        line = (await proc.stdout.readline()).decode()
    if "listening on" not in line:
        assert proc.stderr is not None
        err = (await proc.stderr.read()).decode()
        raise AssertionError(f"serve did not start: {line!r} {err!r}")
    return proc


class Ledger:
    """Per key: the last acknowledged value and the values sent after it, unanswered."""

    def __init__(self) -> None:
        self.acked: dict[str, object] = {}
        self.unsure: dict[str, list[object]] = {}

    async def write(self, key: str, value: object, call: Awaitable[object]) -> None:
        self.unsure.setdefault(key, []).append(value)
        await call
        self.acked[key] = value
        self.unsure[key] = []

    def allowed(self, key: str) -> list[object]:
        return [self.acked.get(key), *self.unsure.get(key, [])]


async def _packed_writer(
    port: int, ledger: Ledger, stop: asyncio.Event, rng: random.Random, me: int
) -> None:
    """Writer ``me`` (0, 1): its own macros, programs and K bytes; writer 0 the parameter."""
    n = 0
    for _ in range(50):  # connections (bounded)
        if stop.is_set():
            return
        try:
            async with FocasClient("127.0.0.1", port, timeout=2.0) as cnc:
                await cnc.sim.set_panel("MDI", pwe=True)
                for _ in range(WRITES_PER_LIFE):
                    if stop.is_set():
                        return
                    n += 1
                    k = rng.randrange(8) + 10 * me
                    what = n % 4
                    if what == 0:
                        await ledger.write(f"#{500 + k}", Decimal(n), cnc.write_macro(500 + k, n))
                    elif what == 1 and me == 0:
                        await ledger.write("P3216", n % 10000, cnc.write_param(3216, n % 10000))
                    elif what == 2:
                        text = f"O{100 + k}\n(REV {n})\nG0X{n % 100}\nM30\n%"
                        await ledger.write(f"O{100 + k}", n, cnc.write_program(text, replace=True))
                    elif what == 3:
                        data = bytes([n % 256])
                        await ledger.write(f"K{k}", data, cnc.write_pmc("K", k, data))
        except (FocasError, OSError, TimeoutError):
            await asyncio.sleep(0.05)


async def _native_writer(
    port: int, ledger: Ledger, stop: asyncio.Event, rng: random.Random, me: int
) -> None:
    n = 0
    for _ in range(50):
        if stop.is_set():
            return
        try:
            async with NativeClient("127.0.0.1", port, timeout=2.0) as cnc:
                for _ in range(WRITES_PER_LIFE):
                    if stop.is_set():
                        return
                    n += 1
                    k = rng.randrange(8)
                    what = n % 3
                    if what == 0:
                        await ledger.write(f"#{600 + k}", Decimal(n), cnc.write_macro(600 + k, n))
                    elif what == 1:
                        data = n.to_bytes(2, "little")
                        await ledger.write(f"D{2 * k}", data, cnc.write_pmc("D", 2 * k, data))
                    else:
                        await ledger.write("P6712", n, cnc.write_param(6712, n))
        except (FocasError, OSError, TimeoutError):
            await asyncio.sleep(0.05)


async def _check(port: int, ledgers: list[Ledger]) -> None:
    async with FocasClient("127.0.0.1", port, timeout=5.0) as cnc:
        for ledger in ledgers:
            for key in sorted(set(ledger.acked) | set(ledger.unsure)):
                allowed = ledger.allowed(key)
                if key.startswith("#"):
                    value: object = await cnc.read_macro(int(key[1:]))
                elif key.startswith("P"):
                    value = await cnc.read_param(int(key[1:]))
                elif key.startswith("O"):
                    numbers = [p.number for p in await cnc.read_program_directory()]
                    if int(key[1:]) not in numbers:
                        value = None
                    else:
                        text = await cnc.read_program(int(key[1:]))
                        value = int(text.split("(REV ")[1].split(")")[0])
                else:
                    letter, start = key[0], int(key[1:])
                    width = 2 if letter == "D" else 1
                    value = await cnc.read_pmc(letter, start, width)
                if allowed[0] is None:  # never acknowledged: as the machine was built
                    allowed[0] = _INITIAL.get(key[0])
                assert value in allowed, f"{key}: {value!r} read, {allowed!r} allowed"


@pytest.mark.skipif(sys.platform == "win32", reason="SIGKILL")
async def test_kill_storm_keeps_every_acknowledged_write(tmp_path: Path) -> None:
    rng = random.Random(45)
    port = free_port()
    state = tmp_path / "state"
    ledgers = [Ledger(), Ledger(), Ledger()]
    stop = asyncio.Event()
    proc = await _start(port, state)
    writers: list[
        Callable[[int, Ledger, asyncio.Event, random.Random, int], Coroutine[Any, Any, None]]
    ] = [
        _packed_writer,
        _packed_writer,
        _native_writer,
    ]
    tasks = [
        asyncio.create_task(w(port, ledger, stop, random.Random(rng.random()), i))
        for i, (w, ledger) in enumerate(zip(writers, ledgers, strict=True))
    ]
    try:
        for _ in range(KILLS):
            await asyncio.sleep(rng.uniform(0.2, 0.6))
            proc.send_signal(signal.SIGKILL)
            await proc.wait()
            proc = await _start(port, state)
        await asyncio.sleep(0.3)
        stop.set()
        async with asyncio.timeout(START_TIMEOUT):
            await asyncio.gather(*tasks)
        acked = sum(len(ledger.acked) for ledger in ledgers)
        assert acked >= 10, "the clients acknowledged too little to test anything"
        proc.send_signal(signal.SIGKILL)
        await proc.wait()
        proc = await _start(port, state)
        await _check(port, ledgers)
        assert not any(p.name.endswith(".tmp") for p in state.iterdir())
    finally:
        stop.set()
        for task in tasks:
            task.cancel()
        if proc.returncode is None:
            proc.kill()
            await proc.wait()


async def test_serve_refuses_a_damaged_state_file_in_one_line(tmp_path: Path) -> None:
    from cli_support import run_focas_net

    from focas_net.sim import DEFAULT_NAME
    from focas_net.sim.statefile import state_path

    state_path(tmp_path, DEFAULT_NAME).write_bytes(b"focas-net-state 1 10 00\n{}")
    code, out, err = await run_focas_net(
        "serve", "--host", "127.0.0.1", "--port", "0", "--state", str(tmp_path)
    )
    assert code == 2 and out == ""
    assert err.count("\n") == 1 and "truncated or corrupted" in err
