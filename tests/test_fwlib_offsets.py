"""FANUC's library against the simulator: tool offsets, work zero offsets and tool life
management (``cnc_rdtofs``, ``cnc_rdzofs``, ``cnc_rdtoolgrp``...), in both command sets, idle
and while a program runs.

Skipped unless ``FOCAS_NET_FWLIB`` names FANUC's libfwlib32. Each test serves the 16i-class
or the 0i-F machine file of ``tests/data`` with the tools below, on a clock the test steps,
and checks every value the library returns against the machine (the packed protocol has no
offsets; it shows the positions the offsets move).
"""

from __future__ import annotations

import struct
from collections.abc import AsyncIterator
from pathlib import Path
from typing import Any

import pytest
from fwlib_support import LIBRARY, MACHINE_16I, MACHINE_30I, Cnc, buf, i32, s16, served_cnc

from focas_net.adapters import NativeAdapter
from focas_net.errors import EW
from focas_net.native import CommandSet, LibraryCall
from focas_net.native import offsets as calls
from focas_net.sim import Machine, PathSpec, Session, ToolsSpec, load_machine
from focas_net.sim.nc import ManualClock

pytestmark = pytest.mark.skipif(
    not LIBRARY,
    reason="set FOCAS_NET_FWLIB to the path of FANUC's libfwlib32 (e.g. libfwlib32.so.1) "
    "to run FANUC's library against the simulator",
)

#: The tools of both machines (appended to their machine files).
TOOLS = """
[[tools]]
offsets = 32
work = { EXT = [0.5, 0, 0], G54 = [100.25, -50, -300.125], G55 = [1, 2, 3] }
[[tools.offset]]
number = 1
length_geometry = 150.0
length_wear = -0.02
radius_geometry = 6.0
[[tools.offset]]
number = 3
radius_wear = 0.011
[[tools.group]]
number = 1
life = 2
tools = [{ t = 5, h = 1, d = 25 }, { t = 6, h = 6, d = 26 }]
[[tools.group]]
number = 4
life = 20
type = "time"
tools = [7]
"""

#: Changes to T5 (group 1), cuts 60 mm at F600 (6 s), M30 (the machine files' rapid rates are
#: a few mm/min: every move is G1).
PROGRAM = """O0200
N10 G21 G91 G1 X0 F600
N20 T5 M6
N30 X60.
N40 M30
"""

#: The most values an all-axes read copies (FANUC's MAX_AXIS of the header is 32).
MAX_AXIS = 32


def machine_for(set_name: str, folder: Path, clock: ManualClock) -> Machine:
    source = MACHINE_16I if set_name == "16i" else MACHINE_30I
    path = folder / f"{set_name}.toml"
    path.write_text(source.read_text(encoding="utf-8") + TOOLS, encoding="utf-8")
    return load_machine(path, sim_clock=clock)


@pytest.fixture(params=["30i", "16i"])
async def cnc(request: pytest.FixtureRequest, tmp_path: Path) -> AsyncIterator[Cnc]:
    clock = ManualClock()
    async with served_cnc(request.param, machine_for(request.param, tmp_path, clock)) as c:
        c.clock = clock  # type: ignore[attr-defined]
        yield c


# --------------------------------------------------------------------------------------------
# The library's structures (little-endian, 4-byte longs)


async def rdtofs(cnc: Cnc, number: int, offset_type: int) -> tuple[int, int, int, int]:
    """``cnc_rdtofs``: rc, ODBTOFS datano, type, data."""
    b = buf(8)
    rc = await cnc.call("cnc_rdtofs", s16(number), s16(offset_type), s16(8), b)
    return (rc, *struct.unpack_from("<hhi", b.raw))


async def rdtofsr(
    cnc: Cnc, first: int, offset_type: int, last: int, values: int
) -> tuple[int, tuple[int, int, int], tuple[int, ...]]:
    """``cnc_rdtofsr``: rc, IODBTO (datano_s, type, datano_e) and ``values`` longs."""
    size = 8 + 4 * values
    b = buf(size)
    rc = await cnc.call("cnc_rdtofsr", s16(first), s16(offset_type), s16(last), s16(size), b)
    return rc, struct.unpack_from("<hhh", b.raw), struct.unpack_from(f"<{values}i", b.raw, 8)


