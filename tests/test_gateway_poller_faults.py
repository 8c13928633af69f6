"""The poller against faults of its own parts: a sink that raises, a machine whose shape read
fails with an error no client should raise, an answer its conversion cannot read, NaN values,
and what shutting it down leaves behind. Simulated machines on 127.0.0.1; the poller stepped by
hand on a ManualClock."""

from __future__ import annotations

import asyncio
import logging
import math
from collections.abc import Sequence
from typing import Any, Literal

import pytest
from poller_support import QUICK, SLOW, Garbage, RecordingSink, Silent, all_online, config, until
from support import serving

from focas_net.client import NativeClient, ReconnectPolicy, StartedCall
from focas_net.errors import OPCUA_GOOD, ProtocolError
from focas_net.gateway import AlarmChange, MachineConfig, MachineShape, Sample
from focas_net.gateway.poller import Poller
from focas_net.sim.nc import ManualClock


class FailingSink(RecordingSink):
    """A sink whose every ``described`` and ``online`` call raises (after keeping it)."""

    def described(self, shape: MachineShape) -> None:
        super().described(shape)
        raise RuntimeError("described failed")

    def online(self, machine: str, online: bool, reason: str, time: float) -> None:
        super().online(machine, online, reason, time)
        raise RuntimeError("online failed")


class SamplesFailSink(RecordingSink):
    def samples(self, samples: Sequence[Sample]) -> None:
        super().samples(samples)
        raise RuntimeError("samples failed")

    def alarms(self, changes: Sequence[AlarmChange]) -> None:
        super().alarms(changes)
        raise RuntimeError("alarms failed")


async def test_a_sink_that_raises_is_logged_and_misses_nothing_else(
    caplog: pytest.LogCaptureFixture,
) -> None:
    clock = ManualClock(1_000.0)
    failing, other = FailingSink(), SamplesFailSink()
    async with serving() as one, serving() as two:
        machines = [config("one", one.port), config("two", two.port)]
        async with Poller(machines, [failing, other], clock=clock.now, policy=QUICK) as poller:
            with caplog.at_level(logging.ERROR, "focas_net.gateway.poller"):
                await until(poller, clock, all_online(poller))
                await poller.step()
                one.machine.raise_alarm(0, 1, 100, "TEST")
                clock.advance(1.0)
                await poller.step()
    for sink in (failing, other):  # each call of each sink made, though others raised
        assert {s.name for s in sink.shapes} == {"one", "two"}
        assert {(m, up) for m, up, _ in sink.states} == {("one", True), ("two", True)}
        assert (1, "mode", "") in sink.of("one") and (1, "mode", "") in sink.of("two")
        assert [(c.machine, c.alm_no, c.active) for c in sink.changes] == [("one", 100, True)]
    failures = {r.getMessage() for r in caplog.records if r.exc_info}
    assert any("FailingSink" in m and "online" in m for m in failures)
    assert any("SamplesFailSink" in m and "alarms" in m for m in failures)


def polling_with(
    kind: type[NativeClient], port: int, sink: RecordingSink, clock: ManualClock, policy: Any
) -> Poller:
    """A poller of machine "one" on ``port`` through a client of class ``kind``."""

    def client_of(c: MachineConfig, p: ReconnectPolicy) -> NativeClient:
        return kind(c.host, c.port, timeout=c.timeout, reconnect=p)

    return Poller(
        [config("one", port)], [sink], clock=clock.now, policy=policy, client_of=client_of
    )


class Garbled(NativeClient):
    """A client whose shape read fails with what no client's error is (a bug, a garbled
    answer decoded into nonsense), counting the attempts."""

    attempts = 0

    async def read_sysinfo(self, **kwargs: Any) -> Any:
        Garbled.attempts += 1
        raise RuntimeError("nonsense")


