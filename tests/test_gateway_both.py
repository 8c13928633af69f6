"""The gateway as a plant runs it: ``focas-net gateway CONFIG.toml`` in a process of its own, in
front of running simulated machines (a 2-path lathe over FOCAS/2, a mill over the packed
protocol), publishing to a mosquitto broker and serving OPC UA at once. An asyncua client and an
MQTT subscriber both see the values; a machine whose server stops shows as lost on both sides
(every OPC UA value BadCommunicationError, the MQTT availability UNAVAILABLE and every value
Bad) and recovers on both when it is served again on its port."""

from __future__ import annotations

import asyncio
import json
from collections.abc import Awaitable, Callable
from contextlib import AsyncExitStack
from pathlib import Path

import pytest
from asyncua import Client, Node, ua
from cli_support import gateway_process
from mosquitto_support import Broker, Seen, broker, subscriber
from support import free_port

from focas_net.gateway._mqtt_messages import Availability, ValuePayload
from focas_net.gateway._opcua_types import CNC_NAMESPACE
from focas_net.server import FocasServer
from focas_net.sim import default_machine, load_machine

__all__ = ["broker"]  # the fixture, used by name

LATHE = Path(__file__).resolve().parent.parent / "examples" / "lathe_2path.toml"
#: A failure bound for each wait: never a figure a test asserts.
WAIT = 30.0
LOST = ua.StatusCode(ua.StatusCodes.BadCommunicationError)


def plant(lathe: int, mill: int, broker: Broker, opcua: int) -> str:
    return f"""
[groups]
fast = 0.2
slow = 1
alarms = 0.2

[[machine]]
name = "lathe"
host = "127.0.0.1"
port = {lathe}
protocol = "native"
timeout = 1.0

[[machine]]
name = "mill"
host = "127.0.0.1"
port = {mill}
protocol = "packed"
timeout = 1.0

[mqtt]
host = "{broker.host}"
port = {broker.port}
prefix = "focas"

[opcua]
endpoint = "opc.tcp://127.0.0.1:{opcua}/focas_net/"
"""


async def opcua_client(port: int) -> Client:
    """A client connected to the gateway's OPC UA server (which starts after the ready line
    may be printed: the connection is tried again, a bounded number of times)."""
    for _ in range(200):
        client = Client(f"opc.tcp://127.0.0.1:{port}/focas_net/", timeout=WAIT)
        try:
            await client.connect()
        except (OSError, TimeoutError, ua.UaError):
            await asyncio.sleep(0.05)
            continue
        return client
    pytest.fail("the gateway's OPC UA server never accepted a connection")


async def node_at(client: Client, machine: str, *names: str) -> Node:
    ns = await client.get_namespace_index("urn:focas-net:gateway")
    cnc = await client.get_namespace_index(CNC_NAMESPACE)
    root = await client.nodes.objects.get_child([f"{ns}:{machine}"])
    return await root.get_child([f"{cnc}:{n}" for n in names])


async def eventually(check: Callable[[], Awaitable[bool]], what: str) -> None:
    """Poll ``check`` until it holds; fail after :data:`WAIT` seconds naming ``what``."""
    async with asyncio.timeout(WAIT):
        for _ in range(100_000):
            if await check():
                return
            await asyncio.sleep(0.05)
    pytest.fail(f"never: {what}")


async def found(client: Client, machine: str, *names: str) -> Node:
    """The node at ``names`` of ``machine``, once the gateway has made it."""
    nodes: list[Node] = []

    async def made() -> bool:
        try:
            nodes.append(await node_at(client, machine, *names))
        except ua.UaError:
            return False
        return True

    await eventually(made, f"{machine}/{'/'.join(names)} in the address space")
    return nodes[-1]


async def status_of(node: Node) -> ua.StatusCode:
    value = await node.read_data_value(raise_on_bad_status=False)
    assert value.StatusCode is not None
    return value.StatusCode


def mqtt_state(seen: Seen, machine: str) -> str | None:
    payload = seen.latest(f"focas/{machine}/availability")
    return None if payload is None else Availability.decode(payload).state


def mqtt_status(seen: Seen, topic: str) -> str | None:
    payload = seen.latest(topic)
    return None if payload is None else ValuePayload.decode(payload).status


