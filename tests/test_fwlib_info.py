"""FANUC's library reads the CNC's information from the simulator, in both command sets, and
gets what :class:`NativeClient` and the machine say.

Skipped unless ``FOCAS_NET_FWLIB`` names FANUC's libfwlib32 (see ``tests/fwlib_support.py``).
Each test serves one machine (the built-in 0i-F, the 30i set; a 16i machine file, the 16i set),
opens a library handle and a :class:`NativeClient` on it, and checks every value the library
copies into its structure: ``cnc_getfigure``, ``cnc_statinfo2`` (idle and running),
``cnc_rdsyssoft``, ``cnc_rdparanum``, ``cnc_rddiagnum``, ``cnc_rddiaginfo``, ``cnc_rdset``,
``cnc_rdsetinfo``, ``pmc_rdpmcinfo``, ``pmc_rdpmctitle``, ``cnc_rdetherinfo``
and ``cnc_rdprstrinfo``.
"""

from __future__ import annotations

import ctypes
from collections.abc import AsyncIterator
from dataclasses import dataclass

import pytest
from fwlib_support import LIBRARY, Cnc, buf, s16, served_cnc, us
from support import IO_TIMEOUT

from focas_net.client import NativeClient
from focas_net.errors import EW
from focas_net.sim import POSITION_DECIMALS, VALID_FIGURES, default_machine
from focas_net.sim.nc import ManualClock

pytestmark = pytest.mark.skipif(
    not LIBRARY,
    reason="set FOCAS_NET_FWLIB to the path of FANUC's libfwlib32 (e.g. libfwlib32.so.1) "
    "to run FANUC's library against the simulator",
)

i32 = ctypes.c_int32
MAX_AXIS = 32


class ODBST2(ctypes.Structure):
    _fields_ = [
        (name, ctypes.c_short)
        for name in (
            "hdck", "tmmode", "aut", "run", "motion", "mstb", "emergency", "alarm", "edit",
            "warning", "o3dchk", "ext_opt", "restart",
        )
    ]  # fmt: skip


class ODBSYSS(ctypes.Structure):
    _fields_ = [
        ("slot_no_p", ctypes.c_ubyte * 16),
        ("slot_no_l", ctypes.c_ubyte * 16),
        ("module_id", ctypes.c_short * 16),
        ("soft_id", ctypes.c_short * 16),
        ("soft_series", (ctypes.c_char * 5) * 16),
        ("soft_version", (ctypes.c_char * 5) * 16),
        ("soft_inst", ctypes.c_short),
        ("boot_ser", ctypes.c_char * 5),
        ("boot_ver", ctypes.c_char * 5),
        ("servo_ser", ctypes.c_char * 5),
        ("servo_ver", ctypes.c_char * 5),
        ("pmc_ser", ctypes.c_char * 5),
        ("pmc_ver", ctypes.c_char * 5),
        ("ladder_ser", ctypes.c_char * 5),
        ("ladder_ver", ctypes.c_char * 5),
        ("rest", ctypes.c_char * 250),
    ]


class ODBNUM(ctypes.Structure):  # ODBPARANUM, ODBDIAGNUM
    _fields_ = [("minimum", ctypes.c_ushort), ("maximum", ctypes.c_ushort), ("total", us)]


class INFO(ctypes.Structure):
    _fields_ = [("number", ctypes.c_short), ("type", ctypes.c_short)]


class ODBIF(ctypes.Structure):  # ODBDIAGIF, ODBSETIF
    _fields_ = [
        ("info_no", ctypes.c_ushort),
        ("prev_no", ctypes.c_short),
        ("next_no", ctypes.c_short),
        ("info", INFO * 10),
    ]


class PMCINF(ctypes.Structure):
    _fields_ = [
        ("pmc_adr", ctypes.c_char),
        ("adr_attr", ctypes.c_char),
        ("top_num", ctypes.c_ushort),
        ("last_num", ctypes.c_ushort),
    ]


class ODBPMCINF(ctypes.Structure):
    _fields_ = [("datano", ctypes.c_short), ("info", PMCINF * 64)]


class ODBPMCTITLE(ctypes.Structure):
    _fields_ = [
        ("mtb", ctypes.c_char * 48),
        ("machine", ctypes.c_char * 48),
        ("type", ctypes.c_char * 48),
        ("prgno", ctypes.c_char * 8),
        ("prgvers", ctypes.c_char * 4),
        ("prgdraw", ctypes.c_char * 48),
        ("date", ctypes.c_char * 32),
        ("design", ctypes.c_char * 48),
        ("written", ctypes.c_char * 48),
        ("remarks", ctypes.c_char * 48),
    ]