async def rdzofs(cnc: Cnc, number: int, axis: int) -> tuple[int, int, int, tuple[int, ...]]:
    """``cnc_rdzofs``: rc, IODBZOFS datano, type, data[MAX_AXIS]."""
    b = buf(4 + 4 * MAX_AXIS)
    length = 4 + 4 * (cnc.slots if axis == -1 else 1)
    rc = await cnc.call("cnc_rdzofs", s16(number), s16(axis), s16(length), b)
    datano, kind = struct.unpack_from("<hh", b.raw)
    return rc, datano, kind, struct.unpack_from(f"<{MAX_AXIS}i", b.raw, 4)


async def rdzofsr(
    cnc: Cnc, first: int, axis: int, last: int
) -> tuple[int, tuple[int, int, int], tuple[int, ...]]:
    """``cnc_rdzofsr``: rc, IODBZOR head, the values (the open answer's max axes per number
    for -1, in both command sets)."""
    per = max_axes(cnc) if axis == -1 else 1
    values = per * (last - first + 1)
    size = 8 + 4 * values
    b = buf(size)
    rc = await cnc.call("cnc_rdzofsr", s16(first), s16(axis), s16(last), s16(size), b)
    return rc, struct.unpack_from("<hhh", b.raw), struct.unpack_from(f"<{values}i", b.raw, 8)


def max_axes(cnc: Cnc) -> int:
    """The max axes of the open answer (the records of an all-axes work offset)."""
    return cnc.machine.identity().max_axis


async def wrzofs(cnc: Cnc, number: int, axis: int, values: list[int]) -> int:
    """``cnc_wrzofs`` of ``values`` (IODBZOFS; the slots after them 0)."""
    b = buf(4 + 4 * MAX_AXIS)
    struct.pack_into("<hh", b, 0, number, axis)
    struct.pack_into(f"<{len(values)}i", b, 4, *values)
    length = 4 + 4 * (cnc.slots if axis == -1 else 1)
    return await cnc.call("cnc_wrzofs", s16(length), b)


async def life3(cnc: Cnc, function: str, group: int) -> tuple[int, int, int]:
    """``cnc_rdntool`` / ``cnc_rdlife`` / ``cnc_rdcount``: rc, ODBTLIFE3 datano, data."""
    b = buf(8)
    rc = await cnc.call(function, s16(group), b)
    datano, _, data = struct.unpack_from("<hhi", b.raw)
    return rc, datano, data


async def rdtoolgrp(
    cnc: Cnc, group: int, tools: int
) -> tuple[int, tuple[int, ...], list[tuple[int, ...]]]:
    """``cnc_rdtoolgrp``: rc, (grp_num, ntool, life, count), each tool's 5 longs."""
    size = 20 + 20 * tools
    b = buf(size)
    rc = await cnc.call("cnc_rdtoolgrp", s16(group), s16(size), b)
    (grp,) = struct.unpack_from("<h", b.raw)
    ntool, life, count = struct.unpack_from("<3i", b.raw, 8)
    entries = [struct.unpack_from("<5i", b.raw, 20 + 20 * i) for i in range(tools)]
    return rc, (grp, ntool, life, count), entries


async def short_after_head(cnc: Cnc, function: str) -> tuple[int, int]:
    """``cnc_rdmaxgrp`` / ``cnc_rdmaxtool``: rc, ODBLFNO data."""
    b = buf(8)
    rc = await cnc.call(function, b)
    return rc, struct.unpack_from("<h", b.raw, 4)[0]


# --------------------------------------------------------------------------------------------
# Tool offsets


async def test_tool_offsets_read_one_by_one_and_by_range(cnc: Cnc) -> None:
    machine = cnc.machine
    for number in (1, 2, 3):
        for offset_type in range(4):
            (expected,) = machine.tool_offsets(number, number, offset_type)[0]
            assert await rdtofs(cnc, number, offset_type) == (0, number, offset_type, expected)
    assert (await rdtofs(cnc, 1, 3))[3] == 150_000  # 150 mm in 0.001 mm
    rc, head, values = await rdtofsr(cnc, 1, 2, 3, 3)
    assert (rc, head) == (0, (1, 2, 3))
    assert values == tuple(row[0] for row in machine.tool_offsets(1, 3, 2))
    rc, head, values = await rdtofsr(cnc, 1, -1, 3, 12)  # memory C: 4 types per number
    assert (rc, head) == (0, (1, -1, 3))
    assert values == tuple(v for row in machine.tool_offsets(1, 3, None) for v in row)
    assert values[:4] == (0, 6000, -20, 150_000)


