"""Native FOCAS/2: :class:`~focas_net.client.NativeClient` against FANUC's library and pyfocas.

The server is ``focas-net serve`` in its own process (FOCAS/2 on the same port as the packed
protocol); each subject's client runs in a worker process of its own (``benchmarks.worker``,
ops ``native_*`` below), like the packed suite's. Subjects:

* ``native_client``: :class:`~focas_net.client.NativeClient`, asyncio;
* ``fwlib``: FANUC's library (``FOCAS_NET_FWLIB``) through :mod:`ctypes`, one handle opened
  with ``cnc_allclibhndl3`` and every call on that handle. A handle belongs to the thread that
  opened it (another thread gets EW_HANDLE), so "64 concurrent callers on one handle" are the
  same sequential calls: the handle can carry one call at a time from one thread;
* ``pyfocas``: pyfocas (pure Python, blocking sockets), one ``FOCAS`` object; its 64
  concurrent callers are 64 threads taking turns on it behind a lock (it is not thread-safe).
  pyfocas has ``read_macro`` and ``get_status_info`` but no ``cnc_rddynamic2``: it takes part
  in the status poll, not in the ``cnc_rddynamic2`` one;
* ``asyncio_floor``: the least an asyncio client of these frames costs per call
  (:class:`FloorProtocol`): one connection opened as pyfocas opens it and read and written as
  the native client reads and writes its own (``focas_net.client._channel``), the call's
  request frame built once, and per call one write and one future completed by the answer taken as a
  whole frame, nothing decoded. It is the bound the event loop itself sets on a sequential
  asyncio client, measured beside the others. In ``native_pipe64`` its 64 callers queue one
  block each and frames of up to ten leave one at a time (:class:`PipeFloorProtocol`): no
  deadline, no check, nothing decoded, the bound on a pipelined asyncio client of FOCAS/2.

Scenarios: ``native_seq`` (sequential ``read_macro`` and ``read_status``: calls per second),
``native_pipe64`` (64 concurrent ``read_macro`` on one connection) and ``native_poll100``
(100 machines of ``serve --fleet 100``, each read at 10 Hz: the client process's CPU per poll;
rows ``native_poll100`` with ``cnc_rddynamic2``, the library and focas_net, and
``native_poll100_status`` with ``cnc_statinfo``, the call all three subjects have, which is the
like-for-like comparison with pyfocas).
"""

from __future__ import annotations

import asyncio
import ctypes
import importlib.util
import os
import statistics
import struct
import sys
import threading
import time
from collections.abc import Awaitable, Callable, Iterator, Sequence
from functools import partial
from typing import TYPE_CHECKING, Any, Final, cast

from benchmarks.report import FOCAS, Check, Results, Row, pairwise_ratios

if TYPE_CHECKING:
    from benchmarks.run import Suite, WorkerProcess
    from focas_net.client._channel import Channel
    from focas_net.native.calls import LibraryCall

NATIVE: Final = "native_client"
FWLIB: Final = "fwlib"
PYFOCAS: Final = "pyfocas"
FLOOR: Final = "asyncio_floor"
SUBJECTS: Final = (NATIVE, FWLIB, PYFOCAS, FLOOR)
SCENARIOS: Final = ("native_seq", "native_pipe64", "native_poll100")
#: The calls of ``native_seq``: the row name's suffix and the call.
SEQ_CALLS: Final = (("macro", "read_macro"), ("status", "read_status"))
CALLERS: Final = 64
FLEET: Final = 100
POLL_HZ: Final = 10.0
#: The macro variable read (written once before the runs: pyfocas cannot read a vacant one).
MACRO: Final = 100
MACRO_VALUE: Final = "12.5"
#: The polls of ``native_poll100``: the row name and the call. pyfocas has no
#: ``cnc_rddynamic2``, so it takes part in the status poll only.
POLL_CALLS: Final = (("native_poll100", "read_dynamic"), ("native_poll100_status", "read_status"))
#: The rows of the "ahead of pyfocas" targets: each mode, with the call pyfocas has.
PYFOCAS_MODES: Final = (
    "native_seq_macro",
    "native_seq_status",
    "native_pipe64",
    "native_poll100_status",
)
#: Targets: pipe64 read_macro against the library, sequential calls against the library.
PIPE64_TARGET: Final = 10.0
SEQ_TARGET: Final = 0.7

