"""OPC 40502 (OPC UA for CNC Systems) as the gateway's OPC UA server declares it, built in code
from the specification's facts: its namespace, the node ids and browse names of its types, its
enumerations, and the engineering units of OPC 10000-8. No nodeset file is read.

Everything here is pure: :func:`cnc_type_nodes` returns the ``AddNodesItem`` list the server
adds in one call; :class:`NodeBuilder` collects the nodes of a machine for
:mod:`focas_net.gateway._opcua_model`.
"""

from __future__ import annotations

import enum
from typing import Final

from asyncua import ua

from focas_net.gateway.model import Unit

__all__ = [
    "CNC_NAMESPACE",
    "ENUMERATIONS",
    "EU_NAMESPACE",
    "POSITION_FIELDS",
    "CncId",
    "NodeBuilder",
    "child",
    "cnc_type_nodes",
    "enum_definitions",
    "eu_information",
    "eu_range",
    "unit_id",
]

#: The namespace of OPC 40502's types.
CNC_NAMESPACE: Final = "http://opcfoundation.org/UA/CNC"
#: The namespace of UN/CEFACT unit ids (OPC 10000-8, EUInformation).
EU_NAMESPACE: Final = "http://www.opcfoundation.org/UA/units/un/cefact"


#: The fields of ``CncPositionDataType``, in order.
POSITION_FIELDS: Final = ("ActPos", "CmdPos", "RemDist")


class CncId(enum.IntEnum):
    """The numeric node ids OPC 40502 gives its types (in :data:`CNC_NAMESPACE`)."""

    COMPONENT_TYPE = 1001
    CHANNEL_TYPE = 1002
    DRIVE_TYPE = 1003
    AXIS_TYPE = 1004
    SPINDLE_TYPE = 1005
    ALARM_TYPE = 1006
    INTERFACE_TYPE = 1007
    AXIS_LIST_TYPE = 1008
    SPINDLE_LIST_TYPE = 1009
    CHANNEL_LIST_TYPE = 1010
    MESSAGE_TYPE = 1011
    POSITION_VARIABLE_TYPE = 2001
    SPINDLE_TURN_DIRECTION = 3001
    CHANNEL_PROGRAM_STATUS = 3002
    CHANNEL_STATUS = 3003
    AXIS_STATUS = 3004
    SPINDLE_STATUS = 3005
    OPERATION_MODE = 3006
    POSITION_DATA_TYPE = 3007
    POSITION_BINARY_ENCODING = 5001


# Standard (namespace 0) ids used here.
BASE_OBJECT_TYPE: Final = 58
BASE_EVENT_TYPE: Final = 2041
DISCRETE_ALARM_TYPE: Final = 10523
BASE_DATA_VARIABLE_TYPE: Final = 63
PROPERTY_TYPE: Final = 68
DATA_ITEM_TYPE: Final = 2365
ANALOG_ITEM_TYPE: Final = 2368
ANALOG_UNIT_TYPE: Final = 17497
FOLDER_TYPE: Final = 61
ENUMERATION: Final = 29
STRUCTURE: Final = 22
HAS_COMPONENT: Final = 47
HAS_PROPERTY: Final = 46
HAS_SUBTYPE: Final = 45
ORGANIZES: Final = 35
MANDATORY: Final = 78
OPTIONAL: Final = 80

#: OPC 40502's enumerations: type id -> (browse name, the names of values 0, 1, ...).
ENUMERATIONS: Final[dict[CncId, tuple[str, tuple[str, ...]]]] = {
    CncId.SPINDLE_TURN_DIRECTION: ("CncSpindleTurnDirection", ("None", "CW", "CCW")),
    CncId.CHANNEL_PROGRAM_STATUS: (
        "CncChannelProgramStatus",
        ("Stopped", "Running", "Waiting", "Interrupted", "Canceled"),
    ),
    CncId.CHANNEL_STATUS: ("CncChannelStatus", ("Active", "Interrupted", "Reset")),
    CncId.AXIS_STATUS: ("CncAxisStatus", ("InPosition", "Moving", "Parked")),
    CncId.SPINDLE_STATUS: (
        "CncSpindleStatus",
        ("Stopped", "InTargetArea", "Accelerating", "Decelerating", "Parked"),
    ),
    CncId.OPERATION_MODE: ("CncOperationMode", ("Manual", "MDA", "Automatic")),
}

