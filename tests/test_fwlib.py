"""FANUC's own FOCAS library against a real :class:`FocasServer`, through ``ctypes``.

Skipped unless ``FOCAS_NET_FWLIB`` names FANUC's libfwlib32 (x86-64 Linux, never part of this
repository). Each test serves one machine on 127.0.0.1 (an ephemeral port; both protocols on
that one port) and drives the library in worker threads (it blocks), while the packed
:class:`FocasClient` reads the same server on the event loop: every value the library returns
is checked against what the packed protocol answers for the same machine, or against the
machine where the packed protocol has no such function. Both command sets are covered: the
built-in 0i-F machine (the 30i set, open answer version 3) and a 16i-class machine file (the
16i set, version 2). ``FOCAS_NET_FWLIB_LOG`` names a file for the library's own log.
"""

from __future__ import annotations

import asyncio
import ctypes
import struct
from collections.abc import AsyncIterator
from decimal import Decimal
from pathlib import Path
from typing import Any

import pytest
from fwlib_support import (
    _FORMATS,
    _SIZES,
    EW_SOCKET,
    HANDLE_TIMEOUT,
    LIBRARY,
    MACHINE_16I,
    Cnc,
    buf,
    connect,
    i32,
    library,
    rdparam,
    s16,
    served_cnc,
    us,
    wrparam,
)
from support import IO_TIMEOUT, serving, wait_until

from focas_net.client import FocasClient
from focas_net.errors import EW, CncError
from focas_net.protocol import FaultKind, FaultScope
from focas_net.sim import POSITION_DECIMALS, ParamKind, default_machine, load_machine
from focas_net.sim.nc import ManualClock

pytestmark = pytest.mark.skipif(
    not LIBRARY,
    reason="set FOCAS_NET_FWLIB to the path of FANUC's libfwlib32 (e.g. libfwlib32.so.1) "
    "to run FANUC's library against the simulator",
)


@pytest.fixture(params=["30i", "16i"])
async def cnc(request: pytest.FixtureRequest) -> AsyncIterator[Cnc]:
    async with served_cnc(request.param) as served:
        yield served


@pytest.fixture(params=["30i-file", "16i"])
async def kinds_cnc(request: pytest.FixtureRequest) -> AsyncIterator[Cnc]:
    """A machine with bit, byte, word, two-word and real parameters, in either set."""
    async with served_cnc(request.param) as served:
        yield served


# --------------------------------------------------------------------------------------------
# The handshake, identity and status


async def test_the_command_set_follows_the_control_class(cnc: Cnc) -> None:
    listener = cnc.served.listener
    await wait_until(lambda: len(listener.native_connections) == 2)  # connections A and B
    opt = ctypes.c_int64(0)
    assert await cnc.call("cnc_getfocas1opt", s16(0), ctypes.byref(opt)) == 0
    assert opt.value & 1  # what cnc_rddynamic2 needs
    # a 30i-class handle wants room for the open answer's max axes (32) in an all-axes read, a
    # 16i-class one for the path's axes (3)
    b = buf(4 + 8 * 32)
    rc = await cnc.call("cnc_rdparam", s16(1320), s16(-1), s16(4 + 4 * 3), b)
    assert rc == (0 if cnc.machine.control_class == "16i" else EW.LENGTH)


async def test_getpath_reports_the_machines_one_path(cnc: Cnc) -> None:
    """``cnc_getpath`` sends nothing: the library answers it from the open answer, which
    carries the path count (a collector that loops paths 1..max reads path 1)."""
    path, most = s16(0), s16(0)
    assert await cnc.call("cnc_getpath", ctypes.byref(path), ctypes.byref(most)) == 0
    assert (path.value, most.value) == (1, 1)


async def test_sysinfo(cnc: Cnc) -> None:
    b = buf(18)
    assert await cnc.call("cnc_sysinfo", b) == 0
    addinfo, max_axis, *texts = struct.unpack("<hh2s2s4s4s2s", b.raw)
    si = await cnc.packed.read_sysinfo()
    assert (addinfo, max_axis) == (si.addinfo, si.max_axis)
    assert texts == [si.cnc_type, si.mt_type, si.series, si.version, si.axes]


