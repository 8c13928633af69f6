"""The simulator control commands of a client, as ``client.sim`` (``docs/protocol.md``)."""

# Every call takes a per-call ``timeout=`` by contract, so ASYNC109 does not apply here.
# ruff: noqa: ASYNC109

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Final

from .._refusals import cycle_refusal, parts_refusal, system_read_only
from .._typed import alarm_axis_unfit, override_percent, override_unfit
from ..errors import EW, CncError
from ..protocol import (
    COMMANDS,
    AlarmType,
    ArmedFault,
    AutMode,
    ClearAlarms,
    CycleAction,
    CycleControl,
    FaultKind,
    FaultScope,
    FaultsRequest,
    InjectFault,
    Overrides,
    PmcArea,
    RaiseAlarm,
    SetPanel,
    StatusInfo,
    VacateMacro,
    alarm_message,
)
from ..protocol import Command as C
from ..protocol.faults import fault_refusal, scope_refusal
from ._composite import with_reason
from ._pmc import write_pmc_range
from ._values import (
    AreaLike,
    alarm_type_number,
    check_alarm_axis,
    check_int,
    number_of_name,
    pmc_data,
)

if TYPE_CHECKING:
    from .client import FocasClient

__all__ = ["PanelSwitches", "SimControl"]

_UNCHANGED: Final = -1
#: The macro variables of the parts count and the total parts, which always hold a number.
_PARTS_VARIABLES: Final = (3901, 3902)
_I16_MAX: Final = 0x7FFF


def mode_of(status: StatusInfo) -> str | None:
    """The name of the mode of ``status`` (``EDIT``), as the machine names it; None for a
    number no mode has."""
    return AutMode(status.aut).name if status.aut in AutMode._value2member_map_ else None


@dataclass(frozen=True, slots=True)
class PanelSwitches:
    """The operator panel's switches (:meth:`SimControl.read_panel`): ``mode`` an
    :class:`~focas_net.protocol.AutMode` (an ``int`` for a number it has no member for)."""

    mode: AutMode | int
    pwe: bool
    emergency: bool


def _switch(what: str, value: bool | None) -> int:
    if value is None:
        return _UNCHANGED
    if not isinstance(value, int):
        raise TypeError(f"{what} must be True, False or None (unchanged), got {value!r}")
    if value not in (0, 1):
        raise ValueError(f"{what} must be True, False or None (unchanged), got {value!r}")
    return int(value)


_SET_PANEL: Final = COMMANDS[C.SIM_SET_PANEL]
_READ_PANEL: Final = COMMANDS[C.SIM_READ_PANEL]
_CYCLE: Final = COMMANDS[C.SIM_CYCLE]
_OVERRIDES: Final = COMMANDS[C.SIM_SET_OVERRIDES]
_RAISE_ALARM: Final = COMMANDS[C.SIM_RAISE_ALARM]
_CLEAR_ALARMS: Final = COMMANDS[C.SIM_CLEAR_ALARMS]
_SET_PMC: Final = COMMANDS[C.SIM_SET_PMC]
_INJECT_FAULT: Final = COMMANDS[C.SIM_INJECT_FAULT]
_LIST_FAULTS: Final = COMMANDS[C.SIM_LIST_FAULTS]
_CLEAR_FAULTS: Final = COMMANDS[C.SIM_CLEAR_FAULTS]
_VACATE_MACRO: Final = COMMANDS[C.SIM_VACATE_MACRO]
#: The refusals of a cycle start whose reason the status tells.
_TOLD: Final = (EW.MODE, EW.ALARM)


