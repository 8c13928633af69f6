"""The client process of a benchmark: one per subject, driven by JSON lines on stdin.

Each command line is a JSON object with an ``op``; the answer is one JSON line on stdout,
``{"ok": true, "result": {...}}`` or ``{"ok": false, "error": "..."}``. The event loop lives as
long as the process, so idle connections opened by one command stay open until another closes
them. Run as ``python -m benchmarks.worker --subject NAME [--uvloop]``.
"""

from __future__ import annotations

import argparse
import asyncio
import json
import sys
import time
from collections.abc import Awaitable, Callable, Sequence
from typing import Any, cast

from benchmarks._loop import make_runner
from benchmarks.floor import STATUS, FloorClient
from benchmarks.report import FLOOR
from benchmarks.subjects import FocasConn, StatusConn, connector

_perf = time.perf_counter


def _read_status(conn: StatusConn) -> Callable[[], Awaitable[object]]:
    """``conn``'s status read; focas_net's client's own method, not the benchmark's wrapper
    around it (a coroutine more per call that the other subjects do not pay)."""
    return conn.client.read_status if isinstance(conn, FocasConn) else conn.read_status


async def open_conns(
    connect: Callable[[str, int], Awaitable[StatusConn]], host: str, port: int, count: int
) -> list[StatusConn]:
    """``count`` connections, opened in batches (the listen backlog is finite), each used once."""
    conns: list[StatusConn] = []
    try:
        while len(conns) < count:
            batch = min(50, count - len(conns))
            conns += await asyncio.gather(*(connect(host, port) for _ in range(batch)))
        await asyncio.gather(*(c.read_status() for c in conns))
    except BaseException:
        await close_conns(conns)
        raise
    return conns


async def close_conns(conns: Sequence[StatusConn]) -> None:
    await asyncio.gather(*(c.close() for c in conns), return_exceptions=True)


async def throughput(
    subject: str, host: str, port: int, conns: int, callers: int, duration: float
) -> dict[str, float]:
    """``callers`` loops per connection calling ``read_status`` until the deadline."""
    opened = await open_conns(connector(subject), host, port, conns)
    counts: list[int] = []

    async def caller(conn: StatusConn, deadline: float) -> None:
        read_status = _read_status(conn)
        n = 0
        while not n or _perf() < deadline:
            await read_status()
            n += 1
        counts.append(n)

    try:
        cpu = time.process_time()
        start = _perf()
        deadline = start + duration
        await asyncio.gather(*(caller(c, deadline) for c in opened for _ in range(callers)))
        elapsed = _perf() - start
        cpu = time.process_time() - cpu
    finally:
        await close_conns(opened)
    return {"ops": sum(counts), "elapsed": elapsed, "cpu": cpu}


async def pmc_pair(
    host: str, port: int, area: str, big: int, small: int, duration: float
) -> dict[str, float]:
    """Mean latency of sequential ``read_pmc`` calls of ``big`` bytes, then of ``small``."""
    conn = await FocasConn.connect(host, port)
    client = conn.client
    out: dict[str, float] = {}
    try:
        for key, count in (("big", big), ("small", small)):
            data = await client.read_pmc(area, 0, count)
            if len(data) != count:
                raise RuntimeError(f"read_pmc({area!r}, 0, {count}) gave {len(data)} bytes")
            n = 0
            start = _perf()
            deadline = start + duration
            while not n or _perf() < deadline:
                await client.read_pmc(area, 0, count)
                n += 1
            out[key] = (_perf() - start) / n
    finally:
        await conn.close()
    return out


async def burst_pair(
    subject: str, host: str, port: int, burst: int, duration: float
) -> dict[str, float]:
    """Mean latency of ``burst`` concurrent ``read_status`` calls, then of a single call: what
    a chunked read of ``burst`` frames costs at the least, against one round trip."""
    conn = await connector(subject)(host, port)
    out: dict[str, float] = {}
    try:
        for key, count in (("big", burst), ("small", 1)):
            n = 0
            start = _perf()
            deadline = start + duration
            while not n or _perf() < deadline:
                if count == 1:
                    await conn.read_status()
                else:
                    await asyncio.gather(*(conn.read_status() for _ in range(count)))
                n += 1
            out[key] = (_perf() - start) / n
    finally:
        await conn.close()
    return out


