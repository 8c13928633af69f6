"""Part programs through FANUC's own FOCAS library, against a real :class:`FocasServer`.

Skipped unless ``FOCAS_NET_FWLIB`` names FANUC's libfwlib32 (x86-64 Linux, never part of this
repository). Both command sets (the built-in 0i-F machine, the 30i set; the 16i-class machine
file, the 16i set) send the same program frames, and each function is checked in both against
what the packed client reads of the same machine: the directory, the program memory, an upload
(``cnc_upstart``/``cnc_upload``/``cnc_upend`` and the ``3`` forms), a download (and the ``3``
forms) that is then listed, read and run through the packed client, delete, search, and the EW
codes of the refusals.

Run as a script (``python tests/test_fwlib_programs.py``, with ``FOCAS_NET_FWLIB`` set) it
rewrites ``tests/data/fwlib_programs.json``: every frame the library sent for the scenario of
:func:`scenario` and the frames the server answered, which ``tests/test_native_programs.py``
replays through the adapter without the library.
"""

from __future__ import annotations

import asyncio
import ctypes
import json
import struct
import sys
from collections.abc import AsyncIterator, Callable
from contextlib import asynccontextmanager
from pathlib import Path
from typing import Any

import pytest
from fwlib_support import (
    LIBRARY,
    Cnc,
    buf,
    connect,
    demo_machine,
    download,
    i32,
    library,
    s16,
    served_cnc,
    upload,
    us,
)
from support import IO_TIMEOUT, serving

from focas_net.client import FocasClient
from focas_net.errors import EW, CncError
from focas_net.native import TransferFrame
from focas_net.server import NativeFront
from focas_net.sim import default_machine
from focas_net.sim.nc import ManualClock

pytestmark = pytest.mark.skipif(
    not LIBRARY,
    reason="set FOCAS_NET_FWLIB to the path of FANUC's libfwlib32 (e.g. libfwlib32.so.1) "
    "to run FANUC's library against the simulator",
)

GOLDEN = Path(__file__).with_name("data") / "fwlib_programs.json"

#: A program the tests download: one motion, then the end of the program.
NEW_PROGRAM = "O0321 (NATIVE)\nN10 G91 G1 X10. F600\nN20 M30\n"
#: The same as a download sends it (a leading newline, the ending ``%``).
NEW_PUNCHED = b"\n" + NEW_PROGRAM.encode() + b"%"
#: A program longer than one upload frame (1280 bytes) and than the library's 256-byte
#: ``cnc_upload`` buffer.
LONG_PROGRAM = "O0400 (LONG)\n" + "".join(f"N{n} G0 X{n}.\n" for n in range(10, 3000, 10)) + "M30\n"

#: The library's program-memory struct in type 0: ODBNC ``bin`` (short, short, int, int).
ODBNC = "<hhii"
#: PRGDIR2 (cnc_rdprogdir2o8 fills the o8 form: i32 number, i32 length, comment[51], pad)
PRGDIR2 = "<ii51sx"
#: PRGDIR3: i32 number, length, page, comment[52], then two 6-short dates.
PRGDIR3 = "<iii52s12h"

SETS = ["30i", "16i"]


@asynccontextmanager
async def program_cnc(set_name: str, clock: ManualClock | None = None) -> AsyncIterator[Cnc]:
    async with served_cnc(set_name, demo_machine(set_name, clock)) as cnc:
        yield cnc


@pytest.fixture(params=SETS)
async def cnc(request: pytest.FixtureRequest) -> AsyncIterator[Cnc]:
    async with program_cnc(request.param) as served:
        yield served


# --------------------------------------------------------------------------------------------
# The library's calls


def _comment(raw: bytes) -> str:
    return raw.split(b"\x00", 1)[0].decode("latin-1")


async def rdprogdir2(cnc: Cnc, kind: int, top: int = 0, count: int = 10) -> list[Any]:
    b = buf(4096)
    n, first = s16(count), s16(top)
    rc = await cnc.call("cnc_rdprogdir2", s16(kind), ctypes.byref(first), ctypes.byref(n), b)
    assert rc == 0, f"cnc_rdprogdir2 returned {rc}"
    size = struct.calcsize(PRGDIR2)
    return [struct.unpack_from(PRGDIR2, b.raw, i * size) for i in range(n.value)]


