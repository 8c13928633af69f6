"""The simulator control commands of a client, as ``client.sim`` (``docs/protocol.md``)."""

# Every call takes a per-call ``timeout=`` by contract, so ASYNC109 does not apply here.
# ruff: noqa: ASYNC109

from __future__ import annotations

from typing import TYPE_CHECKING, Final

from ..protocol import (
    COMMANDS,
    ArmedFault,
    AutMode,
    ClearAlarms,
    FaultKind,
    FaultScope,
    FaultsRequest,
    InjectFault,
    RaiseAlarm,
    SetPanel,
)
from ..protocol import Command as C
from ._pmc import AreaLike, write_pmc_range

if TYPE_CHECKING:
    from .client import FocasClient

__all__ = ["SimControl"]

_SET_PANEL: Final = COMMANDS[C.SIM_SET_PANEL]
_RAISE_ALARM: Final = COMMANDS[C.SIM_RAISE_ALARM]
_CLEAR_ALARMS: Final = COMMANDS[C.SIM_CLEAR_ALARMS]
_SET_PMC: Final = COMMANDS[C.SIM_SET_PMC]
_INJECT_FAULT: Final = COMMANDS[C.SIM_INJECT_FAULT]
_LIST_FAULTS: Final = COMMANDS[C.SIM_LIST_FAULTS]
_CLEAR_FAULTS: Final = COMMANDS[C.SIM_CLEAR_FAULTS]


class SimControl:
    """The simulator control commands (0x0E01..0x0E07), as ``client.sim``.

    A real CNC, or a server with control disabled, answers them with ``EW_FUNC``.
    """

    __slots__ = ("_client",)

    def __init__(self, client: FocasClient) -> None:
        self._client = client

    async def set_panel(
        self,
        mode: AutMode | str | int,
        *,
        pwe: bool = False,
        emergency: bool = False,
        timeout: float | None = None,
    ) -> None:
        """Set the operator panel: ``mode`` (an ``aut`` value or name: ``"MDI"``, ``AutMode.MEM``,
        ``3``...), parameter write enable and emergency stop (all three are set)."""
        aut = AutMode.parse(mode)
        payload = _SET_PANEL.request.encode(SetPanel(int(aut), int(pwe), int(emergency)))
        client = self._client
        await client._request(_SET_PANEL, payload, client._deadline(timeout))

    async def raise_alarm(
        self,
        alm_type: int,
        alm_no: int,
        msg: str = "",
        *,
        axis_no: int = 0,
        timeout: float | None = None,
    ) -> None:
        """Raise an alarm (a no-op when the same ``(axis_no, alm_type, alm_no)`` is active)."""
        try:
            raw = msg.encode("ascii")
        except UnicodeEncodeError:
            raise ValueError(f"alarm message must be ASCII: {msg!r}") from None
        payload = _RAISE_ALARM.request.encode(RaiseAlarm(axis_no, alm_type, alm_no, raw))
        client = self._client
        await client._request(_RAISE_ALARM, payload, client._deadline(timeout))

    async def clear_alarms(
        self, alm_type: int = -1, alm_no: int = -1, *, timeout: float | None = None
    ) -> None:
        """Clear the matching active alarms (-1 matches any); the history is kept."""
        payload = _CLEAR_ALARMS.request.encode(ClearAlarms(alm_type, alm_no))
        client = self._client
        await client._request(_CLEAR_ALARMS, payload, client._deadline(timeout))

    async def set_pmc(
        self, area: AreaLike, start: int, data: bytes, *, timeout: float | None = None
    ) -> None:
        """Write PMC bytes ignoring write protection (to drive X and F inputs); chunked like
        :meth:`FocasClient.write_pmc`."""
        client = self._client
        await write_pmc_range(client, _SET_PMC, area, start, data, client._deadline(timeout))

    async def inject_fault(
        self,
        kind: FaultKind | int,
        *,
        count: int = 1,
        arg: int = 0,
        scope: FaultScope | int = FaultScope.CONNECTION,
        timeout: float | None = None,
    ) -> None:
        """Make the next ``count`` answers misbehave (see :class:`FaultKind`).

        Faults queue first in, first out in their scope: a fault armed behind others applies
        once those are used up (:meth:`list_faults` shows the queue).
        """
        payload = _INJECT_FAULT.request.encode(InjectFault(int(kind), int(scope), count, arg))
        client = self._client
        await client._request(_INJECT_FAULT, payload, client._deadline(timeout))

    async def list_faults(
        self, scope: FaultScope | int = FaultScope.CONNECTION, *, timeout: float | None = None
    ) -> tuple[ArmedFault, ...]:
        """The pending faults of ``scope``, the one applying to the next answer first; each
        with its ``kind`` (a :class:`FaultKind` when known), the answers it still applies to
        (``remaining``) and its ``arg``."""
        payload = _LIST_FAULTS.request.encode(FaultsRequest(_scope(scope)))
        client = self._client
        listing = await client._request(_LIST_FAULTS, payload, client._deadline(timeout))
        return tuple(_typed(f) for f in listing.faults)

    async def clear_faults(
        self, scope: FaultScope | int = FaultScope.CONNECTION, *, timeout: float | None = None
    ) -> int:
        """Remove the pending faults of ``scope``; returns how many were removed."""
        payload = _CLEAR_FAULTS.request.encode(FaultsRequest(_scope(scope)))
        client = self._client
        answer = await client._request(_CLEAR_FAULTS, payload, client._deadline(timeout))
        return int(answer.cleared)


def _scope(scope: FaultScope | int) -> int:
    try:
        return int(FaultScope(scope))
    except ValueError:
        raise ValueError(
            f"fault scope must be 0 (connection) or 1 (machine), got {scope!r}"
        ) from None


def _typed(fault: ArmedFault) -> ArmedFault:
    try:
        kind = FaultKind(fault.kind)
    except ValueError:
        return fault  # a kind this client does not know: its number
    return ArmedFault(kind, fault.remaining, fault.arg)
