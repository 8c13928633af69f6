"""What both transports carry: :class:`CncClient`, the static type of "a FOCAS client".

:class:`~focas_net.client.FocasClient` (the packed protocol) and
:class:`~focas_net.client.NativeClient` (FOCAS/2 Ethernet) are separate classes; code that
works with either (the ``focas-net`` commands, :class:`~focas_net.client.AlarmProjection`, a
poller) takes a :class:`CncClient`, which lists the calls both have with the same arguments
and results. It is a :class:`typing.Protocol`: neither client inherits from it, and the type
checker matches them by their methods.
"""

# Every call takes a per-call ``timeout=`` by contract, so ASYNC109 does not apply here.
# ruff: noqa: ASYNC109

from __future__ import annotations

from decimal import Decimal
from types import TracebackType
from typing import Protocol, Self

from ..protocol import (
    ActiveAlarm,
    AlarmHistory,
    ParamValue,
    PmcArea,
    PositionKind,
    ProgramNumbers,
    StatusInfo,
    SysInfo,
)
from ._values import Paths, Positions
from .reconnect import ClientState, ReconnectPolicy, StateCallback

__all__ = ["CncClient"]


class CncClient(Protocol):
    """The calls of a FOCAS client on either transport (see the two clients for each call's
    details); a method one transport lacks is not listed (program store, simulator
    control, parameter unlock, VersaMax records: packed only; ``read_dynamic``, timers, loads:
    native only). Every per-path call takes ``path=`` (1..10; None: the client's
    :attr:`path`)."""

    host: str
    port: int
    path: int

    @property
    def state(self) -> ClientState: ...

    @property
    def reconnect_policy(self) -> ReconnectPolicy | None: ...

    @property
    def lost_reason(self) -> BaseException | None: ...

    @property
    def reconnect_error(self) -> BaseException | None: ...

    def add_state_callback(self, callback: StateCallback) -> None: ...

    def remove_state_callback(self, callback: StateCallback) -> None: ...

    async def connect(self) -> None: ...

    async def aclose(self) -> None: ...

    async def __aenter__(self) -> Self: ...

    async def __aexit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None: ...

    async def read_status(
        self, *, path: int | None = None, timeout: float | None = None
    ) -> StatusInfo: ...

    async def read_sysinfo(self, *, timeout: float | None = None) -> SysInfo: ...

    async def read_paths(self, *, timeout: float | None = None) -> Paths: ...

    async def read_program_numbers(
        self, *, path: int | None = None, timeout: float | None = None
    ) -> ProgramNumbers: ...

    async def read_feed(self, *, path: int | None = None, timeout: float | None = None) -> int: ...

    async def read_spindle_speed(
        self, *, path: int | None = None, timeout: float | None = None
    ) -> int: ...

    async def read_positions(
        self,
        kind: PositionKind | str | int = PositionKind.ABSOLUTE,
        *,
        axis: int | None = None,
        path: int | None = None,
        timeout: float | None = None,
    ) -> Positions: ...

    async def read_param_value(
        self, number: int, *, axis: int = 0, path: int | None = None, timeout: float | None = None
    ) -> ParamValue: ...

    async def read_param(
        self, number: int, *, axis: int = 0, path: int | None = None, timeout: float | None = None
    ) -> int: ...

    async def read_param_real(
        self, number: int, *, axis: int = 0, path: int | None = None, timeout: float | None = None
    ) -> Decimal: ...

    async def write_param(
        self,
        number: int,
        value: int | Decimal | str,
        *,
        axis: int = 0,
        width: int | None = None,
        path: int | None = None,
        timeout: float | None = None,
    ) -> None: ...

    async def write_param_bit(
        self,
        number: int,
        bit: int,
        value: bool | int,
        *,
        axis: int = 0,
        path: int | None = None,
        timeout: float | None = None,
    ) -> None: ...

    async def read_diag(
        self, number: int, *, axis: int = 0, path: int | None = None, timeout: float | None = None
    ) -> int: ...

    async def read_macro(
        self, number: int, *, path: int | None = None, timeout: float | None = None
    ) -> Decimal | None: ...

    async def write_macro(
        self,
        number: int,
        value: Decimal | float | int | str,
        *,
        path: int | None = None,
        timeout: float | None = None,
    ) -> None: ...

    async def read_pmc(
        self, area: str | int | PmcArea, start: int, count: int, *, timeout: float | None = None
    ) -> bytes: ...

    async def write_pmc(
        self, area: str | int | PmcArea, start: int, data: bytes, *, timeout: float | None = None
    ) -> None: ...

    async def read_pmc_bit(
        self, area: str | int | PmcArea, byte: int, bit: int, *, timeout: float | None = None
    ) -> bool: ...

    async def write_pmc_bit(
        self,
        area: str | int | PmcArea,
        byte: int,
        bit: int,
        value: bool | int,
        *,
        timeout: float | None = None,
    ) -> None: ...

    async def read_alarms(
        self, *, alm_type: int = -1, path: int | None = None, timeout: float | None = None
    ) -> tuple[ActiveAlarm, ...]: ...

    async def read_alarm_history(
        self, depth: int = 10, *, timeout: float | None = None
    ) -> AlarmHistory: ...
