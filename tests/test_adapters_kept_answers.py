"""The answers both adapters keep: a poller's repeated request is answered again as it was (the
same object) while the machine counters its reads follow hold, and never with anything that
changed. Kept answers are checked against a fresh adapter's after every kind of change a
machine has: writes of each kind, the panel, alarms, the motion figures, a program running in
machine time. Reads that move with time alone or with the program store are never kept, nor
refusals."""

from __future__ import annotations

from decimal import Decimal

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from focas_net.adapters import NativeAdapter, PackedAdapter
from focas_net.native import (
    CommandSet,
    Device,
    NativeCommand,
    NativePmcArea,
    RequestBlock,
    StatInfo,
    decode_frame,
    decode_response_body,
    encode_request_body,
)
from focas_net.native import calls as native_calls
from focas_net.protocol import (
    Command,
    DataRequest,
    MacroRequest,
    PmcArea,
    PmcRange,
    PositionRequest,
)
from focas_net.protocol.codecs import AlarmHistoryRequest, AlarmMsgRequest
from focas_net.sim import Machine, MachineError, default_machine
from focas_net.sim.nc import ManualClock

#: cnc_statinfo's frame (0x19, 0xE1, 0x98) and a system information block.
STATINFO = encode_request_body(native_calls.cnc_statinfo(CommandSet.FS30I).blocks()[0])
SYSINFO = encode_request_body([RequestBlock(Device.CNC, 1, NativeCommand.SYSINFO)])


def _body(*calls: native_calls.LibraryCall) -> bytes:
    """One request body of the first frame of each call, in order."""
    return encode_request_body([b for call in calls for b in call.blocks()[0]])


def _bodies(cs: CommandSet) -> list[bytes]:
    """Requests of every read the memo keeps, alone and mixed, in command set ``cs``."""
    c = native_calls
    pmc = NativePmcArea
    alone = [
        c.cnc_statinfo(cs),
        c.cnc_rdmacro(cs, 3901),
        c.cnc_rdmacror2(cs, 100, 4),
        c.cnc_rdparam(cs, 6711, 0),
        c.cnc_rdparam(cs, 1320, -1),
        c.cnc_diagnoss(cs, 410, 0),
        c.pmc_rdpmcrng(cs, pmc.R, 0, 0, 7),
        c.cnc_alarm(cs),
        c.cnc_rdalmmsg(cs, -1, 4),
        c.cnc_rdalmhistry(cs, 1, 3),
        c.cnc_rdprgnum(cs),
        c.cnc_exeprgname(cs),
        c.cnc_rdseqnum(cs),
        c.cnc_actf(cs),
        c.cnc_acts(cs),
        c.cnc_absolute(cs, -1),
        c.cnc_rdcncid(cs),
        c.cnc_rdaxisname(cs),
    ]
    return [
        *(_body(call) for call in alone),
        _body(c.cnc_rdmacro(cs, 100), c.cnc_rdmacro(cs, 101), c.cnc_rdmacro(cs, 3901)),
        _body(c.cnc_actf(cs), c.cnc_acts(cs), c.cnc_absolute(cs, -1), c.cnc_machine(cs, 1)),
        _body(c.cnc_rddynamic2(cs, -1)),
        _body(c.cnc_rdmacro(cs, 100), c.cnc_statinfo(cs), c.pmc_rdpmcrng(cs, pmc.G, 0, 0, 1)),
        encode_request_body([RequestBlock(Device.CNC, 1, NativeCommand.STATINFO)]),
        # reads never kept: time moves them, or the program store
        _body(c.cnc_rdtimer(cs, 0), c.cnc_rdmacro(cs, 100)),
        _body(c.cnc_rdspload(cs, 1), c.cnc_rdproginfo(cs)),
    ]


