"""The gateway's OPC UA server seen by an asyncua client: the OPC 40502 tree of a 2-path lathe,
values with their units and source timestamps, data changes, EW codes as status codes, a lost
machine's variables all Bad and Good again with fresh samples, alarm conditions raised and
cleared."""

from __future__ import annotations

import math
from dataclasses import replace
from datetime import UTC, datetime

import pytest
from asyncua import Client, Node, ua
from opcua_support import LATHE, MILL, Handler, cnc_path, connected, machine_node, running, sample

from focas_net.errors import EW, ew_info
from focas_net.gateway._opcua_types import CNC_NAMESPACE, CncId, unit_id
from focas_net.gateway.model import ITEMS, MILLIMETRE, MM_PER_MINUTE, AlarmChange, Scope

T0 = 1_800_000_000.0


async def browse_names(node: Node) -> list[str]:
    return [(await child.read_browse_name()).Name for child in await node.get_children()]


async def test_a_machine_is_a_cnc_interface_with_a_channel_per_path() -> None:
    async with running() as sink:
        sink.described(LATHE)
        sink.described(MILL)
        await sink.flush()
        async with connected(sink) as client:
            cnc = await client.get_namespace_index(CNC_NAMESPACE)
            root = await machine_node(client, "lathe")
            assert await root.read_type_definition() == ua.NodeId(CncId.INTERFACE_TYPE, cnc)
            assert await (await cnc_path(client, root, "VendorName")).read_value() == "FANUC"
            channels = await cnc_path(client, root, "CncChannelList")
            assert await browse_names(channels) == ["Channel_1", "Channel_2"]
            ch2 = await cnc_path(client, root, "CncChannelList", "Channel_2")
            assert await ch2.read_type_definition() == ua.NodeId(CncId.CHANNEL_TYPE, cnc)
            assert await (await cnc_path(client, ch2, "Id")).read_value() == 2
            # both paths have X and Z: the list names them as FANUC's screens do
            axes = await cnc_path(client, root, "CncAxisList")
            assert await browse_names(axes) == ["X1", "Z1", "X2", "Z2"]
            organized = await ch2.get_referenced_nodes(refs=ua.ObjectIds.Organizes)
            assert sorted([(await n.read_browse_name()).Name for n in organized]) == [
                "S2",
                "X2",
                "Z2",
            ]
            x2 = await cnc_path(client, root, "CncAxisList", "X2")
            assert await x2.read_type_definition() == ua.NodeId(CncId.AXIS_TYPE, cnc)
            assert await (await cnc_path(client, x2, "ActChannel")).read_value() == ch2.nodeid
            for name in ("ActPos", "RemDist"):
                await cnc_path(client, x2, "PosIndirect", name)
            s1 = await cnc_path(client, root, "CncSpindleList", "S1")
            assert await s1.read_type_definition() == ua.NodeId(CncId.SPINDLE_TYPE, cnc)
            assert await browse_names(s1) == ["ActChannel", "ActLoad", "ActSpeed", "ActOverride"]
            mill = await machine_node(client, "mill")
            assert await browse_names(await cnc_path(client, mill, "CncAxisList")) == [
                "X",
                "Y",
                "Z",
            ]


async def test_every_item_is_in_the_focas_folder_of_its_path() -> None:
    async with running() as sink:
        sink.described(LATHE)
        await sink.flush()
        async with connected(sink) as client:
            ns = await client.get_namespace_index("urn:focas-net:gateway")
            root = await machine_node(client, "lathe")
            for path in LATHE.paths:
                folder = await root.get_child([f"{ns}:Focas", f"{ns}:Path_{path.number}"])
                names = await browse_names(folder)
                for it in ITEMS.values():
                    if it.scope is Scope.PATH:
                        assert it.name in names
                    elif it.scope is Scope.AXIS:
                        for axis in path.axes:
                            await folder.get_child([f"{ns}:Axis_{axis}", f"{ns}:{it.name}"])
                    elif it.scope is Scope.SPINDLE:
                        for s in path.spindles:
                            await folder.get_child([f"{ns}:Spindle_{s}", f"{ns}:{it.name}"])


