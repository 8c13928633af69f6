"""The MQTT publisher against a real broker (Debian's mosquitto on 127.0.0.1): a subscriber
sees the topics, the retained ``$model`` and values, the birth and the will; a broker restart
loses nothing buffered; a full buffer drops the oldest and counts them."""

from __future__ import annotations

import asyncio
import math
import os
import signal
import sys
from collections.abc import Callable

import pytest
from gateway_support import machine_shape
from mosquitto_support import BOUND, Broker, broker, subscriber

from focas_net.errors import OPCUA_GOOD
from focas_net.gateway import (
    AlarmChange,
    MqttSettings,
    Sample,
    Sink,
    item,
)
from focas_net.gateway._keys import ConfigError
from focas_net.gateway._mqtt_messages import (
    ActiveAlarms,
    AlarmEvent,
    Availability,
    DroppedCount,
    ValuePayload,
)
from focas_net.gateway.mqtt import MqttSink

__all__ = ["broker"]  # the fixture, used by name

SHAPE = machine_shape("m1", ("X", "Y", "Z"), ("X", "Z"), mt_type="M")


def settings(broker: Broker, **changes: object) -> MqttSettings:
    return MqttSettings(host=broker.host, port=broker.port, prefix="focas", **changes)  # type: ignore[arg-type]


def sink_for(broker: Broker, **changes: object) -> MqttSink:
    return MqttSink(settings(broker, **changes), gateway_name="gw", reconnect=(0.05, 0.2))


def position(axis: str, value: float, t: float = 0.0, machine: str = "m1") -> Sample:
    return Sample(machine, 1, item("absolute"), axis, value, OPCUA_GOOD, t)


async def until_true(condition: Callable[[], bool]) -> None:
    """Wait until ``condition`` holds (checked every 10 ms, failing after :data:`BOUND` s)."""
    for _ in range(int(BOUND * 100)):
        if condition():
            return
        await asyncio.sleep(0.01)
    raise AssertionError("the condition never held")


def value_of(payload: bytes | None) -> ValuePayload:
    assert payload is not None
    return ValuePayload.decode(payload)


async def test_a_subscriber_sees_birth_model_values_and_alarms(broker: Broker) -> None:
    async with subscriber(broker) as early, sink_for(broker) as sink:
        sink.described(SHAPE)
        sink.online("m1", True, "", 1.0)
        sink.samples([position("X", 10.5), position("Y", -2.25)])
        sink.alarms([AlarmChange("m1", 2, 6, 401, 1, "V-READY OFF", True, 2.0)])
        event = "focas/m1/path2/alarms/event"
        await early.until(lambda s: s.latest(event) is not None)
        await until_true(lambda: sink.pending == 0)
        assert early.latest("focas/$gateway/gw/state") == b"online"
        assert AlarmEvent.decode(early.on(event)[0]) == AlarmEvent(
            6, 401, 1, "V-READY OFF", True, "1970-01-01T00:00:02.000Z"
        )

        # a subscriber coming later gets the retained state, and not the event
        async with subscriber(broker) as late:
            model = "focas/m1/$model"
            await late.until(
                lambda s: all(
                    s.latest(t) is not None
                    for t in (
                        model,
                        "focas/m1/availability",
                        "focas/m1/path1/absolute/Y",
                        "focas/m1/path2/alarms/active",
                    )
                )
            )
            assert late.retained(model) and late.retained("focas/$gateway/gw/state")
            described = late.latest(model)
            assert described is not None and b'"axes":["X","Y","Z"]' in described
            assert value_of(late.latest("focas/m1/path1/absolute/X")).value == 10.5
            assert value_of(late.latest("focas/m1/path1/absolute/Y")).unit == "mm"
            availability = late.latest("focas/m1/availability")
            assert availability is not None
            assert Availability.decode(availability).state == "AVAILABLE"
            active = late.latest("focas/m1/path2/alarms/active")
            assert active is not None
            alarms = ActiveAlarms.decode(active).alarms
            assert alarms is not None and [a.alm_no for a in alarms] == [401]
            assert late.on(event) == []
    # a clean stop says offline itself
    async with subscriber(broker) as after:
        await after.until(lambda s: s.latest("focas/$gateway/gw/state") == b"offline")
    assert sink.errors == 0 and sink.dropped == 0


async def test_a_lost_machine_goes_bad_on_the_broker(broker: Broker) -> None:
    async with subscriber(broker) as seen, sink_for(broker) as sink:
        sink.online("m1", True, "", 0.0)
        sink.samples([position("X", 1.0)])
        sink.online("m1", False, "connection refused", 5.0)
        topic = "focas/m1/path1/absolute/X"
        # the Good value and the Bad one may be coalesced in the buffer: the latest counts
        await seen.until(lambda s: b"BadCommunicationError" in (s.latest(topic) or b""))
        assert value_of(seen.latest(topic)).value is None
        availability = seen.latest("focas/m1/availability")
        assert availability is not None
        assert Availability.decode(availability).reason == "connection refused"


_DYING = """
import asyncio, sys
from focas_net.gateway import MqttSettings
from focas_net.gateway.mqtt import MqttSink

async def main() -> None:
    settings = MqttSettings(host="127.0.0.1", port=int(sys.argv[1]), prefix="focas")
    async with MqttSink(settings, gateway_name="dying") as sink:
        for _ in range(2000):
            if sink.published:
                break
            await asyncio.sleep(0.01)
        print("ready", flush=True)
        await asyncio.sleep(60)

asyncio.run(main())
"""