#: What changes a machine: (action, argument) steps.
STEPS = st.lists(
    st.one_of(
        st.tuples(st.just("mode"), st.sampled_from([0, 1, 3, 4, 5])),
        st.tuples(st.just("emergency"), st.sampled_from([0, 1])),
        st.tuples(st.just("alarm"), st.integers(1, 999)),
        st.tuples(st.just("clear"), st.just(0)),
        st.tuples(st.just("start"), st.just(0)),
        st.tuples(st.just("reset"), st.just(0)),
        st.tuples(st.just("time"), st.floats(0.0, 30.0)),
        st.tuples(st.just("macro"), st.integers(100, 101)),
        st.tuples(st.just("param"), st.integers(0, 9999)),
        st.tuples(st.just("diag"), st.integers(0, 9999)),
        st.tuples(st.just("pmc"), st.integers(0, 255)),
        st.tuples(st.just("motion"), st.integers(-9999, 9999)),
    ),
    max_size=12,
)


def _change(machine: Machine, clock: ManualClock, action: str, arg: float) -> None:
    """Apply one step; a step the machine refuses in its state changes nothing."""
    n = int(arg)
    try:
        if action == "mode":
            machine.set_panel(mode=n)
        elif action == "emergency":
            machine.set_panel(emergency=n)
        elif action == "alarm":
            machine.raise_alarm(0, 2, n, "memo")
        elif action == "clear":
            machine.clear_alarms()
        elif action == "start":
            machine.set_panel(mode=1)
            machine.cycle_start()
        elif action == "reset":
            machine.reset()
        elif action == "time":
            clock.advance(arg)
        elif action == "macro":
            machine.write_macro(n, Decimal(n) / 8 + machine.sim_clock.now().__floor__())
        elif action == "param":
            machine.set_panel(pwe=1)
            machine.write_param(machine.new_session(), 6711, 0, n)
        elif action == "diag":
            machine.set_diag(410, 0, n)
        elif action == "pmc":
            machine.write_pmc("R", 3, bytes([n]))
        else:
            machine.set_motion(
                feed=abs(n), absolute=[n, -n, 2 * n], sequence=abs(n), program_running=abs(n)
            )
    except MachineError:
        pass


@pytest.mark.parametrize("version", [2, 3])
@settings(max_examples=40, deadline=None)
@given(steps=STEPS)
def test_memo_answers_what_a_fresh_adapter_answers(
    version: int, steps: list[tuple[str, float]]
) -> None:
    clock = ManualClock()
    machine = default_machine(sim_clock=clock)
    machine.raise_alarm(0, 2, 1, "history")  # so that the history has a record to read
    adapter = NativeAdapter(machine, version=version)
    bodies = _bodies(adapter.command_set)
    # every kept read is answered again as it was before the first step, the others afresh
    assert [adapter.answer(body) is adapter.answer(body) for body in bodies] == [True] * (
        len(bodies) - 2
    ) + [False, False]
    for action, arg in steps:
        _change(machine, clock, action, arg)
        for body in bodies:
            fresh = NativeAdapter(machine, version=version).answer(body)
            assert adapter.answer(body) == fresh, (action, arg, body.hex())
        assert adapter.answer(SYSINFO) == NativeAdapter(machine, version=version).answer(SYSINFO)


def test_a_repeated_read_is_answered_from_the_memo_and_a_timer_never() -> None:
    adapter = NativeAdapter(default_machine())
    cs = adapter.command_set
    macros = _body(native_calls.cnc_rdmacro(cs, 100), native_calls.cnc_rdparam(cs, 6711, 0))
    assert adapter.answer(macros) is adapter.answer(macros)
    timer = _body(native_calls.cnc_rdtimer(cs, 0), native_calls.cnc_rdmacro(cs, 100))
    assert adapter.answer(timer) is not adapter.answer(timer)
    assert adapter.answer(timer) == adapter.answer(timer)


def test_an_answer_with_an_ew_code_is_not_kept() -> None:
    machine = default_machine()
    adapter = NativeAdapter(machine)
    body = _body(native_calls.cnc_rdmacro(adapter.command_set, 100))
    unknown = _body(native_calls.cnc_rdmacro(adapter.command_set, 29999))
    first = adapter.answer(unknown)
    assert decode_response_body(decode_frame(first)[2])[0].ew != 0
    again = adapter.answer(unknown)
    assert again == first and again is not first
    assert adapter.answer(body) is adapter.answer(body)


