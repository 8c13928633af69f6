"""The machine's parameters and diagnostics: their FANUC types and ranges, and their values."""

from __future__ import annotations

import enum
from collections.abc import Iterable
from dataclasses import dataclass, field
from typing import Final

from focas_net.errors import EW

from ._base import NUMBERS, Counters, MachineError, n_bytes, need_int

__all__ = [
    "MAX_REAL_DECIMALS",
    "PARTS_COUNT",
    "PARTS_REQUIRED",
    "PARTS_TOTAL",
    "DataItem",
    "Items",
    "ParamKind",
]

#: Parts count, total parts, parts required (parameters).
PARTS_COUNT: Final = 6711
PARTS_TOTAL: Final = 6712
PARTS_REQUIRED: Final = 6713


class ParamKind(enum.IntEnum):
    """The data type of a parameter (or diagnostic), numbered as FANUC numbers them.

    ``BIT`` is eight bits ``#7..#0`` held as 0..255; ``BYTE`` a signed byte, ``WORD`` an i16,
    ``TWO_WORD`` an i32; ``REAL`` a real value kept as FANUC's REALPRM keeps it: an i32 mantissa
    with the parameter's fixed number of decimals (:attr:`DataItem.decimals`), so ``12.345``
    with 3 decimals is the mantissa ``12345``.
    """

    BIT = 0
    BYTE = 1
    WORD = 2
    TWO_WORD = 3
    REAL = 4

    @property
    def width(self) -> int:
        """Bytes of a value of this kind on a wire: 1, 1, 2, 4, and 8 for REAL (REALPRM: the
        i32 mantissa and the i32 number of decimals)."""
        return _KIND_WIDTHS[self]

    @property
    def span(self) -> tuple[int, int]:
        """The values a parameter of this kind can hold (REAL: its mantissa)."""
        return _KIND_SPANS[self]


_KIND_WIDTHS: Final[dict[int, int]] = {0: 1, 1: 1, 2: 2, 3: 4, 4: 8}
_KIND_SPANS: Final[dict[int, tuple[int, int]]] = {
    0: (0, 0xFF),
    1: (-0x80, 0x7F),
    2: (-0x8000, 0x7FFF),
    3: (-0x8000_0000, 0x7FFF_FFFF),
    4: (-0x8000_0000, 0x7FFF_FFFF),
}
#: The kind of an item given by its width only.
_KIND_OF_WIDTH: Final[dict[int, ParamKind]] = {
    1: ParamKind.BYTE,
    2: ParamKind.WORD,
    4: ParamKind.TWO_WORD,
}
#: Most decimals of a real parameter (REALPRM ``dec_val``).
MAX_REAL_DECIMALS: Final = 9


@dataclass(slots=True)
class DataItem:
    """A parameter or a diagnostic: number, type, per-axis or not, allowed range (inclusive)
    and its value(s): one value, or one per axis.

    The type is ``kind`` (a :class:`ParamKind`); ``width`` follows from it (bit and byte 1,
    word 2, two-word 4, real 8). An item given only a ``width`` (1, 2 or 4) is a byte, word or
    two-word item. A ``REAL`` item holds mantissas with ``decimals`` decimals (0..9): its range
    and values are mantissas too. A ``BIT`` item holds 0..255 (bit ``#n`` is ``1 << n``).
    """

    number: int
    width: int = 0
    axis: bool = False
    low: int | None = None
    high: int | None = None
    values: list[int] = field(default_factory=lambda: [0])
    name: str = ""
    kind: ParamKind | None = None
    decimals: int = 0

    def check(self, axes: int) -> None:
        """Raise ValueError when the item is not consistent (for machine builders); fills in
        ``kind`` (from ``width``), ``width`` (from ``kind``) and the range (the kind's)."""
        if not NUMBERS[0] <= self.number <= NUMBERS[1]:
            raise ValueError(f"number {self.number} is outside {NUMBERS[0]}..{NUMBERS[1]}")
        if self.kind is None:
            kind = _KIND_OF_WIDTH.get(self.width)
            if kind is None:
                raise ValueError(f"width must be 1, 2 or 4, got {self.width}")
            self.kind = kind
        else:
            self.kind = ParamKind(self.kind)
            if self.width == 0:
                self.width = self.kind.width
            elif self.width != self.kind.width:
                raise ValueError(
                    f"a {self.kind.name.lower()} item is {n_bytes(self.kind.width)} wide, "
                    f"width {self.width} given"
                )
        if self.kind is ParamKind.REAL:
            if not 0 <= self.decimals <= MAX_REAL_DECIMALS:
                raise ValueError(f"decimals {self.decimals} outside 0..{MAX_REAL_DECIMALS}")
        elif self.decimals:
            raise ValueError(f"decimals apply to a real item only, got {self.decimals}")
        span = self.kind.span
        if self.low is None:
            self.low = span[0]
        if self.high is None:
            self.high = span[1]
        if not span[0] <= self.low <= self.high <= span[1]:
            raise ValueError(
                f"range {self.low}..{self.high} is empty or outside the type ({span[0]}..{span[1]})"
            )
        want = axes if self.axis else 1
        if self.axis and len(self.values) == 1 and want > 1:
            self.values = self.values * want
        if len(self.values) != want:
            raise ValueError(f"{len(self.values)} values given, {want} expected")
        for v in self.values:
            if not self.low <= v <= self.high:
                raise ValueError(f"value {v} is outside {self.low}..{self.high}")