async def test_values_come_with_units_timestamps_and_data_changes() -> None:
    async with running() as sink:
        sink.described(LATHE)
        await sink.flush()
        async with connected(sink) as client:
            root = await machine_node(client, "lathe")
            feed = await cnc_path(client, root, "CncChannelList", "Channel_2", "ActFeedrate")
            eu = await feed.get_child(["0:EngineeringUnits"])
            info = await eu.read_value()
            assert info.UnitId == unit_id(MM_PER_MINUTE) == 0x483831
            assert info.NamespaceUri == "http://www.opcfoundation.org/UA/units/un/cefact"
            assert await feed.read_type_definition() == ua.NodeId(ua.ObjectIds.AnalogItemType)
            x2 = await cnc_path(client, root, "CncAxisList", "X2", "PosIndirect", "ActPos")
            assert (await (await x2.get_child(["0:EngineeringUnits"])).read_value()).UnitId == (
                unit_id(MILLIMETRE)
            )
            handler = Handler()
            sub = await client.create_subscription(10, handler)
            await sub.subscribe_data_change([feed, x2])
            for i, value in enumerate((100.0, 250.0, 250.5)):
                sink.samples(
                    [
                        sample("lathe", 2, "feed", value, time=T0 + i),
                        sample("lathe", 2, "machine", -value, key="X", time=T0 + i),
                    ]
                )
                dv = await handler.value_of(feed, value)
                assert dv.StatusCode is not None and dv.StatusCode.is_good()
                assert dv.SourceTimestamp == datetime.fromtimestamp(T0 + i, UTC)
                await handler.value_of(x2, -value)
            await sub.delete()
            # the position's structure, made of its parts (FOCAS reads no command position)
            pos = await cnc_path(client, root, "CncAxisList", "X2", "PosIndirect")
            lost = await pos.read_data_value(raise_on_bad_status=False)
            assert lost.StatusCode == ua.StatusCode(ua.StatusCodes.BadWaitingForInitialData)
            sink.samples([sample("lathe", 2, "distance", 0.5, key="X", time=T0 + 9)])
            await sink.flush()
            await client.load_data_type_definitions()
            value = await pos.read_value()
            assert (value.ActPos, value.RemDist) == (-250.5, 0.5)
            assert math.isnan(value.CmdPos)


async def test_focas_states_become_opc_40502_enumerations() -> None:
    async with running() as sink:
        sink.described(LATHE)
        sink.samples(
            [
                sample("lathe", 1, "mode", "MEM"),
                sample("lathe", 1, "run", "HOLD"),
                sample("lathe", 1, "program", 1234),
                sample("lathe", 1, "tool", 5),
                sample("lathe", 2, "mode", "MDI"),
                sample("lathe", 2, "run", "STRT"),
            ]
        )
        await sink.flush()
        async with connected(sink) as client:
            root = await machine_node(client, "lathe")

            async def read(path: int, name: str) -> object:
                node = await cnc_path(client, root, "CncChannelList", f"Channel_{path}", name)
                return await node.read_value()

            assert await read(1, "ActOperationMode") == 2  # Automatic
            assert await read(1, "ActProgramStatus") == 3  # Interrupted
            assert await read(1, "ActStatus") == 1  # Interrupted
            assert await read(1, "ActProgramName") == "O1234"
            assert await read(1, "ToolId") == 5
            assert await read(2, "ActOperationMode") == 1  # MDA
            assert await read(2, "ActProgramStatus") == 1  # Running
            assert await read(2, "ActStatus") == 0  # Active
            sink.samples([sample("lathe", 1, "run", "****"), sample("lathe", 1, "mode", "EDIT")])
            await sink.flush()
            assert await read(1, "ActProgramStatus") == 0  # Stopped
            assert await read(1, "ActStatus") == 2  # Reset
            assert await read(1, "ActOperationMode") == 0  # Manual
            cnc = await client.get_namespace_index(CNC_NAMESPACE)
            strings = await client.get_node(ua.NodeId(CncId.OPERATION_MODE, cnc)).get_child(
                ["0:EnumStrings"]
            )
            assert [t.Text for t in await strings.read_value()] == ["Manual", "MDA", "Automatic"]


