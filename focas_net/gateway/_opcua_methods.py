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

__all__ = ["add_write_methods", "refusal"]

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


async def _run(call: Callable[[], Awaitable[None]]) -> Result:
    try:
        await call()
    except (PermissionError, FocasError, ValueError, TypeError) as exc:
        log.info("opcua: a write was refused: %s", exc)
        return refusal(exc)
    return []


def _arg(name: str, dtype: int, text: str) -> ua.Argument:
    return ua.Argument(
        Name=name, DataType=ua.NodeId(dtype), ValueRank=-1, Description=ua.LocalizedText(text)
    )


async def add_write_methods(root: Node, ns: int, writer: Writer, machine: str) -> None:
    """Add the three methods to ``root``, the object of ``machine`` (node ids
    ``<root>/WriteMacro`` ... in namespace ``ns``)."""

    async def write_macro(parent: Any, number: Any, value: Any, path: Any) -> Result:
        async def call() -> None:
            decimal = Decimal(repr(float(value.Value)))
            await writer.write_macro(machine, int(number.Value), decimal, int(path.Value))

        return await _run(call)

    async def write_param(parent: Any, number: Any, axis: Any, value: Any) -> Result:
        async def call() -> None:
            await writer.write_param(machine, int(number.Value), int(value.Value), int(axis.Value))

        return await _run(call)

    async def write_pmc(parent: Any, area: Any, address: Any, value: Any) -> Result:
        async def call() -> None:
            await writer.write_pmc(machine, str(area.Value), int(address.Value), int(value.Value))

        return await _run(call)

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
    for name, func, args in methods:
        nid = ua.NodeId(f"{root.nodeid.Identifier}/{name}", ns)
        await root.add_method(nid, ua.QualifiedName(name, ns), func, args, [])
