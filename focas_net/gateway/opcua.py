"""The gateway's OPC UA server: a :class:`~focas_net.gateway.model.Sink` that shows each machine
as an OPC 40502 ``CncInterfaceType`` object (:mod:`focas_net.gateway._opcua_model` builds it),
its alarms as alarm conditions, and, when the configuration allows writes, the write methods.

The poller calls :meth:`OpcUaSink.described`, :meth:`~OpcUaSink.online`,
:meth:`~OpcUaSink.samples` and :meth:`~OpcUaSink.alarms` from its own task; each only queues
the change (a bounded queue: past :data:`QUEUE_LIMIT` samples the oldest batches are dropped
and counted) and the sink's task applies it to the address space, writing each variable's
value in place (no network round trip, no deadband: every change is a data change).

Security (``docs/gateway.md``, OPC UA): anonymous sessions only on a loopback endpoint and only
while writes are off; users by name and password; with a certificate and a private key the
Basic256Sha256 Sign and SignAndEncrypt endpoints, and the None endpoint only on the loopback
(an endpoint beyond the loopback without a certificate is refused).
"""

from __future__ import annotations

import asyncio
import hmac
import ipaddress
import logging
import uuid
from collections import deque
from collections.abc import Sequence
from datetime import UTC, datetime
from decimal import Decimal
from types import TracebackType
from typing import Any, Final
from urllib.parse import urlparse

from asyncua import Node, Server, ua
from asyncua.common import event_objects
from asyncua.crypto.permission_rules import User, UserRole
from asyncua.server.internal_server import InternalServer

from focas_net.errors import FocasError, OpcUaStatus
from focas_net.gateway import _opcua_model as om
from focas_net.gateway import _opcua_types as ot
from focas_net.gateway.config import OpcUaSettings
from focas_net.gateway.model import AlarmChange, MachineShape, Sample, Writer
from focas_net.protocol.alarms import alarm_code, alarm_text

__all__ = ["QUEUE_LIMIT", "OpcUaSink"]

log = logging.getLogger(__name__)

#: The most samples queued for the server's task; older batches are dropped (and counted).
QUEUE_LIMIT: Final = 1_000_000
#: The severity of every FANUC alarm condition (OPC UA 1..1000: "high").
ALARM_SEVERITY: Final = 700

_VALUE: Final = ua.AttributeIds.Value
_GOOD: Final = ua.StatusCode(ua.StatusCodes.Good)
_OUT_OF_RANGE: Final = ua.StatusCode(ua.StatusCodes.BadOutOfRange)
_LOST: Final = ua.StatusCode(ua.StatusCodes.BadCommunicationError)
_WAITING: Final = ua.StatusCode(ua.StatusCodes.BadWaitingForInitialData)
_DENIED: Final = ua.StatusCode(ua.StatusCodes.BadUserAccessDenied)
_NULL: Final = ua.Variant(None)
#: The built-in types of the data types asyncua's event fields name by node id.
_BUILT_IN: Final = {
    ua.ObjectIds.UtcTime: ua.VariantType.DateTime,
    ua.ObjectIds.Duration: ua.VariantType.Double,
    ua.ObjectIds.AudioDataType: ua.VariantType.ByteString,
}


def is_loopback(host: str | None) -> bool:
    """True for ``localhost`` and the loopback addresses."""
    if host is None:
        return False
    if host == "localhost":
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False


class _Users:
    """The configuration's users (passwords compared in constant time); anonymous sessions
    when allowed."""

    def __init__(self, settings: OpcUaSettings, anonymous: bool) -> None:
        self._users = {u.name: u.password for u in settings.users}
        self._anonymous = anonymous

    def get_user(
        self,
        iserver: InternalServer,
        username: str | None = None,
        password: str | None = None,
        certificate: Any = None,
    ) -> User | None:
        # only anonymous and user name tokens are offered: no user name is an anonymous session
        # (``certificate`` is then the secure channel's, not an identity)
        if username is None:
            return User(role=UserRole.User) if self._anonymous else None
        if password is None:
            return None
        expected = self._users.get(username)
        if expected is None or not hmac.compare_digest(expected.encode(), password.encode()):
            return None
        return User(role=UserRole.User, name=username)


class _Value(ua.DataValue):  # type: ignore[misc]
    """A DataValue the sink never changes once written: the monitored items may keep it as it
    is instead of deep-copying it for every data change."""

    __slots__ = ()

    def __deepcopy__(self, memo: dict[int, Any]) -> _Value:
        return self


