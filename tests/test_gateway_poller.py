"""The gateway's poller against simulated machines served on 127.0.0.1: every item of every
path delivered once, then only changes; alarms as events; a machine stopped and started again
goes offline and comes back with every value sent again; both protocols, a 2-path lathe."""

from __future__ import annotations

from contextlib import AsyncExitStack
from pathlib import Path
from typing import Literal

import pytest
from poller_support import QUICK, RecordingSink, all_online, config, polling, until
from support import serving, two_path_lathe

from focas_net.errors import EW, OPCUA_GOOD, ew_info
from focas_net.gateway import (
    MachineConfig,
)
from focas_net.gateway.poller import reason_of
from focas_net.gateway.reads import NOT_SUPPORTED
from focas_net.server import FocasServer
from focas_net.sim import Machine, default_machine, load_machine
from focas_net.sim.nc import ManualClock

LATHE = Path(__file__).resolve().parent.parent / "examples" / "lathe_2path.toml"


def lathe() -> Machine:
    return load_machine(LATHE, sim_clock=ManualClock())


async def test_every_item_of_every_path_once_then_only_changes() -> None:
    clock = ManualClock(1_000.0)
    async with AsyncExitStack() as stack:
        mill = await stack.enter_async_context(serving(default_machine()))
        turn = await stack.enter_async_context(serving(lathe()))
        machines = [
            config("mill", mill.port),
            config("lathe", turn.port),
            config("lathe-packed", turn.port, "packed"),
        ]
        poller, sink = await stack.enter_async_context(polling(machines, clock))
        await until(poller, clock, all_online(poller))
        clock.advance(10.0)  # (each machine's first reads are staggered over the intervals)
        await poller.step()  # the first reads of every group

        shapes = {s.name: s for s in sink.shapes}
        assert [p.number for p in shapes["lathe"].paths] == [1, 2]
        # (each axis named as the screen shows it, its suffix after its letter, over both)
        assert [p.axes for p in shapes["lathe"].paths] == [("X1", "Z1"), ("X2", "Z2")]
        assert [p.axes for p in shapes["lathe-packed"].paths] == [("X1", "Z1"), ("X2", "Z2")]
        assert [p.number for p in shapes["mill"].paths] == [1]
        assert shapes["mill"].protocol == "native"
        for name in ("lathe", "lathe-packed"):
            got = sink.of(name)
            for path in shapes[name].paths:
                for item in ("mode", "run", "feed", "program", "feed_override", "parts"):
                    assert (path.number, item, "") in got, (name, path.number, item)
                for axis in path.axes:
                    for item in ("absolute", "machine", "relative", "distance", "servo_load"):
                        assert got[(path.number, item, axis)].status == OPCUA_GOOD
        native, packed = sink.of("lathe"), sink.of("lathe-packed")
        assert native[(1, "sequence", "")].status == OPCUA_GOOD
        assert packed[(1, "sequence", "")].status == NOT_SUPPORTED
        assert packed[(2, "message", "")].value is None
        for same, sample in packed.items():  # one CNC through both transports, alike
            if sample.status == OPCUA_GOOD and same[1] not in _MOVING:
                assert native[same].status == OPCUA_GOOD, same
                assert native[same].value == sample.value, same
        keys = [
            (s.machine, s.path, s.item.name, s.key) for s in sink.got if s.item.name not in _MOVING
        ]
        assert len(keys) == len(set(keys)), keys  # each value once

        sink.clear()
        for _ in range(3):
            clock.advance(1.0)
            await poller.step()
        assert [s for s in sink.got if s.item.name not in _MOVING] == []
        clock.advance(10.0)
        await poller.step()
        assert [s for s in sink.got if s.item.name not in _MOVING] == []

        turn.machine.set_overrides(feed=70, path=2)
        turn.machine.set_motion(path=2, feed=321)
        mill.machine.set_overrides(spindle=120)
        clock.advance(1.0)
        await poller.step()
        changed = {(s.machine, s.path, s.item.name, s.value) for s in sink.got}
        assert changed - {c for c in changed if c[2] in _MOVING} == {
            ("lathe", 2, "feed", 321.0),
            ("lathe-packed", 2, "feed", 321.0),
            # (FOCAS/2 reads path 2's feed override from G1012, the packed protocol asks it)
            ("lathe", 2, "feed_override", 70),
            ("lathe-packed", 2, "feed_override", 70),
            ("mill", 1, "spindle_override", 120),
        }


#: Items that move with time alone on a machine that is not running (the power-on timer).
_MOVING = {"power_on_time"}


