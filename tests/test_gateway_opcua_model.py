"""The OPC UA model without a server: OPC 40502's ids and enumerations, UN/CEFACT unit ids,
where each item of a machine goes, names of axes shared by paths, and the sink's coalescing
queue."""

from __future__ import annotations

from dataclasses import replace

from asyncua import ua
from opcua_support import LATHE, MILL, SETTINGS, sample

from focas_net.gateway._opcua_model import axis_names, machine_nodes, spindle_names
from focas_net.gateway._opcua_types import ENUMERATIONS, CncId, cnc_type_nodes, unit_id
from focas_net.gateway.model import ITEMS, MILLIMETRE, ONE, PERCENT, PathShape, Scope
from focas_net.gateway.opcua import OpcUaSink


def test_unit_ids_are_the_common_codes_bytes() -> None:
    assert unit_id(MILLIMETRE) == 5066068  # OPC 10000-8's example for MMT
    assert unit_id(PERCENT) == 0x5031
    assert unit_id(ONE) == 0x433632


def test_the_types_keep_opc_40502s_ids() -> None:
    items, _ = cnc_type_nodes(3)
    named = {
        i.BrowseName.Name: i.RequestedNewNodeId for i in items if i.BrowseName.NamespaceIndex == 3
    }
    assert named["CncInterfaceType"] == ua.NodeId(1007, 3)
    assert named["CncChannelType"] == ua.NodeId(1002, 3)
    assert named["CncAxisType"] == ua.NodeId(1004, 3)
    assert named["CncSpindleType"] == ua.NodeId(1005, 3)
    assert named["CncAlarmType"] == ua.NodeId(1006, 3)
    assert named["CncOperationMode"] == ua.NodeId(3006, 3)
    assert named["AlarmIdentifier"] == ua.NodeId(6865, 3)
    assert ENUMERATIONS[CncId.CHANNEL_STATUS][1] == ("Active", "Interrupted", "Reset")


def test_axes_shared_by_paths_take_the_paths_number() -> None:
    assert list(axis_names(LATHE).values()) == ["X1", "Z1", "X2", "Z2"]
    assert list(spindle_names(LATHE).values()) == ["S1", "S2"]
    odd = replace(MILL, paths=(PathShape(1, ("X", "Y"), ()), PathShape(2, ("X", "B"), ())))
    assert axis_names(odd) == {(1, "X"): "X1", (1, "Y"): "Y", (2, "X"): "X2", (2, "B"): "B"}


def test_a_name_ending_in_a_digit_on_two_paths_takes_the_path_after_p() -> None:
    """A twin-turret lathe whose paths both name their spindle S1 (and their axes X1, Z1 as
    the control numbers them) lists S1_P1 and S1_P2, not S11 and S12 (spindles 11 and 12)."""
    twin = replace(
        LATHE, paths=(PathShape(1, ("X1", "Z1"), ("S1",)), PathShape(2, ("X1", "Z2"), ("S1",)))
    )
    assert spindle_names(twin) == {(1, "S1"): "S1_P1", (2, "S1"): "S1_P2"}
    assert axis_names(twin) == {
        (1, "X1"): "X1_P1",
        (1, "Z1"): "Z1",
        (2, "X1"): "X1_P2",
        (2, "Z2"): "Z2",
    }


def test_every_item_of_every_path_axis_and_spindle_has_a_variable() -> None:
    _, _, nodes = machine_nodes(LATHE, 2, 3)
    for path in LATHE.paths:
        for it in ITEMS.values():
            keys = {
                Scope.PATH: [""],
                Scope.AXIS: list(path.axes),
                Scope.SPINDLE: list(path.spindles),
                Scope.MACHINE: [],
            }[it.scope]
            for key in keys:
                targets = nodes.targets[(path.number, it.name, key)]
                assert any("/Focas/" in str(t.node.Identifier) for t in targets)
    machine = nodes.targets[(2, "machine", "X")]
    assert sorted(str(t.node.Identifier) for t in machine) == [
        "lathe/CncAxisList/X2/PosIndirect/ActPos",
        "lathe/CncChannelList/Channel_2/PosTcpBcsX/ActPos",
        "lathe/Focas/Path_2/Axis_X/machine",
    ]
    run = nodes.targets[(1, "run", "")]
    assert [t.convert("STRT") for t in run if t.convert is not None] == [1, 0]
    assert len(nodes.variables) == len(set(nodes.variables))


def test_a_waiting_sample_is_replaced_by_the_newer_one_of_its_variable() -> None:
    sink = OpcUaSink(SETTINGS)
    batch = [sample("lathe", 1, "feed", float(i)) for i in range(3)]
    sink.samples(batch)
    sink.samples(batch)
    assert sink.pending == 1 and sink.coalesced == 5  # one variable: its newest sample waits
    sink.online("lathe", False, "connection lost", 0.0)
    sink.samples([sample("lathe", 1, "feed", 9.0), sample("lathe", 2, "feed", 1.0)])
    assert sink.pending == 2 and sink.coalesced == 6
    sink.samples([])
    assert sink.pending == 2
