"""The program folders through FANUC's own FOCAS library, against a real :class:`FocasServer`.

Skipped unless ``FOCAS_NET_FWLIB`` names FANUC's libfwlib32 (x86-64 Linux, never part of this
repository). The library sends the same frames in both command sets: the 30i set's machine
(the built-in 0i-F) answers them from its folder tree, in agreement with what the packed
client reads of the same programs; the 16i set's machine (a 16i has no program folders)
answers EW_FUNC to each, which the library returns. Every frame the library sends is the one
:mod:`focas_net.native.files` builds for the same call (golden bytes).
"""

from __future__ import annotations

import ctypes
import math
from collections.abc import AsyncIterator
from contextlib import asynccontextmanager
from typing import Any

import pytest
from fwlib_support import (
    LIBRARY,
    Cnc,
    Recorder,
    buf,
    demo_machine,
    download,
    s16,
    served_cnc,
)
from support import two_path_lathe

from focas_net.errors import EW
from focas_net.native import (
    CommandSet,
    LibraryCall,
    cnc_pdf_del,
    cnc_pdf_rdmain,
    cnc_pdf_slctmain,
    cnc_rdpdf_alldir,
    cnc_rdpdf_curdir,
    cnc_rdpdf_drive,
    cnc_rdpdf_inf,
    cnc_rdpdf_prginf,
    cnc_rdpdf_subdir,
    cnc_rdpdf_subdirn,
    cnc_wrpdf_curdir,
)
from focas_net.sim.nc import ManualClock

pytestmark = pytest.mark.skipif(
    not LIBRARY,
    reason="set FOCAS_NET_FWLIB to the path of FANUC's libfwlib32 (e.g. libfwlib32.so.1) "
    "to run FANUC's library against the simulator",
)

PATH1 = "//CNC_MEM/USER/PATH1/"
NEW_PUNCHED = b"\nO0321 (NATIVE)\nN10 G91 G1 X10. F600\nN20 M30\n%"
CS = CommandSet.FS30I


class ODBPDFDRV(ctypes.Structure):
    _pack_ = 4
    _fields_ = [
        ("max_num", ctypes.c_short),
        ("dummy", ctypes.c_short),
        ("drive", ctypes.c_char * 12 * 16),
    ]


class ODBPDFINF(ctypes.Structure):
    _pack_ = 4
    _fields_ = [(n, ctypes.c_int32) for n in ("used_page", "all_page", "used_dir", "all_dir")]


class IDBPDFSDIR(ctypes.Structure):
    _pack_ = 4
    _fields_ = [
        ("path", ctypes.c_char * 212),
        ("req_num", ctypes.c_short),
        ("dummy", ctypes.c_short),
    ]


class ODBPDFSDIR(ctypes.Structure):
    _pack_ = 4
    _fields_ = [
        ("sub_exist", ctypes.c_short),
        ("dummy", ctypes.c_short),
        ("d_f", ctypes.c_char * 36),
    ]


class IDBPDFADIR(ctypes.Structure):
    _pack_ = 4
    _fields_ = [
        ("path", ctypes.c_char * 212),
        ("req_num", ctypes.c_short),
        ("size_kind", ctypes.c_short),
        ("type", ctypes.c_short),
        ("dummy", ctypes.c_short),
    ]


_DATE = [(n, ctypes.c_short) for n in ("year", "mon", "day", "hour", "min", "sec")]


class ODBPDFADIR(ctypes.Structure):
    _pack_ = 4
    _fields_ = [
        ("data_kind", ctypes.c_short),
        *_DATE,
        ("dummy", ctypes.c_short),
        ("dummy2", ctypes.c_int32),
        ("size", ctypes.c_int32),
        ("attr", ctypes.c_uint32),
        ("d_f", ctypes.c_char * 36),
        ("comment", ctypes.c_char * 52),
        ("o_time", ctypes.c_char * 12),
    ]


class IDBPDFPRG(ctypes.Structure):
    _pack_ = 4
    _fields_ = [
        ("path", ctypes.c_char * 244),
        ("size_kind", ctypes.c_short),
        ("type", ctypes.c_short),
        ("dummy", ctypes.c_short),
    ]


