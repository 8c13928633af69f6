"""End to end: a simulated 2-path lathe served on 127.0.0.1, read by the gateway's poller,
published by the MQTT sink to mosquitto, seen by a subscriber: the ``$model`` of both paths,
every axis's values, an alarm, the machine lost (UNAVAILABLE, every value Bad) and back."""

from __future__ import annotations

import json
from pathlib import Path

from mosquitto_support import Broker, Seen, broker, subscriber
from poller_support import QUICK, until

from focas_net.gateway import GroupIntervals, MachineConfig, MqttSettings
from focas_net.gateway._mqtt_messages import AlarmEvent, Availability, ValuePayload
from focas_net.gateway.mqtt import MqttSink
from focas_net.gateway.poller import Poller
from focas_net.server import FocasServer
from focas_net.sim import load_machine
from focas_net.sim.nc import ManualClock

__all__ = ["broker"]  # the fixture, used by name

LATHE = Path(__file__).resolve().parent.parent / "examples" / "lathe_2path.toml"


def status(seen: Seen, topic: str) -> str | None:
    payload = seen.latest(topic)
    return None if payload is None else ValuePayload.decode(payload).status


def state(seen: Seen, topic: str) -> str | None:
    payload = seen.latest(topic)
    return None if payload is None else Availability.decode(payload).state


async def test_a_two_path_lathe_through_the_poller_to_a_subscriber(broker: Broker) -> None:
    clock = ManualClock(1_000.0)
    machine = load_machine(LATHE, sim_clock=ManualClock())
    server = FocasServer(machine, host="127.0.0.1", port=0, grace_period=0.5)
    await server.start()
    port = server.listeners[0].address[1]
    lathe = MachineConfig(
        "lathe", "127.0.0.1", port, timeout=2.0, groups=GroupIntervals(1.0, 10.0, 1.0)
    )
    try:
        async with (
            subscriber(broker) as seen,
            MqttSink(MqttSettings(port=broker.port), gateway_name="gw") as sink,
            Poller([lathe], [sink], clock=clock.now, policy=QUICK) as poller,
        ):
            await until(poller, clock, lambda: poller.is_online("lathe") is True, 0.0)
            await poller.step()  # the first reads of every group
            model_topic = "focas/lathe/$model"
            await seen.until(lambda s: s.latest(model_topic) is not None)
            model = json.loads(seen.latest(model_topic) or b"")
            assert [p["number"] for p in model["paths"]] == [1, 2]
            values = [
                f"{p['topic']}/{name}/{axis}"
                for p in model["paths"]
                for axis in p["axes"]
                for name in ("absolute", "machine", "servo_load")
            ] + [f"{p['topic']}/{name}" for p in model["paths"] for name in ("mode", "feed")]
            assert len(values) == 16
            await seen.until(lambda s: all(status(s, t) == "Good" for t in values))
            await seen.until(lambda s: state(s, "focas/lathe/availability") == "AVAILABLE")

            machine.raise_alarm(1, 4, 510, "OVER TRAVEL +Z", path=2)
            clock.advance(1.0)
            await poller.step()
            event = "focas/lathe/path2/alarms/event"
            await seen.until(lambda s: s.latest(event) is not None)
            raised = AlarmEvent.decode(seen.latest(event) or b"")
            assert (raised.alm_type, raised.alm_no, raised.active) == (4, 510, True)

            await server.aclose()
            await until(poller, clock, lambda: poller.is_online("lathe") is False, 1.0)
            await seen.until(lambda s: state(s, "focas/lathe/availability") == "UNAVAILABLE")
            await seen.until(lambda s: all(status(s, t) == "BadCommunicationError" for t in values))

            server = FocasServer(machine, host="127.0.0.1", port=port, grace_period=0.5)
            await server.start()
            await until(poller, clock, lambda: poller.is_online("lathe") is True, 1.0)
            clock.advance(10.0)
            await poller.step()
            await seen.until(lambda s: state(s, "focas/lathe/availability") == "AVAILABLE")
            await seen.until(lambda s: all(status(s, t) == "Good" for t in values))
            assert sink.errors == 0 and sink.dropped == 0
    finally:
        await server.aclose()
