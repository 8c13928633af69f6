"""Spindles and servo figures over the native protocol: the declarations (golden bytes and
round trips), the adapter's answers from the machine (idle and running, every selector), and
the native client against the server in both command sets.

The frames were seen sent by FANUC's library (``tests/test_fwlib_spindles.py`` compares them
with the library's, byte for byte, when ``FOCAS_NET_FWLIB`` is set); the golden bytes below
are those frames.
"""

from __future__ import annotations

import struct
from collections.abc import AsyncIterator
from decimal import Decimal

import pytest
from hypothesis import given
from hypothesis import strategies as st
from support import IO_TIMEOUT, serving

from focas_net.adapters import NativeAdapter
from focas_net.client import NativeClient, SpindleMeter
from focas_net.errors import EW, CncError
from focas_net.native import (
    CommandSet,
    RequestBlock,
    ServoFigure,
    SpindleFigure,
    SpindleLoadRequest,
    SpindleName,
    SpindleNameRequest,
    SpindleNames,
    build_open_answer,
    decode_open_answer,
    decode_request,
    encode_request_body,
    spindles,
)
from focas_net.native.calls import LibraryCall
from focas_net.native.opening import OpenHeadV3, PathDescription
from focas_net.sim import Machine, PathSpec, default_machine
from focas_net.sim.nc import ManualClock

PROGRAM = "O0100 (SPINDLE)\nN10 G90 G21 S3000 M3\nN20 G1 X60. F1200\nN30 M30\n"


def _body(call: LibraryCall) -> bytes:
    part = call.parts[0]
    return struct.pack(">H", part.count) + part.blocks


def _block(command: int, *args: int) -> str:
    full = (*args, 0, 0, 0, 0, 0)[:5]
    return struct.pack(">HHHH5i", 28, 1, 1, command, *full).hex()


# -- declarations --------------------------------------------------------------------------


def test_golden_frames_of_each_function() -> None:
    s16, s30 = CommandSet.FS16I, CommandSet.FS30I
    assert _body(spindles.cnc_rdspmaxrpm(s16, -1)).hex() == "0001" + _block(0x40, 1, -1)
    assert _body(spindles.cnc_rdspgear(s16, 2)).hex() == "0001" + _block(0x40, 2, 2)
    assert _body(spindles.cnc_acts2(s30, -1)).hex() == "0003" + "".join(
        [_block(0xA4, 1), _block(0x40, 3, -1), _block(0xA4, 1)]
    )
    assert _body(spindles.cnc_rdspdlname(s30)).hex() == "0001" + _block(0x8A, 0)
    assert _body(spindles.cnc_rdspmeter(s16, 0)).hex() == "0003" + "".join(
        [_block(0x40, 4, -1), _block(0x40, 5, -1), _block(0x8A, 0)]
    )
    assert _body(spindles.cnc_rdspmeter(s30, 1)).hex() == "0004" + "".join(
        [_block(0xA4, 1), _block(0x8A, -1), _block(0x40, 5, -1), _block(0xA4, 1)]
    )
    assert _body(spindles.cnc_rdspeed(s30, -1)).hex() == "0007" + "".join(
        [
            _block(0xA4, 3), _block(0x8A, 1), _block(0x88, 3), _block(0x88, 4), _block(0x24),
            _block(0x25), _block(0xA4, 3),
        ]
    )  # fmt: skip
    pmc = struct.pack(">HHHH5i", 28, 2, 1, 0x8001, 28, 28, 0, 0, 0).hex()  # G28, device PMC
    assert _body(spindles.cnc_rdspeed(s16, -1)).hex() == "0008" + "".join(
        [
            _block(0x24), _block(0x25), _block(0x88, 0), _block(0x0E, 3106, 3106),
            _block(0x0E, 3107, 3107), _block(0x0E, 9936, 9936), _block(0x21, 4), pmc,
        ]
    )  # fmt: skip
    for name, figure in (("cnc_rdloopgain", 0), ("cnc_rdcurrent", 1), ("cnc_rdsrvspeed", 2)):
        assert _body(getattr(spindles, name)(s16)).hex() == "0001" + _block(0x56, figure)