async def test_an_ew_code_is_the_variables_status() -> None:
    status = ew_info(EW.NUMBER).opcua
    async with running() as sink:
        sink.described(LATHE)
        sink.samples([sample("lathe", 1, "servo_load", None, key="Z", status=status)])
        await sink.flush()
        async with connected(sink) as client:
            root = await machine_node(client, "lathe")
            load = await cnc_path(client, root, "CncAxisList", "Z1", "ActLoad")
            dv = await load.read_data_value(raise_on_bad_status=False)
            assert dv.StatusCode == ua.StatusCode(ua.StatusCodes.BadOutOfRange)
            assert status.value == ua.StatusCodes.BadOutOfRange


async def variables(client: Client, node: Node) -> list[Node]:
    """Every variable below ``node`` a sample writes: components, not properties, not the
    constant ``ActChannel``."""
    cnc = await client.get_namespace_index(CNC_NAMESPACE)
    found: list[Node] = []
    todo = [node]
    for _ in range(10_000):
        if not todo:
            break
        here = todo.pop()
        for child in await here.get_children(refs=ua.ObjectIds.HierarchicalReferences):
            if await child.read_node_class() == ua.NodeClass.Object:
                todo.append(child)
                continue
            if (await child.read_type_definition()) == ua.NodeId(ua.ObjectIds.PropertyType):
                continue
            if (await child.read_browse_name()).Name == "ActChannel":
                continue
            if await child.read_type_definition() == ua.NodeId(CncId.POSITION_VARIABLE_TYPE, cnc):
                todo.append(child)  # its parts
            found.append(child)
    return found


async def test_a_lost_machine_is_bad_everywhere_and_good_again_with_fresh_samples() -> None:
    async with running() as sink:
        sink.described(LATHE)
        sink.described(MILL)
        sink.samples([sample("lathe", 1, "feed", 10.0), sample("mill", 1, "feed", 20.0)])
        await sink.flush()
        async with connected(sink) as client:
            root = await machine_node(client, "lathe")
            nodes = await variables(client, root)
            assert len(nodes) > 2 * len(ITEMS)
            feed = await cnc_path(client, root, "CncChannelList", "Channel_1", "ActFeedrate")
            handler = Handler()
            sub = await client.create_subscription(10, handler)
            await sub.subscribe_data_change(feed)
            await handler.value_of(feed, 10.0)
            sink.online("lathe", False, "connection refused", T0 + 5)
            await sink.flush()
            lost = ua.StatusCode(ua.StatusCodes.BadCommunicationError)
            for node in nodes:
                dv = await node.read_data_value(raise_on_bad_status=False)
                assert dv.StatusCode == lost, node
            _, dv = await handler.change()
            assert dv.StatusCode == lost
            # the other machine is untouched
            mill_feed = await cnc_path(
                client,
                await machine_node(client, "mill"),
                "CncChannelList",
                "Channel_1",
                "ActFeedrate",
            )
            assert await mill_feed.read_value() == 20.0
            sink.online("lathe", True, "", T0 + 6)
            sink.samples([sample("lathe", 1, "feed", 11.0, time=T0 + 6)])
            dv = await handler.value_of(feed, 11.0)
            assert dv.StatusCode is not None and dv.StatusCode.is_good()
            await sub.delete()


def alarm(active: bool, time: float, axis: int = 0) -> AlarmChange:
    return AlarmChange("lathe", 2, 3, 10, axis, "IMPROPER G-CODE", active, time)