class ODBPRS(ctypes.Structure):
    _fields_ = [
        ("datano", ctypes.c_short),
        ("type", ctypes.c_short),
        ("data_info", ctypes.c_short * 5),
        ("rstr_bc", i32),
        ("rstr_m", i32 * 35),
        ("rstr_t", i32 * 2),
        ("rstr_s", i32),
        ("rstr_b", i32),
        ("dest", i32 * MAX_AXIS),
        ("dist", i32 * MAX_AXIS),
    ]


class IODBPSD(ctypes.Structure):
    _fields_ = [("datano", ctypes.c_short), ("type", ctypes.c_short), ("value", ctypes.c_byte)]


@dataclass
class Both:
    cnc: Cnc
    client: NativeClient


@pytest.fixture(params=["30i", "16i"])
async def both(request: pytest.FixtureRequest) -> AsyncIterator[Both]:
    async with served_cnc(request.param) as cnc:
        served = cnc.served
        async with NativeClient(served.host, served.port, timeout=IO_TIMEOUT) as client:
            yield Both(cnc, client)


async def test_figures(both: Both) -> None:
    valid = s16()
    inputs, outputs = (ctypes.c_short * MAX_AXIS)(), (ctypes.c_short * MAX_AXIS)()
    rc = await both.cnc.call("cnc_getfigure", s16(0), ctypes.byref(valid), inputs, outputs)
    assert rc == 0
    axes = len(both.cnc.machine.axes)
    assert valid.value == VALID_FIGURES
    assert list(inputs[:axes]) == list(outputs[:axes]) == [POSITION_DECIMALS] * axes
    assert inputs[axes] == 0  # one value per axis of the path
    figures = await both.client.read_figures()
    assert (figures.valid, list(figures.input_decimals)) == (valid.value, list(inputs[:axes]))
    # the library refuses a data type above 6 itself; the machine models type 0 only
    assert await both.cnc.call("cnc_getfigure", s16(1), ctypes.byref(valid), inputs, outputs) == (
        EW.ATTRIB
    )


async def _statinfo2(both: Both) -> ODBST2:
    st = ODBST2()
    assert await both.cnc.call("cnc_statinfo2", ctypes.byref(st)) == 0
    return st


async def test_status2_idle(both: Both) -> None:
    st = await _statinfo2(both)
    s = both.cnc.machine.status()
    fields = ("hdck", "tmmode", "aut", "run", "motion", "mstb", "emergency", "alarm", "edit")
    assert [getattr(st, f) for f in fields] == [getattr(s, f) for f in fields]
    assert (st.warning, st.o3dchk, st.ext_opt, st.restart) == (0, 0, 0, 0)
    client = await both.client.read_status2()
    names = [field[0] for field in ODBST2._fields_]
    assert [getattr(client, f) for f in names] == [getattr(st, f) for f in names]
    packed = await both.cnc.packed.read_status()  # the packed protocol's cnc_statinfo
    assert (packed.aut, packed.run, packed.motion) == (st.aut, st.run, st.motion)


async def test_status2_running() -> None:
    clock = ManualClock()
    machine = default_machine(sim_clock=clock)
    async with served_cnc("30i", machine) as cnc:
        machine.set_panel(1, 1, 0)  # MEM
        machine.cycle_start()
        clock.advance(1.0)
        st = ODBST2()
        assert await cnc.call("cnc_statinfo2", ctypes.byref(st)) == 0
        s = machine.status()
        assert (st.aut, st.run, st.motion) == (s.aut, s.run, s.motion)
        assert st.run != 0


async def test_system_software(both: Both) -> None:
    ss = ODBSYSS()
    assert await both.cnc.call("cnc_rdsyssoft", ctypes.byref(ss)) == 0
    identity = both.cnc.machine.identity()
    assert list(ss.slot_no_p[:2]) == [0, 0xFF]
    assert ss.slot_no_l[0] == 0
    assert (ss.soft_series[0].value, ss.soft_version[0].value) == (
        identity.series.encode(),
        identity.version.encode(),
    )
    assert ss.soft_inst == 1
    software = {s.name: s for s in both.cnc.machine.system_software()}
    for name in ("boot", "servo", "pmc", "ladder"):
        got = (getattr(ss, f"{name}_ser"), getattr(ss, f"{name}_ver"))
        assert got == (software[name].series.encode(), software[name].version.encode())
    # the packed protocol's cnc_sysinfo tells the same series and version
    packed = await both.cnc.packed.read_sysinfo()
    assert (packed.series, packed.version) == (ss.soft_series[0].value, ss.soft_version[0].value)
    client = await both.client.read_system_software()
    assert client.software[0].series == identity.series
    assert client.servo == (ss.servo_ser.decode(), ss.servo_ver.decode())