class SimControl:
    """The simulator control commands (0x0E01..0x0E07, 0x0E10, 0x0E11, 0x0E20 and 0x0E21), as
    ``client.sim``.

    A real CNC, or a server with control disabled, answers them with ``EW_FUNC``.
    """

    __slots__ = ("_client",)

    def __init__(self, client: FocasClient) -> None:
        self._client = client

    def __repr__(self) -> str:
        return f"<SimControl of {self._client!r}>"

    async def set_panel(
        self,
        mode: AutMode | str | int | None = None,
        *,
        pwe: bool | None = None,
        emergency: bool | None = None,
        path: int | None = None,
        timeout: float | None = None,
    ) -> None:
        """Set the operator panel: ``mode`` (an ``aut`` value or name: ``"MDI"``, ``AutMode.MEM``,
        ``3``...; :meth:`AutMode.parse_panel`), parameter write enable and emergency stop. A
        switch not given (None) stays as it is (the command carries -1 for it:
        ``docs/protocol.md`` section 8)."""
        aut = _UNCHANGED if mode is None else int(AutMode.parse_panel(mode))
        payload = _SET_PANEL.request.encode(
            SetPanel(aut, _switch("pwe", pwe), _switch("emergency", emergency))
        )
        client = self._client
        await client._request(_SET_PANEL, payload, timeout, client._path_of(path))

    async def read_panel(
        self, *, path: int | None = None, timeout: float | None = None
    ) -> PanelSwitches:
        """The operator panel's switches: mode, parameter write enable, emergency stop."""
        client = self._client
        panel: SetPanel = await client._request(_READ_PANEL, b"", timeout, client._path_of(path))
        mode = AutMode(panel.mode) if panel.mode in AutMode._value2member_map_ else panel.mode
        return PanelSwitches(mode, bool(panel.pwe), bool(panel.emergency))

    async def vacate_macro(
        self, number: int, *, path: int | None = None, timeout: float | None = None
    ) -> None:
        """Make macro variable ``#number`` vacant (``cnc_wrmacro`` has no way to write a vacant
        value). EW_NUMBER for an unknown variable, EW_PROT for a read-only one or a read-only
        server."""
        check_int("macro variable number", number, -0x8000, 0x7FFF)
        payload = _VACATE_MACRO.request.encode(VacateMacro(number))
        client = self._client
        try:
            await client._request(_VACATE_MACRO, payload, timeout, client._path_of(path))
        except CncError as exc:
            # the packed answer carries the code only: the machine's reason, in its words
            why = None
            if exc.ew == EW.DATA and number in _PARTS_VARIABLES:
                why = parts_refusal(number, None)
            elif exc.ew == EW.PROT:
                why = system_read_only(number)  # one of FANUC's read-only variables
            if why is None:
                raise
            raise CncError.from_ew(exc.ew, f"{exc.detail}: {why}") from None

    async def raise_alarm(
        self,
        alm_type: AlarmType | str | int,
        alm_no: int,
        msg: str = "",
        *,
        axis_no: int = 0,
        path: int | None = None,
        timeout: float | None = None,
    ) -> None:
        """Raise an alarm: ``alm_type`` by name (``"PS"``), as an :class:`AlarmType` or a
        number 0..31; ``alm_no`` 0..32767; ``axis_no`` 0 (the whole CNC) or 1..n; ``msg``
        ASCII text of one line (ValueError otherwise, in the machine's words for a control
        character, before anything is sent).

        A CNC shows one entry per alarm: when the same ``(axis_no, alm_type, alm_no)`` is
        active, nothing changes (it keeps its first message)."""
        t = alarm_type_number(alm_type)
        check_int("alarm number", alm_no, 0, _I16_MAX)
        check_alarm_axis(axis_no)
        raw = alarm_message(msg)
        payload = _RAISE_ALARM.request.encode(RaiseAlarm(axis_no, t, alm_no, raw))
        client = self._client
        p = client._path_of(path)
        deadline = client._deadline(timeout)
        try:
            await client._request_at(_RAISE_ALARM, payload, deadline, path=p)
        except CncError as exc:
            if exc.ew != EW.ATTRIB or axis_no == 0:
                raise
            unfit = await self._axis_unfit(axis_no, p, deadline)
            if unfit is None:
                raise
            raise CncError.from_ew(exc.ew, f"{exc.detail}: {unfit}") from None

    async def _axis_unfit(self, axis_no: int, path: int, deadline: float | None) -> str | None:
        """Why the CNC refused an alarm of axis ``axis_no`` on ``path`` with EW_ATTRIB, in the
        machine's words with the path's axis count (a packed answer carries the code only, so
        the count is read, within the call's deadline); None when it cannot be read."""
        axes = await self._client._axis_count(path, deadline)
        return None if axes is None else alarm_axis_unfit(axis_no, axes)

    async def clear_alarms(
        self,
        alm_type: AlarmType | str | int = -1,
        alm_no: int = -1,
        *,
        path: int | None = None,
        timeout: float | None = None,
    ) -> None:
        """Clear the matching active alarms (-1 matches any; ``alm_type`` also by name,
        ``"PS"``); the history is kept."""
        t = alarm_type_number(alm_type, every=True)
        check_int("alarm number", alm_no, -1, _I16_MAX)  # -1: any, as the machine words it
        payload = _CLEAR_ALARMS.request.encode(ClearAlarms(t, alm_no))
        client = self._client
        await client._request(_CLEAR_ALARMS, payload, timeout, client._path_of(path))

    async def _cycle(self, action: CycleAction, path: int | None, timeout: float | None) -> None:
        client = self._client
        payload = _CYCLE.request.encode(CycleControl(action))
        await client._request(_CYCLE, payload, timeout, client._path_of(path))

    async def cycle_start(self, *, path: int | None = None, timeout: float | None = None) -> None:
        """Cycle start (0x0E20): run the main program, continue it, or resume after a feed
        hold. EW_MODE outside MEM, EW_ALARM with an alarm or emergency stop (reset first),
        EW_DATA without a main program: raised with the machine's reason (the mode, or
        whether the emergency stop is on, read from the status after the refusal)."""
        client = self._client
        p, deadline = client._path_of(path), client._deadline(timeout)
        payload = _CYCLE.request.encode(CycleControl(CycleAction.START))
        try:
            await client._request_at(_CYCLE, payload, deadline, path=p)
        except CncError as exc:
            raise with_reason(exc, await self._not_started(exc.ew, p, deadline)) from None

    async def _not_started(self, ew: int, path: int, deadline: float | None) -> str | None:
        """Why a cycle start of ``path`` was answered ``ew``, in the machine's words: the
        packed answer carries the code only, so the status is read (within the call's
        deadline) for the mode or the emergency stop; without it, what the code alone says."""
        status = await self._client._status_now(path, deadline) if ew in _TOLD else None
        if status is None:
            return cycle_refusal(ew)
        return cycle_refusal(ew, mode=mode_of(status), emergency=bool(status.emergency))

    async def feed_hold(self, *, path: int | None = None, timeout: float | None = None) -> None:
        """Feed hold (0x0E20): the axes stop where they are; cycle start resumes."""
        await self._cycle(CycleAction.HOLD, path, timeout)

    async def reset(self, *, path: int | None = None, timeout: float | None = None) -> None:
        """Reset (0x0E20): stop and rewind; the program's alarms are cleared."""
        await self._cycle(CycleAction.RESET, path, timeout)

    async def set_overrides(
        self,
        *,
        feed: int | None = None,
        rapid: int | str | None = None,
        spindle: int | None = None,
        path: int | None = None,
        timeout: float | None = None,
    ) -> None:
        """Feed override 0..254 %, rapid override 0 (F0), 25, 50 or 100 %, spindle override
        0..254 % (0x0E21); an override not given stays as it is. The rapid override also takes
        the name of its slowest step as the command line and the page read it, ``"F0"`` (any
        case; ``"F25"`` is a ValueError listing the steps). A value
        out of range (a rapid override between the steps) is a ValueError in the machine's
        words, a value of another type a TypeError, both before anything is sent."""
        values = []
        for what, value in (("feed", feed), ("rapid", rapid), ("spindle", spindle)):
            if value is None:
                values.append(_UNCHANGED)
                continue
            percent = override_percent(what, value)
            unfit = override_unfit(what, percent)
            if unfit is not None:
                raise ValueError(unfit)  # the machine's words
            values.append(percent)
        client = self._client
        payload = _OVERRIDES.request.encode(Overrides(*values))
        await client._request(_OVERRIDES, payload, timeout, client._path_of(path))

    async def set_pmc(
        self, area: AreaLike, start: int, data: bytes, *, timeout: float | None = None
    ) -> None:
        """Write PMC bytes ignoring write protection (to drive X and F inputs); chunked like
        :meth:`FocasClient.write_pmc`."""
        a = PmcArea.parse(area)
        raw = pmc_data(start, data)
        client = self._client
        await write_pmc_range(client, _SET_PMC, a, start, raw, client._deadline(timeout))

    async def inject_fault(
        self,
        kind: FaultKind | str | int,
        *,
        count: int = 1,
        arg: int = 0,
        scope: FaultScope | str | int = FaultScope.CONNECTION,
        timeout: float | None = None,
    ) -> None:
        """Make the next ``count`` answers misbehave (see :class:`FaultKind`); ``kind`` and
        ``scope`` as members, names (``"drop"``, ``"machine"``) or numbers.

        Faults queue first in, first out in their scope: a fault armed behind others applies
        once those are used up (:meth:`list_faults` shows the queue). ``count`` and ``arg``
        are integers (TypeError, naming them, for another type). The server checks the
        numbers (an unknown kind or scope, a count outside 1..10000, an arg outside the kind's
        range answer EW_DATA, raised with the reason the command line gives), as it does for
        every front end.
        """
        k, s = _fault_number(FaultKind, kind, "kind"), _fault_number(FaultScope, scope, "scope")
        for what, value in (("count", count), ("arg", arg)):
            if isinstance(value, bool) or not isinstance(value, int):
                raise TypeError(f"{what} must be an integer, got {value!r}")
        payload = _INJECT_FAULT.request.encode(InjectFault(k, s, count, arg))
        client = self._client
        try:
            await client._request(_INJECT_FAULT, payload, timeout)
        except CncError as exc:
            # a packed answer carries the code only: EW_DATA told with the server's reason,
            # in the words the command line and the dashboard give it
            why = fault_refusal(k, s, count, arg) if exc.ew == EW.DATA else None
            if why is None:
                raise
            raise CncError.from_ew(exc.ew, f"{exc.detail}: {why}") from None

    async def list_faults(
        self, scope: FaultScope | str | int = FaultScope.CONNECTION, *, timeout: float | None = None
    ) -> tuple[ArmedFault, ...]:
        """The pending faults of ``scope``, the one applying to the next answer first; each
        with its ``kind`` (a :class:`FaultKind` when known), the answers it still applies to
        (``remaining``) and its ``arg``. ``scope`` as :meth:`inject_fault` takes it (a member,
        ``"connection"``/``"machine"`` or a number; the server refuses one it does not know
        with EW_DATA)."""
        payload = _LIST_FAULTS.request.encode(
            FaultsRequest(_fault_number(FaultScope, scope, "scope"))
        )
        client = self._client
        try:
            listing = await client._request(_LIST_FAULTS, payload, timeout)
        except CncError as exc:
            raise _scope_refused(exc, scope) from None
        return tuple(_typed(f) for f in listing.faults)

    async def clear_faults(
        self, scope: FaultScope | str | int = FaultScope.CONNECTION, *, timeout: float | None = None
    ) -> int:
        """Remove the pending faults of ``scope`` (as :meth:`list_faults` takes it); returns
        how many were removed."""
        payload = _CLEAR_FAULTS.request.encode(
            FaultsRequest(_fault_number(FaultScope, scope, "scope"))
        )
        client = self._client
        try:
            answer = await client._request(_CLEAR_FAULTS, payload, timeout)
        except CncError as exc:
            raise _scope_refused(exc, scope) from None
        return int(answer.cleared)


def _scope_refused(exc: CncError, scope: object) -> CncError:
    """``exc`` (a fault listing or clearing refused), told with the server's reason for
    EW_DATA as :meth:`SimControl.inject_fault` tells it: the packed answer carries the code
    only."""
    if exc.ew != EW.DATA or not isinstance(scope, int):
        return exc
    why = scope_refusal(int(scope))
    return exc if why is None else CncError.from_ew(exc.ew, f"{exc.detail}: {why}")


def _fault_number(names: type[FaultKind | FaultScope], given: object, what: str) -> int:
    """The number of a fault kind or scope given as a member, a name or a number: ValueError
    for an unknown name, TypeError for anything else, each naming what was given. A number
    goes as it is (the server refuses one it does not know)."""
    if isinstance(given, str):
        return number_of_name(names, given, f"fault {what}", "its number")
    if isinstance(given, bool) or not isinstance(given, int):
        raise TypeError(
            f"fault {what} must be a {names.__name__}, its name or its number, got {given!r}"
        )
    return int(given)


def _typed(fault: ArmedFault) -> ArmedFault:
    try:
        kind = FaultKind(fault.kind)
    except ValueError:
        return fault  # a kind this client does not know: its number
    return ArmedFault(kind, fault.remaining, fault.arg)
