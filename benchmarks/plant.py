"""The plant and the native side: scenarios of ``python -m benchmarks`` on focas_net alone.

``plant``: one client process polls the status of every machine of one ``focas-net serve
--fleet 1000`` (its own process, or a parent and ``--workers`` processes) every 100 ms, first
idle, then with ``--run`` (the machines running programs), over connections opened once; the
server's CPU is that of its whole process tree, from ``/proc``. The floor's client
(``benchmarks/floor.py``) polls the same machines over connections of its own, taking turns
with focas_net's client: what a poll costs a client at the least. Then ``serve --fleet 5000``:
the time from its start to its last ready line, and the RSS of its process tree then.

``native``: the server's CPU per request of FANUC's FOCAS/2 statinfo (the project's
``NativeClient``, which sends the frames FANUC's library sends) against that of a packed status
request, on the same server, turn about in each repetition, in three modes: one caller on one
connection (``seq``); 64 connections with one caller each (``conc64``); 64 concurrent callers on
one connection (``pipe64``). The target applies to ``seq`` and ``conc64``, the two ways FANUC's
library and pyfocas use a server: each of their handles has one call, so one frame, in flight,
and more load means more handles. ``pipe64`` is reported and not held to the target: FOCAS/2
carries one frame in flight per connection (a statinfo is three blocks, so a frame of ten blocks
holds three calls), while the packed protocol pipelines all 64 requests, so the comparison there
is of the two protocols' framing, not of the server's work per request.
"""

from __future__ import annotations

import os
import statistics
import time
from pathlib import Path
from typing import TYPE_CHECKING

from benchmarks._process import log
from benchmarks.report import FLOOR, FOCAS, Check, Results, Row, pairwise_ratios

if TYPE_CHECKING:
    from benchmarks.run import Suite, WorkerProcess

#: Polls per second the plant's client must keep up, as a share of those due.
PLANT_ACHIEVED = 0.99
#: The slowest status poll allowed (seconds).
PLANT_SLOWEST = 0.050
#: CPU (cores) the plant's client, its idle server and its running server may use.
PLANT_CLIENT_CORES = 0.5
PLANT_SERVER_CORES = 0.5
PLANT_RUN_SERVER_CORES = 1.0
#: ``serve --fleet 5000``: seconds until ready, and the RSS of its processes then (KiB).
READY_SECONDS = 15.0
READY_RSS_KIB = 1024 * 1024
#: Server CPU per native request against per packed request, at most.
NATIVE_TARGET = 1.5
#: (name, connections, concurrent callers on each, held to NATIVE_TARGET) of the native
#: scenario's modes.
NATIVE_MODES = (("seq", 1, 1, True), ("conc64", 64, 1, True), ("pipe64", 1, 64, False))


def process_tree(pid: int) -> list[int]:
    """``pid`` and its descendants still running, from ``/proc/PID/task/*/children``."""
    found = [pid]
    i = 0
    while i < len(found):
        task_dir = Path(f"/proc/{found[i]}/task")
        try:
            tasks = list(task_dir.iterdir())
        except OSError:
            tasks = []
        for task in tasks:
            try:
                text = (task / "children").read_text(encoding="ascii")
            except OSError:
                continue
            found.extend(int(child) for child in text.split())
        i += 1
    return found


def _stat_cpu(pid: int, clk_tck: int) -> float:
    try:
        with open(f"/proc/{pid}/stat", encoding="ascii") as f:
            fields = f.read().rsplit(")", 1)[1].split()
    except OSError:  # gone meanwhile
        return 0.0
    return (int(fields[11]) + int(fields[12])) / clk_tck


def tree_cpu_seconds(pid: int) -> float:
    """User + system CPU time of ``pid`` and its running descendants (seconds)."""
    clk_tck = os.sysconf("SC_CLK_TCK")
    return sum(_stat_cpu(p, clk_tck) for p in process_tree(pid))