async def test_item_numbers_and_attributes(both: Both) -> None:
    machine = both.cnc.machine
    for function, numbers, read in (
        ("cnc_rdparanum", machine.param_numbers(), both.client.read_param_numbers),
        ("cnc_rddiagnum", machine.diag_numbers(), both.client.read_diag_numbers),
    ):
        n = ODBNUM()
        assert await both.cnc.call(function, ctypes.byref(n)) == 0
        assert (n.minimum, n.maximum, n.total) == (numbers[0], numbers[-1], len(numbers))
        r = await read()
        assert (r.minimum, r.maximum, r.total) == (n.minimum, n.maximum, n.total)
    diags = machine.diag_numbers()
    di = ODBIF()
    assert await both.cnc.call("cnc_rddiaginfo", s16(0), us(10), ctypes.byref(di)) == 0
    assert di.info_no == min(10, len(diags))
    assert [di.info[i].number for i in range(di.info_no)] == list(diags[:10])
    attributes = await both.client.read_diag_attributes(0, 10)
    assert attributes.items == tuple((i.number, i.type) for i in di.info[: di.info_no])
    si = ODBIF()
    assert await both.cnc.call("cnc_rdsetinfo", s16(0), us(10), ctypes.byref(si)) == 0
    assert (si.info_no, si.info[0].number, si.info[0].type) == (1, 20, 1)  # a byte setting
    assert (await both.client.read_setting_attributes()).items == ((20, 1),)


async def test_setting_data(both: Both) -> None:
    psd = IODBPSD()
    assert await both.cnc.call("cnc_rdset", s16(20), s16(0), s16(5), ctypes.byref(psd)) == 0
    assert (psd.datano, psd.type, psd.value) == (20, 0, both.cnc.machine.read_param(20, 0))
    assert (await both.client.read_setting(20)).value == psd.value
    assert await both.cnc.packed.read_param(20) == psd.value  # the packed protocol's parameter
    # a parameter that is no setting data
    rc = await both.cnc.call("cnc_rdset", s16(1320), s16(0), s16(8), ctypes.byref(psd))
    assert rc == EW.NUMBER


async def test_pmc_areas_and_title(both: Both) -> None:
    inf = ODBPMCINF()
    assert await both.cnc.call("pmc_rdpmcinfo", s16(-1), ctypes.byref(inf)) == 0
    machine = both.cnc.machine
    ranges = {r.letter: r for r in machine.pmc_ranges()}
    assert inf.datano == len(ranges)
    seen = []
    for entry in inf.info[: inf.datano]:
        letter = entry.pmc_adr.decode()
        seen.append((letter, entry.adr_attr, entry.top_num, entry.last_num))
        assert (entry.top_num, entry.last_num) == (ranges[letter].first, ranges[letter].last)
        # the last address is one pmc_rdpmcrng reads
        data, last = buf(16), us(entry.last_num)
        area = s16("GFYXARTKCD".index(letter))
        assert await both.cnc.call("pmc_rdpmcrng", area, s16(0), last, last, us(9), data) == 0
        # and the packed protocol reads it too
        assert len(await both.cnc.packed.read_pmc(letter, entry.last_num, 1)) == 1
    client = await both.client.read_pmc_areas()
    assert [(a.letter, bytes([a.attribute]), a.first, a.last) for a in client] == seen
    title = ODBPMCTITLE()
    assert await both.cnc.call("pmc_rdpmctitle", ctypes.byref(title)) == 0
    expected = machine.pmc_title()
    assert (title.mtb, title.machine, title.type, title.prgno, title.prgvers) == (
        expected.mtb.encode(),
        expected.machine.encode(),
        expected.pmc_type.encode(),
        expected.program.encode(),
        expected.edition.encode(),
    )
    client_title = await both.client.read_pmc_title()
    assert (client_title.machine, client_title.type) == (machine.name, expected.pmc_type)


async def test_ethernet_and_program_restart(both: Both) -> None:
    kind, device = s16(-1), s16(-1)
    assert await both.cnc.call("cnc_rdetherinfo", ctypes.byref(kind), ctypes.byref(device)) == 0
    board = both.cnc.machine.ethernet_board()
    assert (kind.value, device.value) == (board.kind, board.device)
    e = await both.client.read_ethernet_info()
    assert (e.type, e.device) == (kind.value, device.value)
    prs = ODBPRS()
    ctypes.memset(ctypes.byref(prs), 0x55, ctypes.sizeof(prs))
    assert await both.cnc.call("cnc_rdprstrinfo", ctypes.byref(prs)) == 0
    axes = len(both.cnc.machine.axes)
    assert list(prs.data_info) == [0] * 5  # no restart data kept
    # the library packs the distances right after the points it copied (the path's axes in
    # the 16i set, the open answer's max axes in the 30i set), as cnc_rddynamic2 packs
    stride = both.cnc.slots
    packed = list(prs.dest) + list(prs.dist)
    assert packed[:axes] == packed[stride : stride + axes] == [0] * axes
    restart = await both.client.read_restart_info()
    assert restart.block_counter == () and restart.distance == (0,) * axes
