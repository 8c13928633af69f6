"""Machines at work on their own: production scenarios and the loads of cutting.

A :class:`Scenario` says how a machine runs by itself: its main program repeated for a number
of parts (or forever), with operator pauses (a feed hold, then cycle start), tool-change waits
(the cycle stopped while the operator changes a worn tool) and alarms (the cycle stopped until
a repair, then reset and a new cycle) at given rates, events per hour of machine time, each
lasting a random time around its mean.

Everything is computed, nothing ticks: a :class:`Schedule` draws the events of one machine in
machine-time order from its own seeded generators (one per kind of event, so the events of one
kind never depend on another's), lazily, as far as the clock has gone. The same seed gives the
same events at the same machine times on every run, however often and whenever the machine is
read. :func:`fleet_seed` derives the seed of each machine of a fleet from one fleet seed.

The loads (:func:`spindle_load`, :func:`servo_load`) are functions of what the machine does
now (cutting or not, feed, spindle speed, each axis's speed) and of a seeded noise that depends
only on the seed and the machine time's bucket (:func:`noise`): two reads at the same machine
time give the same value.

Standard library only; no protocol, no I/O.
"""

from __future__ import annotations

import hashlib
import math
import random
from dataclasses import dataclass
from typing import Final, Literal

__all__ = [
    "DEFAULT_SCENARIO",
    "EVENT_KINDS",
    "MAX_PARTS",
    "MAX_SEED",
    "SCENARIO_ALARMS",
    "Scenario",
    "ScenarioAlarm",
    "ScenarioEvent",
    "Schedule",
    "checked_scenario",
    "fleet_seed",
    "noise",
    "servo_load",
    "spindle_load",
]

#: The kinds of event a scenario has, in the order their generators are seeded.
EVENT_KINDS: Final = ("pause", "tool", "alarm")
#: Shortest duration of an event (seconds): a draw below it is lifted to it.
MIN_EVENT_TIME: Final = 5.0
#: Bucket of machine time (seconds) within which the loads' noise stays the same.
NOISE_BUCKET: Final = 0.25
_HOUR: Final = 3600.0
_MASK64: Final = (1 << 64) - 1


@dataclass(frozen=True, slots=True)
class ScenarioAlarm:
    """An alarm a scenario raises: FANUC's alarm type number (5 OH, 6 SV, 9 SP, 15 EX),
    its number, its message and whether it is an axis's alarm (the axis then drawn)."""

    alm_type: int
    alm_no: int
    message: str
    per_axis: bool = False


#: The alarms a scenario draws from, equally likely.
SCENARIO_ALARMS: Final = (
    ScenarioAlarm(6, 411, "SV0411 EXCESS ERROR IN MOVE", per_axis=True),
    ScenarioAlarm(9, 9001, "SP9001 SPINDLE MOTOR OVERHEAT"),
    ScenarioAlarm(5, 700, "OH0700 OVERHEAT: CONTROL UNIT"),
    ScenarioAlarm(15, 1001, "EX1001 COOLANT LEVEL LOW"),
    ScenarioAlarm(15, 1002, "EX1002 CHIP CONVEYOR OVERLOAD"),
)


#: The largest seed of a scenario (a machine file's ``[run]`` seed, ``serve --seed``).
MAX_SEED: Final = 2**63 - 1
#: The most parts a scenario makes before it stops (the parts count is a two-word parameter).
MAX_PARTS: Final = 2**31 - 1