_perf = time.perf_counter


def fwlib_path() -> str | None:
    return os.environ.get("FOCAS_NET_FWLIB") or None


def fwlib_missing() -> str | None:
    """None when FANUC's library can be loaded, else why not."""
    path = fwlib_path()
    if path is None:
        return "FOCAS_NET_FWLIB is not set (the path of FANUC's libfwlib32)"
    if not os.path.exists(path):
        return f"FOCAS_NET_FWLIB={path}: no such file"
    return None


def pyfocas_missing() -> str | None:
    """None when pyfocas is installed, else why not."""
    if importlib.util.find_spec("pyfocas") is None:
        return "pyfocas is not installed (pip install focas-net[bench])"
    return None


# -- the subjects' clients, in the worker process ---------------------------------------------


class _Library:
    """FANUC's library, loaded and started once per process; every function returns a C
    ``short`` (the EW code)."""

    _lib: Any = None

    @classmethod
    def get(cls) -> Any:
        if cls._lib is None:
            path = fwlib_path()
            if path is None:
                raise RuntimeError("FOCAS_NET_FWLIB is not set")
            lib = ctypes.cdll.LoadLibrary(path)
            for name in (
                "cnc_startupprocess",
                "cnc_allclibhndl3",
                "cnc_freelibhndl",
                "cnc_rdmacro",
                "cnc_statinfo",
                "cnc_rddynamic2",
            ):
                getattr(lib, name).restype = ctypes.c_short
            lib.cnc_startupprocess(0, b"/dev/null")
            cls._lib = lib
        return cls._lib


#: Bytes of ``cnc_rddynamic2``'s answer for every axis: the head and 16 bytes per axis at
#: FANUC's header's MAX_AXIS (32), the max axes a 30i-class control reports.
_DYNAMIC_SIZE = 28 + 16 * 32


class FwlibHandle:
    """One handle of FANUC's library, used only from the thread that opened it."""

    def __init__(self, host: str, port: int) -> None:
        self.lib = _Library.get()
        handle = ctypes.c_ushort()
        rc = self.lib.cnc_allclibhndl3(
            host.encode(), ctypes.c_ushort(port), ctypes.c_int32(10), ctypes.byref(handle)
        )
        if rc != 0:
            raise RuntimeError(f"cnc_allclibhndl3 to {host}:{port} returned {rc}")
        self.handle = handle
        self._macro = ctypes.create_string_buffer(16)
        self._stat = ctypes.create_string_buffer(64)
        #: ODBDY2 as FANUC's header declares it (MAX_AXIS 32): the size programs pass.
        self._dynamic = ctypes.create_string_buffer(_DYNAMIC_SIZE)

    def _check(self, rc: int, name: str) -> None:
        if rc != 0:
            raise RuntimeError(f"{name} returned {rc}")

    def read_macro(self) -> None:
        rc = self.lib.cnc_rdmacro(
            self.handle, ctypes.c_short(MACRO), ctypes.c_short(10), self._macro
        )
        self._check(rc, "cnc_rdmacro")

    def read_status(self) -> None:
        self._check(self.lib.cnc_statinfo(self.handle, self._stat), "cnc_statinfo")

    def read_dynamic(self) -> None:
        rc = self.lib.cnc_rddynamic2(
            self.handle, ctypes.c_short(-1), ctypes.c_short(_DYNAMIC_SIZE), self._dynamic
        )
        self._check(rc, "cnc_rddynamic2")

    def close(self) -> None:
        self.lib.cnc_freelibhndl(self.handle)


class PyfocasConn:
    """One pyfocas connection."""

    def __init__(self, host: str, port: int) -> None:
        from pyfocas.protocol.protocol import FOCAS

        self.client = FOCAS(host, port)
        if not self.client.connect():
            raise RuntimeError(f"pyfocas could not connect to {host}:{port}")

    def read_macro(self) -> None:
        if MACRO not in self.client.read_macro(MACRO):
            raise RuntimeError(f"pyfocas read_macro({MACRO}) gave no value")

    def read_status(self) -> None:
        self.client.get_status_info()

    def close(self) -> None:
        if self.client.socket is not None:
            self.client.socket.close()