async def test_an_unexpected_error_in_the_shape_read_is_a_failure_tried_again_later() -> None:
    clock = ManualClock(1_000.0)
    sink = RecordingSink()
    Garbled.attempts = 0
    policy = ReconnectPolicy(initial_delay=5.0, max_delay=5.0, jitter=0.0)

    async with serving() as one:
        async with polling_with(Garbled, one.port, sink, clock, policy) as poller:
            await until(poller, clock, lambda: poller.is_online("one") is False)
            for _ in range(20):  # the clock stands still: no attempt is due
                await poller.step()
                await asyncio.sleep(0.005)
            assert Garbled.attempts == 1
            ((_, up, reason),) = sink.states
            assert not up and "nonsense" in reason
            clock.advance(5.0)
            await until(poller, clock, lambda: Garbled.attempts == 2)


class BadDynamic(NativeClient):
    """A client whose ``cnc_rddynamic2`` answers something its conversion cannot read."""

    def start_read_dynamic(self, *args: Any, **kwargs: Any) -> StartedCall[Any]:
        async def garbage() -> object:
            return object()

        return StartedCall.running(garbage())


async def test_an_answer_that_cannot_be_converted_gives_its_items_a_bad_status() -> None:
    clock = ManualClock(1_000.0)
    sink = RecordingSink()

    async with serving() as one:
        async with polling_with(BadDynamic, one.port, sink, clock, QUICK) as poller:
            await until(poller, clock, all_online(poller))
            await poller.step()
            got = sink.of("one")
            assert got[(1, "feed", "")].status == ProtocolError.opcua_status
            assert got[(1, "feed", "")].value is None
            assert got[(1, "mode", "")].status == OPCUA_GOOD  # the other reads deliver
            assert poller.is_online("one")
            sink.clear()
            clock.advance(1.0)
            await poller.step()  # the same failure again: nothing new to tell
            assert (1, "feed", "") not in sink.of("one")


async def test_nan_is_the_same_value_as_nan() -> None:
    clock = ManualClock(1_000.0)
    sink = RecordingSink()
    async with serving() as one:
        async with Poller([config("one", one.port)], [sink], clock=clock.now) as poller:
            station = poller._stations["one"]
            key = (1, "feed", "")
            first = poller._changed(station, key, float("nan"), OPCUA_GOOD, 1.0)
            assert first is not None and math.isnan(first.value)  # type: ignore[arg-type]
            poller._sample(station, key, float("nan"), OPCUA_GOOD, 1.0)
            assert poller._changed(station, key, float("nan"), OPCUA_GOOD, 2.0) is None
            assert poller._changed(station, key, 1.0, OPCUA_GOOD, 3.0) is not None


async def test_leaving_the_poller_leaves_no_task_behind() -> None:
    clock = ManualClock(1_000.0)
    sink = RecordingSink()
    async with serving() as one, serving() as two:
        machines = [config("one", one.port), config("two", two.port, "packed")]
        async with Poller(machines, [sink], clock=clock.now, policy=QUICK) as poller:
            await until(poller, clock, all_online(poller))
            await poller.step()
            clock.advance(10.0)
            poller._turn()  # every group started, none of its answers taken
        left = [t for t in asyncio.all_tasks() if t is not asyncio.current_task()]
        assert left == []
        assert all(
            poller.client(m).state.value in ("closed", "disconnected") for m in poller.machines
        )


@pytest.mark.parametrize("peer", [Silent, Garbage])
@pytest.mark.parametrize("protocol", ["native", "packed"])
async def test_a_hung_or_garbled_machine_is_lost_and_the_others_deliver(
    peer: type[Silent], protocol: Literal["native", "packed"], caplog: pytest.LogCaptureFixture
) -> None:
    caplog.set_level(logging.INFO, "focas_net.gateway.poller")
    clock = ManualClock(1_000.0)
    sink = RecordingSink()
    async with serving() as good, peer() as bad:
        machines = [
            config("good", good.port),
            MachineConfig("bad", "127.0.0.1", bad.port, protocol, timeout=0.2),
        ]
        async with Poller(machines, [sink], clock=clock.now, policy=SLOW) as poller:
            await until(poller, clock, lambda: poller.is_online("bad") is False)
            await until(poller, clock, lambda: poller.is_online("good") is True)
            await poller.step()
            assert (1, "mode", "") in sink.of("good")
            assert not sink.of("bad")
            ((_, up, reason),) = [s for s in sink.states if s[0] == "bad"]
            assert f"bad: unavailable ({reason})" in caplog.messages  # (never reached)
            assert not up and reason.split(":")[0] in ("timeout", "protocol", "closed", "reset")
            before = bad.asked
            good.machine.set_overrides(spindle=130)
            clock.advance(1.0)
            await poller.step()  # the bad machine's attempt is not due: not tried again
            assert sink.of("good")[(1, "spindle_override", "")].value == 130
            assert bad.asked == before
            clock.advance(5.0)
            await until(poller, clock, lambda: bad.asked > before)  # tried again, by itself
            assert poller.is_online("good")


