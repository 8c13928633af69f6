"""What both adapters share: the answers of reads kept while the machine counters they follow
hold, and how a refused request becomes its EW code.

Protocol-neutral, pure and synchronous: it knows the machine and :mod:`focas_net.errors` only.

**Kept answers.** Each adapter has a table of the reads whose answer follows machine counters
(``status_version``, ``data_version``, ``macro_version``, ``alarm_version``, ``pmc_version``,
``motion_version``; ``""`` for what never changes: the identity, the axes). The answer of a
request made of such reads only, and refused by nothing, is kept in an :class:`AnswerMemo`
under the request with :func:`counters_of` its counters and what they read *before* it was
answered (a machine that moves meanwhile only makes the next look-up miss). It is the answer
for as long as they read the same. Writes are never kept, nor reads that move with time alone
(timers, loads) or with the program store (directory, memory, the blocks being executed).

**Refusals.** A handler refuses a request by raising one of :data:`REFUSALS`: the machine's
:class:`~focas_net.sim.MachineError`, :class:`Refused` for a check of the wire's own, or a
:class:`~focas_net.errors.PayloadError` of its codec for what does not decode;
:func:`refusal_code` is the EW code each answers.

**Answers a wire cannot carry.** The machine refuses every value it cannot hold, so what it
holds fits both wires. Should it hold one that does not (an encoder raises one of
:data:`UNENCODABLE`), the request is answered EW_DATA and a warning names the machine, the
request and the value (:func:`unencodable_code`): an adapter never raises because of the
machine's state, and the connection stays up.
"""

from __future__ import annotations

import logging
import struct
from collections.abc import Callable, Iterable
from operator import attrgetter
from typing import Any, Final

from focas_net._memo import Memo
from focas_net.errors import EW, PayloadError
from focas_net.sim import Machine, MachineError

__all__ = [
    "COUNTERS",
    "REFUSALS",
    "UNENCODABLE",
    "AnswerMemo",
    "Counters",
    "Refused",
    "counters_of",
    "need_room",
    "refusal_code",
    "unencodable_code",
]

_log = logging.getLogger("focas_net.adapters")

#: The machine counters an answer may follow.
COUNTERS: Final = frozenset(
    {
        "status_version",
        "data_version",
        "macro_version",
        "alarm_version",
        "pmc_version",
        "motion_version",
    }
)

#: What reads the counters an answer follows from a machine (compared with ``==``).
Counters = Callable[[Machine], Any]


def _no_counters(machine: Machine) -> tuple[()]:
    """The counters of an answer that never changes: none."""
    return ()


def counters_of(names: Iterable[str]) -> Counters:
    """The reader of the machine counters ``names`` (each once; ``""`` stands for none)."""
    wanted = sorted({name for name in names if name})
    unknown = set(wanted) - COUNTERS
    if unknown:
        raise ValueError(f"not a machine counter: {sorted(unknown)}")
    if not wanted:
        return _no_counters
    return attrgetter(*wanted)


class AnswerMemo(Memo):
    """Kept answers (see the module docstring): ``key -> (counters, what they read, answer)``,
    emptied when full.

    A look-up is one dict look-up and one compare, written where the answer is wanted (the
    adapters' hot path makes no call for it)::

        kept = memo.get(key)
        if kept is not None and kept[0](machine) == kept[1]:
            return kept[2]
    """

    __slots__ = ()

    def keep(self, key: Any, counters: Counters, seen: Any, answer: bytes) -> None:
        """Keep ``answer`` for ``key``: good while ``counters`` read ``seen``, read before the
        answer was made."""
        self.put(key, (counters, seen, answer))


class Refused(Exception):
    """A request refused by the wire's own rules (not by the machine): answer it with ``ew``."""

    def __init__(self, ew: int) -> None:
        super().__init__(ew)
        self.ew = ew


#: What a handler raises for a request it refuses (:func:`refusal_code` gives its EW code).
REFUSALS: Final = (MachineError, Refused, PayloadError)


def refusal_code(exc: MachineError | Refused | PayloadError) -> int:
    """The EW code answering a refused request: the machine's, the wire check's, the one a
    payload error carries (the native codec's), else EW_LENGTH (what does not decode)."""
    ew: int | None = getattr(exc, "ew", None)
    return EW.LENGTH if ew is None else ew


#: What an encoder raises for a value its wire cannot carry: the codecs' ValueError, a bare
#: struct's error, OverflowError of a number with no integer value.
UNENCODABLE: Final = (ValueError, struct.error, OverflowError)


def unencodable_code(machine: Machine, request: str, exc: Exception) -> int:
    """The EW code answering a request whose answer the wire cannot carry (EW_DATA), logged
    as a warning naming ``machine``, ``request`` and what did not fit."""
    _log.warning(
        "%s: %s answered EW_DATA: the answer does not fit the wire: %s", machine.name, request, exc
    )
    return EW.DATA


def need_room(size: int, room: int) -> None:
    """EW_LENGTH unless ``size`` bytes of data fit the ``room`` left in the answer."""
    if size > room:
        raise Refused(EW.LENGTH)