async def rdprogdir3(cnc: Cnc, kind: int) -> list[Any]:
    b = buf(4096)
    n, first = s16(10), i32(0)
    rc = await cnc.call("cnc_rdprogdir3", s16(kind), ctypes.byref(first), ctypes.byref(n), b)
    assert rc == 0, f"cnc_rdprogdir3 returned {rc}"
    size = struct.calcsize(PRGDIR3)
    return [struct.unpack_from(PRGDIR3, b.raw, i * size) for i in range(n.value)]


async def rdprogdir_text(cnc: Cnc, kind: int) -> str:
    b = buf(1024)
    rc = await cnc.call("cnc_rdprogdir", s16(kind), s16(0), s16(9999), us(1000), b)
    assert rc == 0, f"cnc_rdprogdir returned {rc}"
    return b.value.decode("latin-1")


async def _upload_to_end(cnc: Cnc, form: str) -> bytes:
    """``cnc_upload3``/``cnc_upload4`` (``form`` "3" or "4") in 1024-byte pieces until it
    ends (-2), then ``cnc_upend3``/``4``: the bytes."""
    out = b""
    b = buf(2048)
    for _ in range(200):
        n = i32(1024)
        rc = await cnc.call(f"cnc_upload{form}", ctypes.byref(n), b)
        if rc:
            break
        out += b.raw[: n.value]
    assert rc == -2, f"cnc_upload{form} ended with {rc}"
    assert await cnc.call(f"cnc_upend{form}") == 0
    return out


async def upload3(cnc: Cnc, number: int) -> tuple[int, bytes]:
    """``cnc_upstart3(0, n, n)``, ``cnc_upload3`` until it ends, ``cnc_upend3``."""
    rc = await cnc.call("cnc_upstart3", s16(0), i32(number), i32(number))
    if rc:
        return rc, b""
    return 0, await _upload_to_end(cnc, "3")


async def download3(cnc: Cnc, data: bytes) -> int:
    """``cnc_dwnstart3(0)``, ``cnc_download3``, ``cnc_dwnend3``."""
    rc = await cnc.call("cnc_dwnstart3", s16(0))
    if rc:
        return rc
    n = i32(len(data))
    rc = await cnc.call("cnc_download3", ctypes.byref(n), ctypes.create_string_buffer(data))
    assert rc == 0 and n.value == len(data), f"cnc_download3 returned {rc}, took {n.value}"
    return await cnc.call("cnc_dwnend3")


async def upload4(cnc: Cnc, number: int) -> tuple[int, bytes]:
    """``cnc_upstart4(0, "O<n>")``, ``cnc_upload4`` until it ends, ``cnc_upend4``."""
    name = ctypes.create_string_buffer(f"O{number:04d}".encode())
    rc = await cnc.call("cnc_upstart4", s16(0), name)
    if rc:
        return rc, b""
    return 0, await _upload_to_end(cnc, "4")


async def download4(cnc: Cnc, data: bytes) -> int:
    """``cnc_dwnstart4(0, folder)``, ``cnc_download4``, ``cnc_dwnend4``."""
    folder = ctypes.create_string_buffer(b"//CNC_MEM/USER/PATH1/")
    rc = await cnc.call("cnc_dwnstart4", s16(0), folder)
    if rc:
        return rc
    n = i32(len(data))
    rc = await cnc.call("cnc_download4", ctypes.byref(n), ctypes.create_string_buffer(data))
    assert rc == 0 and n.value == len(data), f"cnc_download4 returned {rc}, took {n.value}"
    return await cnc.call("cnc_dwnend4")


async def rdexecprog(cnc: Cnc, length: int = 256) -> tuple[int, int, bytes]:
    """``cnc_rdexecprog``: (return, blknum, the text)."""
    b = buf(1024)
    n, blocks = us(length), s16(0)
    rc = await cnc.call("cnc_rdexecprog", ctypes.byref(n), ctypes.byref(blocks), b)
    return rc, blocks.value, b.raw[: n.value]


def unpunched(data: bytes) -> str:
    """An upload's text without its ``%`` lines."""
    text = data.decode("ascii")
    assert text.startswith("%\n") and text.endswith("%"), text[:20]
    return text[2:-1]


async def packed_ew(call: Any) -> int:
    try:
        await call
    except CncError as exc:
        return exc.ew
    return 0


# --------------------------------------------------------------------------------------------
# Directory and memory


