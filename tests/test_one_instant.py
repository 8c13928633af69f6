"""A CNC answers one request at one instant: the blocks of one FOCAS/2 frame, and the figures
of one packed answer, are of one moment of machine time, however many clock readings building
the answer takes (``Machine.instant``).

The clock here moves a little every time it is read while ``ticking``, as a real clock moves
while an answer is built; without the instant the blocks of one frame would carry figures of
different moments (an axis's absolute and relative positions differing in one answer).
"""

from __future__ import annotations

import pytest

from focas_net.adapters import NativeAdapter, PackedAdapter
from focas_net.native import (
    NativePositionRequest,
    ResponseBlock,
    ScaledValues,
    decode_frame,
    decode_response_body,
    encode_request_body,
)
from focas_net.protocol import COMMANDS, Command
from focas_net.sim import Machine, default_machine

#: X from 0 to 600 at F1200: thirty seconds of motion, absolute = relative throughout.
PROGRAM = """O0100 (ONE INSTANT)
N10 G90 G21 G17 G54
N20 G1 X600. F1200
N30 M30
"""

#: Machine seconds a reading of the ticking clock moves it on.
TICK = 0.01


class TickingClock:
    """Machine time that moves by :data:`TICK` after every reading while :attr:`ticking`."""

    def __init__(self) -> None:
        self.at = 0.0
        self.ticking = False
        self.readings = 0

    def now(self) -> float:
        at = self.at
        self.readings += 1
        if self.ticking:
            self.at += TICK
        return at

    def advance(self, seconds: float) -> None:
        self.at += seconds


@pytest.fixture
def clock() -> TickingClock:
    return TickingClock()


@pytest.fixture
def machine(clock: TickingClock) -> Machine:
    m = default_machine(sim_clock=clock, programs=(PROGRAM,))
    m.cycle_start()
    clock.advance(5.0)  # X is on its way
    clock.ticking = True
    return m


def _positions(machine: Machine, kinds: tuple[int, ...]) -> list[ResponseBlock]:
    body = encode_request_body(tuple(NativePositionRequest(k, -1).to_block() for k in kinds))
    frame = NativeAdapter(machine).answer(body)
    return list(decode_response_body(decode_frame(frame).body))


def test_one_native_frame_is_one_instant(machine: Machine, clock: TickingClock) -> None:
    """Absolute (4), machine (1) and relative (6) of one frame agree, although the clock
    moved with every reading while the frame was answered."""
    blocks = _positions(machine, (4, 1, 6, 4))
    values = [ScaledValues.decode(b.data).values[0].mantissa for b in blocks]
    assert all(b.ew == 0 for b in blocks)
    assert values[0] > 0
    assert values == [values[0]] * 4
    # the next frame is of a later instant: time went on meanwhile
    later = ScaledValues.decode(_positions(machine, (4,))[0].data).values[0].mantissa
    assert later > values[0]


def test_a_frame_reads_the_clock_once(machine: Machine, clock: TickingClock) -> None:
    before = clock.readings
    _positions(machine, (4, 1, 6, 7, 4, 1, 6, 7))
    assert clock.readings - before == 1


def test_instants_nest_and_machine_time_runs_after(machine: Machine, clock: TickingClock) -> None:
    with machine.instant():
        first = machine.positions("absolute", 1)
        with machine.instant():
            assert machine.positions("relative", 1) == [("X", first[0][1])]
        assert machine.positions("machine", 1) == first
    assert machine.positions("absolute", 1)[0][1] > first[0][1]


def test_one_packed_answer_is_one_instant(machine: Machine, clock: TickingClock) -> None:
    """The packed run information carries the timers of one moment: the operating and
    cutting times of one answer grew by the same amount since the cycle start."""
    packed = PackedAdapter(machine)
    session = machine.new_session()
    before = clock.readings
    answer = packed.answer(session, Command.RDRUNINFO, b"")
    assert clock.readings - before == 1
    info = COMMANDS[Command.RDRUNINFO].response.decode(answer)
    # powered on, cycle started and cutting since machine time 0: one instant, one figure
    assert info.power_on_ms >= 5000
    assert info.power_on_ms == info.operating_ms == info.cutting_ms == info.cycle_ms
