"""Waiting M codes: the paths of one control meet at them.

A path's program that reaches a waiting M code (an M code within parameters 8110..8111, on a
control of two or more paths) stops there until every path the wait names has reached a
waiting M code too; then they all go on at the moment the last of them arrived. Without P the
wait names every path; with P it names the paths by their digits (``M100 P12``: paths 1 and
2), and only those wait.

Paths that wait for each other with another M code, or with another P, would wait for ever: the
control stops them with alarm PS0160 (MISMATCH WAITING M-CODE). A P that names a path the
control has not, a path twice, not the path itself or the path alone is PS0161 (ILLEGAL P OF
WAITING M-CODE), raised by the interpreter.

Nothing ticks here either. An engine that stands at a wait and is brought to a moment first
brings the other paths of the wait to that moment (:meth:`PathSync.release`), so a path never
runs past a wait before it knows when the wait ended. An engine being brought there already
stands at a wait of its own (it asked), so the recursion ends; when the answer hangs on such
an engine, which has not been brought to the moment yet, the answer is :data:`UNKNOWN` and the
asking engine stays where it is until it asks again.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Final

if TYPE_CHECKING:
    from .engine import Engine

__all__ = ["MISMATCH", "UNKNOWN", "PathSync", "Unknown"]

#: The alarm of paths that wait for each other with another M code or another P.
MISMATCH: Final = 160


class Unknown:
    """The answer of :meth:`PathSync.release` when a path of the wait is still on its way to
    the moment asked (it stands at an earlier wait, asking for its own end)."""


UNKNOWN: Final = Unknown()


class PathSync:
    """The waiting M codes of one control: its engines by path number (1..)."""

    __slots__ = ("_busy", "engines")

    def __init__(self) -> None:
        self.engines: list[Engine] = []
        self._busy: set[int] = set()

    def join(self, engine: Engine) -> int:
        """Add the next path's engine; returns its path number."""
        self.engines.append(engine)
        return len(self.engines)

    def release(self, engine: Engine, number: int, now: float) -> float | Unknown | None:
        """When the wait path ``number`` (``engine``) stands at ends, once every path it
        names is brought to machine time ``now``: the moment the last of them arrived, None
        while one has not arrived by ``now``, :data:`UNKNOWN` while one cannot be brought
        there yet. A mismatch marks every path of it for PS0160 (each raises it when it reads
        its mark) and answers None."""
        if engine.released_at is not None:
            return engine.released_at
        wait = engine.sync_wait
        if wait is None:
            return None
        busy = self._busy
        busy.add(number)
        try:
            for other in sorted(wait.paths):
                if other != number and other not in busy:
                    self.engines[other - 1].advance(until=now)
            if engine.released_at is not None:  # another path of the wait released it
                return engine.released_at
            if engine.sync_mismatch is not None:
                return None
            arrivals: list[float] = []
            for other in sorted(wait.paths):
                e = self.engines[other - 1]
                theirs = e.sync_wait
                if theirs is None or e.released_at is not None:
                    # not there by now (or still leaving the wait before): asking, it may
                    # not have been brought to now
                    return UNKNOWN if other in busy and other != number else None
                if number in theirs.paths and (theirs.code, theirs.paths) != (
                    wait.code,
                    wait.paths,
                ):
                    detail = (
                        f"path {number} waits at M{wait.code} {_named(wait.paths)}, "
                        f"path {other} at M{theirs.code} {_named(theirs.paths)}"
                    )
                    engine.sync_mismatch = e.sync_mismatch = detail
                    e.revision += 1
                    return None
                if number not in theirs.paths:  # it waits for others first
                    return UNKNOWN if other in busy else None
                arrivals.append(e.sync_arrival)
            end = max(arrivals)
            for other in wait.paths:
                e = self.engines[other - 1]
                e.released_at = end
                e.revision += 1
            return end
        finally:
            busy.discard(number)


def _named(paths: frozenset[int]) -> str:
    return "with paths " + ", ".join(str(p) for p in sorted(paths))