async def test_alarms_are_conditions_raised_and_cleared() -> None:
    async with running() as sink:
        sink.described(LATHE)
        await sink.flush()
        async with connected(sink) as client:
            cnc = await client.get_namespace_index(CNC_NAMESPACE)
            alarm_type = client.get_node(ua.NodeId(CncId.ALARM_TYPE, cnc))
            assert (await alarm_type.read_browse_name()).Name == "CncAlarmType"
            parent = (
                await alarm_type.get_referenced_nodes(
                    refs=ua.ObjectIds.HasSubtype, direction=ua.BrowseDirection.Inverse
                )
            )[0]
            assert parent.nodeid == ua.NodeId(ua.ObjectIds.DiscreteAlarmType)
            handler = Handler()
            sub = await client.create_subscription(10, handler)
            await sub.subscribe_events(client.nodes.server, alarm_type)
            sink.alarms([alarm(True, T0)])
            raised = await handler.event()
            assert raised.ConditionName == "PS0010"
            assert raised.AlarmIdentifier == "PS0010"
            assert raised.Message.Text == "PS0010 IMPROPER G-CODE"
            assert getattr(raised, "ActiveState/Id") is True
            assert getattr(raised, "AckedState/Id") is False
            assert raised.Retain is True
            assert raised.EventType == alarm_type.nodeid
            assert raised.Time == datetime.fromtimestamp(T0, UTC)
            root = await machine_node(client, "lathe")
            assert raised.SourceNode == root.nodeid
            sink.alarms([alarm(True, T0)])  # still in the list: nothing new
            condition = client.get_node(raised.NodeId)
            acknowledge = ua.NodeId(ua.ObjectIds.AcknowledgeableConditionType_Acknowledge)
            seen = ua.LocalizedText("seen at the machine")
            with pytest.raises(ua.uaerrors.BadEventIdUnknown):
                await condition.call_method(
                    acknowledge, ua.Variant(b"old", ua.VariantType.ByteString), seen
                )
            await condition.call_method(
                acknowledge, ua.Variant(raised.EventId, ua.VariantType.ByteString), seen
            )
            acked = await handler.event()
            assert getattr(acked, "AckedState/Id") is True
            assert getattr(acked, "ActiveState/Id") is True and acked.Retain is True
            with pytest.raises(ua.uaerrors.BadConditionBranchAlreadyAcked):
                await condition.call_method(
                    acknowledge, ua.Variant(acked.EventId, ua.VariantType.ByteString), seen
                )
            sink.alarms([alarm(False, T0 + 3)])
            cleared = await handler.event()
            assert cleared.ConditionName == "PS0010"
            assert getattr(cleared, "ActiveState/Id") is False
            assert cleared.Retain is False
            assert cleared.NodeId == raised.NodeId
            # the condition's object stays, inactive, with nothing left to acknowledge
            assert (await condition.read_browse_name()).Name == "PS0010"
            with pytest.raises(ua.uaerrors.BadEventIdUnknown):
                await condition.call_method(
                    acknowledge, ua.Variant(cleared.EventId, ua.VariantType.ByteString), seen
                )
            assert handler.events.empty()
            sink.alarms([alarm(True, T0 + 5)])  # raised again: the same object, unacknowledged
            again = await handler.event()
            assert again.NodeId == raised.NodeId
            assert getattr(again, "ActiveState/Id") is True
            assert getattr(again, "AckedState/Id") is False and again.Retain is True
            await condition.call_method(
                acknowledge, ua.Variant(again.EventId, ua.VariantType.ByteString), seen
            )
            assert getattr((await handler.event()), "AckedState/Id") is True
            assert handler.events.empty()
            await sub.delete()


async def test_a_machines_object_notifies_its_own_alarms() -> None:
    async with running() as sink:
        sink.described(LATHE)
        sink.described(MILL)
        await sink.flush()
        async with connected(sink) as client:
            handler = Handler()
            sub = await client.create_subscription(10, handler)
            cnc = await client.get_namespace_index(CNC_NAMESPACE)
            alarm_type = client.get_node(ua.NodeId(CncId.ALARM_TYPE, cnc))
            await sub.subscribe_events(await machine_node(client, "lathe"), alarm_type)
            sink.alarms([AlarmChange("mill", 1, 4, 411, 1, "EXCESS ERROR", True, T0)])
            sink.alarms([alarm(True, T0, axis=2)])
            event = await handler.event()
            assert event.Message.Text == "PS0010 (axis 2) IMPROPER G-CODE"
            assert event.SourceName == "lathe/Channel_2"
            sink.online("lathe", False, "timeout", T0 + 1)
            event = await handler.event()
            assert event.Quality == ua.StatusCode(ua.StatusCodes.BadCommunicationError)
            assert event.Retain is True
            assert handler.events.empty()
            await sub.delete()


async def test_a_new_shape_rebuilds_the_machine() -> None:
    async with running() as sink:
        sink.described(MILL)
        sink.described(replace(MILL))  # the same shape again: nothing to do
        sink.described(replace(MILL, paths=LATHE.paths))
        await sink.flush()
        async with connected(sink) as client:
            root = await machine_node(client, "mill")
            channels = await cnc_path(client, root, "CncChannelList")
            assert await browse_names(channels) == ["Channel_1", "Channel_2"]
