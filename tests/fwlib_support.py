"""FANUC's library through ``ctypes``, for the tests that drive it against a real server.

``FOCAS_NET_FWLIB`` names the library (x86-64 Linux libfwlib32, never part of this
repository); ``FOCAS_NET_FWLIB_LOG`` a file for its own log. The library blocks and ties a
handle to the thread that opened it, so each :class:`Handle` runs on a thread of its own.
"""

from __future__ import annotations

import asyncio
import contextlib
import ctypes
import os
import struct
import threading
from collections.abc import AsyncIterator, Callable, Iterator
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from decimal import Decimal
from pathlib import Path
from typing import Any, TypeVar

from support import IO_TIMEOUT, Served, serving

from focas_net.adapters import NativeAdapter
from focas_net.client import FocasClient
from focas_net.server import FocasServer, NativeFront
from focas_net.sim import DataItem, Machine, ParamKind, default_machine, load_machine
from focas_net.sim import Session as SimSession
from focas_net.sim.default import DEMO_PROGRAM
from focas_net.sim.nc import ManualClock

LIBRARY = os.environ.get("FOCAS_NET_FWLIB")


T = TypeVar("T")


us, s16, i32 = ctypes.c_ushort, ctypes.c_short, ctypes.c_int32


#: The library's socket error (the call's answer never came, or the connection is gone).
EW_SOCKET = -16


#: Seconds the library waits for an answer (its handle timeout).
HANDLE_TIMEOUT = 3


#: A 16i-class machine file (the 16i command set, open answer version 2).
MACHINE_16I = Path(__file__).with_name("data") / "fwlib_16i_machine.toml"


#: The same parameters on a 0i-F (the 30i command set): bit, byte, word, two-word and real.
MACHINE_30I = Path(__file__).with_name("data") / "fwlib_30i_machine.toml"


class _Library:
    """FANUC's library with every function returning a C ``short`` (the EW code)."""

    def __init__(self, path: str) -> None:
        self._cdll = ctypes.cdll.LoadLibrary(path)

    def __getattr__(self, name: str) -> Any:
        function = getattr(self._cdll, name)
        function.restype = ctypes.c_short
        setattr(self, name, function)
        return function


_LIB: _Library | None = None


_LIB_LOCK = threading.Lock()


def library() -> _Library:
    """The library, loaded and started once per test run."""
    global _LIB
    with _LIB_LOCK:
        if _LIB is None:
            assert LIBRARY is not None
            lib = _Library(LIBRARY)
            log = os.environ.get("FOCAS_NET_FWLIB_LOG")
            lib.cnc_startupprocess(3 if log else 0, (log or "/dev/null").encode())
            _LIB = lib
        return _LIB


def buf(size: int) -> ctypes.Array[ctypes.c_char]:
    return ctypes.create_string_buffer(size)


class Handle:
    """A handle of FANUC's library, opened, used and freed on one thread of its own (the
    library ties a handle to the thread that made it)."""

    def __init__(self) -> None:
        self._executor = ThreadPoolExecutor(max_workers=1)
        self.number = 0

    async def run(self, function: Callable[..., T], *args: Any) -> T:
        """``function(*args)`` on this handle's thread, bounded."""
        loop = asyncio.get_running_loop()
        async with asyncio.timeout(HANDLE_TIMEOUT * 4 + IO_TIMEOUT):
            return await loop.run_in_executor(self._executor, function, *args)

    async def call(self, name: str, *args: Any) -> int:
        """``name(handle, *args)``; its return code."""
        rc: int = await self.run(getattr(library(), name), us(self.number), *args)
        return rc

    async def open(self, served: Served, seconds: int = HANDLE_TIMEOUT) -> int:
        """``cnc_allclibhndl3`` to ``served``; its return code."""
        handle = us()
        rc: int = await self.run(
            library().cnc_allclibhndl3,
            b"127.0.0.1",
            us(served.port),
            i32(seconds),
            ctypes.byref(handle),
        )
        self.number = handle.value
        return rc

    async def free(self) -> int:
        """``cnc_freelibhndl``, then the thread ends."""
        try:
            return await self.call("cnc_freelibhndl")
        finally:
            self._executor.shutdown(wait=False)


async def connect(served: Served, seconds: int = HANDLE_TIMEOUT) -> Handle:
    """A new handle on ``served`` (asserts EW_OK)."""
    handle = Handle()
    rc = await handle.open(served, seconds)
    assert rc == 0, f"cnc_allclibhndl3 returned {rc}"
    return handle