class ODBPDFPRG(ctypes.Structure):
    _pack_ = 4
    _fields_ = [
        *_DATE,
        ("size", ctypes.c_int32),
        ("attr", ctypes.c_uint32),
        ("comment", ctypes.c_char * 52),
        ("o_time", ctypes.c_char * 12),
    ]


class ODBPDFNFIL(ctypes.Structure):
    _pack_ = 4
    _fields_ = [("dir_num", ctypes.c_short), ("file_num", ctypes.c_short)]


assert ctypes.sizeof(ODBPDFADIR) == 128 and ctypes.sizeof(ODBPDFPRG) == 84


@asynccontextmanager
async def files_cnc(set_name: str, clock: ManualClock | None = None) -> AsyncIterator[Cnc]:
    async with served_cnc(set_name, demo_machine(set_name, clock)) as cnc:
        yield cnc


def sent(rec: Recorder, call: LibraryCall) -> None:
    """The last frame the library sent is exactly the one ``call`` encodes (compared from
    its body on: the 10-byte head is the link's)."""
    assert rec.take()[-1:] == [call.encode()[0][10:]]


# --------------------------------------------------------------------------------------------
# The library's calls


async def rdpdf_drive(cnc: Cnc) -> tuple[int, list[bytes]]:
    out = ODBPDFDRV()
    rc = await cnc.call("cnc_rdpdf_drive", ctypes.byref(out))
    return rc, [bytes(out.drive[i].value) for i in range(min(out.max_num, 16))]


async def rdpdf_alldir(
    cnc: Cnc, folder: str, first: int = 0, count: int = 20, size_kind: int = 1, kind: int = 1
) -> tuple[int, list[ODBPDFADIR]]:
    n = s16(count)
    inp = IDBPDFADIR(folder.encode(), first, size_kind, kind, 0)
    out = (ODBPDFADIR * 20)()
    rc = await cnc.call("cnc_rdpdf_alldir", ctypes.byref(n), ctypes.byref(inp), out)
    return rc, list(out[: n.value]) if rc == 0 else []


async def rdpdf_prginf(
    cnc: Cnc, name: str, size_kind: int = 1, kind: int = 1
) -> tuple[int, ODBPDFPRG]:
    out = ODBPDFPRG()
    inp = IDBPDFPRG(name.encode(), size_kind, kind, 0)
    rc = await cnc.call("cnc_rdpdf_prginf", ctypes.byref(inp), ctypes.byref(out))
    return rc, out


async def text_call(cnc: Cnc, function: str, *args: Any) -> tuple[int, str]:
    b = buf(512)
    rc = await cnc.call(function, *args, b)
    return rc, b.value.decode("latin-1")


def name(text: str) -> ctypes.Array[ctypes.c_char]:
    return ctypes.create_string_buffer(text.encode())


# --------------------------------------------------------------------------------------------
# The 30i set: the folder tree