class _Live:
    """A machine's variables as the address space holds them: each sample's targets resolved
    once to the ``AttributeValue`` of their Value attribute, written in place."""

    def __init__(self, server: Server, nodes: om.MachineNodes) -> None:
        aspace = server.iserver.aspace

        def value_of(node: ua.NodeId) -> Any:
            data = aspace.get(node)
            if data is None:
                raise LookupError(f"no node {node}")
            return data.attributes[_VALUE]

        self.slots: dict[tuple[int, str, str], tuple[tuple[Any, ua.VariantType, Any], ...]] = {
            key: tuple((value_of(t.node), t.variant, t.convert) for t in targets)
            for key, targets in nodes.targets.items()
        }
        self.values: list[Any] = [value_of(node) for node in nodes.variables]


async def _notify(att: Any, dv: ua.DataValue) -> None:
    """Tell the monitored items of ``att`` its new value (as the address space's own write
    does, one failing callback not keeping the others from theirs)."""
    for handle, callback in list(att.datachange_callbacks.items()):
        try:
            await callback(handle, dv)
        except Exception:
            log.exception("opcua: a data change callback failed")


class _Alarm:
    """One alarm condition: the event it was raised with (fields change as it moves)."""

    def __init__(self, event: Any) -> None:
        self.event = event


