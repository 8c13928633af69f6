"""Where each of the gateway's items (:data:`~focas_net.gateway.model.ITEMS`) goes in a
machine's OPC 40502 ``CncInterfaceType`` object (:mod:`focas_net.gateway._opcua_types` declares
the types), and how FOCAS values become OPC 40502's.

Everything here is pure: :func:`machine_nodes` returns the ``AddNodesItem`` list the server adds
in one call, and :class:`MachineNodes` tells the sink which variables each sample writes.
``docs/gateway.md`` (OPC UA) draws the tree.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Final

from asyncua import ua

from focas_net.gateway._opcua_types import (
    ANALOG_ITEM_TYPE,
    ANALOG_UNIT_TYPE,
    BASE_DATA_VARIABLE_TYPE,
    DATA_ITEM_TYPE,
    FOLDER_TYPE,
    HAS_PROPERTY,
    ORGANIZES,
    POSITION_FIELDS,
    PROPERTY_TYPE,
    CncId,
    NodeBuilder,
    child,
    eu_information,
    eu_range,
)
from focas_net.gateway.model import ITEMS, MILLIMETRE, Item, MachineShape, Scope, Unit, Value
from focas_net.protocol.values import AutMode, RunState, control_type_name

__all__ = ["MachineNodes", "Target", "axis_names", "machine_nodes", "spindle_names"]

_VARIANT: Final[dict[type, ua.VariantType]] = {
    bool: ua.VariantType.Boolean,
    int: ua.VariantType.Int32,
    float: ua.VariantType.Double,
    str: ua.VariantType.String,
}

#: A sample's value turned into the variable's value (None: the value has no place there).
Convert = Callable[[Value], Value]


@dataclass(frozen=True, slots=True)
class Target:
    """One variable a sample writes: its node id, the variant type of its value, and how the
    sample's value becomes its value (None: as it is)."""

    node: ua.NodeId
    variant: ua.VariantType
    convert: Convert | None = None


@dataclass(slots=True)
class MachineNodes:
    """A machine's nodes as the sink uses them: its root object, where each sample goes
    (``(path, item name, key)`` -> targets), and every variable a sample can write."""

    root: ua.NodeId
    targets: dict[tuple[int, str, str], tuple[Target, ...]] = field(default_factory=dict)
    variables: list[ua.NodeId] = field(default_factory=list)
    #: The ``CncPositionVariableType`` variables each sample goes into, with the index of its
    #: field in ``CncPositionDataType`` (:data:`POSITION_FIELDS`).
    positions: dict[tuple[int, str, str], list[tuple[ua.NodeId, int]]] = field(default_factory=dict)

    def add(self, key: tuple[int, str, str], target: Target) -> None:
        self.targets[key] = (*self.targets.get(key, ()), target)
        self.variables.append(target.node)


# --- conversions of FOCAS values into OPC 40502's ---------------------------------------------

# (the poller names the modes and run states by the one table's labels, as the CNC screen and
# every front end: AutMode.MEM is "MEM", RunState.RESET "****")
_OPERATION_MODE: Final = {
    **{m.label: 0 for m in AutMode if m not in (AutMode.NOSEL, AutMode.MDI)},  # Manual
    AutMode.MDI.label: 1,  # MDA
    AutMode.MEM.label: 2,  # Automatic
    AutMode.RMT.label: 2,
}
_PROGRAM_STATUS: Final = {
    RunState.RESET.label: 0,  # Stopped
    RunState.STOP.label: 3,  # Interrupted
    RunState.HOLD.label: 3,
    RunState.STRT.label: 1,  # Running
    RunState.MSTR.label: 1,
}
_CHANNEL_STATUS: Final = {
    RunState.RESET.label: 2,  # Reset
    RunState.STOP.label: 1,  # Interrupted
    RunState.HOLD.label: 1,
    RunState.STRT.label: 0,  # Active
    RunState.MSTR.label: 0,
}


def _operation_mode(value: Value) -> Value:
    """MDI is OPC 40502's MDA, memory and remote (DNC) operation Automatic, the other modes
    Manual; no selection (``****``) and a number without a name are none of them (None: the
    variable is BadOutOfRange)."""
    return _OPERATION_MODE.get(str(value))


def _program_status(value: Value) -> Value:
    return _PROGRAM_STATUS.get(str(value))


def _channel_status(value: Value) -> Value:
    return _CHANNEL_STATUS.get(str(value))


def _program_name(value: Value) -> Value:
    return None if value is None else f"O{int(value):04d}"


def _as_double(value: Value) -> Value:
    return None if value is None else float(value)


def _tool_id(value: Value) -> Value:
    return None if value is None else max(0, int(value))


