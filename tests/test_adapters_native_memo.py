"""The native adapter's memo of status answers: a poller's repeated ``cnc_statinfo`` is
answered from it while the status holds, and never with a status that changed."""

from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st

from focas_net.adapters import NativeAdapter
from focas_net.native import (
    CommandSet,
    Device,
    NativeCommand,
    RequestBlock,
    StatInfo,
    decode_frame,
    decode_response_body,
    encode_request_body,
)
from focas_net.native import calls as native_calls
from focas_net.sim import default_machine
from focas_net.sim.nc import ManualClock

#: cnc_statinfo's frame (0x19, 0xE1, 0x98) and a system information block.
STATINFO = encode_request_body(native_calls.cnc_statinfo(CommandSet.FS30I).blocks()[0])
SYSINFO = encode_request_body([RequestBlock(Device.CNC, 1, NativeCommand.SYSINFO)])

#: What changes a status: (action, argument) steps applied to the machine.
STEPS = st.lists(
    st.one_of(
        st.tuples(st.just("mode"), st.sampled_from([0, 1, 3, 4, 5])),
        st.tuples(st.just("emergency"), st.sampled_from([0, 1])),
        st.tuples(st.just("alarm"), st.integers(1, 999)),
        st.tuples(st.just("clear"), st.just(0)),
        st.tuples(st.just("start"), st.just(0)),
        st.tuples(st.just("time"), st.floats(0.0, 30.0)),
    ),
    max_size=12,
)


@settings(max_examples=60, deadline=None)
@given(STEPS)
def test_memo_answers_what_a_fresh_adapter_answers(steps: list[tuple[str, float]]) -> None:
    clock = ManualClock()
    machine = default_machine(sim_clock=clock)
    adapter = NativeAdapter(machine)
    for action, arg in steps:
        adapter.answer(STATINFO)  # the memo holds the answer before this step
        if action == "mode":
            machine.set_panel(mode=int(arg))
        elif action == "emergency":
            machine.set_panel(emergency=int(arg))
        elif action == "alarm":
            machine.raise_alarm(0, 2, int(arg), "memo")
        elif action == "clear":
            machine.clear_alarms()
        elif action == "start":
            try:
                machine.cycle_start()
            except Exception:  # refused in this state (an alarm, not MEM): nothing changed
                pass
        else:
            clock.advance(arg)
        fresh = NativeAdapter(machine).answer(STATINFO)
        assert adapter.answer(STATINFO) == fresh
        assert adapter.answer(SYSINFO) == NativeAdapter(machine).answer(SYSINFO)


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
