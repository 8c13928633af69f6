"""``focas-net serve --workers N``: one fleet served by N worker processes.

The fleet's machines are cut into N contiguous slices, sizes differing by at most one; worker
``k`` serves its slice on the ports of those machines (``--port`` + the slice's first index,
or ephemeral ports with ``--port 0``), with the same options otherwise, and builds each
machine from its index in the whole fleet, so machine ``i`` is the same machine whatever N.

The parent starts the workers (``python -c`` running :func:`worker_main`, ``serve``'s entry
point and the options sent as a pickle on the worker's standard input, which stays open; the
machines are built by :mod:`._fleet`, in the parent's probe and in each worker), waits until
every worker printed all its ready lines, prints them in port order (every machine's line, then
every native-only line, as one process would) and then:

* SIGINT or SIGTERM: sends SIGTERM to every worker, waits for them all, exits 0 when they
  all stopped cleanly;
* a worker that exits on its own: stops the others, prints which worker and how it ended,
  and exits 1 (or the worker's own exit code if it failed before it was ready).

The workers run in sessions of their own, so that a terminal's Ctrl-C (SIGINT to the whole
foreground process group) reaches the parent alone and each worker gets one SIGTERM. A worker
whose standard input reaches end of file (the parent is gone, however it ended) stops itself,
so no worker outlives its parent.
"""

from __future__ import annotations

import argparse
import copy
import os
import pickle
import queue
import signal
import subprocess
import sys
import threading
from collections.abc import Callable
from dataclasses import dataclass
from typing import IO, Final

from ._args import EXIT_CNC, PROG, print_error
from ._fleet import build_machines, fleet_slices
from ._signals import on_first_signal

__all__ = ["MAX_WORKERS", "Serve", "run_workers", "worker_args", "worker_main"]

#: Most worker processes one ``serve --workers`` starts.
MAX_WORKERS: Final = 64
_ERROR_PREFIX: Final = f"{PROG} serve: error"
_NATIVE_MARK: Final = "(native FOCAS/2"
#: How long a stopping worker may take before it is killed (seconds): past the server's
#: grace period for answers in flight.
_KILL_AFTER: Final = 10.0
_WORKER_CODE: Final = (
    "import sys; from focas_net.cli._workers import worker_main; sys.exit(worker_main())"
)
#: What a worker runs with its options: ``serve``'s entry point, which starts no workers
#: itself for options of one slice.
Serve = Callable[[argparse.Namespace], int]


def worker_args(args: argparse.Namespace, served: range) -> argparse.Namespace:
    """The options of the worker serving the machines ``served``."""
    mine = copy.copy(args)
    mine.workers = 1
    mine.fleet_slice = served
    if args.port:
        mine.port = args.port + served.start
    if args.native_port:
        mine.native_port = args.native_port + served.start
    return mine


def worker_main() -> int:
    """A worker process: read what to run and its options from standard input, serve its
    slice until SIGINT or SIGTERM, or until standard input ends (the parent is gone)."""
    # written by run_workers: the same program's serve function and options
    serve, args = pickle.load(sys.stdin.buffer)

    def watch_parent() -> None:
        # The file descriptor itself, not sys.stdin: a daemon thread must hold no lock of a
        # buffered stream the interpreter closes at exit.
        while os.read(0, 4096):
            pass
        os.kill(os.getpid(), signal.SIGTERM)

    threading.Thread(target=watch_parent, name="parent-watch", daemon=True).start()
    code: int = serve(args)
    return code


class _Flag:
    """Stopping: set from a signal handler too, so no lock (``threading.Event.set`` takes
    one, and a handler run while the main thread holds it would wait for ever)."""

    __slots__ = ("_set",)

    def __init__(self) -> None:
        self._set = False

    def set(self) -> None:
        self._set = True

    def is_set(self) -> bool:
        return self._set


@dataclass(slots=True)
class _Worker:
    index: int
    served: range
    proc: subprocess.Popen[bytes]
    expected: int
    lines: list[str]
    #: SIGTERM sent (once: a second one would cut its shutdown short).
    signalled: bool = False

    def describe(self) -> str:
        first, last = self.served.start + 1, self.served.stop
        machines = f"machine {first}" if first == last else f"machines {first}..{last}"
        return f"worker {self.index + 1} ({machines}, pid {self.proc.pid})"


def _exit_text(code: int) -> str:
    if code < 0:
        try:
            return f"was killed by {signal.Signals(-code).name}"
        except ValueError:
            return f"was killed by signal {-code}"
    return f"exited with code {code}"


def _pump(worker: int, stream: IO[bytes], events: queue.Queue[tuple[int, str | None]]) -> None:
    """Each line of a worker's standard output, then None at its end."""
    for raw in stream:
        events.put((worker, raw.decode("utf-8", "replace").rstrip("\n")))
    events.put((worker, None))