class FloorProtocol(asyncio.Protocol):
    """The asyncio floor's connection: each answer, taken as one whole frame (its 10-byte
    header's length word), completes the one call waiting. It reads and writes through the
    native client's own connections (:func:`_floor_connect`)."""

    def __init__(self) -> None:
        self.transport: asyncio.Transport | Channel | None = None
        self.waiter: asyncio.Future[bytes] | None = None
        self.buffer = bytearray()

    def connection_made(self, transport: asyncio.BaseTransport) -> None:
        # a stream transport (uvloop's is not a subclass of asyncio.Transport)
        self.transport = cast(asyncio.Transport, transport)

    def data_received(self, data: bytes) -> None:
        buffer = self.buffer
        if not buffer and len(data) >= 10 and len(data) == 10 + int.from_bytes(data[8:10]):
            self._answer(data)
            return
        buffer += data
        while len(buffer) >= 10:
            size = 10 + int.from_bytes(buffer[8:10])
            if len(buffer) < size:
                break
            self._answer(bytes(buffer[:size]))
            del buffer[:size]

    def _answer(self, frame: bytes) -> None:
        waiter, self.waiter = self.waiter, None
        if waiter is not None and not waiter.done():
            waiter.set_result(frame)

    def connection_lost(self, exc: Exception | None) -> None:
        waiter, self.waiter = self.waiter, None
        if waiter is not None and not waiter.done():
            waiter.set_exception(ConnectionError(f"connection lost: {exc}"))

    async def call(self, frame: bytes) -> bytes:
        assert self.transport is not None
        waiter: asyncio.Future[bytes] = asyncio.get_running_loop().create_future()
        self.waiter = waiter
        self.transport.write(frame)
        return await waiter


class PipeFloorProtocol(FloorProtocol):
    """The asyncio floor's pipelined connection: callers queue one block each; at the end of
    the loop turn, and after each answer, the blocks waiting leave in one frame of at most
    :data:`FLOOR_MAX_BLOCKS` (one frame in flight, as FOCAS/2 allows); each answer block (its
    length word) completes its caller, nothing decoded."""

    def __init__(self) -> None:
        super().__init__()
        self.queue: list[tuple[bytes, asyncio.Future[bytes]]] = []
        self.inflight: list[tuple[bytes, asyncio.Future[bytes]]] | None = None
        self.soon = False
        self.loop = asyncio.get_running_loop()
        self.version = 0  # the request frames' version word, set once connected

    def block(self, block: bytes) -> asyncio.Future[bytes]:
        future = self.loop.create_future()
        self.queue.append((block, future))
        if self.inflight is None and not self.soon:
            self.soon = True
            self.loop.call_soon(self.kick)
        return future

    def kick(self) -> None:
        self.soon = False
        if self.inflight is not None or not self.queue:
            return
        batch = self.queue[:FLOOR_MAX_BLOCKS]
        del self.queue[:FLOOR_MAX_BLOCKS]
        body = b"".join([block for block, _ in batch])
        head = _FLOOR_HEAD.pack(0xA0A0A0A0, self.version, 0x2101, 2 + len(body), len(batch))
        assert self.transport is not None
        self.transport.write(head + body)
        self.inflight = batch

    def _answer(self, frame: bytes) -> None:
        batch, self.inflight = self.inflight, None
        if batch is None:  # the open answer
            super()._answer(frame)
            return
        self.kick()
        pos = 12  # the header, then the block count
        for _, future in batch:
            end = pos + int.from_bytes(frame[pos : pos + 2])
            future.set_result(frame[pos:end])
            pos = end


#: Most blocks a frame of the pipelined floor carries (as many as FANUC's library sends).
FLOOR_MAX_BLOCKS: Final = 10
_FLOOR_HEAD: Final = struct.Struct(">IHHHH")


