"""The parameters the machine itself reads, with the types FANUC's controls give them.

A machine may hold any parameter of any type; but a parameter the machine acts on (its rapid
traverse rate, its waiting M codes, its parts count, the bits FANUC's library reads at
connect ...) must have a type the machine can read as the control does, or the machine would
read a real parameter's mantissa as mm/min, or an axis parameter where it looks for one value.
:func:`param_type_problem` says what is wrong with such a parameter's type; every builder of a
machine (a machine file, :class:`~focas_net.sim.Machine` itself) meets it.

The diagnostics the machine computes while a program runs (410, 4901, 4902: the loads) are
checked alike (:data:`KNOWN_DIAGS`).

Parameter 1020 names each axis's program letter (``'X'`` is 88): :func:`axis_letter_problem`
keeps its values and the machine's axes in agreement, at build and at every write. A control
takes a new 1020 at the next power-on (PW0000); the simulated machine's axes are fixed when it
is built, so it refuses a write that would rename an axis.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import Final

from focas_net._refusals import AXIS_NAME_PARAM, FANUC_SPANS  # (1020: each axis's letter)
from focas_net.errors import EW

from ._base import MachineError
from ._items import _KIND_OF_WIDTH, DataItem, Items, ParamKind

__all__ = [
    "AXIS_NAME_PARAM",
    "KNOWN_DIAGS",
    "KNOWN_PARAMS",
    "RENAME_REFUSED",
    "KnownParam",
    "axis_letter_problem",
    "check_known",
    "check_rename",
    "known_range",
    "param_type_problem",
    "params_problem",
    "with_known_ranges",
]

#: Why a write of 1020 that renames an axis is refused (after :func:`axis_letter_problem`).
RENAME_REFUSED: Final = (
    ": the machine's axes are fixed when it is built (a control takes a new name at its "
    "next power-on)"
)


@dataclass(frozen=True, slots=True)
class KnownParam:
    """What the machine does with a parameter (``what``: ``"the machine counts parts in
    it"``), the types it may have (FANUC's; the 16i class has integer types where the 30i
    class has real ones) and whether it has one value per axis (None: either; a diagnostic the
    machine computes in one shape only and reads as given in the other)."""

    what: str
    kinds: tuple[ParamKind, ...]
    axis: bool | None
    #: FANUC's valid data range, taken (within the type) when a builder gives no range
    span: tuple[int, int] | None = None


_W, _2W, _R = ParamKind.WORD, ParamKind.TWO_WORD, ParamKind.REAL
_PARTS: Final = KnownParam("the machine counts parts in it", (_W, _2W), False, FANUC_SPANS[6711])
_TIMER: Final = KnownParam("the machine keeps a timer in it", (_2W,), False, FANUC_SPANS[6750])
_TIMER_MS: Final = KnownParam("the machine keeps a timer in it", (_2W,), False, FANUC_SPANS[6751])
_WAIT: Final = KnownParam("the machine reads its waiting M codes from it", (_W, _2W), False)
_LIBRARY: Final = "FANUC's library reads its bits"

#: The parameters the machine reads, by number.
KNOWN_PARAMS: Final[dict[int, KnownParam]] = {
    AXIS_NAME_PARAM: KnownParam("it names each axis's letter", (ParamKind.BYTE,), True),
    1240: KnownParam("the machine reads each axis's reference position from it", (_2W, _R), True),
    1320: KnownParam("the machine reads each axis's stroke limit from it", (_2W, _R), True),
    1321: KnownParam("the machine reads each axis's stroke limit from it", (_2W, _R), True),
    1420: KnownParam("the machine reads each axis's rapid traverse rate from it", (_2W, _R), True),
    1422: KnownParam("the machine reads its maximum cutting feed from it", (_2W, _R), False),
    1825: KnownParam("the machine reads each axis's servo loop gain from it", (_W,), True),
    3106: KnownParam(_LIBRARY, (ParamKind.BIT,), False),
    3107: KnownParam(_LIBRARY, (ParamKind.BIT,), False),
    3115: KnownParam(_LIBRARY, (ParamKind.BIT,), True),
    6711: _PARTS,
    6712: _PARTS,
    6713: _PARTS,
    **dict.fromkeys(range(6750, 6759, 2), _TIMER),  # minutes
    **dict.fromkeys(range(6751, 6759, 2), _TIMER_MS),  # the ms past the minutes
    8110: _WAIT,
    8111: _WAIT,
    9936: KnownParam(_LIBRARY, (ParamKind.BIT,), False),
    9968: KnownParam(_LIBRARY, (ParamKind.BIT,), False),
}


_DIAG_LOAD: Final = "the machine shows the spindle's load in it"
#: The diagnostics whose values the machine computes while a program runs, by number.
KNOWN_DIAGS: Final[dict[int, KnownParam]] = {
    410: KnownParam(_DIAG_LOAD, (_W, _2W), None),
    4901: KnownParam("the machine shows each axis's servo power in it", (_W, _2W), None),
    4902: KnownParam("the machine shows the spindle's power in it", (_W, _2W), None),
}


def _type_name(kind: ParamKind) -> str:
    return kind.name.lower().replace("_", "-")


def param_type_problem(
    number: int,
    kind: ParamKind | int | None,
    is_axis: bool,
    known_items: Mapping[int, KnownParam] = KNOWN_PARAMS,
) -> str | None:
    """What is wrong with parameter ``number`` of ``kind`` (per axis or not) as the machine
    reads it (:data:`KNOWN_PARAMS`; a diagnostic with ``known_items`` :data:`KNOWN_DIAGS`);
    None when nothing is, or the machine does not read it."""
    known = known_items.get(number)
    if known is None:
        return None
    if kind in known.kinds and known.axis in (None, is_axis):
        return None
    types = " or ".join(_type_name(k) for k in known.kinds)
    shape = {True: ", one per axis", False: ", not per axis", None: ""}[known.axis]
    noun = "diagnostic" if known_items is KNOWN_DIAGS else "parameter"
    given = "an axis" if is_axis else "a"
    if kind is None:
        type_name = "?"
    else:
        type_name = _type_name(ParamKind(kind))
        given = given if is_axis or type_name[0] not in "aeiou" else "an"
    article = "an" if types[0] in "aeiou" else "a"
    return f"{known.what}: it is {article} {types} {noun}{shape} (got {given} {type_name} {noun})"


def known_range(number: int, kind: ParamKind) -> tuple[int, int]:
    """The range parameter ``number`` of ``kind`` takes when its builder gives none: FANUC's
    valid data range of a parameter the machine keeps a count or a timer in (a parts count is
    never negative, the ms past a minute 0..59999), within the type; else the whole type."""
    low, high = kind.span
    known = KNOWN_PARAMS.get(number)
    if known is None or known.span is None:
        return low, high
    return max(low, known.span[0]), min(high, known.span[1])


def with_known_ranges(params: Iterable[DataItem]) -> list[DataItem]:
    """``params``, each item without a range given :func:`known_range`'s (for builders; an
    item of no valid type is left for :meth:`DataItem.check` to refuse)."""
    items = list(params)
    for item in items:
        if item.number not in KNOWN_PARAMS or (item.low is not None and item.high is not None):
            continue
        try:
            kind = ParamKind(item.kind) if item.kind is not None else _KIND_OF_WIDTH[item.width]
        except (ValueError, KeyError):
            continue
        low, high = known_range(item.number, kind)
        item.low = low if item.low is None else item.low
        item.high = high if item.high is None else item.high
    return items


def axis_letter_problem(value: int, axis: str) -> str | None:
    """What is wrong with ``value`` as parameter 1020 of the axis named ``axis`` (its letter's
    code: 88 for ``X``, ``X1`` or ``XA``); None when it is that."""
    letter = axis[0]
    if value == ord(letter):
        return None
    shown = f"{value} ({chr(value)!r})" if 65 <= value <= 90 else str(value)
    return f"axis {axis}'s letter {letter!r} is {ord(letter)}, not {shown}"


def params_problem(
    params: Mapping[int, DataItem], diags: Mapping[int, DataItem], axes: Sequence[str]
) -> str | None:
    """The first problem of a machine's parameters and diagnostics (``params``, ``diags``, by
    number) with the machine's ``axes`` (every axis, path by path): a type of
    :func:`param_type_problem`, or a value of parameter 1020 that does not name its axis
    (:func:`axis_letter_problem`); None when none."""
    tables = (("parameter", params, KNOWN_PARAMS), ("diagnostic", diags, KNOWN_DIAGS))
    for what, items, known in tables:
        for number, item in sorted(items.items()):
            problem = param_type_problem(number, item.kind, item.axis, known)
            if problem is not None:
                return f"{what} {number}: {problem}"
    names = params.get(AXIS_NAME_PARAM)
    if names is not None:
        for value, axis in zip(names.values, axes, strict=True):
            problem = axis_letter_problem(value, axis)
            if problem is not None:
                return f"parameter {AXIS_NAME_PARAM}: {problem}"
    return None


def check_known(items: Items, axes: Sequence[str]) -> None:
    """ValueError naming the first problem :func:`params_problem` finds (for builders)."""
    problem = params_problem(items.params, items.diags, axes)
    if problem is not None:
        raise ValueError(problem)


def check_rename(number: int, value: int, axis: str) -> None:
    """EW_DATA with why when writing ``value`` to parameter ``number`` of the axis named
    ``axis`` would rename the axis (parameter 1020 other than its letter)."""
    renamed = number == AXIS_NAME_PARAM and axis_letter_problem(value, axis)
    if renamed:
        raise MachineError(EW.DATA, f"parameter {number}: {renamed}{RENAME_REFUSED}")
