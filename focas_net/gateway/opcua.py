"""The gateway's OPC UA server: a :class:`~focas_net.gateway.model.Sink` that shows each machine
as an OPC 40502 ``CncInterfaceType`` object (:mod:`focas_net.gateway._opcua_model` builds it),
its alarms as alarm conditions, and, when the configuration allows writes, the write methods.

The poller calls :meth:`OpcUaSink.described`, :meth:`~OpcUaSink.online`,
:meth:`~OpcUaSink.samples` and :meth:`~OpcUaSink.alarms` from its own task; each only queues
the change and the sink's task applies it to the address space, writing each variable's value
in place (no network round trip, no deadband: every change is a data change). While the task
is behind, each variable keeps only its newest sample waiting (a newer one replaces it, counted
in :attr:`OpcUaSink.coalesced`): no sample is ever dropped, since the poller sends changes only
and a dropped one would leave a stale value, and the queue is bounded by the number of
variables.

Security (``docs/gateway.md``, OPC UA): anonymous sessions only on a loopback endpoint and only
while writes are off; users by name and password; with a certificate and a private key the
Basic256Sha256 Sign and SignAndEncrypt endpoints, and the None endpoint only on the loopback
(an endpoint beyond the loopback without a certificate is refused).
"""

from __future__ import annotations

import asyncio
import contextlib
import gc
import logging
import math
from collections import deque
from collections.abc import Awaitable, Callable, Iterator, Sequence
from datetime import UTC, datetime
from pathlib import Path
from types import TracebackType
from typing import Any, Final

from asyncua import Server, ua

from focas_net._tls import pem_holds
from focas_net._typed import os_words
from focas_net.errors import OpcUaStatus
from focas_net.gateway import _opcua_model as om
from focas_net.gateway import _opcua_types as ot
from focas_net.gateway._keys import ConfigError
from focas_net.gateway._opcua_conditions import Conditions
from focas_net.gateway._opcua_methods import add_write_methods
from focas_net.gateway._opcua_sessions import SESSION_LOGGERS, RefusedSessions, Users
from focas_net.gateway.config import OpcUaSettings, is_loopback, with_port
from focas_net.gateway.model import AlarmChange, MachineShape, Sample, Writer

__all__ = ["OpcUaSink", "is_loopback"]

log = logging.getLogger(__name__)

#: What the OPC UA server's own log says while it starts that this module tells in its own
#: words: a port it cannot listen on (the caller's error names it, without a traceback) and
#: passwords without encryption (warned above, saying what to give).
_TOLD: Final = ("error starting server", "No encrypting policy available")


class _Told(logging.Filter):
    def filter(self, record: logging.LogRecord) -> bool:
        return not any(t in str(record.msg) for t in _TOLD)


@contextlib.contextmanager
def _told_by_us() -> Iterator[None]:
    """Leave out of the OPC UA server's log, while it starts, what this module tells itself."""
    logger, told = logging.getLogger("asyncua.server.server"), _Told()
    logger.addFilter(told)
    try:
        yield
    finally:
        logger.removeFilter(told)


async def _load(load: Callable[..., Awaitable[Any]], key: str, path: Path) -> None:
    """``load`` (the server's loader of a certificate or a private key) of ``path``, PEM or
    DER by what the file holds (asyncua goes by the name's ending, so that a PEM
    ``server.crt`` would be read as DER); a file it cannot read is a :class:`ConfigError`
    naming the key and the file, in the words of the file's other checks
    (``opcua.certificate: ...``) and of the command line's ``--tls-cert``."""
    what = "a certificate" if key == "certificate" else "a private key"
    label = "CERTIFICATE" if key == "certificate" else "PRIVATE KEY"
    try:
        content = await asyncio.to_thread(path.read_bytes)
    except OSError as exc:
        why = os_words(exc)
    else:
        pem = b"-----BEGIN " in content
        try:
            await load(content, format="pem" if pem else "der")
            return
        except Exception as exc:  # (cryptography's ValueError, asyncua's own)
            if pem and not pem_holds(str(path), label):
                why = f"no PEM {label.lower()} in it"
            elif not pem:
                why = "it is neither"
            else:
                why = " ".join(str(exc).split(" See http")[0].split()) or type(exc).__name__
    raise ConfigError(f"opcua.{key}: got {str(path)!r}; expected {what} in PEM or DER ({why})")


#: Nodes added, or samples applied, between two turns of the event loop: the server's work
#: comes in slices of a few milliseconds, so the poller's reads are never held up for long.
CHUNK: Final = 64

_VALUE: Final = ua.AttributeIds.Value
_GOOD: Final = ua.StatusCode(ua.StatusCodes.Good)
_OUT_OF_RANGE: Final = ua.StatusCode(ua.StatusCodes.BadOutOfRange)
_LOST: Final = ua.StatusCode(ua.StatusCodes.BadCommunicationError)
_WAITING: Final = ua.StatusCode(ua.StatusCodes.BadWaitingForInitialData)
_NULL: Final = ua.Variant(None)

#: A variable's samples: machine, path, item and key (axis or spindle).
_Key = tuple[str, int, str, str]


