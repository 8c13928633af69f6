"""Spindles and servo figures through FANUC's library, in both command sets, idle and running.

Skipped unless ``FOCAS_NET_FWLIB`` names FANUC's libfwlib32 (see ``tests/fwlib_support.py``).
For each function the request bodies the library sends are recorded at the server and compared
byte for byte with the frames :mod:`focas_net.native.spindles` declares (what
:class:`NativeClient` sends); the values the library fills in are those of the machine, and
those the native client reads.
"""

from __future__ import annotations

import ctypes
import struct
from collections.abc import AsyncIterator
from dataclasses import dataclass
from decimal import Decimal
from pathlib import Path

import pytest
from fwlib_support import LIBRARY, MACHINE_16I, Cnc, Recorder, buf, s16, served_cnc
from support import IO_TIMEOUT

from focas_net.client.native import NativeClient
from focas_net.native import CommandSet, ServoFigure, SpindleFigure, spindles
from focas_net.native.calls import LibraryCall
from focas_net.sim import Machine, default_machine, load_machine
from focas_net.sim.nc import ManualClock

pytestmark = pytest.mark.skipif(
    not LIBRARY,
    reason="set FOCAS_NET_FWLIB to the path of FANUC's libfwlib32 (e.g. libfwlib32.so.1) "
    "to run the spindle functions through FANUC's library",
)

#: A program that turns the spindle at 3000 min^-1 and cuts along X.
PROGRAM = "O0100 (SPINDLE)\nN10 G90 G21 S3000 M3\nN20 G1 X60. F1200\nN30 M30\n"
#: ODBSPN: short datano, short type, short data[8] (MAX_SPINDLE 8 at MAX_AXIS 32).
ODBSPN = struct.Struct("<hh8h")
#: ODBACT2: short datano, short type, long data[8].
ODBACT2 = struct.Struct("<hh8i")
#: ODBSPLOAD: two LOADELM (long data, short dec, short unit, char name, suff1, suff2, reserve).
LOADELM = struct.Struct("<ihhcccc")
#: The G signals of a ladder.
G_AREA = "\n[pmc.G]\nsize = 768\n"


@dataclass
class Bench:
    cnc: Cnc
    clock: ManualClock
    recorder: Recorder
    command_set: CommandSet

    @property
    def machine(self) -> Machine:
        return self.cnc.machine

    async def sent(self, call: LibraryCall, name: str, *args: object) -> int:
        """``name(*args)`` through the library; asserts it sent exactly ``call``'s frame."""
        before = len(self.recorder.bodies)
        rc = await self.cnc.call(name, *args)
        part = call.parts[0]
        assert self.recorder.bodies[before:] == [struct.pack(">H", part.count) + part.blocks]
        return rc

    def run(self) -> None:
        machine = self.machine
        machine.store_program(PROGRAM)
        machine.set_panel(1)  # MEM
        machine.select_program(100)
        machine.cycle_start()
        self.clock.advance(1.0)


@pytest.fixture(params=["30i", "16i"])
async def bench(
    request: pytest.FixtureRequest, recorder: Recorder, tmp_path: Path
) -> AsyncIterator[Bench]:
    clock = ManualClock()
    if request.param == "30i":
        machine = default_machine(sim_clock=clock)
    else:  # the 16i-class file with the G area a ladder has (cnc_rdspeed reads G28)
        path = tmp_path / "16i.toml"
        path.write_text(MACHINE_16I.read_text(encoding="utf-8") + G_AREA, encoding="utf-8")
        machine = load_machine(path, sim_clock=clock)
    async with served_cnc(request.param, machine) as cnc:
        cs = CommandSet.FS16I if request.param == "16i" else CommandSet.FS30I
        yield Bench(cnc, clock, recorder, cs)


async def _client(bench: Bench) -> NativeClient:
    served = bench.cnc.served
    return NativeClient(served.host, served.port, timeout=IO_TIMEOUT)


