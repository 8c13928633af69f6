"""FANUC's library reads what data collectors read, in both command sets, idle and running:
``cnc_gettimer``/``cnc_settimer`` (0x45/0x46), ``cnc_rdopnlsgnl`` (0x5D), the run-time
parameters 6750-6758 next to ``cnc_rdtimer``, diagnostics 4901, 410 and 4902 (a spindle's
by its number), ``#3011``/``#3012`` and the override G signals and state F signals through
``pmc_rdpmcrng``/``pmc_wrpmcrng``; each value against the machine or the packed protocol.
Skipped unless ``FOCAS_NET_FWLIB`` names FANUC's libfwlib32; the structures are this file's
own (IODBTIMER, IODBSGNL as fwlib32.h lays them out for the 16/18/21/0i/30i)."""

from __future__ import annotations

import ctypes
import struct
import tomllib
from collections.abc import AsyncIterator
from dataclasses import astuple
from datetime import UTC, datetime
from decimal import Decimal

import pytest
from fwlib_support import LIBRARY, MACHINE_16I, Cnc, buf, rdparam, s16, served_cnc, us

from focas_net.sim import DEMO_PROGRAM, Machine, default_machine, machine_from_dict
from focas_net.sim.nc import ManualClock

pytestmark = pytest.mark.skipif(
    not LIBRARY,
    reason="set FOCAS_NET_FWLIB to the path of FANUC's libfwlib32 (e.g. libfwlib32.so.1) "
    "to run FANUC's library against the simulator",
)

WALL = datetime(2026, 12, 7, 4, 30, 15, tzinfo=UTC)
G, F = 0, 1  # pmc_rdpmcrng area codes


class IODBTIMER(ctypes.Structure):
    _pack_ = 4
    _fields_ = [(name, ctypes.c_short) for name in ("type", "dummy", "a", "b", "c")]


class IODBSGNL(ctypes.Structure):
    _pack_ = 4
    _fields_ = [
        (name, ctypes.c_short)
        for name in (
            "datano type mode hndl_ax hndl_mv rpd_ovrd jog_ovrd feed_ovrd spdl_ovrd blck_del "
            "sngl_blck machn_lock dry_run mem_prtct feed_hold"
        ).split()
    ]


def _machine(set_name: str) -> Machine:
    """The set's machine with G and F areas and the demo program, on a manual clock."""
    clock = ManualClock(0.0)
    if set_name == "30i":
        return default_machine(sim_clock=clock, clock=lambda: WALL)
    data = tomllib.loads(MACHINE_16I.read_text())
    data["pmc"] |= {"G": {"size": 768}, "F": {"size": 768, "write_protected": True}}
    m = machine_from_dict(data, clock=lambda: WALL)
    m.set_clock(ManualClock(m.sim_clock.now() + 1.0))
    m.store_program(DEMO_PROGRAM)
    return m


@pytest.fixture(params=["30i", "16i"])
async def cnc(request: pytest.FixtureRequest) -> AsyncIterator[Cnc]:
    async with served_cnc(request.param, _machine(request.param)) as served:
        yield served


def _run(cnc: Cnc, seconds: float) -> None:
    """Run the demo program ``seconds`` of machine time."""
    m = cnc.machine
    m.set_panel(1)
    m.select_program(1)
    m.cycle_start()
    clock = m.sim_clock
    assert isinstance(clock, ManualClock)
    clock.advance(seconds)


async def _gettimer(cnc: Cnc, kind: int) -> tuple[int, tuple[int, int, int]]:
    t = IODBTIMER(type=kind)
    rc = await cnc.call("cnc_gettimer", ctypes.byref(t))
    return rc, (t.a, t.b, t.c)


async def _settimer(cnc: Cnc, kind: int, a: int, b: int, c: int) -> int:
    return await cnc.call("cnc_settimer", ctypes.byref(IODBTIMER(type=kind, a=a, b=b, c=c)))


async def test_the_clock_reads_and_is_set(cnc: Cnc) -> None:
    assert await _gettimer(cnc, 0) == (0, (2026, 12, 7))
    assert await _gettimer(cnc, 1) == (0, (4, 30, 15))
    assert await _settimer(cnc, 0, 2030, 2, 28) == 0
    assert await _settimer(cnc, 1, 23, 59, 1) == 0
    assert cnc.machine.now() == datetime(2030, 2, 28, 23, 59, 1, tzinfo=UTC)
    assert await _gettimer(cnc, 0) == (0, (2030, 2, 28))
    assert await cnc.packed.read_macro(3011) == Decimal(20300228)
    assert await cnc.packed.read_macro(3012) == Decimal(235901)
    assert await _settimer(cnc, 0, 2030, 2, 30) == 5  # EW_DATA: no such date
    assert await _settimer(cnc, 1, 24, 0, 0) == 5
    assert await _gettimer(cnc, 2) == (3, (0, 0, 0))  # EW_NUMBER


async def test_clock_variables_through_the_library(cnc: Cnc) -> None:
    for number, want in ((3011, 20261207), (3012, 43015)):
        b = buf(12)
        assert await cnc.call("cnc_rdmacro", s16(number), s16(10), b) == 0
        _datano, _, mcr, dec = struct.unpack("<hhih2x", b.raw)
        assert Decimal(mcr).scaleb(-max(dec, 0)) == want


