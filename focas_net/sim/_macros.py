"""The machine's macro variables: the ranges it has and the values they hold.

A variable holds a decimal of 0..9 decimal places (kept as given) whose digits as an integer
fit a signed 32-bit word, or nothing (vacant).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from decimal import Decimal, InvalidOperation
from typing import Final

from focas_net._refusals import no_item, system_read_only
from focas_net._typed import macro_unfit
from focas_net.errors import EW

from ._base import I32_MAX, I32_MIN, NUMBERS, Counters, MachineError

__all__ = [
    "MAX_MACRO_DECIMALS",
    "MacroRange",
    "Macros",
    "float_macro",
    "macro_value",
]

#: Most decimal places a macro variable holds.
MAX_MACRO_DECIMALS: Final = 9
_MACRO_STEP: Final = Decimal(1).scaleb(-MAX_MACRO_DECIMALS)
#: Digits of a signed 32-bit integer at most.
_I32_DIGITS: Final = len(str(I32_MAX))


@dataclass(frozen=True, slots=True)
class MacroRange:
    """Macro variables ``first..last`` (inclusive), writable or read-only."""

    first: int
    last: int
    writable: bool = True


def macro_value(value: Decimal | int) -> Decimal | None:
    """``value`` as a macro variable holds it, or None when it cannot hold it; -0 is held as
    0 (with the decimals given): the wire has no negative zero, so every front end shows 0."""
    if isinstance(value, bool) or not isinstance(value, Decimal | int):
        raise TypeError(f"a macro value is a Decimal, an int or None, got {value!r}")
    if isinstance(value, int):
        return Decimal(value) if I32_MIN <= value <= I32_MAX else None
    if not value.is_finite():
        return None
    sign, digits, exponent = value.as_tuple()
    assert isinstance(exponent, int)
    if not -MAX_MACRO_DECIMALS <= exponent <= 0 or len(digits) > _I32_DIGITS:
        return None
    coefficient = int("".join(map(str, digits)))
    if not I32_MIN <= (-coefficient if sign else coefficient) <= I32_MAX:
        return None
    return value.copy_abs() if sign and not coefficient else value


def _unheld(number: int, value: Decimal | int) -> str:
    """Why variable ``#number`` cannot hold ``value`` (a write's, or a machine's built with it),
    in the clients' words (:func:`focas_net.client._values.macro_write`)."""
    if isinstance(value, Decimal) and not value.is_finite():
        return f"#{number}: macro value {value} is not finite"
    return f"#{number}: macro value {macro_unfit(value)}"


def float_macro(value: float) -> Decimal | None:
    """The macro value a float of the program stands for (at most 9 decimals), or None when
    a variable cannot hold it."""
    if not math.isfinite(value):
        return None
    try:
        d = Decimal(repr(float(value))).quantize(_MACRO_STEP).normalize()
        exponent = d.as_tuple().exponent
        if isinstance(exponent, int) and exponent > 0:
            d = d.quantize(Decimal(1))
    except InvalidOperation:
        return None
    return macro_value(d)


class Macros:
    """The variables of a machine: its ranges (ascending, none overlapping) and the values of
    those that are not vacant. Every change moves the macro counter."""

    __slots__ = ("counters", "ranges", "values")

    def __init__(
        self,
        ranges: Iterable[MacroRange],
        values: Mapping[int, Decimal | int | None],
        counters: Counters,
    ) -> None:
        self.counters = counters
        self.ranges = tuple(sorted(ranges, key=lambda r: r.first))
        for r in self.ranges:
            low, high = NUMBERS
            if not low <= r.first <= r.last <= high:
                raise ValueError(
                    f"macro range {r.first}..{r.last} is empty or outside {low}..{high}"
                )
        for a, b in zip(self.ranges, self.ranges[1:], strict=False):
            if b.first <= a.last:
                raise ValueError(f"macro ranges {a.first}..{a.last} and {b.first}.. overlap")
        self.values: dict[int, Decimal] = {}
        for number, value in values.items():
            if self.range_of(number) is None:
                raise ValueError(f"macro #{number} is not in any macro range")
            if value is not None:
                held = macro_value(value)
                if held is None:
                    raise ValueError(_unheld(number, value))
                self.values[number] = held

    def range_of(self, number: int) -> MacroRange | None:
        """The range variable ``number`` is in, None when the machine has no such variable."""
        for r in self.ranges:
            if number < r.first:
                return None
            if number <= r.last:
                return r
        return None

    def check_write(self, number: int) -> None:
        """EW_NUMBER (no such variable), EW_PROT (a read-only one)."""
        r = self.range_of(number)
        if r is None:
            raise MachineError(EW.NUMBER, no_item("macro variable", f"#{number}"))
        if not r.writable:
            why = system_read_only(number) or f"macro variable #{number} is read-only"
            raise MachineError(EW.PROT, why)

    def write(
        self, number: int, value: Decimal | int | None, values: dict[int, Decimal] | None = None
    ) -> None:
        """Set a variable (None: vacant; a vacant one made vacant changes nothing): EW_DATA
        for a value it cannot hold. ``values``: where it is held (a path's own variables),
        the machine's by default."""
        if values is None:
            values = self.values
        if value is None:
            if values.pop(number, None) is not None:
                self.changed()
            return
        held = macro_value(value)
        if held is None:
            raise MachineError(EW.DATA, _unheld(number, value))
        values[number] = held
        self.changed()

    def changed(self) -> None:
        self.counters.macro += 1
        self.counters.version += 1