async def test_statinfo(cnc: Cnc) -> None:
    await cnc.packed.sim.set_panel("MEM", emergency=True)
    await cnc.packed.sim.raise_alarm(2, 100, "ALARM")
    b = buf(18)
    assert await cnc.call("cnc_statinfo", b) == 0
    st = await cnc.packed.read_status()
    assert list(struct.unpack("<9h", b.raw)) == [
        st.hdck,
        st.tmmode,
        st.aut,
        st.run,
        st.motion,
        st.mstb,
        st.emergency,
        st.alarm,
        st.edit,
    ]
    assert (st.aut, st.emergency, st.alarm) == (1, 1, 1)


# --------------------------------------------------------------------------------------------
# Macro variables


async def rdmacro(cnc: Cnc, number: int) -> tuple[int, int, int]:
    b = buf(12)
    rc = await cnc.call("cnc_rdmacro", s16(number), s16(10), b)
    datano, _, mcr, dec = struct.unpack("<hhih2x", b.raw)
    if rc == 0:
        assert datano == number
    return rc, mcr, dec


async def test_macros(cnc: Cnc) -> None:
    await cnc.packed.write_macro(101, Decimal("-2.5"))
    for n in (100, 101, 102):
        rc, mcr, dec = await rdmacro(cnc, n)
        value = await cnc.packed.read_macro(n)
        parts = (0, -1) if value is None else _parts(value)
        assert (rc, mcr, dec) == (0, *parts)
    # written through the library, read through the packed protocol
    for number, mcr, dec, written in (
        (500, 12345, 3, Decimal("12.345")),
        (501, -25, 1, Decimal("-2.5")),
        (502, 100, 0, Decimal(100)),
    ):
        assert await cnc.call("cnc_wrmacro", s16(number), s16(10), i32(mcr), s16(dec)) == 0
        assert await cnc.packed.read_macro(number) == written
        assert await rdmacro(cnc, number) == (0, *_parts(written))
    # doubles
    num = ctypes.c_uint64(3)
    d = (ctypes.c_double * 3)()
    assert await cnc.call("cnc_rdmacror2", ctypes.c_ulong(500), ctypes.byref(num), d) == 0
    assert list(d) == [12.345, -2.5, 100.0]
    one = ctypes.c_uint64(1)
    assert (
        await cnc.call(
            "cnc_wrmacror2", ctypes.c_ulong(503), ctypes.byref(one), (ctypes.c_double * 1)(0.125)
        )
        == 0
    )
    assert await cnc.packed.read_macro(503) == Decimal("0.125")
    # refusals: the codes the packed protocol answers for the same request
    assert (
        (await rdmacro(cnc, 9999))[0] == EW.NUMBER == await _packed_ew(cnc.packed.read_macro(9999))
    )
    assert await cnc.call("cnc_wrmacro", s16(4003), s16(10), i32(1), s16(0)) == EW.PROT
    assert await _packed_ew(cnc.packed.write_macro(4003, 1)) == EW.PROT
    assert await cnc.call("cnc_wrmacro", s16(9999), s16(10), i32(1), s16(0)) == EW.NUMBER
    err = buf(4)
    assert await cnc.call("cnc_getdtailerr", err) == 0
    assert struct.unpack("<hh", err.raw) == (1, 9999)


def _parts(value: Decimal) -> tuple[int, int]:
    sign, digits, exponent = value.as_tuple()
    assert isinstance(exponent, int)
    mantissa = int("".join(map(str, digits)))
    return (-mantissa if sign else mantissa), max(-exponent, 0)


async def _packed_ew(call: Any) -> int:
    try:
        await call
    except CncError as exc:
        return exc.ew
    return 0


# --------------------------------------------------------------------------------------------
# Parameters and diagnostics


async def packed_param(cnc: Cnc, number: int, axis: int = 0) -> Any:
    """The packed protocol's value of parameter ``number``: a Decimal for a real one."""
    item = cnc.machine.param_item(number)
    assert item is not None
    if item.kind is ParamKind.REAL:
        return await cnc.packed.read_param_real(number, axis=axis)
    return await cnc.packed.read_param(number, axis=axis)


async def test_parameters_read_as_the_packed_protocol_reads_them(cnc: Cnc) -> None:
    for number in cnc.machine.param_numbers():
        item = cnc.machine.param_item(number)
        assert item is not None
        if item.axis:
            for axis in (2, -1):
                rc, got = await rdparam(cnc, number, axis)
                axes = (2,) if axis == 2 else range(1, len(cnc.machine.axes) + 1)
                want = [await packed_param(cnc, number, a) for a in axes]
                assert (rc, got) == (0, want), number
        else:
            rc, got = await rdparam(cnc, number, 0)
            assert (rc, got) == (0, [await packed_param(cnc, number)]), number