@dataclass(frozen=True, slots=True)
class Scenario:
    """How a machine runs on its own. Rates are events per hour of machine time (0: none),
    times are mean seconds (each event's own is drawn around it, at least
    :data:`MIN_EVENT_TIME`).

    ``parts``: parts to make, then the cycle ends in reset; 0 makes parts forever;
    ``"required"`` makes parts until the parts count (parameter 6711) reaches the parts
    required (parameter 6713; forever when that is 0). ``seed``: the seed of the events and of
    the loads' noise. ``phase``: seconds the machine has already been at work when the
    scenario starts (so machines started together are not in step); None draws it from the
    seed, 0..``phase_span``."""

    parts: int | Literal["required"] = 0
    seed: int = 0
    phase: float | None = None
    phase_span: float = 120.0
    pause_rate: float = 3.0
    pause_time: float = 45.0
    tool_rate: float = 1.0
    tool_time: float = 90.0
    alarm_rate: float = 0.5
    alarm_time: float = 240.0

    def __post_init__(self) -> None:
        if self.parts != "required" and (
            isinstance(self.parts, bool) or not isinstance(self.parts, int) or self.parts < 0
        ):
            raise ValueError(f"parts is a count >= 0 or 'required', got {self.parts!r}")
        if isinstance(self.parts, int) and self.parts > MAX_PARTS:
            raise ValueError(f"parts {self.parts} is outside 0..{MAX_PARTS}")
        if (
            isinstance(self.seed, bool)
            or not isinstance(self.seed, int)
            or not 0 <= self.seed <= MAX_SEED
        ):
            raise ValueError(f"seed is an integer 0..{MAX_SEED}, got {self.seed!r}")
        checks: tuple[tuple[str, float | None], ...] = (
            ("phase", self.phase),
            ("phase_span", self.phase_span),
            ("pause_rate", self.pause_rate),
            ("pause_time", self.pause_time),
            ("tool_rate", self.tool_rate),
            ("tool_time", self.tool_time),
            ("alarm_rate", self.alarm_rate),
            ("alarm_time", self.alarm_time),
        )
        for name, value in checks:
            if value is None and name == "phase":
                continue
            if (
                isinstance(value, bool)
                or not isinstance(value, int | float)
                or not math.isfinite(value)
                or value < 0
            ):
                raise ValueError(f"{name} is a finite number >= 0, got {value!r}")

    def rate(self, kind: str) -> float:
        """Events of ``kind`` per hour."""
        return float(getattr(self, f"{kind}_rate"))

    def mean_time(self, kind: str) -> float:
        """Mean seconds an event of ``kind`` lasts."""
        return float(getattr(self, f"{kind}_time"))

    def start_phase(self) -> float:
        """The phase, drawn from the seed when not given."""
        if self.phase is not None:
            return float(self.phase)
        return _stream(self.seed, "phase").random() * self.phase_span


#: What ``serve --run`` gives a machine whose file has no ``[run]`` section.
DEFAULT_SCENARIO: Final = Scenario()


@dataclass(frozen=True, slots=True)
class ScenarioEvent:
    """One event: from machine time ``time`` for ``duration`` seconds. ``alarm`` (alarms
    only) indexes :data:`SCENARIO_ALARMS`; ``axis`` is its axis number (1..n, 0 none)."""

    time: float
    kind: str
    duration: float
    alarm: int = 0
    axis: int = 0

    @property
    def end(self) -> float:
        return self.time + self.duration


class Schedule:
    """The events of one machine in machine-time order from ``origin``, drawn lazily.

    Each kind has its own generator seeded from ``(seed, kind)``: inter-arrival times are
    exponential (a Poisson process at the kind's rate), durations exponential around the mean
    time. ``axes`` is the machine's number of axes (for an axis's alarm)."""

    __slots__ = ("_axes", "_next", "_scenario", "_streams")

    def __init__(self, scenario: Scenario, origin: float, axes: int = 1) -> None:
        self._scenario = scenario
        self._axes = max(1, axes)
        self._streams = {kind: _stream(scenario.seed, kind) for kind in EVENT_KINDS}
        self._next: dict[str, ScenarioEvent | None] = {}
        for kind in EVENT_KINDS:
            self._next[kind] = self._draw(kind, origin)

    def _draw(self, kind: str, after: float) -> ScenarioEvent | None:
        rate = self._scenario.rate(kind)
        if rate <= 0:
            return None
        rng = self._streams[kind]
        when = after + rng.expovariate(rate / _HOUR)
        mean = self._scenario.mean_time(kind)
        duration = max(MIN_EVENT_TIME, rng.expovariate(1.0 / mean)) if mean > 0 else 0.0
        alarm = axis = 0
        if kind == "alarm":
            alarm = rng.randrange(len(SCENARIO_ALARMS))
            if SCENARIO_ALARMS[alarm].per_axis:
                axis = rng.randrange(self._axes) + 1
        return ScenarioEvent(when, kind, duration, alarm, axis)

    @property
    def next_time(self) -> float:
        """Machine time of the next event (infinity: none)."""
        times = [e.time for e in self._next.values() if e is not None]
        return min(times, default=math.inf)

    def pop(self) -> ScenarioEvent:
        """The next event, removed (IndexError when there is none); ties go by kind order."""
        best: ScenarioEvent | None = None
        for kind in EVENT_KINDS:
            event = self._next[kind]
            if event is not None and (best is None or event.time < best.time):
                best = event
        if best is None:
            raise IndexError("the scenario has no events")
        self._next[best.kind] = self._draw(best.kind, best.time)
        return best

    def until(self, when: float) -> list[ScenarioEvent]:
        """Every event before machine time ``when``, removed, in order."""
        events = []
        while self.next_time < when:
            events.append(self.pop())
        return events


