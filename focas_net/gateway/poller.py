"""The poll loop: :class:`Poller` reads many machines from one task and hands every change to
the sinks.

**Groups.** Each machine has three intervals
(:class:`~focas_net.gateway.config.GroupIntervals`): the fast group, the slow group and the
active alarm list. One scheduler (a heap of the due times, in the poller's one task; a turn
looks only at what is due and at the machines whose connection changed) starts, at each turn,
every read that is due on every machine (:class:`~focas_net.gateway.reads.Reader`), each client
sending at once what it can (a native client packs the calls queued together into frames of up
to ten blocks), then takes the answers in the order they come (:meth:`StartedCall.on_done`).
There is no task per machine and none per value; a group of a machine is not started again
while its last reads are still out, so a machine that answers slowly (or not: every call has
the machine's ``timeout``) delays nobody else.

**Change detection.** A sample goes to the sinks only when its value or its status differs
from the last one sent; after a machine comes (back) online every value is sent once, and the
items its transport cannot read once, BadNotSupported. An EW code on one read gives its items
the EW's status; the other reads deliver.

**Staggering.** The machines' polls are spread evenly over each interval: the k-th of n
machines (in the configuration's order) is first read, once online, k/n of each group's
interval after it came online, and every interval after that, so that 1,000 machines coming
online together are not read in one burst (nor every slow group in one turn), however often
they come back together.

**Connections.** Each client has the poller's :class:`ReconnectPolicy`: a connection lost
after it was up is opened again by the client itself; a first connection that fails is tried
again by the poller after the policy's delays, in a short task of its own that also reads the
machine's shape (:func:`~focas_net.gateway.reads.describe`). A machine is online from the turn
after its shape was read (``described`` to the sinks the first time and whenever it changed,
then ``online(True)``) until a read fails for want of a connection (refused, reset, closed, no
answer in time) or its client is found reconnecting: then ``online(False, reason)`` and
nothing more of it until it is back, but ``online(False, reason)`` again when an attempt fails
for another reason than the one told (the outputs show the current one). A read answered
EW_SOCKET or EW_HANDLE (the handle is dead) is a lost connection too, as FANUC's practice has
it: the client is closed (the handle freed) and a new one connects after the policy's delay.

**Alarms.** Each path's active alarm list is diffed with the last one
(:func:`~focas_net.client.alarm_changes`, the logic of :class:`AlarmProjection`) into
:class:`AlarmChange` events; the list is kept across an outage, so an alarm that cleared
meanwhile is told as cleared.

Time is two injected clocks: ``clock`` (seconds since the epoch by default) gives the samples'
times, ``timer`` (``time.monotonic`` by default) the due times, so that the wall clock set back
(an edge box's first NTP sync, a daylight-saving mistake) never holds the polls back. Tests
step the poller by hand (:meth:`Poller.step`) on a clock they move, which is then both.
"""

from __future__ import annotations

import asyncio
import contextlib
import heapq
import itertools
import logging
import math
import socket
import time
from collections import deque
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from functools import partial
from types import TracebackType
from typing import Any, Final, Self

from focas_net.client import (
    ClientState,
    FocasClient,
    NativeClient,
    NativeUnsupportedError,
    ReconnectPolicy,
    alarm_changes,
)
from focas_net.client._probes import GATEWAY, diagnosed
from focas_net.errors import (
    EW,
    OPCUA_GOOD,
    CncError,
    FocasError,
    FocasTimeoutError,
    OpcUaStatus,
    ProtocolError,
)
from focas_net.protocol import ActiveAlarm

from .config import MachineConfig
from .model import ITEMS, AlarmChange, Group, MachineShape, Sample, Sink, Value
from .reads import NOT_SUPPORTED, Key, Outcome, Read, Reader, Unavailable, describe

__all__ = ["DEFAULT_POLICY", "Client", "Poller", "client_for", "reason_of"]

_log = logging.getLogger(__name__)

