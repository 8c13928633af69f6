"""What every part of a machine file is read with: the error naming the file and the key,
where in the file a value is (:class:`_Ctx`), and the checks of TOML values (a table, an
integer within a span, a string, an array ...) that name the key of a bad value."""

from __future__ import annotations

import json
import re
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, Final, NoReturn

from focas_net._typed import file_text
from focas_net.errors import FocasError

__all__ = ["MachineFileError"]

#: The spans of a signed 16-bit and a signed 32-bit value.
_I16: Final = (-0x8000, 0x7FFF)
_I32: Final = (-0x8000_0000, 0x7FFF_FFFF)
#: A key TOML writes without quotes.
_BARE_KEY: Final = re.compile(r"[A-Za-z0-9_-]+")


class MachineFileError(FocasError, ValueError):
    """A machine file that cannot be used: ``path``, ``key`` (dotted) and ``problem``."""

    def __init__(self, path: str, key: str, problem: str) -> None:
        self.path = path
        self.key = key
        self.problem = problem
        where = f"{path}: {key}" if key else path
        super().__init__(f"{where}: {problem}" if where else problem)


_TOML_AT: Final = re.compile(r"\(at line (\d+), column (\d+)\)$")


def toml_point_hint(text: str, error: str) -> str:
    """A hint for a TOML error at a number written with a point as a part program writes it
    (``1000.``, ``.5``), which TOML does not read; empty for any other error."""
    at = _TOML_AT.search(error)
    if at is None:
        return ""
    lines = text.splitlines()
    row, column = int(at.group(1)) - 1, int(at.group(2)) - 1
    line = lines[row] if 0 <= row < len(lines) else ""
    near = line[max(column - 1, 0) : column + 3]
    if re.search(r"\d\.(?!\d)|(?<!\d)\.\d", near) is None:
        return ""
    return (
        " (TOML writes a decimal with a digit on each side of its point: 1000.0 and 0.5, "
        "not 1000. and .5 as a part program does)"
    )


class TomlFloat(float):
    """A float of a machine file that reads as typed in it (``1e400`` rather than the
    ``inf`` TOML makes of it, ``1_000.5``): every refusal naming the value names the file's
    text. Arithmetic gives plain floats. ``tomllib.loads(text, parse_float=TomlFloat)``."""

    __slots__ = ("text",)
    text: str

    def __new__(cls, text: str) -> TomlFloat:
        self = super().__new__(cls, text)
        self.text = text
        return self

    def __repr__(self) -> str:
        return self.text

    __str__ = __repr__

    def __format__(self, spec: str) -> str:
        return self.text if not spec else float.__format__(self, spec)


@dataclass(frozen=True, slots=True)
class _Ctx:
    """Where we are: the file and the dotted key of the current table."""

    path: str
    key: str

    def sub(self, key: str | int) -> _Ctx:
        if isinstance(key, int):
            return _Ctx(self.path, f"{self.key}[{key}]")
        if not _BARE_KEY.fullmatch(key):  # as TOML writes it: " 1420" stays visible
            key = json.dumps(key, ensure_ascii=False)
        return _Ctx(self.path, f"{self.key}.{key}" if self.key else key)

    def fail(self, problem: str) -> NoReturn:
        raise MachineFileError(self.path, self.key, problem)


def _table(ctx: _Ctx, value: Any) -> dict[str, Any]:
    if not isinstance(value, dict):
        ctx.fail(f"must be a table, got {_kind(value)}")
    return value


def _kind(value: Any) -> str:
    if isinstance(value, bool):
        return f"a boolean ({str(value).lower()})"
    if isinstance(value, int):
        return f"an integer ({value})"
    if isinstance(value, str):
        return f"a string ({value!r})"
    if isinstance(value, float):
        return f"a float ({value})"
    if isinstance(value, list):
        return "an array"
    if isinstance(value, dict):
        return "a table"
    return f"a {type(value).__name__}"


def _only(ctx: _Ctx, table: Mapping[str, Any], allowed: tuple[str, ...]) -> None:
    for key in table:
        if key not in allowed:
            ctx.sub(key).fail(f"unknown key (expected one of: {', '.join(allowed)})")


def _int(ctx: _Ctx, value: Any, span: tuple[int, int] | None = None) -> int:
    if isinstance(value, bool) or not isinstance(value, int):
        ctx.fail(f"must be an integer, got {_kind(value)}")
    if span is not None and not span[0] <= value <= span[1]:
        ctx.fail(f"{value} is outside {span[0]}..{span[1]}")
    return value


def _bool(ctx: _Ctx, value: Any) -> bool:
    if isinstance(value, bool):
        return value
    if isinstance(value, int) and value in (0, 1):
        return bool(value)
    ctx.fail(f"must be true or false, got {_kind(value)}")


def _str(ctx: _Ctx, value: Any) -> str:
    if isinstance(value, int | float) and not isinstance(value, bool):
        ctx.fail(f'must be a string, got {_kind(value)}: write it in quotes, "{value}"')
    if not isinstance(value, str):
        ctx.fail(f"must be a string, got {_kind(value)}")
    return value


def _ascii(ctx: _Ctx, value: Any, size: int | None = None) -> str:
    text = _str(ctx, value)
    if not text.isascii():
        ctx.fail(f"must be ASCII: {text!r}")
    if size is not None and len(text) != size:
        ctx.fail(f"must be exactly {size} characters: {text!r}")
    return text


def _list(ctx: _Ctx, value: Any) -> list[Any]:
    if not isinstance(value, list):
        ctx.fail(f"must be an array, got {_kind(value)}")
    return value


def _bytes(ctx: _Ctx, value: Any) -> bytes:
    items = _list(ctx, value)
    return bytes(_int(ctx.sub(i), v, (0, 255)) for i, v in enumerate(items))


def _number_key(ctx: _Ctx, key: str, span: tuple[int, int]) -> int:
    if not re.fullmatch(r"-?[0-9]+", key):
        ctx.fail(f"the key must be a number of ASCII digits, got {key!r}")
    number = int(key)
    if not span[0] <= number <= span[1]:
        ctx.fail(f"{number} is outside {span[0]}..{span[1]}")
    return number


def _text(name: str, raw: bytes) -> str:
    """The text of a machine file: UTF-8, with or without a byte-order mark."""
    try:
        return file_text(raw)
    except ValueError as exc:
        raise MachineFileError(name, "", str(exc)) from None
