"""The pollers ``benchmarks.gateway`` measures against the gateway, each in a process of its
own: ``python -m benchmarks.gateway_poll SUBJECT --targets FILE``.

Every subject reads the same things from every machine of the fleet, the reads the gateway
makes of a one-path native machine (``focas_net.gateway.reads``), on the gateway's schedule:

* the fast group once a ``--fast`` interval (1 s): ``cnc_statinfo``, ``cnc_rddynamic2`` of
  every axis (program numbers, sequence number, feed, spindle speed, the four positions), the
  overrides with one ``pmc_rdpmcrng`` of G12..G30 (feed override G12, rapid override G14,
  spindle override G30) and the active alarms (``cnc_rdalmmsg2``, 32 at most): 4 calls;
* the slow group once a ``--slow`` interval (10 s), each machine in the fast cycle of its turn
  (machine ``i`` in cycles ``c`` with ``c % 10 == i % 10``, so the slow reads are spread over
  the interval rather than all due in one cycle): the parts counts (``cnc_rdmacro`` #3901,
  #3902, ``cnc_rdparam`` 6713), four timers (``cnc_rdtimer`` 0..3), ``cnc_rdspload``,
  ``cnc_rdsvmeter``, the modal T (``cnc_rdcommand``), the operator message (``cnc_rdopmsg``)
  and a tool offset (``cnc_rdtofs``): 12 calls.

Subjects:

* ``floor``: the client floor, a poll loop of one asyncio task over one
  :class:`~focas_net.client.NativeClient` per machine, with
  :func:`~focas_net.client.read_status_all` and :func:`~focas_net.client.read_dynamic_all`
  (every machine's request started before any answer is awaited) and the client's own
  ``read_pmc``, ``read_alarms`` and slow-group methods gathered: what the reads cost through
  focas_net's client with no gateway around them;
* ``fwlib-threads``: FANUC's library (``FOCAS_NET_FWLIB``) through :mod:`ctypes`, a handle per
  machine opened with ``cnc_allclibhndl3``, each on a thread of its own (a handle belongs to
  the thread that opened it), as collectors drive it; the threads' starts are staggered over
  the interval;
* ``fwlib-pool``: the same library calls from a pool of ``--pool`` threads (32), each owning
  the handles of every ``pool``-th machine and reading them in turn once a cycle.

FANUC's Linux library waits on its sockets with ``select``: a handle whose socket is a file
descriptor of 1024 (``FD_SETSIZE``) or more aborts the process ("bit out of range 0 -
FD_SETSIZE on fd_set"). One process of the library therefore holds at most about a thousand
handles; the library's subjects run :data:`PER_PROCESS` machines per process (the threads
of the pool shared out among them), started by one process that adds up their counts. Their
CPU is that of the whole process tree.

Each prints one JSON line when every machine is connected (``{"event": "ready", ...}``), then
one a second with its cumulative counts (``{"event": "count", ...}``): fast and slow polls
completed and failed, and the fast polls a late cycle skipped. A poll is one machine's group
read whole; a cycle that overruns its interval skips the ticks that went by (they are not
caught up) and counts their polls as skipped.
"""

from __future__ import annotations

import argparse
import asyncio
import ctypes
import json
import os
import resource
import subprocess
import sys
import tempfile
import threading
import time
from collections.abc import Awaitable, Callable, Iterator, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Final

if TYPE_CHECKING:
    from focas_net.client import NativeClient

FLOOR: Final = "floor"
FWLIB_THREADS: Final = "fwlib-threads"
FWLIB_POOL: Final = "fwlib-pool"
SUBJECTS: Final = (FLOOR, FWLIB_THREADS, FWLIB_POOL)
#: The overrides read in one pmc_rdpmcrng: G12 (feed), G14 (rapid), G30 (spindle).
PMC_G: Final = 0
PMC_FIRST: Final = 12
PMC_LAST: Final = 30
#: The parts counts: macro variables #3901 (parts) and #3902 (total), parameter 6713
#: (required).
PARTS_MACROS: Final = (3901, 3902)
PARTS_REQUIRED: Final = 6713
#: cnc_rdtimer's types read: power-on, operating, cutting, cycle.
TIMERS: Final = (0, 1, 2, 3)
#: The tool offset read: number 1, length wear (type 2).
TOOL_OFFSET: Final = (1, 2)
#: Active alarms asked for.
ALARMS: Final = 32
#: Most handles of FANUC's library one process holds (see the module docstring).
PER_PROCESS: Final = 500
_perf = time.perf_counter


