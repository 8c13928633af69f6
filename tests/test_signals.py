"""What data collectors read, following the machine: run-time parameters, the CNC's clock,
diagnostic 4901, the override G signals both ways, the F signals of the state, the panel's
signals; the native codec of 0x45/0x46/0x5D, the adapter and the client."""

from __future__ import annotations

from collections.abc import Callable
from datetime import UTC, date, datetime, time, timedelta
from decimal import Decimal

import pytest
from hypothesis import given
from hypothesis import strategies as st
from support import IO_TIMEOUT, serving

from focas_net.client import FocasClient, NativeClient
from focas_net.errors import EW, CncError
from focas_net.native import (
    ClockReadRequest,
    ClockValue,
    ClockWriteRequest,
    PanelSignals,
    PanelSignalsRequest,
    cnc_gettimer,
    cnc_rdopnlsgnl,
    cnc_settimer,
    encode_part,
)
from focas_net.sim import Machine, MachineError, PathSpec, default_machine
from focas_net.sim.nc import ManualClock

_WALL = datetime(2026, 12, 7, 4, 30, 15, tzinfo=UTC)


def _machine(clock: ManualClock) -> Machine:
    return default_machine(sim_clock=clock, clock=lambda: _WALL)


def test_run_time_parameters_follow_the_timers() -> None:
    clock = ManualClock(0.0)
    m = _machine(clock)
    clock.advance(3725.5)
    assert m.read_param(6750, 0) == 62 == m.timer_ms(0) // 60_000
    m.cycle_start()
    clock.advance(10.0)
    assert m.timer_ms(1) == 10_000
    assert [m.read_param(n, 0) for n in (6751, 6752, 6757, 6758)] == [10_000, 0, 10_000, 0]
    assert m.read_param(6753, 0) == m.timer_ms(2) % 60_000


def test_a_run_time_parameter_written_sets_its_timer() -> None:
    clock = ManualClock(0.0)
    m = _machine(clock)
    m.set_panel(0, 1, 0)
    s = m.new_session()
    m.write_param(s, 6752, 0, 1000)  # operating time, minutes
    m.write_param(s, 6751, 0, 1234)  # and the ms past them
    assert m.timer_ms(1) == 60_001_234
    assert (m.read_param(6752, 0), m.read_param(6751, 0)) == (1000, 1234)
    with pytest.raises(MachineError) as refused:
        m.write_param(s, 6751, 0, 60_000)
    assert refused.value.ew == EW.DATA


def test_the_data_counter_moves_with_the_power_on_minute_once_it_was_read() -> None:
    clock = ManualClock(0.0)
    m = _machine(clock)
    before = m.read_param(6750, 0)
    seen = m.data_version
    clock.advance(30.0)
    assert m.data_version == seen
    clock.advance(30.0)
    assert m.data_version != seen
    assert m.read_param(6750, 0) == before + 1


def test_time_moves_no_counter_while_nothing_that_follows_it_was_read() -> None:
    clock = ManualClock(0.0)
    wall = [_WALL]
    m = default_machine(sim_clock=clock, clock=lambda: wall[0])
    data, macro = m.data_version, m.macro_version
    m.read_param(1020, 1)
    m.read_macro(500)
    clock.advance(600.0)
    wall[0] += timedelta(seconds=600)
    assert (m.data_version, m.macro_version) == (data, macro)
    hhmmss = m.read_macro(3012)  # from now on the macro counter follows the clock's second
    assert m.macro_version == macro
    wall[0] += timedelta(seconds=1)
    assert m.macro_version != macro
    assert hhmmss is not None
    assert m.read_macro(3012) == hhmmss + 1


def test_clock_variables_and_setting_the_clock() -> None:
    m = _machine(ManualClock(0.0))
    assert (m.read_macro(3011), m.read_macro(3012)) == (Decimal(20261207), Decimal(43015))
    m.set_cnc_date(2030, 2, 28)
    m.set_cnc_time(23, 59, 1)
    assert (m.read_macro(3011), m.read_macro(3012)) == (Decimal(20300228), Decimal(235901))
    assert m.now() == datetime(2030, 2, 28, 23, 59, 1, tzinfo=UTC)
    bads: list[tuple[Callable[[], None], str]] = [
        (lambda: m.set_cnc_date(2030, 2, 30), r"day 30 is outside 1\.\.28 \(2030-02\)"),
        (lambda: m.set_cnc_date(1986, 1, 1), "year 1986"),
        (lambda: m.set_cnc_time(24, 0, 0), r"hour 24 is outside 0\.\.23"),
        (lambda: m.set_cnc_time(0, 0, -1), r"second -1 is outside 0\.\.59"),
    ]
    for bad, named in bads:
        with pytest.raises(MachineError, match=named) as refused:
            bad()
        assert refused.value.ew == EW.DATA
    with pytest.raises(MachineError) as refused:
        m.write_macro(3011, 1)
    assert refused.value.ew == EW.PROT
    ro = default_machine(read_only=True)
    with pytest.raises(MachineError) as refused:
        ro.set_cnc_time(1, 2, 3)
    assert refused.value.ew == EW.PROT


