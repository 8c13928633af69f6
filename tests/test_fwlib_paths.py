"""FANUC's own FOCAS library on a twin-turret lathe (two paths) served by :class:`FocasServer`.

Skipped unless ``FOCAS_NET_FWLIB`` names FANUC's libfwlib32 (x86-64 Linux, never part of this
repository). In both command sets (a 16i-class control, open answer version 2, and a 0i-F,
version 3), ``cnc_getpath`` gives (1, 2), ``cnc_setpath`` selects each path in turn, and each
path reads its own values through the library: status, positions, dynamic data, program
numbers and name, sequence number, parts count, macro variables, alarms and the sysinfo stored
at connect time; ``cnc_setpath(3)`` fails with EW_PATH in the library itself. The machine's
figures of each path (``tests/paths_support.py``) are what every value is checked against.
"""

from __future__ import annotations

import ctypes
import struct
from collections.abc import AsyncIterator
from decimal import Decimal
from pathlib import Path

import pytest
from fwlib_support import LIBRARY, Cnc, buf, download, s16, served_cnc, upload, us
from paths_support import SHARED_MACRO, VALUES, PathValues, twin_turret

from focas_net.adapters._native_cnc import path_sysinfo
from focas_net.errors import EW
from focas_net.sim import POSITION_DECIMALS, load_machine
from focas_net.sim.nc import ManualClock

pytestmark = pytest.mark.skipif(
    not LIBRARY,
    reason="set FOCAS_NET_FWLIB to the path of FANUC's libfwlib32 (e.g. libfwlib32.so.1) "
    "to run FANUC's library against the simulator",
)

#: The open answer's max axes (the machine's ODBSYS max_axis).
MAX_AXES = 8
#: The example twin-turret lathe.
EXAMPLE = Path(__file__).parent.parent / "examples" / "lathe_2path.toml"


@pytest.fixture(params=["16i", "30i"])
async def cnc(request: pytest.FixtureRequest) -> AsyncIterator[Cnc]:
    machine = twin_turret(request.param)
    async with served_cnc(request.param, machine) as served:
        yield served


async def getpath(cnc: Cnc) -> tuple[int, int, int]:
    path, most = s16(0), s16(0)
    rc = await cnc.call("cnc_getpath", ctypes.byref(path), ctypes.byref(most))
    return rc, path.value, most.value


async def setpath(cnc: Cnc, path: int) -> int:
    return await cnc.call("cnc_setpath", s16(path))


def _paths() -> list[tuple[int, PathValues]]:
    return list(enumerate(VALUES, 1))


# --------------------------------------------------------------------------------------------
# Selecting a path


async def test_getpath_and_setpath(cnc: Cnc) -> None:
    assert await getpath(cnc) == (0, 1, 2)
    assert await setpath(cnc, 2) == 0
    assert await getpath(cnc) == (0, 2, 2)
    # a path past the last: the library refuses it (its table of 10 paths holds no third) and
    # keeps the path selected
    assert await setpath(cnc, 3) == EW.PATH
    assert await setpath(cnc, 10) == EW.PATH
    assert await getpath(cnc) == (0, 2, 2)
    # 0 (and below) selects path 1
    assert await setpath(cnc, 0) == 0
    assert await getpath(cnc) == (0, 1, 2)


async def test_sysinfo_of_each_path(cnc: Cnc) -> None:
    """``cnc_sysinfo`` answers the 0x18 record of the selected path, read at connect time."""
    for path, v in _paths():
        assert await setpath(cnc, path) == 0
        b = buf(18)
        assert await cnc.call("cnc_sysinfo", b) == 0
        addinfo, max_axis, *texts = struct.unpack("<hh2s2s4s4s2s", b.raw)
        i = path_sysinfo(cnc.machine, path)
        assert (addinfo, max_axis) == (i.addinfo, i.max_axis)
        assert [t.decode() for t in texts] == [i.cnc_type, i.mt_type, i.series, i.version, i.axes]
        assert (texts[1], texts[4]) == (b"TT", f"{len(v.axes):02d}".encode())


