"""The write methods of a machine's object: ``WriteMacro``, ``WriteParameter`` and
``WritePmc``, each calling the gateway's :class:`~focas_net.gateway.model.Writer` (which applies
the write gates). A refusal is the call's Bad status (``docs/gateway.md``, Write methods)."""

from __future__ import annotations

import logging
from collections.abc import Awaitable, Callable
from decimal import Decimal
from typing import Any, Final, TypeAlias

from asyncua import Node, ua

from focas_net.errors import FocasError, OpcUaStatus
from focas_net.gateway.model import Writer

__all__ = ["add_write_methods", "arguments", "refusal"]

log = logging.getLogger(__name__)

_DENIED: Final = ua.StatusCode(ua.StatusCodes.BadUserAccessDenied)
_INVALID: Final = ua.StatusCode(ua.StatusCodes.BadInvalidArgument)

#: What a method returns: its (no) output arguments, or the Bad status of a refusal.
Result: TypeAlias = Any


def refusal(exc: BaseException) -> ua.StatusCode:
    """The status a refused write answers: BadUserAccessDenied for a write gate
    (``PermissionError``), the EW code's status for the CNC (or the lost connection's), and
    BadInvalidArgument for a value the writer's checks refused."""
    if isinstance(exc, PermissionError):
        return _DENIED
    status = getattr(exc, "opcua_status", None)
    if isinstance(status, OpcUaStatus):
        return ua.StatusCode(status.value)
    return _INVALID


def _given_text(given: tuple[Any, ...], declared: list[ua.Argument]) -> str:
    """Why ``given`` (variants) do not fit ``declared``, in words: the values as sent and the
    declared arguments with their types (``('500', True, 1) are not of the declared types
    (Number Int32, Value Double, Path Int32)``), never a variant's repr."""

    def shown(v: Any) -> str:
        value = v.Value if isinstance(v, ua.Variant) else v
        return "an empty variant" if value is None else repr(value)

    types = ", ".join(
        f"{a.Name} {ua.ObjectIdNames.get(a.DataType.Identifier, a.DataType)}" for a in declared
    )
    values = f"({', '.join(shown(v) for v in given)})"
    if len(given) != len(declared):
        return f"{len(given)} arguments {values}; expected {len(declared)} ({types})"
    return f"its arguments {values} are not of the declared types ({types})"


async def _run(told: str, call: Callable[[], Awaitable[None]]) -> Result:
    try:
        await call()
    except (PermissionError, FocasError, ValueError, TypeError) as exc:
        log.info("OPC UA: %s refused: %s", told, exc)
        return refusal(exc)
    return []


_V = ua.VariantType
#: The variant types an argument of each data type takes: any integer for an Int32 (a client
#: may send the number as Int16 or UInt16), an integer or a float for a Double, a String.
_TAKES: Final[dict[int, frozenset[ua.VariantType]]] = {
    ua.ObjectIds.Int32: frozenset(
        {_V.SByte, _V.Byte, _V.Int16, _V.UInt16, _V.Int32, _V.UInt32, _V.Int64, _V.UInt64}
    ),
    ua.ObjectIds.Double: frozenset(
        {_V.SByte, _V.Byte, _V.Int16, _V.UInt16, _V.Int32, _V.UInt32, _V.Int64, _V.UInt64}
        | {_V.Float, _V.Double}
    ),
    ua.ObjectIds.String: frozenset({_V.String}),
}


def arguments(given: tuple[Any, ...], declared: list[ua.Argument]) -> list[Any] | Result:
    """The values of the call's input arguments ``given`` (variants) against the method's
    ``declared`` ones; or, for a call no write may come of, its result: BadArgumentsMissing,
    BadTooManyArguments, or BadInvalidArgument with BadTypeMismatch for each argument of
    another type (a Boolean, text for a number, an array), as OPC UA's Call service has it."""
    if len(given) < len(declared):
        return ua.StatusCode(ua.StatusCodes.BadArgumentsMissing)
    if len(given) > len(declared):
        return ua.StatusCode(ua.StatusCodes.BadTooManyArguments)
    results = [
        ua.StatusCode()
        if isinstance(v, ua.Variant)
        and v.VariantType in _TAKES[a.DataType.Identifier]
        and not v.is_array
        and v.Value is not None
        else ua.StatusCode(ua.StatusCodes.BadTypeMismatch)
        for v, a in zip(given, declared, strict=True)
    ]
    if all(r.is_good() for r in results):
        return [v.Value for v in given]
    bad = ua.CallMethodResult()
    bad.StatusCode = _INVALID
    bad.InputArgumentResults = results
    return bad


def _arg(name: str, dtype: int, text: str) -> ua.Argument:
    return ua.Argument(
        Name=name, DataType=ua.NodeId(dtype), ValueRank=-1, Description=ua.LocalizedText(text)
    )


async def add_write_methods(root: Node, ns: int, writer: Writer, machine: str) -> None:
    """Add the three methods to ``root``, the object of ``machine`` (node ids
    ``<root>/WriteMacro`` ... in namespace ``ns``). A call's arguments are checked against
    the declared ones first (:func:`arguments`), then by the writer's gates and checks."""

    def method(
        name: str, declared: list[ua.Argument], write: Callable[..., Awaitable[None]]
    ) -> Callable[..., Awaitable[Result]]:
        told = f"{machine} {name}"

        async def called(parent: Any, *given: Any) -> Result:
            values = arguments(given, declared)
            if not isinstance(values, list):
                log.info("OPC UA: %s refused: %s", told, _given_text(given, declared))
                return values
            return await _run(told, lambda: write(*values))

        return called

    async def write_macro(number: int, value: float, path: int) -> None:
        await writer.write_macro(machine, number, Decimal(repr(float(value))), path)

    async def write_param(number: int, axis: int, value: int) -> None:
        await writer.write_param(machine, number, value, axis)

    async def write_pmc(area: str, address: int, value: int) -> None:
        await writer.write_pmc(machine, area, address, value)

    i32, dbl, txt = ua.ObjectIds.Int32, ua.ObjectIds.Double, ua.ObjectIds.String
    methods: tuple[tuple[str, Any, list[ua.Argument]], ...] = (
        (
            "WriteMacro",
            write_macro,
            [
                _arg("Number", i32, "macro variable number"),
                _arg("Value", dbl, "value"),
                _arg("Path", i32, "path (channel) number"),
            ],
        ),
        (
            "WriteParameter",
            write_param,
            [
                _arg("Number", i32, "parameter number"),
                _arg("Axis", i32, "axis number, 0 for a parameter of no axis"),
                _arg("Value", i32, "value"),
            ],
        ),
        (
            "WritePmc",
            write_pmc,
            [
                _arg("Area", txt, "PMC area letter (G, R, D, ...)"),
                _arg("Address", i32, "byte address"),
                _arg("Value", i32, "byte value 0..255"),
            ],
        ),
    )
    for name, write, args in methods:
        nid = ua.NodeId(f"{root.nodeid.Identifier}/{name}", ns)
        await root.add_method(nid, ua.QualifiedName(name, ns), method(name, args, write), args, [])