def tree_rss_kib(pid: int) -> int:
    """``VmRSS`` of ``pid`` and its running descendants (KiB)."""
    total = 0
    for p in process_tree(pid):
        try:
            with open(f"/proc/{p}/status", encoding="ascii") as f:
                for line in f:
                    if line.startswith("VmRSS:"):
                        total += int(line.split()[1])
                        break
        except OSError:
            continue
    return total


def cpu_pressure() -> float | None:
    """The share of the last 10 s in which some runnable task waited for a CPU
    (``/proc/pressure/cpu``, "some avg10"), or None where the kernel does not say."""
    try:
        with open("/proc/pressure/cpu", encoding="ascii") as f:
            first = f.readline().split()
    except OSError:
        return None
    for field in first[1:]:
        key, _, value = field.partition("=")
        if key == "avg10":
            return float(value) / 100
    return None


def _serve_extra(size: int, workers: int, running: bool) -> tuple[str, ...]:
    extra = ["--fleet", str(size), "--max-connections", "4"]
    if workers > 1:
        extra += ["--workers", str(workers)]
    if running:
        extra.append("--run")
    return tuple(extra)


def _floor_poll(
    worker: WorkerProcess, interval: float, duration: float, slots: int
) -> tuple[float, float]:
    """One poll run of the floor's client over the plant: its cores and CPU us per poll."""
    r = worker.call("plant_poll", interval=interval, duration=duration, slots=slots, floor=True)
    return r["cpu"] / r["wall"], 1e6 * float(r["cpu"]) / max(1, int(r["polls"]))


def plant(suite: Suite) -> None:
    """The ``plant`` scenario: the 1,000-machine poll idle and running, then the 5,000 start."""
    from benchmarks.run import start_server

    cfg = suite.cfg
    n = cfg.plant_size
    workers = cfg.plant_workers
    how = f"{workers} worker processes" if workers > 1 else "one process"
    if cfg.plant_slots:
        how += f", polls in {cfg.plant_slots} slots"
    else:
        how += ", a task per machine"
    interval = 1.0 / cfg.plant_hz
    worker = suite.workers[FOCAS]
    for running in (False, True):
        name = "plant_run" if running else "plant"
        log(
            f"{name}: {n} machines ({how}) at {cfg.plant_hz:g} Hz, "
            f"{cfg.reps} x {cfg.plant_duration:g} s"
        )
        server = start_server(
            FOCAS, cfg, extra=_serve_extra(n, workers, running), count=n, timeout=120.0
        )
        try:
            targets = [list(e) for e in server.endpoints]
            if len(targets) < n:
                raise RuntimeError(f"plant server announced {len(targets)} of {n} machines")
            worker.call("plant_open", targets=targets, floor=True)
            slots = cfg.plant_slots
            for floor in (False, True):
                worker.call(
                    "plant_poll",
                    interval=interval,
                    duration=min(1.0, cfg.plant_duration),
                    slots=slots,
                    floor=floor,
                )
            rates: list[float] = []
            achieved: list[float] = []
            client: list[float] = []
            served: list[float] = []
            client_us: list[float] = []
            server_us: list[float] = []
            pressure: list[float] = []
            floor_samples: list[tuple[float, float]] = []  # (cores, us per poll)
            errors = 0
            worst = 0.0

            for rep in range(cfg.reps):
                if rep % 2 == 0:  # side by side, the order alternating
                    floor_samples.append(_floor_poll(worker, interval, cfg.plant_duration, slots))
                cpu0 = tree_cpu_seconds(server.pid)
                r = worker.call(
                    "plant_poll", interval=interval, duration=cfg.plant_duration, slots=slots
                )
                cpu = tree_cpu_seconds(server.pid) - cpu0
                served.append(cpu / float(r["wall"]))
                polls = max(1, int(r["polls"]))
                client_us.append(1e6 * float(r["cpu"]) / polls)
                server_us.append(1e6 * cpu / polls)
                waited = cpu_pressure()
                if waited is not None:
                    pressure.append(waited)
                rates.append(r["polls"] / r["duration"])
                achieved.append(r["polls"] / r["due"])
                client.append(r["cpu"] / r["wall"])
                errors += int(r["errors"])
                worst = max(worst, float(r["worst_latency"]))
                if rep % 2 != 0:
                    floor_samples.append(_floor_poll(worker, interval, cfg.plant_duration, slots))
            worker.call("plant_close")
        finally:
            server.stop()
        nominal = n * cfg.plant_hz
        contended = f", CPU pressure {statistics.median(pressure):.0%}" if pressure else ""
        suite.add(
            Row(
                f"{name}_rate",
                FOCAS,
                "polls/s",
                rates,
                ratio_to=f"nominal {nominal:g}/s",
                ratios=achieved,
                note=f"{errors} errors, slowest poll {worst * 1e3:.1f} ms{contended}",
                extra={"errors": errors, "worst_ms": worst * 1e3},
            )
        )
        per_poll = statistics.median(client_us)
        suite.add(
            Row(
                f"{name}_client",
                FOCAS,
                "cores",
                client,
                note=f"client process_time / wall; {per_poll:.1f} us per poll, "
                f"{per_poll * nominal / 1e6:.2f} core at the nominal rate",
                extra={"us_per_poll": per_poll},
            )
        )
        floor_client = [cores for cores, _ in floor_samples]
        per_poll = statistics.median(us for _, us in floor_samples)
        suite.add(
            Row(
                f"{name}_floor_client",
                FLOOR,
                "cores",
                floor_client,
                ratio_to="focas_net's client",
                ratios=pairwise_ratios(floor_client, client),
                note=f"the floor's client polling the same machines; {per_poll:.1f} us per poll",
                extra={"us_per_poll": per_poll},
            )
        )
        per_poll = statistics.median(server_us)
        suite.add(
            Row(
                f"{name}_server",
                FOCAS,
                "cores",
                served,
                note=f"{how}, from /proc; {per_poll:.1f} us per poll, "
                f"{per_poll * nominal / 1e6:.2f} core at the nominal rate",
                extra={"us_per_poll": per_poll},
            )
        )
    ready(suite)