async def _floor_connect(proto: FloorProtocol, host: str, port: int) -> Channel:
    """``proto`` connected to ``host``:``port`` on the connection the native client would
    open on this loop (its own socket on asyncio's selector loop, the loop's transport on
    uvloop): the floor leaves out the client's work, not what its I/O costs."""
    from focas_net.client._channel import open_channel

    channel = await open_channel(host, port)
    proto.transport = channel
    channel.start(proto.data_received, proto.connection_lost)
    return channel


async def floor_pipe_run(
    host: str, port: int, call: str, callers: int, duration: float
) -> dict[str, float]:
    """The asyncio floor with ``callers`` concurrent callers of ``call`` on one connection
    (:class:`PipeFloorProtocol`), as :func:`native_run` makes them."""
    from focas_net.native import CLIENT_VERSION

    proto = PipeFloorProtocol()
    transport = await _floor_connect(proto, host, port)
    proto.version = CLIENT_VERSION
    try:
        library = await _floor_open(proto, call)
        (frame,) = library.encode()
        block = frame[12:]
        if int.from_bytes(frame[10:12]) != 1:
            raise RuntimeError(f"{library.function} is not one block")
        answer = await proto.block(block)
        if int.from_bytes(answer[8:10]) != 0:  # the block's EW code
            raise RuntimeError(f"{library.function} answered {answer!r}")
        return await _callers_timed(callers, duration, proto.block, block)
    finally:
        transport.close()


async def _floor_open(proto: FloorProtocol, call: str) -> LibraryCall:
    """Open the floor's connection ``proto`` (as pyfocas opens one); the library call of
    ``call`` in the command set the open answer picks."""
    from focas_net.native import CommandSet, FrameType, calls, decode_frame, encode_open_request

    opened = decode_frame(await proto.call(encode_open_request(2)))
    if opened.type != FrameType.OPEN_RESPONSE:
        raise RuntimeError(f"open answered with type 0x{opened.type:04X}")
    cs = CommandSet.for_version(opened.version)
    return calls.cnc_rdmacro(cs, MACRO) if call == "read_macro" else calls.cnc_statinfo(cs)


async def _callers_timed(
    callers: int, duration: float, fn: Callable[..., Awaitable[object]], *args: object
) -> dict[str, float]:
    """``callers`` coroutines each awaiting ``fn(*args)`` again and again for ``duration``
    seconds, at least once each however late they start (the same loop for every asyncio
    subject): the calls made, the wall time and the process's CPU time."""
    counts: list[int] = []
    deadline = _perf() + duration

    async def caller() -> None:
        n = 0
        while not n or _perf() < deadline:
            await fn(*args)
            n += 1
        counts.append(n)

    cpu = time.process_time()
    start = _perf()
    await asyncio.gather(*(caller() for _ in range(callers)))
    elapsed = _perf() - start
    return {"ops": sum(counts), "elapsed": elapsed, "cpu": time.process_time() - cpu}


async def floor_run(host: str, port: int, call: str, duration: float) -> dict[str, float]:
    """The asyncio floor: sequential calls of ``call``'s request frame, as
    :func:`native_run` makes them with one caller. The first answer is decoded and checked
    (outside the timed loop); the timed ones are not."""
    from focas_net.native import decode_frame, decode_response_body

    proto = FloorProtocol()
    transport = await _floor_connect(proto, host, port)
    try:
        library = await _floor_open(proto, call)
        (frame,) = library.encode()
        answer = decode_frame(await proto.call(frame))
        blocks = decode_response_body(answer.body)
        if len(blocks) != len(library.frames[0]) or any(b.ew for b in blocks):
            raise RuntimeError(f"{library.function} answered {blocks!r}")
        fn = proto.call
        n = 0
        deadline = _perf() + duration
        cpu = time.process_time()
        start = _perf()
        while not n or _perf() < deadline:
            await fn(frame)
            n += 1
        elapsed = _perf() - start
        cpu = time.process_time() - cpu
    finally:
        transport.close()
    return {"ops": n, "elapsed": elapsed, "cpu": cpu}


Blocking = FwlibHandle | PyfocasConn


def _blocking(subject: str, host: str, port: int) -> Blocking:
    if subject == FWLIB:
        return FwlibHandle(host, port)
    if subject == PYFOCAS:
        return PyfocasConn(host, port)
    raise ValueError(f"not a blocking subject: {subject!r}")