async def test_tool_offset_info_is_memory_c_and_the_count(cnc: Cnc) -> None:
    b = buf(8)
    assert await cnc.call("cnc_rdtofsinfo", b) == 0
    assert struct.unpack_from("<hh", b.raw) == (2, 32)
    assert await cnc.call("cnc_rdtofsinfo2", b) == 0
    assert struct.unpack_from("<hhh", b.raw) == (2, 32, 1)


async def test_tool_offset_refusals(cnc: Cnc) -> None:
    assert (await rdtofs(cnc, 33, 0))[0] == EW.NUMBER  # 32 offsets
    assert (await rdtofs(cnc, 1, 4))[0] == EW.ATTRIB  # memory C has types 0..3


async def test_write_a_tool_offset_and_the_program_applies_it(cnc: Cnc) -> None:
    machine = cnc.machine
    rc = await cnc.call("cnc_wrtofs", s16(2), s16(3), s16(8), i32(-12_345))
    assert rc == 0
    assert machine.tool_offsets(2, 2, 3) == [(-12_345,)]
    assert (await rdtofs(cnc, 2, 3))[3] == -12_345
    assert machine.path_engine().tool_offsets[2] == pytest.approx(-12.345)
    rc = await cnc.call("cnc_wrtofs", s16(2), s16(3), s16(8), i32(10**6))
    assert rc == EW.DATA  # beyond 999.999 mm
    assert (await rdtofs(cnc, 2, 3))[3] == -12_345


# --------------------------------------------------------------------------------------------
# Work zero offsets


async def test_work_offsets_every_axis_and_one(cnc: Cnc) -> None:
    machine = cnc.machine
    rc, datano, kind, data = await rdzofs(cnc, 1, -1)
    assert (rc, datano, kind) == (0, 1, -1)
    assert data[:3] == (100_250, -50_000, -300_125) == machine.work_offsets(1, 1, None)[0]
    assert data[3 : cnc.slots] == (0,) * (cnc.slots - 3)
    rc, datano, kind, data = await rdzofs(cnc, 0, 1)
    assert (rc, datano, kind, data[0]) == (0, 0, 1, 500)
    rc, head, values = await rdzofsr(cnc, 0, -1, 2)
    assert (rc, head) == (0, (0, -1, 2))
    per = max_axes(cnc)
    for row, expected in enumerate(machine.work_offsets(0, 2, None)):
        assert values[row * per : row * per + 3] == expected
    rc, head, values = await rdzofsr(cnc, 1, 3, 6)
    assert (rc, head) == (0, (1, 3, 6))
    assert values == (-300_125, 3000, 0, 0, 0, 0)


async def test_write_a_work_offset_moves_the_work_position(cnc: Cnc) -> None:
    machine = cnc.machine
    assert await wrzofs(cnc, 2, -1, [10_000, 20_000, -30_000]) == 0
    assert machine.work_offsets(2, 2, None) == [(10_000, 20_000, -30_000)]
    assert (await rdzofs(cnc, 2, -1))[3][:3] == (10_000, 20_000, -30_000)
    assert await wrzofs(cnc, 2, 3, [-40_000]) == 0
    assert (await rdzofs(cnc, 2, 3))[3][0] == -40_000
    assert (await rdzofs(cnc, 7, 1))[0] == EW.NUMBER
    machine.set_panel(0)  # MDI: G55 takes the offsets just written
    machine.store_program("O0300\nG55 G90 G1 X0 Y0 F6000\nM30\n")
    machine.set_panel(1)
    machine.select_program(300)
    machine.cycle_start()
    cnc.clock.advance(60)  # type: ignore[attr-defined]
    positions = await cnc.packed.read_positions("machine")
    assert positions.increments == {"X": 10_500, "Y": 20_000, "Z": 0}  # EXT X 0.5 too


# --------------------------------------------------------------------------------------------
# Tool life


