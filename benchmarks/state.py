"""``python -m benchmarks.state``: the write path with and without ``serve --state``.

Each row runs ``focas-net serve`` (the built-in machine) in its own process, without and
with ``--state DIR`` (a fresh temporary folder), and one packed client on 127.0.0.1 that
writes for ``--seconds`` seconds after a warm-up:

* ``macro_seq``: ``cnc_wrmacro`` one at a time (each answer awaited before the next write);
* ``macro_pipe64``: 64 ``cnc_wrmacro`` in flight at once;
* ``pmc_seq``: ``pmc_wrpmcrng`` of two D bytes, one at a time;
* ``bit_storm``: 64 tasks setting and clearing bits of 8 K bytes (``write_pmc_bit``: a
  read-modify-write under the client's lock of the byte), so reads and writes interleave.

With ``--state`` an answer leaves only once the write is on the disk: one save (a record
appended to the machine's journal and flushed with ``fdatasync``) per event-loop turn,
whatever the number of writes in that turn. The figures depend on the disk's flush above all.
"""

from __future__ import annotations

import argparse
import asyncio
import shutil
import sys
import tempfile
import time
from collections.abc import Awaitable, Callable
from pathlib import Path

from focas_net.client import FocasClient

Scenario = Callable[[FocasClient, float], Awaitable[int]]


async def _start(state: Path | None) -> tuple[asyncio.subprocess.Process, int]:
    extra = ["--state", str(state)] if state is not None else []
    proc = await asyncio.create_subprocess_exec(
        sys.executable, "-m", "focas_net", "serve", "--host", "127.0.0.1", "--port", "0",
        *extra, stdout=asyncio.subprocess.PIPE,
    )  # fmt: skip
    assert proc.stdout is not None
    line = (await asyncio.wait_for(proc.stdout.readline(), 30)).decode()
    return proc, int(line.rsplit(":", 1)[1])


async def macro_seq(cnc: FocasClient, until: float) -> int:
    n = 0
    while time.perf_counter() < until:
        await cnc.write_macro(500 + n % 100, n)
        n += 1
    return n


async def macro_pipe64(cnc: FocasClient, until: float) -> int:
    async def one(k: int) -> int:
        n = 0
        while time.perf_counter() < until:
            await cnc.write_macro(500 + k, n)
            n += 1
        return n

    return sum(await asyncio.gather(*(one(k) for k in range(64))))


async def pmc_seq(cnc: FocasClient, until: float) -> int:
    n = 0
    while time.perf_counter() < until:
        await cnc.write_pmc("D", 2 * (n % 100), (n & 0xFFFF).to_bytes(2, "little"))
        n += 1
    return n


async def bit_storm(cnc: FocasClient, until: float) -> int:
    async def one(k: int) -> int:
        n = 0
        while time.perf_counter() < until:
            await cnc.write_pmc_bit("K", k % 8, k // 8, n & 1)
            n += 1
        return n

    return sum(await asyncio.gather(*(one(k) for k in range(64))))


SCENARIOS: dict[str, Scenario] = {
    "macro_seq": macro_seq,
    "macro_pipe64": macro_pipe64,
    "pmc_seq": pmc_seq,
    "bit_storm": bit_storm,
}


async def measure(name: str, state: Path | None, seconds: float) -> float:
    """Writes per second of scenario ``name`` against a fresh server."""
    proc, port = await _start(state)
    try:
        async with FocasClient("127.0.0.1", port, max_in_flight=64) as cnc:
            scenario = SCENARIOS[name]
            await scenario(cnc, time.perf_counter() + min(0.3, seconds))  # warm-up
            start = time.perf_counter()
            done = await scenario(cnc, start + seconds)
            return done / (time.perf_counter() - start)
    finally:
        proc.terminate()
        await proc.wait()


async def main(seconds: float) -> None:
    print(f"{'scenario':<14} {'no --state':>12} {'--state':>12} {'ratio':>7}  unit")
    for name in SCENARIOS:
        folder = Path(tempfile.mkdtemp(prefix="focas-state-"))
        try:
            plain = await measure(name, None, seconds)
            kept = await measure(name, folder, seconds)
        finally:
            shutil.rmtree(folder, ignore_errors=True)
        print(f"{name:<14} {plain:>12,.0f} {kept:>12,.0f} {kept / plain:>7.2f}  writes/s")


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0] if __doc__ else None)
    parser.add_argument("--seconds", type=float, default=2.0, help="per row (default 2)")
    asyncio.run(main(parser.parse_args().seconds))