async def test_every_kind_of_parameter_read_as_the_packed_protocol_reads_it(
    kinds_cnc: Cnc,
) -> None:
    cnc = kinds_cnc
    kinds = set()
    for number in cnc.machine.param_numbers():
        item = cnc.machine.param_item(number)
        assert item is not None
        kinds.add(item.kind)
        for axis in (2, -1) if item.axis else (0,):
            rc, got = await rdparam(cnc, number, axis)
            axes = (axis,) if axis != -1 else range(1, len(cnc.machine.axes) + 1)
            want = [await packed_param(cnc, number, a) for a in axes]
            assert (rc, got) == (0, want), number
    assert kinds == set(ParamKind)
    assert (await rdparam(cnc, 1815, -1))[1] == [0b10110000, 0b00000001, 0b11111111]
    assert (await rdparam(cnc, 1451, 0))[1] == [Decimal("12.345")]
    assert (await rdparam(cnc, 1420, -1))[1] == [Decimal("1.5"), Decimal(-2), Decimal("3.1")]


async def test_every_kind_of_parameter_written_through_the_library(kinds_cnc: Cnc) -> None:
    cnc = kinds_cnc
    m = cnc.machine
    # a bit parameter, as its eight bits
    assert await wrparam(cnc, 1815, 2, [0b11000011]) == 0
    assert await cnc.packed.read_param(1815, axis=2) == 0b11000011 == m.read_param(1815, 2)
    assert await wrparam(cnc, 1815, -1, [0x80, 0x7F, 0]) == 0
    assert [await cnc.packed.read_param(1815, axis=a) for a in (1, 2, 3)] == [0x80, 0x7F, 0]
    assert await wrparam(cnc, 3401, 0, [0xFE]) == 0
    assert await cnc.packed.read_param(3401) == 0xFE
    # byte, word, two-word
    for number, value in ((20, 9), (3216, -2), (6711, 987654321)):
        assert await wrparam(cnc, number, 0, [value]) == 0
        assert await cnc.packed.read_param(number) == value
    # refusals of each kind are the packed protocol's
    assert (
        await wrparam(cnc, 20, 0, [36])
        == EW.DATA
        == await _packed_ew(cnc.packed.write_param(20, 36))
    )
    assert await wrparam(cnc, 1815, 4, [1]) == EW.ATTRIB  # the library checks the axis
    before = m.state_digest()
    if cnc.set_name == "16i":
        # the 16i set cannot write a real parameter: every length answers EW_LENGTH
        for length in (0, 5, 8, 12):
            assert await wrparam(cnc, 1451, 0, [(5, 1)], length) == EW.LENGTH, length
        assert m.state_digest() == before
        return
    # the 30i set: REALPRM (value, decimals), rescaled to the parameter's decimals
    assert await wrparam(cnc, 1451, 0, [(-15, 1)]) == 0
    assert await cnc.packed.read_param_real(1451) == Decimal("-1.500")
    assert await wrparam(cnc, 1420, -1, [(7, 0), (25, 1), (-5, 1)]) == 0
    got = [await cnc.packed.read_param_real(1420, axis=a) for a in (1, 2, 3)]
    assert got == [Decimal(7), Decimal("2.5"), Decimal("-0.5")]
    # a value with more decimals than the parameter has is EW_DATA through both protocols
    before = m.state_digest()
    assert await wrparam(cnc, 1451, 0, [(12345, 4)]) == EW.DATA
    assert await _packed_ew(cnc.packed.write_param(1451, Decimal("1.2345"))) == EW.DATA
    assert m.state_digest() == before
    await cnc.packed.sim.set_panel("MEM")
    assert await wrparam(cnc, 1451, 0, [(1, 0)]) == EW.PASSWD
    assert await wrparam(cnc, 1815, 1, [1]) == EW.PASSWD


