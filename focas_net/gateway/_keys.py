"""The checks of a TOML value that name where it was written: :class:`ConfigError` and
:class:`At`, the key path of a value as the user wrote it (``machine[3].groups.fast``).

Every message names the file, the key path, what was typed and what is expected::

    gateway.toml: machine[3].groups.fast: got -1; expected a finite number of seconds > 0

Arrays of tables and arrays count from 1 (``machine[1]`` is the first ``[[machine]]``), as a
person counts the blocks of a file. Nothing here knows the gateway's schema.
"""

from __future__ import annotations

import difflib
import math
from collections.abc import Collection, Mapping
from dataclasses import dataclass
from typing import Any, NoReturn

__all__ = ["At", "ConfigError"]


class ConfigError(ValueError):
    """A configuration that cannot be used: the message names the file, the key path, what
    was typed and what is expected."""


def _typed(value: object) -> str:
    """``value`` as the user typed it, in TOML's words where they differ from Python's."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, Mapping):
        return "a table"
    if isinstance(value, str):
        return repr(value) if len(value) <= 60 else f"{value[:60]!r}... ({len(value)} characters)"
    text = repr(value)
    return text if len(text) <= 60 else f"{text[:60]}..."


@dataclass(frozen=True, slots=True)
class At:
    """Where a value stands: the file (``source``) and its key path (empty: the top)."""

    source: str
    path: str = ""

    def key(self, name: str) -> At:
        """The value of key ``name`` below this one."""
        return At(self.source, f"{self.path}.{name}" if self.path else name)

    def index(self, i: int) -> At:
        """Entry ``i`` (0-based) of the array here, written 1-based."""
        return At(self.source, f"{self.path}[{i + 1}]")

    def fail(self, message: str) -> NoReturn:
        """Raise :class:`ConfigError` for this place."""
        where = ": ".join(part for part in (self.source, self.path) if part)
        raise ConfigError(f"{where}: {message}")

    def expected(self, value: object, what: str) -> NoReturn:
        """Raise :class:`ConfigError`: ``value`` was typed here, ``what`` is expected."""
        self.fail(f"got {_typed(value)}; expected {what}")

    # -- values --------------------------------------------------------------------------
    def table(self, value: object, keys: Collection[str]) -> Mapping[str, Any]:
        """``value`` as a table whose keys are all among ``keys`` (an unknown key is named,
        with the known key closest to it)."""
        if not isinstance(value, Mapping):
            self.expected(value, "a table")
        for name in value:
            if name not in keys:
                close = difflib.get_close_matches(name, list(keys), n=1)
                hint = f" (did you mean {close[0]!r}?)" if close else ""
                known = ", ".join(sorted(keys))
                self.key(name).fail(f"unknown key{hint}; known keys here: {known}")
        return value

    def tables(self, value: object) -> list[Mapping[str, Any]]:
        """``value`` as an array of tables (``[[name]]``)."""
        if not isinstance(value, list) or not all(isinstance(v, Mapping) for v in value):
            self.expected(value, "an array of tables ([[...]] blocks)")
        return value

    def array(self, value: object, low: int, high: int) -> list[Any]:
        """``value`` as an array of ``low..high`` entries (a list, as TOML gives it, or a
        tuple, as Python may)."""
        if not isinstance(value, list | tuple):
            self.expected(value, f"an array of {low}..{high} entries")
        if not low <= len(value) <= high:
            self.fail(f"got {len(value)} entries; expected {low}..{high}")
        return list(value)

    def integer(self, value: object, low: int, high: int) -> int:
        """``value`` as an integer within ``low..high``."""
        if isinstance(value, bool) or not isinstance(value, int) or not low <= value <= high:
            self.expected(value, f"an integer {low}..{high}")
        return value

    def seconds(self, value: object, least: float = 0.0) -> float:
        """``value`` as a finite number of seconds above 0, and at ``least`` that when given."""
        if (
            isinstance(value, bool)
            or not isinstance(value, int | float)
            or not 0 < value < math.inf
            or value < least
        ):
            self.expected(
                value,
                f"a finite number of seconds >= {least:g}"
                if least
                else "a finite number of seconds > 0",
            )
        return float(value)

    def number(self, value: object, low: float = 0.0) -> float:
        """``value`` as a finite number at or above ``low``."""
        if (
            isinstance(value, bool)
            or not isinstance(value, int | float)
            or not low <= value < math.inf
        ):
            self.expected(value, f"a finite number >= {low:g}")
        return float(value)

    def text(self, value: object, what: str = "a string") -> str:
        """``value`` as a non-empty string."""
        if not isinstance(value, str) or not value:
            self.expected(value, what)
        return value

    def boolean(self, value: object) -> bool:
        """``value`` as true or false."""
        if not isinstance(value, bool):
            self.expected(value, "true or false")
        return value

    def choice(self, value: object, choices: Collection[str]) -> str:
        """``value`` as one of ``choices``."""
        if not isinstance(value, str) or value not in choices:
            self.expected(value, " or ".join(repr(c) for c in choices))
        return value

    def checked(self, value: object, check: Any, what: str, *, why: bool = True) -> Any:
        """``check(value)``, a check of the project's that raises ``ValueError`` or
        ``TypeError``: its refusal as :class:`ConfigError` of this place, with the check's own
        reason after ``what`` unless ``why`` is false (a range that ``what`` already says)."""
        try:
            return check(value)
        except (TypeError, ValueError) as exc:
            self.fail(f"got {_typed(value)}; expected {what}" + (f" ({exc})" if why else ""))
