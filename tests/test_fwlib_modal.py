"""Modal data, operator messages and program pointers through FANUC's own FOCAS library,
against a real :class:`FocasServer`.

Skipped unless ``FOCAS_NET_FWLIB`` names FANUC's libfwlib32 (x86-64 Linux, never part of this
repository). In both command sets (the built-in 0i-F machine, the 30i set; the 16i-class
machine file, the 16i set) and idle and running a program that stops with ``#3006`` and then
cuts: ``cnc_modal`` (G codes one by one and all, the other data one by one and all, the axes),
``cnc_rdgcode``, ``cnc_rdcommand``, ``cnc_rdopmsg``/``2``/``3`` (``#3006`` and an external
operator message of the A area), ``cnc_exeprgname2``, ``cnc_rdactpt``, ``cnc_rdblkcount`` and
``cnc_rdmdipntr``, each compared with what the packed client reads of the same machine
(``#4001``-``#4017``, ``#4109``, ``#4119``, the program numbers) and with the native client.
"""

from __future__ import annotations

import ctypes
import struct
from collections.abc import AsyncIterator
from contextlib import asynccontextmanager
from decimal import Decimal
from pathlib import Path
from typing import Final

import pytest
from fwlib_support import LIBRARY, MACHINE_16I, Cnc, buf, i32, s16, served_cnc
from support import IO_TIMEOUT

from focas_net.client import NativeClient
from focas_net.native import G_CODE_INDEX
from focas_net.sim import ExternalMessage, Machine, default_machine, load_machine
from focas_net.sim.nc import ManualClock

pytestmark = pytest.mark.skipif(
    not LIBRARY,
    reason="set FOCAS_NET_FWLIB to the path of FANUC's libfwlib32 (e.g. libfwlib32.so.1) "
    "to run FANUC's library against the simulator",
)

SETS: Final = ["30i", "16i"]

PROGRAM: Final = (
    "O0007 (MESSAGE)\n"
    "N10 G90 G17 G54 G00 X0 Y0 Z0\n"
    "N20 #3006 = 1 (CHECK THE PART)\n"
    "N30 G91 G01 X50. F600 S1200 M3\n"
    "N40 G90 G00 X0\n"
    "N50 M30\n"
)

#: ODBMDL: datano, type, then the union (g_rdata or 8-byte aux entries: i32, char, char).
AUX: Final = "<ibbxx"


def build_machine(set_name: str, clock: ManualClock, tmp_path: Path) -> Machine:
    """The set's machine with :data:`PROGRAM` selected and the message of A0.0."""
    if set_name == "30i":
        machine = default_machine(sim_clock=clock, programs=[PROGRAM])
        machine.set_external_messages([ExternalMessage(0, 0, 2005, "COOLANT LOW")])
        return machine
    text = MACHINE_16I.read_text().replace(
        "[pmc.R]",
        '[[operator_messages]]\naddress = "A0.0"\nnumber = 2005\ntext = "COOLANT LOW"\n\n'
        "[pmc.A]\nsize = 16\n[pmc.R]",
        1,
    )
    file = tmp_path / "machine.toml"
    file.write_text(text)
    machine = load_machine(file, sim_clock=clock)
    machine.store_program(PROGRAM)
    machine.set_panel(1)
    machine.select_program(7)
    return machine


@asynccontextmanager
async def running(set_name: str, tmp_path: Path) -> AsyncIterator[tuple[Cnc, ManualClock]]:
    clock = ManualClock()
    async with served_cnc(set_name, build_machine(set_name, clock, tmp_path)) as cnc:
        cnc.machine.set_panel(1)  # MEM: served_cnc leaves MDI
        yield cnc, clock


async def modal(cnc: Cnc, kind: int, block: int = 0) -> tuple[int, bytes]:
    b = buf(4 + 8 * 32)
    rc = await cnc.call("cnc_modal", s16(kind), s16(block), b)
    datano, _ = struct.unpack_from("<hh", b.raw)
    if rc == 0:
        assert datano == kind
    return rc, b.raw[4:]