#: Object types: id -> (browse name, supertype (ns 0 int or CncId), abstract).
_OBJECT_TYPES: Final[tuple[tuple[CncId, str, int, bool], ...]] = (
    (CncId.COMPONENT_TYPE, "CncComponentType", BASE_OBJECT_TYPE, True),
    (CncId.INTERFACE_TYPE, "CncInterfaceType", BASE_OBJECT_TYPE, False),
    (CncId.CHANNEL_LIST_TYPE, "CncChannelListType", BASE_OBJECT_TYPE, False),
    (CncId.AXIS_LIST_TYPE, "CncAxisListType", BASE_OBJECT_TYPE, False),
    (CncId.SPINDLE_LIST_TYPE, "CncSpindleListType", BASE_OBJECT_TYPE, False),
    (CncId.CHANNEL_TYPE, "CncChannelType", CncId.COMPONENT_TYPE, False),
    (CncId.DRIVE_TYPE, "CncDriveType", CncId.COMPONENT_TYPE, True),
    (CncId.AXIS_TYPE, "CncAxisType", CncId.DRIVE_TYPE, False),
    (CncId.SPINDLE_TYPE, "CncSpindleType", CncId.DRIVE_TYPE, False),
    (CncId.ALARM_TYPE, "CncAlarmType", DISCRETE_ALARM_TYPE, False),
    (CncId.MESSAGE_TYPE, "CncMessageType", BASE_EVENT_TYPE, False),
)

#: CncAlarmType's properties: (id, browse name, value rank, modelling rule).
_ALARM_PROPERTIES: Final = (
    (6865, "AlarmIdentifier", -1, MANDATORY),
    (6862, "AuxParameters", 1, OPTIONAL),
    (6854, "HelpSource", -1, OPTIONAL),
)


def unit_id(unit: Unit) -> int:
    """``EUInformation.UnitId`` of a UN/CEFACT common code (OPC 10000-8): its ASCII bytes as a
    big-endian number (``MMT`` -> 5066068)."""
    return int.from_bytes(unit.code.encode("ascii"), "big")


def eu_information(unit: Unit) -> ua.EUInformation:
    """The ``EngineeringUnits`` value of ``unit``."""
    return ua.EUInformation(
        NamespaceUri=EU_NAMESPACE,
        UnitId=unit_id(unit),
        DisplayName=ua.LocalizedText(unit.symbol),
        Description=ua.LocalizedText(unit.description),
    )


#: ``EURange`` by unit code: the span a FANUC control's values of that unit take.
_RANGES: Final[dict[str, tuple[float, float]]] = {
    "MMT": (-99999.999, 99999.999),
    "H81": (0.0, 999999.0),
    "RPM": (-99999.0, 99999.0),
    "P1": (0.0, 255.0),
    "SEC": (0.0, 2.0**31),
    "C62": (-(2.0**31), 2.0**31),
}


def eu_range(unit: Unit) -> ua.Range:
    """The ``EURange`` value of a variable in ``unit``."""
    low, high = _RANGES.get(unit.code, (-(2.0**31), 2.0**31))
    return ua.Range(Low=low, High=high)


# --- building nodes ---------------------------------------------------------------------------


