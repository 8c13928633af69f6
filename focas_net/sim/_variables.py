"""The variables as the interpreter of one path reads and writes them (see
:class:`PathVariables`)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Final

from ._items import PARTS_COUNT, PARTS_TOTAL
from ._macros import Macros, float_macro
from ._signals import CLOCK_VARIABLES, clock_variable
from .nc import VariableRefused

if TYPE_CHECKING:
    from ._path import Path

__all__ = ["PARTS_VARIABLES", "PathVariables"]

#: The macro variables of the parts count and the total parts.
PARTS_VARIABLES: Final = {3901: PARTS_COUNT, 3902: PARTS_TOTAL}


class PathVariables:
    """The variables as a path's interpreter reads and writes them: #3901/#3902 (the path's
    parts), the machine's macro ranges (#500-#999 and whatever else it has; #100-#199 the
    path's own); 115 for a number the machine lacks, 116 for a read-only one, 111 for a value
    a variable cannot hold."""

    __slots__ = ("_macros", "_path")

    def __init__(self, path: Path, macros: Macros) -> None:
        self._path = path
        self._macros = macros

    def read_variable(self, number: int) -> float | None:
        if number in PARTS_VARIABLES:
            return float(self._path.parts(PARTS_VARIABLES[number]))
        if number in CLOCK_VARIABLES:  # the CNC's clock: the alarms are stamped by it
            return float(clock_variable(number, self._path.alarms.now()))
        if self._macros.range_of(number) is None:
            raise VariableRefused(115, f"#{number}")
        value = self._path.macro_values(number).get(number)
        return None if value is None else float(value)

    def write_variable(self, number: int, value: float | None) -> None:
        if number in PARTS_VARIABLES:
            self._path.set_parts(PARTS_VARIABLES[number], 0 if value is None else round(value))
            return
        if number in CLOCK_VARIABLES:
            raise VariableRefused(116, f"#{number}")
        macros = self._macros
        r = macros.range_of(number)
        if r is None:
            raise VariableRefused(115, f"#{number}")
        if not r.writable:
            raise VariableRefused(116, f"#{number}")
        values = self._path.macro_values(number)
        if value is None:
            values.pop(number, None)
        else:
            held = float_macro(value)
            if held is None:
                raise VariableRefused(111, f"#{number} = {value!r}")
            values[number] = held
        macros.changed()