def raise_nofile() -> int:
    """Raise this process's open-file limit to its hard limit (a connection per machine);
    the new soft limit."""
    soft, hard = resource.getrlimit(resource.RLIMIT_NOFILE)
    if soft != hard:
        resource.setrlimit(resource.RLIMIT_NOFILE, (hard, hard))
    return resource.getrlimit(resource.RLIMIT_NOFILE)[0]


@dataclass(slots=True)
class Counts:
    """Cumulative counts of one poller (one slot per thread, each written by its own thread
    only, summed by the reporter)."""

    fast: list[int]
    fast_errors: list[int]
    slow: list[int]
    slow_errors: list[int]
    skipped: list[int]
    first_error: list[str] = field(default_factory=list)

    @classmethod
    def of(cls, slots: int) -> Counts:
        return cls([0] * slots, [0] * slots, [0] * slots, [0] * slots, [0] * slots)

    def error(self, exc: BaseException) -> None:
        if not self.first_error:
            self.first_error.append(repr(exc))

    def line(self) -> dict[str, Any]:
        return {
            "event": "count",
            "t": time.monotonic(),
            "fast": sum(self.fast),
            "fast_errors": sum(self.fast_errors),
            "slow": sum(self.slow),
            "slow_errors": sum(self.slow_errors),
            "skipped": sum(self.skipped),
            "error": self.first_error[0] if self.first_error else "",
        }


def emit(line: dict[str, Any]) -> None:
    sys.stdout.write(json.dumps(line) + "\n")
    sys.stdout.flush()