class _Value(ua.DataValue):  # type: ignore[misc]
    """A DataValue the sink never changes once written: the monitored items may keep it as it
    is instead of deep-copying it for every data change."""

    __slots__ = ()

    def __deepcopy__(self, memo: dict[int, Any]) -> _Value:
        return self


class _Live:
    """A machine's variables as the address space holds them: each sample's targets resolved
    once to the ``AttributeValue`` of their Value attribute, written in place."""

    def __init__(self, server: Server, nodes: om.MachineNodes, position_cls: Any) -> None:
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
        structs: dict[ua.NodeId, _Position] = {}
        for fields in nodes.positions.values():
            for node, index in fields:
                if node not in structs:
                    structs[node] = _Position(value_of(node), position_cls)
                structs[node].sourced.add(index)
        self.structs = list(structs.values())
        for p in self.structs:
            p.lose(_WAITING)  # (its value is made when read: no write of it to keep)
        self.positions: dict[tuple[int, str, str], tuple[tuple[_Position, int], ...]] = {
            key: tuple((structs[node], index) for node, index in fields)
            for key, fields in nodes.positions.items()
        }


class _Position:
    """The ``CncPositionDataType`` value of one ``CncPositionVariableType`` variable, made of
    the parts its samples give (CmdPos, which FOCAS does not read, is NaN): Good once every part
    it has a source for is Good, else the status of a part that is not. The value is made when
    it is read, or at once for the variable's monitored items."""

    __slots__ = ("att", "bad", "cls", "now", "sourced", "stamp", "values")

    def __init__(self, att: Any, cls: Any) -> None:
        self.att, self.cls = att, cls
        self.values = [math.nan] * len(ot.POSITION_FIELDS)
        self.sourced: set[int] = set()
        self.bad: dict[int, ua.StatusCode] = {}
        self.stamp: datetime | None = None
        self.now: datetime | None = None
        att.value_callback = self.current

    def lose(self, status: ua.StatusCode, stamp: datetime | None = None) -> None:
        self.bad = dict.fromkeys(self.sourced, status)
        self.stamp, self.now = stamp, datetime.now(UTC)

    def current(self, nodeid: Any = None, attr: Any = None) -> ua.DataValue:
        if self.bad:
            return _Value(_NULL, next(iter(self.bad.values())), self.stamp, self.now)
        variant = ua.Variant(self.cls(*self.values), ua.VariantType.ExtensionObject)
        return _Value(variant, _GOOD, self.stamp, self.now)


async def _notify(att: Any, dv: ua.DataValue) -> None:
    """Tell the monitored items of ``att`` its new value (as the address space's own write
    does, one failing callback not keeping the others from theirs)."""
    for handle, callback in list(att.datachange_callbacks.items()):
        try:
            await callback(handle, dv)
        except Exception:
            log.exception("opcua: a data change callback failed")


