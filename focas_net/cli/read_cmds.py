"""The reading commands: ``status``, ``sysinfo``, ``program``, ``position``, ``param get``,
``macro get``, ``diag``, ``pmc read``, ``alarms`` (and ``--follow``) and ``versamax``."""

from __future__ import annotations

import argparse
import json
from decimal import Decimal
from typing import Any, Final

from focas_net._refusals import axis_misfit, path_axes
from focas_net.client import (
    AlarmCleared,
    AlarmHistoryEvent,
    AlarmProjection,
    AlarmRaised,
    CncClient,
    FocasClient,
    NativeClient,
    ProjectionMode,
)
from focas_net.client._values import check_bit, check_int, check_item, check_macro, check_pmc_range
from focas_net.errors import EW, CncError, FocasError
from focas_net.protocol import ParamDataType, ParamValue, PmcArea, PositionKind

from . import _format as fmt
from . import _run
from ._args import PROG, named, typed_number_bit
from ._run import (
    Go,
    HintedError,
    Output,
    PackedOnly,
    report_state,
    stopping_on_signals,
    write,
)

__all__ = [
    "PMC_LAST",
    "alarms",
    "axis_hint",
    "diag",
    "item_name",
    "macro_dict",
    "macro_get",
    "param_get",
    "param_number",
    "param_output",
    "pmc_read",
    "position",
    "program",
    "status",
    "sysinfo",
    "versamax",
]


# -- status and identity --------------------------------------------------------------------


def status(args: argparse.Namespace) -> Go:
    async def go(cnc: CncClient) -> Output:
        st = await cnc.read_status()
        mt_type = fmt.mt_type_text(await cnc.read_sysinfo())  # names tmmode
        rows = fmt.status_rows(st, mt_type)
        table = fmt.render_table(("field", "value", "name", "meaning"), rows)
        return Output(fmt.status_dict(st, mt_type), f"{fmt.status_summary(st)}\n\n{table}")

    return go


def sysinfo(args: argparse.Namespace) -> Go:
    async def go(cnc: CncClient) -> Output:
        info = await cnc.read_sysinfo()
        table = fmt.render_table(("field", "value", "meaning"), fmt.sysinfo_rows(info))
        return Output(fmt.sysinfo_json(info), table)

    return go


# -- program numbers, feed, spindle, positions ----------------------------------------------


def program(args: argparse.Namespace) -> Go:
    async def go(cnc: CncClient) -> Output:
        numbers = await cnc.read_program_numbers()
        feed = await cnc.read_feed()
        speed = await cnc.read_spindle_speed()
        data = fmt.program_dict(numbers, feed, speed)
        return Output(data, fmt.render_table(("item", "value", "meaning"), fmt.program_rows(data)))

    return go


def position(args: argparse.Namespace) -> Go:
    kind = PositionKind.parse(args.kind)

    async def go(cnc: CncClient) -> Output:
        try:
            pos = await cnc.read_positions(kind, axis=args.axis)
        except CncError as exc:
            raise await axis_past(cnc, exc, args.axis) from exc
        data = fmt.positions_dict(pos.kind.name.lower(), pos.decimals, pos.values, pos.increments)
        table = fmt.render_table(("axis", "position", "increments"), fmt.positions_rows(data))
        return Output(data, f"{data['kind']} position\n\n{table}")

    return go


# -- parameters, diagnostics, macros --------------------------------------------------------


async def axis_hint(cnc: CncClient, exc: CncError, kind: str, number: int, axis: int) -> FocasError:
    """``exc`` with advice when it is ``EW_ATTRIB`` for the axis of parameter or diagnostic
    ``number`` (``kind``): an axis item read without ``--axis``, an axis past the machine's,
    or ``--axis`` on an item of no axis; the axis count is the path's (:func:`_axis_count`)."""
    if exc.ew != EW.ATTRIB:
        return exc
    axes = await _axis_count(cnc)
    if axis > axes:
        return HintedError(exc, _axes_text(axes, told=path_axes(axes) in str(exc)))
    give = f"give --axis 1..{axes}" if axis == 0 else "leave out --axis"
    said = axis_misfit(kind, number, axis)
    if said in exc.detail:  # (the client's words of it: said once, the hint's)
        exc = CncError.from_ew(exc.ew, exc.detail.partition(": ")[0])
    return HintedError(exc, f"{said}: {give}")


async def axis_past(cnc: CncClient, exc: CncError, axis: int | None, also: str = "") -> FocasError:
    """``exc`` with advice when it is ``EW_ATTRIB`` for an ``--axis`` past the path's (the
    same words as :func:`axis_hint`'s, then ``also``)."""
    if exc.ew != EW.ATTRIB or axis is None:
        return exc
    axes = await _axis_count(cnc)
    if axis <= axes:
        return exc
    # the count once: where the machine's own words tell it already, only what to give
    told = path_axes(axes) in str(exc)
    return HintedError(exc, f"{_axes_text(axes, told=told)}{also}")