async def test_the_machines_first_polls_are_spread_over_each_interval() -> None:
    clock = ManualClock(1_000.0)
    async with serving(default_machine()) as mill:
        machines = [config(f"m{i}", mill.port) for i in range(4)]  # fast 1 s, slow 10 s
        async with polling(machines, clock) as (poller, sink):
            await until(poller, clock, all_online(poller))  # (the clock stands still)

            def read(item: str) -> set[str]:
                return {s.machine for s in sink.got if s.item.name == item}

            fast: list[set[str]] = []
            for _ in range(4):  # the k-th of 4 machines: k/4 of the fast interval later
                await poller.step()
                fast.append(read("mode"))
                assert read("parts") == {"m0"}
                clock.advance(0.25)
            assert fast == [{"m0"}, {"m0", "m1"}, {"m0", "m1", "m2"}, {"m0", "m1", "m2", "m3"}]
            slow: list[set[str]] = []
            for _ in range(3):  # and k/4 of the slow interval later
                clock.advance(2.5)
                await poller.step()
                slow.append(read("parts"))
            assert slow == [{"m0", "m1"}, {"m0", "m1", "m2"}, {"m0", "m1", "m2", "m3"}]


async def test_alarms_raised_and_cleared_are_events_of_their_path() -> None:
    clock = ManualClock(1_000.0)
    async with AsyncExitStack() as stack:
        turn = await stack.enter_async_context(serving(lathe()))
        machines = [config("lathe", turn.port), config("packed", turn.port, "packed")]
        poller, sink = await stack.enter_async_context(polling(machines, clock))
        await until(poller, clock, all_online(poller))
        await poller.step()
        assert sink.changes == []
        turn.machine.raise_alarm(1, 4, 510, "OVER TRAVEL +Z", path=2)
        clock.advance(1.0)
        await poller.step()
        assert {
            (c.machine, c.path, c.alm_type, c.alm_no, c.axis_no, c.active) for c in sink.changes
        } == {
            ("lathe", 2, 4, 510, 1, True),
            ("packed", 2, 4, 510, 1, True),
        }
        assert all(c.msg == "OVER TRAVEL +Z" for c in sink.changes)
        assert sink.of("lathe")[(2, "alarm", "")].value is True
        sink.clear()
        clock.advance(1.0)
        await poller.step()
        assert sink.changes == []  # still active: no event
        turn.machine.clear_alarms(path=2)
        clock.advance(1.0)
        await poller.step()
        assert {(c.machine, c.path, c.alm_no, c.active) for c in sink.changes} == {
            ("lathe", 2, 510, False),
            ("packed", 2, 510, False),
        }


@pytest.mark.parametrize("protocol", ["native", "packed"])
async def test_a_stopped_machine_goes_offline_and_comes_back_with_every_value(
    protocol: Literal["native", "packed"],
) -> None:
    clock = ManualClock(1_000.0)
    machine = lathe()
    async with AsyncExitStack() as stack:
        other = await stack.enter_async_context(serving(default_machine()))
        server = FocasServer(machine, host="127.0.0.1", port=0, grace_period=0.5)
        await server.start()
        port = server.listeners[0].address[1]
        try:
            machines = [config("lathe", port, protocol), config("other", other.port)]
            poller, sink = await stack.enter_async_context(polling(machines, clock))
            await until(poller, clock, all_online(poller))
            await poller.step()
            before = sink.of("lathe")
            sink.clear()
            sink.shapes.clear()

            await server.aclose()
            await until(poller, clock, lambda: poller.is_online("lathe") is False, 1.0)
            ((name, up, reason),) = sink.states
            assert (name, up) == ("lathe", False) and reason
            assert poller.is_online("other")

            sink.clear()
            server = FocasServer(machine, host="127.0.0.1", port=port, grace_period=0.5)
            await server.start()
            await until(poller, clock, lambda: poller.is_online("lathe") is True, 1.0)
            clock.advance(10.0)
            await poller.step()
            assert ("lathe", True, "") in sink.states
            again = sink.of("lathe")
            assert set(again) == set(before)  # every value sent again
            assert len(sink.shapes) == 0  # the same shape: not described again
        finally:
            await server.aclose()


async def test_a_machine_never_reached_is_offline_and_the_others_deliver() -> None:
    clock = ManualClock(1_000.0)
    async with AsyncExitStack() as stack:
        mill = await stack.enter_async_context(serving(default_machine()))
        closed = await stack.enter_async_context(serving(default_machine()))
        dead = closed.port
        await closed.server.aclose()
        machines = [config("mill", mill.port), config("dead", dead)]
        poller, sink = await stack.enter_async_context(polling(machines, clock))
        await until(poller, clock, lambda: poller.is_online("mill") is True)
        await until(poller, clock, lambda: poller.is_online("dead") is False)
        assert [(m, up) for m, up, _ in sink.states if m == "dead"] == [("dead", False)]
        assert next(r for m, _, r in sink.states if m == "dead").startswith("refused")
        assert sink.of("mill")
        assert not sink.of("dead")


async def test_an_ew_code_on_one_read_gives_its_items_the_ews_status() -> None:
    clock = ManualClock(1_000.0)
    async with serving(two_path_lathe()) as bare:
        async with polling([config("bare", bare.port)], clock) as (poller, sink):
            await until(poller, clock, all_online(poller))
            await poller.step()
            got = sink.of("bare")
    # a machine without parameter 6713 nor #3901 (EW_NUMBER), nor a PMC (EW_NOOPT)
    for path in (1, 2):
        for item in ("parts_required", "parts"):
            assert got[(path, item, "")].status == ew_info(EW.NUMBER).opcua
            assert got[(path, item, "")].value is None
        assert got[(path, "spindle_override", "")].status == ew_info(EW.NOOPT).opcua
        assert got[(path, "mode", "")].status == OPCUA_GOOD
        assert got[(path, "program", "")].value == path


