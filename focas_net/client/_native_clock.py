"""The native client's calls of the CNC's clock and the operator panel's signals.

:class:`NativeClock` is the part of :class:`~focas_net.client.NativeClient` that sends
``cnc_gettimer``, ``cnc_settimer`` (0x45, 0x46) and ``cnc_rdopnlsgnl`` (0x5D), the frames
FANUC's library sends in both command sets (:mod:`focas_net.native.clock`).
"""

# Every call takes a per-call ``timeout=`` by contract, so ASYNC109 does not apply here.
# ruff: noqa: ASYNC109

from __future__ import annotations

from datetime import date, time

from .._typed import cnc_year_unfit
from ..errors import EW, CncError
from ..native import (
    CLOCK_DATE,
    CLOCK_TIME,
    ClockValue,
    LibraryCall,
    PanelSignals,
    cnc_gettimer,
    cnc_rdopnlsgnl,
    cnc_settimer,
)
from ._native_items import only_answer
from ._native_link import NativeLink
from ._values import I16_MAX, check_int

__all__: list[str] = []

#: IODBSGNL's data select bits: every signal (``mode`` .. ``feed_hold``).
ALL_SIGNALS = 0x1FFF


class NativeClock(NativeLink):
    """The CNC's clock and the panel's signals over FOCAS/2 (see the module docstring)."""

    async def _call(self, call: LibraryCall, path: int | None, timeout: float | None) -> object:
        p = self._path_of(path)
        deadline = self._deadline(timeout)
        handle = self._handle_now() or await self._handle_for(deadline)
        return only_answer(handle, call, await self._exchange(handle, call, deadline, 0, p))

    async def read_date(self, *, path: int | None = None, timeout: float | None = None) -> date:
        """``cnc_gettimer`` type 0: the CNC's date."""
        value = await self._call(cnc_gettimer(CLOCK_DATE), path, timeout)
        assert isinstance(value, ClockValue)
        return date(value.year, value.month, value.day)

    async def read_time(self, *, path: int | None = None, timeout: float | None = None) -> time:
        """``cnc_gettimer`` type 1: the CNC's time of day."""
        value = await self._call(cnc_gettimer(CLOCK_TIME), path, timeout)
        assert isinstance(value, ClockValue)
        return time(value.hour, value.minute, value.second)

    async def write_date(
        self, day: date, *, path: int | None = None, timeout: float | None = None
    ) -> None:
        """``cnc_settimer`` type 0: set the CNC's date (its time of day runs on).

        :raises TypeError: ``day`` is no :class:`datetime.date` (naming what was given).
        :raises CncError: EW_PROT (a read-only machine), EW_DATA (a year the CNC's calendar
            does not have, the detail naming its years, ``year 1900 is outside 1987..2037``).
        """
        if not isinstance(day, date):
            raise TypeError(f"the date must be a datetime.date, got {day!r}")
        value = ClockValue(day.year, day.month, day.day, 0, 0, 0)
        try:
            await self._call(cnc_settimer(CLOCK_DATE, value), path, timeout)
        except CncError as exc:  # the answer carries the code: the reason the client knows
            why = cnc_year_unfit(day.year) if exc.ew == EW.DATA else None
            if why is None:
                raise
            raise CncError.from_ew(exc.ew, f"{exc.detail}: {why}") from None

    async def write_time(
        self, moment: time, *, path: int | None = None, timeout: float | None = None
    ) -> None:
        """``cnc_settimer`` type 1: set the CNC's time of day (whole seconds; its date stays).

        :raises TypeError: ``moment`` is no :class:`datetime.time` (naming what was given).
        :raises CncError: EW_PROT (a read-only machine).
        """
        if not isinstance(moment, time):
            raise TypeError(f"the time of day must be a datetime.time, got {moment!r}")
        value = ClockValue(0, 0, 0, moment.hour, moment.minute, moment.second)
        await self._call(cnc_settimer(CLOCK_TIME, value), path, timeout)

    async def read_panel_signals(
        self,
        select: int = ALL_SIGNALS,
        *,
        path: int | None = None,
        timeout: float | None = None,
    ) -> PanelSignals:
        """``cnc_rdopnlsgnl``: the operator panel's signals (IODBSGNL after ``datano`` and
        ``type``; ``select`` is its data select bits, 0..0x7FFF)."""
        check_int("signal select bits", select, 0, I16_MAX)
        value = await self._call(cnc_rdopnlsgnl(select), path, timeout)
        assert isinstance(value, PanelSignals)
        return value