async def test_parameters_written_through_either_protocol(cnc: Cnc) -> None:
    async def wrparam(number: int, axis: int, values: list[int]) -> int:
        item = cnc.machine.param_item(number)
        assert item is not None
        size = _SIZES[item.width]
        b = buf(4 + 8 * 32)
        struct.pack_into("<hh", b, 0, number, axis)
        for i, v in enumerate(values):
            struct.pack_into(f"<{_FORMATS[size]}", b, 4 + i * size, v)
        length = 4 + size * (cnc.slots if axis == -1 else 1)
        return await cnc.call("cnc_wrparam", s16(length), b)

    assert await wrparam(20, 0, [7]) == 0
    assert await cnc.packed.read_param(20) == 7
    assert await wrparam(1825, 2, [1234]) == 0
    assert await cnc.packed.read_param(1825, axis=2) == 1234
    assert await wrparam(1320, -1, [1, -2, 3]) == 0
    assert [await cnc.packed.read_param(1320, axis=a) for a in (1, 2, 3)] == [1, -2, 3]
    assert await wrparam(6711, 0, [42]) == 0
    assert await cnc.packed.read_param(6711) == 42
    await cnc.packed.write_param(3216, 300)
    assert await rdparam(cnc, 3216, 0) == (0, [300])
    # refusals, as the packed protocol refuses them
    assert (
        await wrparam(6711, 0, [-1])
        == EW.DATA
        == await _packed_ew(cnc.packed.write_param(6711, -1))
    )
    assert (await rdparam(cnc, 1320, 0))[0] == EW.ATTRIB
    assert await _packed_ew(cnc.packed.read_param(1320)) == EW.ATTRIB
    b = buf(4 + 8 * 32)
    assert await cnc.call("cnc_rdparam", s16(9999), s16(0), s16(8), b) == EW.NUMBER
    assert await _packed_ew(cnc.packed.read_param(9999)) == EW.NUMBER
    await cnc.packed.sim.set_panel("MEM")  # PWE off: the write gate is closed
    assert await wrparam(20, 0, [8]) == EW.PASSWD
    assert await _packed_ew(cnc.packed.write_param(20, 8)) == EW.PASSWD
    assert cnc.machine.read_param(20, 0) == 7


async def test_diagnostics(cnc: Cnc) -> None:
    for number in cnc.machine.diag_numbers():
        item = cnc.machine.diag_item(number)
        assert item is not None
        for axis in (2, -1) if item.axis else (0,):
            rc, got = await rdparam(cnc, number, axis, "cnc_diagnoss")
            axes = (axis,) if axis != -1 else range(1, len(cnc.machine.axes) + 1)
            want = [await cnc.packed.read_diag(number, axis=a) for a in axes]
            assert (rc, got) == (0, want), number


# --------------------------------------------------------------------------------------------
# PMC


async def rdpmc(
    cnc: Cnc, area: int, data_type: int, first: int, count: int
) -> tuple[int, list[int]]:
    width = 1 << data_type
    last = first + width * count - 1
    b = buf(8 + width * count)
    rc = await cnc.call(
        "pmc_rdpmcrng", s16(area), s16(data_type), us(first), us(last), us(8 + width * count), b
    )
    fmt = {1: "B", 2: "H", 4: "I"}[width]
    return rc, list(struct.unpack_from(f"<{count}{fmt}", b.raw, 8))


async def wrpmc(cnc: Cnc, area: int, data_type: int, first: int, values: list[int]) -> int:
    width = 1 << data_type
    last = first + width * len(values) - 1
    b = buf(8 + width * len(values))
    struct.pack_into("<hhHH", b, 0, area, data_type, first, last)
    fmt = {1: "B", 2: "H", 4: "I"}[width]
    struct.pack_into(f"<{len(values)}{fmt}", b, 8, *values)
    rc: int = await cnc.call("pmc_wrpmcrng", us(8 + width * len(values)), b)
    return rc