def _timed(run: Callable[[], int]) -> dict[str, float]:
    cpu = time.process_time()
    start = _perf()
    ops = run()
    return {"ops": ops, "elapsed": _perf() - start, "cpu": time.process_time() - cpu}


def _loop_calls(call: Callable[[], None], duration: float) -> int:
    n = 0
    deadline = _perf() + duration
    while not n or _perf() < deadline:
        call()
        n += 1
    return n


def _threads_on_one(call: Callable[[], None], callers: int, duration: float) -> int:
    """``callers`` threads calling ``call`` in turns behind one lock until the deadline."""
    lock = threading.Lock()
    counts = [0] * callers
    errors: list[BaseException] = []
    deadline = _perf() + duration

    def caller(i: int) -> None:
        try:
            while not counts[i] or _perf() < deadline:
                with lock:
                    call()
                counts[i] += 1
        except BaseException as exc:  # reported below, not lost in the thread
            errors.append(exc)

    threads = [threading.Thread(target=caller, args=(i,)) for i in range(callers)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    if errors:
        raise RuntimeError(f"{len(errors)} caller(s) failed: {errors[0]!r}")
    return sum(counts)


def blocking_run(
    subject: str, host: str, port: int, call: str, callers: int, duration: float
) -> dict[str, float]:
    """Sequential calls (``callers`` 1) or concurrent callers on one connection or handle."""
    conn = _blocking(subject, host, port)
    try:
        fn: Callable[[], None] = getattr(conn, call)
        fn()
        if callers == 1 or subject == FWLIB:  # a handle serves its own thread only
            return _timed(lambda: _loop_calls(fn, duration))
        return _timed(lambda: _threads_on_one(fn, callers, duration))
    finally:
        conn.close()


def _waits(ticks: int, interval: float) -> Iterator[float]:
    """The seconds to wait before each tick of a poll of ``ticks`` ticks, one every
    ``interval`` from now, taken as each tick's work is done (``time.monotonic``); a tick
    whose whole interval went by is skipped, not caught up."""
    t0 = time.monotonic()
    tick = 0
    while tick < ticks:
        due = t0 + tick * interval
        now = time.monotonic()
        if now >= due + interval:
            tick += int((now - due) // interval)
            continue
        yield due - now
        tick += 1


def blocking_poll(
    subject: str, targets: list[list[Any]], call: str, interval: float, duration: float
) -> dict[str, float]:
    """Every target read with ``call`` once per ``interval`` from one thread, in turn; a tick
    whose whole interval went by is skipped."""
    conns: list[Blocking] = []
    try:
        for host, port in targets:
            conns.append(_blocking(subject, str(host), int(port)))
        calls: list[Callable[[], None]] = [getattr(c, call) for c in conns]
        for fn in calls:
            fn()
        ticks = round(duration / interval)
        polls = errors = 0
        cpu0, wall0 = time.process_time(), _perf()
        for wait in _waits(ticks, interval):
            if wait > 0:
                time.sleep(wait)
            for fn in calls:
                try:
                    fn()
                    polls += 1
                except Exception:
                    errors += 1
        wall, cpu = _perf() - wall0, time.process_time() - cpu0
    finally:
        for c in conns:
            c.close()
    return {"polls": polls, "due": ticks * len(targets), "errors": errors, "wall": wall, "cpu": cpu}


async def native_run(
    host: str, port: int, call: str, callers: int, duration: float
) -> dict[str, float]:
    """:class:`NativeClient`: ``callers`` coroutines calling ``call`` on one client."""
    from focas_net.client import NativeClient

    async with NativeClient(host, port, timeout=10.0) as client:
        # called as the floor's callers call it: the method and its arguments, no wrapper
        fn: Callable[..., Awaitable[object]]
        args: tuple[int, ...]
        fn, args = (
            (client.read_macro, (MACRO,)) if call == "read_macro" else (client.read_status, ())
        )
        await fn(*args)
        frames = client.frames_sent
        result = await _callers_timed(callers, duration, fn, *args)
        result["frames"] = client.frames_sent - frames
    return result


async def native_poll(
    targets: list[list[Any]], call: str, interval: float, duration: float
) -> dict[str, float]:
    """100 :class:`NativeClient` (one per machine) read from one task once a tick, every
    ``interval`` (a tick whose whole interval went by is skipped), the schedule of the
    blocking subjects (:func:`blocking_poll` sleeps once a tick, then reads every machine in
    turn from its one thread): ``call`` ``read_status`` by
    :func:`~focas_net.client.read_status_all`, ``read_dynamic`` by
    :func:`~focas_net.client.read_dynamic_all`, every machine's request sent before any
    answer is awaited."""
    from focas_net.client import NativeClient, read_dynamic_all, read_status_all

    clients = [NativeClient(str(h), int(p), timeout=10.0) for h, p in targets]

    async def read_all(clients: list[NativeClient]) -> Sequence[object]:
        if call == "read_status":
            return await read_status_all(clients)
        return await read_dynamic_all(clients)

    try:
        for i in range(0, len(clients), 25):
            await asyncio.gather(*(c.connect() for c in clients[i : i + 25]))
        await read_all(clients)
        ticks = round(duration / interval)
        polls = errors = 0
        cpu0, wall0 = time.process_time(), _perf()
        for wait in _waits(ticks, interval):
            if wait > 0:
                await asyncio.sleep(wait)
            for result in await read_all(clients):
                if isinstance(result, Exception):
                    errors += 1
                else:
                    polls += 1
        wall, cpu = _perf() - wall0, time.process_time() - cpu0
    finally:
        await asyncio.gather(*(c.aclose() for c in clients), return_exceptions=True)
    return {
        "polls": polls,
        "due": ticks * len(clients),
        "errors": errors,
        "wall": wall,
        "cpu": cpu,
    }


async def native_prepare(host: str, port: int) -> dict[str, float]:
    """Write the macro variable the runs read (through the native client)."""
    from focas_net.client import NativeClient

    async with NativeClient(host, port, timeout=10.0) as client:
        await client.write_macro(MACRO, MACRO_VALUE)
    return {}


async def handle(subject: str, cmd: dict[str, Any]) -> dict[str, float]:
    """A worker's ``native_*`` op for ``subject``."""
    op = cmd["op"]
    if op == "native_prepare":
        return await native_prepare(cmd["host"], cmd["port"])
    if op == "native_run":
        args = (cmd["host"], cmd["port"], cmd["call"], cmd["callers"], cmd["duration"])
        if subject == NATIVE:
            return await native_run(*args)
        if subject == FLOOR:
            if cmd["callers"] != 1:
                return await floor_pipe_run(*args)
            return await floor_run(cmd["host"], cmd["port"], cmd["call"], cmd["duration"])
        return blocking_run(subject, *args)
    if op == "native_poll":
        poll = (cmd["targets"], cmd["call"], cmd["interval"], cmd["duration"])
        if subject == NATIVE:
            return await native_poll(*poll)
        return blocking_poll(subject, *poll)
    raise ValueError(f"unknown op {op!r}")


# -- the orchestration, in the suite's process ------------------------------------------------


def _ratio_rows(
    scenario: str, unit: str, samples: dict[str, list[float]], note: dict[str, str]
) -> list[Row]:
    """One row per subject; the others' ratios to FANUC's library, pair by pair, when it ran."""
    base = samples.get(FWLIB)
    rows = []
    for subject, values in samples.items():
        vs = FWLIB if base is not None and subject != FWLIB else None
        ratios = pairwise_ratios(values, base) if vs is not None and base is not None else None
        rows.append(Row(scenario, subject, unit, values, vs, ratios, note.get(subject, "")))
    return rows


def run_native(suite: Suite) -> None:
    """The ``native_*`` scenarios the suite was asked for, each subject in its own process."""
    from benchmarks.run import WorkerProcess, start_server

    cfg = suite.cfg
    wanted = [s for s in SCENARIOS if s in suite.scenarios]
    if not wanted:
        return
    subjects = [NATIVE]
    for subject, missing in ((FWLIB, fwlib_missing()), (PYFOCAS, pyfocas_missing())):
        if missing is None:
            subjects.append(subject)
        else:
            suite.skip(f"{subject} rows skipped: {missing}")
    if "native_seq" in wanted or "native_pipe64" in wanted:
        subjects.append(FLOOR)
    workers: dict[str, WorkerProcess] = {}
    try:
        for subject in subjects:
            workers[subject] = WorkerProcess(subject, cfg)
        if "native_seq" in wanted or "native_pipe64" in wanted:
            server = start_server(FOCAS, cfg)
            try:
                host, port = server.endpoint
                workers[NATIVE].call("native_prepare", host=host, port=port)
                if "native_seq" in wanted:
                    for suffix, call in SEQ_CALLS:
                        scenario = f"native_seq_{suffix}"
                        suite.guarded(
                            scenario,
                            partial(_throughput, suite, workers, scenario, host, port, call, 1),
                        )
                if "native_pipe64" in wanted:
                    suite.guarded(
                        "native_pipe64",
                        lambda: _throughput(
                            suite, workers, "native_pipe64", host, port, "read_macro", CALLERS
                        ),
                    )
            finally:
                server.stop()
        if "native_poll100" in wanted:
            for scenario, call in POLL_CALLS:
                suite.guarded(scenario, partial(_poll, suite, workers, scenario, call))
    finally:
        for worker in workers.values():
            worker.stop()


def _turns(subjects: list[str], rep: int) -> list[str]:
    return subjects if rep % 2 == 0 else subjects[::-1]


def _throughput(
    suite: Suite,
    workers: dict[str, WorkerProcess],
    scenario: str,
    host: str,
    port: int,
    call: str,
    callers: int,
) -> None:
    cfg = suite.cfg
    subjects = list(workers)
    print(
        f"{scenario}: {callers} caller(s) of {call}, warm-up, then {cfg.reps} x "
        f"{cfg.duration:g} s per subject",
        file=sys.stderr,
        flush=True,
    )
    kwargs = {"host": host, "port": port, "call": call, "callers": callers}
    for subject in subjects:
        workers[subject].call("native_run", duration=cfg.warmup, **kwargs)
    rates: dict[str, list[float]] = {s: [] for s in subjects}
    cpu: dict[str, list[float]] = {s: [] for s in subjects}
    frames: list[float] = []
    for rep in range(cfg.reps):
        for subject in _turns(subjects, rep):
            r = workers[subject].call("native_run", duration=cfg.duration, **kwargs)
            rates[subject].append(r["ops"] / r["elapsed"])
            cpu[subject].append(1e6 * r["cpu"] / r["ops"])
            if subject == NATIVE:
                frames.append(r["ops"] / max(r["frames"], 1))
    note = {s: f"client CPU {statistics.median(cpu[s]):.0f} us/call" for s in subjects}
    if FLOOR in rates:
        to_floor = statistics.median(pairwise_ratios(rates[NATIVE], rates[FLOOR]))
        note[NATIVE] += f", {to_floor:.2f} x the asyncio floor"
        if PYFOCAS in rates and callers == 1:
            floor_to_pyfocas = statistics.median(pairwise_ratios(rates[FLOOR], rates[PYFOCAS]))
            note[FLOOR] += f", {floor_to_pyfocas:.2f} x pyfocas"
    if callers > 1:
        note[NATIVE] += f", {statistics.median(frames):.1f} calls per frame"
        if FWLIB in note:
            note[FWLIB] += ", sequential on its one handle"
        if PYFOCAS in note:
            note[PYFOCAS] += f", {callers} threads taking turns"
    for row in _ratio_rows(scenario, "calls/s", rates, note):
        suite.add(row)


def _poll(suite: Suite, workers: dict[str, WorkerProcess], scenario: str, call: str) -> None:
    from benchmarks.run import start_server

    cfg = suite.cfg
    # pyfocas has no cnc_rddynamic2: it polls the status only; the asyncio floor does not poll
    subjects = [s for s in workers if s != FLOOR and (call != "read_dynamic" or s != PYFOCAS)]
    print(
        f"{scenario}: {FLEET} machines, {call} at {POLL_HZ:g} Hz, "
        f"{cfg.reps} x {cfg.fleet_duration:g} s per subject",
        file=sys.stderr,
        flush=True,
    )
    server = start_server(FOCAS, cfg, extra=("--fleet", str(FLEET)), count=FLEET)
    try:
        targets = [list(e) for e in server.endpoints]
        if len(targets) < FLEET:
            raise RuntimeError(f"fleet server announced {len(targets)} of {FLEET} machines")
        interval = 1.0 / POLL_HZ
        for subject in subjects:
            workers[subject].call(
                "native_poll",
                targets=targets,
                call=call,
                interval=interval,
                duration=min(1.0, cfg.warmup * 4),
            )
        per_poll: dict[str, list[float]] = {s: [] for s in subjects}
        achieved: dict[str, list[float]] = {s: [] for s in subjects}
        errors = dict.fromkeys(subjects, 0)
        for rep in range(cfg.reps):
            for subject in _turns(subjects, rep):
                r = workers[subject].call(
                    "native_poll",
                    targets=targets,
                    call=call,
                    interval=interval,
                    duration=cfg.fleet_duration,
                )
                per_poll[subject].append(1e6 * r["cpu"] / max(r["polls"], 1))
                achieved[subject].append(r["polls"] / r["due"])
                errors[subject] += int(r["errors"])
    finally:
        server.stop()
    note = {
        s: f"{statistics.median(achieved[s]):.1%} of the polls due, {errors[s]} errors"
        for s in per_poll
    }
    for row in _ratio_rows(scenario, "us/poll", per_poll, note):
        suite.add(row)


# -- the targets ----------------------------------------------------------------------------


def _ratio_check(name: str, row: Row | None, low: float, floor: Row | None) -> Check:
    """``row`` (the native client's) at least ``low`` x the library; the asyncio floor's
    ratio beside it (``floor``, when measured): what an asyncio client reaches on that box."""
    if row is None or row.ratio is None:
        return Check(name, None, "not measured")
    value = row.ratio.median
    detail = f"median {value:.2f} x FANUC's library"
    if floor is not None and floor.ratio is not None:
        detail += f" (the asyncio floor: {floor.ratio.median:.2f} x)"
    return Check(name, value >= low, detail)


def checks(results: Results) -> list[Check]:
    """The native targets, each PASS, FAIL or SKIP: pipe64 ``read_macro`` at least 10 x the
    library on one handle, sequential calls at least 0.7 x, ahead of pyfocas in every mode.
    Each says where the asyncio floor stood in the same run, when it was measured."""
    out = [
        _ratio_check(
            f"native_pipe64 read_macro >= {PIPE64_TARGET:g} x FANUC's library on one handle",
            results.find("native_pipe64", NATIVE),
            PIPE64_TARGET,
            results.find("native_pipe64", FLOOR),
        )
    ]
    for suffix, call in SEQ_CALLS:
        scenario = f"native_seq_{suffix}"
        out.append(
            _ratio_check(
                f"native_seq {call} >= {SEQ_TARGET:g} x FANUC's library",
                results.find(scenario, NATIVE),
                SEQ_TARGET,
                results.find(scenario, FLOOR),
            )
        )
    for scenario in PYFOCAS_MODES:
        name = f"{scenario}: ahead of pyfocas"
        ours, theirs = results.find(scenario, NATIVE), results.find(scenario, PYFOCAS)
        if ours is None or theirs is None:
            out.append(Check(name, None, "not measured"))
            continue
        if scenario.startswith("native_poll100"):  # CPU per poll: less is ahead
            value = statistics.median(pairwise_ratios(theirs.samples, ours.samples))
            out.append(Check(name, value > 1.0, f"pyfocas uses {value:.2f} x the CPU per poll"))
            continue
        value = statistics.median(pairwise_ratios(ours.samples, theirs.samples))
        detail = f"{value:.2f} x pyfocas"
        floor = results.find(scenario, FLOOR)
        if floor is not None:
            to_pyfocas = statistics.median(pairwise_ratios(floor.samples, theirs.samples))
            detail += f" (the asyncio floor: {to_pyfocas:.2f} x)"
        out.append(Check(name, value > 1.0, detail))
    return out
