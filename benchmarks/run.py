"""Run the focas_net benchmark suite: ``python -m benchmarks`` or ``python benchmarks/run.py``.

Every server and every client runs in a process of its own on 127.0.0.1. Each scenario runs for
a fixed time, once to warm up and then ``--reps`` times; the subjects take turns within each
repetition, so the ratio to the floor is taken pair by pair from samples measured side by side.
"""

from __future__ import annotations

import argparse
import functools
import json
import os
import platform
import re
import shlex
import statistics
import subprocess
import sys
import threading
import time
from collections import deque
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parent.parent
if __package__ in (None, ""):  # run as a script: make ``benchmarks`` importable
    sys.path.insert(0, str(ROOT))

from benchmarks import native, plant  # noqa: E402
from benchmarks._loop import uvloop_available  # noqa: E402
from benchmarks._process import child_env, end, log  # noqa: E402
from benchmarks.report import (  # noqa: E402
    FLOOR,
    FOCAS,
    PEER,
    THROUGHPUT_MODES,
    Results,
    Row,
    evaluate,
    pairwise_ratios,
    print_results,
)
from benchmarks.subjects import (  # noqa: E402
    LISTEN_PATTERN,
    focas_available,
    peer_available,
    server_argv,
)

SCENARIOS = (
    *THROUGHPUT_MODES,
    "pmc4k",
    "bitstorm",
    "native",
    "fleet",
    "plant",
    "memory",
    *native.SCENARIOS,
)
#: (connections, concurrent callers per connection) of each throughput mode.
MODES: dict[str, tuple[int, int]] = {"seq": (1, 1), "pipe64": (1, 64), "conc100": (100, 1)}
DEFAULT_JSON = ROOT / "benchmarks" / "results" / "latest.json"
_LISTEN = re.compile(LISTEN_PATTERN)
#: The floor's second server (the plain ``asyncio.Protocol`` variant): not a subject of its own,
#: the floor of each sample is the faster of the two.
FLOOR_PLAIN = "floor-plain"
_CLK_TCK = os.sysconf("SC_CLK_TCK") if hasattr(os, "sysconf") else 100


@dataclass(frozen=True, slots=True)
class Config:
    reps: int = 5
    duration: float = 1.0
    warmup: float = 0.5
    fleet_size: int = 200
    fleet_hz: float = 10.0
    fleet_duration: float = 3.0
    idle_conns: int = 1000
    storm_calls: int = 1000
    storm_bytes: int = 8
    pmc_big: int = 4096
    pmc_small: int = 32
    plant_size: int = 1000
    plant_hz: float = 10.0
    plant_duration: float = 3.0
    #: ``serve --workers`` of the plant's server (0 or 1: one process).
    plant_workers: int = 0
    #: Slots per interval of the plant's polls, each slot's machines read together by one
    #: task (0: a task for each machine, at a start time of its own).
    plant_slots: int = 10
    ready_size: int = 5000
    use_uvloop: bool = False

    @classmethod
    def quick(cls, use_uvloop: bool) -> Config:
        return cls(
            reps=2,
            duration=0.2,
            warmup=0.1,
            fleet_duration=1.0,
            idle_conns=200,
            plant_size=100,
            plant_duration=1.0,
            ready_size=200,
            use_uvloop=use_uvloop,
        )