async def test_tool_life_idle(cnc: Cnc) -> None:
    assert await life3(cnc, "cnc_rdntool", 1) == (0, 1, 2)
    assert await life3(cnc, "cnc_rdlife", 1) == (0, 1, 2)
    assert await life3(cnc, "cnc_rdcount", 1) == (0, 1, 0)
    assert await life3(cnc, "cnc_rdlife", 4) == (0, 4, 20)
    assert (await life3(cnc, "cnc_rdntool", 2))[0] == EW.NUMBER  # not declared
    rc, head, entries = await rdtoolgrp(cnc, 1, 2)
    assert (rc, head) == (0, (1, 2, 2, 0))
    assert entries == [(1, 5, 1, 25, 0), (2, 6, 6, 26, 0)]
    b = buf(8)
    assert await cnc.call("cnc_toolnum", s16(1), s16(2), b) == 0
    assert struct.unpack_from("<hhi", b.raw) == (1, 2, 6)
    assert await cnc.call("cnc_rdngrp", b) == 0
    assert struct.unpack_from("<i", b.raw, 4)[0] == 2
    assert await short_after_head(cnc, "cnc_rdmaxgrp") == (0, 16)
    assert await short_after_head(cnc, "cnc_rdmaxtool") == (0, 4)
    info = buf(16)
    assert await cnc.call("cnc_rdtlinfo", info) == 0
    assert struct.unpack_from("<4i", info.raw) == (16, 4, 4300, 9999)
    use = buf(20)
    assert await cnc.call("cnc_rdusegrpid", use) == 0
    assert struct.unpack_from("<3i", use.raw, 4) == (0, 0, 0)


async def test_tool_life_follows_the_running_program(cnc: Cnc) -> None:
    machine = cnc.machine
    clock: ManualClock = cnc.clock  # type: ignore[attr-defined]
    machine.store_program(PROGRAM)
    machine.set_panel(1)
    machine.select_program(200)
    machine.cycle_start()
    clock.advance(3)  # past the tool change, cutting
    use = buf(20)
    assert await cnc.call("cnc_rdusegrpid", use) == 0
    assert struct.unpack_from("<3i", use.raw, 4) == (1, 1, 1)
    rc, head, entries = await rdtoolgrp(cnc, 1, 2)
    assert (rc, head[3], entries[0][4]) == (0, 1, 1)  # T5 in use, counted at its M6
    clock.advance(60)  # the cut, then M30
    assert await life3(cnc, "cnc_rdcount", 1) == (0, 1, 1)
    machine.cycle_start()
    clock.advance(60)  # the second cycle: T5's life of 2 is reached
    assert await life3(cnc, "cnc_rdcount", 1) == (0, 1, 2)
    rc, head, entries = await rdtoolgrp(cnc, 1, 2)
    assert [e[4] for e in entries] == [2, 0]  # T5 expired
    machine.cycle_start()
    clock.advance(60)  # the third: the selection takes T6
    rc, head, entries = await rdtoolgrp(cnc, 1, 2)
    assert (head[3], [e[4] for e in entries]) == (1, [2, 1])
    assert machine.tool_group(1).in_use == 2


async def test_time_life_counts_minutes_of_cutting(cnc: Cnc) -> None:
    machine = cnc.machine
    clock: ManualClock = cnc.clock  # type: ignore[attr-defined]
    machine.store_program("O0400\nG21 G91\nT7 M6\nG1 X600. F300\nM30\n")
    machine.set_panel(1)
    machine.select_program(400)
    machine.cycle_start()
    clock.advance(300)  # the tool change, 2 minutes of cutting, M30
    assert machine.path_engine().cutting_time == pytest.approx(120)
    assert await life3(cnc, "cnc_rdcount", 4) == (0, 4, 2)


# --------------------------------------------------------------------------------------------
# The native client's frames are the library's


