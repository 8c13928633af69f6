"""Writes to machines through the configuration's write gates: :class:`GatedWriter`, the
:class:`~focas_net.gateway.model.Writer` the outputs (the OPC UA methods) write through.

A write is first held against the machine's :class:`~focas_net.gateway.config.WriteGates`
(``[machine.writes]``: nothing may be written unless it says so); a write outside them raises
``PermissionError`` naming the machine, the gate and the value asked, and nothing is sent.
Then it is the client's write, with the client's checks of the values and the CNC's refusals
(:class:`~focas_net.errors.CncError` for an EW code, a connection error for a lost machine).
A refusal of the CNC (of a parameter, a macro or a PMC write) carries its reason after the
code, in the command line's words (:mod:`focas_net._refusals`): ``EW_DATA (5): data error:
cnc_wrparam; the CNC refused 1000000000 for parameter 6711: outside its range 0..999999999``.
"""

from __future__ import annotations

from collections.abc import Awaitable, Callable
from decimal import Decimal
from functools import partial
from typing import Final

from focas_net._refusals import (
    PARAM_GATE,
    axis_misfit,
    axis_past,
    macro_refusal,
    param_refusal,
)
from focas_net.client import ClientState, FocasClient, NativeClient
from focas_net.client._values import check_int
from focas_net.errors import EW, CncError, FocasConnectionError, FocasError
from focas_net.protocol import PmcArea

from .config import MachineConfig

__all__ = ["GatedWriter"]


def _ranges(ranges: tuple[tuple[int, int], ...]) -> str:
    return ", ".join(str(a) if a == b else f"{a}..{b}" for a, b in ranges)


class GatedWriter:
    """A :class:`~focas_net.gateway.model.Writer` over ``machine(name)``, which gives a
    machine's configuration and client (``KeyError`` naming an unknown machine), such as
    :meth:`Gateway.machine <focas_net.gateway.run.Gateway.machine>`."""

    def __init__(
        self, machine: Callable[[str], tuple[MachineConfig, FocasClient | NativeClient]]
    ) -> None:
        self._machine = machine

    async def write_macro(self, machine: str, number: int, value: Decimal, path: int) -> None:
        """``cnc_wrmacro`` of ``#number`` on ``path``, if ``writes.macros`` allows it."""
        config, client = self._machine(machine)
        _gate(machine, "macros", config.writes.macros, number, f"#{number}", "macro variables")
        why = partial(macro_refusal, number=number, value=value)
        write = partial(client.write_macro, number, value, path=path)
        await _said(_sent(machine, client, write), why)

    async def write_param(self, machine: str, number: int, value: int, axis: int) -> None:
        """``cnc_wrparam`` of parameter ``number`` (``axis`` 0: not an axis parameter), if
        ``writes.params`` allows it."""
        config, client = self._machine(machine)
        shown = f"parameter {number}"
        _gate(machine, "params", config.writes.params, number, shown, "parameters")
        why = partial(
            param_refusal, number=number, value=value, axis=axis, protocol=config.protocol
        )
        try:
            write = partial(client.write_param, number, value, axis=axis)
            await _said(_sent(machine, client, write), why)
        except CncError as exc:
            if exc.ew != EW.ATTRIB:
                raise
            raise await _axis_said(client, exc, number, axis) from exc

    async def write_pmc(self, machine: str, area: str, address: int, value: int) -> None:
        """``pmc_wrpmcrng`` of one byte, if ``writes.pmc`` allows ``area`` ``address``."""
        config, client = self._machine(machine)
        letter = PmcArea.parse(area).name
        gates = config.writes.pmc
        if not any(a == letter and first <= address <= last for a, first, last in gates):
            allowed = ", ".join(f"{a}{f}-{a}{t}" if f != t else f"{a}{f}" for a, f, t in gates)
            raise PermissionError(
                f"{machine}: writes.pmc does not allow {letter}{address} "
                f"({'allowed: ' + allowed if allowed else 'no PMC byte may be written'})"
            )
        byte = check_int("PMC byte value", value, 0, 0xFF)
        write = partial(client.write_pmc, letter, address, bytes([byte]))
        await _sent(machine, client, write)  # (its refusal names why)


#: EW_PASSWD of a parameter write: the gate, and that the gateway cannot unlock a password.
_PARAM_GATE: Final = (
    f"{PARAM_GATE} at the CNC; the gateway sends no parameter password (a CNC that has one "
    "takes no parameter write from it)"
)


async def _said(write: Awaitable[None], why: Callable[[int], str | None]) -> None:
    """``write``; a refusal of the CNC again with ``why(ew)``, its reason, after the code."""
    try:
        await write
    except CncError as exc:
        said = why(exc.ew)
        said = _PARAM_GATE if said == PARAM_GATE else said
        if said is None:
            raise
        call = _call(exc)  # (the client's words of the reason, said once: the gateway's)
        raise CncError.from_ew(exc.ew, f"{call}; {said}" if call else said) from exc


def _call(exc: CncError) -> str:
    """The call a client's refusal names, without the reason its words give after it."""
    return exc.detail.partition(": ")[0]


async def _axis_said(
    client: FocasClient | NativeClient, exc: CncError, number: int, axis: int
) -> CncError:
    """EW_ATTRIB of parameter ``number`` written with ``axis``, again with which Axis to give
    (the path's axes, as its positions name them, as the command line counts them, and as it
    words them for an axis past the path's); ``exc`` itself when they cannot be read."""
    try:
        axes = len((await client.read_positions()).values)
    except FocasError:
        return exc
    if axis > axes:
        said = f"{axis_past(axis, axes)}: give Axis 1..{axes}"
    else:
        give = f"give Axis 1..{axes}" if axis == 0 else "give Axis 0"
        said = f"{axis_misfit('parameter', number, axis)}: {give}"
    return CncError.from_ew(exc.ew, f"{_call(exc)}; {said}")


#: The deadline of a write while the client is not connected: its checks of the values run,
#: then it is refused at once rather than waiting for a reconnect.
_AT_ONCE: Final = 1e-6


async def _sent(
    machine: str,
    client: FocasClient | NativeClient,
    write: Callable[..., Awaitable[None]],
) -> None:
    """``write(timeout=...)``, refused at once (after the client's checks of the values) with
    why when ``client`` is not connected: it would wait out its timeout for a reconnect (and
    an OPC UA session's other requests with it), where FANUC's library answers a call on a
    lost handle at once."""
    if client.state is ClientState.CONNECTED:
        await write(timeout=None)
        return
    try:
        await write(timeout=_AT_ONCE)
    except FocasConnectionError as exc:  # (waiting for the link: nothing was sent)
        causes = [str(e) for e in (client.lost_reason, client.reconnect_error) if e]
        why = f" ({'; '.join(causes)})" if causes else ""
        raise FocasConnectionError(
            f"{machine}: not connected to {client.address}{why}: nothing was written"
        ) from exc


def _gate(
    machine: str, key: str, gates: tuple[tuple[int, int], ...], number: int, shown: str, what: str
) -> None:
    """``PermissionError`` unless ``number`` is within one of ``gates`` (``writes.<key>``)."""
    if not any(a <= number <= b for a, b in gates):
        allowed = f"allowed: {_ranges(gates)}" if gates else f"no {what} may be written"
        raise PermissionError(f"{machine}: writes.{key} does not allow {shown} ({allowed})")