class NodeBuilder:
    """Collects ``AddNodesItem``s (parents before children) and references."""

    def __init__(self) -> None:
        self.items: list[ua.AddNodesItem] = []
        self.references: list[ua.AddReferencesItem] = []

    def object(
        self,
        parent: ua.NodeId,
        node: ua.NodeId,
        name: ua.QualifiedName,
        typedef: ua.NodeId,
        reference: int = HAS_COMPONENT,
        notifier: bool = False,
    ) -> ua.NodeId:
        attrs = ua.ObjectAttributes(
            DisplayName=ua.LocalizedText(name.Name),
            EventNotifier=1 if notifier else 0,
        )
        self._add(parent, node, name, ua.NodeClass.Object, typedef, reference, attrs)
        return node

    def variable(
        self,
        parent: ua.NodeId,
        node: ua.NodeId,
        name: ua.QualifiedName,
        datatype: ua.NodeId,
        value: ua.Variant,
        typedef: int | ua.NodeId = BASE_DATA_VARIABLE_TYPE,
        reference: int = HAS_COMPONENT,
        description: str = "",
    ) -> ua.NodeId:
        read = ua.AccessLevel.CurrentRead.mask
        attrs = ua.VariableAttributes(
            DisplayName=ua.LocalizedText(name.Name),
            Description=ua.LocalizedText(description) if description else ua.LocalizedText(),
            Value=value,
            DataType=datatype,
            ValueRank=-1,
            AccessLevel=read,
            UserAccessLevel=read,
        )
        typeid = typedef if isinstance(typedef, ua.NodeId) else ua.NodeId(typedef)
        self._add(parent, node, name, ua.NodeClass.Variable, typeid, reference, attrs)
        return node

    def prop(
        self, parent: ua.NodeId, name: str, datatype: int, value: ua.Variant, rank: int = -1
    ) -> ua.NodeId:
        node = child(parent, name)
        attrs = ua.VariableAttributes(
            DisplayName=ua.LocalizedText(name),
            Value=value,
            DataType=ua.NodeId(datatype),
            ValueRank=rank,
            AccessLevel=ua.AccessLevel.CurrentRead.mask,
            UserAccessLevel=ua.AccessLevel.CurrentRead.mask,
        )
        self._add(
            parent,
            node,
            ua.QualifiedName(name, 0),
            ua.NodeClass.Variable,
            ua.NodeId(PROPERTY_TYPE),
            HAS_PROPERTY,
            attrs,
        )
        return node

    def reference(self, source: ua.NodeId, target: ua.NodeId, kind: int, cls: ua.NodeClass) -> None:
        self.references.append(
            ua.AddReferencesItem(
                SourceNodeId=source,
                ReferenceTypeId=ua.NodeId(kind),
                IsForward=True,
                TargetNodeId=target,
                TargetNodeClass=cls,
            )
        )

    def _add(
        self,
        parent: ua.NodeId,
        node: ua.NodeId,
        name: ua.QualifiedName,
        cls: ua.NodeClass,
        typedef: ua.NodeId,
        reference: int,
        attrs: ua.ObjectAttributes | ua.VariableAttributes | ua.ObjectTypeAttributes,
    ) -> None:
        self.items.append(
            ua.AddNodesItem(
                ParentNodeId=parent,
                ReferenceTypeId=ua.NodeId(reference),
                RequestedNewNodeId=node,
                BrowseName=name,
                NodeClass=cls,
                NodeAttributes=attrs,
                TypeDefinition=typedef,
            )
        )


def child(parent: ua.NodeId, name: str) -> ua.NodeId:
    return ua.NodeId(f"{parent.Identifier}/{name}", parent.NamespaceIndex)