async def test_the_directory_is_the_packed_directory(cnc: Cnc) -> None:
    cnc.machine.store_program("O0123 (SECOND ONE)\nG0 X1.\nM30\n")
    packed = await cnc.packed.read_program_directory()
    assert [e.number for e in packed] == [1, 123]
    expected = [(e.number, e.size, f"({e.name})") for e in packed]
    for kind in (0, 1, 2):
        got = await rdprogdir2(cnc, kind)
        # type 0 numbers only, 1 with comments, 2 with sizes: the library picks the fields
        want = [
            (n, size if kind == 2 else 0, comment if kind else "") for n, size, comment in expected
        ]
        assert [(g[0], g[1], _comment(g[2])) for g in got] == want
    got3 = await rdprogdir3(cnc, 2)
    assert [(g[0], g[1], _comment(g[3])) for g in got3] == expected
    assert all(g[4:] == (0,) * 12 for g in got3)  # no dates: the entries carry none
    assert await rdprogdir_text(cnc, 0) == "O1O123%"
    assert await rdprogdir_text(cnc, 1) == "%\nO1(DEMO CONTOUR)\nO123(SECOND ONE)\n%"


async def test_the_directory_from_a_number_on(cnc: Cnc) -> None:
    cnc.machine.store_program("O0123 (SECOND ONE)\nG0 X1.\nM30\n")
    packed = await cnc.packed.read_program_directory(first=2)
    got = await rdprogdir2(cnc, 2, top=2)
    assert [(g[0], g[1]) for g in got] == [(e.number, e.size) for e in packed]
    assert [e.number for e in packed] == [123]
    assert await rdprogdir2(cnc, 2, top=124) == []


async def test_program_memory(cnc: Cnc) -> None:
    packed = await cnc.packed.read_program_directory()
    used = sum(e.size for e in packed)
    store = cnc.machine.programs
    b = buf(64)
    assert await cnc.call("cnc_rdproginfo", s16(0), s16(12), b) == 0
    assert struct.unpack_from(ODBNC, b.raw) == (
        len(packed),
        store.max_programs - len(packed),
        used,
        store.capacity - used,
    )
    assert await cnc.call("cnc_rdproginfo", s16(1), s16(31), b) == 0
    numbers = (len(packed), store.max_programs - len(packed), used, store.capacity - used)
    assert b.value.decode() == "%\n" + "".join(f"{n}\n" for n in numbers) + "%"


# --------------------------------------------------------------------------------------------
# Upload


@pytest.mark.parametrize("reader", [upload, upload3, upload4])
async def test_an_upload_is_the_packed_read(cnc: Cnc, reader: Callable[[Cnc, int], Any]) -> None:
    cnc.machine.store_program(LONG_PROGRAM)
    for number in (1, 400):
        rc, data = await reader(cnc, number)
        assert rc == 0
        text = unpunched(data)
        assert text == await cnc.packed.read_program(number) == cnc.machine.program_text(number)
    assert len(text) > 1280 * 2


async def test_an_upload_of_no_program_is_ew_number(cnc: Cnc) -> None:
    assert await packed_ew(cnc.packed.read_program(77)) == EW.NUMBER
    assert await cnc.call("cnc_upstart", s16(77)) == EW.NUMBER
    assert await cnc.call("cnc_upend") == EW.FUNC  # the library's own: nothing was started
    rc, _ = await upload(cnc, 1)  # the connection is fine
    assert rc == 0


# --------------------------------------------------------------------------------------------
# Download, search, delete


@pytest.mark.parametrize("set_name", SETS)
@pytest.mark.parametrize("writer", [download, download3, download4])
async def test_a_download_is_listed_read_and_runs(
    set_name: str, writer: Callable[[Cnc, bytes], Any]
) -> None:
    clock = ManualClock()
    async with program_cnc(set_name, clock) as cnc:
        assert await writer(cnc, NEW_PUNCHED) == 0
        entries = {e.number: e for e in await cnc.packed.read_program_directory()}
        assert entries[321].name == "NATIVE"
        text = await cnc.packed.read_program(321)
        assert text == NEW_PROGRAM  # stored as sent (already one block per line)
        rc, data = await upload(cnc, 321)
        assert rc == 0
        assert unpunched(data) == text
        # it runs: search (MEM mode) through the library, cycle start through the packed client
        cnc.machine.set_panel(1)
        assert await cnc.call("cnc_search", s16(321)) == 0
        numbers = await cnc.packed.read_program_numbers()
        assert numbers.main == 321
        parts = (await cnc.packed.read_run_info()).parts_count
        await cnc.packed.sim.cycle_start()
        clock.advance(0.5)
        assert (await cnc.packed.read_status()).run == 3  # STRT
        clock.advance(10.0)  # X10 at F600 takes 1 s; then M30
        assert (await cnc.packed.read_run_info()).parts_count == parts + 1
        position = await cnc.packed.read_positions("absolute")
        assert next(iter(position.increments.values())) == 10_000


