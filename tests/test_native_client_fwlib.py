"""The native client's reads equal FANUC's library's on the same server, in both command sets.

Skipped unless ``FOCAS_NET_FWLIB`` names FANUC's libfwlib32 (see ``tests/fwlib_support.py``,
whose handle helpers run the library on a thread of its own). One server per command set (the
built-in 30i-class machine, a 16i-class machine file); the library's handle and a
:class:`NativeClient` are open at the same time, and every value must agree.
"""

from __future__ import annotations

import ctypes
import struct
from collections.abc import AsyncIterator
from decimal import Decimal
from pathlib import Path
from typing import Any

import pytest
from fwlib_support import (
    LIBRARY,
    Handle,
    buf,
    connect,
    machine_for,
    rdparam,
    s16,
    served_cnc,
    us,
    wrparam,
)
from support import IO_TIMEOUT, serving

from focas_net.client.native import NativeClient
from focas_net.errors import EW, CncError
from focas_net.sim import ParamKind

pytestmark = pytest.mark.skipif(
    not LIBRARY,
    reason="set FOCAS_NET_FWLIB to the path of FANUC's libfwlib32 (e.g. libfwlib32.so.1) "
    "to cross-check the native client with FANUC's library",
)


@pytest.fixture(params=["30i", "16i"])
async def pair(
    request: pytest.FixtureRequest, tmp_path: Path
) -> AsyncIterator[tuple[Handle, NativeClient]]:
    machine = machine_for(request.param)
    machine.set_panel(0, 1, 0)
    machine.write_macro(101, Decimal("-2.5"))
    machine.write_pmc("R", 100, bytes(range(1, 41)))
    machine.raise_alarm(1, 4, 500, "OVER TRAVEL +X")
    async with serving(machine) as served:
        handle = await connect(served)
        try:
            async with NativeClient(served.host, served.port, timeout=IO_TIMEOUT) as native:
                yield handle, native
        finally:
            await handle.free()


async def test_reads_equal_the_librarys(pair: tuple[Handle, NativeClient]) -> None:
    handle, native = pair
    b = buf(18)
    assert await handle.call("cnc_sysinfo", b) == 0
    info = await native.read_sysinfo()
    assert b.raw == struct.pack(
        "<hh2s2s4s4s2s", info.addinfo, info.max_axis, info.cnc_type, info.mt_type,
        info.series, info.version, info.axes,
    )  # fmt: skip
    b = buf(18)
    assert await handle.call("cnc_statinfo", b) == 0
    st = await native.read_status()
    assert list(struct.unpack("<9h", b.raw)) == [
        st.hdck, st.tmmode, st.aut, st.run, st.motion, st.mstb, st.emergency, st.alarm, st.edit,
    ]  # fmt: skip
    for number in (100, 101, 102):
        b = buf(12)
        assert await handle.call("cnc_rdmacro", s16(number), s16(10), b) == 0
        _, _, mcr, dec = struct.unpack("<hhih2x", b.raw)
        value = None if dec == -1 and mcr == 0 else Decimal(mcr).scaleb(-dec)
        assert await native.read_macro(number) == value
    b = buf(8 + 40)
    assert await handle.call("pmc_rdpmcrng", s16(5), s16(0), us(100), us(139), us(48), b) == 0
    assert b.raw[8:] == await native.read_pmc("R", 100, 40)
    b = buf(12)
    assert await handle.call("cnc_rdprgnumo8", b) == 0
    programs = await native.read_program_numbers()
    assert struct.unpack_from("<ii", b.raw, 4) == (programs.running, programs.main)
    for fn, want in (("cnc_actf", native.read_feed), ("cnc_acts", native.read_spindle_speed)):
        b = buf(8)
        assert await handle.call(fn, b) == 0
        assert struct.unpack_from("<i", b.raw, 4)[0] == await want()
    b = buf(16)
    assert await handle.call("cnc_rdcncid", b) == 0
    assert struct.unpack("<4I", b.raw) == await native.read_cnc_id()
    for kind in range(5):
        b = buf(8)
        assert await handle.call("cnc_rdtimer", s16(kind), b) == 0
        timer = await native.read_timer(kind)
        minute, msec = struct.unpack("<ii", b.raw)
        if kind == 0:  # power-on time moves on: the client read it after the library
            assert 60_000 * minute + msec <= 60_000 * timer.minute + timer.msec
        else:
            assert (minute, msec) == (timer.minute, timer.msec)
    b = buf(8)
    assert await handle.call("cnc_rdseqnum", b) == 0
    assert struct.unpack_from("<i", b.raw, 4)[0] == await native.read_sequence_number()
    b = buf(4 + 4)
    assert await handle.call("cnc_alarm2", b) == 0
    assert struct.unpack_from("<i", b.raw)[0] == await native.read_alarm_status()
    axes = native._handle.axes if native._handle else 0
    b = buf(28 + 16 * 32)
    assert await handle.call("cnc_rddynamic2", s16(-1), s16(len(b)), b) == 0
    dynamic = await native.read_dynamic()
    head = struct.unpack_from("<hhiiiiii", b.raw)
    assert head[2:] == (
        dynamic.alarm, dynamic.running, dynamic.main, dynamic.sequence, dynamic.feed,
        dynamic.spindle_speed,
    )  # fmt: skip
    assert struct.unpack_from(f"<{axes}i", b.raw, 28) == dynamic.absolute
    num = s16(8)
    b = buf(12 * 8)
    assert await handle.call("cnc_rdsvmeter", ctypes.byref(num), b) == 0
    meters = await native.read_servo_meters()
    assert num.value == len(meters)
    assert [struct.unpack_from("<i", b.raw, 12 * i)[0] for i in range(num.value)] == [
        int(m.load) for m in meters
    ]


