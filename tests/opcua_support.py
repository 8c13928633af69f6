"""Helpers of the OPC UA sink's tests: a 2-path lathe and a 1-path mill, a sink on 127.0.0.1
(an ephemeral port), a client, and a subscription handler that queues what it receives."""

from __future__ import annotations

import asyncio
from collections.abc import AsyncIterator
from contextlib import AsyncExitStack, asynccontextmanager
from dataclasses import replace
from typing import Any

from asyncua import Client, Node, ua
from gateway_support import machine_shape

from focas_net.errors import OPCUA_GOOD, OpcUaStatus
from focas_net.gateway._opcua_types import CNC_NAMESPACE
from focas_net.gateway.config import OpcUaSettings, OpcUaUser, WriteGates
from focas_net.gateway.model import ITEMS, Sample, Writer
from focas_net.gateway.opcua import OpcUaSink

#: How long a test waits for one notification before it fails (a bound, not a measure).
WAIT = 20.0

LATHE = machine_shape("lathe", series="G1B1")
MILL = machine_shape("mill", ("X", "Y", "Z"), mt_type="M", series="G1B1")

SETTINGS = OpcUaSettings(endpoint="opc.tcp://127.0.0.1:0/focas_net/")
USERS = (OpcUaUser("operator", "s3cret"),)


def sample(
    machine: str,
    path: int,
    name: str,
    value: Any,
    key: str = "",
    status: OpcUaStatus = OPCUA_GOOD,
    time: float = 1_800_000_000.0,
) -> Sample:
    return Sample(machine, path, ITEMS[name], key, value, status, time)


@asynccontextmanager
async def running(
    settings: OpcUaSettings = SETTINGS, writer: Writer | None = None
) -> AsyncIterator[OpcUaSink]:
    async with OpcUaSink(settings, writer) as sink:
        yield sink


def url(sink: OpcUaSink) -> str:
    return f"opc.tcp://127.0.0.1:{sink.port}/focas_net/"


@asynccontextmanager
async def connected(
    sink: OpcUaSink, user: str | None = None, password: str | None = None
) -> AsyncIterator[Client]:
    client = Client(url(sink), timeout=WAIT)
    if user is not None:
        client.set_user(user)
    if password is not None:
        client.set_password(password)
    async with client:
        yield client


async def machine_node(client: Client, name: str) -> Node:
    ns = await client.get_namespace_index("urn:focas-net:gateway")
    return await client.nodes.objects.get_child([f"{ns}:{name}"])


async def cnc_path(client: Client, root: Node, *names: str) -> Node:
    """The node at ``names`` (browse names in the CNC namespace) below ``root``."""
    cnc = await client.get_namespace_index(CNC_NAMESPACE)
    return await root.get_child([f"{cnc}:{n}" for n in names])


class Handler:
    """Queues data changes (node, DataValue) and events."""

    def __init__(self) -> None:
        self.changes: asyncio.Queue[tuple[Node, ua.DataValue]] = asyncio.Queue()
        self.events: asyncio.Queue[Any] = asyncio.Queue()

    def datachange_notification(self, node: Node, val: Any, data: Any) -> None:
        self.changes.put_nowait((node, data.monitored_item.Value))

    def event_notification(self, event: Any) -> None:
        self.events.put_nowait(event)

    async def change(self) -> tuple[Node, ua.DataValue]:
        return await asyncio.wait_for(self.changes.get(), WAIT)

    async def event(self) -> Any:
        return await asyncio.wait_for(self.events.get(), WAIT)

    async def value_of(self, node: Node, wanted: Any) -> ua.DataValue:
        """The first data change of ``node`` whose value is ``wanted`` (at most 50 looked at)."""
        for _ in range(50):
            got, dv = await self.change()
            if got.nodeid == node.nodeid and dv.Value is not None and dv.Value.Value == wanted:
                return dv
        raise AssertionError(f"no data change of {node} to {wanted!r}")


@asynccontextmanager
async def writable(port: int, gates: WriteGates) -> AsyncIterator[tuple[Node, int]]:
    """The gateway in front of the machine served on ``port`` (named ``mill``, FOCAS/2) with
    ``gates`` open and the OPC UA write methods on, and an operator's session: the machine's
    node and the gateway's namespace index, once the machine is online."""
    from poller_support import QUICK
    from support import wait_until

    from focas_net.gateway import Gateway, GatewayConfig, GroupIntervals, MachineConfig
    from focas_net.gateway.run import outputs

    settings = replace(SETTINGS, writes=True, users=USERS, anonymous=False)
    mill = MachineConfig(
        "mill", "127.0.0.1", port, timeout=2.0, groups=GroupIntervals(1.0, 10.0, 1.0),
        writes=gates,
    )  # fmt: skip
    conf = GatewayConfig((mill,), opcua=settings)
    gateway = Gateway(conf, policy=QUICK)
    async with AsyncExitStack() as stack:
        (output,) = outputs(conf, gateway.writer)
        sink = await stack.enter_async_context(output)
        assert isinstance(sink, OpcUaSink)
        gateway.add_sink(sink)
        await stack.enter_async_context(gateway)
        await wait_until(lambda: gateway.poller.is_online("mill") is True)
        await sink.flush()
        client = await stack.enter_async_context(connected(sink, "operator", "s3cret"))
        root = await machine_node(client, "mill")
        yield root, await client.get_namespace_index("urn:focas-net:gateway")