def test_spindle_names_golden() -> None:
    names = SpindleNames((SpindleName(b"S", b"1"), SpindleName(b"S", b"2")))
    assert names.encode() == b"S1\0\0S2\0\0"
    assert SpindleNames.decode(b"S1\0\0S2\0\0") == names
    assert [n.text for n in names.records] == ["S1", "S2"]
    block = SpindleNameRequest(-1).to_block()
    assert decode_request(block) == SpindleNameRequest(-1)


_CHAR = st.binary(min_size=1, max_size=1)


@given(st.lists(st.tuples(_CHAR, _CHAR, _CHAR, _CHAR), max_size=8))
def test_spindle_names_round_trip(raw: list[tuple[bytes, bytes, bytes, bytes]]) -> None:
    names = SpindleNames(tuple(SpindleName(*r) for r in raw))
    assert SpindleNames.decode(names.encode()) == names


@given(st.integers(-(2**31), 2**31 - 1), st.integers(-(2**31), 2**31 - 1))
def test_spindle_data_request_round_trip(kind: int, spindle: int) -> None:
    request = SpindleLoadRequest(kind, spindle)
    block = request.to_block()
    assert block.args[:2] == (kind, spindle)
    assert decode_request(RequestBlock(block.device, 1, block.command, block.args)) == request


def test_open_answer_carries_the_controlled_spindles() -> None:
    paths = [PathDescription(" M", 3, 2), PathDescription(" T", 2, 1)]
    body = build_open_answer(paths, 8, version=3)
    assert body[20:22] == b"\0\3"
    head = decode_open_answer(body, 3).head
    assert isinstance(head, OpenHeadV3) and head.controlled_spindles == 3
    assert build_open_answer(paths, 8, version=3, controlled_spindles=0)[20:22] == b"\0\0"


# -- the adapter -----------------------------------------------------------------------------


def _three_spindles(clock: ManualClock | None = None) -> Machine:
    spec = PathSpec(("X", "Y", "Z"), spindles=3)
    return Machine("spindles", paths=[spec], control_class="0i-F", sim_clock=clock)


def _answer(adapter: NativeAdapter, *blocks: RequestBlock) -> list[tuple[int, bytes]]:
    frame = adapter.answer(encode_request_body(blocks))
    body, out, pos = frame[12:], [], 0
    for _ in blocks:
        (length,) = struct.unpack_from(">H", body, pos)
        ew = struct.unpack_from(">h", body, pos + 8)[0]
        out.append((ew, body[pos + 16 : pos + length]))
        pos += length
    return out


def _mantissas(data: bytes) -> list[int]:
    return [struct.unpack_from(">i", data, i)[0] for i in range(0, len(data), 8)]


def _running(clock: ManualClock, machine: Machine) -> None:
    machine.store_program(PROGRAM)
    machine.set_panel(1)
    machine.select_program(100)
    machine.cycle_start()
    clock.advance(1.0)


@pytest.mark.parametrize("running", [False, True])
def test_each_figure_of_each_spindle(running: bool) -> None:
    clock = ManualClock()
    machine = _three_spindles(clock)
    adapter = NativeAdapter(machine)
    if running:
        _running(clock, machine)
    states = machine.spindles()
    assert [s.speed for s in states] == [3000 if running else 0, 0, 0]
    assert (states[0].load > 0) == running
    expected = {
        SpindleFigure.LOAD: [s.load for s in states],
        SpindleFigure.MAX_SPEED: [6000] * 3,
        SpindleFigure.GEAR: [1] * 3,
        SpindleFigure.SPEED: [s.speed for s in states],
        SpindleFigure.LOAD_METER: [s.load for s in states],
        SpindleFigure.MOTOR_SPEED: [s.speed for s in states],
    }
    for figure, values in expected.items():
        for every in (-1, 0):
            ((ew, data),) = _answer(adapter, SpindleLoadRequest(figure, every).to_block())
            assert ew == 0 and _mantissas(data) == values
        ((ew, data),) = _answer(adapter, SpindleLoadRequest(figure, 2).to_block())
        assert ew == 0 and _mantissas(data) == values[1:2]
    ((ew, _),) = _answer(adapter, SpindleLoadRequest(0, 4).to_block())
    assert ew == EW.NUMBER
    ((ew, _),) = _answer(adapter, SpindleLoadRequest(6, -1).to_block())
    assert ew == EW.ATTRIB
    ((ew, data),) = _answer(adapter, SpindleNameRequest(0).to_block())
    assert ew == 0 and data == b"S1\0\0S2\0\0S3\0\0"
    counts = _answer(adapter, *(RequestBlock(1, 1, 0xA4, (k, 0, 0, 0, 0)) for k in (1, 3)))
    assert counts == [(0, b"\0\3"), (0, b"\0\3")]