async def test_pmc(cnc: Cnc) -> None:
    R, D, X = 5, 9, 3
    await cnc.packed.write_pmc("R", 100, bytes([1, 2, 3, 4, 5, 6, 7, 8]))
    assert await rdpmc(cnc, R, 0, 100, 8) == (0, [1, 2, 3, 4, 5, 6, 7, 8])
    # words and longs: the machine's little-endian memory, the host's values
    assert await rdpmc(cnc, R, 1, 100, 4) == (0, [0x0201, 0x0403, 0x0605, 0x0807])
    assert await rdpmc(cnc, R, 2, 100, 2) == (0, [0x04030201, 0x08070605])
    assert await wrpmc(cnc, D, 1, 20, [0x1234, 0xFFFE]) == 0
    assert await cnc.packed.read_pmc("D", 20, 4) == bytes([0x34, 0x12, 0xFE, 0xFF])
    assert await wrpmc(cnc, D, 2, 40, [0xDEADBEEF]) == 0
    assert await cnc.packed.read_pmc("D", 40, 4) == bytes([0xEF, 0xBE, 0xAD, 0xDE])
    # one answer carries far more than the packed protocol's 32 bytes
    data = bytes(i % 251 for i in range(1000))
    await cnc.packed.write_pmc("D", 1000, data)
    assert await rdpmc(cnc, D, 0, 1000, 1000) == (0, list(data))
    assert await wrpmc(cnc, D, 0, 3000, list(data)) == 0
    assert await cnc.packed.read_pmc("D", 3000, 1000) == data
    # refusals
    assert (
        await wrpmc(cnc, X, 0, 0, [1])
        == EW.PROT
        == await _packed_ew(cnc.packed.write_pmc("X", 0, b"\x01"))
    )
    assert (await rdpmc(cnc, D, 0, 9999, 4))[0] == EW.NUMBER
    assert await _packed_ew(cnc.packed.read_pmc("D", 9999, 4)) == EW.NUMBER
    assert (await rdpmc(cnc, 12, 0, 0, 1))[0] == EW.NOOPT  # no E area


# --------------------------------------------------------------------------------------------
# Alarms and programs


async def test_alarms(cnc: Cnc) -> None:
    await cnc.packed.sim.raise_alarm(4, 500, "OVER TRAVEL +X", axis_no=1)
    await cnc.packed.sim.raise_alarm(2, 1001, "SPINDLE ALARM")
    active = await cnc.packed.read_alarms()
    for fn, text in (("cnc_rdalmmsg", 32), ("cnc_rdalmmsg2", 64)):
        size = 12 + text
        num = s16(10)
        b = buf(size * 10)
        assert await cnc.call(fn, s16(-1), ctypes.byref(num), b) == 0
        got = []
        for i in range(num.value):
            alm_no, kind, axis, _, length = struct.unpack_from("<ihhhh", b.raw, i * size)
            msg = b.raw[i * size + 12 : i * size + 12 + length].decode()
            got.append((axis, kind, alm_no, msg))
        assert got == [(a.axis_no, a.alm_type, a.alm_no, a.msg) for a in active]
    bits = sum(1 << t for t in {a.alm_type for a in active})
    b = buf(8)
    assert await cnc.call("cnc_alarm", b) == 0
    assert struct.unpack_from("<h", b.raw, 4)[0] == bits
    v = ctypes.c_int64(0)
    assert await cnc.call("cnc_alarm2", ctypes.byref(v)) == 0
    assert v.value & 0xFFFFFFFF == bits
    # the history, newest first, in chunks of 23 records
    for i in range(30):
        await cnc.packed.sim.raise_alarm(3, 2000 + i, f"ALARM {i}")
    history = (await cnc.packed.read_alarm_history(40)).entries
    assert len(history) == 32
    b = buf(6 + 48 * 30)
    assert await cnc.call("cnc_rdalmhistry", us(1), us(30), us(6 + 48 * 30), b) == 0
    s_no, _, e_no = struct.unpack_from("<HhH", b.raw)
    assert (s_no, e_no) == (1, 30)
    for i, e in enumerate(history[:30]):
        f = struct.unpack_from("<hhhbbbbbbbbh32s", b.raw, 6 + 48 * i)
        t = e.occurred_at
        assert (f[1], f[2], f[3]) == (e.alm_type, e.alm_no, e.axis_no)
        assert f[4:10] == (t.year % 100, t.month, t.day, t.hour, t.minute, t.second)
        assert f[12][: f[11]].decode() == e.msg


async def test_programs_feed_and_spindle(cnc: Cnc) -> None:
    cnc.machine.set_motion(
        program_running=1234, program_main=1000, sequence=56, feed=1500, spindle_speed=3000
    )
    pn = await cnc.packed.read_program_numbers()
    b = buf(8)
    assert await cnc.call("cnc_rdprgnum", b) == 0
    assert list(struct.unpack_from("<hh", b.raw, 4)) == [pn.running, pn.main]
    b = buf(12)
    assert await cnc.call("cnc_rdprgnumo8", b) == 0
    assert list(struct.unpack_from("<ii", b.raw, 4)) == [pn.running, pn.main]
    b = buf(40)
    assert await cnc.call("cnc_exeprgname", b) == 0
    assert (b.raw[:36].rstrip(b"\0"), struct.unpack_from("<i", b.raw, 36)[0]) == (b"O1234", 1234)
    b = buf(8)
    assert await cnc.call("cnc_rdseqnum", b) == 0
    assert struct.unpack_from("<i", b.raw, 4)[0] == cnc.machine.motion.sequence == 56
    for fn, want in (
        ("cnc_actf", await cnc.packed.read_feed()),
        ("cnc_acts", await cnc.packed.read_spindle_speed()),
    ):
        b = buf(8)
        assert await cnc.call(fn, b) == 0
        assert struct.unpack_from("<i", b.raw, 4)[0] == want
    assert want == 3000