def _unique(names: list[tuple[int, str]]) -> dict[tuple[int, str], str]:
    """Each ``(path, name)`` as its browse name in a list of the whole machine: the name, or
    when another path has that name too, the name with the path's number: appended to a
    name without a subscript (a 2-path lathe's X of path 2 is ``X2``, as FANUC's screens name
    it), after ``_P`` to one that ends in a digit already (the S1 of path 2 is ``S1_P2``, never
    ``S12``, which reads as spindle 12)."""
    counts: dict[str, int] = {}
    for _, name in names:
        counts[name] = counts.get(name, 0) + 1
    out: dict[tuple[int, str], str] = {}
    for path, name in names:
        if counts[name] == 1:
            out[(path, name)] = name
        else:
            out[(path, name)] = f"{name}_P{path}" if name[-1:].isdigit() else f"{name}{path}"
    return out


def axis_names(shape: MachineShape) -> dict[tuple[int, str], str]:
    """The browse name of each ``(path, axis)`` in the machine's ``CncAxisList`` (see
    :func:`_unique`)."""
    return _unique([(p.number, a) for p in shape.paths for a in p.axes])


def spindle_names(shape: MachineShape) -> dict[tuple[int, str], str]:
    """As :func:`axis_names`, for ``CncSpindleList``."""
    return _unique([(p.number, s) for p in shape.paths for s in p.spindles])