# --------------------------------------------------------------------------------------------
# Each path reads its own values


async def test_statinfo_of_each_path(cnc: Cnc) -> None:
    for path, v in _paths():
        assert await setpath(cnc, path) == 0
        b = buf(18)
        assert await cnc.call("cnc_statinfo", b) == 0
        _, _, aut, run, motion, mstb, emergency, alarm, edit = struct.unpack("<9h", b.raw)
        st = cnc.machine.status(path=path)
        assert (aut, run, motion, mstb, emergency, alarm, edit) == (
            st.aut, st.run, st.motion, st.mstb, st.emergency, st.alarm, st.edit,
        )  # fmt: skip
        assert (aut, alarm) == (v.mode, 1)


async def test_positions_of_each_path(cnc: Cnc) -> None:
    for path, v in _paths():
        assert await setpath(cnc, path) == 0
        n = len(v.axes)
        # an all-axes read needs room for the path's axes (16i set) or the max axes (30i set)
        slots = n if cnc.set_name == "16i" else MAX_AXES
        for fn, want in (
            ("cnc_absolute", v.absolute),
            ("cnc_machine", v.machine),
            ("cnc_relative", v.relative),
            ("cnc_distance", v.distance),
        ):
            b = buf(4 + 4 * 32)
            assert await cnc.call(fn, s16(-1), s16(4 + 4 * slots), b) == 0, fn
            assert struct.unpack_from(f"<{n}i", b.raw, 4) == want, fn
            b = buf(8)
            assert await cnc.call(fn, s16(2), s16(8), b) == 0, fn
            assert struct.unpack_from("<hhi", b.raw)[1:] == (2, want[1]), fn
        num = s16(MAX_AXES)
        b = buf(48 * MAX_AXES)
        assert await cnc.call("cnc_rdposition", s16(-1), ctypes.byref(num), b) == 0
        assert num.value == n
        for i, name in enumerate(v.axes):
            for k, want in enumerate((v.absolute, v.machine, v.relative, v.distance)):
                d, dec, _, _, nm, _ = struct.unpack_from("<ihhhcc", b.raw, 48 * i + 12 * k)
                assert (d, dec, nm.decode()) == (want[i], POSITION_DECIMALS, name[0])


async def test_an_axis_past_the_paths_axes(cnc: Cnc) -> None:
    """Axis 3 is turret 2's B2 and not an axis of turret 1: EW_ATTRIB on path 1 (at 16i class
    the library refuses it itself, from the path record's axis count)."""
    assert await setpath(cnc, 1) == 0
    assert await cnc.call("cnc_absolute", s16(3), s16(8), buf(8)) == EW.ATTRIB
    assert await setpath(cnc, 2) == 0
    b = buf(8)
    assert await cnc.call("cnc_absolute", s16(3), s16(8), b) == 0
    assert struct.unpack_from("<hhi", b.raw)[1:] == (3, VALUES[1].absolute[2])


async def test_dynamic_data_of_each_path(cnc: Cnc) -> None:
    for path, v in _paths():
        assert await setpath(cnc, path) == 0
        b = buf(28 + 16 * 32)
        assert await cnc.call("cnc_rddynamic2", s16(-1), s16(28 + 16 * MAX_AXES), b) == 0
        head = struct.unpack_from("<hhiiiiii", b.raw)
        bits = 1 << v.alarm[1]
        assert head[1:] == (-1, bits, v.running, v.main, v.sequence, v.feed, v.speed)
        n = len(v.axes)
        arrays = [struct.unpack_from(f"<{n}i", b.raw, 28 + 4 * MAX_AXES * k) for k in range(4)]
        assert arrays == [v.absolute, v.machine, v.relative, v.distance]


