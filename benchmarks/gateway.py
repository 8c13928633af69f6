"""The gateway at plant scale: ``python -m benchmarks gateway`` (``--machines N --seconds S``).

What one gateway process costs to poll ``N`` simulated machines (1,000) over FOCAS/2, the fast
group every second and the slow group every ten, publishing to OPC UA and to an MQTT broker,
against FANUC's library reading the same machines from threads. The CPU of each subject is its
process's user + system time from ``/proc/PID/stat`` (every thread of it) over a steady window
after a warm-up, divided by the window's wall time: cores.

Every process is its own:

* the fleet: ``focas-net serve --fleet N --port 0 --workers 2 --run`` (machines running their
  programs, so values change); its CPU is noted, not counted;
* the MQTT broker: ``mosquitto`` on 127.0.0.1 on a free port, for the gateway;
* each subject in turn, on the same fleet: ``gateway`` (focas_net's gateway with its OPC UA
  and MQTT sinks, ``benchmarks.gateway_run``), ``floor`` (the client floor: the same reads
  through focas_net's client in a poll loop of its own, no gateway), ``fwlib-threads`` (FANUC's
  library, a handle and a thread per machine) and ``fwlib-pool`` (the library from a pool of
  32 threads); see ``benchmarks.gateway_poll`` for the reads.

The polls completed are counted against those due over the window: a cycle that overran its
interval skipped the ticks that went by, and they show as missing polls, never as caught up.
The box's load average and CPU pressure are noted with each figure: the box may be shared.
"""

from __future__ import annotations

import argparse
import contextlib
import importlib.util
import json
import os
import queue
import shutil
import socket
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from collections.abc import Iterator, Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any, Final

from benchmarks._process import ROOT, child_env, end, log
from benchmarks.gateway_poll import FLOOR, FWLIB_POOL, FWLIB_THREADS, raise_nofile
from benchmarks.plant import cpu_pressure, tree_cpu_seconds
from benchmarks.report import (
    FOCAS,
    Check,
    Results,
    Row,
    pairwise_ratios,
    print_results,
)

GATEWAY: Final = "gateway"
SUBJECTS: Final = (GATEWAY, FLOOR, FWLIB_THREADS, FWLIB_POOL)
LIBRARY: Final[tuple[str, ...]] = (FWLIB_THREADS, FWLIB_POOL)
DEFAULT_JSON: Final = ROOT / "benchmarks" / "results" / "gateway.json"
MOSQUITTO: Final = "/usr/sbin/mosquitto"
#: The gateway's targets: under half a core, and at least 3 x less CPU than the
#: library (its cheaper way of the two); every poll due made.
GATEWAY_CORES: Final = 0.5
LIBRARY_FACTOR: Final = 3.0
POLLS_DUE: Final = 0.99


@dataclass(frozen=True, slots=True)
class Options:
    machines: int = 1000
    seconds: float = 30.0
    warmup: float = 12.0
    fast: float = 1.0
    slow: float = 10.0
    pool: int = 32
    fleet_workers: int = 2
    reps: int = 1
    subjects: tuple[str, ...] = SUBJECTS
    timeout: float = 3.0
    ready_timeout: float = 240.0
    #: The gateway's outputs: "mqtt,opcua", one of them, or "none".
    outputs: str = "mqtt,opcua"


DEFAULTS: Final = Options()


@dataclass(slots=True)
class Window:
    """One subject's steady window: its CPU, the fleet's, the polls made and due, the box."""

    subject: str
    wall: float
    cpu: float
    fleet_cpu: float
    fast: int
    fast_errors: int
    slow: int
    slow_errors: int
    skipped: int
    fast_due: float
    slow_due: float
    load: tuple[float, float]
    pressure: float | None
    error: str = ""
    extra: dict[str, float] = field(default_factory=dict)
    #: The outputs the gateway published to (its ready line's "sinks").
    sinks: str = ""
    #: The slow group's interval (s).
    slow_interval: float = 10.0
    #: When the gateway's outputs had not caught up at the start: how far behind they were.
    behind: str = ""

    @property
    def cores(self) -> float:
        return self.cpu / self.wall

    @property
    def fleet_cores(self) -> float:
        return self.fleet_cpu / self.wall