class ServerProcess:
    """A server in its own process; ready once it printed its ``listening on`` line(s)."""

    def __init__(self, name: str, argv: list[str]) -> None:
        self.name = name
        self.argv = argv
        self.started_at = time.monotonic()
        self.proc = subprocess.Popen(
            argv,
            cwd=ROOT,
            env=child_env(),
            stdin=subprocess.DEVNULL,
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            text=True,
        )
        self.lines: deque[str] = deque(maxlen=50)
        self.endpoints: list[tuple[str, int]] = []
        self._cond = threading.Condition()
        self._last = time.monotonic()
        #: When the latest ``listening on`` line came.
        self.ready_at = self._last
        threading.Thread(target=self._drain, daemon=True).start()

    @property
    def pid(self) -> int:
        return self.proc.pid

    def _drain(self) -> None:
        assert self.proc.stdout is not None
        for line in self.proc.stdout:
            with self._cond:
                self.lines.append(line.rstrip())
                match = _LISTEN.search(line)
                if match:
                    self.endpoints.append((match["host"].strip("[]"), int(match["port"])))
                    self._last = self.ready_at = time.monotonic()
                self._cond.notify_all()
        with self._cond:
            self._cond.notify_all()

    def wait_ready(self, count: int = 1, timeout: float = 30.0, settle: float = 1.0) -> None:
        """Wait for ``count`` endpoints (or, past the first, ``settle`` s without a new one)."""
        deadline = time.monotonic() + timeout
        with self._cond:
            while len(self.endpoints) < count:
                if self.proc.poll() is not None:
                    tail = "\n".join(self.lines)
                    raise RuntimeError(f"{self.name} server exited:\n{tail}")
                now = time.monotonic()
                if now > deadline:
                    raise RuntimeError(f"{self.name} server not ready in {timeout:g} s")
                if self.endpoints and now - self._last > settle:
                    break
                self._cond.wait(0.1)

    @property
    def endpoint(self) -> tuple[str, int]:
        return self.endpoints[0]

    def cpu_seconds(self) -> float:
        """User + system CPU time of the server process so far, from /proc."""
        with open(f"/proc/{self.pid}/stat", encoding="ascii") as f:
            fields = f.read().rsplit(")", 1)[1].split()
        return (int(fields[11]) + int(fields[12])) / _CLK_TCK

    def rss_kib(self) -> int:
        """Resident set size of the server process, from /proc (KiB)."""
        with open(f"/proc/{self.pid}/status", encoding="ascii") as f:
            for line in f:
                if line.startswith("VmRSS:"):
                    return int(line.split()[1])
        raise RuntimeError("no VmRSS in /proc status")

    def stop(self) -> None:
        end(self.proc)


def start_server(
    subject: str,
    cfg: Config,
    extra: tuple[str, ...] = (),
    count: int = 1,
    timeout: float = 30.0,
) -> ServerProcess:
    server = ServerProcess(subject, server_argv(subject, use_uvloop=cfg.use_uvloop, extra=extra))
    try:
        server.wait_ready(count, timeout=timeout, settle=timeout if count > 1 else 1.0)
    except BaseException:
        server.stop()
        raise
    return server


class WorkerProcess:
    """A client process of one subject, driven by JSON lines (see ``benchmarks.worker``)."""

    def __init__(self, subject: str, cfg: Config) -> None:
        argv = [sys.executable, "-m", "benchmarks.worker", "--subject", subject]
        if cfg.use_uvloop:
            argv.append("--uvloop")
        self.subject = subject
        self.proc = subprocess.Popen(
            argv,
            cwd=ROOT,
            env=child_env(),
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )
        self.errors: deque[str] = deque(maxlen=50)
        threading.Thread(target=self._drain_stderr, daemon=True).start()

    def _drain_stderr(self) -> None:
        assert self.proc.stderr is not None
        for line in self.proc.stderr:
            self.errors.append(line.rstrip())

    def call(self, op: str, **kwargs: Any) -> dict[str, Any]:
        assert self.proc.stdin is not None and self.proc.stdout is not None
        self.proc.stdin.write(json.dumps({"op": op, **kwargs}) + "\n")
        self.proc.stdin.flush()
        line = self.proc.stdout.readline()
        if not line:
            tail = "\n".join(self.errors)
            raise RuntimeError(f"{self.subject} client process died:\n{tail}")
        answer = json.loads(line)
        if not answer["ok"]:
            raise RuntimeError(f"{self.subject} client: {op} failed: {answer['error']}")
        result: dict[str, Any] = answer["result"]
        return result

    def stop(self) -> None:
        if self.proc.poll() is None:
            try:
                assert self.proc.stdin is not None
                self.proc.stdin.write('{"op": "quit"}\n')
                self.proc.stdin.close()
                self.proc.wait(10)
            except (OSError, subprocess.TimeoutExpired):
                self.proc.kill()
                self.proc.wait(5)