async def test_cnc_id_timers_and_loads(cnc: Cnc) -> None:
    b = buf(16)
    assert await cnc.call("cnc_rdcncid", b) == 0
    ids = struct.unpack("<4I", b.raw)
    assert any(ids)
    assert await cnc.call("cnc_rdcncid", b) == 0 and struct.unpack("<4I", b.raw) == ids
    for kind in range(5):  # 0 power-on, 1 operating, 2 cutting, 3 cycle, 4 free purpose
        before = (await cnc.packed.read_run_info()) if kind == 0 else None
        b = buf(8)
        assert await cnc.call("cnc_rdtimer", s16(kind), b) == 0
        minute, msec = struct.unpack("<ii", b.raw)
        assert 0 <= msec < 60_000
        if before is None:  # an idle machine: no operation, no cutting, no cycle; no free timer
            assert (minute, msec) == (0, 0)
        else:  # power-on time moves: between the packed reads before and after
            after = await cnc.packed.read_run_info()
            assert before.power_on_ms <= 60_000 * minute + msec <= after.power_on_ms
    for spindle in (-1, 1):
        b = buf(4 + 2 * 8)
        assert await cnc.call("cnc_rdspload", s16(spindle), b) == 0
        assert struct.unpack_from("<hh", b.raw) == (spindle, 0)
    num = s16(8)
    b = buf(12 * 8)
    assert await cnc.call("cnc_rdsvmeter", ctypes.byref(num), b) == 0
    assert num.value == len(cnc.machine.axes)
    names = [b.raw[12 * i + 8 : 12 * i + 9].decode() for i in range(num.value)]
    assert names == cnc.machine.axes
    assert [struct.unpack_from("<i", b.raw, 12 * i)[0] for i in range(num.value)] == [0, 0, 0]


# --------------------------------------------------------------------------------------------
# Positions


_KINDS = (("cnc_absolute", "absolute"), ("cnc_machine", "machine"), ("cnc_relative", "relative"))


async def test_positions(cnc: Cnc) -> None:
    cnc.machine.set_motion(
        absolute=[12345, -2500, 100000],
        machine=[22345, -12500, 90000],
        relative=[345, 500, -1000],
        distance_to_go=[10, 0, -20],
    )
    packed = {k: await cnc.packed.read_positions(k) for k in ("absolute", "machine", "relative")}
    packed["distance"] = await cnc.packed.read_positions("distance")
    n = len(cnc.machine.axes)
    for fn, kind in (*_KINDS, ("cnc_distance", "distance")):
        want = list(packed[kind].increments.values())
        b = buf(4 + 4 * 32)
        assert await cnc.call(fn, s16(2), s16(8), b) == 0
        assert struct.unpack_from("<hhi", b.raw)[1:] == (2, want[1])
        b = buf(4 + 4 * 32)
        assert await cnc.call(fn, s16(-1), s16(4 + 4 * cnc.slots), b) == 0
        assert list(struct.unpack_from(f"<{n}i", b.raw, 4)) == want
    # cnc_rdposition: four positions of every axis, with the names
    num = s16(8)
    b = buf(48 * 8)
    assert await cnc.call("cnc_rdposition", s16(-1), ctypes.byref(num), b) == 0
    assert num.value == n
    for i, name in enumerate(cnc.machine.axes):
        for k, kind in enumerate(("absolute", "machine", "relative", "distance")):
            d, dec, _, _, nm, _ = struct.unpack_from("<ihhhcc", b.raw, 48 * i + 12 * k)
            assert (d, dec, nm.decode()) == (packed[kind].increments[name], 3, name)
    # cnc_rddynamic2: alarm, programs, feed, spindle and the four positions at once
    cnc.machine.set_motion(program_running=7, program_main=8, sequence=9, feed=10, spindle_speed=11)
    # the library lays the four arrays out at the open answer's max axes: a 0i-F's 32, a 16i's 8,
    # as ODBDY2 compiled with FANUC's header (MAX_AXIS 32) expects on a 30i-class control
    most = cnc.machine.identity().max_axis
    assert most == (8 if cnc.set_name == "16i" else 32)
    b = buf(28 + 16 * 32)
    assert await cnc.call("cnc_rddynamic2", s16(-1), s16(28 + 16 * most - 1), b) == EW.LENGTH
    assert await cnc.call("cnc_rddynamic2", s16(-1), s16(28 + 16 * most), b) == 0
    head = struct.unpack_from("<hhiiiiii", b.raw)
    assert head[1:] == (-1, 0, 7, 8, 9, 10, 11)
    arrays = [list(struct.unpack_from(f"<{n}i", b.raw, 28 + 4 * most * k)) for k in range(4)]
    assert arrays == [
        list(packed[k].increments.values()) for k in ("absolute", "machine", "relative", "distance")
    ]
    b = buf(28 + 16 * 32)
    assert await cnc.call("cnc_rddynamic2", s16(2), s16(44), b) == 0
    one = struct.unpack_from("<hhiiiiiiiiii", b.raw)
    want = [packed[k].increments["Y"] for k in ("absolute", "machine", "relative", "distance")]
    assert (one[1], *one[8:]) == (2, *want)
    # an axis the machine has not
    b = buf(4 + 4 * 32)
    assert await cnc.call("cnc_absolute", s16(9), s16(8), b) == EW.ATTRIB