def ticks(interval: float, offset: float = 0.0) -> Iterator[tuple[int, float, int]]:
    """``(tick, when it is due, ticks skipped)`` for a cycle every ``interval`` from
    ``offset`` seconds from now (``time.monotonic``), taken as each cycle's work is done: a
    tick whose whole interval went by is skipped, not caught up."""
    t0 = time.monotonic() + offset
    tick = 0
    while True:
        due = t0 + tick * interval
        late = int((time.monotonic() - due) // interval)
        if late > 0:
            tick += late
            due = t0 + tick * interval
        yield tick, due, max(late, 0)
        tick += 1


# -- FANUC's library -------------------------------------------------------------------------

_us, _s16, _i32 = ctypes.c_ushort, ctypes.c_short, ctypes.c_int32
#: ODBDY2 with FANUC's header's MAX_AXIS (32): the size programs pass.
_DYNAMIC_SIZE: Final = 28 + 16 * 32
_ALMMSG2_SIZE: Final = 76  # ODBALMMSG2 ("long" is 4 bytes in this build)


def library() -> Any:
    """FANUC's library, loaded and started (every function returns the EW code, a short)."""
    path = os.environ.get("FOCAS_NET_FWLIB")
    if not path:
        raise RuntimeError("FOCAS_NET_FWLIB is not set (the path of FANUC's libfwlib32)")
    lib = ctypes.cdll.LoadLibrary(path)
    for name in (
        "cnc_startupprocess",
        "cnc_allclibhndl3",
        "cnc_freelibhndl",
        "cnc_statinfo",
        "cnc_rddynamic2",
        "pmc_rdpmcrng",
        "cnc_rdalmmsg2",
        "cnc_rdmacro",
        "cnc_rdparam",
        "cnc_rdtimer",
        "cnc_rdspload",
        "cnc_rdsvmeter",
        "cnc_rdcommand",
        "cnc_rdopmsg",
        "cnc_rdtofs",
    ):
        getattr(lib, name).restype = ctypes.c_short
    lib.cnc_startupprocess(0, b"/dev/null")
    return lib


class LibraryMachine:
    """One machine through one handle of FANUC's library: open, used and freed on one thread.
    The buffers are made once; every call is the one a collector makes, its EW code checked."""

    def __init__(self, lib: Any, host: str, port: int, timeout: int) -> None:
        self.lib = lib
        handle = _us()
        rc = lib.cnc_allclibhndl3(host.encode(), _us(port), _i32(timeout), ctypes.byref(handle))
        if rc != 0:
            raise RuntimeError(f"cnc_allclibhndl3 to {host}:{port} returned {rc}")
        self.h = handle
        self.stat = ctypes.create_string_buffer(32)
        self.dynamic = ctypes.create_string_buffer(_DYNAMIC_SIZE)
        self.pmc = ctypes.create_string_buffer(8 + PMC_LAST - PMC_FIRST + 1)
        self.alarms = ctypes.create_string_buffer(ALARMS * _ALMMSG2_SIZE)
        self.buf = ctypes.create_string_buffer(512)
        self.count = _s16()

    @staticmethod
    def _ok(rc: int, name: str) -> None:
        if rc != 0:
            raise RuntimeError(f"{name} returned {rc}")

    def fast(self) -> None:
        """The fast group."""
        lib, h, ok = self.lib, self.h, self._ok
        ok(lib.cnc_statinfo(h, self.stat), "cnc_statinfo")
        ok(
            lib.cnc_rddynamic2(h, _s16(-1), _s16(_DYNAMIC_SIZE), self.dynamic),
            "cnc_rddynamic2",
        )
        ok(
            lib.pmc_rdpmcrng(
                h, _s16(PMC_G), _s16(0), _us(PMC_FIRST), _us(PMC_LAST), _us(len(self.pmc)), self.pmc
            ),
            "pmc_rdpmcrng",
        )
        self.count.value = ALARMS
        ok(lib.cnc_rdalmmsg2(h, _s16(-1), ctypes.byref(self.count), self.alarms), "cnc_rdalmmsg2")

    def slow(self) -> None:
        """The slow group."""
        lib, h, ok, buf, count = self.lib, self.h, self._ok, self.buf, self.count
        for number in PARTS_MACROS:
            ok(lib.cnc_rdmacro(h, _s16(number), _s16(10), buf), "cnc_rdmacro")
        ok(lib.cnc_rdparam(h, _s16(PARTS_REQUIRED), _s16(0), _s16(8), buf), "cnc_rdparam")
        for kind in TIMERS:
            ok(lib.cnc_rdtimer(h, _s16(kind), buf), "cnc_rdtimer")
        ok(lib.cnc_rdspload(h, _s16(-1), buf), "cnc_rdspload")
        count.value = 32
        ok(lib.cnc_rdsvmeter(h, ctypes.byref(count), buf), "cnc_rdsvmeter")
        count.value = 32
        ok(lib.cnc_rdcommand(h, _s16(-1), _s16(0), ctypes.byref(count), buf), "cnc_rdcommand")
        ok(lib.cnc_rdopmsg(h, _s16(0), _s16(6 + 256), buf), "cnc_rdopmsg")
        number, kind = TOOL_OFFSET
        ok(lib.cnc_rdtofs(h, _s16(number), _s16(kind), _s16(8), buf), "cnc_rdtofs")

    def close(self) -> None:
        self.lib.cnc_freelibhndl(self.h)


def library_poll(
    targets: Sequence[tuple[str, int]], threads: int, fast: float, slow: float, timeout: int
) -> None:
    """``threads`` threads (one per machine when it equals the machines), thread ``j`` owning
    machines ``j``, ``j + threads``, ...: each opens its handles, then reads them once a
    ``fast`` interval from a start of its own, staggered over the interval."""
    lib = library()
    turns = max(1, round(slow / fast))
    counts = Counts.of(threads)
    opened = threading.Barrier(threads + 1)
    failed: list[str] = []
    stop = threading.Event()

    def run(j: int) -> None:
        machines: list[tuple[int, LibraryMachine]] = []
        try:
            for i in range(j, len(targets), threads):
                host, port = targets[i]
                machines.append((i, LibraryMachine(lib, host, port, timeout)))
        except Exception as exc:
            failed.append(repr(exc))
        opened.wait()
        if failed:
            return
        try:
            for tick, due, skipped in ticks(fast, offset=fast * j / threads):
                wait = due - time.monotonic()
                if wait > 0 and stop.wait(wait):
                    return
                counts.skipped[j] += skipped * len(machines)
                for i, machine in machines:
                    try:
                        machine.fast()
                        counts.fast[j] += 1
                    except Exception as exc:
                        counts.fast_errors[j] += 1
                        counts.error(exc)
                    if tick % turns == i % turns:
                        try:
                            machine.slow()
                            counts.slow[j] += 1
                        except Exception as exc:
                            counts.slow_errors[j] += 1
                            counts.error(exc)
        finally:
            for _, machine in machines:
                machine.close()

    threading.stack_size(512 * 1024)
    workers = [threading.Thread(target=run, args=(j,), daemon=True) for j in range(threads)]
    for worker in workers:
        worker.start()
    opened.wait()
    if failed:
        stop.set()
        raise RuntimeError(f"{len(failed)} thread(s) could not open their handles: {failed[0]}")
    emit({"event": "ready", "machines": len(targets), "threads": threads})
    report(counts.line, fast)
    stop.set()
    for worker in workers:
        worker.join(timeout + fast)


def until_closed() -> threading.Event:
    """An event set once stdin ends (the measuring process closed it)."""
    closed = threading.Event()

    def watch() -> None:
        sys.stdin.read()
        closed.set()

    threading.Thread(target=watch, daemon=True).start()
    return closed


def report(line: Callable[[], dict[str, Any]], every: float) -> None:
    """Print ``line()`` once every ``every`` seconds (on a fixed schedule, so that the lines'
    times do not drift from the cycles') until stdin ends, and once more then."""
    closed = until_closed()
    for _, due, _ in ticks(every, offset=every / 2):
        if closed.wait(max(due - time.monotonic(), 0.0)):
            break
        emit(line())
    emit(line())


#: The counts a child's line carries, summed over the children.
_SUMMED: Final = ("fast", "fast_errors", "slow", "slow_errors", "skipped")


def library_processes(
    subject: str, targets: Sequence[tuple[str, int]], argv: Sequence[str], every: float
) -> None:
    """The library's machines in processes of at most :data:`PER_PROCESS` (``argv`` the
    options to pass on, the pool's threads shared out among them), their counts added up."""
    parts = -(-len(targets) // PER_PROCESS)
    size = -(-len(targets) // parts)
    children: list[subprocess.Popen[str]] = []
    latest: list[dict[str, Any]] = []
    ready = threading.Semaphore(0)
    failed: list[str] = []

    def read(i: int, child: subprocess.Popen[str]) -> None:
        assert child.stdout is not None
        for text in child.stdout:
            line = json.loads(text)
            if line["event"] == "count":
                latest[i] = line
            elif line["event"] == "ready":
                ready.release()
            elif line["event"] == "failed":
                failed.append(str(line["error"]))
        if child.poll() is None:
            child.wait()
        failed.append(f"process {i} ended ({child.returncode})")
        ready.release()

    with tempfile.TemporaryDirectory(prefix="focas-fwlib-") as tmp:
        for i in range(parts):
            chunk = Path(tmp) / f"targets-{i}.json"
            chunk.write_text(json.dumps(targets[i * size : (i + 1) * size]), encoding="utf-8")
            child = subprocess.Popen(
                [sys.executable, "-m", "benchmarks.gateway_poll", subject, "--targets",
                 str(chunk), "--share", f"{i}/{parts}", *argv],
                stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True,
            )  # fmt: skip
            children.append(child)
            latest.append({})
            threading.Thread(target=read, args=(i, child), daemon=True).start()
        try:
            for _ in children:
                ready.acquire()
                if failed:
                    raise RuntimeError(failed[0])
            emit({"event": "ready", "machines": len(targets), "processes": parts})

            def line() -> dict[str, Any]:
                out: dict[str, Any] = {"event": "count", "t": time.monotonic()}
                for key in _SUMMED:
                    out[key] = sum(int(c.get(key, 0)) for c in latest)
                out["error"] = next((c["error"] for c in latest if c.get("error")), "")
                if failed:
                    out["error"] = failed[0]
                return out

            report(line, every)
        finally:
            for child in children:
                if child.stdin is not None:
                    child.stdin.close()
            for child in children:
                try:
                    child.wait(30)
                except subprocess.TimeoutExpired:
                    child.kill()
                    child.wait(5)


# -- the client floor ------------------------------------------------------------------------


async def _slow_reads(client: NativeClient) -> None:
    """The slow group of one machine, its calls started together (in frames of up to ten)."""
    number, kind = TOOL_OFFSET
    calls: list[Awaitable[object]] = [client.read_macro(n) for n in PARTS_MACROS]
    calls.append(client.read_param(PARTS_REQUIRED))
    calls += [client.read_timer(kind) for kind in TIMERS]
    calls += [
        client.read_spindle_loads(),
        client.read_servo_meters(),
        client.read_commands(),
        client.read_operator_message(),
        client.read_tool_offset(number, kind),
    ]
    await asyncio.gather(*calls)


async def floor_poll(
    targets: Sequence[tuple[str, int]], fast: float, slow: float, call_timeout: float
) -> None:
    """The client floor: every machine's fast group once a ``fast`` interval from one task, and
    the slow group of the machines whose turn it is in the same cycle."""
    from focas_net.client import NativeClient, read_dynamic_all, read_status_all

    turns = max(1, round(slow / fast))
    clients = [NativeClient(host, port, timeout=call_timeout) for host, port in targets]
    counts = Counts.of(1)

    async def pmc(client: NativeClient) -> bytes:
        return await client.read_pmc("G", PMC_FIRST, PMC_LAST - PMC_FIRST + 1)

    async def alarms(client: NativeClient) -> object:
        return await client.read_alarms(count=ALARMS)

    def tally(results: Sequence[object], ok: list[int], errors: list[int]) -> None:
        for result in results:
            if isinstance(result, BaseException):
                errors[0] += 1
                counts.error(result)
            else:
                ok[0] += 1

    async def cycle(tick: int) -> None:
        group = [c for i, c in enumerate(clients) if tick % turns == i % turns]
        status, dynamic, overrides, active, slow_results = await asyncio.gather(
            read_status_all(clients),
            read_dynamic_all(clients),
            asyncio.gather(*(pmc(c) for c in clients), return_exceptions=True),
            asyncio.gather(*(alarms(c) for c in clients), return_exceptions=True),
            asyncio.gather(*(_slow_reads(c) for c in group), return_exceptions=True),
        )
        whole = [
            next((r for r in reads if isinstance(r, BaseException)), True)
            for reads in zip(status, dynamic, overrides, active, strict=True)
        ]
        tally(whole, counts.fast, counts.fast_errors)
        tally(slow_results, counts.slow, counts.slow_errors)

    async def poll() -> None:
        """The cycles until stdin ends; after each, the counts, timed at the end of its
        interval (so that the counts of whole cycles are set against whole intervals)."""
        closed = until_closed()
        for tick, due, skipped in ticks(fast):
            if closed.is_set():
                return
            wait = due - time.monotonic()
            if wait > 0:
                await asyncio.sleep(wait)
            counts.skipped[0] += skipped * len(clients)
            await cycle(tick)
            emit({**counts.line(), "t": due + fast})

    try:
        for i in range(0, len(clients), 50):
            opened = await asyncio.gather(
                *(c.connect() for c in clients[i : i + 50]), return_exceptions=True
            )
            errors = [e for e in opened if isinstance(e, BaseException)]
            if errors:
                raise RuntimeError(f"{len(errors)} machine(s) would not connect: {errors[0]!r}")
        emit({"event": "ready", "machines": len(clients), "threads": 1})
        await poll()
    finally:
        await asyncio.gather(*(c.aclose() for c in clients), return_exceptions=True)


def _parse(argv: Sequence[str] | None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(prog="python -m benchmarks.gateway_poll")
    parser.add_argument("subject", choices=SUBJECTS)
    parser.add_argument("--targets", required=True, help="JSON file: [[host, port], ...]")
    parser.add_argument("--fast", type=float, default=1.0, help="fast group interval (s)")
    parser.add_argument("--slow", type=float, default=10.0, help="slow group interval (s)")
    parser.add_argument("--pool", type=int, default=32, help="fwlib-pool's threads")
    parser.add_argument("--timeout", type=float, default=3.0, help="seconds per call")
    parser.add_argument("--share", help="i/n: one of the library's n processes")
    return parser.parse_args(argv)


def main(argv: Sequence[str] | None = None) -> int:
    args = _parse(argv)
    raise_nofile()
    with open(args.targets, encoding="utf-8") as f:
        targets = [(str(host), int(port)) for host, port in json.load(f)]
    try:
        if args.subject == FLOOR:
            asyncio.run(floor_poll(targets, args.fast, args.slow, args.timeout))
        elif args.share is None and len(targets) > PER_PROCESS:
            parts = -(-len(targets) // PER_PROCESS)
            times = ["--fast", str(args.fast), "--slow", str(args.slow)]
            times += ["--timeout", str(args.timeout), "--pool", str(-(-args.pool // parts))]
            library_processes(args.subject, targets, times, args.fast)
        else:
            threads = len(targets) if args.subject == FWLIB_THREADS else args.pool
            threads = max(1, min(threads, len(targets)))
            library_poll(targets, threads, args.fast, args.slow, max(1, round(args.timeout)))
    except RuntimeError as exc:
        emit({"event": "failed", "error": str(exc)})
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