def test_reasons_name_what_happened() -> None:
    from focas_net.errors import FocasConnectionError, FocasTimeoutError, ProtocolError

    assert reason_of(FocasTimeoutError("no answer")).startswith("timeout: ")
    assert reason_of(FocasConnectionError("connection refused by 1.2.3.4")).startswith("refused")
    assert reason_of(FocasConnectionError("connection reset by peer")).startswith("reset")
    assert reason_of(ProtocolError("bad frame")).startswith("protocol: ")
    assert reason_of(FocasConnectionError("gone")) == "lost: gone"


async def test_the_gateway_runs_the_poller_and_writes_through_the_gates() -> None:
    from decimal import Decimal

    from support import wait_until

    from focas_net.errors import CncError
    from focas_net.gateway import Gateway, GatewayConfig, WriteGates
    from focas_net.gateway.run import outputs

    machine = default_machine()
    async with serving(machine) as turn:
        gates = WriteGates(macros=((500, 599),), params=((6711, 6713),), pmc=(("R", 100, 199),))
        configs = (
            MachineConfig("open", "127.0.0.1", turn.port, "native", timeout=2.0, writes=gates),
            MachineConfig("shut", "127.0.0.1", turn.port, "packed", timeout=2.0),
        )
        sink = RecordingSink()
        gateway = Gateway(GatewayConfig(configs), policy=QUICK)
        gateway.add_sink(sink)
        assert outputs(gateway.config, gateway.writer) == []  # no [mqtt], no [opcua]
        async with gateway:
            assert gateway.running
            await wait_until(lambda: {m for m, up, _ in sink.states if up} == {"open", "shut"})
            await wait_until(lambda: (1, "mode", "") in sink.of("shut"))
            with pytest.raises(RuntimeError):
                gateway.add_sink(RecordingSink())

            writer = gateway.writer
            await writer.write_macro("open", 510, Decimal("1.25"), 1)
            assert machine.read_macro(510) == Decimal("1.25")
            with pytest.raises(CncError) as refused:  # let through, refused by the CNC
                await writer.write_param("open", 6713, 40, 0)
            assert refused.value.ew == EW.PASSWD
            await writer.write_pmc("open", "R", 150, 7)
            assert machine.read_pmc("R", 150, 1) == b"\x07"
            refusals = [
                (writer.write_macro("open", 600, Decimal(1), 1), "open: writes.macros", "#600"),
                (writer.write_param("open", 1320, 1, 1), "writes.params", "parameter 1320"),
                (writer.write_pmc("open", "D", 150, 1), "writes.pmc does not allow D150", "R100"),
                (writer.write_macro("shut", 500, Decimal(1), 1), "shut: writes.macros", "no macro"),
                (writer.write_pmc("shut", "R", 100, 1), "shut: writes.pmc", "no PMC byte"),
            ]
            for call, gate, value in refusals:
                with pytest.raises(PermissionError) as caught:
                    await call
                assert gate in str(caught.value) and value in str(caught.value)
            with pytest.raises(ValueError, match="PMC byte value"):
                await writer.write_pmc("open", "R", 100, 256)
            with pytest.raises(CncError) as refused:  # a path it has not
                await writer.write_macro("open", 590, Decimal(1), 2)
            assert refused.value.ew == EW.PATH
            with pytest.raises(KeyError, match="no machine 'nowhere'"):
                await writer.write_macro("nowhere", 500, Decimal(1), 1)
        assert not gateway.running


async def test_a_machine_that_answers_late_holds_back_no_other() -> None:
    from support import wait_until

    from focas_net.client import FocasClient
    from focas_net.gateway import Gateway, GatewayConfig
    from focas_net.protocol import FaultKind, FaultScope

    async with serving() as late, serving() as quick:
        configs = (
            MachineConfig("late", "127.0.0.1", late.port, timeout=60.0),
            MachineConfig("quick", "127.0.0.1", quick.port, timeout=5.0),
        )
        sink = RecordingSink()
        async with Gateway(GatewayConfig(configs), [sink], policy=QUICK):
            await wait_until(lambda: (1, "spindle_override", "") in sink.of("late"))
            await wait_until(lambda: (1, "spindle_override", "") in sink.of("quick"))
            async with FocasClient(late.host, late.port) as packed:  # every answer 30 s late
                await packed.sim.inject_fault(
                    FaultKind.DELAY, count=100, arg=30_000, scope=FaultScope.MACHINE
                )
            for percent in (130, 90, 110):  # the quick machine's changes keep coming
                quick.machine.set_overrides(spindle=percent)
                await wait_until(
                    lambda p=percent: sink.of("quick")[(1, "spindle_override", "")].value == p,
                    within=20.0,
                )
            assert not [s for s in sink.states if s[0] == "late" and not s[1]]  # not lost yet
