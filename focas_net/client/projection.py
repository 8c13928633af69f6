"""Alarm projection: turn periodic alarm polls into a stream of typed events.

:class:`AlarmProjection` polls ``cnc_rdalmmsg`` (and, in ``ACTIVE_PLUS_HISTORY`` mode,
``cnc_rdalmhistry``) every ``interval`` seconds and yields:

* :class:`AlarmRaised` / :class:`AlarmCleared` when an alarm enters or leaves the active list;
* :class:`AlarmHistoryEvent` for each history entry not seen before, oldest first,
  deduplicated by ``(occurred_at, alm_no, alm_type)`` across polls and reconnects.

A poll that fails (an error answer, a timeout, a lost connection, a client still
reconnecting) yields nothing and the next tick tries again; the projection's state is only
changed by complete polls. The iteration gives up, raising the error of the poll that failed,
when it cannot make progress any more: when the client is ``DISCONNECTED`` after a failed poll
because its reconnect policy used up its ``max_attempts`` or because the peer broke the wire
protocol (which is never retried), or after ``max_failures`` polls in a row failed (when
given). A client without a reconnect policy that lost its connection is polled on (its owner
may connect it again) unless ``max_failures`` bounds it.

Polling happens inside ``__anext__``: there is no background task, and
:meth:`AlarmProjection.stop` (or leaving ``async with``) ends the iteration at once.
"""

from __future__ import annotations

import asyncio
import enum
import logging
import sys
from collections import deque
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from datetime import datetime
from types import TracebackType
from typing import Final, Self

from focas_net._typed import nan_refused
from focas_net.errors import FocasError, PayloadError, ProtocolError

from ..protocol import ActiveAlarm, AlarmHistoryEntry
from ._values import an_int, check_timeout, history_depth
from .cnc import CncClient
from .reconnect import ClientState

__all__ = [
    "AlarmCleared",
    "AlarmEvent",
    "AlarmHistoryEvent",
    "AlarmProjection",
    "AlarmRaised",
    "ProjectionMode",
    "alarm_changes",
]

logger = logging.getLogger(__name__)

#: Fewest history keys remembered for deduplication (the bound is ``max(4 * depth, this)``).
MIN_HISTORY_MEMORY: Final = 1_000


class ProjectionMode(enum.Enum):
    """What an :class:`AlarmProjection` follows."""

    ACTIVE = "active"  #: the active alarm list only
    ACTIVE_PLUS_HISTORY = "active+history"  #: the active list and the alarm history


def _mode(mode: object) -> ProjectionMode:
    """A :class:`ProjectionMode` given as a member or its value (``"active"``,
    ``"active+history"``): ValueError naming the modes for other text, TypeError otherwise."""
    if isinstance(mode, ProjectionMode):
        return mode
    if isinstance(mode, str):
        word = mode.strip()
        try:
            return ProjectionMode(word.lower())
        except ValueError:
            pass
        try:  # the member's name, as other modes and kinds are taken by name
            return ProjectionMode[word.upper()]
        except KeyError:
            modes = ", ".join(repr(m.value) for m in ProjectionMode)
            raise ValueError(f"unknown projection mode {mode!r} (one of {modes})") from None
    raise TypeError(f"mode must be a ProjectionMode, got {mode!r}")


@dataclass(frozen=True, slots=True)
class AlarmRaised:
    """An alarm entered the active list."""

    alarm: ActiveAlarm


@dataclass(frozen=True, slots=True)
class AlarmCleared:
    """An alarm left the active list."""

    alarm: ActiveAlarm


@dataclass(frozen=True, slots=True)
class AlarmHistoryEvent:
    """A new entry of the alarm history."""

    entry: AlarmHistoryEntry


AlarmEvent = AlarmRaised | AlarmCleared | AlarmHistoryEvent
_HistoryKey = tuple[datetime, int, int, int]
#: An active alarm's identity: ``(axis, type, number)`` (:attr:`ActiveAlarm.key`).
AlarmKey = tuple[int, int, int]