class OpcUaSink:
    """The OPC UA server of the gateway (``async with OpcUaSink(settings, writer) as sink``).

    ``writer`` (None: writes off) serves the write methods, which exist only when
    ``settings.writes`` is true too. Raises ``ValueError`` for settings no client could use
    safely (see the module's docstring).
    """

    def __init__(self, settings: OpcUaSettings, writer: Writer | None = None) -> None:
        url = urlparse(settings.endpoint)
        self._settings = settings
        self._loopback = is_loopback(url.hostname)
        self._writer = writer if settings.writes else None
        if (settings.certificate is None) != (settings.private_key is None):
            raise ValueError("opcua: certificate and private_key come together")
        if not self._loopback and settings.certificate is None:
            raise ValueError(
                f"opcua: the endpoint {settings.endpoint} is beyond the loopback: "
                "it needs certificate and private_key"
            )
        self._anonymous = settings.anonymous and self._loopback and self._writer is None
        if not self._anonymous and not settings.users:
            raise ValueError(
                "opcua: no client could connect: anonymous access is off "
                "(beyond the loopback or with writes on) and there are no users"
            )
        self._server: Server | None = None
        self._ns = 0
        self._cnc = 0
        self._machines: dict[str, om.MachineNodes] = {}
        self._live: dict[str, _Live] = {}
        self._shapes: dict[str, MachineShape] = {}
        self._online: dict[str, bool] = {}
        self._alarms: dict[tuple[str, int, int, int, int], _Alarm] = {}
        self._ops: deque[tuple[str, Any]] = deque()
        self._queued = 0
        self._wake = asyncio.Event()
        self._idle = asyncio.Event()
        self._idle.set()
        self._task: asyncio.Task[None] | None = None
        self._status_cache: dict[int, ua.StatusCode] = {}
        #: Samples dropped because the queue was full.
        self.dropped = 0
        #: Samples written to the address space.
        self.applied = 0

    # --- lifecycle ----------------------------------------------------------------------

    async def __aenter__(self) -> OpcUaSink:
        await self.start()
        return self

    async def __aexit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        await self.stop()

    async def start(self) -> None:
        """Build the server and listen."""
        s = self._settings
        server = Server(user_manager=_Users(s, self._anonymous))
        await server.init()
        server.set_endpoint(s.endpoint)
        server.set_server_name("focas_net gateway")
        await server.set_application_uri(s.namespace)
        policies: list[ua.SecurityPolicyType] = []
        if self._loopback:
            policies.append(ua.SecurityPolicyType.NoSecurity)
        if s.certificate is not None and s.private_key is not None:
            await server.load_certificate(str(s.certificate))
            await server.load_private_key(str(s.private_key))
            policies += [
                ua.SecurityPolicyType.Basic256Sha256_Sign,
                ua.SecurityPolicyType.Basic256Sha256_SignAndEncrypt,
            ]
        server.set_security_policy(policies)
        tokens: list[type] = [ua.AnonymousIdentityToken] if self._anonymous else []
        if s.users:
            tokens.append(ua.UserNameIdentityToken)
        server.set_identity_tokens(tokens)
        self._cnc = await server.register_namespace(ot.CNC_NAMESPACE)
        self._ns = await server.register_namespace(s.namespace)
        items, refs = ot.cnc_type_nodes(self._cnc)
        await self._add(server, items, refs)
        for node, definition in ot.enum_definitions(self._cnc).items():
            await server.get_node(node).write_data_type_definition(definition)
        await server.start()
        self._server = server
        self._task = asyncio.create_task(self._run(), name="opcua-sink")

    async def stop(self) -> None:
        """Stop applying changes and stop the server."""
        if self._task is not None:
            self._task.cancel()
            try:
                await self._task
            except asyncio.CancelledError:
                pass
            self._task = None
        if self._server is not None:
            await self._server.stop()
            self._server = None

    @property
    def port(self) -> int:
        """The port the server listens on."""
        if self._server is None or self._server.bserver is None:
            raise RuntimeError("the OPC UA server is not running")
        return int(self._server.bserver.port)

    @property
    def namespace_index(self) -> int:
        """The index of the gateway's namespace (machines' browse names)."""
        return self._ns

    @property
    def cnc_namespace_index(self) -> int:
        """The index of OPC 40502's namespace."""
        return self._cnc

    async def flush(self) -> None:
        """Return once every change queued so far is applied."""
        while self._ops or not self._idle.is_set():
            self._wake.set()
            await self._idle.wait()

    # --- the Sink interface (the poller's task) -----------------------------------------

    def described(self, shape: MachineShape) -> None:
        self._push("described", shape)

    def online(self, machine: str, online: bool, reason: str, time: float) -> None:
        self._push("online", (machine, online, reason, time))

    def samples(self, samples: Sequence[Sample]) -> None:
        if not samples:
            return
        self._queued += len(samples)
        self._push("samples", samples)
        while self._queued > QUEUE_LIMIT:
            for i, (kind, batch) in enumerate(self._ops):
                if kind == "samples":
                    del self._ops[i]
                    self._queued -= len(batch)
                    self.dropped += len(batch)
                    break
            else:
                break

    def alarms(self, changes: Sequence[AlarmChange]) -> None:
        if changes:
            self._push("alarms", changes)

    def _push(self, kind: str, value: Any) -> None:
        self._ops.append((kind, value))
        self._idle.clear()
        self._wake.set()

    # --- the sink's task ------------------------------------------------------------------

    async def _run(self) -> None:
        while True:
            await self._wake.wait()
            self._wake.clear()
            while self._ops:
                kind, value = self._ops.popleft()
                try:
                    if kind == "samples":
                        self._queued -= len(value)
                        await self.apply_samples(value)
                    elif kind == "described":
                        await self._describe(value)
                    elif kind == "online":
                        await self._set_online(*value)
                    else:
                        await self._apply_alarms(value)
                except asyncio.CancelledError:
                    raise
                except Exception:
                    log.exception("opcua: applying %s failed", kind)
            self._idle.set()

    def _status(self, status: OpcUaStatus) -> ua.StatusCode:
        code = self._status_cache.get(status.value)
        if code is None:
            code = self._status_cache[status.value] = ua.StatusCode(status.value)
        return code

    async def apply_samples(self, samples: Sequence[Sample]) -> None:
        """Write each sample's value (or Bad status) to its variables, stamped with the time
        it was read, and notify their monitored items. The sink's task calls this; it is public
        for the benchmark."""
        machines = self._live
        now = datetime.now(UTC)
        last, stamp = -1.0, now
        for s in samples:
            live = machines.get(s.machine)
            if live is None:
                continue
            slots = live.slots.get((s.path, s.item.name, s.key))
            if slots is None:
                continue
            if s.time != last:
                last, stamp = s.time, datetime.fromtimestamp(s.time, UTC)
            if s.status.value:
                dv = _Value(_NULL, self._status(s.status), stamp, now)
                for att, _, _ in slots:
                    att.value = dv
                    if att.datachange_callbacks:
                        await _notify(att, dv)
            else:
                for att, variant, convert in slots:
                    v = s.value if convert is None else convert(s.value)
                    if v is None:
                        dv = _Value(_NULL, _OUT_OF_RANGE, stamp, now)
                    else:
                        dv = _Value(ua.Variant(v, variant), _GOOD, stamp, now)
                    att.value = dv
                    if att.datachange_callbacks:
                        await _notify(att, dv)
            self.applied += 1

    async def _set_all(self, live: _Live, dv: ua.DataValue) -> None:
        for att in live.values:
            att.value = dv
            if att.datachange_callbacks:
                await _notify(att, dv)

    async def _add(
        self, server: Server, items: list[ua.AddNodesItem], refs: list[ua.AddReferencesItem]
    ) -> None:
        session = server.iserver.isession
        for result in await session.add_nodes(items):
            result.StatusCode.check()
        if refs:
            for status in await session.add_references(refs):
                status.check()

    async def _describe(self, shape: MachineShape) -> None:
        assert self._server is not None
        server = self._server
        if self._shapes.get(shape.name) == shape:
            return
        old = self._machines.pop(shape.name, None)
        self._live.pop(shape.name, None)
        if old is not None:
            await server.delete_nodes([server.get_node(old.root)], recursive=True)
        items, refs, nodes = om.machine_nodes(shape, self._ns, self._cnc)
        refs.append(
            ua.AddReferencesItem(
                SourceNodeId=ua.NodeId(ua.ObjectIds.Server),
                ReferenceTypeId=ua.NodeId(ua.ObjectIds.HasNotifier),
                IsForward=True,
                TargetNodeId=nodes.root,
                TargetNodeClass=ua.NodeClass.Object,
            )
        )
        await self._add(server, items, refs)
        if self._writer is not None:
            await self._add_methods(server.get_node(nodes.root))
        live = _Live(server, nodes)
        await self._set_all(live, _Value(_NULL, _WAITING, None, datetime.now(UTC)))
        self._live[shape.name] = live
        self._machines[shape.name] = nodes
        self._shapes[shape.name] = shape
        self._online[shape.name] = True

    async def _set_online(self, machine: str, online: bool, reason: str, time: float) -> None:
        assert self._server is not None
        nodes = self._machines.get(machine)
        live = self._live.get(machine)
        was = self._online.get(machine)
        self._online[machine] = online
        if nodes is None or live is None or was == online:
            return
        if not online:
            stamp = datetime.fromtimestamp(time, UTC)
            await self._set_all(live, _Value(_NULL, _LOST, stamp, datetime.now(UTC)))
        quality = _GOOD if online else _LOST
        for key, alarm in self._alarms.items():
            if key[0] == machine:
                alarm.event.Quality = quality
                await self._trigger(alarm.event, time, nodes.root)

    # --- alarms -------------------------------------------------------------------------

    async def _apply_alarms(self, changes: Sequence[AlarmChange]) -> None:
        for c in changes:
            nodes = self._machines.get(c.machine)
            if nodes is None:
                continue
            key = (c.machine, c.path, c.alm_type, c.alm_no, c.axis)
            alarm = self._alarms.get(key)
            if c.active:
                if alarm is not None:
                    continue
                alarm = self._alarms[key] = _Alarm(self._new_alarm(c, nodes.root))
            elif alarm is None:
                continue
            else:
                del self._alarms[key]
            ev = alarm.event
            when = datetime.fromtimestamp(c.time, UTC)
            ev.ActiveState = ua.LocalizedText("Active" if c.active else "Inactive")
            setattr(ev, "ActiveState/Id", c.active)
            setattr(ev, "ActiveState/TransitionTime", when)
            ev.Retain = c.active
            await self._trigger(ev, c.time, nodes.root)

    def _new_alarm(self, c: AlarmChange, source: ua.NodeId) -> Any:
        """An alarm condition event of OPC 40502's ``CncAlarmType`` (a DiscreteAlarmType)."""
        cls: Any = event_objects.DiscreteAlarm
        ev = cls()
        for name, dtype in ev.data_types.items():  # fields typed by a data type's node id
            if isinstance(dtype, ua.NodeId):
                ev.data_types[name] = _BUILT_IN.get(dtype.Identifier, ua.VariantType.Variant)
        code = alarm_code(c.alm_type, c.alm_no)
        ident = f"{code}" if not c.axis else f"{code}/{c.axis}"
        ev.add_property("AlarmIdentifier", ident, ua.VariantType.String)
        ev.add_property("NodeId", None, ua.VariantType.NodeId)
        ev.EventType = ua.NodeId(ot.CncId.ALARM_TYPE, self._cnc)
        ev.NodeId = ua.NodeId(f"{c.machine}/Alarms/{c.path}/{ident}", self._ns)
        ev.SourceNode = source
        ev.SourceName = c.machine if c.path == 0 else f"{c.machine}/Channel_{c.path}"
        ev.ConditionName = ident
        ev.ConditionClassId = ua.NodeId(ua.ObjectIds.ProcessConditionClassType)
        ev.ConditionClassName = ua.LocalizedText("ProcessConditionClassType")
        ev.Message = ua.LocalizedText(alarm_text(c.alm_type, c.alm_no, c.message, c.axis))
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
        assert self._server is not None
        service = self._server.iserver.subscription_service
        ev.EventId = uuid.uuid4().bytes
        ev.Time = datetime.fromtimestamp(time, UTC)
        ev.ReceiveTime = datetime.now(UTC)
        ev.emitting_node = machine
        await service.trigger_event(ev)
        ev.emitting_node = ua.NodeId(ua.ObjectIds.Server)
        await service.trigger_event(ev)

    # --- write methods ------------------------------------------------------------------

    async def _add_methods(self, root: Node) -> None:
        def arg(name: str, dtype: int, text: str) -> ua.Argument:
            return ua.Argument(
                Name=name,
                DataType=ua.NodeId(dtype),
                ValueRank=-1,
                Description=ua.LocalizedText(text),
            )

        i32, dbl, txt = ua.ObjectIds.Int32, ua.ObjectIds.Double, ua.ObjectIds.String
        methods = (
            (
                "WriteMacro",
                self._write_macro,
                [
                    arg("Number", i32, "macro variable number"),
                    arg("Value", dbl, "value"),
                    arg("Path", i32, "path (channel) number"),
                ],
            ),
            (
                "WriteParameter",
                self._write_param,
                [
                    arg("Number", i32, "parameter number"),
                    arg("Axis", i32, "axis number, 0 for a parameter of no axis"),
                    arg("Value", i32, "value"),
                ],
            ),
            (
                "WritePmc",
                self._write_pmc,
                [
                    arg("Area", txt, "PMC area letter (G, R, D, ...)"),
                    arg("Address", i32, "byte address"),
                    arg("Value", i32, "byte value 0..255"),
                ],
            ),
        )
        for name, func, args in methods:
            nid = ua.NodeId(f"{root.nodeid.Identifier}/{name}", self._ns)
            await root.add_method(nid, ua.QualifiedName(name, self._ns), func, args, [])

    def _machine_of(self, parent: ua.NodeId) -> str:
        for name, nodes in self._machines.items():
            if nodes.root == parent:
                return name
        raise LookupError(parent)

    async def _call(self, parent: ua.NodeId, call: Any) -> ua.StatusCode | list[ua.Variant]:
        try:
            machine = self._machine_of(parent)
            await call(machine)
        except LookupError:
            return ua.StatusCode(ua.StatusCodes.BadNodeIdUnknown)
        except PermissionError:
            return _DENIED
        except (FocasError, ValueError, TypeError) as exc:
            status = getattr(exc, "opcua_status", None)
            if isinstance(status, OpcUaStatus):
                return ua.StatusCode(status.value)
            return ua.StatusCode(ua.StatusCodes.BadInvalidArgument)
        return []

    async def _write_macro(
        self, parent: ua.NodeId, number: ua.Variant, value: ua.Variant, path: ua.Variant
    ) -> ua.StatusCode | list[ua.Variant]:
        writer = self._writer
        assert writer is not None
        decimal = Decimal(repr(float(value.Value)))
        return await self._call(
            parent, lambda m: writer.write_macro(m, int(number.Value), decimal, int(path.Value))
        )

    async def _write_param(
        self, parent: ua.NodeId, number: ua.Variant, axis: ua.Variant, value: ua.Variant
    ) -> ua.StatusCode | list[ua.Variant]:
        writer = self._writer
        assert writer is not None
        return await self._call(
            parent,
            lambda m: writer.write_param(m, int(number.Value), int(value.Value), int(axis.Value)),
        )

    async def _write_pmc(
        self, parent: ua.NodeId, area: ua.Variant, address: ua.Variant, value: ua.Variant
    ) -> ua.StatusCode | list[ua.Variant]:
        writer = self._writer
        assert writer is not None
        return await self._call(
            parent,
            lambda m: writer.write_pmc(m, str(area.Value), int(address.Value), int(value.Value)),
        )