def loadavg() -> float:
    """The one-minute load average."""
    with open("/proc/loadavg", encoding="ascii") as f:
        return float(f.read().split()[0])


def free_port() -> int:
    """A port free on 127.0.0.1 now (for a program that cannot take port 0 and say which)."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port: int = s.getsockname()[1]
        return port


class Broker:
    """``mosquitto`` on 127.0.0.1 on a free port, anonymous, nothing persisted."""

    def __init__(self, directory: Path) -> None:
        self.port = free_port()
        conf = directory / "mosquitto.conf"
        conf.write_text(
            f"listener {self.port} 127.0.0.1\nallow_anonymous true\npersistence false\n",
            encoding="ascii",
        )
        self.proc = subprocess.Popen(
            [MOSQUITTO, "-c", str(conf)],
            stdin=subprocess.DEVNULL,
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )
        deadline = time.monotonic() + 10
        while True:
            with contextlib.suppress(OSError), socket.create_connection(("127.0.0.1", self.port)):
                return
            if self.proc.poll() is not None or time.monotonic() > deadline:
                self.stop()
                raise RuntimeError(f"mosquitto did not listen on port {self.port}")
            time.sleep(0.1)

    def stop(self) -> None:
        end(self.proc)


class Subject:
    """One subject's process: it prints a ``ready`` line, then its cumulative counts once a
    second (JSON lines), until its stdin closes."""

    def __init__(self, name: str, argv: list[str]) -> None:
        self.name = name
        self.proc = subprocess.Popen(
            argv,
            cwd=ROOT,
            env=child_env(),
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )
        self.lines: queue.Queue[dict[str, Any] | None] = queue.Queue()
        self.errors: list[str] = []
        threading.Thread(target=self._read, daemon=True).start()
        threading.Thread(target=self._read_errors, daemon=True).start()

    def _read(self) -> None:
        assert self.proc.stdout is not None
        for line in self.proc.stdout:
            with contextlib.suppress(ValueError):
                self.lines.put(json.loads(line))
        self.lines.put(None)

    def _read_errors(self) -> None:
        assert self.proc.stderr is not None
        for line in self.proc.stderr:
            self.errors.append(line.rstrip())
            del self.errors[:-20]

    def next(self, timeout: float) -> dict[str, Any]:
        """The next line; RuntimeError when the process ended or said nothing in time."""
        try:
            line = self.lines.get(timeout=timeout)
        except queue.Empty:
            raise RuntimeError(f"{self.name}: nothing in {timeout:g} s") from None
        if line is None:
            tail = "\n".join(self.errors[-10:])
            raise RuntimeError(f"{self.name} ended:\n{tail}")
        if line.get("event") == "failed":
            raise RuntimeError(f"{self.name} failed: {line.get('error')}")
        return line

    def counts(self, timeout: float) -> dict[str, Any]:
        while True:
            line = self.next(timeout)
            if line.get("event") == "count":
                return line

    def stop(self) -> None:
        if self.proc.poll() is None:
            with contextlib.suppress(OSError):
                assert self.proc.stdin is not None
                self.proc.stdin.close()
            try:
                self.proc.wait(15)
            except subprocess.TimeoutExpired:
                end(self.proc)


def gateway_available() -> str | None:
    """None when the gateway's poller can be imported, else why not."""
    for module in ("focas_net.gateway.poller",):
        try:
            if importlib.util.find_spec(module) is None:
                return f"{module} is not there yet"
        except ImportError as exc:
            return f"{module}: {exc}"
    return None


