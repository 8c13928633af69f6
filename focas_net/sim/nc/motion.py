"""Motion segments: where the axes are at each moment of one block's motion.

Every segment is parametrised by its *progress* in nominal seconds (its duration at 100 %
override): the engine moves the progress at the override's rate, so an override change or a
feed hold never re-plans the geometry. Coordinates are machine coordinates in mm.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

__all__ = ["ArcMove", "LinearMove", "Motion", "RapidMove"]

Vector = tuple[float, ...]


@dataclass(frozen=True, slots=True)
class LinearMove:
    """Linear interpolation at ``feed`` mm/min (cutting feed)."""

    start: Vector
    end: Vector
    feed: float
    duration: float

    rapid = False

    @classmethod
    def plan(cls, start: Vector, end: Vector, feed: float) -> LinearMove:
        length = math.dist(start, end)
        return cls(start, end, feed, length / feed * 60.0 if length else 0.0)

    def at(self, p: float) -> Vector:
        if p >= self.duration:
            return self.end
        f = p / self.duration if self.duration else 1.0
        return tuple(s + (e - s) * f for s, e in zip(self.start, self.end, strict=True))

    def speed(self, p: float) -> float:
        return self.feed if p < self.duration else 0.0

    def critical(self) -> list[float]:
        return [0.0, self.duration]


@dataclass(frozen=True, slots=True)
class RapidMove:
    """Positioning with each axis at its own rapid rate (FANUC's non-linear positioning, the
    default of parameter 1401#1 LRP = 0): each axis stops when it arrives."""

    start: Vector
    end: Vector
    rates: Vector  #: mm/min per axis
    duration: float

    rapid = True
    feed = 0.0

    @classmethod
    def plan(cls, start: Vector, end: Vector, rates: Vector) -> RapidMove:
        times = [abs(e - s) / r * 60.0 for s, e, r in zip(start, end, rates, strict=True)]
        return cls(start, end, rates, max(times, default=0.0))

    def at(self, p: float) -> Vector:
        if p >= self.duration:
            return self.end
        out = []
        for s, e, r in zip(self.start, self.end, self.rates, strict=True):
            step = r / 60.0 * p
            out.append(e if abs(e - s) <= step else s + math.copysign(step, e - s))
        return tuple(out)

    def speed(self, p: float) -> float:
        if p >= self.duration:
            return 0.0
        moving = [
            r
            for s, e, r in zip(self.start, self.end, self.rates, strict=True)
            if abs(e - s) > r / 60.0 * p
        ]
        return math.sqrt(sum(r * r for r in moving))

    def critical(self) -> list[float]:
        return [0.0, self.duration]


@dataclass(frozen=True, slots=True)
class ArcMove:
    """Circular (or helical) interpolation in the plane of axes ``a``, ``b`` (indices) around
    ``center``: ``sweep`` radians (positive counter-clockwise), the radius going from ``r0``
    to ``r1`` (equal unless the program's end point was off the circle within the
    tolerance); the other axes move linearly. ``feed`` is the speed along the arc."""

    start: Vector
    end: Vector
    feed: float
    duration: float
    a: int
    b: int
    center: tuple[float, float]
    theta0: float
    sweep: float
    r0: float
    r1: float

    rapid = False

    def at(self, p: float) -> Vector:
        if p >= self.duration:
            return self.end
        f = p / self.duration if self.duration else 1.0
        theta = self.theta0 + self.sweep * f
        r = self.r0 + (self.r1 - self.r0) * f
        out = [s + (e - s) * f for s, e in zip(self.start, self.end, strict=True)]
        out[self.a] = self.center[0] + r * math.cos(theta)
        out[self.b] = self.center[1] + r * math.sin(theta)
        return tuple(out)

    def speed(self, p: float) -> float:
        return self.feed if p < self.duration else 0.0

    def critical(self) -> list[float]:
        """Progress of the start, the end and every quarter angle the arc passes (between
        these each coordinate is monotone)."""
        points = [0.0, self.duration]
        if self.sweep and self.duration:
            quarter = math.pi / 2
            lo, hi = sorted((self.theta0, self.theta0 + self.sweep))
            k = math.ceil(lo / quarter)
            while k * quarter < hi:
                points.append((k * quarter - self.theta0) / self.sweep * self.duration)
                k += 1
        return sorted(points)


Motion = LinearMove | RapidMove | ArcMove