async def test_programs_and_sequence_of_each_path(cnc: Cnc) -> None:
    for path, v in _paths():
        assert await setpath(cnc, path) == 0
        b = buf(8)
        assert await cnc.call("cnc_rdprgnum", b) == 0
        assert struct.unpack_from("<hh", b.raw, 4) == (v.running, v.main)
        b = buf(12)
        assert await cnc.call("cnc_rdprgnumo8", b) == 0
        assert struct.unpack_from("<ii", b.raw, 4) == (v.running, v.main)
        b = buf(40)
        assert await cnc.call("cnc_exeprgname", b) == 0
        name, number = b.raw[:36].rstrip(b"\0"), struct.unpack_from("<i", b.raw, 36)[0]
        assert (name, number) == (f"O{v.running}".encode(), v.running)
        b = buf(8)
        assert await cnc.call("cnc_rdseqnum", b) == 0
        assert struct.unpack_from("<i", b.raw, 4)[0] == v.sequence
        for fn, want in (("cnc_actf", v.feed), ("cnc_acts", v.speed)):
            b = buf(8)
            assert await cnc.call(fn, b) == 0
            assert struct.unpack_from("<i", b.raw, 4)[0] == want, fn


async def rdmacro(cnc: Cnc, number: int) -> Decimal | None:
    b = buf(12)
    assert await cnc.call("cnc_rdmacro", s16(number), s16(10), b) == 0
    _, _, mcr, dec = struct.unpack("<hhih2x", b.raw)
    return None if dec == -1 else Decimal(mcr).scaleb(-dec)


async def test_parts_and_macros_of_each_path(cnc: Cnc) -> None:
    shared_number, shared_value = SHARED_MACRO
    for path, v in _paths():
        assert await setpath(cnc, path) == 0
        # the parts count: parameter 6711 (a path-type parameter) and its variable #3901
        b = buf(8)
        assert await cnc.call("cnc_rdparam", s16(6711), s16(0), s16(8), b) == 0
        assert struct.unpack_from("<i", b.raw, 4)[0] == v.parts
        assert await rdmacro(cnc, 3901) == v.parts
        assert await rdmacro(cnc, 100) == v.macro  # each path's own #100
        assert await rdmacro(cnc, shared_number) == shared_value  # #500-#999 are shared
    # a write goes to the selected path
    assert await setpath(cnc, 2) == 0
    assert await cnc.call("cnc_wrmacro", s16(101), s16(10), ctypes.c_int32(125), s16(1)) == 0
    assert cnc.machine.read_macro(101, path=2) == Decimal("12.5")
    assert cnc.machine.read_macro(101, path=1) is None


async def test_alarms_of_each_path(cnc: Cnc) -> None:
    for path, v in _paths():
        assert await setpath(cnc, path) == 0
        axis, alm_type, number, message = v.alarm
        num = s16(10)
        b = buf(44 * 10)
        assert await cnc.call("cnc_rdalmmsg", s16(-1), ctypes.byref(num), b) == 0
        assert num.value == 1  # that path's alarm only
        alm_no, kind, axis_no, _, length = struct.unpack_from("<ihhhh", b.raw)
        assert (alm_no, kind, axis_no, b.raw[12 : 12 + length].decode()) == (
            number, alm_type, axis, message,
        )  # fmt: skip
        bits = ctypes.c_int64(0)
        assert await cnc.call("cnc_alarm2", ctypes.byref(bits)) == 0
        assert bits.value & 0xFFFFFFFF == 1 << alm_type
    # the history is the machine's: both alarms, whichever path is selected
    b = buf(6 + 48 * 2)
    assert await cnc.call("cnc_rdalmhistry", us(1), us(2), us(6 + 48 * 2), b) == 0
    numbers = {struct.unpack_from("<hhh", b.raw, 6 + 48 * i)[2] for i in range(2)}
    assert numbers == {v.alarm[2] for v in VALUES}