async def test_a_running_plant_to_opc_ua_and_mqtt_at_once_lost_and_back(
    broker: Broker, tmp_path: Path
) -> None:
    lathe = load_machine(LATHE)
    mill = default_machine()
    async with AsyncExitStack() as stack:
        lathe_server = FocasServer(lathe, host="127.0.0.1", port=0, grace_period=0.5)
        await lathe_server.start()
        stack.push_async_callback(lambda: lathe_server.aclose())
        lathe_port = lathe_server.listeners[0].address[1]
        mill_server = FocasServer(mill, host="127.0.0.1", port=0, grace_period=0.5)
        await mill_server.start()
        stack.push_async_callback(mill_server.aclose)
        mill_port = mill_server.listeners[0].address[1]
        opcua_port = free_port()
        config = tmp_path / "plant.toml"
        config.write_text(plant(lathe_port, mill_port, broker, opcua_port))
        lathe.set_motion(path=2, feed=250)

        seen = await stack.enter_async_context(subscriber(broker))
        plant_gateway = await stack.enter_async_context(gateway_process(str(config)))
        assert plant_gateway.ready.startswith("focas-net: gateway polling 2 machines")
        client = await opcua_client(opcua_port)
        stack.push_async_callback(client.disconnect)

        # Both sides see both machines, the lathe's second path included.
        feed2 = await found(client, "lathe", "CncChannelList", "Channel_2", "ActFeedrate")
        x2 = await found(client, "lathe", "CncAxisList", "X2", "PosIndirect", "ActPos")
        mill_feed = await found(client, "mill", "CncChannelList", "Channel_1", "ActFeedrate")

        async def opcua_feed_is_250() -> bool:
            value = await feed2.read_data_value(raise_on_bad_status=False)
            return value.Value is not None and value.Value.Value == 250.0

        await eventually(opcua_feed_is_250, "the lathe's path 2 feed of 250 over OPC UA")
        assert (await status_of(x2)).is_good()

        async def mill_feed_is_good() -> bool:  # (the mill's polls are staggered after the lathe's)
            good: bool = (await status_of(mill_feed)).is_good()
            return good

        await eventually(mill_feed_is_good, "the mill's feed Good over OPC UA")
        feed_topic = "focas/lathe/path2/feed"
        await seen.until(
            lambda s: (
                s.latest(feed_topic) is not None
                and ValuePayload.decode(s.latest(feed_topic) or b"").value == 250.0
            )
        )
        async with subscriber(broker) as late:  # retained: a newcomer gets it at once
            await late.until(lambda s: s.retained(feed_topic))
        model = json.loads(seen.latest("focas/lathe/$model") or b"{}")
        assert len(model["paths"]) == 2
        await seen.until(lambda s: mqtt_state(s, "mill") == "AVAILABLE")

        # The lathe's server stops: lost on both sides, the mill unaffected.
        await lathe_server.aclose()

        async def opcua_lost() -> bool:
            return bool(await status_of(feed2) == LOST and await status_of(x2) == LOST)

        await eventually(opcua_lost, "the lathe's values BadCommunicationError over OPC UA")
        await seen.until(lambda s: mqtt_state(s, "lathe") == "UNAVAILABLE")
        await seen.until(lambda s: mqtt_status(s, feed_topic) == "BadCommunicationError")
        assert (await status_of(mill_feed)).is_good()
        assert mqtt_state(seen, "mill") == "AVAILABLE"

        # Served again on its port: back on both sides, by itself.
        lathe.set_motion(path=2, feed=300)
        lathe_server = FocasServer(lathe, host="127.0.0.1", port=lathe_port, grace_period=0.5)
        await lathe_server.start()

        async def opcua_back() -> bool:
            value = await feed2.read_data_value(raise_on_bad_status=False)
            good = value.StatusCode is not None and value.StatusCode.is_good()
            return good and value.Value is not None and value.Value.Value == 300.0

        await eventually(opcua_back, "the lathe's feed Good again over OPC UA")
        await seen.until(lambda s: mqtt_state(s, "lathe") == "AVAILABLE")
        await seen.until(lambda s: mqtt_status(s, feed_topic) == "Good")
        assert ValuePayload.decode(seen.latest(feed_topic) or b"").value == 300.0