class OpcUaSink:
    """The OPC UA server of the gateway (``async with OpcUaSink(settings, writer) as sink``).

    ``writer`` (None: writes off) serves the write methods, which exist only when
    ``settings.writes`` is true too. A sample waiting for the server's task is replaced by a
    newer one of the same variable (counted in :attr:`coalesced`), never dropped. Raises
    :class:`~focas_net.gateway.config.ConfigError` (a ``ValueError``) for settings no client
    could use safely: :meth:`OpcUaSettings.check <focas_net.gateway.config.OpcUaSettings.check>`,
    the file's own check.
    """

    def __init__(
        self,
        settings: OpcUaSettings,
        writer: Writer | None = None,
    ) -> None:
        if not isinstance(settings, OpcUaSettings):
            raise TypeError(f"settings must be an OpcUaSettings, got {settings!r}")
        settings.check()
        self._settings = settings
        self._loopback = settings.loopback
        self._writer = writer if settings.writes else None
        self._anonymous = settings.anonymous_sessions
        self._server: Server | None = None
        self._refused = RefusedSessions()
        self._ns = 0
        self._cnc = 0
        self._machines: dict[str, om.MachineNodes] = {}
        self._live: dict[str, _Live] = {}
        self._shapes: dict[str, MachineShape] = {}
        self._online: dict[str, bool] = {}
        self._alarm_conditions: Conditions | None = None
        self._ops: deque[tuple[str, Any]] = deque()
        #: The variable of each sample waiting, and the run of samples in _ops holding it.
        self._waiting: dict[_Key, dict[_Key, Sample]] = {}
        self._wake = asyncio.Event()
        self._idle = asyncio.Event()
        self._idle.set()
        self._task: asyncio.Task[None] | None = None
        self._status_cache: dict[int, ua.StatusCode] = {}
        self._position_cls: Any = None
        #: Samples replaced, while waiting, by a newer sample of the same variable.
        self.coalesced = 0
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
        server = Server(user_manager=Users(s, self._anonymous))
        # ConditionRefresh (and ConditionRefresh2) of ConditionType send the retained
        # conditions again; asyncua binds them only when asked
        server.iserver.bind_condition_methods = True
        await server.init()
        server.set_endpoint(s.endpoint)
        server.set_server_name("focas_net gateway")
        await server.set_application_uri(s.namespace)
        policies: list[ua.SecurityPolicyType] = []
        if self._loopback:
            policies.append(ua.SecurityPolicyType.NoSecurity)
        if s.certificate is not None and s.private_key is not None:
            await _load(server.load_certificate, "certificate", s.certificate)
            await _load(server.load_private_key, "private_key", s.private_key)
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
        made = await server.load_data_type_definitions()
        self._position_cls = made.get("CncPositionDataType") or ua.CncPositionDataType
        with _told_by_us():
            await server.start()
        for name in SESSION_LOGGERS:
            logging.getLogger(name).addFilter(self._refused)
        gc.freeze()  # the standard address space, for good (see _describe)
        self._server = server
        if s.users and s.certificate is None:  # (named with the port it took: port 0 asks any)
            log.warning(
                "OPC UA %s: users' passwords travel unencrypted on this endpoint (give "
                "certificate and private_key to encrypt them)",
                with_port(s.endpoint, self.port),
            )
        self._alarm_conditions = Conditions(server, self._ns, self._cnc)
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
            for name in SESSION_LOGGERS:
                logging.getLogger(name).removeFilter(self._refused)

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
        if self._task is None:
            raise RuntimeError("the OPC UA server is not running")
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
        # The samples join the run of samples at the end of the queue (a new run after any
        # other change, which keeps its place between them); a variable's older sample still
        # waiting, in this run or an earlier one, is replaced.
        run: dict[_Key, Sample] | None = None
        if self._ops and self._ops[-1][0] == "samples":
            run = self._ops[-1][1]
        if run is None:
            run = {}
            self._push("samples", run)
        waiting = self._waiting
        for s in samples:
            key = (s.machine, s.path, s.item.name, s.key)
            held = waiting.get(key)
            if held is not None:
                self.coalesced += 1
                if held is not run:
                    del held[key]
            run[key] = s
            waiting[key] = run
        self._wake.set()

    @property
    def pending(self) -> int:
        """Samples waiting for the server's task (at most one per variable)."""
        return len(self._waiting)

    def alarms(self, changes: Sequence[AlarmChange]) -> None:
        if changes:
            self._push("alarms", tuple(changes))

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
                        for key in value:
                            del self._waiting[key]
                        if value:
                            await self.apply_samples(list(value.values()))
                    elif kind == "described":
                        await self._describe(value)
                    elif kind == "online":
                        await self._set_online(*value)
                    else:
                        await self._conditions().apply(
                            value, {name: nodes.root for name, nodes in self._machines.items()}
                        )
                except asyncio.CancelledError:
                    raise
                except Exception:
                    log.exception("opcua: applying %s failed", kind)
                await asyncio.sleep(0)  # the poller's task runs between two changes
            self._idle.set()

    def _conditions(self) -> Conditions:
        if self._alarm_conditions is None:
            raise RuntimeError("the OPC UA server is not running")
        return self._alarm_conditions

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
        for i, s in enumerate(samples):
            if i and not i % (16 * CHUNK):
                await asyncio.sleep(0)
            live = machines.get(s.machine)
            if live is None:
                continue
            key = (s.path, s.item.name, s.key)
            slots = live.slots.get(key)
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
            fields = live.positions.get(key)
            if fields is not None:
                await self._put_positions(fields, s, stamp, now)
            self.applied += 1

    async def _put_positions(
        self,
        fields: tuple[tuple[_Position, int], ...],
        s: Sample,
        stamp: datetime,
        now: datetime,
    ) -> None:
        for p, index in fields:
            if s.status.value:
                p.bad[index] = self._status(s.status)
            elif s.value is None or isinstance(s.value, str):
                p.bad[index] = _OUT_OF_RANGE
            else:
                p.values[index] = float(s.value)
                p.bad.pop(index, None)
            p.stamp, p.now = stamp, now
            if p.att.datachange_callbacks:
                await _notify(p.att, p.current())

    async def _set_all(self, live: _Live, dv: ua.DataValue) -> None:
        for att in live.values:
            att.value = dv
            if att.datachange_callbacks:
                await _notify(att, dv)

    async def _add(
        self, server: Server, items: list[ua.AddNodesItem], refs: list[ua.AddReferencesItem]
    ) -> None:
        session = server.iserver.isession
        for first in range(0, len(items), CHUNK):
            for result in await session.add_nodes(items[first : first + CHUNK]):
                result.StatusCode.check()
            await asyncio.sleep(0)  # (a machine's nodes take tens of ms: let the poller run)
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
            await add_write_methods(server.get_node(nodes.root), self._ns, self._writer, shape.name)
        # The address space's nodes (tens of thousands of objects a machine) live as long as the
        # server: taken out of the collector's generations, they no longer make every full
        # collection scan them (which took most of a machine's build and held the loop for up
        # to a second with 50 machines).
        gc.freeze()
        live = _Live(server, nodes, self._position_cls)
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
            for p in live.structs:
                p.lose(_LOST, stamp)
            await self._set_all(live, _Value(_NULL, _LOST, stamp, datetime.now(UTC)))
        await self._conditions().quality(machine, _GOOD if online else _LOST, time, nodes.root)