@pytest.mark.parametrize("running", [False, True])
async def test_spindle_figures_follow_the_program(bench: Bench, running: bool) -> None:
    if running:
        bench.run()
    machine, cs = bench.machine, bench.command_set
    (spindle,) = machine.spindles()
    assert (spindle.speed > 0) == running and (spindle.load > 0) == running
    expected = {
        "cnc_rdspload": spindle.load,
        "cnc_rdspmaxrpm": spindle.max_speed,
        "cnc_rdspgear": spindle.gear,
    }
    figures = {
        "cnc_rdspload": SpindleFigure.LOAD,
        "cnc_rdspmaxrpm": SpindleFigure.MAX_SPEED,
        "cnc_rdspgear": SpindleFigure.GEAR,
    }
    async with await _client(bench) as native:
        for name, value in expected.items():
            for sp in (-1, 1):
                b = buf(ODBSPN.size)
                call = spindles.cnc_rdspload_figure(cs, figures[name], sp)
                assert await bench.sent(call, name, s16(sp), b) == 0
                assert ODBSPN.unpack(b.raw)[:3] == (sp, 0, value)
        b = buf(ODBACT2.size)
        assert await bench.sent(spindles.cnc_acts2(cs, -1), "cnc_acts2", s16(-1), b) == 0
        assert ODBACT2.unpack(b.raw)[2] == spindle.speed == (3000 if running else 0)
        assert await native.read_spindle_speeds() == (spindle.speed,)
        assert await native.read_spindle_max_speeds() == (spindle.max_speed,)
        assert await native.read_spindle_gears(1) == (spindle.gear,)
        assert await native.read_spindle_loads() == (spindle.load,)
        # the spindle names
        n = s16(8)
        b = buf(4 * 8)
        call = spindles.cnc_rdspdlname(cs)
        assert await bench.sent(call, "cnc_rdspdlname", ctypes.byref(n), b) == 0
        assert n.value == 1 and b.raw[:4] == b"S1\0\0"
        assert await native.read_spindle_names() == ("S1",)
        # the spindle meters: the load meter and the motor speed
        for kind in (-1, 0, 1):
            n = s16(8)
            b = buf(2 * LOADELM.size * 8)
            call = spindles.cnc_rdspmeter(cs, kind)
            assert await bench.sent(call, "cnc_rdspmeter", s16(kind), ctypes.byref(n), b) == 0
            assert n.value == 1
            load = LOADELM.unpack_from(b.raw, 0)
            speed = LOADELM.unpack_from(b.raw, LOADELM.size)
            if kind in (-1, 0):
                assert load[:5] == (spindle.load, 0, 0, b"S", b"1")
            if kind in (-1, 1):
                assert speed[:5] == (spindle.speed, 0, 1, b"S", b"1")
            (meter,) = await native.read_spindle_meters(kind)
            assert meter.name == "S1"
            assert meter.load == (Decimal(spindle.load) if kind != 1 else None)
            assert meter.speed == (Decimal(spindle.speed) if kind != 0 else None)


@pytest.mark.parametrize("running", [False, True])
async def test_servo_figures_by_selector(bench: Bench, running: bool) -> None:
    if running:
        bench.run()
    machine, cs = bench.machine, bench.command_set
    loads, speeds, gains = machine.servo_loads(), machine.servo_speeds(), machine.loop_gains()
    assert (speeds[0] == 120) == running  # X at F1200 over a 10 mm lead
    assert gains == (3000, 3000, 3000)
    async with await _client(bench) as native:
        for name, figure, width, values in (
            ("cnc_rdloopgain", ServoFigure.LOOP_GAIN, 4, gains),
            ("cnc_rdcurrent", ServoFigure.LOAD, 2, loads),
            ("cnc_rdsrvspeed", ServoFigure.SPEED, 4, speeds),
        ):
            b = buf(width * 8)
            call = getattr(spindles, name)(cs)
            assert await bench.sent(call, name, b) == 0
            got = struct.unpack_from(f"<{len(values)}{'h' if width == 2 else 'i'}", b.raw)
            assert got == values
            assert await native.read_servo_figures(figure) == values
        n = s16(8)
        b = buf(12 * 8)
        assert await bench.cnc.call("cnc_rdsvmeter", ctypes.byref(n), b) == 0
        assert [struct.unpack_from("<i", b.raw, 12 * i)[0] for i in range(3)] == list(loads)


@pytest.mark.parametrize("running", [False, True])
async def test_rdspeed(bench: Bench, running: bool) -> None:
    """The feed and the spindle speed; in the 16i set the library reads parameters 3106, 3107
    and 9936 (every machine has them), the modal group 4 and G28 as well."""
    if running:
        bench.run()
    b = buf(24)
    call = spindles.cnc_rdspeed(bench.command_set, -1)
    assert await bench.sent(call, "cnc_rdspeed", s16(-1), b) == 0
    feed, *_ = struct.unpack_from("<ihhhcc", b.raw)
    speed, _dec, unit, disp, name, suffix = struct.unpack_from("<ihhhcc", b.raw, 12)
    # the 30i set names the spindle from 0x8A; the 16i set gives a suffix only on a lathe
    named = b"1" if bench.command_set is CommandSet.FS30I else b"\0"
    expected = (1200, 3000) if running else (0, 0)
    assert (feed, speed, unit, disp, name, suffix) == (*expected, 2, 1, b"S", named)
    for n in spindles.SPEED_PARAMS:
        assert bench.machine.read_param(n, 0) == 0


async def test_the_30i_open_answer_carries_the_controlled_spindles(bench: Bench) -> None:
    """``cnc_sysinfo_ex`` reads the open answer's body[20:22] as ``ctrl_spdl``, the word
    ``cnc_rdspmeter`` needs (EW_NOOPT, nothing sent, while it is 0)."""
    b = buf(24 + 16 * 10)
    assert await bench.cnc.call("cnc_sysinfo_ex", b) == 0
    max_axis, max_spdl, max_path, *_, ctrl_spdl, ctrl_path = struct.unpack_from("<8h", b.raw)
    assert max_axis == bench.machine.identity().max_axis and max_path == 1
    if bench.command_set is CommandSet.FS30I:
        assert (max_spdl, ctrl_spdl, ctrl_path) == (1, 1, 1)