def alarm_changes(
    before: Mapping[AlarmKey, ActiveAlarm], active: Iterable[ActiveAlarm]
) -> tuple[list[ActiveAlarm], list[ActiveAlarm], dict[AlarmKey, ActiveAlarm]]:
    """What changed from the active list ``before`` (by key) to ``active``: the alarms that
    left it (in ``before``'s order), those that entered it (in ``active``'s order), and the
    new list by key. An alarm is the same while its key is: a new message text alone is no
    change. TypeError naming what was given for a ``before`` that is no mapping (``{}`` at
    first) and an ``active`` that is no list of :class:`ActiveAlarm`."""
    if not isinstance(before, Mapping):
        raise TypeError(
            "before must be the alarms by key a previous call returned ({} at first), "
            f"got {before!r}"
        )
    if isinstance(active, str | bytes) or not isinstance(active, Iterable):
        raise TypeError(f"active must be a list of ActiveAlarm, got {active!r}")
    now: dict[AlarmKey, ActiveAlarm] = {}
    for alarm in active:
        if not isinstance(alarm, ActiveAlarm):
            raise TypeError(f"active must be a list of ActiveAlarm, it holds {alarm!r}")
        now[alarm.key] = alarm
    cleared = [a for k, a in before.items() if k not in now]
    raised = [a for k, a in now.items() if k not in before]
    return cleared, raised, now


