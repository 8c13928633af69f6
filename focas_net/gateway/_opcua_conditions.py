"""FANUC alarms as OPC UA alarm conditions of OPC 40502's ``CncAlarmType`` (a subtype of
``DiscreteAlarmType``): raised when an alarm enters a path's active list, cleared when it leaves
it, sent again with a Bad quality while its machine is lost, acknowledged by a client with the
standard ``Acknowledge`` method. Each event is notified by the machine's object and by the
Server object; each condition is an object of the address space (its ConditionId) that the
machine's object references with HasCondition from the alarm's first raise on: a cleared
condition keeps its object (inactive, ``Retain`` false), which the same alarm raised again
reuses, so an alarm that comes and goes costs no change of the address space
(``docs/gateway.md``, Alarms)."""

from __future__ import annotations

import uuid
from collections.abc import Sequence
from datetime import UTC, datetime
from typing import Any, Final

from asyncua import Server, ua
from asyncua.common import event_objects

from focas_net.gateway._opcua_types import CncId
from focas_net.gateway.model import AlarmChange
from focas_net.protocol.alarms import alarm_code, alarm_text

__all__ = ["ALARM_SEVERITY", "Conditions", "condition_name"]

#: The severity of every FANUC alarm condition (OPC UA 1..1000: "high").
ALARM_SEVERITY: Final = 700

_GOOD: Final = ua.StatusCode(ua.StatusCodes.Good)
_ACKNOWLEDGE: Final = ua.NodeId(ua.ObjectIds.AcknowledgeableConditionType_Acknowledge)
_REFRESH: Final = (
    ua.NodeId(ua.ObjectIds.ConditionType_ConditionRefresh),
    ua.NodeId(ua.ObjectIds.ConditionType_ConditionRefresh2),
)
_SERVER: Final = ua.NodeId(ua.ObjectIds.Server)
_REFRESH_MARKS: Final = (ua.ObjectIds.RefreshStartEventType, ua.ObjectIds.RefreshEndEventType)
#: The built-in types of the data types asyncua's event fields name by node id.
_BUILT_IN: Final = {
    ua.ObjectIds.UtcTime: ua.VariantType.DateTime,
    ua.ObjectIds.Duration: ua.VariantType.Double,
    ua.ObjectIds.AudioDataType: ua.VariantType.ByteString,
}


def condition_name(alm_type: int, alm_no: int, axis: int) -> str:
    """An alarm's ``ConditionName`` and ``AlarmIdentifier``: its code as the CNC screen shows
    it, and ``/<axis>`` for an axis's alarm (``SV0411/1``)."""
    code = alarm_code(alm_type, alm_no)
    return f"{code}/{axis}" if axis else code