@dataclass
class Cnc:
    """One handle of FANUC's library on a served machine, and a packed client of the same."""

    served: Served
    packed: FocasClient
    handle: Handle
    set_name: str

    @property
    def machine(self) -> Machine:
        return self.served.machine

    @property
    def slots(self) -> int:
        """Values an all-axes read must make room for: the path's axes at 16i class, the
        open answer's max axes at 30i class (the machine's, 32 on a 0i-F)."""
        return 3 if self.set_name == "16i" else self.machine.identity().max_axis

    async def call(self, name: str, *args: Any) -> int:
        """``name(handle, *args)`` on the handle's thread; its return code."""
        return await self.handle.call(name, *args)


def demo_machine(set_name: str, clock: ManualClock | None = None) -> Machine:
    """The set's machine on ``clock`` (else a clock of its own) with the demo program O0001
    (the 16i machine file has none)."""
    clock = clock or ManualClock()
    if set_name == "30i":
        return default_machine(sim_clock=clock)
    machine = load_machine(MACHINE_16I, sim_clock=clock)
    machine.store_program(DEMO_PROGRAM)
    return machine


def machine_for(set_name: str) -> Machine:
    if set_name == "30i":
        return default_machine()
    if set_name == "30i-file":
        return load_machine(MACHINE_30I)
    return load_machine(MACHINE_16I)


@contextlib.asynccontextmanager
async def served_cnc(set_name: str, machine: Machine | None = None) -> AsyncIterator[Cnc]:
    """``machine`` (else one of ``set_name``) in MDI with parameter writes enabled, served,
    with the packed client and one library handle on it."""
    if machine is None:
        machine = machine_for(set_name)
    machine.set_panel(0, 1, 0)  # MDI, parameter writes enabled
    async with serving(machine) as served:
        async with FocasClient(served.host, served.port, timeout=IO_TIMEOUT) as packed:
            handle = await connect(served)
            try:
                yield Cnc(served, packed, handle, set_name)
            finally:
                await handle.free()


_SIZES = {1: 1, 2: 2, 4: 4, 8: 8}


_FORMATS = {1: "b", 2: "h", 4: "i"}


def _value_format(item: DataItem) -> str:
    """How the library gives one value of ``item`` in IODBPSD: a bit parameter's byte as its
    eight bits, a real parameter's REALPRM ``(prm_val, dec_val)``."""
    if item.kind is ParamKind.REAL:
        return "ii"
    if item.kind is ParamKind.BIT:
        return "B"
    return _FORMATS[item.width]


async def rdparam(
    cnc: Cnc, number: int, axis: int, fn: str = "cnc_rdparam"
) -> tuple[int, list[Any]]:
    """The library's values: integers, or ``Decimal`` for a real parameter."""
    item = (cnc.machine.param_item if fn == "cnc_rdparam" else cnc.machine.diag_item)(number)
    assert item is not None
    size = _SIZES[item.width]
    count = cnc.slots if axis == -1 and item.axis else 1
    b = buf(4 + 8 * 32)
    rc = await cnc.call(fn, s16(number), s16(axis), s16(4 + size * count), b)
    datano, kind = struct.unpack_from("<hh", b.raw)
    n = len(cnc.machine.axes) if axis == -1 and item.axis else 1
    fmt = _value_format(item)
    raw = struct.unpack_from(f"<{n * len(fmt)}{fmt[0]}", b.raw, 4)
    values: list[Any] = list(raw)
    if item.kind is ParamKind.REAL:
        values = [Decimal(raw[i]).scaleb(-raw[i + 1]) for i in range(0, len(raw), 2)]
    if rc == 0:
        assert (datano, kind) == (number, axis if item.axis else 0)
    return rc, values


async def wrparam(cnc: Cnc, number: int, axis: int, values: list[Any], length: int = 0) -> int:
    """``cnc_wrparam`` of ``values`` (integers, or ``(prm_val, dec_val)`` for a real
    parameter); ``length`` defaults to the one the parameter's type needs."""
    item = cnc.machine.param_item(number)
    assert item is not None
    size = _SIZES[item.width]
    b = buf(4 + 8 * 32)
    struct.pack_into("<hh", b, 0, number, axis)
    fmt = _value_format(item)
    for i, v in enumerate(values):
        struct.pack_into(f"<{fmt}", b, 4 + i * size, *(v if isinstance(v, tuple) else (v,)))
    length = length or 4 + size * (cnc.slots if axis == -1 else 1)
    return await cnc.call("cnc_wrparam", s16(length), b)