def test_the_memo_keeps_a_bounded_number_of_answers() -> None:
    """Of a hundred different reads, the first is no longer kept at the end."""
    adapter = NativeAdapter(default_machine())
    cs = adapter.command_set
    bodies = [_body(native_calls.cnc_rdmacro(cs, number)) for number in range(100, 200)]
    first = adapter.answer(bodies[0])
    assert adapter.answer(bodies[0]) is first
    for body in bodies[1:]:
        adapter.answer(body)
    assert adapter.answer(bodies[-1]) is adapter.answer(bodies[-1])
    again = adapter.answer(bodies[0])
    assert again == first and again is not first


def test_the_memo_follows_an_alarm() -> None:
    machine = default_machine()
    adapter = NativeAdapter(machine)

    def alarm_field() -> int:
        _, _, body = decode_frame(adapter.answer(STATINFO))
        first = decode_response_body(body)[0]
        return StatInfo.decode(first.data).alarm

    assert alarm_field() == 0
    assert adapter.answer(STATINFO) is adapter.answer(STATINFO)  # served from the memo
    machine.raise_alarm(0, 2, 100, "memo")
    assert alarm_field() == 1


#: Packed requests: (command, request payload) of every read the packed adapter keeps.
PACKED_KEPT = [
    (Command.RDCNCSTAT, b""),
    (Command.RDPARAM, DataRequest(6711, 0).encode()),
    (Command.RDPARAM, DataRequest(1320, 1).encode()),
    (Command.RDDIAG, DataRequest(410, 0).encode()),
    (Command.RDMACRO, MacroRequest(100).encode()),
    (Command.RDMACRO, MacroRequest(3901).encode()),
    (Command.RDALMMSG, AlarmMsgRequest(-1, 4).encode()),
    (Command.RDALMHISTRY, AlarmHistoryRequest(3).encode()),
    (Command.RDPMCRNG, PmcRange(PmcArea.R, 0, 0, 7).encode()),
    (Command.RDPRGNUM, b""),
    (Command.ACTF, b""),
    (Command.ACTS, b""),
    (Command.RDPOSITION, PositionRequest(0, -1).encode()),
    (Command.RDPOSITION, PositionRequest(1, 2).encode()),
]
#: Packed reads never kept: timers and parts counts move with time, loads too.
PACKED_AFRESH = [(Command.RDRUNINFO, b""), (Command.RDLOADS, b"")]


@settings(max_examples=40, deadline=None)
@given(steps=STEPS)
def test_packed_kept_answers_are_what_a_fresh_adapter_answers(
    steps: list[tuple[str, float]],
) -> None:
    clock = ManualClock()
    machine = default_machine(sim_clock=clock)
    machine.raise_alarm(0, 2, 1, "history")
    session = machine.new_session()
    adapter = PackedAdapter(machine)
    requests = PACKED_KEPT + PACKED_AFRESH
    kept = [adapter.answer(session, c, p) is adapter.answer(session, c, p) for c, p in requests]
    assert kept == [True] * len(PACKED_KEPT) + [False] * len(PACKED_AFRESH)
    for action, arg in steps:
        _change(machine, clock, action, arg)
        for command, payload in requests:
            fresh = PackedAdapter(machine).answer(session, command, payload)
            assert adapter.answer(session, command, payload) == fresh, (action, arg, command)


def test_packed_answers_kept_are_bounded() -> None:
    """Of two thousand different PMC reads, the first is no longer kept at the end."""
    machine = default_machine()
    session = machine.new_session()
    adapter = PackedAdapter(machine)
    payloads = [PmcRange(PmcArea.R, 0, start, start).encode() for start in range(2000)]
    first = adapter.answer(session, Command.RDPMCRNG, payloads[0])
    for payload in payloads[1:]:
        adapter.answer(session, Command.RDPMCRNG, payload)
    again = adapter.answer(session, Command.RDPMCRNG, payloads[0])
    assert again == first and again is not first


def test_packed_status_follows_the_panel() -> None:
    machine = default_machine()
    session = machine.new_session()
    adapter = PackedAdapter(machine)
    before = adapter.answer(session, Command.RDCNCSTAT, b"")
    assert adapter.answer(session, Command.RDCNCSTAT, b"") is before
    machine.set_panel(emergency=1)
    after = adapter.answer(session, Command.RDCNCSTAT, b"")
    assert after != before
    assert after == PackedAdapter(machine).answer(session, Command.RDCNCSTAT, b"")