class _Machine:
    """Builds one machine's nodes (a :class:`NodeBuilder` and the :class:`MachineNodes`)."""

    def __init__(self, shape: MachineShape, ns: int, cnc: int) -> None:
        self.shape, self.ns, self.cnc = shape, ns, cnc
        self.b = NodeBuilder()
        self.root = ua.NodeId(shape.name, ns)
        self.nodes = MachineNodes(self.root)

    def qn(self, name: str) -> ua.QualifiedName:
        return ua.QualifiedName(name, self.cnc)

    def tid(self, cid: CncId) -> ua.NodeId:
        return ua.NodeId(cid, self.cnc)

    def obj(
        self, parent: ua.NodeId, name: str, cid: CncId | int, qns: int | None = None
    ) -> ua.NodeId:
        typedef = self.tid(cid) if isinstance(cid, CncId) else ua.NodeId(cid)
        qname = ua.QualifiedName(name, self.cnc if qns is None else qns)
        return self.b.object(parent, child(parent, name), qname, typedef)

    def prop(self, parent: ua.NodeId, name: str, value: str) -> None:
        node = child(parent, name)
        self.b.items.append(
            ua.AddNodesItem(
                ParentNodeId=parent,
                ReferenceTypeId=ua.NodeId(HAS_PROPERTY),
                RequestedNewNodeId=node,
                BrowseName=self.qn(name),
                NodeClass=ua.NodeClass.Variable,
                NodeAttributes=ua.VariableAttributes(
                    DisplayName=ua.LocalizedText(name),
                    Value=ua.Variant(value, ua.VariantType.String),
                    DataType=ua.NodeId(ua.ObjectIds.String),
                    ValueRank=-1,
                    AccessLevel=ua.AccessLevel.CurrentRead.mask,
                    UserAccessLevel=ua.AccessLevel.CurrentRead.mask,
                ),
                TypeDefinition=ua.NodeId(PROPERTY_TYPE),
            )
        )

    def slot(
        self,
        parent: ua.NodeId,
        name: str,
        key: tuple[int, str, str],
        variant: ua.VariantType,
        datatype: ua.NodeId | int,
        unit: Unit | None = None,
        convert: Convert | None = None,
        typedef: int | ua.NodeId = DATA_ITEM_TYPE,
        qns: int | None = None,
        description: str = "",
    ) -> ua.NodeId:
        """A variable a sample of ``key`` writes. With a unit: a data item becomes an
        AnalogItemType with EngineeringUnits and EURange; another type gets EngineeringUnits."""
        node = child(parent, name)
        dt = datatype if isinstance(datatype, ua.NodeId) else ua.NodeId(datatype)
        if unit is not None and typedef == DATA_ITEM_TYPE:
            typedef = ANALOG_ITEM_TYPE
        qname = ua.QualifiedName(name, self.cnc if qns is None else qns)
        self.b.variable(parent, node, qname, dt, ua.Variant(None), typedef, description=description)
        if unit is not None:
            self.units(node, unit, with_range=typedef == ANALOG_ITEM_TYPE)
        self.nodes.add(key, Target(node, variant, convert))
        return node

    def units(self, node: ua.NodeId, unit: Unit, with_range: bool = True) -> None:
        self.b.prop(
            node, "EngineeringUnits", ua.ObjectIds.EUInformation, ua.Variant(eu_information(unit))
        )
        if with_range:
            self.b.prop(node, "EURange", ua.ObjectIds.Range, ua.Variant(eu_range(unit)))

    def position(
        self, parent: ua.NodeId, name: str, parts: dict[str, tuple[int, str, str]]
    ) -> None:
        """A ``CncPositionVariableType`` variable: samples write its parts (ActPos, RemDist)
        and its ``CncPositionDataType`` value."""
        node = child(parent, name)
        self.nodes.variables.append(node)
        for part, key in parts.items():
            self.nodes.positions.setdefault(key, []).append((node, POSITION_FIELDS.index(part)))
        self.b.variable(
            parent,
            node,
            self.qn(name),
            self.tid(CncId.POSITION_DATA_TYPE),
            ua.Variant(None),
            self.tid(CncId.POSITION_VARIABLE_TYPE),
        )
        self.units(node, MILLIMETRE)
        for part, key in parts.items():
            self.slot(
                node,
                part,
                key,
                ua.VariantType.Double,
                ua.ObjectIds.Double,
                MILLIMETRE,
                typedef=BASE_DATA_VARIABLE_TYPE,
            )

    def build(self) -> None:
        shape, dbl = self.shape, ua.VariantType.Double
        root = self.b.object(
            ua.NodeId(ua.ObjectIds.ObjectsFolder),
            self.root,
            ua.QualifiedName(shape.name, self.ns),
            self.tid(CncId.INTERFACE_TYPE),
            reference=ORGANIZES,
            notifier=True,
        )
        self.prop(root, "VendorName", "FANUC")
        self.prop(root, "VendorRevision", f"{shape.series} {shape.version}".strip())
        self.prop(root, "Version", "1.00")
        self.prop(root, "CncTypeName", control_type_name(shape.cnc_type, shape.mt_type))
        channels = self.obj(root, "CncChannelList", CncId.CHANNEL_LIST_TYPE)
        axes = self.obj(root, "CncAxisList", CncId.AXIS_LIST_TYPE)
        spindles = self.obj(root, "CncSpindleList", CncId.SPINDLE_LIST_TYPE)
        focas = self.obj(root, "Focas", FOLDER_TYPE, qns=self.ns)
        anames, snames = axis_names(shape), spindle_names(shape)
        for path in shape.paths:
            n = path.number
            ch = self.obj(channels, f"Channel_{n}", CncId.CHANNEL_TYPE)
            self.b.items.append(
                ua.AddNodesItem(
                    ParentNodeId=ch,
                    ReferenceTypeId=ua.NodeId(HAS_PROPERTY),
                    RequestedNewNodeId=child(ch, "Id"),
                    BrowseName=self.qn("Id"),
                    NodeClass=ua.NodeClass.Variable,
                    NodeAttributes=ua.VariableAttributes(
                        DisplayName=ua.LocalizedText("Id"),
                        Value=ua.Variant(n, ua.VariantType.UInt32),
                        DataType=ua.NodeId(ua.ObjectIds.UInt32),
                        ValueRank=-1,
                        AccessLevel=ua.AccessLevel.CurrentRead.mask,
                        UserAccessLevel=ua.AccessLevel.CurrentRead.mask,
                    ),
                    TypeDefinition=ua.NodeId(PROPERTY_TYPE),
                )
            )
            self.channel(ch, n)
            for a in path.axes:
                ax = self.obj(axes, anames[(n, a)], CncId.AXIS_TYPE)
                self.b.reference(ch, ax, ORGANIZES, ua.NodeClass.Object)
                self.drive(ax, ch)
                self.position(
                    ax, "PosIndirect", {"ActPos": (n, "machine", a), "RemDist": (n, "distance", a)}
                )
                self.slot(
                    ax,
                    "ActLoad",
                    (n, "servo_load", a),
                    dbl,
                    ua.ObjectIds.Double,
                    ITEMS["servo_load"].unit,
                )
                letter = a[:1].upper()
                if letter in "XYZABC" and letter and a.rstrip("0123456789") == letter:
                    self.position(
                        ch,
                        f"PosTcpBcs{letter}",
                        {"ActPos": (n, "machine", a), "RemDist": (n, "distance", a)},
                    )
                    self.position(
                        ch,
                        f"PosTcpWcs{letter}",
                        {"ActPos": (n, "absolute", a), "RemDist": (n, "distance", a)},
                    )
            for i, s in enumerate(path.spindles):
                sp = self.obj(spindles, snames[(n, s)], CncId.SPINDLE_TYPE)
                self.b.reference(ch, sp, ORGANIZES, ua.NodeClass.Object)
                self.drive(sp, ch)
                self.slot(
                    sp,
                    "ActLoad",
                    (n, "spindle_load", s),
                    dbl,
                    ua.ObjectIds.Double,
                    ITEMS["spindle_load"].unit,
                )
                if i == 0:
                    # cnc_acts and the spindle override G signal are the path's main spindle's
                    self.slot(
                        sp,
                        "ActSpeed",
                        (n, "spindle_speed", ""),
                        dbl,
                        ua.ObjectIds.Double,
                        ITEMS["spindle_speed"].unit,
                        _as_double,
                    )
                    self.slot(
                        sp,
                        "ActOverride",
                        (n, "spindle_override", ""),
                        dbl,
                        ua.ObjectIds.Double,
                        ITEMS["spindle_override"].unit,
                        _as_double,
                    )
            self.focas_items(focas, path.number, path.axes, path.spindles)

    def drive(self, drive: ua.NodeId, channel: ua.NodeId) -> None:
        node = child(drive, "ActChannel")
        self.b.variable(
            drive,
            node,
            self.qn("ActChannel"),
            ua.NodeId(ua.ObjectIds.NodeId),
            ua.Variant(channel, ua.VariantType.NodeId),
            DATA_ITEM_TYPE,
        )

    def channel(self, ch: ua.NodeId, n: int) -> None:
        dbl, i32 = ua.VariantType.Double, ua.VariantType.Int32
        self.slot(
            ch,
            "ActOperationMode",
            (n, "mode", ""),
            i32,
            self.tid(CncId.OPERATION_MODE),
            convert=_operation_mode,
        )
        self.slot(
            ch,
            "ActProgramStatus",
            (n, "run", ""),
            i32,
            self.tid(CncId.CHANNEL_PROGRAM_STATUS),
            convert=_program_status,
        )
        self.slot(
            ch,
            "ActStatus",
            (n, "run", ""),
            i32,
            self.tid(CncId.CHANNEL_STATUS),
            convert=_channel_status,
        )
        self.slot(
            ch,
            "ActProgramName",
            (n, "program", ""),
            ua.VariantType.String,
            ua.ObjectIds.String,
            convert=_program_name,
        )
        self.slot(
            ch,
            "ActMainProgramName",
            (n, "main_program", ""),
            ua.VariantType.String,
            ua.ObjectIds.String,
            convert=_program_name,
        )
        self.slot(ch, "ActFeedrate", (n, "feed", ""), dbl, ua.ObjectIds.Double, ITEMS["feed"].unit)
        self.slot(
            ch,
            "ActOverride",
            (n, "feed_override", ""),
            dbl,
            ua.ObjectIds.Double,
            ITEMS["feed_override"].unit,
            _as_double,
        )
        self.slot(
            ch,
            "ToolId",
            (n, "tool", ""),
            ua.VariantType.UInt32,
            ua.ObjectIds.UInt32,
            convert=_tool_id,
        )

    def focas_items(
        self, focas: ua.NodeId, n: int, axes: tuple[str, ...], spindles: tuple[str, ...]
    ) -> None:
        """Every item, as the gateway reads it, under ``Focas/Path_<n>`` (axis and spindle
        items under ``Axis_<name>`` and ``Spindle_<name>``)."""
        folder = self.obj(focas, f"Path_{n}", FOLDER_TYPE, qns=self.ns)
        holders: dict[Scope, list[tuple[str, ua.NodeId]]] = {Scope.PATH: [("", folder)]}
        holders[Scope.MACHINE] = [("", focas)] if n == self.shape.paths[0].number else []
        holders[Scope.AXIS] = [
            (a, self.obj(folder, f"Axis_{a}", FOLDER_TYPE, qns=self.ns)) for a in axes
        ]
        holders[Scope.SPINDLE] = [
            (s, self.obj(folder, f"Spindle_{s}", FOLDER_TYPE, qns=self.ns)) for s in spindles
        ]
        for it in ITEMS.values():
            for key, parent in holders[it.scope]:
                self.focas_item(parent, n if it.scope is not Scope.MACHINE else 0, it, key)

    def focas_item(self, parent: ua.NodeId, n: int, it: Item, key: str) -> None:
        variant = _VARIANT[it.kind]
        analog = it.unit is not None and it.kind in (int, float)
        typedef = ANALOG_UNIT_TYPE if analog else DATA_ITEM_TYPE
        self.slot(
            parent,
            it.name,
            (n, it.name, key),
            variant,
            int(variant.value),
            it.unit if analog else None,
            typedef=typedef,
            qns=self.ns,
            description=it.description,
        )


def machine_nodes(
    shape: MachineShape, ns: int, cnc: int
) -> tuple[list[ua.AddNodesItem], list[ua.AddReferencesItem], MachineNodes]:
    """The nodes of one machine (its ``CncInterfaceType`` object under Objects, browse name its
    configured name in namespace ``ns``), the references between its channels and their axes
    and spindles, and the :class:`MachineNodes` the sink writes through."""
    m = _Machine(shape, ns, cnc)
    m.build()
    return m.b.items, m.b.references, m.nodes
