"""The spindle and servo calls of :class:`~focas_net.client.NativeClient` over FOCAS/2.

:class:`NativeSpindles` reads what FANUC's library reads with ``cnc_rdspmaxrpm``,
``cnc_rdspgear``, ``cnc_acts2``, ``cnc_rdspdlname``, ``cnc_rdspmeter``, ``cnc_rdloopgain``,
``cnc_rdcurrent`` and ``cnc_rdsrvspeed``, with the frames it sends
(:mod:`focas_net.native.spindles`) and the values it takes from the answers:

* a 0x40 figure is the mantissa of each 8-byte record, up to the path's spindles (the open
  answer's count); ``cnc_rdspmaxrpm`` and ``cnc_rdspgear`` keep the low 16 bits (ODBSPN has
  short fields), ``cnc_acts2`` all 32;
* ``cnc_rdspmeter`` gives each spindle's name, load meter (percent) and motor speed (min^-1)
  with the decimals of its record; in the 30i set it is refused (EW_NOOPT, nothing sent) when
  the open answer's controlled spindles are 0, as FANUC's library refuses it;
* a 0x56 figure is the mantissa of each record, up to the path's axes.
"""

# Every call takes a per-call ``timeout=`` by contract, so ASYNC109 does not apply here.
# ruff: noqa: ASYNC109

from __future__ import annotations

from dataclasses import dataclass
from decimal import Decimal
from typing import Final

from focas_net.errors import EW, CncError

from ..native import (
    CommandSet,
    OpenHeadV3,
    ScaledNumber,
    ScaledValues,
    ServoFigure,
    SpindleFigure,
    SpindleNames,
    spindles,
)
from ._native_items import decoded, signed
from ._native_link import Handle, NativeLink
from ._values import check_axis, check_int

__all__ = ["SpindleMeter"]

#: The spindle number of every spindle.
_EVERY: Final = -1
#: The FOCAS function of each servo figure.
_SERVO_CALLS: Final = {
    ServoFigure.LOOP_GAIN: spindles.cnc_rdloopgain,
    ServoFigure.LOAD: spindles.cnc_rdcurrent,
    ServoFigure.SPEED: spindles.cnc_rdsrvspeed,
}


@dataclass(frozen=True, slots=True)
class SpindleMeter:
    """One spindle of ``cnc_rdspmeter``: its name (``"S1"``), its load meter in percent and
    its motor speed in min^-1 (None for the figure not asked)."""

    name: str
    load: Decimal | None
    speed: Decimal | None


def _value(number: ScaledNumber) -> Decimal:
    return Decimal(number.mantissa).scaleb(-max(number.decimals, 0))


def _controlled_spindles(handle: Handle) -> int:
    head = handle.opened.head
    return head.controlled_spindles if isinstance(head, OpenHeadV3) else 1


