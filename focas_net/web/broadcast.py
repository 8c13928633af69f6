"""Live updates: one broadcaster computes each view once per tick and offers it to every page.

A page subscribes to a :data:`Topic`: the fleet, or one machine (with the PMC window its viewer
shows). Each :meth:`Broadcaster.tick` computes the fleet view once (when a page watches it;
it records every machine's tool path on the way) and each watched machine's view once, serialises
each topic's frame once, and offers it to the topic's subscriptions. An offer never waits: a
subscription keeps at most ``depth`` frames and drops the oldest, so a slow page skips
frames and never holds up the others. :meth:`Broadcaster.run` ticks every ``interval``
seconds until cancelled; the tests call :meth:`tick` by hand.
"""

from __future__ import annotations

import asyncio
import json
import logging
import time
from collections import deque
from collections.abc import Sequence
from typing import Final

from focas_net.protocol import pmc_address_unfit
from focas_net.sim import PMC_AREAS, MachineError

from .operations import Station, path_unfit
from .view import JsonDict, fleet_view, machine_view, no_machine, pmc_window

__all__ = ["DEFAULT_INTERVAL", "FLEET", "Broadcaster", "Subscription", "Topic", "machine_topic"]

_log = logging.getLogger(__name__)

#: Seconds between two ticks (4 updates a second).
DEFAULT_INTERVAL: Final = 0.25
#: Frames a subscription keeps for a page that has not taken them (the oldest is dropped).
DEFAULT_DEPTH: Final = 2

#: Seconds of pause per second a tick took (the updates take at most 1/(1+4) of the loop).
_IDLE_PER_BUSY: Final = 4.0

#: ``("fleet",)`` or ``("machine", index, pmc area, pmc start)``.
Topic = tuple[str, ...] | tuple[str, int, str, int, int]
#: The fleet view's topic.
FLEET: Final[Topic] = ("fleet",)


def machine_topic(index: int, pmc_area: str = "X", pmc_start: int = 0, path: int = 1) -> Topic:
    """The topic of machine ``index``'s view of ``path`` with that PMC window."""
    return ("machine", index, pmc_area.strip().upper(), pmc_start, path)


def _path_unfit(station: Station, path: int) -> str | None:
    """Why ``station``'s machine shows no ``path``, in the machine's words (as the page's
    actions and ``--path`` say it) and naming the machine; None when it has the path."""
    why = path_unfit(path)  # no CNC's path, as the actions and the clients word it
    if why is not None:
        return f"{why} (machine {station.index})"
    try:
        station.machine.path_info(path)
    except MachineError as exc:
        return f"{exc.detail} (machine {station.index})"
    return None


class Subscription:
    """One open page: its topic and the frames waiting for it."""

    __slots__ = ("_frames", "_wake", "closed", "depth", "dropped", "topic")

    def __init__(self, topic: Topic, depth: int = DEFAULT_DEPTH) -> None:
        if depth < 1:
            raise ValueError(f"depth must be at least 1, got {depth}")
        self.topic = topic
        self.depth = depth
        self._frames: deque[str] = deque()
        self._wake = asyncio.Event()
        #: Frames dropped because the page had not taken the older ones.
        self.dropped = 0
        self.closed = False

    def __len__(self) -> int:
        return len(self._frames)

    def offer(self, frame: str) -> None:
        """Queue ``frame``, dropping the oldest when ``depth`` are waiting (never blocks)."""
        if self.closed:
            return
        if len(self._frames) >= self.depth:
            self._frames.popleft()
            self.dropped += 1
        self._frames.append(frame)
        self._wake.set()

    def take(self) -> str | None:
        """The oldest waiting frame, or None."""
        if not self._frames:
            return None
        frame = self._frames.popleft()
        if not self._frames:
            self._wake.clear()
        return frame

    async def next(self) -> str | None:
        """Wait for the next frame; None once the subscription is closed."""
        while not self.closed:
            frame = self.take()
            if frame is not None:
                return frame
            await self._wake.wait()
        return None

    def close(self) -> None:
        self.closed = True
        self._frames.clear()
        self._wake.set()