def _connect_params() -> tuple[DataItem, ...]:
    """The parameters a FOCAS client reads on its own, with their defaults for a machine that
    does not give them: 9968, the FOCAS option bits (#0 set: ``cnc_rddynamic2`` is there),
    3115, the position display bits of each axis (0: every position shown), and the display
    bits FANUC's library reads for ``cnc_rdspeed`` in the 16i set, 3106, 3107 and 9936, all 0
    as a control leaves them from the factory: 3106 #3 gives a lathe's spindle speed the
    suffix of its spindle, 3107 #5 lets a signal pick which, 9936 #3 shows the feed per
    revolution (see ``docs/native-protocol.md``)."""
    return (
        DataItem(9968, kind=ParamKind.BIT, values=[0b0000_0001], name="FOCAS option bits"),
        DataItem(3115, axis=True, kind=ParamKind.BIT, values=[0], name="position display"),
        DataItem(3106, kind=ParamKind.BIT, values=[0], name="display of the spindle speed"),
        DataItem(3107, kind=ParamKind.BIT, values=[0], name="spindle speed display selection"),
        DataItem(9936, kind=ParamKind.BIT, values=[0], name="feed display of rdspeed"),
    )


class Items:
    """The parameters and the diagnostics of a machine with ``axes`` axes, by number. Every
    change of a value moves the data counter."""

    __slots__ = ("axes", "counters", "diags", "params")

    def __init__(
        self,
        params: Iterable[DataItem],
        diags: Iterable[DataItem],
        axes: int,
        counters: Counters,
    ) -> None:
        self.axes = axes
        self.counters = counters
        self.params = self._table(params, "parameter")
        for item in _connect_params():  # what a FOCAS client reads at connect, when not given
            if item.number not in self.params:
                item.check(axes)
                self.params[item.number] = item
        self.diags = self._table(diags, "diagnostic")

    def _table(self, items: Iterable[DataItem], what: str) -> dict[int, DataItem]:
        table: dict[int, DataItem] = {}
        for item in items:
            try:
                item.check(self.axes)
            except ValueError as exc:
                raise ValueError(f"{what} {item.number}: {exc}") from None
            if item.number in table:
                raise ValueError(f"{what} {item.number} given twice")
            table[item.number] = item
        return table

    def lookup(self, table: dict[int, DataItem], datano: int, axis: int) -> tuple[DataItem, int]:
        """An item and the index of ``axis``'s value: EW_NUMBER (no such item), EW_ATTRIB
        (axis 0 for an axis item, an axis for another, an axis outside 1..n)."""
        need_int("number", datano)
        need_int("axis", axis)
        item = table.get(datano)
        if item is None:
            raise MachineError(EW.NUMBER, f"no item {datano}")
        if item.axis:
            if not 1 <= axis <= self.axes:
                raise MachineError(EW.ATTRIB, f"item {datano} needs an axis 1..{self.axes}")
            return item, axis - 1
        if axis != 0:
            raise MachineError(EW.ATTRIB, f"item {datano} is not an axis item")
        return item, 0

    @staticmethod
    def rescaled(item: DataItem, value: int, decimals: int | None) -> int:
        """A real parameter's mantissa given with ``decimals`` decimals, in the parameter's own
        decimals: EW_DATA when it has no exact mantissa there (or ``decimals`` is outside
        0..9). Any other item's value as it is."""
        if decimals is None or item.kind is not ParamKind.REAL or decimals == item.decimals:
            return value
        if not 0 <= decimals <= MAX_REAL_DECIMALS:
            raise MachineError(EW.DATA, f"parameter {item.number}: {decimals} decimals")
        shift = item.decimals - decimals
        scale: int = 10 ** abs(shift)
        if shift > 0:
            return value * scale
        if value % scale:
            raise MachineError(
                EW.DATA,
                f"parameter {item.number} has {item.decimals} decimals, {value}E-{decimals}",
            )
        return value // scale

    def set(self, item: DataItem, index: int, value: int, what: str) -> None:
        """Set one value: EW_DATA outside the item's range (TypeError for no integer)."""
        need_int(f"{what} value", value)
        low, high = item.low, item.high
        assert low is not None and high is not None
        if not low <= value <= high:
            raise MachineError(EW.DATA, f"{what} {item.number}: {value} outside {low}..{high}")
        item.values[index] = value
        self.counters.data += 1
        self.counters.version += 1

    def clamp(self, number: int, value: int) -> bool:
        """Set non-axis parameter ``number`` to ``value`` held within its range; False when
        the machine has no such parameter."""
        item = self.params.get(number)
        if item is None:
            return False
        assert item.high is not None and item.low is not None
        item.values[0] = max(item.low, min(item.high, value))
        self.counters.data += 1
        self.counters.version += 1
        return True

    def param_or(self, number: int, default: int, axis: int = 0) -> int:
        """The value of parameter ``number`` (of ``axis``, 0 for a non-axis one), ``default``
        when the machine has none such."""
        item = self.params.get(number)
        if item is None or (axis == 0) == item.axis:
            return default
        return item.values[max(axis - 1, 0)]

    def param_float(self, number: int, default: float, axis: int, unit: float) -> float:
        """Parameter ``number`` of ``axis`` as a number: a real parameter's value as it reads
        (mantissa over its decimals), an integer one's times ``unit``; ``default`` when the
        machine has no such parameter."""
        item = self.params.get(number)
        if item is None or (axis == 0) == item.axis:
            return default
        raw = item.values[max(axis - 1, 0)]
        if item.kind is ParamKind.REAL:
            return raw / float(10**item.decimals)
        return raw * unit