async def upload(cnc: Cnc, number: int) -> tuple[int, bytes]:
    """``cnc_upstart``, ``cnc_upload`` until it ends (-2), ``cnc_upend``: (the first code that
    is not 0 of upstart/upend, the bytes)."""
    rc = await cnc.call("cnc_upstart", s16(number))
    if rc:
        await cnc.call("cnc_upend")
        return rc, b""
    out = b""
    b = buf(4 + 256)
    for _ in range(200):
        n = us(256)
        rc = await cnc.call("cnc_upload", b, ctypes.byref(n))
        if rc:
            break
        out += b.raw[4 : 4 + n.value]
    assert rc == -2, f"cnc_upload ended with {rc}"  # EW_RESET: the end of the data
    assert await cnc.call("cnc_upend") == 0
    return 0, out


async def download(cnc: Cnc, data: bytes) -> int:
    """``cnc_dwnstart``, ``cnc_download`` in 256-byte pieces, ``cnc_dwnend``."""
    rc = await cnc.call("cnc_dwnstart")
    if rc:
        return rc
    for i in range(0, len(data), 256):
        piece = data[i : i + 256]
        rc = await cnc.call("cnc_download", ctypes.create_string_buffer(piece), s16(len(piece)))
        assert rc == 0, f"cnc_download returned {rc}"
    return await cnc.call("cnc_dwnend")


class Recorder:
    """The data-request bodies the native adapter was given, in order (the ``recorder``
    fixture of conftest.py: :func:`record_requests`)."""

    def __init__(self) -> None:
        self.bodies: list[bytes] = []

    def take(self) -> list[bytes]:
        """The bodies recorded since the last take."""
        taken, self.bodies = self.bodies, []
        return taken


def record_requests(monkeypatch: Any) -> Recorder:
    """Have every native adapter record the request bodies it answers, until ``monkeypatch``
    (a :class:`pytest.MonkeyPatch`) undoes it."""
    rec = Recorder()
    answer = NativeAdapter.answer

    def recorded(self: NativeAdapter, body: bytes, session: Any = None) -> bytes:
        rec.bodies.append(bytes(body))
        return answer(self, body, session)

    monkeypatch.setattr(NativeAdapter, "answer", recorded)
    return rec


@dataclass
class Recorded:
    """A simulator served by :func:`recorded_server`: its port and what it answered."""

    server: FocasServer
    port: int
    #: Every FOCAS/2 data request and its answer, in order, not yet taken.
    exchanges: list[tuple[bytes, bytes]]

    def take(self) -> list[tuple[bytes, bytes]]:
        """The exchanges recorded since the last take."""
        taken = list(self.exchanges)
        self.exchanges.clear()
        return taken

    @property
    def open_response(self) -> bytes:
        """The open answer of the FOCAS/2 front."""
        return self.server.listeners[0]._native_front().open_response


@contextlib.contextmanager
def recorded_server(machine: Machine, seconds: float = 30.0) -> Iterator[Recorded]:
    """``machine`` served on 127.0.0.1 (an ephemeral port) by an event loop in a thread of its
    own, so that FANUC's library can be called synchronously from this one; every FOCAS/2 data
    request and the simulator's answer are recorded (:attr:`Recorded.exchanges`). The capture
    scripts' one set-up; ``seconds`` bounds the stop."""
    exchanges: list[tuple[bytes, bytes]] = []
    original = NativeFront.answer

    def recording(self: NativeFront, body: bytes, session: SimSession | None = None) -> bytes:
        answer = original(self, body, session)
        exchanges.append((body, answer))
        return answer

    NativeFront.answer = recording  # type: ignore[method-assign]
    loop = asyncio.new_event_loop()
    server = FocasServer(machine, host="127.0.0.1", port=0)
    thread = threading.Thread(target=loop.run_forever, daemon=True)
    try:
        loop.run_until_complete(server.start())
        thread.start()
        yield Recorded(server, server.listeners[0].address[1], exchanges)
    finally:
        NativeFront.answer = original  # type: ignore[method-assign]
        if thread.is_alive():
            asyncio.run_coroutine_threadsafe(server.aclose(), loop).result(seconds)
            loop.call_soon_threadsafe(loop.stop)
            thread.join(seconds)
        loop.close()