class Conditions:
    """The active alarm conditions of every machine of ``server`` (machines' browse names in
    namespace ``ns``, OPC 40502's in ``cnc``)."""

    def __init__(self, server: Server, ns: int, cnc: int) -> None:
        self._server, self._ns, self._cnc = server, ns, cnc
        #: The event each active alarm was raised with (its fields move with it).
        self._active: dict[tuple[str, int, int, int, int], Any] = {}
        #: The active conditions by ConditionId.
        self._by_id: dict[ua.NodeId, Any] = {}
        #: The ConditionIds whose object is in the address space (active or not).
        self._nodes: set[ua.NodeId] = set()
        session = server.iserver.isession
        session.add_method_callback(_ACKNOWLEDGE, self._acknowledge)
        for refresh in _REFRESH:
            session.add_method_callback(refresh, self._refresh)

    async def apply(self, changes: Sequence[AlarmChange], roots: dict[str, ua.NodeId]) -> None:
        """Raise or clear a condition for each change of a machine in ``roots`` (its object)."""
        for c in changes:
            root = roots.get(c.machine)
            if root is None:
                continue
            key = (c.machine, c.path, c.alm_type, c.alm_no, c.axis_no)
            ev = self._active.get(key)
            if c.active:
                if ev is not None:
                    continue
                ev = self._active[key] = self._new(c, root)
                self._by_id[ev.NodeId] = ev
                if ev.NodeId not in self._nodes:
                    await self._add_node(ev, root)
                    self._nodes.add(ev.NodeId)
            elif ev is None:
                continue
            else:
                del self._active[key]
                del self._by_id[ev.NodeId]
            ev.ActiveState = ua.LocalizedText("Active" if c.active else "Inactive")
            setattr(ev, "ActiveState/Id", c.active)
            setattr(ev, "ActiveState/TransitionTime", datetime.fromtimestamp(c.time, UTC))
            ev.Retain = c.active
            await self._trigger(ev, c.time, root)

    async def quality(
        self, machine: str, quality: ua.StatusCode, time: float, root: ua.NodeId
    ) -> None:
        """Send the machine's active conditions again with ``quality``."""
        for key, ev in self._active.items():
            if key[0] == machine:
                ev.Quality = quality
                await self._trigger(ev, time, root)

    async def _add_node(self, ev: Any, root: ua.NodeId) -> None:
        """The condition's object, which ``Acknowledge`` is called on."""
        item = ua.AddNodesItem(
            ParentNodeId=root,
            ReferenceTypeId=ua.NodeId(ua.ObjectIds.HasCondition),
            RequestedNewNodeId=ev.NodeId,
            BrowseName=ua.QualifiedName(ev.ConditionName, self._ns),
            NodeClass=ua.NodeClass.Object,
            NodeAttributes=ua.ObjectAttributes(DisplayName=ua.LocalizedText(ev.ConditionName)),
            TypeDefinition=ua.NodeId(CncId.ALARM_TYPE, self._cnc),
        )
        for result in await self._server.iserver.isession.add_nodes([item]):
            result.StatusCode.check()

    async def _acknowledge(self, condition: ua.NodeId, event_id: Any, comment: Any) -> Any:
        """``Acknowledge(EventId, Comment)`` on an active condition: its AckedState becomes
        Acknowledged and the condition is sent again (FANUC's alarm stays until the control
        drops it)."""
        ev = self._by_id.get(condition)
        if ev is None:  # (a cleared condition retains no event to acknowledge)
            cleared = condition in self._nodes
            return ua.StatusCode(
                ua.StatusCodes.BadEventIdUnknown
                if cleared
                else ua.StatusCodes.BadConditionIdUnknown
            )
        if event_id.Value != ev.EventId:
            return ua.StatusCode(ua.StatusCodes.BadEventIdUnknown)
        if getattr(ev, "AckedState/Id"):
            return ua.StatusCode(ua.StatusCodes.BadConditionBranchAlreadyAcked)
        ev.AckedState = ua.LocalizedText("Acknowledged")
        setattr(ev, "AckedState/Id", True)
        if isinstance(comment.Value, ua.LocalizedText):
            ev.Comment = comment.Value
        await self._trigger(ev, datetime.now(UTC).timestamp(), ev.SourceNode)
        return []

    async def _refresh(self, parent: ua.NodeId, subscription: Any, *item: Any) -> Any:
        """``ConditionRefresh(SubscriptionId)`` and ``ConditionRefresh2(SubscriptionId,
        MonitoredItemId)``: every active condition sent again to that subscription (or that
        monitored item of it), as the machine's object and the Server object notify it,
        between a RefreshStartEvent and a RefreshEndEvent."""
        service = self._server.iserver.subscription_service
        sub = service.subscriptions.get(subscription.Value)
        if sub is None:
            return ua.StatusCode(ua.StatusCodes.BadSubscriptionIdInvalid)
        items = sub.monitored_item_srv
        mid = item[0].Value if item else None
        if mid is not None and mid not in items._monitored_items:
            return ua.StatusCode(ua.StatusCodes.BadMonitoredItemIdInvalid)
        marks = [service.standard_events.get(t) for t in _REFRESH_MARKS]
        if marks[0] is not None:
            await marks[0].trigger(subscription_id=sub.data.SubscriptionId)
        for ev in list(self._by_id.values()):
            for node in (ev.SourceNode, _SERVER):
                if mid is None or mid in items._monitored_events.get(node, ()):
                    ev.emitting_node = node
                    await items.trigger_event(ev, mid)
        if marks[1] is not None:
            await marks[1].trigger(subscription_id=sub.data.SubscriptionId)
        return []

    def _new(self, c: AlarmChange, source: ua.NodeId) -> Any:
        """An alarm condition event of ``CncAlarmType``, raised."""
        cls: Any = event_objects.DiscreteAlarm
        ev = cls()
        for name, dtype in ev.data_types.items():  # fields typed by a data type's node id
            if isinstance(dtype, ua.NodeId):
                ev.data_types[name] = _BUILT_IN.get(dtype.Identifier, ua.VariantType.Variant)
        ident = condition_name(c.alm_type, c.alm_no, c.axis_no)
        ev.add_property("AlarmIdentifier", ident, ua.VariantType.String)
        ev.add_property("NodeId", None, ua.VariantType.NodeId)  # the ConditionId
        ev.EventType = ua.NodeId(CncId.ALARM_TYPE, self._cnc)
        ev.NodeId = ua.NodeId(f"{c.machine}/Alarms/{c.path}/{ident}", self._ns)
        ev.SourceNode = source
        ev.SourceName = c.machine if c.path == 0 else f"{c.machine}/Channel_{c.path}"
        ev.ConditionName = ident
        ev.ConditionClassId = ua.NodeId(ua.ObjectIds.ProcessConditionClassType)
        ev.ConditionClassName = ua.LocalizedText("ProcessConditionClassType")
        ev.Message = ua.LocalizedText(alarm_text(c.alm_type, c.alm_no, c.msg, c.axis_no))
        ev.Severity = ALARM_SEVERITY
        ev.LastSeverity = ALARM_SEVERITY
        ev.EnabledState = ua.LocalizedText("Enabled")
        setattr(ev, "EnabledState/Id", True)
        ev.AckedState = ua.LocalizedText("Unacknowledged")
        setattr(ev, "AckedState/Id", False)
        ev.Quality = _GOOD
        return ev

    async def _trigger(self, ev: Any, time: float, machine: ua.NodeId) -> None:
        """Send ``ev`` to the subscribers of the machine's object and of the Server object."""
        service = self._server.iserver.subscription_service
        ev.EventId = uuid.uuid4().bytes
        ev.Time = datetime.fromtimestamp(time, UTC)
        ev.ReceiveTime = datetime.now(UTC)
        ev.emitting_node = machine
        await service.trigger_event(ev)
        ev.emitting_node = ua.NodeId(ua.ObjectIds.Server)
        await service.trigger_event(ev)