def library_missing() -> str | None:
    path = os.environ.get("FOCAS_NET_FWLIB")
    if not path:
        return "FOCAS_NET_FWLIB is not set (the path of FANUC's libfwlib32)"
    if not os.path.exists(path):
        return f"FOCAS_NET_FWLIB={path}: no such file"
    return None


def subject_argv(name: str, opts: Options, targets: Path, broker: Broker | None) -> list[str]:
    py = sys.executable
    times = ["--fast", str(opts.fast), "--slow", str(opts.slow), "--timeout", str(opts.timeout)]
    if name == GATEWAY:
        assert broker is not None
        return [
            py, "-m", "benchmarks.gateway_run", "--targets", str(targets),
            "--mqtt-port", str(broker.port), "--opcua-port", str(free_port()), *times,
            "--sinks", opts.outputs, "--ready-timeout", str(opts.ready_timeout),
        ]  # fmt: skip
    argv = [py, "-m", "benchmarks.gateway_poll", name, "--targets", str(targets), *times]
    return [*argv, "--pool", str(opts.pool)] if name == FWLIB_POOL else argv


def measure(name: str, argv: list[str], opts: Options, fleet_pid: int) -> Window:
    """Start ``name``, wait until it is ready and warm, and measure one steady window."""
    log(f"{name}: starting ({opts.machines} machines)")
    subject = Subject(name, argv)
    try:
        started = time.monotonic()
        announced = subject.next(opts.ready_timeout + 30)
        while announced.get("event") != "ready":
            announced = subject.next(opts.ready_timeout + 30)
        ready = time.monotonic()
        log(f"{name}: ready in {ready - started:.1f} s; warm-up {opts.warmup:g} s")
        wait = 2 * opts.fast + 10
        first = subject.counts(wait)
        while first["t"] < ready + opts.warmup:
            first = subject.counts(wait)
        cpu0, fleet0 = tree_cpu_seconds(subject.proc.pid), tree_cpu_seconds(fleet_pid)
        load0 = loadavg()
        last = subject.counts(wait)
        while last["t"] - first["t"] < opts.seconds - 0.5 * opts.fast:
            last = subject.counts(wait)
        cpu = tree_cpu_seconds(subject.proc.pid) - cpu0
        fleet = tree_cpu_seconds(fleet_pid) - fleet0
        wall = float(last["t"] - first["t"])

        def delta(key: str) -> int:
            return int(last[key]) - int(first[key])

        window = Window(
            name, wall, cpu, fleet,
            delta("fast"), delta("fast_errors"), delta("slow"), delta("slow_errors"),
            delta("skipped"),
            opts.machines * wall / opts.fast, opts.machines * wall / opts.slow,
            (load0, loadavg()), cpu_pressure(), str(last.get("error", "")),
            {k[2:]: float(v) - float(first[k]) for k, v in last.items() if k.startswith("x_")},
            str(announced.get("sinks", "")), opts.slow, str(announced.get("behind", "")),
        )  # fmt: skip
        log(
            f"{name}: {window.cores:.3f} core over {wall:.1f} s, fast {window.fast}/"
            f"{window.fast_due:.0f}, slow {window.slow}/{window.slow_due:.0f}, load "
            f"{window.load[0]:.2f}..{window.load[1]:.2f}"
        )
        return window
    finally:
        subject.stop()