LINE = "O0100 (LINE)\nN10 G90 G21 G1 X60. F1200\nN20 M30\n"
G, F = 0, 1  # pmc_rdpmcrng/pmc_wrpmcrng area codes


async def statinfo(cnc: Cnc) -> list[int]:
    b = buf(18)
    assert await cnc.call("cnc_statinfo", b) == 0
    return list(struct.unpack("<9h", b.raw))


async def dynamic_x(cnc: Cnc) -> tuple[int, int]:
    """cnc_rddynamic2 of axis 1: its absolute position and the actual feed."""
    b = buf(44)
    assert await cnc.call("cnc_rddynamic2", s16(1), s16(44), b) == 0
    one = struct.unpack_from("<hhiiiiiiiiii", b.raw)
    return one[8], one[6]


@pytest.mark.parametrize("set_name", ["30i", "16i"])
async def test_the_library_runs_a_program_through_the_g_signals(
    set_name: str, tmp_path: Path
) -> None:
    """Mode select, cycle start and feed hold written as a ladder writes them (G43, G7.2
    ST, G8.5 *SP), the cycle read back through cnc_statinfo, the F signals, cnc_rddynamic2
    and the packed client, on a clock the test steps."""
    clock = ManualClock()
    if set_name == "30i":
        machine = default_machine(sim_clock=clock)
    else:  # the 16i-class file, with the G and F areas a ladder has
        path = tmp_path / "16i.toml"
        areas = "\n[pmc.G]\nsize = 768\n[pmc.F]\nsize = 768\n"
        path.write_text(MACHINE_16I.read_text(encoding="utf-8") + areas, encoding="utf-8")
        machine = load_machine(path, sim_clock=clock)
    async with served_cnc(set_name, machine) as cnc:
        machine = cnc.machine
        machine.store_program(LINE)
        count, total = machine.parts_counts()
        assert await wrpmc(cnc, G, 0, 43, [0b001]) == 0  # MD1: MEM
        assert (await statinfo(cnc))[2] == 1
        machine.select_program(100)
        assert await wrpmc(cnc, G, 0, 8, [0x20]) == 0  # *SP on (not holding)
        assert await wrpmc(cnc, G, 0, 7, [0x04]) == 0  # ST pressed ...
        assert (await statinfo(cnc))[3] != 3
        assert await wrpmc(cnc, G, 0, 7, [0x00]) == 0  # ... and released: cycle start
        status = await statinfo(cnc)
        assert status[3] == 3 and status[4] == 1  # run STRT, motion MTN
        rc, (f0,) = await rdpmc(cnc, F, 0, 0, 1)
        assert rc == 0 and f0 & 0b1010_0000 == 0b1010_0000  # OP and STL lit
        clock.advance(1.5)
        x, feed = await dynamic_x(cnc)
        packed = await cnc.packed.read_positions("absolute")
        assert x == packed.increments["X"] == 30 * 10**POSITION_DECIMALS
        assert feed == 1200 == await cnc.packed.read_feed()
        assert await wrpmc(cnc, G, 0, 8, [0x00]) == 0  # *SP off: feed hold
        assert (await statinfo(cnc))[3] == 2  # HOLD
        rc, (f0,) = await rdpmc(cnc, F, 0, 0, 1)
        assert f0 & 0b0011_0000 == 0b0001_0000  # SPL lit, STL out
        clock.advance(5.0)
        assert (await dynamic_x(cnc))[0] == x  # held: X stays
        assert await wrpmc(cnc, G, 0, 8, [0x20]) == 0
        assert await wrpmc(cnc, G, 0, 7, [0x04]) == 0
        assert await wrpmc(cnc, G, 0, 7, [0x00]) == 0  # cycle start resumes
        assert (await statinfo(cnc))[3] == 3
        clock.advance(1.5)  # the rest of the line, then M30
        assert (await dynamic_x(cnc))[0] == 60 * 10**POSITION_DECIMALS
        assert (await statinfo(cnc))[3] == 0  # reset after M30
        assert machine.parts_counts() == (count + 1, total + 1)
        assert (await cnc.packed.read_run_info()).parts_count == count + 1