async def test_drives_and_their_use(recorder: Recorder) -> None:
    async with files_cnc("30i") as cnc:
        rc, drives = await rdpdf_drive(cnc)
        assert (rc, drives) == (0, [b"CNC_MEM"])
        sent(recorder, cnc_rdpdf_drive(CS))
        info = ODBPDFINF()
        rc = await cnc.call("cnc_rdpdf_inf", name("//CNC_MEM/"), s16(0), ctypes.byref(info))
        assert rc == 0
        sent(recorder, cnc_rdpdf_inf(CS, "//CNC_MEM/", 0))
        store = cnc.machine.path_programs(1)
        used = sum(e.size for e in await cnc.packed.read_program_directory())
        assert (info.used_page, info.all_page) == (math.ceil(used / 256), store.capacity // 256)
        # SYSTEM, MTB1, MTB2, USER, PATH1, LIBRARY and the one program
        assert (info.used_dir, info.all_dir) == (7, 6 + store.max_programs)
        rc = await cnc.call("cnc_rdpdf_inf", name("//DATA_SV/"), s16(0), ctypes.byref(info))
        assert rc == EW.DATA


async def test_the_path_folder_lists_the_packed_directory(recorder: Recorder) -> None:
    async with files_cnc("30i") as cnc:
        assert await download(cnc, NEW_PUNCHED) == 0
        recorder.take()
        rc, entries = await rdpdf_alldir(cnc, PATH1)
        assert rc == 0
        sent(recorder, cnc_rdpdf_alldir(CS, PATH1, 0, 20, 1, 1))
        packed = await cnc.packed.read_program_directory()
        assert [(e.d_f, e.data_kind, e.size, e.comment) for e in entries] == [
            (f"O{p.number:04d}".encode(), 1, p.size, p.name.encode()) for p in packed
        ]
        stored = cnc.machine.file_entry(PATH1 + "O0321").stamped
        assert stored is not None
        e = entries[1]
        assert (e.year, e.mon, e.day, e.hour, e.min, e.sec) == (
            stored.year,
            stored.month,
            stored.day,
            stored.hour,
            stored.minute,
            stored.second,
        )
        # sizes in kilobytes (rounded up), and type 0: no size, no comment
        rc, entries = await rdpdf_alldir(cnc, PATH1, size_kind=2)
        assert [e.size for e in entries] == [math.ceil(p.size / 1024) for p in packed]
        rc, entries = await rdpdf_alldir(cnc, PATH1, kind=0)
        assert [(e.size, e.comment) for e in entries] == [(0, b""), (0, b"")]
        # from the second entry on; past the last: EW_NUMBER
        rc, entries = await rdpdf_alldir(cnc, PATH1, first=1)
        assert (rc, [e.d_f for e in entries]) == (0, [b"O0321"])
        assert (await rdpdf_alldir(cnc, PATH1, first=2))[0] == EW.NUMBER
        # a count of 0 is refused by the library itself
        recorder.take()
        assert (await rdpdf_alldir(cnc, PATH1, count=0))[0] == EW.LENGTH
        assert recorder.take() == []


async def test_the_tree(recorder: Recorder) -> None:
    async with files_cnc("30i") as cnc:
        rc, entries = await rdpdf_alldir(cnc, "//CNC_MEM/")
        assert [(e.d_f, e.data_kind) for e in entries] == [
            (b"SYSTEM", 0),
            (b"MTB1", 0),
            (b"MTB2", 0),
            (b"USER", 0),
        ]
        recorder.take()
        n = s16(5)
        inp = IDBPDFSDIR(b"//CNC_MEM/", 0, 0)
        out = (ODBPDFSDIR * 5)()
        rc = await cnc.call("cnc_rdpdf_subdir", ctypes.byref(n), ctypes.byref(inp), out)
        assert rc == 0
        sent(recorder, cnc_rdpdf_subdir(CS, "//CNC_MEM/", 0, 5))
        assert [(o.d_f, o.sub_exist) for o in out[: n.value]] == [
            (b"SYSTEM", 0),
            (b"MTB1", 0),
            (b"MTB2", 0),
            (b"USER", 1),
        ]
        counts = ODBPDFNFIL()
        rc = await cnc.call("cnc_rdpdf_subdirn", name("//CNC_MEM/USER/"), ctypes.byref(counts))
        assert (rc, counts.dir_num, counts.file_num) == (0, 2, 0)
        sent(recorder, cnc_rdpdf_subdirn(CS, "//CNC_MEM/USER/"))
        rc = await cnc.call("cnc_rdpdf_subdirn", name(PATH1), ctypes.byref(counts))
        assert (rc, counts.dir_num, counts.file_num) == (0, 0, 1)
        rc = await cnc.call(
            "cnc_rdpdf_subdirn", name("//CNC_MEM/USER/PATH2/"), ctypes.byref(counts)
        )
        assert rc == EW.DATA


async def test_file_information(recorder: Recorder) -> None:
    async with files_cnc("30i") as cnc:
        rc, info = await rdpdf_prginf(cnc, PATH1 + "O0001")
        assert rc == 0
        sent(recorder, cnc_rdpdf_prginf(CS, PATH1 + "O0001", 1, 1))
        (entry,) = await cnc.packed.read_program_directory()
        assert (info.size, info.comment, info.attr) == (entry.size, entry.name.encode(), 0)
        rc, info = await rdpdf_prginf(cnc, PATH1 + "O0001", 0, 0)
        assert (rc, info.size, info.comment) == (0, 0, b"")
        sent(recorder, cnc_rdpdf_prginf(CS, PATH1 + "O0001", 0, 0))
        assert (await rdpdf_prginf(cnc, PATH1 + "O0002"))[0] == EW.DATA


async def test_the_current_folder(recorder: Recorder) -> None:
    async with files_cnc("30i") as cnc:
        assert await text_call(cnc, "cnc_rdpdf_curdir", s16(1)) == (0, PATH1)
        sent(recorder, cnc_rdpdf_curdir(CS, 1))
        rc = await cnc.call("cnc_wrpdf_curdir", s16(1), name("//CNC_MEM/USER/"))
        assert rc == 0
        sent(recorder, cnc_wrpdf_curdir(CS, 1, "//CNC_MEM/USER/"))
        assert await text_call(cnc, "cnc_rdpdf_curdir", s16(1)) == (0, "//CNC_MEM/USER/")
        assert await text_call(cnc, "cnc_rdpdf_curdir", s16(2)) == (0, PATH1)
        # a relative name is of the current folder
        rc, info = await rdpdf_prginf(cnc, "PATH1/O0001")
        assert rc == 0 and info.comment == b"DEMO CONTOUR"
        assert await cnc.call("cnc_wrpdf_curdir", s16(1), name("//CNC_MEM/NOPE/")) == EW.DATA
        assert await text_call(cnc, "cnc_rdpdf_curdir", s16(3)) == (EW.DATA, "")


async def test_main_program_and_delete(recorder: Recorder) -> None:
    clock = ManualClock()
    async with files_cnc("30i", clock) as cnc:
        assert await download(cnc, NEW_PUNCHED) == 0
        recorder.take()
        assert await text_call(cnc, "cnc_pdf_rdmain") == (0, PATH1 + "O0001")
        sent(recorder, cnc_pdf_rdmain(CS))
        # MDI (served_cnc's mode): a program search is refused
        assert await cnc.call("cnc_pdf_slctmain", name(PATH1 + "O0321")) == EW.MODE
        sent(recorder, cnc_pdf_slctmain(CS, PATH1 + "O0321"))
        cnc.machine.set_panel(1)  # MEM
        assert await cnc.call("cnc_pdf_slctmain", name(PATH1 + "O0321")) == 0
        assert (await cnc.packed.read_program_numbers()).main == 321
        assert await text_call(cnc, "cnc_pdf_rdmain") == (0, PATH1 + "O0321")
        assert await cnc.call("cnc_pdf_slctmain", name(PATH1 + "O0555")) == EW.DATA
        # running: its file is not deleted
        await cnc.packed.sim.cycle_start()
        clock.advance(0.2)
        assert await cnc.call("cnc_pdf_del", name(PATH1 + "O0321")) == EW.REJECT
        assert [e.number for e in await cnc.packed.read_program_directory()] == [1, 321]
        await cnc.packed.sim.reset()
        recorder.take()
        assert await cnc.call("cnc_pdf_del", name(PATH1 + "O0321")) == 0
        sent(recorder, cnc_pdf_del(CS, PATH1 + "O0321"))
        assert [e.number for e in await cnc.packed.read_program_directory()] == [1]
        assert await cnc.call("cnc_pdf_del", name(PATH1 + "O0321")) == EW.DATA
        assert await cnc.call("cnc_pdf_del", name("//CNC_MEM/USER/")) == EW.DATA
        assert await text_call(cnc, "cnc_pdf_rdmain") == (0, "")


async def test_the_folders_of_a_running_machine() -> None:
    """While O0001 runs: the listing and the file are the packed directory's, the main file
    is the running program's, and the program is not deleted."""
    clock = ManualClock()
    async with files_cnc("30i", clock) as cnc:
        cnc.machine.set_panel(1)
        await cnc.packed.sim.cycle_start()
        clock.advance(1.5)
        assert (await cnc.packed.read_status()).run == 3  # STRT
        numbers = await cnc.packed.read_program_numbers()
        assert await text_call(cnc, "cnc_pdf_rdmain") == (0, f"{PATH1}O{numbers.main:04d}")
        rc, entries = await rdpdf_alldir(cnc, PATH1)
        (packed,) = await cnc.packed.read_program_directory()
        assert (rc, [(e.d_f, e.size) for e in entries]) == (0, [(b"O0001", packed.size)])
        assert (await rdpdf_prginf(cnc, PATH1 + "O0001"))[1].size == packed.size
        assert await cnc.call("cnc_pdf_del", name(PATH1 + "O0001")) == EW.REJECT
        # selecting by file is the program search cnc_search makes
        search = await cnc.call("cnc_search", s16(1))
        assert await cnc.call("cnc_pdf_slctmain", name(PATH1 + "O0001")) == search


async def dwnstart4(cnc: Cnc, folder: str, data: bytes) -> int:
    """``cnc_dwnstart4(0, folder)``, ``cnc_download4``, ``cnc_dwnend4``."""
    rc = await cnc.call("cnc_dwnstart4", s16(0), name(folder))
    if rc:
        return rc
    n = ctypes.c_int32(len(data))
    rc = await cnc.call("cnc_download4", ctypes.byref(n), ctypes.create_string_buffer(data))
    assert rc == 0 and n.value == len(data)
    return await cnc.call("cnc_dwnend4")


async def test_transfers_by_folder_go_to_its_path() -> None:
    """``cnc_dwnstart4`` into ``PATH2`` stores in path 2 and ``cnc_upstart4`` of a file
    of ``PATH2`` reads path 2's program, from a handle on path 1; a folder of no path is
    refused (EW_DATA)."""
    machine = two_path_lathe()
    async with served_cnc("30i", machine) as cnc:
        assert await dwnstart4(cnc, "//CNC_MEM/USER/PATH2/", NEW_PUNCHED) == 0
        assert [e.number for e in machine.program_directory(path=2)] == [321]
        assert machine.program_directory(path=1) == []
        rc, entries = await rdpdf_alldir(cnc, "//CNC_MEM/USER/PATH2/")
        assert (rc, [e.d_f for e in entries]) == (0, [b"O0321"])
        rc = await cnc.call("cnc_upstart4", s16(0), name("//CNC_MEM/USER/PATH2/O0321"))
        assert rc == 0
        out = b""
        b = buf(2048)
        for _ in range(20):
            n = ctypes.c_int32(1024)
            rc = await cnc.call("cnc_upload4", ctypes.byref(n), b)
            if rc:
                break
            out += b.raw[: n.value]
        assert rc == -2 and await cnc.call("cnc_upend4") == 0
        assert b"O0321 (NATIVE)" in out
        assert await dwnstart4(cnc, "//CNC_MEM/USER/LIBRARY/", NEW_PUNCHED) == EW.DATA
        assert (
            await cnc.call("cnc_upstart4", s16(0), name("//CNC_MEM/USER/PATH1/O0321")) == EW.NUMBER
        )
        await cnc.call("cnc_upend4")


# --------------------------------------------------------------------------------------------
# The 16i set: no program folders


async def test_a_16i_has_no_folders(recorder: Recorder) -> None:
    async with files_cnc("16i") as cnc:
        rc, _ = await rdpdf_drive(cnc)
        assert rc == EW.FUNC
        sent(recorder, cnc_rdpdf_drive(CommandSet.FS16I))
        assert (await rdpdf_alldir(cnc, PATH1))[0] == EW.FUNC
        sent(recorder, cnc_rdpdf_alldir(CommandSet.FS16I, PATH1, 0, 20, 1, 1))
        assert (await text_call(cnc, "cnc_rdpdf_curdir", s16(1)))[0] == EW.FUNC
        assert (await rdpdf_prginf(cnc, PATH1 + "O0001"))[0] == EW.FUNC
        assert (await text_call(cnc, "cnc_pdf_rdmain"))[0] == EW.FUNC
        assert await cnc.call("cnc_pdf_del", name(PATH1 + "O0001")) == EW.FUNC
        assert [e.number for e in await cnc.packed.read_program_directory()] == [1]