def _note(windows: list[Window]) -> str:
    w = windows[-1] if len(windows) == 1 else None
    fast = sum(x.fast for x in windows)
    fast_due = sum(x.fast_due for x in windows)
    slow = sum(x.slow for x in windows)
    slow_due = sum(x.slow_due for x in windows)
    errors = sum(x.fast_errors + x.slow_errors for x in windows)
    skipped = sum(x.skipped for x in windows)
    loads = [v for x in windows for v in x.load]
    fleet = statistics.median(x.fleet_cores for x in windows)
    cpu = sum(x.cpu for x in windows)
    text = (
        f"{1e6 * cpu / max(1, fast):,.0f} us per machine and fast cycle; "
        f"fast {fast:,}/{fast_due:,.0f} ({fast / fast_due:.1%}), slow {slow:,}/{slow_due:,.0f}, "
        f"{errors} errors, {skipped} skipped; fleet {fleet:.2f} core; load "
        f"{min(loads):.2f}..{max(loads):.2f}"
    )
    pressures = [x.pressure for x in windows if x.pressure is not None]
    if pressures:
        text += f", CPU pressure {statistics.median(pressures):.0%}"
    if w is not None and w.sinks:
        rates = f"{w.extra.get('samples', 0) / w.wall:,.0f} samples/s"
        rates += f", {w.extra.get('turns', 0) / w.wall:,.1f} poller turns/s"
        if "mqtt" in w.sinks:
            rates += f", {w.extra.get('published', 0) / w.wall:,.0f} MQTT messages/s"
            rates += f" ({w.extra.get('dropped', 0):,.0f} dropped)"
        text = f"outputs: {w.sinks}; {rates}; " + text
    if w is not None and w.behind:
        text += f"; the outputs behind at the start ({w.behind})"
    if w is not None and w.error:
        text += f"; first error: {w.error}"
    return text


def rows(windows: dict[str, list[Window]]) -> list[Row]:
    """One row per subject: cores, with the ratio to the library's cheaper way (the gateway's
    and the floor's) and to the floor (the gateway's, in the note)."""
    out: list[Row] = []
    library = [s for s in LIBRARY if s in windows]
    best = (
        min(library, key=lambda s: statistics.median(w.cores for w in windows[s]))
        if library
        else None
    )
    for name, measured in windows.items():
        cores = [w.cores for w in measured]
        note = _note(measured)
        ratio_to = None
        ratios = None
        if best is not None and name not in LIBRARY:
            ratio_to = best
            ratios = pairwise_ratios(cores, [w.cores for w in windows[best]])
        if name == GATEWAY and FLOOR in windows:
            over = statistics.median(pairwise_ratios(cores, [w.cores for w in windows[FLOOR]]))
            note = f"{over:.2f} x the client floor; " + note
        subject = FOCAS if name in (GATEWAY, FLOOR) else name
        out.append(
            Row(
                f"gateway_{name.replace('-', '_')}" if name != GATEWAY else "gateway",
                subject,
                "cores",
                cores,
                ratio_to,
                ratios,
                note,
                extra={
                    "fast": sum(w.fast for w in measured),
                    "fast_due": sum(w.fast_due for w in measured),
                    "slow": sum(w.slow for w in measured),
                    "slow_due": sum(w.slow_due for w in measured),
                    "errors": sum(w.fast_errors + w.slow_errors for w in measured),
                    "skipped": sum(w.skipped for w in measured),
                    "fleet_cores": statistics.median(w.fleet_cores for w in measured),
                    "load_max": max(v for w in measured for v in w.load),
                },
            )
        )
    return out