def ready(suite: Suite) -> None:
    """``serve --fleet 5000``: seconds to the last ready line, and RSS then; a fresh server
    each repetition."""
    from benchmarks.run import ServerProcess
    from benchmarks.subjects import server_argv

    cfg = suite.cfg
    n = cfg.ready_size
    workers = cfg.plant_workers
    log(f"plant_ready: serve --fleet {n}, {cfg.reps} starts")
    seconds: list[float] = []
    rss: list[float] = []
    argv = server_argv(FOCAS, use_uvloop=cfg.use_uvloop, extra=_serve_extra(n, workers, False))
    for _ in range(cfg.reps):
        t0 = time.monotonic()
        server = ServerProcess(FOCAS, argv)
        try:
            server.wait_ready(n, timeout=120.0, settle=60.0)
            seconds.append(server.ready_at - t0)
            if len(server.endpoints) < n:
                raise RuntimeError(f"serve --fleet {n} announced {len(server.endpoints)}")
            rss.append(tree_rss_kib(server.pid) / 1024)
        finally:
            server.stop()
    suite.add(Row("plant_ready", FOCAS, "s", seconds, note=f"serve --fleet {n}"))
    suite.add(Row("plant_rss", FOCAS, "MiB", rss, note="VmRSS of the server's processes"))