def run_workers(args: argparse.Namespace, serve: Serve) -> int:
    """Serve the fleet of ``args`` over ``args.workers`` processes; returns the exit code.
    Each worker runs ``serve`` (a module-level function, sent by name) with the options of its
    slice.

    The first machine is built here first, so that a bad machine file (or a ``--run`` the
    machine refuses) is reported once, as ``serve``'s own ConfigError, before any worker
    starts."""
    probe = copy.copy(args)
    probe.fleet_slice = range(1)
    build_machines(probe)
    slices = fleet_slices(args.fleet, args.workers)
    events: queue.Queue[tuple[int, str | None]] = queue.Queue()
    workers: list[_Worker] = []
    stopping = _Flag()

    def stop_all() -> None:
        for w in workers:
            if not w.signalled and w.proc.poll() is None:
                w.signalled = True
                try:
                    w.proc.send_signal(signal.SIGTERM)
                except ProcessLookupError:  # pragma: no cover - exited meanwhile
                    pass

    def on_signal() -> None:  # in the signal handler: it takes no lock (see ._signals)
        stopping.set()
        stop_all()

    with on_first_signal(on_signal):
        return _start_and_supervise(args, serve, slices, workers, events, stopping, stop_all)


def _start_and_supervise(
    args: argparse.Namespace,
    serve: Serve,
    slices: list[range],
    workers: list[_Worker],
    events: queue.Queue[tuple[int, str | None]],
    stopping: _Flag,
    stop_all: Callable[[], None],
) -> int:
    per_machine = 2 if args.native_port is not None else 1
    try:
        for k, served in enumerate(slices):
            if stopping.is_set():
                break
            proc = subprocess.Popen(
                [sys.executable, "-c", _WORKER_CODE],
                stdin=subprocess.PIPE,
                stdout=subprocess.PIPE,
                # Its own session: a terminal's Ctrl-C reaches the parent alone, which passes
                # one SIGTERM on (a second signal would cut the worker's shutdown short).
                start_new_session=True,
            )
            workers.append(_Worker(k, served, proc, per_machine * len(served), []))
            assert proc.stdin is not None and proc.stdout is not None
            try:
                proc.stdin.write(pickle.dumps((serve, worker_args(args, served))))
                proc.stdin.flush()
            except OSError:  # it died already: its end of output tells
                pass
            threading.Thread(
                target=_pump, args=(k, proc.stdout, events), name=f"worker-{k + 1}", daemon=True
            ).start()
        return _supervise(workers, events, stopping, stop_all)
    finally:
        stop_all()
        for w in workers:
            _reap(w)


def _reap(worker: _Worker) -> None:
    try:
        worker.proc.wait(_KILL_AFTER)
    except subprocess.TimeoutExpired:
        worker.proc.kill()
        worker.proc.wait()
    if worker.proc.stdin is not None:
        try:
            worker.proc.stdin.close()
        except OSError:  # pragma: no cover - a broken pipe to a dead worker
            pass


def _supervise(
    workers: list[_Worker],
    events: queue.Queue[tuple[int, str | None]],
    stopping: _Flag,
    stop_all: Callable[[], None],
) -> int:
    """Print the ready lines once all are in, then wait for the workers to end."""
    waiting = sum(w.expected for w in workers)
    announced = False
    running = len(workers)
    failure: int | None = None
    while running:
        try:
            k, line = events.get(timeout=0.2)
        except queue.Empty:
            continue
        worker = workers[k]
        if line is not None:
            if announced or len(worker.lines) >= worker.expected:
                sys.stdout.write(f"{line}\n")  # anything a worker prints past its ready lines
                sys.stdout.flush()
                continue
            worker.lines.append(line)
            waiting -= 1
            if waiting == 0 and not stopping.is_set():
                _announce(workers)
                announced = True
            continue
        running -= 1
        code = worker.proc.wait()
        if stopping.is_set() or failure is not None:
            if code != 0 and failure is None and announced:
                failure = EXIT_CNC
                print_error(f"{worker.describe()} {_exit_text(code)} while stopping", _ERROR_PREFIX)
            continue
        failure = code if not announced and code > 0 else EXIT_CNC
        how = "before it was ready" if not announced else "while serving"
        print_error(
            f"{worker.describe()} {_exit_text(code)} {how}; stopping the other workers",
            _ERROR_PREFIX,
        )
        stopping.set()
        stop_all()
    return 0 if failure is None else failure


def _announce(workers: list[_Worker]) -> None:
    """Every worker's machine lines in port order, then every native-only line."""
    main = [line for w in workers for line in w.lines if _NATIVE_MARK not in line]
    native = [line for w in workers for line in w.lines if _NATIVE_MARK in line]
    sys.stdout.write("".join(f"{line}\n" for line in (*main, *native)))
    sys.stdout.flush()
