"""The gateway end to end: simulated machines served on 127.0.0.1 (a 2-path lathe among them),
polled by the gateway's poller into its OPC UA server, seen by an asyncua client: values and
their changes, alarm events raised and cleared, a stopped machine Bad everywhere and Good again
once it is back; write methods through the configuration's write gates."""

from __future__ import annotations

from contextlib import AsyncExitStack
from decimal import Decimal
from pathlib import Path
from typing import Any

import pytest
from asyncua import Node, ua
from opcua_support import SETTINGS, Handler, cnc_path, connected, machine_node, writable
from poller_support import QUICK, until
from support import serving

from focas_net.gateway import GroupIntervals, MachineConfig, WriteGates
from focas_net.gateway._opcua_types import CNC_NAMESPACE, CncId
from focas_net.gateway.opcua import OpcUaSink
from focas_net.gateway.poller import Poller
from focas_net.protocol.alarms import alarm_code
from focas_net.server import FocasServer
from focas_net.sim import default_machine, load_machine
from focas_net.sim.nc import ManualClock

LATHE = Path(__file__).resolve().parent.parent / "examples" / "lathe_2path.toml"
LOST = ua.StatusCode(ua.StatusCodes.BadCommunicationError)


def config(name: str, port: int) -> MachineConfig:
    return MachineConfig(
        name, "127.0.0.1", port, "native", timeout=2.0, groups=GroupIntervals(1.0, 10.0, 1.0)
    )


async def status_of(node: Node) -> Any:
    return (await node.read_data_value(raise_on_bad_status=False)).StatusCode


async def test_a_simulated_fleet_through_the_poller_to_an_opc_ua_client() -> None:
    clock = ManualClock(1_000.0)
    lathe = load_machine(LATHE, sim_clock=ManualClock())
    async with AsyncExitStack() as stack:
        mill = await stack.enter_async_context(serving(default_machine()))
        server = FocasServer(lathe, host="127.0.0.1", port=0, grace_period=0.5)
        await server.start()
        stack.push_async_callback(lambda: server.aclose())
        port = server.listeners[0].address[1]
        sink = await stack.enter_async_context(OpcUaSink(SETTINGS))
        poller = await stack.enter_async_context(
            Poller(
                [config("lathe", port), config("mill", mill.port)],
                [sink],
                clock=clock.now,
                policy=QUICK,
            )
        )
        await until(poller, clock, lambda: all(poller.is_online(m) for m in poller.machines))
        await poller.step()
        await sink.flush()
        client = await stack.enter_async_context(connected(sink))
        cnc = await client.get_namespace_index(CNC_NAMESPACE)
        root = await machine_node(client, "lathe")
        channels = await cnc_path(client, root, "CncChannelList")
        assert [(await c.read_browse_name()).Name for c in await channels.get_children()] == [
            "Channel_1",
            "Channel_2",
        ]
        feed = await cnc_path(client, root, "CncChannelList", "Channel_2", "ActFeedrate")
        x2 = await cnc_path(client, root, "CncAxisList", "X2", "PosIndirect", "ActPos")
        pos = await cnc_path(client, root, "CncChannelList", "Channel_2", "PosTcpWcsZ")
        mode = await cnc_path(client, root, "CncChannelList", "Channel_1", "ActOperationMode")
        for node in (feed, x2, pos, mode):
            assert (await status_of(node)).is_good(), node
        status = await cnc_path(client, root, "CncChannelList", "Channel_1", "ActStatus")
        assert await status.read_value() == 2  # Reset: the lathe is not running
        ns = await client.get_namespace_index("urn:focas-net:gateway")
        parts = await root.get_child([f"{ns}:Focas", f"{ns}:Path_2", f"{ns}:parts"])
        parts_status = await status_of(parts)  # (a slow item: Good or the EW of its read)
        assert parts_status != LOST

        handler = Handler()
        sub = await client.create_subscription(10, handler)
        await sub.subscribe_data_change(feed)
        await handler.change()  # the value it has
        await sub.subscribe_events(
            client.nodes.server, client.get_node(ua.NodeId(CncId.ALARM_TYPE, cnc))
        )
        lathe.set_motion(path=2, feed=321)
        clock.advance(1.0)
        await poller.step()
        await handler.value_of(feed, 321.0)

        lathe.raise_alarm(1, 4, 510, "OVER TRAVEL +Z", path=2)
        clock.advance(1.0)
        await poller.step()
        raised = await handler.event()
        assert raised.ConditionName == f"{alarm_code(4, 510)}/1"
        assert getattr(raised, "ActiveState/Id") is True and raised.Retain is True
        assert raised.SourceName == "lathe/Channel_2"
        lathe.clear_alarms(path=2)
        clock.advance(1.0)
        await poller.step()
        cleared = await handler.event()
        assert cleared.NodeId == raised.NodeId
        assert getattr(cleared, "ActiveState/Id") is False and cleared.Retain is False

        await server.aclose()
        await until(poller, clock, lambda: poller.is_online("lathe") is False, 1.0)
        await sink.flush()
        for node in (feed, x2, pos, mode, parts):
            assert await status_of(node) == LOST, node
        mill_feed = await cnc_path(
            client, await machine_node(client, "mill"), "CncChannelList", "Channel_1", "ActFeedrate"
        )
        assert (await status_of(mill_feed)).is_good()

        server = FocasServer(lathe, host="127.0.0.1", port=port, grace_period=0.5)
        await server.start()
        await until(poller, clock, lambda: poller.is_online("lathe") is True, 1.0)
        clock.advance(10.0)
        await poller.step()
        await sink.flush()
        for node in (feed, x2, pos, mode):
            assert (await status_of(node)).is_good(), node
        assert await status_of(parts) == parts_status
        await sub.delete()


async def test_the_write_methods_go_through_the_gateways_write_gates() -> None:
    machine = default_machine()
    async with serving(machine) as served:
        gates = WriteGates(macros=((500, 599),), pmc=(("R", 100, 199),))
        async with writable(served.port, gates) as (root, ns):
            i32 = ua.VariantType.Int32
            await root.call_method(
                f"{ns}:WriteMacro", ua.Variant(510, i32), 1.25, ua.Variant(1, i32)
            )
            assert machine.read_macro(510) == Decimal("1.25")
            await root.call_method(f"{ns}:WritePmc", "R", ua.Variant(150, i32), ua.Variant(7, i32))
            assert machine.read_pmc("R", 150, 1) == b"\x07"
            with pytest.raises(ua.uaerrors.BadUserAccessDenied):  # outside the gates
                await root.call_method(
                    f"{ns}:WriteMacro", ua.Variant(600, i32), 1.0, ua.Variant(1, i32)
                )
            with pytest.raises(ua.uaerrors.BadUserAccessDenied):  # no parameter is open
                await root.call_method(
                    f"{ns}:WriteParameter",
                    ua.Variant(6711, i32),
                    ua.Variant(0, i32),
                    ua.Variant(1, i32),
                )
            with pytest.raises(ua.uaerrors.BadOutOfRange):  # a path the mill has not: EW_PATH
                await root.call_method(
                    f"{ns}:WriteMacro", ua.Variant(590, i32), 1.0, ua.Variant(2, i32)
                )
            with pytest.raises(ua.uaerrors.BadInvalidArgument):  # the writer's own check
                await root.call_method(
                    f"{ns}:WritePmc", "R", ua.Variant(150, i32), ua.Variant(256, i32)
                )
            assert machine.read_macro(600) is None
            assert machine.read_pmc("R", 150, 1) == b"\x07"