def machine_info(cfg: Config) -> dict[str, str]:
    model = "unknown"
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as f:
            for line in f:
                if line.startswith("model name"):
                    model = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    loop = "uvloop" if cfg.use_uvloop and uvloop_available() else "asyncio"
    return {
        "nproc": str(
            len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
        ),
        "cpu": model,
        "python": platform.python_version(),
        "implementation": platform.python_implementation(),
        "platform": platform.platform(),
        "event_loop": loop,
    }


class Suite:
    def __init__(self, cfg: Config, scenarios: Sequence[str], results: Results) -> None:
        self.cfg = cfg
        self.scenarios = scenarios
        self.results = results
        self.subjects = [FLOOR]
        self.servers: dict[str, ServerProcess] = {}
        self.workers: dict[str, WorkerProcess] = {}
        #: Repetitions (warm-ups included) in which the floor's plain server was the faster.
        self.plain_wins: dict[str, int] = {}
        why = focas_available()
        if why is None:
            self.subjects.append(FOCAS)
        else:
            self.skip(f"focas_net skipped: {why}")
        why = peer_available()
        if why is None:
            self.subjects.append(PEER)
        else:
            self.skip(f"pymodbus peer skipped: {why}")

    def skip(self, message: str) -> None:
        log(message)
        self.results.skipped.append(message)

    def turns(self, rep: int) -> list[str]:
        """The subjects in the order they take their turn in repetition ``rep`` (alternating,
        so that neither goes first every time)."""
        return self.subjects if rep % 2 == 0 else self.subjects[::-1]

    def guarded(self, name: str, scenario: Callable[[], None]) -> None:
        """Run one scenario; a failure is reported and the suite goes on."""
        try:
            scenario()
        except RuntimeError as exc:
            self.skip(f"{name} failed: {exc}")

    def add(self, row: Row) -> None:
        self.results.rows.append(row)

    def run(self) -> None:
        try:
            for subject in list(self.subjects):
                try:
                    self.servers[subject] = start_server(subject, self.cfg)
                    if subject == FLOOR:
                        self.servers[FLOOR_PLAIN] = start_server(
                            FLOOR, self.cfg, extra=("--variant", "plain")
                        )
                    self.workers[subject] = WorkerProcess(subject, self.cfg)
                except RuntimeError as exc:
                    self.subjects.remove(subject)
                    self.skip(f"{subject} skipped: {exc}")
            for mode in THROUGHPUT_MODES:
                if mode in self.scenarios:
                    self.guarded(mode, functools.partial(self.throughput, mode))
            if FOCAS in self.subjects:
                if "pmc4k" in self.scenarios:
                    self.guarded("pmc4k", self.pmc4k)
                if "bitstorm" in self.scenarios:
                    self.guarded("bitstorm", self.bitstorm)
                if "native" in self.scenarios:
                    self.guarded("native", functools.partial(plant.native, self))
            else:
                for name in ("pmc4k", "bitstorm", "native"):
                    if name in self.scenarios:
                        self.skip(f"{name} skipped: focas_net is not available")
        finally:
            for server in self.servers.values():
                server.stop()
            self.servers.clear()
        if "fleet" in self.scenarios:
            if FOCAS in self.subjects:
                self.guarded("fleet", self.fleet)
            else:
                self.skip("fleet skipped: focas_net is not available")
        if "plant" in self.scenarios:
            if FOCAS in self.subjects:
                self.guarded("plant", functools.partial(plant.plant, self))
            else:
                self.skip("plant skipped: focas_net is not available")
        try:
            if "memory" in self.scenarios:
                self.guarded("memory", self.memory)
        finally:
            for worker in self.workers.values():
                worker.stop()
        native.run_native(self)

    def _sample(self, subject: str, mode: str, duration: float) -> tuple[float, float, float]:
        """Requests per second, and server and client CPU microseconds per request; for the
        floor, those of the faster of its two servers (``self.plain_wins`` counts the plain
        one's wins)."""
        if subject != FLOOR or FLOOR_PLAIN not in self.servers:
            return self._sample_server(subject, subject, mode, duration)
        buffered = self._sample_server(FLOOR, FLOOR, mode, duration)
        plain = self._sample_server(FLOOR, FLOOR_PLAIN, mode, duration)
        if plain[0] > buffered[0]:
            self.plain_wins[mode] = self.plain_wins.get(mode, 0) + 1
            return plain
        return buffered

    def _sample_server(
        self, subject: str, server_name: str, mode: str, duration: float
    ) -> tuple[float, float, float]:
        conns, callers = MODES[mode]
        server = self.servers[server_name]
        host, port = server.endpoint
        cpu = server.cpu_seconds()
        r = self.workers[subject].call(
            "throughput", host=host, port=port, conns=conns, callers=callers, duration=duration
        )
        cpu = server.cpu_seconds() - cpu  # includes connecting; clock ticks of 10 ms
        ops = float(r["ops"])
        return ops / float(r["elapsed"]), 1e6 * cpu / ops, 1e6 * float(r["cpu"]) / ops

    def throughput(self, mode: str) -> None:
        cfg = self.cfg
        log(f"{mode}: warm-up, then {cfg.reps} x {cfg.duration:g} s per subject")
        samples: dict[str, list[float]] = {s: [] for s in self.subjects}
        server_us: dict[str, list[float]] = {s: [] for s in self.subjects}
        client_us: dict[str, list[float]] = {s: [] for s in self.subjects}
        for subject in self.subjects:
            self._sample(subject, mode, cfg.warmup)
        self.plain_wins[mode] = 0
        for rep in range(cfg.reps):
            for subject in self.turns(rep):
                rate, srv, cli = self._sample(subject, mode, cfg.duration)
                samples[subject].append(rate)
                server_us[subject].append(srv)
                client_us[subject].append(cli)
        rows = []
        wins = self.plain_wins.get(mode, 0)
        for subject in self.subjects:
            vs = None if subject == FLOOR else "floor"
            note = ""
            if subject == FLOOR and FLOOR_PLAIN in self.servers:
                note = f"Protocol server faster in {wins} of {cfg.reps}, else BufferedProtocol"
            rows.append(Row(mode, subject, "req/s", samples[subject], vs, note=note))
            total = [s + c for s, c in zip(server_us[subject], client_us[subject], strict=True)]
            note = (
                f"server {statistics.median(server_us[subject]):.1f}"
                f" + client {statistics.median(client_us[subject]):.1f}"
            )
            rows.append(Row(f"{mode}_cpu", subject, "us/req", total, vs, note=note))
        for row in rows:
            if row.ratio_to is not None:
                floor = next(r for r in rows if r.scenario == row.scenario and r.subject == FLOOR)
                row.ratios = pairwise_ratios(row.samples, floor.samples)
            self.add(row)

    def pmc4k(self) -> None:
        cfg = self.cfg
        log(f"pmc4k: read_pmc('D', 0, {cfg.pmc_big}) against a {cfg.pmc_small}-byte read")
        host, port = self.servers[FOCAS].endpoint
        worker = self.workers[FOCAS]
        kwargs = {
            "host": host,
            "port": port,
            "area": "D",
            "big": cfg.pmc_big,
            "small": cfg.pmc_small,
        }
        burst = -(-cfg.pmc_big // cfg.pmc_small)  # the number of chunks
        floor = self.workers[FLOOR]
        floors = [self.servers[name] for name in (FLOOR, FLOOR_PLAIN) if name in self.servers]
        fkwargs = [{"host": s.endpoint[0], "port": s.endpoint[1], "burst": burst} for s in floors]
        worker.call("pmc_pair", duration=cfg.warmup, **kwargs)
        for fk in fkwargs:
            floor.call("burst_pair", duration=cfg.warmup, **fk)
        big: list[float] = []
        small: list[float] = []
        fbig: list[float] = []
        fsmall: list[float] = []
        for _ in range(cfg.reps):
            r = worker.call("pmc_pair", duration=cfg.duration, **kwargs)
            big.append(r["big"] * 1e3)
            small.append(r["small"] * 1e3)
            # the floor's faster server in this repetition
            r = min(
                (floor.call("burst_pair", duration=cfg.duration, **fk) for fk in fkwargs),
                key=lambda answer: float(answer["big"]),
            )
            fbig.append(r["big"] * 1e3)
            fsmall.append(r["small"] * 1e3)
        per_small = statistics.median(pairwise_ratios(big, small))
        self.add(
            Row(
                "pmc4k",
                FOCAS,
                "ms",
                big,
                # speed against the floor's burst: its time over ours, pair by pair
                ratio_to="floor speed",
                ratios=pairwise_ratios(fbig, big),
                note=f"{per_small:.2f} x a {cfg.pmc_small}-byte read",
            )
        )
        self.add(Row(f"pmc{cfg.pmc_small}", FOCAS, "ms", small))
        self.add(
            Row(
                "pmc4k",
                FLOOR,
                "ms",
                fbig,
                ratio_to="1 request",
                ratios=pairwise_ratios(fbig, fsmall),
                note=f"{burst} pipelined status frames: the least {burst} chunks can cost",
            )
        )

    def bitstorm(self) -> None:
        cfg = self.cfg
        log(f"bitstorm: {cfg.storm_calls} concurrent write_pmc_bit over {cfg.storm_bytes} bytes")
        host, port = self.servers[FOCAS].endpoint
        worker = self.workers[FOCAS]
        kwargs = {
            "host": host,
            "port": port,
            "area": "D",
            "start": 1000,
            "nbytes": cfg.storm_bytes,
            "calls": cfg.storm_calls,
        }
        worker.call("bitstorm", **kwargs)
        rates: list[float] = []
        lost = errors = calls = 0
        for _ in range(cfg.reps):
            r = worker.call("bitstorm", **kwargs)
            rates.append(r["calls"] / r["elapsed"])
            lost += int(r["lost"])
            errors += int(r["errors"])
            calls += int(r["calls"])
        self.add(
            Row(
                "bitstorm",
                FOCAS,
                "calls/s",
                rates,
                note=f"{lost} bits lost, {errors} errors in {calls} calls",
                extra={"lost": lost, "errors": errors, "calls": calls},
            )
        )

    def fleet(self) -> None:
        cfg = self.cfg
        n = cfg.fleet_size
        log(f"fleet: {n} machines at {cfg.fleet_hz:g} Hz, {cfg.reps} x {cfg.fleet_duration:g} s")
        try:
            server = start_server(FOCAS, cfg, extra=("--fleet", str(n)), count=n)
        except RuntimeError as exc:
            self.skip(f"fleet skipped: {exc}")
            return
        try:
            targets = [list(e) for e in server.endpoints]
            if len(targets) < n:
                raise RuntimeError(f"fleet server announced {len(targets)} of {n} machines")
            worker = self.workers[FOCAS]
            interval = 1.0 / cfg.fleet_hz
            worker.call(
                "fleet", targets=targets, interval=interval, duration=min(1.0, cfg.fleet_duration)
            )
            rates: list[float] = []
            achieved: list[float] = []
            cpu: list[float] = []
            errors = 0
            worst = 0.0
            for _ in range(cfg.reps):
                r = worker.call(
                    "fleet", targets=targets, interval=interval, duration=cfg.fleet_duration
                )
                rates.append(r["polls"] / r["duration"])
                achieved.append(r["polls"] / r["due"])
                cpu.append(r["cpu"] / r["wall"])
                errors += int(r["errors"])
                worst = max(worst, float(r["worst_latency"]))
        except RuntimeError as exc:
            self.skip(f"fleet skipped: {exc}")
            return
        finally:
            server.stop()
        nominal = n * cfg.fleet_hz
        self.add(
            Row(
                "fleet_rate",
                FOCAS,
                "polls/s",
                rates,
                ratio_to=f"nominal {nominal:g}/s",
                ratios=achieved,
                note=f"{errors} errors, slowest poll {worst * 1e3:.1f} ms",
            )
        )
        self.add(Row("fleet_cpu", FOCAS, "cores", cpu, note="client process_time / wall"))

    def memory(self) -> None:
        cfg = self.cfg
        n = cfg.idle_conns
        log(f"memory: server RSS with {n} idle connections minus none, {cfg.reps} fresh servers")
        per_conn: dict[str, list[float]] = {s: [] for s in self.subjects}
        for _ in range(cfg.reps):
            for subject in self.subjects:
                # focas_net's server takes 256 connections per machine unless told otherwise
                extra = ("--max-connections", str(n + 16)) if subject == FOCAS else ()
                server = start_server(subject, cfg, extra=extra)
                try:
                    host, port = server.endpoint
                    worker = self.workers[subject]
                    worker.call("idle_open", host=host, port=port, count=1)
                    worker.call("idle_close")
                    time.sleep(0.2)
                    before = server.rss_kib()
                    worker.call("idle_open", host=host, port=port, count=n)
                    time.sleep(0.3)
                    after = server.rss_kib()
                    worker.call("idle_close")
                finally:
                    server.stop()
                per_conn[subject].append((after - before) / n)
        floor = per_conn[FLOOR]
        for subject in self.subjects:
            self.add(
                Row(
                    "memory",
                    subject,
                    "KiB/conn",
                    per_conn[subject],
                    ratio_to=None if subject == FLOOR else "floor",
                    ratios=None if subject == FLOOR else pairwise_ratios(per_conn[subject], floor),
                )
            )


def parse_args(argv: Sequence[str] | None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(
        prog="python -m benchmarks", description="focas_net benchmarks against a floor and a peer."
    )
    parser.add_argument("--quick", action="store_true", help="a short smoke run")
    parser.add_argument("--uvloop", action="store_true", help="use uvloop if installed")
    parser.add_argument("--json", type=Path, default=DEFAULT_JSON, metavar="PATH")
    parser.add_argument("--reps", type=int, help="repetitions after the warm-up (at least 1)")
    parser.add_argument("--duration", type=float, help="seconds per measurement")
    parser.add_argument(
        "--only",
        default=",".join(SCENARIOS),
        help=f"comma-separated subset of {','.join(SCENARIOS)}",
    )
    parser.add_argument(
        "--plant-workers",
        type=int,
        metavar="N",
        help="serve the plant's fleets with serve --workers N (default: one process)",
    )
    parser.add_argument(
        "--plant-slots",
        type=int,
        metavar="N",
        help="poll the plant's machines in N slots per interval, each slot's machines read "
        "together by one task (default: 10; 0: a task per machine, each at its own time)",
    )
    parser.add_argument("--strict", action="store_true", help="exit 1 when a target fails")
    return parser.parse_args(argv)


def main(argv: Sequence[str] | None = None) -> int:
    args = parse_args(argv)
    scenarios = [s.strip() for s in args.only.split(",") if s.strip()]
    unknown = sorted(set(scenarios) - set(SCENARIOS))
    if unknown:
        log(f"unknown scenarios: {', '.join(unknown)} (known: {', '.join(SCENARIOS)})")
        return 2
    if args.uvloop and not uvloop_available():
        log("--uvloop: uvloop is not installed; using asyncio's own loop")
    cfg = Config.quick(args.uvloop) if args.quick else Config(use_uvloop=args.uvloop)
    overrides: dict[str, Any] = {}
    if args.reps is not None:
        overrides["reps"] = max(1, args.reps)
    if args.duration is not None:
        overrides["duration"] = args.duration
    if args.plant_workers is not None:
        overrides["plant_workers"] = max(0, args.plant_workers)
    if args.plant_slots is not None:
        overrides["plant_slots"] = max(0, args.plant_slots)
    if overrides:
        cfg = Config(**{**asdict(cfg), **overrides})
    prog = ["python", "-m", "benchmarks"] if __package__ else ["python", "benchmarks/run.py"]
    command = shlex.join([*prog, *(sys.argv[1:] if argv is None else argv)])
    results = Results(machine_info(cfg), command, asdict(cfg))
    Suite(cfg, scenarios, results).run()
    results.checks = evaluate(results, fleet_size=cfg.fleet_size, fleet_hz=cfg.fleet_hz)
    results.checks += plant.evaluate_plant(results, size=cfg.plant_size, ready_size=cfg.ready_size)
    if any(s in native.SCENARIOS for s in scenarios):
        results.checks += native.checks(results)
    m = results.machine
    machine = (
        f"machine: {m['nproc']} x {m['cpu']}, {m['implementation']} {m['python']},"
        f" {m['event_loop']}"
    )
    return print_results(results, (machine, f"command: {command}"), args.json, args.strict)


if __name__ == "__main__":
    sys.exit(main())