@pytest.mark.parametrize("set_name", SETS)
async def test_the_blocks_being_executed(set_name: str) -> None:
    clock = ManualClock()
    async with program_cnc(set_name, clock) as cnc:
        cnc.machine.set_panel(1)
        await cnc.packed.select_program(1)
        await cnc.packed.sim.cycle_start()
        clock.advance(2.0)
        sequence = cnc.machine.motion.sequence
        assert sequence > 0
        rc, blocks, text = await rdexecprog(cnc, 64)
        lines = await cnc.packed.read_program(1)
        rest = lines[lines.index(f"\nN{sequence} ") + 1 :]
        assert rc == 0 and rest.startswith(text.decode())
        assert blocks == text.count(b"\n") and 0 < len(text) <= 64


async def test_a_long_download_in_many_frames(cnc: Cnc) -> None:
    assert await download(cnc, b"%\n" + LONG_PROGRAM.encode() + b"%") == 0
    assert await cnc.packed.read_program(400) == LONG_PROGRAM


async def test_download_refusals_are_the_packed_ones(cnc: Cnc) -> None:
    assert await download(cnc, NEW_PUNCHED) == 0
    packed = await packed_ew(cnc.packed.write_program(NEW_PROGRAM))
    assert packed == EW.REJECT
    assert await download3(cnc, NEW_PUNCHED) == EW.REJECT
    # cnc_dwnend (the old function) turns the CNC's 13 into EW_UNEXP (-6) itself
    assert await download(cnc, NEW_PUNCHED) == -6
    bad = b"\nG0 X1.\nM30\n%"  # no O number
    assert await packed_ew(cnc.packed.write_program("G0 X1.\nM30\n")) == EW.DATA
    assert await download3(cnc, bad) == EW.DATA
    assert [e.number for e in await cnc.packed.read_program_directory()] == [1, 321]


async def test_search_and_delete(cnc: Cnc) -> None:
    assert await download(cnc, NEW_PUNCHED) == 0
    # MDI (served_cnc's mode): search is refused as through the packed protocol
    assert await packed_ew(cnc.packed.select_program(321)) == EW.MODE
    assert await cnc.call("cnc_search", s16(321)) == EW.MODE
    cnc.machine.set_panel(1)  # MEM
    assert await cnc.call("cnc_search", s16(321)) == 0
    assert (await cnc.packed.read_program_numbers()).main == 321
    assert await cnc.call("cnc_search", s16(55)) == EW.NUMBER
    assert await packed_ew(cnc.packed.select_program(55)) == EW.NUMBER
    assert await cnc.call("cnc_delete", s16(321)) == 0
    assert [e.number for e in await cnc.packed.read_program_directory()] == [1]
    assert await cnc.call("cnc_delete", s16(321)) == EW.NUMBER
    assert await packed_ew(cnc.packed.delete_program(321)) == EW.NUMBER


async def test_a_read_only_machine_refuses_changes_and_uploads() -> None:
    machine = default_machine(read_only=True)
    async with serving(machine) as served:
        async with FocasClient(served.host, served.port, timeout=IO_TIMEOUT) as packed:
            handle = await connect(served)
            cnc = Cnc(served, packed, handle, "30i")
            try:
                assert await packed_ew(packed.write_program(NEW_PROGRAM)) == EW.PROT
                assert await cnc.call("cnc_dwnstart") == EW.PROT
                assert await packed_ew(packed.delete_program(1)) == EW.PROT
                assert await cnc.call("cnc_delete", s16(1)) == EW.PROT
                assert await cnc.call("cnc_search", s16(1)) == EW.PROT
                rc, data = await upload(cnc, 1)
                assert rc == 0 and unpunched(data) == await packed.read_program(1)
            finally:
                await handle.free()
    assert [e.number for e in machine.program_directory()] == [1]


async def test_a_running_program_is_busy(cnc: Cnc) -> None:
    cnc.machine.set_panel(1)
    await cnc.packed.select_program(1)
    await cnc.packed.sim.cycle_start()
    assert await packed_ew(cnc.packed.delete_program(1)) == EW.BUSY
    assert await cnc.call("cnc_delete", s16(1)) == EW.BUSY


# --------------------------------------------------------------------------------------------
# The golden data


