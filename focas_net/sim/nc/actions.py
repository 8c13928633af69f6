"""What one block asks of the machine: the actions the interpreter answers and the engine
carries out in time (motion, dwell, an M/T function's wait, a waiting M code, a stop, the
program's end).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Final

from .motion import Motion

__all__ = ["BUSY", "Action", "Dwell", "ProgramEnd", "Step", "Stop", "Sync", "Wait"]


@dataclass(frozen=True, slots=True)
class Dwell:
    seconds: float


#: The code of the engine's own wait in a loop of blocks that take no time (not a function).
BUSY: Final = "busy"


@dataclass(frozen=True, slots=True)
class Wait:
    """An M, T or tool-change function: the program waits ``seconds`` for its completion; or
    the engine's own time for a block-only loop (``code`` :data:`BUSY`), which is no function."""

    seconds: float
    code: str

    @property
    def fin(self) -> bool:
        """Whether an M/S/T/B function waits for its completion (ODBST ``mstb`` FIN)."""
        return self.code != BUSY


@dataclass(frozen=True, slots=True)
class Sync:
    """A waiting M code: the path stops until every path of ``paths`` (its own among them)
    has reached a waiting M code; they go on together (see :mod:`.waits`)."""

    code: int
    paths: frozenset[int]


@dataclass(frozen=True, slots=True)
class Stop:
    """M0, or M1 with the optional stop switch on."""

    code: int


@dataclass(frozen=True, slots=True)
class ProgramEnd:
    """M2/M30 (``code``), or the program's last block (``code`` None): counts a part when
    ``code`` is set."""

    code: int | None


Action = Motion | Dwell | Wait | Sync | Stop | ProgramEnd


@dataclass(slots=True)
class Step:
    """What one block asked for: the actions in order, and whether it was an NC block (a
    single-block stop follows those, not macro statements)."""

    actions: list[Action] = field(default_factory=list)
    nc_block: bool = False