def checks(windows: dict[str, list[Window]]) -> list[Check]:
    """The gateway's targets, and every subject's polls made."""
    out: list[Check] = []
    gateway = windows.get(GATEWAY)
    label = f"gateway <= {GATEWAY_CORES:g} core, at {POLLS_DUE:.0%} of its polls"
    if gateway is None:
        out.append(Check(label, None, "not measured"))
    else:
        cores = statistics.median(w.cores for w in gateway)
        made = sum(w.fast for w in gateway) / sum(w.fast_due for w in gateway)
        # a gateway that falls behind uses less CPU than one that keeps up: no pass then
        ok = cores <= GATEWAY_CORES and made >= POLLS_DUE
        detail = f"{cores:.3f} core" + ("" if made >= POLLS_DUE else f" at {made:.1%} of its polls")
        out.append(Check(label, ok, detail))
    label = f"gateway >= {LIBRARY_FACTOR:g} x less CPU than FANUC's library (its cheaper way)"
    library = {s: statistics.median(w.cores for w in windows[s]) for s in LIBRARY if s in windows}
    if gateway is None or not library:
        out.append(Check(label, None, "not measured"))
    else:
        cores = statistics.median(w.cores for w in gateway)
        name, least = min(library.items(), key=lambda kv: kv[1])
        factor = least / cores if cores else float("inf")
        out.append(Check(label, factor >= LIBRARY_FACTOR, f"{factor:.2f} x ({name})"))
    for name, measured in windows.items():
        made = sum(w.fast for w in measured)
        due = sum(w.fast_due for w in measured)
        skipped = sum(w.skipped for w in measured)
        errors = sum(w.fast_errors + w.slow_errors for w in measured)
        dropped = sum(w.extra.get("dropped", 0) for w in measured)
        slow_due = sum(w.slow_due for w in measured)
        slow = sum(w.slow for w in measured) / max(1.0, slow_due)
        # a gateway starts a machine's slow group all at once: only whole slow intervals count
        whole = all(w.wall >= w.slow_interval for w in measured)
        ok = made >= POLLS_DUE * due and skipped == 0 and errors == 0 and dropped == 0
        ok = ok and (slow >= POLLS_DUE or not whole)
        out.append(
            Check(
                f"{name}: >= {POLLS_DUE:.0%} of the polls due, no cycle overrun, no error",
                ok,
                f"fast {made / due:.1%}, slow {slow:.1%}{'' if whole else ' (window < slow)'}, "
                f"{skipped} skipped, {errors} errors"
                + (f", {dropped:,.0f} MQTT messages dropped" if dropped else ""),
            )
        )
    return out


@contextlib.contextmanager
def fleet(opts: Options) -> Iterator[tuple[int, list[tuple[str, int]]]]:
    """``focas-net serve --fleet N --workers W --run`` on ephemeral ports: its pid and the
    machines' addresses."""
    from benchmarks.run import ServerProcess
    from benchmarks.subjects import server_argv

    extra = ["--fleet", str(opts.machines), "--run", "--max-connections", "8"]
    if opts.fleet_workers > 1 and opts.machines > 1:
        extra += ["--workers", str(min(opts.fleet_workers, opts.machines))]
    log(f"fleet: serve {' '.join(extra)}")
    server = ServerProcess(FOCAS, server_argv(FOCAS, use_uvloop=False, extra=tuple(extra)))
    try:
        server.wait_ready(opts.machines, timeout=opts.ready_timeout, settle=opts.ready_timeout)
        if len(server.endpoints) < opts.machines:
            raise RuntimeError(f"the fleet announced {len(server.endpoints)} of {opts.machines}")
        yield server.pid, list(server.endpoints)
    finally:
        server.stop()


def run(opts: Options, results: Results) -> dict[str, list[Window]]:
    """Every subject asked for, in turn (the order alternating between repetitions), on one
    fleet; the windows measured by subject."""
    wanted: list[str] = []
    for name in opts.subjects:
        why = gateway_available() if name == GATEWAY else None
        if name in LIBRARY:
            why = library_missing()
        if name == GATEWAY and why is None and not os.path.exists(MOSQUITTO):
            why = f"{MOSQUITTO} is not installed"
        if why is None:
            wanted.append(name)
        else:
            results.skipped.append(f"{name} skipped: {why}")
            log(f"{name} skipped: {why}")
    windows: dict[str, list[Window]] = {}
    with tempfile.TemporaryDirectory(prefix="focas-gateway-bench-") as tmp:
        directory = Path(tmp)
        with fleet(opts) as (fleet_pid, endpoints):
            targets = directory / "targets.json"
            targets.write_text(json.dumps(endpoints), encoding="utf-8")
            for rep in range(opts.reps):
                for name in wanted if rep % 2 == 0 else wanted[::-1]:
                    broker = Broker(directory) if name == GATEWAY else None
                    try:
                        argv = subject_argv(name, opts, targets, broker)
                        window = measure(name, argv, opts, fleet_pid)
                        windows.setdefault(name, []).append(window)
                    except RuntimeError as exc:
                        results.skipped.append(f"{name} failed: {exc}")
                        log(f"{name} failed: {exc}")
                    finally:
                        if broker is not None:
                            broker.stop()
    return {name: windows[name] for name in wanted if name in windows}