async def scenario(cnc: Cnc) -> list[dict[str, Any]]:
    """The calls of the golden data, in order: (function, arguments, return)."""
    calls: list[dict[str, Any]] = []

    async def note(function: str, rc: int, **arguments: Any) -> None:
        calls.append({"function": function, "arguments": arguments, "return": rc})

    cnc.machine.store_program("O0123 (SECOND ONE)\nG0 X1.\nM30\n")
    for kind in (0, 1, 2):
        await rdprogdir2(cnc, kind)
        await note("cnc_rdprogdir2", 0, type=kind)
    await rdprogdir3(cnc, 2)
    await note("cnc_rdprogdir3", 0, type=2)
    await rdprogdir_text(cnc, 1)
    await note("cnc_rdprogdir", 0, type=1)
    await note("cnc_rdproginfo", await cnc.call("cnc_rdproginfo", s16(0), s16(12), buf(64)))
    rc, _ = await upload(cnc, 1)
    await note("cnc_upstart/cnc_upload/cnc_upend", rc, number=1)
    await note("cnc_upstart", await cnc.call("cnc_upstart", s16(77)), number=77)
    await note("cnc_dwnstart/cnc_download/cnc_dwnend", await download(cnc, NEW_PUNCHED))
    await note("cnc_dwnstart3/cnc_download3/cnc_dwnend3", await download3(cnc, NEW_PUNCHED))
    await note("cnc_search", await cnc.call("cnc_search", s16(321)), number=321, mode="MDI")
    cnc.machine.set_panel(1)
    await note("cnc_search", await cnc.call("cnc_search", s16(321)), number=321, mode="MEM")
    await note("cnc_delete", await cnc.call("cnc_delete", s16(321)), number=321)
    await note("cnc_delete", await cnc.call("cnc_delete", s16(321)), number=321)
    rc, _ = await upload4(cnc, 123)
    await note("cnc_upstart4/cnc_upload4/cnc_upend4", rc, name="O0123")
    await note("cnc_dwnstart4/cnc_download4/cnc_dwnend4", await download4(cnc, NEW_PUNCHED))
    rc, blocks, _ = await rdexecprog(cnc)
    await note("cnc_rdexecprog", rc, blknum=blocks)
    return calls


async def record(set_name: str) -> dict[str, Any]:
    """The scenario's frames in ``set_name``: per frame the library sent after connecting,
    its type, the machine's mode when it came, its body and the frames answered."""
    exchanges: list[dict[str, Any]] = []
    original_answer, original_transfer = NativeFront.answer, NativeFront.transfer

    def answer(self: NativeFront, body: bytes, session: Any = None) -> bytes:
        out = original_answer(self, body, session)
        exchanges.append(
            {
                "type": 0x2101,
                "mode": self.machine.panel.mode,
                "request": body.hex(),
                "answers": [out.hex()],
            }
        )
        return out

    def transfer(self: NativeFront, frame_type: int, body: bytes, state: Any) -> Any:
        out = original_transfer(self, frame_type, body, state)
        answers = None if out is None else [a.hex() for a in out]
        mode = self.machine.panel.mode
        exchanges.append(
            {"type": frame_type, "mode": mode, "request": body.hex(), "answers": answers}
        )
        return out

    async with program_cnc(set_name) as cnc:
        exchanges.clear()  # the connect's own requests are another file's
        NativeFront.answer = answer  # type: ignore[method-assign]
        NativeFront.transfer = transfer  # type: ignore[method-assign]
        try:
            calls = await scenario(cnc)
        finally:
            NativeFront.answer = original_answer  # type: ignore[method-assign]
            NativeFront.transfer = original_transfer  # type: ignore[method-assign]
    return {"command_set": set_name, "calls": calls, "exchanges": exchanges}


async def golden() -> dict[str, Any]:
    library()
    return {
        "library": "libfwlib32 1.0.5 (x86-64 Linux)",
        "sets": [await record(s) for s in SETS],
    }


async def test_the_golden_data_is_what_the_library_does() -> None:
    assert await golden() == json.loads(GOLDEN.read_text())


async def test_transfers_use_their_own_frames() -> None:
    data = json.loads(GOLDEN.read_text())
    for s in data["sets"]:
        types = {e["type"] for e in s["exchanges"]}
        assert {int(TransferFrame.UPLOAD_START), int(TransferFrame.DOWNLOAD_START)} <= types


if __name__ == "__main__":
    if not LIBRARY:
        sys.exit("set FOCAS_NET_FWLIB to the path of FANUC's libfwlib32")
    GOLDEN.write_text(json.dumps(asyncio.run(golden()), indent=1) + "\n")