async def test_the_wall_clock_set_back_holds_no_poll_back() -> None:
    timer = ManualClock(50.0)
    wall = [1_000_000.0]
    sink = RecordingSink()
    async with serving() as one:
        machines = [config("one", one.port)]
        async with Poller(
            machines, [sink], clock=lambda: wall[0], timer=timer.now, policy=QUICK
        ) as poller:
            await until(poller, timer, all_online(poller))
            await poller.step()
            assert sink.of("one")[(1, "mode", "")].time == 1_000_000.0  # the wall clock's
            wall[0] -= 3600.0  # set back an hour
            one.machine.set_overrides(spindle=130)
            timer.advance(1.0)
            await poller.step()  # due a second later on the timer
            got = sink.of("one")[(1, "spindle_override", "")]
            assert (got.value, got.time) == (130, 1_000_000.0 - 3600.0)


def test_the_default_timer_is_monotonic_beside_the_wall_clock() -> None:
    import time

    assert Poller([], []).timer is time.monotonic
    clock = ManualClock(5.0)
    assert Poller([], [], clock=clock.now).timer == clock.now


@pytest.mark.parametrize("protocol", ["native", "packed"])
async def test_alarms_are_diffed_across_an_outage(protocol: Literal["native", "packed"]) -> None:
    from focas_net.server import FocasServer
    from focas_net.sim import default_machine

    clock = ManualClock(1_000.0)
    sink = RecordingSink()
    machine = default_machine()
    machine.raise_alarm(0, 1, 100, "STAYS")
    machine.raise_alarm(0, 1, 200, "CLEARED MEANWHILE")
    server = FocasServer(machine, host="127.0.0.1", port=0, grace_period=0.5)
    await server.start()
    port = server.listeners[0].address[1]
    try:
        machines = [config("one", port, protocol)]
        async with Poller(machines, [sink], clock=clock.now, policy=QUICK) as poller:
            await until(poller, clock, all_online(poller))
            await poller.step()
            assert {(c.alm_no, c.active) for c in sink.changes} == {(100, True), (200, True)}
            await server.aclose()
            await until(poller, clock, lambda: poller.is_online("one") is False, 1.0)
            machine.clear_alarms()
            machine.raise_alarm(0, 1, 100, "STAYS")
            machine.raise_alarm(0, 1, 300, "RAISED MEANWHILE")
            sink.clear()
            server = FocasServer(machine, host="127.0.0.1", port=port, grace_period=0.5)
            await server.start()
            await until(poller, clock, lambda: poller.is_online("one") is True, 1.0)
            await until(poller, clock, lambda: bool(sink.changes), 1.0)
            assert {(c.alm_no, c.active) for c in sink.changes} == {(200, False), (300, True)}
    finally:
        await server.aclose()


async def test_leaving_while_connecting_to_a_hung_machine_leaves_nothing_behind() -> None:
    clock = ManualClock(1_000.0)
    async with Silent() as hung:
        machines = [MachineConfig("hung", "127.0.0.1", hung.port, "native", timeout=30.0)]
        async with Poller(machines, [RecordingSink()], clock=clock.now, policy=QUICK) as poller:
            await poller.step()  # the connection attempt starts, and hangs
            for _ in range(200):
                if hung.asked:
                    break
                await asyncio.sleep(0.01)
            assert hung.asked  # connected, its first request unanswered
        left = [t for t in asyncio.all_tasks() if t is not asyncio.current_task()]
        assert left == []
        assert poller.client("hung").state.value == "closed"