# --------------------------------------------------------------------------------------------
# Faults, threads, handles


async def test_forced_code_is_the_return_value(cnc: Cnc) -> None:
    await cnc.packed.sim.inject_fault(FaultKind.ERROR, arg=EW.BUSY, scope=FaultScope.MACHINE)
    assert (await rdmacro(cnc, 100))[0] == EW.BUSY
    assert (await rdmacro(cnc, 100))[0] == 0  # the fault applied once


@pytest.mark.parametrize("kind", [FaultKind.DELAY, FaultKind.DROP])
async def test_a_lost_answer_kills_the_handle(kind: FaultKind) -> None:
    async with serving(default_machine()) as served:
        async with FocasClient(served.host, served.port, timeout=IO_TIMEOUT) as packed:
            handle = await connect(served, seconds=1)
            arg = 4000 if kind is FaultKind.DELAY else 0
            await packed.sim.inject_fault(kind, arg=arg, scope=FaultScope.MACHINE)
            b = buf(12)
            assert await handle.call("cnc_rdmacro", s16(100), s16(10), b) == EW_SOCKET
            # the handle is dead: every later call fails the same way
            assert await handle.call("cnc_rdmacro", s16(100), s16(10), b) == EW_SOCKET
            await handle.free()
            await wait_until(lambda: not served.listener.native_connections, within=10)
            # the server is fine: a new handle works
            again = await connect(served)
            assert await again.call("cnc_rdmacro", s16(100), s16(10), b) == 0
            assert await again.free() == 0


async def test_two_handles_in_two_threads() -> None:
    machine = default_machine()
    for n in range(500, 520):
        machine.write_macro(n, n * 10)
    async with serving(machine) as served:
        handles = [await connect(served), await connect(served)]
        lib = library()
        errors: list[str] = []

        def work(handle: int, numbers: range) -> None:
            for _ in range(5):
                for n in numbers:
                    b = buf(12)
                    rc = lib.cnc_rdmacro(us(handle), s16(n), s16(10), b)
                    _, _, mcr, dec = struct.unpack("<hhih2x", b.raw)
                    if (rc, mcr, dec) != (0, n * 10, 0):
                        errors.append(f"#{n}: {(rc, mcr, dec)}")

        await asyncio.gather(
            handles[0].run(work, handles[0].number, range(500, 510)),
            handles[1].run(work, handles[1].number, range(510, 520)),
        )
        assert errors == []
        for h in handles:
            assert await h.free() == 0
        await wait_until(lambda: not served.listener.native_connections)


async def test_a_handle_opened_and_freed_100_times_leaves_no_connection() -> None:
    async with serving(default_machine()) as served:
        lib = library()

        def cycle() -> list[int]:
            codes = []
            for _ in range(100):
                handle = us()
                codes.append(
                    lib.cnc_allclibhndl3(
                        b"127.0.0.1", us(served.port), i32(HANDLE_TIMEOUT), ctypes.byref(handle)
                    )
                )
                codes.append(lib.cnc_freelibhndl(handle))
            return codes

        async with asyncio.timeout(120):
            codes = await asyncio.to_thread(cycle)
        assert codes == [0] * 200
        await wait_until(lambda: not served.listener.native_connections)
        assert served.listener.native_accepted == 200