#: The reconnect policy of the poller's clients unless it is given one.
DEFAULT_POLICY: Final = ReconnectPolicy(initial_delay=0.5, max_delay=30.0)
#: A client of either transport.
Client = FocasClient | NativeClient
_ALARMS: Final = "alarms"
_CONNECT: Final = "connect"  # (a heap entry: try to connect again)
_GROUPS: Final = (Group.FAST.value, Group.SLOW.value, _ALARMS)
#: The status of the items of an answer that could not be converted.
_UNDECODED: Final = ProtocolError.opcua_status


def reason_of(exc: BaseException) -> str:
    """Why a machine was lost, in a word and the error's text: ``refused``, ``timeout``,
    ``reset``, ``closed``, ``protocol``, ``unreachable``, ``unresolved`` (its host name has
    no address) or ``lost``."""
    text = " ".join(str(exc).split()) or type(exc).__name__
    if isinstance(exc, FocasTimeoutError | TimeoutError):
        return f"timeout: {text}"
    if isinstance(exc.__cause__ or exc, socket.gaierror):
        return f"unresolved: {text}"
    if isinstance(exc, ProtocolError):
        return f"protocol: {text}"
    low = text.lower()
    for word in ("refused", "timed out", "reset", "closed", "unreachable"):
        if word in low:
            return f"{'timeout' if word == 'timed out' else word}: {text}"
    return f"lost: {text}"


def client_for(config: MachineConfig, policy: ReconnectPolicy) -> Client:
    """The client of ``config`` (its protocol, host, port and timeout) with ``policy``."""
    if config.protocol == "native":
        return NativeClient(config.host, config.port, timeout=config.timeout, reconnect=policy)
    return FocasClient(config.host, config.port, timeout=config.timeout, reconnect=policy)


@dataclass(eq=False, slots=True)
class _Station:
    """One machine as the poller follows it."""

    config: MachineConfig
    client: Client
    phase: float = 0.0  # where in each interval its groups fall (0 <= phase < 1)
    reader: Reader | None = None
    described: MachineShape | None = None
    online: bool | None = None
    reached: bool = False  # whether it was ever online (a loss, else unavailable)
    failure: str | None = None
    told: str | None = None  # the loss last announced (None: none since it was online)
    task: asyncio.Task[None] | None = None
    attempts: int = 0
    next_attempt: float = 0.0
    epoch: int = 0
    due: dict[str, float] = field(default_factory=dict)
    pending: dict[str, int] = field(default_factory=dict)
    last: dict[Key, tuple[Value, OpcUaStatus]] = field(default_factory=dict)
    results: dict[Key, object] = field(default_factory=dict)  # the last result of each read
    alarms: dict[int, dict[tuple[int, int, int], ActiveAlarm]] = field(default_factory=dict)

    def interval(self, group: str) -> float:
        g = self.config.groups
        return {"fast": g.fast, "slow": g.slow, _ALARMS: g.alarms}[group]


@dataclass(eq=False, slots=True)
class _Out:
    """A read under way: its station, the station's epoch when it started, its group."""

    station: _Station
    epoch: int
    group: str
    read: Read | None = None
    path: int = 0
    alarms: Any = None  # the StartedCall of an alarm list