@pytest.mark.parametrize("running", [False, True])
def test_each_servo_figure(running: bool) -> None:
    clock = ManualClock()
    machine = default_machine(sim_clock=clock)
    adapter = NativeAdapter(machine)
    if running:
        _running(clock, machine)
    blocks = [RequestBlock(1, 1, 0x56, (int(f), 0, 0, 0, 0)) for f in ServoFigure]
    answers = _answer(adapter, *blocks)
    assert [ew for ew, _ in answers] == [0, 0, 0]
    gains, loads, speeds = (_mantissas(d) for _, d in answers)
    assert gains == [3000, 3000, 3000]
    assert loads == list(machine.servo_loads())
    assert speeds == list(machine.servo_speeds()) == ([120, 0, 0] if running else [0, 0, 0])
    assert (loads[0] > 0) == running
    ((ew, _),) = _answer(adapter, RequestBlock(1, 1, 0x56, (3, 0, 0, 0, 0)))
    assert ew == EW.ATTRIB


# -- the native client -------------------------------------------------------------------------


@pytest.fixture(params=["0i-F", "16i"])
async def client_on(request: pytest.FixtureRequest) -> AsyncIterator[tuple[Machine, NativeClient]]:
    clock = ManualClock()
    spec = PathSpec(("X", "Y", "Z"), spindles=3)
    machine = Machine("spindles", paths=[spec], control_class=request.param, sim_clock=clock)
    _running(clock, machine)
    async with serving(machine) as served:
        async with NativeClient(served.host, served.port, timeout=IO_TIMEOUT) as client:
            yield machine, client


async def test_client_reads_every_spindle(client_on: tuple[Machine, NativeClient]) -> None:
    machine, client = client_on
    states = machine.spindles()
    assert await client.read_spindle_speeds() == (3000, 0, 0)
    assert await client.read_spindle_speeds(1) == (3000,)
    assert await client.read_spindle_max_speeds() == (6000, 6000, 6000)
    assert await client.read_spindle_gears(3) == (1,)
    assert await client.read_spindle_loads() == tuple(s.load for s in states)
    assert await client.read_spindle_names() == ("S1", "S2", "S3")
    meters = await client.read_spindle_meters()
    assert meters == tuple(
        SpindleMeter(f"S{s.number}", Decimal(s.load), Decimal(s.speed)) for s in states
    )
    assert (await client.read_spindle_meters(1))[0] == SpindleMeter("S1", None, Decimal(3000))
    assert await client.read_servo_figures(ServoFigure.SPEED) == machine.servo_speeds()
    assert await client.read_servo_figures(ServoFigure.LOOP_GAIN) == (3000, 3000, 3000)
    assert await client.read_servo_figures(ServoFigure.LOAD) == machine.servo_loads()
    with pytest.raises(CncError) as refused:
        await client.read_spindle_gears(4)
    assert refused.value.ew == EW.NUMBER
    assert "cnc_rdspgear: spindle 4 (the path has 3)" in str(refused.value)
    with pytest.raises(ValueError, match="kind 2"):
        await client.read_spindle_meters(2)
    with pytest.raises(ValueError, match="spindle 0 is outside"):
        await client.read_spindle_speeds(0)
    with pytest.raises(ValueError, match="servo figure 3 is not 0"):
        await client.read_servo_figures(3)  # type: ignore[arg-type]
    for figure in (True, "1"):  # not an integer: a TypeError, as every argument's
        with pytest.raises(TypeError, match=f"servo figure must be .*got {figure!r}"):
            await client.read_servo_figures(figure)  # type: ignore[arg-type]