def test_a_program_reads_the_clock_variables() -> None:
    clock = ManualClock(0.0)
    program = "O0002\n#500=#3011\n#501=#3012\nM30\n"
    m = default_machine(sim_clock=clock, clock=lambda: _WALL, programs=(program,))
    m.cycle_start()
    clock.advance(1.0)
    assert (m.read_macro(500), m.read_macro(501)) == (Decimal(20261207), Decimal(43015))


def test_overrides_and_g_signals_follow_each_other() -> None:
    m = _machine(ManualClock(0.0))
    assert list(m.read_pmc("G", 12, 3)) == [255 - 100, 0, 0]  # *FV: 100 %, ROV 100 %
    assert m.read_pmc("G", 30, 1) == bytes([100])
    m.set_overrides(50, 25, 120)
    assert (m.read_pmc("G", 12, 1)[0], m.read_pmc("G", 14, 1)[0] & 3) == (205, 2)
    assert m.read_pmc("G", 30, 1) == bytes([120])
    m.write_pmc("G", 12, bytes([255 - 80]))
    m.write_pmc("G", 14, bytes([0x81]))  # ROV1: 50 %; bit 7 is another signal
    m.write_pmc("G", 30, bytes([90]))
    assert m.overrides() == (80, 50, 90)
    assert m.read_pmc("G", 14, 1)[0] == 0x81


def test_g12_all_zeros_is_no_feed_and_a_ladders_bytes_stay_as_written() -> None:
    """FANUC's *FV0-*FV7: all 0s is 0 %, as all 1s; the CNC does not rewrite the ladder's G12
    or G30 when they read as the override they set."""
    m = _machine(ManualClock(0.0))
    for written, feed in ((0, 0), (0xFF, 0), (1, 254), (0xFE, 1)):
        m.write_pmc("G", 12, bytes([written]))
        assert (m.overrides()[0], m.read_pmc("G", 12, 1)[0]) == (feed, written)
    m.write_pmc("G", 30, bytes([0xFF]))  # above the highest spindle override
    assert (m.overrides()[2], m.read_pmc("G", 30, 1)[0]) == (254, 0xFF)
    m.set_overrides(30, 100, 60)  # the panel: the signals follow
    assert (m.read_pmc("G", 12, 1)[0], m.read_pmc("G", 30, 1)[0]) == (0xFF - 30, 60)


def test_g_signals_of_the_second_path_are_1000_bytes_on() -> None:
    from focas_net.sim import PmcAreaSpec

    m = Machine(
        "two",
        paths=[PathSpec(("X",), "P1"), PathSpec(("Z",), "P2")],
        pmc=[PmcAreaSpec("G", 1768), PmcAreaSpec("F", 1768)],
        sim_clock=ManualClock(0.0),
    )
    m.set_overrides(70, path=2)
    assert m.read_pmc("G", 1012, 1)[0] == 255 - 70
    m.write_pmc("G", 1030, bytes([60]))
    assert m.overrides(path=2)[2] == 60 and m.overrides(path=1)[2] == 100
    assert m.read_pmc("F", 1003, 1)[0] == m.read_pmc("F", 3, 1)[0] == 0x20  # MMEM


def test_f_signals_of_the_state() -> None:
    m = _machine(ManualClock(0.0))
    f = m.read_pmc("F", 0, 5)
    assert (f[0] >> 6 & 1, f[1] >> 7 & 1, f[1] & 1, f[3]) == (1, 1, 0, 0x20)  # SA MA AL MMEM
    m.set_panel(0)
    assert m.read_pmc("F", 3, 1)[0] == 0x08  # MMDI
    m.raise_alarm(0, 0, 100, "test")
    assert m.read_pmc("F", 1, 1)[0] & 1 == 1  # AL
    m.set_panel(emergency=1)
    f = m.read_pmc("F", 0, 2)
    assert (f[0] >> 6 & 1, f[1] >> 7 & 1) == (0, 0)


def test_servo_power_follows_the_servo_load() -> None:
    clock = ManualClock(0.0)
    m = _machine(clock)
    m.cycle_start()
    clock.advance(10.0)
    loads = m.servo_loads()
    assert [m.read_diag(4901, a) for a in (1, 2, 3)] == [load * 15 for load in loads]


# -- the codec -------------------------------------------------------------------------------


def test_golden_frames_as_fanuc_library_sends_them() -> None:
    # the bytes FANUC's library sent (logged with cnc_startupprocess(3, ...)), both sets
    head = "a0a0a0a0000121010"
    assert encode_part(cnc_gettimer(1).frames[0]).frame == bytes.fromhex(
        head + "01e0001001c000100010045" + "00000001" + "00" * 16
    )
    assert encode_part(cnc_rdopnlsgnl(0x1FFF).frames[0]).frame == bytes.fromhex(
        head + "01e0001001c00010001005d" + "00001fff" + "00" * 16
    )
    date_call = cnc_settimer(0, ClockValue(2026, 12, 7, 0, 0, 0))
    assert encode_part(date_call.frames[0]).frame == bytes.fromhex(
        head + "02a0001002800010001004600000000" + "00" * 12 + "0000000c07ea000c0007" + "00" * 6
    )