async def test_panel_signals(cnc: Cnc) -> None:
    m = cnc.machine
    m.set_overrides(80, 50, 100)
    s = IODBSGNL()
    assert await cnc.call("cnc_rdopnlsgnl", s16(0x1FFF), ctypes.byref(s)) == 0
    got = [getattr(s, field[0]) for field in IODBSGNL._fields_]
    assert got == [0, 0x1FFF, *astuple(m.panel_signals())]
    assert (s.mode, s.rpd_ovrd, s.feed_ovrd) == (0, 1, 8)  # MDI, ROV 50 %, 80 %


@pytest.mark.parametrize("running", [False, True])
async def test_run_time_parameters_are_the_timers(cnc: Cnc, running: bool) -> None:
    clock = cnc.machine.sim_clock
    assert isinstance(clock, ManualClock)
    clock.advance(3725.0)
    if running:
        _run(cnc, 12.5)
    b = buf(8)
    for kind, (ms_param, min_param) in enumerate(
        ((None, 6750), (6751, 6752), (6753, 6754), (6757, 6758))
    ):
        assert await cnc.call("cnc_rdtimer", s16(kind), b) == 0
        minute, msec = struct.unpack("<ii", b.raw)
        assert await rdparam(cnc, min_param, 0) == (0, [minute])
        assert await cnc.packed.read_param(min_param) == minute
        if ms_param is not None:
            assert await rdparam(cnc, ms_param, 0) == (0, [msec])
    assert (await rdparam(cnc, 6751, 0))[1] == [12_500 if running else 0]


async def test_power_and_load_diagnostics_follow_the_loads(cnc: Cnc) -> None:
    _run(cnc, 10.0)
    for axis in (1, 2, 3):
        rc, got = await rdparam(cnc, 4901, axis, "cnc_diagnoss")
        assert (rc, got) == (0, [await cnc.packed.read_diag(4901, axis=axis)])
        assert got == [cnc.machine.servo_loads()[axis - 1] * 15]
    (load,) = cnc.machine.spindle_loads()
    for number, want in ((410, load), (4902, load * 75)):
        item = cnc.machine.diag_item(number)
        assert item is not None
        b = buf(4 + 8)
        rc = await cnc.call("cnc_diagnoss", s16(number), s16(1), s16(4 + item.width), b)
        fmt = {1: "b", 2: "h", 4: "i"}[item.width]
        got_number, spindle, value = struct.unpack_from(f"<hh{fmt}", b.raw)
        assert (rc, got_number, spindle, value) == (0, number, 1, want)  # spindle 1
        assert await cnc.packed.read_diag(number, axis=1) == want


async def _rdpmc(cnc: Cnc, area: int, first: int, count: int) -> list[int]:
    b = buf(8 + count)
    last = first + count - 1
    rc = await cnc.call("pmc_rdpmcrng", s16(area), s16(0), us(first), us(last), us(8 + count), b)
    assert rc == 0
    return list(b.raw[8 : 8 + count])


async def _wrpmc(cnc: Cnc, area: int, first: int, value: int) -> int:
    b = buf(9)
    struct.pack_into("<hhHHB", b, 0, area, 0, first, first, value)
    rc: int = await cnc.call("pmc_wrpmcrng", us(9), b)
    return rc


async def test_override_signals_both_ways(cnc: Cnc) -> None:
    m = cnc.machine
    g = await _rdpmc(cnc, G, 12, 19)
    assert (g[0], g[2] & 3, g[18]) == (155, 0, 100)  # 100 % each
    m.set_overrides(70, 25, 110)
    g = await _rdpmc(cnc, G, 12, 19)
    assert (g[0], g[2] & 3, g[18]) == (255 - 70, 2, 110)
    assert await _wrpmc(cnc, G, 12, 255 - 120) == 0
    assert await _wrpmc(cnc, G, 14, 1) == 0
    assert await _wrpmc(cnc, G, 30, 80) == 0
    assert m.overrides() == (120, 50, 80)


@pytest.mark.parametrize("running", [False, True])
async def test_state_f_signals(cnc: Cnc, running: bool) -> None:
    if running:
        _run(cnc, 5.0)
    f = await _rdpmc(cnc, F, 0, 5)
    assert (f[0] >> 6 & 1, f[1] >> 7 & 1, f[1] & 1) == (1, 1, 0)  # SA, MA, no AL
    assert f[3] == (0x20 if running else 0x08)  # MMEM running, MMDI idle (served in MDI)
    assert (f[0] >> 7 & 1, f[0] >> 5 & 1) == ((1, 1) if running else (0, 0))  # OP, STL


async def test_the_integrating_meter_counts_while_tmron_is_on(cnc: Cnc) -> None:
    clock = cnc.machine.sim_clock
    assert isinstance(clock, ManualClock)
    assert await _wrpmc(cnc, G, 53, 1) == 0  # TMRON through the library
    clock.advance(61.25)
    assert await _wrpmc(cnc, G, 53, 0) == 0
    clock.advance(30.0)
    b = buf(8)
    assert await cnc.call("cnc_rdtimer", s16(4), b) == 0
    assert struct.unpack("<ii", b.raw) == (1, 1_250)
    assert await rdparam(cnc, 6756, 0) == (0, [1])
    assert await rdparam(cnc, 6755, 0) == (0, [1_250])
