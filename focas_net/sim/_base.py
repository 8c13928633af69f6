"""What every component of the machine shares: its refusal and its version counters.

The machine (:mod:`focas_net.sim.machine`) is a facade over components, one concern each; they
raise :class:`MachineError` for what the CNC refuses and move the :class:`Counters` they share
for every change they make.
"""

from __future__ import annotations

import logging
from collections.abc import Iterable, Mapping
from typing import Final, TypeVar

from focas_net._address import shown
from focas_net.errors import EW, FocasError

__all__ = [
    "I32_MAX",
    "I32_MIN",
    "NUMBERS",
    "Counters",
    "MachineError",
    "logger",
    "n_bytes",
    "n_values",
    "need_int",
    "need_items",
    "need_mapping",
    "need_one",
    "need_text",
]

T = TypeVar("T")
K = TypeVar("K")

#: The machine's logger, one name for all its components.
logger = logging.getLogger("focas_net.sim.machine")

I32_MIN: Final = -0x8000_0000
I32_MAX: Final = 0x7FFF_FFFF
#: The numbers a parameter, a diagnostic or a macro variable can have (FANUC numbers them from
#: 0; a wire carries them in a signed 16-bit word).
NUMBERS: Final = (0, 0x7FFF)


def n_values(given: int, axes: int) -> str:
    """``3 values for 2 axes``, ``1 value for 1 axis``: a count of values against axes."""
    values = "value" if given == 1 else "values"
    return f"{given} {values} for {axes} {'axis' if axes == 1 else 'axes'}"


def n_bytes(width: int) -> str:
    """``1 byte``, ``4 bytes``: a width, as a refusal names it."""
    return f"{width} byte" if width == 1 else f"{width} bytes"


def need_int(what: str, value: object) -> int:
    """``value`` when it is an ``int`` (not a ``bool``): a number of another type given to the
    machine from Python (``1.5``, ``"3"``, ``True``) is a TypeError naming ``what`` and the
    value, before anything changes. The ranges are each operation's own (EW codes)."""
    if isinstance(value, bool) or not isinstance(value, int):
        raise TypeError(f"{what} must be an integer, got {value!r}")
    return value


def need_flag(what: str, value: object) -> bool:
    """``value`` when it is a ``bool``: a switch given another value (``1.5``, ``"yes"``,
    ``0``) is a TypeError naming ``what`` and the value, rather than counting as set because
    it is truthy."""
    if not isinstance(value, bool):
        raise TypeError(f"{what} must be True or False, got {value!r}")
    return value


def need_flag_or_none(what: str, value: object) -> bool | None:
    """``value`` when it is a ``bool`` or None (:func:`need_flag`, None allowed)."""
    if value is not None and not isinstance(value, bool):
        raise TypeError(f"{what} must be True, False or None, got {value!r}")
    return value


def need_text(what: str, value: object) -> str:
    """``value`` when it is a ``str``: TypeError naming ``what`` and the value otherwise."""
    if not isinstance(value, str):
        raise TypeError(f"{what} must be text (str), got {value!r}")
    return value


def _a(kind: type[object]) -> str:
    name = kind.__name__
    return "None" if kind is type(None) else f"{'an' if name[0] in 'AEIOUaeiou' else 'a'} {name}"


def need_one(what: str, value: object, kind: type[T]) -> T | None:
    """``value`` when it is a ``kind`` or None: TypeError naming ``what`` otherwise."""
    if value is not None and not isinstance(value, kind):
        raise TypeError(f"{what} must be {_a(kind)} or None, got {value!r}")
    return value


def need_items(
    what: str,
    given: object,
    kind: type[T],
    *,
    items: str | None = None,
    item: str | None = None,
) -> list[T]:
    """The items of ``given``, a list (any iterable but text or a mapping) of ``kind``:
    TypeError naming ``what`` (and the item, ``params[0]``) otherwise, rather than an
    ``AttributeError`` from deep in the machine. ``items`` names the list's items (``kind``'s
    name by default), ``item`` one of them (``a DataItem``). One text given in place of a list
    of texts, which would be read character by character, is named as such."""
    named = kind.__name__ if items is None else items
    if isinstance(given, str) and kind is str:
        raise TypeError(
            f"{what} must be a list of {named}, got one text {shown(given)}: give it in a list"
        )
    if isinstance(given, str | bytes | Mapping) or not isinstance(given, Iterable):
        raise TypeError(f"{what} must be a list of {named}, got {given!r}")
    values = list(given)
    for i, value in enumerate(values):
        if not isinstance(value, kind):
            raise TypeError(
                f"{what}[{i}] must be {_a(kind) if item is None else item}, got {value!r}"
            )
    return values


def need_mapping(
    what: str, given: object, key: type[K], kind: type[T] | tuple[type[T], ...]
) -> dict[K, T]:
    """``given`` as a dict, when it is a mapping of ``key`` to ``kind`` (None: empty):
    TypeError naming ``what`` and the key or value otherwise (a ``bool`` is no ``int``)."""
    if given is None:
        return {}
    kinds = kind if isinstance(kind, tuple) else (kind,)
    *some, last = [_a(k) for k in kinds]
    names = f"{', '.join(some)} or {last}" if some else last
    if not isinstance(given, Mapping):
        raise TypeError(f"{what} must be a mapping of {key.__name__} to {names}, got {given!r}")
    for k, v in given.items():
        if isinstance(k, bool) or not isinstance(k, key):
            raise TypeError(f"{what}: a key must be {_a(key)}, got {k!r}")
        if isinstance(v, bool) or not isinstance(v, kinds):
            raise TypeError(f"{what}[{k!r}] must be {names}, got {v!r}")
    return dict(given)


class MachineError(FocasError):
    """An operation refused: ``ew`` is the FANUC ``EW_*`` code the CNC answers."""

    def __init__(self, ew: int, detail: str = "") -> None:
        self.ew = int(ew)
        self.detail = detail
        name = EW(self.ew).name if self.ew in EW._value2member_map_ else str(self.ew)
        super().__init__(f"EW_{name}: {detail}" if detail else f"EW_{name}")


class Counters:
    """The version counters of one machine, shared by its components. Each moves on every
    change it covers (front ends key caches of their answers on them); ``version`` moves on
    every change of machine state, so a component that moves a narrower counter moves it too."""

    __slots__ = ("alarm", "data", "macro", "motion", "pmc", "status", "version")

    def __init__(self) -> None:
        #: Every change of machine state.
        self.version = 0
        #: The status: panel, run state, motion, active alarms.
        self.status = 0
        #: A parameter or diagnostic value.
        self.data = 0
        #: A macro variable.
        self.macro = 0
        #: The active alarms or the alarm history.
        self.alarm = 0
        #: PMC data.
        self.pmc = 0
        #: The motion figures.
        self.motion = 0

    def status_changed(self) -> None:
        """The status changed (and so the machine's state)."""
        self.status += 1
        self.version += 1