def storm_plan(calls: int, nbytes: int) -> list[tuple[int, int]]:
    """``(byte offset, bit)`` of each call: every bit of ``nbytes`` bytes in turn, ``calls``
    calls in all (each bit is hit ``calls // (8 * nbytes)`` or one more times)."""
    bits = 8 * nbytes
    return [((k % bits) // 8, k % 8) for k in range(calls)]


def count_wrong(data: bytes, value: bool) -> int:
    """Bits of ``data`` that are not all ``value`` (set, or clear)."""
    ones = sum(bin(b).count("1") for b in data)
    return 8 * len(data) - ones if value else ones


async def bitstorm(
    host: str, port: int, area: str, start: int, nbytes: int, calls: int
) -> dict[str, float]:
    """``calls`` concurrent ``write_pmc_bit`` setting every bit of the range, then as many
    clearing it; after each round every bit must be in the state written."""
    conn = await FocasConn.connect(host, port)
    client = conn.client
    plan = storm_plan(calls, nbytes)
    lost = errors = 0
    elapsed = 0.0
    try:
        await client.write_pmc(area, start, bytes(nbytes))
        for value in (True, False):
            t0 = _perf()
            outcomes = await asyncio.gather(
                *(client.write_pmc_bit(area, start + off, bit, value) for off, bit in plan),
                return_exceptions=True,
            )
            elapsed += _perf() - t0
            errors += sum(isinstance(o, BaseException) for o in outcomes)
            lost += count_wrong(bytes(await client.read_pmc(area, start, nbytes)), value)
    finally:
        await conn.close()
    return {"calls": 2 * calls, "elapsed": elapsed, "lost": lost, "errors": errors}


async def open_fleet(
    targets: list[list[Any]],
    connect: Callable[[str, int], Awaitable[StatusConn]] = FocasConn.connect,
) -> list[StatusConn]:
    """One connection per target (focas_net's client unless ``connect`` says otherwise),
    opened 50 at a time, each used once."""
    conns: list[StatusConn] = []
    try:
        for i in range(0, len(targets), 50):
            conns += await asyncio.gather(
                *(connect(str(h), int(p)) for h, p in targets[i : i + 50])
            )
        await asyncio.gather(*(c.read_status() for c in conns))
    except BaseException:
        await close_conns(conns)
        raise
    return conns


async def poll_fleet(
    conns: Sequence[StatusConn], interval: float, duration: float, slots: int = 0
) -> dict[str, float]:
    """Poll every connection's status every ``interval`` s for ``duration`` s. With ``slots``
    0, one task per machine, each at a start time of its own within the interval; with
    ``slots`` > 0, the machines dealt into that many slots (start times spread over the
    interval), one task per slot reading its machines together: focas_net's clients with
    :func:`focas_net.client.read_status_all`, the floor's by sending every request and then
    awaiting the answers in turn (:meth:`FloorClient.send`), the same shape. A tick missed
    because the previous poll ran late is skipped, not caught up. Returns polls done, polls
    due, the slowest poll (of a slot: its slowest machine) and the client's CPU time."""
    loop = asyncio.get_running_loop()
    ticks = round(duration / interval)
    count = len(conns)
    groups = slots if 0 < slots < count else count
    polls = [0] * groups
    errors = [0] * groups
    worst = [0.0] * groups
    t0 = loop.time() + 0.05
    cpu0 = time.process_time()
    wall0 = _perf()

    async def poll_slot(k: int, read: Callable[[], Awaitable[tuple[int, int]]]) -> None:
        """Poll slot ``k`` with ``read`` (the polls that succeeded and failed) every
        ``interval``."""
        base = t0 + interval * k / groups
        tick = 0
        while tick < ticks:
            due = base + tick * interval
            now = loop.time()
            if now >= due + interval:  # the whole slot went by: that poll is missed
                tick += int((now - due) // interval)
                continue
            if due > now:
                await asyncio.sleep(due - now)
            began = loop.time()
            try:
                done, failed = await read()
                polls[k] += done
                errors[k] += failed
            except Exception:
                errors[k] += 1
            took = loop.time() - began
            if took > worst[k]:
                worst[k] = took
            tick += 1

    def reader(members: Sequence[StatusConn]) -> Callable[[], Awaitable[tuple[int, int]]]:
        if len(members) == 1:
            read_status = _read_status(members[0])

            async def read_one() -> tuple[int, int]:
                await read_status()
                return 1, 0

            return read_one
        if all(isinstance(c, FloorClient) for c in members):
            floor = cast(Sequence[FloorClient], members)

            async def read_floor() -> tuple[int, int]:
                futures = [c.send(STATUS) for c in floor]
                for future in futures:
                    await future
                return len(futures), 0

            return read_floor
        from focas_net.client import read_status_all

        clients = [c.client for c in members if isinstance(c, FocasConn)]
        if len(clients) != len(members):
            raise TypeError("a slot is read together by focas_net's or the floor's clients only")

        async def read_focas() -> tuple[int, int]:
            results = await read_status_all(clients)
            failed = sum(isinstance(r, Exception) for r in results)
            return len(results) - failed, failed

        return read_focas

    # slot k holds every groups-th machine from k on (one machine each when groups == count)
    members = [conns[k::groups] for k in range(groups)]
    await asyncio.gather(*(poll_slot(k, reader(m)) for k, m in enumerate(members)))
    wall = _perf() - wall0
    cpu = time.process_time() - cpu0
    return {
        "polls": sum(polls),
        "due": ticks * count,
        "errors": sum(errors),
        "wall": wall,
        "cpu": cpu,
        "worst_latency": max(worst, default=0.0),
        "duration": ticks * interval,
    }


async def fleet(targets: list[list[Any]], interval: float, duration: float) -> dict[str, float]:
    """:func:`poll_fleet` over fresh connections to ``targets``, closed afterwards."""
    conns = await open_fleet(targets)
    try:
        return await poll_fleet(conns, interval, duration)
    finally:
        await close_conns(conns)


async def native_throughput(
    host: str, port: int, conns: int, callers: int, duration: float
) -> dict[str, float]:
    """``callers`` loops per connection pair calling :meth:`NativeClient.read_status`
    (FOCAS/2 statinfo) on ``conns`` connection pairs until the deadline."""
    from focas_net.client import NativeClient

    counts: list[int] = []
    clients = [NativeClient(host, port) for _ in range(conns)]
    try:
        for client in clients:
            await client.connect()
            await client.read_status()

        async def caller(client: NativeClient, deadline: float) -> None:
            read_status = client.read_status
            n = 0
            while not n or _perf() < deadline:
                await read_status()
                n += 1
            counts.append(n)

        cpu0 = time.process_time()
        t0 = _perf()
        deadline = t0 + duration
        await asyncio.gather(*(caller(c, deadline) for c in clients for _ in range(callers)))
        elapsed = _perf() - t0
        cpu = time.process_time() - cpu0
    finally:
        for client in clients:
            await client.aclose()
    return {"ops": sum(counts), "elapsed": elapsed, "cpu": cpu}


class Worker:
    def __init__(self, subject: str) -> None:
        self.subject = subject
        self.idle: list[StatusConn] = []
        #: The plant's connections: focas_net's client, and the floor's client.
        self.plant: list[StatusConn] = []
        self.plant_floor: list[StatusConn] = []

    async def handle(self, cmd: dict[str, Any]) -> dict[str, Any]:
        op = cmd["op"]
        if op == "throughput":
            return await throughput(
                self.subject,
                cmd["host"],
                cmd["port"],
                cmd["conns"],
                cmd["callers"],
                cmd["duration"],
            )
        if op == "pmc_pair":
            return await pmc_pair(
                cmd["host"], cmd["port"], cmd["area"], cmd["big"], cmd["small"], cmd["duration"]
            )
        if op == "burst_pair":
            return await burst_pair(
                self.subject, cmd["host"], cmd["port"], cmd["burst"], cmd["duration"]
            )
        if op == "bitstorm":
            return await bitstorm(
                cmd["host"], cmd["port"], cmd["area"], cmd["start"], cmd["nbytes"], cmd["calls"]
            )
        if op == "fleet":
            return await fleet(cmd["targets"], cmd["interval"], cmd["duration"])
        if op == "plant_open":
            await close_conns(self.plant + self.plant_floor)
            self.plant_floor = []
            self.plant = await open_fleet(cmd["targets"])
            if cmd.get("floor"):
                self.plant_floor = await open_fleet(cmd["targets"], connector(FLOOR))
            return {"open": len(self.plant) + len(self.plant_floor)}
        if op == "plant_poll":
            conns = self.plant_floor if cmd.get("floor") else self.plant
            return await poll_fleet(conns, cmd["interval"], cmd["duration"], cmd.get("slots", 0))
        if op == "plant_close":
            await close_conns(self.plant + self.plant_floor)
            self.plant = []
            self.plant_floor = []
            return {"open": 0}
        if op == "native_throughput":
            return await native_throughput(
                cmd["host"], cmd["port"], cmd["conns"], cmd["callers"], cmd["duration"]
            )
        if op.startswith("native_"):  # the native FOCAS/2 suite (benchmarks/native.py)
            from benchmarks import native

            return await native.handle(self.subject, cmd)
        if op == "idle_open":
            self.idle += await open_conns(
                connector(self.subject), cmd["host"], cmd["port"], cmd["count"]
            )
            return {"open": len(self.idle)}
        if op == "idle_close":
            await close_conns(self.idle)
            self.idle = []
            await asyncio.sleep(0.05)
            return {"open": 0}
        raise ValueError(f"unknown op {op!r}")


def main() -> int:
    parser = argparse.ArgumentParser(description="Benchmark client process (JSON lines).")
    parser.add_argument("--subject", required=True)
    parser.add_argument("--uvloop", action="store_true")
    args = parser.parse_args()
    worker = Worker(args.subject)
    with make_runner(args.uvloop) as runner:
        for line in sys.stdin:
            if not line.strip():
                continue
            cmd = json.loads(line)
            if cmd.get("op") == "quit":
                break
            try:
                answer: dict[str, Any] = {"ok": True, "result": runner.run(worker.handle(cmd))}
            except Exception as exc:
                answer = {"ok": False, "error": f"{type(exc).__name__}: {exc}"}
            sys.stdout.write(json.dumps(answer) + "\n")
            sys.stdout.flush()
        if worker.idle or worker.plant:
            runner.run(close_conns([*worker.idle, *worker.plant]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