async def test_the_broker_sends_the_will_when_the_gateway_dies(broker: Broker) -> None:
    state = "focas/$gateway/dying/state"
    async with subscriber(broker) as seen:
        process = await asyncio.create_subprocess_exec(
            sys.executable, "-c", _DYING, str(broker.port), stdout=asyncio.subprocess.PIPE
        )
        try:
            assert process.stdout is not None
            async with asyncio.timeout(BOUND):
                assert await process.stdout.readline() == b"ready\n"
            await seen.until(lambda s: s.latest(state) == b"online")
            os.kill(process.pid, signal.SIGKILL)  # no DISCONNECT: the broker sends the will
            await seen.until(lambda s: s.latest(state) == b"offline")
        finally:
            if process.returncode is None:
                process.kill()
            await process.wait()


async def test_a_broker_restart_loses_nothing_buffered_nor_retained(broker: Broker) -> None:
    async with sink_for(broker) as sink:
        sink.described(SHAPE)
        sink.samples([position("X", 1.0), position("Y", 5.0)])
        await until_true(lambda: sink.published >= 4 and sink.pending == 0)
        await broker.stop()  # and with it every retained message (no persistence)
        await until_true(lambda: not sink.connected)

        axes = [f"A{n}" for n in range(40)]
        sink.samples([position(axis, float(n)) for n, axis in enumerate(axes)])
        sink.samples([position("X", 2.0)])
        sink.alarms([AlarmChange("m1", 1, 6, 401, 1, "V-READY OFF", True, 3.0)])
        assert sink.pending == len(axes) + 3  # X, one event, one active list

        await broker.start()  # the same port; no persistence: it starts empty
        async with subscriber(broker) as seen:
            topics = [f"focas/m1/path1/absolute/{a}" for a in [*axes, "X"]]
            await seen.until(lambda s: all(s.latest(t) is not None for t in topics))
            assert [value_of(seen.latest(t)).value for t in topics] == [
                *map(float, range(len(axes))),
                2.0,
            ]
            active = "focas/m1/path1/alarms/active"
            await seen.until(lambda s: s.latest(active) is not None)
            await seen.until(lambda s: s.latest("focas/$gateway/gw/state") == b"online")
            # the rebirth: what the broker lost with its restart is published again
            await seen.until(lambda s: s.latest("focas/m1/$model") is not None)
            await seen.until(lambda s: s.latest("focas/m1/path1/absolute/Y") is not None)
            assert value_of(seen.latest("focas/m1/path1/absolute/Y")).value == 5.0
        assert sink.dropped == 0 and sink.connections == 2


async def test_a_full_buffer_drops_the_oldest_and_counts_them(broker: Broker) -> None:
    await broker.stop()
    async with sink_for(broker, buffer=5) as sink:
        sink.alarms([AlarmChange("m1", 1, 6, 401, 1, "V-READY OFF", True, 0.0)])  # 2 messages
        sink.described(SHAPE)
        sink.samples([position(f"A{n}", float(n)) for n in range(8)])
        sink.samples([position("A7", 70.0)])  # replaces the waiting A7
        assert (sink.pending, sink.dropped, sink.coalesced) == (5, 6, 1)
        await broker.start()
        async with subscriber(broker) as seen:
            dropped = "focas/$gateway/gw/dropped"
            await seen.until(lambda s: s.latest(dropped) is not None)
            payload = seen.latest(dropped)
            assert payload is not None and DroppedCount.decode(payload).dropped == 6
            # the retained state is published again whole: the dropped $model, alarm list
            # and values too (only the alarm event, not retained, is gone)
            values = [f"focas/m1/path1/absolute/A{n}" for n in range(8)]
            state = ["focas/m1/$model", "focas/m1/path1/alarms/active", *values]
            await seen.until(lambda s: all(s.latest(t) is not None for t in state))
            assert [value_of(seen.latest(t)).value for t in values] == [*map(float, range(7)), 70.0]


async def test_the_sink_never_raises_into_the_poller(broker: Broker) -> None:
    async with sink_for(broker) as sink:
        poller_sees: Sink = sink  # what the poller holds (checked by the type checker)
        poller_sees.samples([object()])  # type: ignore[list-item]
        sink.samples([position("X", math.inf)])  # no JSON form: published as null
        assert sink.errors == 1
        await until_true(lambda: sink.pending == 0)


@pytest.mark.parametrize(
    ("changes", "says"),
    [
        ({"prefix": "$plant"}, "mqtt.prefix: got '$plant'"),
        ({"deadbands": {"feed": -1.0}}, "mqtt.deadbands.feed: got -1.0"),
        ({"qos": 3}, "mqtt.qos: got 3"),
        ({"buffer": 0}, "mqtt.buffer: got 0"),
    ],
)
def test_settings_it_cannot_use_are_a_config_error(changes: dict[str, object], says: str) -> None:
    with pytest.raises(ConfigError) as refused:
        MqttSink(MqttSettings(**changes))  # type: ignore[arg-type]
    assert says in str(refused.value)


async def test_a_sink_without_a_broker_stops_at_once(broker: Broker) -> None:
    await broker.stop()
    sink = sink_for(broker)
    async with sink:
        sink.samples([position("X", 1.0)])
        await asyncio.sleep(0)
    assert not sink.connected and sink.pending == 1