@pytest.mark.parametrize("set_name", ["16i", "30i"])
async def test_a_single_path_machine_refuses_path_2(set_name: str) -> None:
    """A single-path machine's open answer has one record: past it the library reads what the
    handle holds and may let ``cnc_setpath(2)`` through; then the server answers the blocks
    of path 2 EW_PATH. Either way the caller gets EW_PATH."""
    async with served_cnc(set_name) as cnc:
        assert await getpath(cnc) == (0, 1, 1)
        rc = await setpath(cnc, 2)
        if rc == 0:
            assert await cnc.call("cnc_statinfo", buf(18)) == EW.PATH
            assert await setpath(cnc, 1) == 0
        else:
            assert rc == EW.PATH
        assert await cnc.call("cnc_statinfo", buf(18)) == 0


@pytest.mark.parametrize("set_name", ["16i", "30i"])
async def test_the_example_twin_turret_runs_both_paths(set_name: str, tmp_path: Path) -> None:
    """``examples/lathe_2path.toml`` on a hand-stepped clock, both paths started: the library
    reads each path running its own program, then each path's part counted."""
    text = EXAMPLE.read_text(encoding="utf-8")
    if set_name == "16i":
        text = text.replace('control_class = "30i"', 'control_class = "16i"')
    (tmp_path / "lathe.toml").write_text(text, encoding="utf-8")
    clock = ManualClock()
    machine = load_machine(tmp_path / "lathe.toml", sim_clock=clock)
    async with served_cnc(set_name, machine) as cnc:
        assert await getpath(cnc) == (0, 1, 2)
        machine.set_panel(1, path=1)  # back to MEM (served_cnc put path 1 in MDI)
        for path in (1, 2):
            machine.cycle_start(path=path)
        clock.advance(1.0)
        for path, program in ((1, 1001), (2, 2001)):
            assert await setpath(cnc, path) == 0
            b = buf(18)
            assert await cnc.call("cnc_statinfo", b) == 0
            assert struct.unpack_from("<h", b.raw, 6)[0] == 3  # run: STRT
            b = buf(12)
            assert await cnc.call("cnc_rdprgnumo8", b) == 0
            assert struct.unpack_from("<ii", b.raw, 4) == (program, program)
        for _ in range(2000):  # 0.05 s steps, 100 s of machine time: a part takes about 30
            clock.advance(0.05)
            if all(machine.status(path=p).run == 0 for p in (1, 2)):
                break
        for path in (1, 2):
            assert await setpath(cnc, path) == 0
            b = buf(8)
            assert await cnc.call("cnc_rdparam", s16(6711), s16(0), s16(8), b) == 0
            assert struct.unpack_from("<i", b.raw, 4)[0] == 1 == machine.parts_counts(path=path)[0]


async def test_programs_of_each_path(cnc: Cnc) -> None:
    """The directory, uploads and downloads are of the selected path: the library writes the
    handle's path into the upload and download start frames (body word 2..3)."""
    machine = cnc.machine
    texts = {
        1: "O1001 (TURRET 1)\nN10 G0 X10.\nN20 M30\n",
        2: "O2001 (TURRET 2)\nN10 G0 X20.\nN20 M30\n",
    }
    for path, text in texts.items():
        machine.store_program(text, path=path)
    for path, number in ((1, 1001), (2, 2001)):
        assert await setpath(cnc, path) == 0
        rc, data = await upload(cnc, number)
        assert rc == 0 and texts[path].encode() in data
        other = 2001 if path == 1 else 1001
        assert (await upload(cnc, other))[0] == EW.NUMBER  # the other path's program
    assert await setpath(cnc, 2) == 0
    assert await download(cnc, b"\nO2002 (NEW)\nN10 M30\n%") == 0
    assert [e.number for e in machine.program_directory(path=2)] == [2001, 2002]
    assert [e.number for e in machine.program_directory(path=1)] == [1001]