class AlarmProjection:
    """An async iterator of :data:`AlarmEvent` built by polling ``client``.

    The first poll reports every alarm already active as :class:`AlarmRaised` and, unless
    ``replay_history`` is False, every history entry within ``depth`` as
    :class:`AlarmHistoryEvent`. ``depth`` (1 or more; more than 250 reads 250, as the
    clients' ``read_alarm_history``) and ``replay_history`` concern the history, which
    only ``ACTIVE_PLUS_HISTORY`` reads: in ACTIVE mode they change nothing (the alarms active
    at the first poll are reported as raised either way). ``timeout`` bounds each poll
    (default: the client's).
    ``max_failures`` (None: no bound) ends the iteration, raising the last error, once that
    many polls in a row have failed; a client left ``DISCONNECTED`` by a protocol violation or
    by its reconnect policy giving up ends it at once.
    """

    def __init__(
        self,
        client: CncClient,
        mode: ProjectionMode | str = ProjectionMode.ACTIVE,
        interval: float = 1.0,
        depth: int = 50,
        *,
        replay_history: bool = True,
        timeout: float | None = None,
        max_failures: int | None = None,
    ) -> None:
        if not all(
            callable(getattr(client, call, None)) for call in ("read_alarms", "read_alarm_history")
        ) or not hasattr(client, "state"):
            # (else the first poll fails with an AttributeError of what was given)
            raise TypeError(f"client must be a FocasClient or a NativeClient, got {client!r}")
        self.mode = _mode(mode)
        if isinstance(interval, bool) or not isinstance(interval, int | float):
            raise TypeError(f"interval must be a number of seconds, got {interval!r}")
        an_int("history depth", depth)  # its range below, with the others' checked
        if max_failures is not None and (
            isinstance(max_failures, bool) or not isinstance(max_failures, int)
        ):
            raise TypeError(f"max_failures must be an integer or None, got {max_failures!r}")
        if not isinstance(replay_history, bool):
            raise TypeError(f"replay_history must be True or False, got {replay_history!r}")
        check_timeout(timeout)
        if interval != interval:
            raise ValueError(nan_refused("interval", "a positive, finite number of seconds"))
        if not 0 < interval <= sys.float_info.max:  # (10**400 holds in no float)
            raise ValueError(
                f"interval must be a positive, finite number of seconds, got {interval}"
            )
        if max_failures is not None and max_failures < 1:
            raise ValueError(f"max_failures must be at least 1 (or None), got {max_failures}")
        self.client = client
        self.interval = interval
        #: History entries read by each poll: ``depth`` as the clients take it (from 1;
        #: more than 250 reads 250).
        self.depth = history_depth(depth)
        self.timeout = timeout
        self.max_failures = max_failures
        self._replay_history = replay_history
        self._failures_in_row = 0
        self._last_error: FocasError | None = None
        self._active: dict[tuple[int, int, int], ActiveAlarm] = {}
        #: How many entries of each key were seen (one alarm raised twice in a second is two
        #: entries of one key); insertion-ordered, oldest first.
        self._seen: dict[_HistoryKey, int] = {}
        self._memory = max(4 * self.depth, MIN_HISTORY_MEMORY)
        self._queue: deque[AlarmEvent] = deque()
        self._stop = asyncio.Event()
        self._polled = False
        self._next_poll = float("-inf")  # when the next poll is due (a failed one counts)
        #: Polls that failed and yielded nothing.
        self.failed_polls = 0
        #: Polls that completed.
        self.polls = 0

    def __repr__(self) -> str:
        """``<AlarmProjection active every 1.0 s of <FocasClient 127.0.0.1:8193 connected>>``."""
        return f"<AlarmProjection {self.mode.value} every {self.interval} s of {self.client!r}>"

    @property
    def active(self) -> tuple[ActiveAlarm, ...]:
        """The active alarms as of the last complete poll."""
        return tuple(self._active.values())

    @property
    def stopped(self) -> bool:
        return self._stop.is_set()

    def stop(self) -> None:
        """End the iteration; a pending ``__anext__`` returns at once."""
        self._stop.set()

    async def aclose(self) -> None:
        self.stop()

    async def __aenter__(self) -> Self:
        return self

    async def __aexit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        self.stop()

    def __aiter__(self) -> Self:
        return self

    async def __anext__(self) -> AlarmEvent:
        queue = self._queue
        loop = asyncio.get_running_loop()
        while True:
            if self._stop.is_set() or self.client.state is ClientState.CLOSED:
                raise StopAsyncIteration
            if queue:
                return queue.popleft()
            delay = self._next_poll - loop.time()
            if delay > 0:
                try:
                    async with asyncio.timeout(delay):
                        await self._stop.wait()
                except TimeoutError:
                    pass
                continue
            self._next_poll = loop.time() + self.interval
            polls = self.polls
            queue.extend(await self.poll())
            if self.polls != polls:
                self._failures_in_row = 0
                continue
            self._failures_in_row += 1
            error = self._last_error
            if error is not None and (
                self._gave_up(error)
                or (self.max_failures is not None and self._failures_in_row >= self.max_failures)
            ):
                raise error

    def _gave_up(self, error: FocasError) -> bool:
        """Whether the client can no longer make progress: disconnected after its reconnect
        policy gave up, or after the peer broke the protocol (which is never retried). A
        client without a policy may still be connected again by its owner."""
        client = self.client
        if client.state is not ClientState.DISCONNECTED:
            return False
        violation = isinstance(error, ProtocolError) and not isinstance(error, PayloadError)
        return violation or client.reconnect_policy is not None

    async def poll(self) -> list[AlarmEvent]:
        """Poll once and return the new events (also usable without iterating)."""
        client = self.client
        with_history = self.mode is ProjectionMode.ACTIVE_PLUS_HISTORY
        try:
            active = await client.read_alarms(timeout=self.timeout)
            history = (
                await client.read_alarm_history(self.depth, timeout=self.timeout)
                if with_history
                else None
            )
        except FocasError as exc:
            self.failed_polls += 1
            self._last_error = exc
            logger.debug("alarm poll of %s:%s failed: %s", client.host, client.port, exc)
            return []
        first = not self._polled
        self._polled = True
        self.polls += 1

        events: list[AlarmEvent] = []
        cleared, raised, self._active = alarm_changes(self._active, active)
        events.extend(AlarmCleared(a) for a in cleared)
        events.extend(AlarmRaised(a) for a in raised)

        if history is not None:
            seen = self._seen
            emit = self._replay_history or not first
            counted: dict[_HistoryKey, int] = {}
            for entry in reversed(history.entries):  # oldest first
                key = entry.key
                n = counted[key] = counted.get(key, 0) + 1
                if n <= seen.get(key, 0):
                    continue
                seen.pop(key, None)
                seen[key] = n
                if emit:
                    events.append(AlarmHistoryEvent(entry))
            excess = len(seen) - self._memory
            if excess > 0:
                for key in list(seen)[:excess]:
                    del seen[key]
        return events