class Broadcaster:
    """The one producer of live frames for a fleet of :class:`Station`."""

    def __init__(self, stations: Sequence[Station], *, interval: float = DEFAULT_INTERVAL) -> None:
        if not interval > 0:
            raise ValueError(f"interval must be positive, got {interval}")
        self.stations = list(stations)
        self.interval = interval
        self.subscriptions: set[Subscription] = set()
        #: Ticks done, and views computed over all of them (a view per topic per tick).
        self.ticks = 0
        self.views_computed = 0

    def subscribe(self, topic: Topic, depth: int = DEFAULT_DEPTH) -> Subscription:
        sub = Subscription(topic, depth)
        self.subscriptions.add(sub)
        return sub

    def unsubscribe(self, sub: Subscription) -> None:
        sub.close()
        self.subscriptions.discard(sub)

    def close(self) -> None:
        """Close every subscription (their pages' senders end)."""
        for sub in list(self.subscriptions):
            self.unsubscribe(sub)

    def refusal(self, topic: Topic, *, window: bool = True) -> str | None:
        """Why ``topic`` cannot be shown (None: it can): a machine or a path the fleet has
        not, a PMC window outside the machine's areas (in the machine's words; ``window``:
        the window was asked for, not the default one)."""
        if topic[0] == "fleet":
            return None
        _, index, area, start, path = topic
        assert isinstance(index, int) and isinstance(area, str) and isinstance(start, int)
        assert isinstance(path, int)
        if not 0 <= index < len(self.stations):
            return no_machine(str(index), len(self.stations))
        machine = self.stations[index].machine
        unfit = _path_unfit(self.stations[index], path)
        if unfit is not None:
            return unfit
        beyond = pmc_address_unfit(start) if window else None
        if beyond is not None:  # as the page's GET and `pmc read R 70000` refuse it
            return f"PMC window: {beyond}"
        try:
            if window:
                pmc_window(machine, area, start)
        except MachineError as exc:
            return f"PMC window: {exc.detail or exc}"
        return None

    def first_pmc_area(self, index: int) -> str:
        """The first PMC area machine ``index`` has (X when it has none, or there is no such
        machine: its frames then say so)."""
        if 0 <= index < len(self.stations):
            machine = self.stations[index].machine
            for letter in PMC_AREAS:
                if machine.pmc_area(letter) is not None:
                    return letter
        return "X"

    def frame(self, topic: Topic) -> str:
        """The JSON frame of ``topic`` now."""
        return json.dumps(self._view(topic, {}), separators=(",", ":"))

    def _view(self, topic: Topic, views: dict[tuple[int, int], JsonDict]) -> JsonDict:
        """The message of ``topic``; ``views`` keeps the machine views of this tick, so
        pages on one path of a machine with different PMC windows share one view."""
        if topic[0] == "fleet":
            self.views_computed += 1
            entries = ((s.index, s.machine, s.port) for s in self.stations)
            trails = [s.trail for s in self.stations]
            return {"type": "fleet", "data": fleet_view(entries, trails)}
        _, index, area, start, path = topic
        assert isinstance(index, int) and isinstance(area, str) and isinstance(start, int)
        assert isinstance(path, int)
        if not 0 <= index < len(self.stations):
            return {"type": "error", "error": no_machine(str(index), len(self.stations))}
        s = self.stations[index]
        unfit = _path_unfit(s, path)
        if unfit is not None:
            return {"type": "error", "error": unfit}
        view = views.get((index, path))
        if view is None:
            self.views_computed += 1
            view = machine_view(
                index,
                s.machine,
                s.port,
                trail=s.trail_of(path),
                faults=s.fault_listing(),
                path=path,
            )
            views[(index, path)] = view
        return {"type": "machine", "data": view, "pmc": self._pmc(s, area, start)}

    @staticmethod
    def _pmc(station: Station, area: str, start: int) -> JsonDict:
        try:
            return pmc_window(station.machine, area, start)
        except MachineError as exc:
            return {"area": area, "start": start, "error": str(exc)}

    def record_paths(self) -> None:
        """Add every machine's current absolute position to its tool path."""
        for s in self.stations:
            s.record_trails()

    def tick(self) -> int:
        """Compute each subscribed topic's frame once (each machine's view once) and offer it
        to its subscriptions; returns how many frames were made. The views record the tool
        paths of the machines they read; with no page open nothing is read."""
        self.ticks += 1
        by_topic: dict[Topic, list[Subscription]] = {}
        for sub in self.subscriptions:
            by_topic.setdefault(sub.topic, []).append(sub)
        views: dict[tuple[int, int], JsonDict] = {}
        for topic, subs in by_topic.items():
            frame = json.dumps(self._view(topic, views), separators=(",", ":"))
            for sub in subs:
                sub.offer(frame)
        return len(by_topic)

    async def run(self) -> None:
        """Tick every :attr:`interval` seconds until cancelled. A tick that takes long (a
        large fleet of running machines) stretches the pause after it, so the updates take
        at most a fifth of the event loop's time from the machines' connections."""
        while True:
            started = time.perf_counter()
            try:
                self.tick()
            except Exception:  # a view that fails must not end the live updates
                _log.exception("dashboard update failed")
            busy = time.perf_counter() - started
            await asyncio.sleep(max(self.interval, busy * _IDLE_PER_BUSY))