def native(suite: Suite) -> None:
    """The ``native`` scenario: server CPU per FOCAS/2 statinfo against per packed status."""

    cfg = suite.cfg
    server = suite.servers[FOCAS]
    worker = suite.workers[FOCAS]
    host, port = server.endpoint
    log(f"native: statinfo against packed status, {cfg.reps} x {cfg.duration:g} s each")

    def sample(native: bool, conns: int, callers: int, duration: float) -> tuple[float, float]:
        op = "native_throughput" if native else "throughput"
        cpu = server.cpu_seconds()
        r = worker.call(op, host=host, port=port, conns=conns, callers=callers, duration=duration)
        cpu = server.cpu_seconds() - cpu
        ops = float(r["ops"])
        return ops / float(r["elapsed"]), 1e6 * cpu / ops

    for mode, conns, callers, held in NATIVE_MODES:
        sample(True, conns, callers, cfg.warmup)
        sample(False, conns, callers, cfg.warmup)
        native_us: list[float] = []
        packed_us: list[float] = []
        native_rate: list[float] = []
        for rep in range(cfg.reps):
            order = (True, False) if rep % 2 == 0 else (False, True)
            for is_native in order:
                rate, us = sample(is_native, conns, callers, cfg.duration)
                (native_us if is_native else packed_us).append(us)
                if is_native:
                    native_rate.append(rate)
        suite.add(Row(f"native_{mode}", FOCAS, "req/s", native_rate, note="NativeClient statinfo"))
        suite.add(
            Row(
                f"native_{mode}_server",
                FOCAS,
                "us/req",
                native_us,
                ratio_to="packed",
                ratios=pairwise_ratios(native_us, packed_us),
                note="server CPU per statinfo" + ("" if held else ", no target"),
            )
        )
        suite.add(
            Row(f"packed_{mode}_server", FOCAS, "us/req", packed_us, note="server CPU per status")
        )


def evaluate_plant(results: Results, *, size: int, ready_size: int) -> list[Check]:
    """The targets of ``plant`` and ``native``, each PASS, FAIL or SKIP."""
    checks: list[Check] = []
    limits = (("plant", PLANT_SERVER_CORES), ("plant_run", PLANT_RUN_SERVER_CORES))
    for name, server_cores in limits:
        what = "running programs" if name == "plant_run" else "idle"
        label = (
            f"{name}: {size} machines ({what}) at the full rate, slowest poll < "
            f"{PLANT_SLOWEST * 1e3:g} ms, client < {PLANT_CLIENT_CORES:g} core, server < "
            f"{server_cores:g} core"
        )
        rate = results.find(f"{name}_rate", FOCAS)
        client = results.find(f"{name}_client", FOCAS)
        server = results.find(f"{name}_server", FOCAS)
        if rate is None or rate.ratio is None or client is None or server is None:
            checks.append(Check(label, None, "not measured"))
            continue
        achieved = rate.ratio.median
        worst = rate.extra.get("worst_ms", float("inf")) / 1e3
        cli = client.summary.median
        srv = server.summary.median
        ok = (
            achieved >= PLANT_ACHIEVED
            and worst < PLANT_SLOWEST
            and cli < PLANT_CLIENT_CORES
            and srv < server_cores
        )
        detail = (
            f"{achieved:.1%} of the polls due, slowest {worst * 1e3:.1f} ms, client "
            f"{cli:.2f} core, server {srv:.2f} core"
        )
        checks.append(Check(label, ok, detail))
    label = (
        f"plant_ready: serve --fleet {ready_size} ready in < {READY_SECONDS:g} s and "
        f"< {READY_RSS_KIB // (1024 * 1024)} GiB RSS"
    )
    seconds = results.find("plant_ready", FOCAS)
    rss = results.find("plant_rss", FOCAS)
    if seconds is None or rss is None:
        checks.append(Check(label, None, "not measured"))
    else:
        s, mib = seconds.summary.max, rss.summary.max
        ok = s < READY_SECONDS and mib * 1024 < READY_RSS_KIB
        checks.append(Check(label, ok, f"slowest start {s:.1f} s, largest RSS {mib:.0f} MiB"))
    for mode, _, _, held in NATIVE_MODES:
        if not held:
            continue
        row = results.find(f"native_{mode}_server", FOCAS)
        label = f"native {mode}: server CPU per statinfo <= {NATIVE_TARGET:g} x per packed status"
        if row is None or row.ratio is None:
            checks.append(Check(label, None, "not measured"))
        else:
            value = row.ratio.median
            checks.append(Check(label, value <= NATIVE_TARGET, f"median ratio {value:.2f}"))
    return checks