def _axes_text(axes: int, *, told: bool = False) -> str:
    # the machine's words (the path's count: on a machine of several paths not the machine's)
    give = f"give --axis 1..{axes}"
    return give if told else f"{path_axes(axes)}: {give}"


async def _axis_count(cnc: CncClient) -> int:
    """The axes of the path the command reads: those its positions name. Not ODBSYS's count,
    which the packed ``cnc_sysinfo`` gives for the whole machine (every path's axes)."""
    return len((await cnc.read_positions()).values)


def item_name(number: int, bit: int | None, axis: int) -> str:
    """``1815.4 axis 1``: a parameter or diagnostic, its bit and its axis."""
    name = f"{number}" if bit is None else f"{number}.{bit}"
    return f"{name} axis {axis}" if axis else name


def param_output(
    number: int, bit: int | None, axis: int, pv: ParamValue, kind: ParamDataType | None = None
) -> tuple[dict[str, Any], str, str | None]:
    """The JSON data of a parameter read, its text, and the text of its bit (when one);
    ``kind`` is the parameter's type when known (a bit parameter is shown as its bits)."""
    data: dict[str, Any] = fmt.param_dict(number, axis, pv, kind)
    whole = f"{item_name(number, None, axis)} = {fmt.param_text(pv, kind)}"
    if bit is None:
        return data, whole, None
    data["bit"] = bit
    data["bit_value"] = pv.bits >> bit & 1
    return data, whole, f"{item_name(number, bit, axis)} = {data['bit_value']}"


async def param_kind(cnc: CncClient, number: int, pv: ParamValue) -> ParamDataType | None:
    """The type of a parameter read as ``pv``: asked (``cnc_rdparainfo``) for a 1-byte value,
    which may be a bit or a byte parameter; None when the CNC cannot tell."""
    if pv.width == fmt.REAL_WIDTH:
        return ParamDataType.REAL
    if pv.width != 1:
        return None
    if isinstance(cnc, NativeClient):  # FOCAS/2: the type word of the cnc_rdparam record
        return await cnc.read_param_type(number, axis=pv.axis)
    if not isinstance(cnc, FocasClient):
        return None
    try:
        return (await cnc.read_param_attributes(number)).type
    except CncError as exc:
        if exc.ew != EW.FUNC:
            raise
        return None


#: The last PMC address a request carries.
PMC_LAST: Final = 0xFFFF
#: A parameter's argument, as ``--help`` names it.
_PARAM_NUMBER: Final = "NUMBER[.BIT]"


def param_number(args: argparse.Namespace) -> tuple[int, int | None]:
    """``param get|set``'s NUMBER[.BIT], the number one a CNC's field carries (the clients'
    rule, :func:`~focas_net.client._values.check_item`), refused without the CNC naming the
    argument."""
    number, bit = named(_PARAM_NUMBER, typed_number_bit, args, args.number)
    named(_PARAM_NUMBER, check_item, number, args.axis, "parameter")
    return number, bit


def param_get(args: argparse.Namespace) -> Go:
    number, bit = param_number(args)

    async def go(cnc: CncClient) -> Output:
        try:
            pv = await cnc.read_param_value(number, axis=args.axis)
        except CncError as exc:
            raise await axis_hint(cnc, exc, "parameter", number, args.axis) from exc
        if bit is not None and pv.width == fmt.REAL_WIDTH:
            raise ValueError(f"parameter {number} is a real parameter: it has no bits")
        if bit is not None:
            check_bit(bit, pv.width, f"parameter {number}")  # the words of param set's
        kind = await param_kind(cnc, number, pv)
        data, whole, bit_text = param_output(number, bit, args.axis, pv, kind)
        return Output(data, whole if bit_text is None else bit_text)

    return go


def diag(args: argparse.Namespace) -> Go:
    named("NUMBER", check_item, args.number, args.axis, "diagnostic")

    async def go(cnc: CncClient) -> Output:
        try:
            value = await cnc.read_diag(args.number, axis=args.axis)
        except CncError as exc:
            raise await axis_hint(cnc, exc, "diagnostic", args.number, args.axis) from exc
        data = {"number": args.number, "axis": args.axis, "value": value}
        return Output(data, f"{item_name(args.number, None, args.axis)} = {value}")

    return go


def macro_dict(number: int, value: Decimal | None) -> dict[str, Any]:
    """The JSON data of a macro variable (its value as a decimal string, or None when vacant)."""
    return {"number": number, "value": None if value is None else fmt.decimal_text(value)}