async def g_codes(cnc: Cnc, kind: int = -1) -> dict[int, tuple[str, int]]:
    b = buf(12 * 40)
    n = s16(40)
    rc = await cnc.call("cnc_rdgcode", s16(kind), s16(0), ctypes.byref(n), b)
    assert rc == 0, f"cnc_rdgcode returned {rc}"
    out = {}
    for i in range(n.value):
        group, flag, code = struct.unpack_from("<hh8s", b.raw, 12 * i)
        out[group] = (code.split(b"\x00", 1)[0].decode(), flag)
    return out


async def commands(cnc: Cnc) -> dict[str, tuple[int, int, int]]:
    b = buf(12 * 10)
    n = s16(10)
    rc = await cnc.call("cnc_rdcommand", s16(-1), s16(0), ctypes.byref(n), b)
    assert rc == 0, f"cnc_rdcommand returned {rc}"
    out = {}
    for i in range(n.value):
        adrs, _num, flag, value, dec = struct.unpack_from("<cBhii", b.raw, 12 * i)
        out[adrs.decode()] = (value, dec, flag)
    return out


async def opmsg(cnc: Cnc) -> tuple[int, int, str]:
    b = buf(6 + 256)
    rc = await cnc.call("cnc_rdopmsg", s16(0), s16(6 + 256), b)
    assert rc == 0, f"cnc_rdopmsg returned {rc}"
    number, _kind, length = struct.unpack_from("<hhh", b.raw)
    return number, length, b.raw[6 : 6 + max(length, 0)].decode()


async def opmsg3(cnc: Cnc) -> list[tuple[int, str]]:
    b = buf(5 * 262)
    n = s16(5)
    rc = await cnc.call("cnc_rdopmsg3", s16(-1), ctypes.byref(n), b)
    assert rc == 0, f"cnc_rdopmsg3 returned {rc}"
    out = []
    for i in range(n.value):
        number, _kind, length = struct.unpack_from("<hhh", b.raw, 262 * i)
        out.append((number, b.raw[262 * i + 6 : 262 * i + 6 + length].decode()))
    return out


async def pointers(cnc: Cnc) -> tuple[str, tuple[int, int], int, tuple[int, ...]]:
    text = buf(260)
    assert await cnc.call("cnc_exeprgname2", text) == 0
    program, blk = i32(), i32()
    assert await cnc.call("cnc_rdactpt", ctypes.byref(program), ctypes.byref(blk)) == 0
    count = i32()
    assert await cnc.call("cnc_rdblkcount", ctypes.byref(count)) == 0
    b = buf(16)
    assert await cnc.call("cnc_rdmdipntr", b) == 0
    return (
        text.value.decode(),
        (program.value, blk.value),
        count.value,
        struct.unpack_from("<4i", b.raw),
    )


async def check_groups_agree_with_the_macros(cnc: Cnc) -> None:
    """``cnc_modal(-1)`` and ``cnc_rdgcode(-1)`` against #4001-#4017 read by the packed
    client."""
    rc, raw = await modal(cnc, -1)
    assert rc == 0
    codes = await g_codes(cnc)
    for group in range(1, 18):
        value = await cnc.packed.read_macro(4000 + group)
        assert value is not None
        code = int(value * 10)
        assert raw[group - 1] & 0x7F == G_CODE_INDEX[group - 1][code], group
        whole, tenth = divmod(code, 10)
        text = f"G{whole:02d}" + (f".{tenth}" if tenth else "")
        assert codes[group][0] == text