class NativeSpindles(NativeLink):
    """Spindles and servo figures over FOCAS/2 (see the module docstring)."""

    async def _spindle_figure(
        self,
        figure: SpindleFigure,
        spindle: int,
        width: int,
        path: int | None,
        timeout: float | None,
    ) -> tuple[int, ...]:
        check_axis(spindle, "spindle", every=_EVERY)
        p = self._path_of(path)
        handle, call, blocks = await self._only(
            spindles.cnc_rdspload_figure, p, timeout, figure, spindle
        )
        index = 0 if handle.command_set is CommandSet.FS16I else 1
        for i in range(len(blocks)):
            if i != index and decoded(handle, call, blocks, i, 0).count == 0:
                raise CncError.from_ew(EW.NOOPT, f"{call.function}: no spindle")
        try:
            values: ScaledValues = decoded(handle, call, blocks, index, 0)
        except CncError as exc:
            if exc.ew != EW.NUMBER:
                raise
            count = handle.spindles_on(p)
            raise CncError.from_ew(
                EW.NUMBER, f"{call.function}: spindle {spindle} (the path has {count})"
            ) from None
        limit = handle.spindles_on(p) if spindle == _EVERY else 1
        return tuple(signed(v.mantissa, width) for v in values.values[: max(limit, 1)])

    async def read_spindle_max_speeds(
        self, spindle: int = -1, *, path: int | None = None, timeout: float | None = None
    ) -> tuple[int, ...]:
        """``cnc_rdspmaxrpm``: the top speed (min^-1) of every spindle (``spindle=-1``) or of
        one (1..n)."""
        return await self._spindle_figure(SpindleFigure.MAX_SPEED, spindle, 2, path, timeout)

    async def read_spindle_gears(
        self, spindle: int = -1, *, path: int | None = None, timeout: float | None = None
    ) -> tuple[int, ...]:
        """``cnc_rdspgear``: the gear of every spindle (``spindle=-1``) or of one (1..n)."""
        return await self._spindle_figure(SpindleFigure.GEAR, spindle, 2, path, timeout)

    async def read_spindle_speeds(
        self, spindle: int = -1, *, path: int | None = None, timeout: float | None = None
    ) -> tuple[int, ...]:
        """``cnc_acts2``: the actual speed (min^-1) of every spindle (``spindle=-1``) or of
        one (1..n)."""
        return await self._spindle_figure(SpindleFigure.SPEED, spindle, 4, path, timeout)

    async def read_spindle_names(
        self, *, path: int | None = None, timeout: float | None = None
    ) -> tuple[str, ...]:
        """``cnc_rdspdlname``: the name of every spindle of the path (``"S1"``...)."""
        p = self._path_of(path)
        handle, call, blocks = await self._only(spindles.cnc_rdspdlname, p, timeout)
        names: SpindleNames = decoded(handle, call, blocks, 0, 0)
        return tuple(n.text for n in names.records[: handle.spindles_on(p)])

    async def read_spindle_meters(
        self, kind: int = -1, *, path: int | None = None, timeout: float | None = None
    ) -> tuple[SpindleMeter, ...]:
        """``cnc_rdspmeter``: the name, load meter (``kind`` 0) and motor speed (1) of every
        spindle of the path (-1: both figures)."""
        check_int("kind", kind, -1, 1)
        p = self._path_of(path)
        deadline = self._deadline(timeout)
        handle = self._handle_now() or await self._handle_for(deadline)
        cs = handle.command_set
        if cs is CommandSet.FS30I and _controlled_spindles(handle) == 0:
            raise CncError.from_ew(EW.NOOPT, "cnc_rdspmeter: the CNC controls no spindle")
        call = spindles.cnc_rdspmeter(cs, kind)
        blocks = await self._exchange(handle, call, deadline, 0, p)
        names: SpindleNames | None = None
        figures: dict[int, ScaledValues] = {}
        for i, request in enumerate(call.frames[0]):
            value = decoded(handle, call, blocks, i, 0)
            if isinstance(value, SpindleNames):
                names = value
            elif isinstance(value, ScaledValues):
                figures[request.kind] = value  # type: ignore[attr-defined]
            elif value.count == 0:
                raise CncError.from_ew(EW.NOOPT, "cnc_rdspmeter: no spindle")
        assert names is not None
        count = min(handle.spindles_on(p), len(names.records))

        def figure(which: SpindleFigure, asked: int, i: int) -> Decimal | None:
            values = figures.get(which)
            if kind not in (-1, asked) or values is None or i >= len(values.values):
                return None
            return _value(values.values[i])

        return tuple(
            SpindleMeter(
                names.records[i].text,
                figure(SpindleFigure.LOAD_METER, 0, i),
                figure(SpindleFigure.MOTOR_SPEED, 1, i),
            )
            for i in range(count)
        )

    async def read_servo_figures(
        self, figure: ServoFigure, *, path: int | None = None, timeout: float | None = None
    ) -> tuple[int, ...]:
        """0x56 ``figure`` of every axis of the path: the loop gain in 0.01/s
        (``cnc_rdloopgain``), the load meter in percent (``cnc_rdcurrent``, the figure
        ``cnc_rdsvmeter`` reads), or the motor speed in min^-1 (``cnc_rdsrvspeed``)."""
        if isinstance(figure, bool) or not isinstance(figure, int):
            raise TypeError(
                f"servo figure must be 0 (loop gain), 1 (load) or 2 (speed), got {figure!r}"
            )
        if figure not in _SERVO_CALLS:
            raise ValueError(f"servo figure {figure!r} is not 0 (loop gain), 1 (load) or 2 (speed)")
        figure = ServoFigure(figure)
        p = self._path_of(path)
        handle, call, blocks = await self._only(_SERVO_CALLS[figure], p, timeout)
        values: ScaledValues = decoded(handle, call, blocks, 0, handle.max_axes)
        # cnc_rdcurrent fills shorts (the low 16 bits), the others longs
        width = 2 if figure is ServoFigure.LOAD else 4
        return tuple(signed(v.mantissa, width) for v in values.values[: handle.axes_on(p)])