async def test_the_client_sends_the_frames_the_library_sends(
    cnc: Cnc, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Each call's data-request frames, as the server received them from FANUC's library,
    are those :mod:`focas_net.native.offsets` builds for the native client."""
    bodies: list[bytes] = []
    answer = NativeAdapter.answer

    def record(self: NativeAdapter, body: bytes, session: Session | None = None) -> bytes:
        bodies.append(bytes(body))
        return answer(self, body, session)

    monkeypatch.setattr(NativeAdapter, "answer", record)
    cs = CommandSet.FS16I if cnc.set_name == "16i" else CommandSet.FS30I
    eight = buf(8)
    cases: list[tuple[Any, LibraryCall]] = [
        (rdtofs(cnc, 2, 3), calls.cnc_rdtofs(cs, 2, 3)),
        (rdtofsr(cnc, 1, -1, 3, 12), calls.cnc_rdtofsr(cs, 1, -1, 3)),
        (rdzofs(cnc, 1, -1), calls.cnc_rdzofs(cs, 1, -1)),
        (rdzofsr(cnc, 0, 2, 6), calls.cnc_rdzofsr(cs, 0, 2, 6)),
        (cnc.call("cnc_rdtofsinfo", eight), calls.cnc_rdtofsinfo(cs)),
        (
            cnc.call("cnc_wrtofs", s16(2), s16(1), s16(8), i32(-9)),
            calls.cnc_wrtofs(cs, 2, 1, -9),
        ),
        (life3(cnc, "cnc_rdcount", 1), calls.cnc_rdcount(cs, 1)),
        (cnc.call("cnc_toolnum", s16(1), s16(2), eight), calls.cnc_toolnum(cs, 1, 2)),
        (cnc.call("cnc_rdngrp", eight), calls.cnc_rdngrp(cs)),
        (cnc.call("cnc_rdtlinfo", buf(16)), calls.cnc_rdtlinfo(cs)),
        (cnc.call("cnc_rdusegrpid", buf(20)), calls.cnc_rdusegrpid(cs)),
    ]
    for run, call in cases:
        bodies.clear()
        await run
        assert bodies == [frame[10:] for frame in call.encode()], call.function
    bodies.clear()
    await rdtoolgrp(cnc, 1, 2)
    expected = [calls.cnc_rdtoolgrp(cs, 1), calls.cnc_rdtoolgrp(cs, 1, 2)]
    assert bodies == [c.encode()[0][10:] for c in expected]
    bodies.clear()
    assert await wrzofs(cnc, 1, -1, [1, 2, 3]) == 0
    values = (1, 2, 3) + (0,) * (max_axes(cnc) - 3)
    assert bodies == [calls.cnc_wrzofs(cs, 1, -1, values).encode()[0][10:]]


# --------------------------------------------------------------------------------------------
# A twin-turret lathe: each path its own offsets


def _lathe(set_name: str) -> Machine:
    path1 = ToolsSpec(offsets=16, offset_values={(1, "x_geometry"): 210_000, (1, "tip"): 3})
    path2 = ToolsSpec(
        offsets=24,
        offset_values={(1, "x_geometry"): -95_500, (1, "z_wear"): 7, (1, "tip"): 8},
        work={"G54": [0, 400_000]},
    )
    return Machine(
        "lathe",
        paths=[PathSpec(("X1", "Z1"), kind="T"), PathSpec(("X2", "Z2"), kind="T")],
        control_class="16i" if set_name == "16i" else "30i",
        tools={1: path1, 2: path2},
    )


@pytest.mark.parametrize("set_name", ["30i", "16i"])
async def test_each_path_of_a_lathe_answers_its_own_offsets(set_name: str) -> None:
    async with served_cnc(set_name, _lathe(set_name)) as cnc:
        machine = cnc.machine
        assert await rdtofs(cnc, 1, 1) == (0, 1, 1, 210_000)
        assert (await rdtofs(cnc, 1, 6))[3] == 3
        assert await cnc.call("cnc_setpath", s16(2)) == 0
        for offset_type in range(7):
            (expected,) = machine.tool_offsets(1, 1, offset_type, path=2)[0]
            assert (await rdtofs(cnc, 1, offset_type))[3] == expected
        assert (await rdtofs(cnc, 1, 1))[3] == -95_500
        assert (await rdtofs(cnc, 1, 7))[0] == EW.ATTRIB  # a lathe has types 0..6
        assert (await rdtofs(cnc, 25, 0))[0] == EW.NUMBER
        rc, head, values = await rdtofsr(cnc, 1, -1, 2, 14)  # the library copies them all
        assert (rc, head) == (0, (1, -1, 2))
        assert values == tuple(v for row in machine.tool_offsets(1, 2, None, path=2) for v in row)
        b = buf(8)
        assert await cnc.call("cnc_rdtofsinfo", b) == 0
        assert struct.unpack_from("<hh", b.raw) == (1, 24)
        rc, _, _, data = await rdzofs(cnc, 1, -1)
        assert (rc, data[:2]) == (0, (0, 400_000))