def parse_args(argv: Sequence[str] | None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(
        prog="python -m benchmarks gateway",
        description="CPU of one gateway process polling a simulated fleet, against FANUC's "
        "library from threads.",
    )
    parser.add_argument("--machines", type=int, default=DEFAULTS.machines, metavar="N")
    parser.add_argument(
        "--seconds", type=float, default=DEFAULTS.seconds, metavar="S", help="steady window"
    )
    parser.add_argument("--warmup", type=float, default=DEFAULTS.warmup, metavar="S")
    parser.add_argument("--fast", type=float, default=DEFAULTS.fast, metavar="S")
    parser.add_argument("--slow", type=float, default=DEFAULTS.slow, metavar="S")
    parser.add_argument("--pool", type=int, default=DEFAULTS.pool, metavar="N")
    parser.add_argument("--fleet-workers", type=int, default=DEFAULTS.fleet_workers, metavar="N")
    parser.add_argument("--reps", type=int, default=DEFAULTS.reps, metavar="N")
    parser.add_argument(
        "--only", default=",".join(SUBJECTS), help=f"subset of {','.join(SUBJECTS)}"
    )
    parser.add_argument(
        "--outputs",
        default=DEFAULTS.outputs,
        help="the gateway's outputs: mqtt,opcua (default), mqtt, opcua or none",
    )
    parser.add_argument(
        "--ready-timeout",
        type=float,
        default=DEFAULTS.ready_timeout,
        metavar="S",
        help="seconds a subject may take to connect every machine (and the gateway's outputs "
        "to take them in)",
    )
    parser.add_argument("--json", type=Path, default=DEFAULT_JSON, metavar="PATH")
    parser.add_argument("--strict", action="store_true", help="exit 1 when a target fails")
    return parser.parse_args(argv)


def main(argv: Sequence[str] | None = None) -> int:
    from benchmarks.run import Config, machine_info

    args = parse_args(argv)
    subjects = tuple(s.strip() for s in args.only.split(",") if s.strip())
    unknown = sorted(set(subjects) - set(SUBJECTS))
    if unknown or args.machines < 1 or args.seconds <= 0:
        log(f"unknown subjects {unknown} or bad sizes (known: {', '.join(SUBJECTS)})")
        return 2
    opts = Options(
        machines=args.machines,
        seconds=args.seconds,
        warmup=args.warmup,
        fast=args.fast,
        slow=args.slow,
        pool=args.pool,
        fleet_workers=args.fleet_workers,
        reps=max(1, args.reps),
        subjects=subjects,
        ready_timeout=args.ready_timeout,
        outputs=args.outputs,
    )
    nofile = raise_nofile()
    command = " ".join(["python -m benchmarks gateway", *(sys.argv[2:] if argv is None else argv)])
    results = Results(machine_info(Config()), command, asdict(opts))
    windows = run(opts, results)
    results.rows = rows(windows)
    results.checks = checks(windows)
    m = results.machine
    header = (
        f"machine: {m['nproc']} x {m['cpu']}, {m['implementation']} {m['python']}",
        f"command: {command}  (open files {nofile}, mosquitto {shutil.which(MOSQUITTO)})",
    )
    return print_results(results, header, args.json, args.strict)


if __name__ == "__main__":
    sys.exit(main())