def cnc_type_nodes(cnc: int) -> tuple[list[ua.AddNodesItem], list[ua.AddReferencesItem]]:
    """The nodes of OPC 40502's types the gateway uses, in namespace ``cnc``: the object types
    (with ``CncAlarmType``'s properties, which its events carry), ``CncPositionVariableType``,
    the enumerations (``EnumStrings``) and ``CncPositionDataType`` with its binary encoding."""
    b = NodeBuilder()

    def ref(x: int) -> ua.NodeId:
        return ua.NodeId(x, cnc) if isinstance(x, CncId) else ua.NodeId(x)

    for tid, name, base, abstract in _OBJECT_TYPES:
        b.items.append(
            ua.AddNodesItem(
                ParentNodeId=ref(base),
                ReferenceTypeId=ua.NodeId(HAS_SUBTYPE),
                RequestedNewNodeId=ua.NodeId(tid, cnc),
                BrowseName=ua.QualifiedName(name, cnc),
                NodeClass=ua.NodeClass.ObjectType,
                NodeAttributes=ua.ObjectTypeAttributes(
                    DisplayName=ua.LocalizedText(name), IsAbstract=abstract
                ),
            )
        )
    alarm = ua.NodeId(CncId.ALARM_TYPE, cnc)
    for nid, name, rank, rule in _ALARM_PROPERTIES:
        node = ua.NodeId(nid, cnc)
        b.items.append(
            ua.AddNodesItem(
                ParentNodeId=alarm,
                ReferenceTypeId=ua.NodeId(HAS_PROPERTY),
                RequestedNewNodeId=node,
                BrowseName=ua.QualifiedName(name, cnc),
                NodeClass=ua.NodeClass.Variable,
                NodeAttributes=ua.VariableAttributes(
                    DisplayName=ua.LocalizedText(name),
                    DataType=ua.NodeId(ua.ObjectIds.String),
                    ValueRank=rank,
                    Value=ua.Variant("" if rank < 0 else [], ua.VariantType.String),
                ),
                TypeDefinition=ua.NodeId(PROPERTY_TYPE),
            )
        )
        b.reference(node, ua.NodeId(rule), ua.ObjectIds.HasModellingRule, ua.NodeClass.Object)
    b.items.append(
        ua.AddNodesItem(
            ParentNodeId=ua.NodeId(BASE_DATA_VARIABLE_TYPE),
            ReferenceTypeId=ua.NodeId(HAS_SUBTYPE),
            RequestedNewNodeId=ua.NodeId(CncId.POSITION_VARIABLE_TYPE, cnc),
            BrowseName=ua.QualifiedName("CncPositionVariableType", cnc),
            NodeClass=ua.NodeClass.VariableType,
            NodeAttributes=ua.VariableTypeAttributes(
                DisplayName=ua.LocalizedText("CncPositionVariableType"),
                DataType=ua.NodeId(CncId.POSITION_DATA_TYPE, cnc),
                ValueRank=-1,
            ),
        )
    )
    for tid, (name, values) in ENUMERATIONS.items():
        node = ua.NodeId(tid, cnc)
        b.items.append(
            ua.AddNodesItem(
                ParentNodeId=ua.NodeId(ENUMERATION),
                ReferenceTypeId=ua.NodeId(HAS_SUBTYPE),
                RequestedNewNodeId=node,
                BrowseName=ua.QualifiedName(name, cnc),
                NodeClass=ua.NodeClass.DataType,
                NodeAttributes=ua.DataTypeAttributes(DisplayName=ua.LocalizedText(name)),
            )
        )
        b.prop(
            node,
            "EnumStrings",
            ua.ObjectIds.LocalizedText,
            ua.Variant([ua.LocalizedText(v) for v in values], ua.VariantType.LocalizedText),
            rank=1,
        )
    b.items.append(
        ua.AddNodesItem(
            ParentNodeId=ua.NodeId(STRUCTURE),
            ReferenceTypeId=ua.NodeId(HAS_SUBTYPE),
            RequestedNewNodeId=ua.NodeId(CncId.POSITION_DATA_TYPE, cnc),
            BrowseName=ua.QualifiedName("CncPositionDataType", cnc),
            NodeClass=ua.NodeClass.DataType,
            NodeAttributes=ua.DataTypeAttributes(
                DisplayName=ua.LocalizedText("CncPositionDataType")
            ),
        )
    )
    b.items.append(
        ua.AddNodesItem(
            ParentNodeId=ua.NodeId(CncId.POSITION_DATA_TYPE, cnc),
            ReferenceTypeId=ua.NodeId(ua.ObjectIds.HasEncoding),
            RequestedNewNodeId=ua.NodeId(CncId.POSITION_BINARY_ENCODING, cnc),
            BrowseName=ua.QualifiedName("Default Binary", 0),
            NodeClass=ua.NodeClass.Object,
            NodeAttributes=ua.ObjectAttributes(DisplayName=ua.LocalizedText("Default Binary")),
            TypeDefinition=ua.NodeId(ua.ObjectIds.DataTypeEncodingType),
        )
    )
    return b.items, b.references


def enum_definitions(cnc: int) -> dict[ua.NodeId, ua.DataTypeDefinition]:
    """The ``DataTypeDefinition`` of each enumeration and of ``CncPositionDataType``."""
    out: dict[ua.NodeId, ua.DataTypeDefinition] = {
        ua.NodeId(tid, cnc): ua.EnumDefinition(
            Fields=[
                ua.EnumField(Value=i, DisplayName=ua.LocalizedText(v), Name=v)
                for i, v in enumerate(values)
            ]
        )
        for tid, (_, values) in ENUMERATIONS.items()
    }
    out[ua.NodeId(CncId.POSITION_DATA_TYPE, cnc)] = ua.StructureDefinition(
        DefaultEncodingId=ua.NodeId(CncId.POSITION_BINARY_ENCODING, cnc),
        BaseDataType=ua.NodeId(STRUCTURE),
        StructureType=ua.StructureType.Structure,
        Fields=[
            ua.StructureField(
                Name=n, DataType=ua.NodeId(ua.ObjectIds.Double), ValueRank=-1, IsOptional=False
            )
            for n in POSITION_FIELDS
        ],
    )
    return out