@given(st.tuples(*[st.integers(-0x8000, 0x7FFF)] * 6), st.integers(0, 1))
def test_clock_write_round_trips(words: tuple[int, ...], kind: int) -> None:
    req = ClockWriteRequest(kind, ClockValue(*words))
    assert ClockWriteRequest.from_block(req.to_block()) == req
    assert ClockValue.decode(req.value.encode()) == req.value


@given(st.tuples(*[st.integers(-0x8000, 0x7FFF)] * 13))
def test_panel_signals_round_trip(words: tuple[int, ...]) -> None:
    assert PanelSignals.decode(PanelSignals(*words).encode()) == PanelSignals(*words)
    assert len(PanelSignals(*words).encode()) == 26


@given(st.integers(-0x8000_0000, 0x7FFF_FFFF), st.integers(-0x8000_0000, 0x7FFF_FFFF))
def test_requests_decode_from_their_blocks(kind: int, select: int) -> None:
    assert ClockReadRequest.from_block(ClockReadRequest(kind).to_block()) == ClockReadRequest(kind)
    panel = PanelSignalsRequest(select)
    assert PanelSignalsRequest.from_block(panel.to_block()) == panel


def test_golden_answers() -> None:
    # the words FANUC's library copies into IODBTIMER and IODBSGNL, big-endian i16
    clock = ClockValue(2026, 12, 7, 4, 30, 15)
    assert clock.encode() == bytes.fromhex("07ea000c00070004001e000f")
    assert ClockValue.decode(bytes.fromhex("07ea000c00070004001e000f")) == clock
    panel = PanelSignals(1, 0, 0, 1, 0, 8, 0, 0, 1, 0, 0, 0, 1)
    golden = bytes.fromhex("0001" + "0000" * 2 + "0001" + "0000" + "0008" + "0000" * 2 + "0001")
    golden += bytes.fromhex("0000" * 3 + "0001")
    assert (panel.encode(), PanelSignals.decode(golden)) == (golden, panel)


# -- the adapter and the client -----------------------------------------------------------------


async def test_native_client_reads_and_sets_the_clock_and_panel_signals() -> None:
    clock = ManualClock(0.0)
    machine = _machine(clock)
    async with (
        serving(machine) as served,
        NativeClient(served.host, served.port, timeout=IO_TIMEOUT) as native,
        FocasClient(served.host, served.port, timeout=IO_TIMEOUT) as packed,
    ):
        assert await native.read_date() == date(2026, 12, 7)
        assert await native.read_time() == time(4, 30, 15)
        await native.write_date(date(2031, 5, 6))
        await native.write_time(time(7, 8, 9))
        assert machine.now() == datetime(2031, 5, 6, 7, 8, 9, tzinfo=UTC)
        with pytest.raises(CncError) as refused:
            await native.write_date(date(2040, 1, 1))
        assert refused.value.ew == EW.DATA
        with pytest.raises(TypeError, match="2031-05-06"):
            await native.write_date("2031-05-06")  # type: ignore[arg-type]
        with pytest.raises(TypeError, match="'07:08'"):
            await native.write_time("07:08")  # type: ignore[arg-type]
        machine.set_overrides(80, 50, 100)
        signals = await native.read_panel_signals()
        assert (signals.mode, signals.rapid, signals.feed, signals.feed_hold) == (1, 1, 8, 0)
        assert (await packed.read_pmc("G", 12, 1))[0] == 255 - 80
        assert await native.read_param(6750) == await packed.read_param(6750)
        assert (await native.read_macro(3011)) == (await packed.read_macro(3011))


def test_spindle_diagnostics_take_the_spindle_number() -> None:
    clock = ManualClock(0.0)
    m = _machine(clock)
    assert m.read_diag(403, 1) == m.read_diag(403, 0) == 33
    assert (m.read_diag(410, 1), m.read_diag(4902, 1)) == (0, 0)
    m.cycle_start()
    clock.advance(10.0)
    (load,) = m.spindle_loads()
    assert load > 0
    assert (m.read_diag(410, 1), m.read_diag(4902, 1)) == (load, load * 75)
    with pytest.raises(MachineError) as refused:
        m.read_diag(410, 2)  # one spindle
    assert refused.value.ew == EW.ATTRIB


def test_the_integrating_meter_counts_while_tmron_is_on() -> None:
    clock = ManualClock(0.0)
    m = _machine(clock)
    m.write_pmc("G", 53, b"\x01")  # TMRON
    clock.advance(61.5)
    m.write_pmc("G", 53, b"\x00")
    clock.advance(100.0)
    assert m.timer_ms(4) == 61_500
    assert (m.read_param(6756, 0), m.read_param(6755, 0)) == (1, 1_500)
    m.set_panel(0, 1, 0)
    m.write_param(m.new_session(), 6756, 0, 10)
    assert m.timer_ms(4) == 601_500