class Poller:
    """Reads ``machines`` and tells ``sinks`` (see the module docstring).

    ``clock`` gives the samples' times (seconds since the epoch), ``timer`` the due times (by
    default ``time.monotonic`` with the default ``clock``, else ``clock`` itself); ``policy`` is
    every client's reconnect policy and the delays between first connection attempts;
    ``client_of(config, policy)`` builds a machine's client (by default a
    :class:`NativeClient` or a :class:`FocasClient` as its ``protocol`` says).

    Use it as an async context manager (its clients are closed on leaving), then
    :meth:`run` it, or :meth:`step` it by hand.
    """

    def __init__(
        self,
        machines: Sequence[MachineConfig],
        sinks: Sequence[Sink],
        *,
        clock: Callable[[], float] = time.time,
        timer: Callable[[], float] | None = None,
        policy: ReconnectPolicy = DEFAULT_POLICY,
        client_of: Callable[[MachineConfig, ReconnectPolicy], Client] = client_for,
    ) -> None:
        names = [m.name for m in machines]
        if len(set(names)) != len(names):
            raise ValueError("machine names must be unique")
        self.sinks = list(sinks)
        self.clock = clock
        self.timer = timer if timer is not None else _timer_of(clock)
        self.policy = policy
        self._client_of = client_of
        count = len(machines)
        self._stations = {
            m.name: _Station(m, client_of(m, policy), phase=i / count)
            for i, m in enumerate(machines)
        }
        for st in self._stations.values():
            st.client.add_state_callback(partial(self._state_changed, st))
        self._freeing: set[asyncio.Task[None]] = set()  # clients of dead handles, closing
        self._heap: list[tuple[float, int, _Station, str, int]] = []
        self._order = itertools.count()  # (ties in the heap never compare stations)
        self._dirty: set[_Station] = set(self._stations.values())
        self._ready: deque[_Out] = deque()
        self._wake = asyncio.Event()
        self._outs: set[_Out] = set()  # the reads under way
        self._closed = False

    # -- what others read ----------------------------------------------------------------
    @property
    def machines(self) -> tuple[str, ...]:
        """The names of the machines, in the configuration's order."""
        return tuple(self._stations)

    def client(self, machine: str) -> Client:
        """The client of ``machine`` (``KeyError`` naming it for an unknown one)."""
        return self._station(machine).client

    def config(self, machine: str) -> MachineConfig:
        """The configuration of ``machine``."""
        return self._station(machine).config

    def shape(self, machine: str) -> MachineShape | None:
        """The shape last described of ``machine`` (None before its first connection)."""
        return self._station(machine).described

    def is_online(self, machine: str) -> bool | None:
        """Whether ``machine`` is online (None: not known yet)."""
        return self._station(machine).online

    def _station(self, machine: str) -> _Station:
        try:
            return self._stations[machine]
        except KeyError:
            raise KeyError(f"no machine {machine!r} in the configuration") from None

    # -- lifecycle -----------------------------------------------------------------------
    async def __aenter__(self) -> Self:
        return self

    async def __aexit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        await self.aclose()

    @property
    def closed(self) -> bool:
        """Whether :meth:`aclose` was called: the poller polls no more."""
        return self._closed

    async def aclose(self) -> None:
        """Give up the reads under way, stop connecting and close every client."""
        self._closed = True
        for out in self._outs:
            (out.alarms if out.read is None else out.read.call).cancel()
        self._outs.clear()
        self._ready.clear()
        tasks = [s.task for s in self._stations.values() if s.task is not None]
        for task in tasks:
            task.cancel()
        if tasks:
            await asyncio.gather(*tasks, return_exceptions=True)
        await asyncio.gather(
            *(s.client.aclose() for s in self._stations.values()),
            *self._freeing,
            return_exceptions=True,
        )

    async def run(self) -> None:
        """Poll until cancelled: each turn starts what is due, takes the answers as they come
        and sleeps (real time) until the next due time, the next answer or a client's change
        of state."""
        while not self._closed:
            self._wake.clear()
            await self._drain()  # first: what is still out counts in the due times
            due = self._turn()
            if self._ready or self._wake.is_set():
                continue
            with contextlib.suppress(TimeoutError):
                async with asyncio.timeout(max(0.0, due - self.timer())):
                    await self._wake.wait()

    async def step(self) -> float:
        """One turn by hand: start what is due at ``clock()`` (connections too), then take
        every answer of every read out (each ends by its timeout). Returns when the next
        read is due."""
        due = self._turn()
        while self._outs:
            self._wake.clear()
            if not self._ready:
                await self._wake.wait()
            await self._drain()
        return due

    # -- a turn --------------------------------------------------------------------------
    def _turn(self) -> float:
        """The machines whose connection changed (announced), then the groups due (started);
        the next due time. Only what changed or is due is looked at: the turn costs what it
        does, not the number of machines."""
        now = self.timer()
        heap = self._heap
        due: list[tuple[_Station, str]] = []
        while heap and heap[0][0] <= now:
            _, _, st, group, epoch = heapq.heappop(heap)
            if epoch != st.epoch:
                continue  # of a connection since lost
            if group == _CONNECT:
                self._dirty.add(st)
            else:
                due.append((st, group))
        samples: list[Sample] = []
        online: list[tuple[str, bool, str]] = []
        described: list[MachineShape] = []
        dirty, self._dirty = self._dirty, set()
        for st in dirty:
            self._follow(st, now, samples, online, described)
        self._tell(described, online, samples, [])
        for st, group in due:
            if not st.online or st.reader is None or st.pending.get(group, 0):
                continue  # (reads still out: the last of them brings the group back)
            self._start(st, group)
            at = max(st.due.get(group, now) + st.interval(group), now)
            st.due[group] = at
            if not st.pending.get(group, 0):
                self._push(at, st, group)  # (nothing to read: due again all the same)
        return heap[0][0] if heap else now + 3600.0

    def _push(self, at: float, st: _Station, group: str) -> None:
        heapq.heappush(self._heap, (at, next(self._order), st, group, st.epoch))

    def _follow(
        self,
        st: _Station,
        now: float,
        samples: list[Sample],
        online: list[tuple[str, bool, str]],
        described: list[MachineShape],
    ) -> None:
        """Where ``st`` stands: announce what changed, start connecting when it is time."""
        state = st.client.state
        if st.reader is not None and state is ClientState.CONNECTED and st.failure is None:
            if st.online is not True:
                shape = st.reader.shape
                if shape != st.described:
                    st.described = shape
                    described.append(shape)
                st.online = st.reached = True
                st.last.clear()
                st.results.clear()
                st.due.clear()
                for group in _GROUPS:
                    self._push(now + st.phase * st.interval(group), st, group)
                st.told = None
                online.append((st.config.name, True, ""))
                stamp = self.clock()
                samples.extend(
                    self._sample(st, key, None, NOT_SUPPORTED, stamp)
                    for key in st.reader.unsupported()
                )
            return
        if state is not ClientState.CONNECTED:
            st.reader = None
        if st.online is True and state is not ClientState.CONNECTED:
            # why the client lost its connection, as a failed read would say it
            why = st.client.lost_reason
            told = reason_of(why) if why is not None else f"lost: the connection is {state.value}"
            st.failure = st.failure or told
        elif st.online is False and state is ClientState.RECONNECTING:
            attempt = st.client.reconnect_error  # (the client's own attempt, failed since)
            st.failure = reason_of(attempt) if attempt is not None else st.failure
        if st.failure is not None and st.failure != st.told:
            # lost, or lost again for another reason than the one told: the current one
            if st.online is not False:
                self._lose(st)
            st.told = st.failure
            online.append((st.config.name, False, st.failure))
        if st.task is not None or self._closed:
            return
        if state is ClientState.RECONNECTING:
            # (the client reconnects: its change of state brings it back here; meanwhile its
            # attempts' failures are looked at once each alarm interval, to tell the current)
            self._push(now + st.interval(_ALARMS), st, _CONNECT)
            return
        if now >= st.next_attempt:
            st.reader = None
            st.task = asyncio.get_running_loop().create_task(
                self._connect(st), name=f"gateway connect {st.config.name}"
            )
        else:
            self._push(st.next_attempt, st, _CONNECT)

    def _lose(self, st: _Station) -> None:
        st.online = False
        st.reader = None
        st.epoch += 1
        st.last.clear()
        st.results.clear()

    def _renew(self, st: _Station) -> None:
        """Close ``st``'s client (its handle is dead) and give it a new one, connected after
        the policy's delay."""
        old = st.client
        st.client = self._client_of(st.config, self.policy)
        st.client.add_state_callback(partial(self._state_changed, st))
        st.next_attempt = self.timer() + self.policy.delay(st.attempts)
        st.attempts += 1
        task = asyncio.get_running_loop().create_task(
            old.aclose(), name=f"gateway free {st.config.name}"
        )
        self._freeing.add(task)
        task.add_done_callback(self._freeing.discard)

    async def _connect(self, st: _Station) -> None:
        """Connect (unless connected) and read the shape; a failure is kept for the turn to
        announce, with the time of the next attempt."""
        try:
            if st.client.state is not ClientState.CONNECTED:
                await st.client.connect()
            reader = await describe(st.config, st.client)
        except Exception as exc:  # (any failure: tried again after the policy's delay)
            # a port that said nothing may be an HTTP server, a TLS port, a port of FOCAS/2
            # alone..., on any attempt (one that took the port after a refusal or a loss too):
            # asked as the command line asks it, with the advice in the file's keys. The probes
            # are asked only of a peer that said nothing, and cost an HTTP server well under a
            # millisecond, a silent peer at most min(timeout, PROBE_TIMEOUT) each, no longer
            # than the failed attempt itself waited (docs/gateway.md)
            c = st.config
            told, hint = await diagnosed(
                exc, c.host, c.port, c.protocol, False, c.timeout, wording=GATEWAY
            )
            st.failure = reason_of(told) + ("" if hint is None else f"; {hint}")
            st.next_attempt = self.timer() + self.policy.delay(st.attempts)
            st.attempts += 1
            unexpected = not isinstance(exc, FocasError | OSError)
            _log.log(
                logging.ERROR if unexpected else logging.INFO,
                "%s: %s",
                st.config.name,
                st.failure,
                exc_info=exc if unexpected else None,
            )
        else:
            st.reader, st.failure, st.attempts = reader, None, 0
        finally:
            st.task = None
            self._dirty.add(st)
            self._wake.set()

    def _start(self, st: _Station, group: str) -> None:
        """Start ``group``'s reads of ``st``."""
        reader = st.reader
        assert reader is not None
        outs: list[_Out] = []
        if group == _ALARMS:
            for path, call in reader.alarms():
                outs.append(_Out(st, st.epoch, group, path=path, alarms=call))
        else:
            reads = reader.fast() if group == Group.FAST.value else reader.slow()
            outs.extend(_Out(st, st.epoch, group, read=r) for r in reads)
        st.pending[group] = st.pending.get(group, 0) + len(outs)
        self._outs.update(outs)
        for out in outs:
            call = out.alarms if out.read is None else out.read.call
            call.on_done(partial(self._answered, out))

    def _state_changed(self, st: _Station, _state: ClientState) -> None:
        self._dirty.add(st)
        self._wake.set()

    def _answered(self, out: _Out) -> None:
        self._ready.append(out)
        self._wake.set()

    # -- answers -------------------------------------------------------------------------
    async def _drain(self) -> None:
        """Take every answer that is there; tell the sinks once."""
        samples: list[Sample] = []
        changes: list[AlarmChange] = []
        online: list[tuple[str, bool, str]] = []
        ready = self._ready
        while ready:
            out = ready.popleft()
            self._outs.discard(out)
            st = out.station
            left = st.pending[out.group] = st.pending[out.group] - 1
            if not left and st.online and st.reader is not None:
                self._push(st.due.get(out.group, self.timer()), st, out.group)
            call = out.alarms if out.read is None else out.read.call
            result: Any = None
            error: BaseException | None = None
            try:
                result = await call.result()  # there: no wait (see StartedCall.on_done)
            except Exception as exc:
                error = exc
            if out.epoch != st.epoch:
                continue  # of a connection since lost
            if error is not None and (not _item_error(error) or _handle_dead(error)):
                st.failure = st.told = reason_of(error)
                self._lose(st)
                if _handle_dead(error):
                    self._renew(st)
                self._dirty.add(st)
                online.append((st.config.name, False, st.failure))
                continue
            now = self.clock()
            if out.read is None:
                if error is None:
                    try:
                        changes.extend(self._alarm_changes(st, out.path, result, now))
                    except Exception:  # (an answer that is no alarm list: the list is kept)
                        _log.exception("%s: path %d: alarm list not read", st.config.name, out.path)
                continue
            # A read is known by its first key (each key is one read's). The clients make
            # one result per answer bytes (made once): the same object as last time is the
            # same values, nothing to convert or compare.
            tag = out.read.keys[0] if out.read.keys else None
            if error is None:
                if tag is not None:
                    if st.results.get(tag) is result:
                        continue
                    st.results[tag] = result
                values = _converted(st, out.read, result)
            else:
                if tag is not None:
                    st.results.pop(tag, None)
                status = getattr(error, "opcua_status", NOT_SUPPORTED)
                values = dict.fromkeys(out.read.keys, status)
            for key, value in values.items():
                if isinstance(value, OpcUaStatus):
                    sample = self._changed(st, key, None, value, now)
                else:
                    sample = self._changed(st, key, value, OPCUA_GOOD, now)
                if sample is not None:
                    samples.append(sample)
        self._tell([], online, samples, changes)

    def _changed(
        self, st: _Station, key: Key, value: Value, status: OpcUaStatus, now: float
    ) -> Sample | None:
        last = st.last.get(key)
        if last is not None and last[1] == status and _same(last[0], value):
            return None
        return self._sample(st, key, value, status, now)

    def _sample(
        self, st: _Station, key: Key, value: Value, status: OpcUaStatus, now: float
    ) -> Sample:
        st.last[key] = (value, status)
        path, name, sub = key
        return Sample(st.config.name, path, ITEMS[name], sub, value, status, now)

    def _alarm_changes(
        self, st: _Station, path: int, active: Sequence[ActiveAlarm], now: float
    ) -> list[AlarmChange]:
        cleared, raised, st.alarms[path] = alarm_changes(st.alarms.get(path, {}), active)
        name = st.config.name
        return [
            AlarmChange(name, path, a.alm_type, a.alm_no, a.axis_no, a.msg, on, now)
            for on, alarms in ((False, cleared), (True, raised))
            for a in alarms
        ]

    def _tell(
        self,
        described: list[MachineShape],
        online: list[tuple[str, bool, str]],
        samples: list[Sample],
        changes: list[AlarmChange],
    ) -> None:
        """Hand the sinks what happened, in that order (a sink that raises is logged)."""
        if not (described or online or samples or changes):
            return
        now = self.clock()
        for name, up, reason in online:
            word = "lost" if self._stations[name].reached else "unavailable"
            _log.info("%s: %s", name, "online" if up else f"{word} ({reason})")
        for sink in self.sinks:
            for shape in described:
                _call(sink, "described", shape)
            for name, up, reason in online:
                _call(sink, "online", name, up, reason, now)
            if samples:
                _call(sink, "samples", samples)
            if changes:
                _call(sink, "alarms", changes)