def checked_scenario(scenario: object) -> Scenario | None:
    """``scenario`` when it is a :class:`Scenario` or None, else a TypeError naming it (a
    scenario's name or its settings are no scenario: a machine file's ``[run]`` makes one)."""
    if scenario is None or isinstance(scenario, Scenario):
        return scenario
    raise TypeError(
        f"scenario must be a Scenario (focas_net.sim.nc.scenario) or None, got {scenario!r}"
    )


def _stream(seed: int, name: str) -> random.Random:
    """A generator of its own for ``name`` under ``seed`` (a string seed: the same stream on
    every run and platform, whatever the hash seed)."""
    return random.Random(f"focas-net scenario {seed} {name}")


def fleet_seed(seed: int, index: int) -> int:
    """The seed of machine ``index`` (0-based) of a fleet whose seed is ``seed``."""
    digest = hashlib.blake2b(f"{seed}/{index}".encode(), digest_size=8).digest()
    return int.from_bytes(digest, "little") >> 1


def noise(seed: int, when: float, channel: int) -> float:
    """A value in -1..1 that depends only on ``seed``, the bucket of machine time ``when``
    falls in (:data:`NOISE_BUCKET`) and ``channel`` (a spindle or an axis)."""
    bucket = math.floor(when / NOISE_BUCKET)
    x = (seed * 0x9E37_79B9_7F4A_7C15 + bucket * 0xBF58_476D_1CE4_E5B9 + channel + 1) & _MASK64
    x ^= x >> 30
    x = (x * 0xBF58_476D_1CE4_E5B9) & _MASK64
    x ^= x >> 27
    x = (x * 0x94D0_49BB_1331_11EB) & _MASK64
    x ^= x >> 31
    return x / float(1 << 63) - 1.0


def spindle_load(
    cutting: bool, feed: float, speed: float, max_speed: float, wiggle: float, hardness: float
) -> int:
    """Spindle load in percent: 0 with the spindle stopped, a few percent turning in the air,
    while cutting rising with the feed (mm/min) and the spindle speed (of ``max_speed``);
    ``wiggle`` is the noise (-1..1), ``hardness`` the machine's material factor (about 1)."""
    if speed <= 0:
        return 0
    if not cutting:
        return max(0, round(2.0 + 1.5 * wiggle))
    load = hardness * (12.0 + 30.0 * min(feed, 5000.0) / 1000.0 + 20.0 * speed / max_speed)
    return max(0, min(150, round(load * (1.0 + 0.06 * wiggle))))


def servo_load(
    axis_speed: float, rapid_rate: float, cutting: bool, feed: float, wiggle: float
) -> int:
    """Servo load of one axis in percent: 0 at rest, with its speed (of its ``rapid_rate``)
    while it moves, more while it cuts (the cutting force grows with ``feed``)."""
    if axis_speed <= 0:
        return 0
    load = 4.0 + 25.0 * min(axis_speed / rapid_rate, 1.0)
    if cutting:
        load += 8.0 + 10.0 * min(feed, 5000.0) / 1000.0
    return max(0, min(200, round(load * (1.0 + 0.08 * wiggle))))