@pytest.mark.parametrize("set_name", ["30i-file", "16i"])
async def test_every_kind_of_parameter_equals_the_librarys(set_name: str) -> None:
    async with served_cnc(set_name) as cnc:
        async with NativeClient(cnc.served.host, cnc.served.port, timeout=IO_TIMEOUT) as native:
            for number in cnc.machine.param_numbers():
                item = cnc.machine.param_item(number)
                assert item is not None
                axis = 2 if item.axis else 0
                rc, got = await rdparam(cnc, number, axis)
                if item.kind is ParamKind.REAL:
                    want: Any = await native.read_param_real(number, axis=axis)
                else:
                    want = await native.read_param(number, axis=axis)
                assert (rc, got) == (0, [want]), number
            # a bit parameter written by either, read by the other, as its eight bits
            await native.write_param(1815, 0xA5, axis=1)
            assert await rdparam(cnc, 1815, 1) == (0, [0xA5])
            assert await wrparam(cnc, 3401, 0, [0x96]) == 0
            assert await native.read_param(3401) == 0x96
            # a REALPRM (12 bytes) to a 2-word parameter: EW_LENGTH from the library; the
            # client refuses the value with decimals as the packed client does, nothing written
            parts = await native.read_param(6711)
            assert await wrparam(cnc, 6711, 0, [15], length=4 + 8) == EW.LENGTH
            with pytest.raises(ValueError, match="parameter 6711 is not a real parameter"):
                await native.write_param(6711, Decimal("1.5"))
            assert await native.read_param(6711) == parts
            if set_name == "16i":  # no real parameter write in the 16i set, from either
                assert await wrparam(cnc, 1451, 0, [(7125, 3)]) == EW.LENGTH
                for value in (7, Decimal("7.125")):
                    with pytest.raises(CncError) as refused:
                        await native.write_param(1451, value)
                    assert refused.value.ew == EW.LENGTH
                return
            await native.write_param(1451, Decimal("7.125"))
            assert await rdparam(cnc, 1451, 0) == (0, [Decimal("7.125")])
            assert await wrparam(cnc, 1420, 3, [(-35, 1)]) == 0
            assert await native.read_param_real(1420, axis=3) == Decimal("-3.5")