def _item_error(exc: BaseException) -> bool:
    """Whether ``exc`` is of one read (an EW code, a call the transport lacks, an item with
    no value now), not of the connection."""
    return isinstance(exc, CncError | NativeUnsupportedError | Unavailable)


def _handle_dead(exc: BaseException) -> bool:
    """Whether ``exc`` is an EW code that says the connection is gone (EW_SOCKET, EW_HANDLE):
    FANUC's practice is to free the handle and connect again."""
    return isinstance(exc, CncError) and exc.ew in (EW.SOCKET, EW.HANDLE)


def _call(sink: Sink, method: str, *args: Any) -> None:
    """``sink.method(*args)``; what it raises is logged (the sink breaks its contract, the
    poller goes on and the sink's other calls are made)."""
    try:
        getattr(sink, method)(*args)
    except Exception:
        _log.exception("sink %r failed in %s()", sink, method)


def _same(last: Value, value: Value) -> bool:
    """Whether ``value`` is the value sent last: NaN is the same as NaN (it would otherwise be
    sent again on every read), and a value of another type is another value (True is not 1)."""
    if type(last) is not type(value):
        return False
    if isinstance(value, float) and isinstance(last, float) and math.isnan(value):
        return math.isnan(last)
    return last == value


def _converted(st: _Station, read: Read, result: object) -> dict[Key, Outcome]:
    """The values of ``read``'s ``result``; an answer its conversion cannot read (a value out
    of every range the conversion knows) gives its items BadDecodingError, logged."""
    try:
        return read.values(result)
    except Exception:
        _log.exception("%s: an answer for %s not converted", st.config.name, read.keys[:1])
        return dict.fromkeys(read.keys, _UNDECODED)


def _timer_of(clock: Callable[[], float]) -> Callable[[], float]:
    """The due times' clock beside ``clock``: the monotonic clock beside the wall clock, a
    test's clock beside itself."""
    return time.monotonic if clock is time.time else clock