def macro_get(args: argparse.Namespace) -> Go:
    named("NUMBER", check_macro, args.number)

    async def go(cnc: CncClient) -> Output:
        value = await cnc.read_macro(args.number)
        return Output(macro_dict(args.number, value), f"#{args.number} = {fmt.macro_text(value)}")

    return go


# -- PMC ------------------------------------------------------------------------------------


def pmc_read(args: argparse.Namespace) -> Go:
    area: PmcArea = args.area
    named("START", check_int, "PMC start address", args.start, 0, PMC_LAST)
    named("COUNT", check_pmc_range, 0, args.count)  # (the count alone: the clients' words)
    check_pmc_range(args.start, args.count)  # (where the bytes end: both arguments)

    async def go(cnc: CncClient) -> Output:
        data = await cnc.read_pmc(area, args.start, args.count)
        out = {
            "area": area.name,
            "start": args.start,
            "count": len(data),
            "hex": data.hex(),
            "data": list(data),
        }
        return Output(out, fmt.hexdump(area.name, args.start, data))

    return go


# -- alarms ---------------------------------------------------------------------------------


def alarms(args: argparse.Namespace) -> Go:
    if args.follow:
        return _alarms_follow(args)
    given = {"--count": args.count, "--interval": args.interval}
    given = {option: value for option, value in given.items() if value is not None}
    if given:  # named as given, with the command that takes them
        verb = "apply" if len(given) > 1 else "applies"
        typed = " ".join(f"{option} {value:g}" for option, value in given.items())
        raise ValueError(
            f"{' and '.join(given)} {verb} to --follow ({PROG} alarms --follow {typed})"
        )

    async def go(cnc: CncClient) -> Output:
        active = await cnc.read_alarms()
        data: dict[str, Any] = {"active": [fmt.alarm_dict(a) for a in active]}
        lines = [f"active alarms: {len(active)}"]
        lines += [f"  {fmt.format_active_alarm(a)}" for a in active]
        if args.history:
            history = await cnc.read_alarm_history(args.history)
            data["history"] = [fmt.history_dict(e) for e in history.entries]
            lines.append(f"alarm history, newest first: {len(history.entries)}")
            lines += [f"  {fmt.format_history_entry(e)}" for e in history.entries]
        return Output(data, "\n".join(lines))

    return go


def _event_output(event: AlarmRaised | AlarmCleared | AlarmHistoryEvent) -> Output:
    if isinstance(event, AlarmHistoryEvent):
        return Output(
            {"event": "history", "entry": fmt.history_dict(event.entry)},
            f"history  {fmt.format_history_entry(event.entry)}",
        )
    kind = "raised" if isinstance(event, AlarmRaised) else "cleared"
    return Output(
        {"event": kind, "alarm": fmt.alarm_dict(event.alarm)},
        f"{kind:<8} {fmt.format_active_alarm(event.alarm)}",
    )


def _alarms_follow(args: argparse.Namespace) -> Go:
    mode = ProjectionMode.ACTIVE_PLUS_HISTORY if args.history else ProjectionMode.ACTIVE
    interval = 1.0 if args.interval is None else args.interval

    async def go(cnc: CncClient) -> None:
        # the first read as a one-shot command's: a peer that never answers (TLS on one side
        # only, not a FOCAS server) fails at once, diagnosed in the same words
        await cnc.read_alarms()
        cnc.add_state_callback(report_state(cnc))
        projection = AlarmProjection(
            cnc,
            mode,
            interval=interval,
            depth=args.history or 50,
            max_failures=_run.FOLLOW_MAX_FAILURES,  # (read when it runs, as the reconnect's)
        )
        printed = 0
        with stopping_on_signals(projection.stop):
            try:
                async for event in projection:
                    out = _event_output(event)
                    line = json.dumps(out.data) if args.json else out.text
                    if not write(line + "\n"):
                        break  # the reader went away (| head): nothing more to print
                    printed += 1
                    if args.count is not None and printed >= args.count:
                        break
            except FocasError as exc:
                raise HintedError(
                    exc, f"alarms --follow gave up after {projection.failed_polls} failed poll(s)"
                ) from exc
            finally:
                projection.stop()

    return go


# -- VersaMax -------------------------------------------------------------------------------


def versamax(args: argparse.Namespace) -> PackedOnly:
    async def go(cnc: FocasClient) -> Output:
        record = await cnc.read_module_config(args.rack, args.slot)
        return Output(
            fmt.module_dict(args.rack, args.slot, record),
            "\n\n".join(fmt.module_lines(args.rack, args.slot, record)),
        )

    return PackedOnly(go, "versamax_rdconfig is a packed-protocol command")