@pytest.mark.parametrize("set_name", SETS)
async def test_idle_and_running(set_name: str, tmp_path: Path) -> None:
    async with running(set_name, tmp_path) as (cnc, clock):
        machine = cnc.machine
        # idle: the power-on modal state, no message, the main program's path
        await check_groups_agree_with_the_macros(cnc)
        assert (await modal(cnc, 0))[1][0] == 0  # G00, not commanded
        assert await opmsg(cnc) == (-1, 0, "")
        assert await opmsg3(cnc) == []
        assert await pointers(cnc) == ("//CNC_MEM/USER/PATH1/O0007", (7, 0), 0, (7, 0, 7, 0))
        # the A bit of the external message, then the program stops at #3006
        machine.write_pmc("A", 0, b"\x01")
        machine.cycle_start()
        clock.advance(1.0)
        assert await opmsg(cnc) == (2005, 11, "COOLANT LOW")
        assert await opmsg3(cnc) == [(2005, "COOLANT LOW"), (1, "CHECK THE PART")]
        path_text, active, count, mdi = await pointers(cnc)
        assert path_text == "//CNC_MEM/USER/PATH1/O0007"
        assert active == (7, 2) and count == 2
        assert mdi[0] == mdi[2] == 7 and PROGRAM[mdi[1] :].startswith("N20")
        machine.write_pmc("A", 0, b"\x00")
        machine.cycle_start()
        clock.advance(1.0)  # N30 cuts
        assert await opmsg3(cnc) == []
        await check_groups_agree_with_the_macros(cnc)
        rc, raw = await modal(cnc, 0)
        assert rc == 0 and raw[0] == 0x81  # G01, commanded
        rc, raw = await modal(cnc, 103)  # F
        assert rc == 0 and struct.unpack_from(AUX, raw) == (600, -128 | 3, 0)
        # the next blocks (the MTConnect adapter's F and T): the state they start from
        assert await modal(cnc, 103, 1) == await modal(cnc, 103, 2) == (rc, raw)
        rc, raw = await modal(cnc, -2)
        entries = [struct.unpack_from(AUX, raw, 8 * i) for i in range(27)]
        assert entries[3][0] == 600 and entries[7][0] == 1200  # F (103), S (107)
        if set_name == "30i":  # the 16i machine file's macro ranges end before #4100
            assert Decimal(entries[3][0]) == await cnc.packed.read_macro(4109)
            assert Decimal(entries[7][0]) == await cnc.packed.read_macro(4119)
        rc, raw = await modal(cnc, -3)
        assert rc == 0 and struct.unpack_from(AUX, raw)[0] == 50  # X50. in the block
        rc, raw = await modal(cnc, 200)
        assert rc == 0 and struct.unpack_from(AUX, raw)[0] == 50
        codes = await g_codes(cnc)
        assert codes[1] == ("G01", 1) and codes[3] == ("G91", 1) and codes[14] == ("G54", 0)
        values = await commands(cnc)
        assert values["F"] == (600, 0, 1) and values["S"] == (1200, 0, 1)
        assert values["N"] == (30, 0, 1) and values["O"] == (7, 0, 0)
        one = s16(1)  # more entries than the caller's num: the library's EW_LENGTH
        assert await cnc.call("cnc_rdcommand", s16(-1), s16(0), ctypes.byref(one), buf(24)) == 2
        numbers = await cnc.packed.read_program_numbers()
        _, active, count, mdi = await pointers(cnc)
        assert active == (numbers.running, 3) and count == 3
        assert PROGRAM[mdi[1] :].startswith("N30") and PROGRAM[mdi[3] :].startswith("N40")
        # the native client reads what the library reads
        async with NativeClient(cnc.served.host, cnc.served.port, timeout=IO_TIMEOUT) as native:
            assert (await native.read_modal_groups(1))[0].code == "G01"
            assert (await native.read_modal_values("F"))[0].value == 600
            assert await native.read_block_count() == count


@pytest.mark.parametrize("set_name", SETS)
async def test_what_the_library_and_the_control_refuse(set_name: str, tmp_path: Path) -> None:
    async with running(set_name, tmp_path) as (cnc, _clock):
        b = buf(6 + 256)
        # the library's own refusals, nothing sent
        assert await cnc.call("cnc_rdopmsg", s16(1), s16(6 + 256), b) == 4  # EW_ATTRIB
        assert await cnc.call("cnc_rdopmsg", s16(0), s16(6 + 64), b) == 2  # EW_LENGTH
        assert (await modal(cnc, 127))[0] == 3  # EW_NUMBER
        # the control's: a block past the next two, a group it has not, the one-shot table
        assert (await modal(cnc, 1, 3))[0] == 3
        assert (await modal(cnc, 22))[0] == 3
        assert (await modal(cnc, -4))[0] == 3
        assert (await modal(cnc, 203))[0] == 3  # an axis the path has not
