"""The client commands of ``focas-net``: read and write a CNC from the terminal.

``status``, ``sysinfo``, ``program``, ``position``, ``param get|set``, ``macro get|set``, ``diag``,
``pmc read|write|bit``, ``alarms``, ``unlock``, ``versamax`` and ``sim panel|alarm|clear|fault``.
Every command takes ``--host`` (default 127.0.0.1), ``--port`` (8193), ``--timeout`` (seconds,
3) and ``--json``; the commands that write also take ``--password`` (sent with
``cnc_wrunlockparam`` right after connecting).

Output is a readable table by default (FOCAS names and their meanings); ``--json`` prints one
JSON document instead (``alarms --follow --json`` prints one JSON object per line). A failure
prints one line on stderr, ``focas-net: EW_PASSWD (17): protection / password error
(cnc_wrparam)``, and exits with:

====  ==========================================================================
0     success
1     the CNC answered an EW code (or a chunked PMC write failed part way)
2     usage error (bad arguments, or a value the protocol cannot carry)
3     connection refused or lost, or no answer within ``--timeout``
4     the peer broke the wire protocol
====  ==========================================================================

``alarms --follow`` polls until interrupted (Ctrl-C or SIGTERM end it cleanly with exit 0), or
until ``--count`` events were printed; it reconnects when the connection is lost.
"""

from __future__ import annotations

import argparse
import asyncio
import json
import os
import signal
import sys
from collections.abc import Awaitable, Callable
from dataclasses import dataclass
from typing import Any, Final

from focas_net.client import (
    AlarmCleared,
    AlarmHistoryEvent,
    AlarmProjection,
    AlarmRaised,
    ClientState,
    FaultKind,
    FaultScope,
    FocasClient,
    ProjectionMode,
)
from focas_net.errors import (
    AccessDeniedError,
    ChunkedWriteError,
    CncError,
    FocasConnectionError,
    FocasError,
    FocasTimeoutError,
    ProtocolError,
)
from focas_net.protocol import MAX_ALARM_MSG, ParamValue, PmcArea, PositionKind

from . import _format as fmt

__all__ = [
    "EXIT_CNC",
    "EXIT_CONNECTION",
    "EXIT_OK",
    "EXIT_PROTOCOL",
    "EXIT_USAGE",
    "register",
]

#: Exit codes of the client commands.
EXIT_OK: Final = 0
EXIT_CNC: Final = 1
EXIT_USAGE: Final = 2
EXIT_CONNECTION: Final = 3
EXIT_PROTOCOL: Final = 4

_PROG: Final = "focas-net"
_EPILOG: Final = (
    "exit status: 0 success, 1 CNC error (EW code), 2 usage error, "
    "3 connection error or timeout, 4 protocol violation"
)
_PASSWD_HINT: Final = (
    "parameter writes need MDI mode and PWE on (focas-net sim panel --mode MDI --pwe on) "
    "and, when the CNC has a parameter password, --password"
)


@dataclass(frozen=True, slots=True)
class Output:
    """What a command prints: ``text`` normally, ``data`` (JSON) with ``--json``."""

    data: Any
    text: str


Go = Callable[[FocasClient], Awaitable[Output | None]]
Command = Callable[[argparse.Namespace], Go]


# -- argument types -------------------------------------------------------------------------


def _arg(parse: Callable[[str], Any], what: str) -> Callable[[str], Any]:
    def convert(text: str) -> Any:
        try:
            return parse(text)
        except ValueError as exc:
            raise argparse.ArgumentTypeError(str(exc)) from None

    convert.__name__ = what  # argparse names the type in its messages
    return convert


def _port(text: str) -> int:
    value = fmt.parse_int(text)
    if not 0 < value <= 65_535:
        raise ValueError(f"port must be 1..65535, got {value}")
    return value


def _positive_float(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise ValueError(f"not a number: {text!r}") from None
    if not 0 < value < float("inf"):
        raise ValueError(f"must be a positive number, got {text}")
    return value


def _non_negative(text: str) -> int:
    value = fmt.parse_int(text)
    if value < 0:
        raise ValueError(f"must not be negative, got {value}")
    return value


def _positive(text: str) -> int:
    value = fmt.parse_int(text)
    if value < 1:
        raise ValueError(f"must be at least 1, got {value}")
    return value


_INT = _arg(fmt.parse_int, "integer")
_NON_NEGATIVE = _arg(_non_negative, "count")
_POSITIVE = _arg(_positive, "count")
_PORT = _arg(_port, "port")
_SECONDS = _arg(_positive_float, "seconds")
_BOOL = _arg(fmt.parse_bool, "on/off")


def _area(text: str) -> PmcArea:
    try:
        return PmcArea.parse(text)
    except ValueError:
        letters = "".join(a.name for a in PmcArea)
        raise ValueError(f"unknown PMC area {text!r} (one of {letters})") from None


_AREA = _arg(_area, "area")


# -- running a command ----------------------------------------------------------------------


def _error(message: str) -> None:
    sys.stderr.write(f"{_PROG}: {' '.join(message.split())}\n")
    sys.stderr.flush()


def _write(text: str) -> None:
    try:
        sys.stdout.write(text)
        sys.stdout.flush()
    except BrokenPipeError:
        # The reader went away (``| head``): stop writing without a traceback at exit.
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        os.close(devnull)


def _emit(args: argparse.Namespace, out: Output) -> None:
    if args.json:
        _write(json.dumps(out.data, indent=2) + "\n")
    elif out.text:
        _write(out.text.rstrip("\n") + "\n")


def _exit_code(exc: BaseException) -> int:
    if isinstance(exc, _HintedError | ChunkedWriteError):
        return _exit_code(exc.cause)
    if isinstance(exc, CncError):
        return EXIT_CNC
    if isinstance(exc, FocasConnectionError | FocasTimeoutError | OSError):
        return EXIT_CONNECTION
    if isinstance(exc, ProtocolError):
        return EXIT_PROTOCOL
    if isinstance(exc, ValueError):
        return EXIT_USAGE
    return EXIT_CNC


async def _session(args: argparse.Namespace, go: Go, reconnect: bool) -> Output | None:
    client = FocasClient(
        args.host,
        args.port,
        timeout=args.timeout,
        password=getattr(args, "password", None),
        reconnect=reconnect,
    )
    if reconnect:
        client.add_state_callback(_report_state(client))
    async with client:
        return await go(client)


def _report_state(client: FocasClient) -> Callable[[ClientState], None]:
    lost = False

    def report(state: ClientState) -> None:
        nonlocal lost
        if state is ClientState.RECONNECTING:
            lost = True
            _error(f"connection to {client.host}:{client.port} lost; reconnecting")
        elif state is ClientState.CONNECTED and lost:
            lost = False
            _error(f"reconnected to {client.host}:{client.port}")

    return report


def _entry(command: Command) -> Callable[[argparse.Namespace], int]:
    """``args -> exit code``: parse, connect, run, print; failures become one line."""

    def run(args: argparse.Namespace) -> int:
        reconnect = bool(getattr(args, "follow", False))
        try:
            go = command(args)
            out = asyncio.run(_session(args, go, reconnect))
        except (FocasError, ValueError, OSError) as exc:
            _error(_failure_text(args, exc))
            return _exit_code(exc)
        if out is not None:
            _emit(args, out)
        return EXIT_OK

    return run


class _HintedError(FocasError):
    """A failure with advice for the user appended to its one-line text."""

    def __init__(self, cause: FocasError, hint: str) -> None:
        super().__init__(f"{cause}; {hint}")
        self.cause = cause
        self.hint = hint


def _failure_text(args: argparse.Namespace, exc: BaseException) -> str:
    if isinstance(exc, _HintedError):
        return f"{_failure_text(args, exc.cause)}; {exc.hint}"
    text = fmt.error_line(exc)
    if isinstance(exc, FocasTimeoutError):
        return f"timed out after {args.timeout:g} s ({args.host}:{args.port}): {text}"
    return text


# -- status and identity --------------------------------------------------------------------


def _status(args: argparse.Namespace) -> Go:
    async def go(cnc: FocasClient) -> Output:
        st = await cnc.read_status()
        table = fmt.render_table(("field", "value", "name", "meaning"), fmt.status_rows(st))
        return Output(fmt.status_dict(st), f"{fmt.status_summary(st)}\n\n{table}")

    return go


def _sysinfo(args: argparse.Namespace) -> Go:
    async def go(cnc: FocasClient) -> Output:
        info = await cnc.read_sysinfo()
        table = fmt.render_table(("field", "value", "meaning"), fmt.sysinfo_rows(info))
        return Output(fmt.sysinfo_dict(info), table)

    return go


# -- program numbers, feed, spindle, positions ----------------------------------------------


def _program(args: argparse.Namespace) -> Go:
    async def go(cnc: FocasClient) -> Output:
        numbers = await cnc.read_program_numbers()
        feed = await cnc.read_feed()
        speed = await cnc.read_spindle_speed()
        data = fmt.program_dict(numbers, feed, speed)
        return Output(data, fmt.render_table(("item", "value", "meaning"), fmt.program_rows(data)))

    return go


def _position(args: argparse.Namespace) -> Go:
    kind = PositionKind.parse(args.kind)

    async def go(cnc: FocasClient) -> Output:
        pos = await cnc.read_positions(kind, axis=args.axis)
        data = fmt.positions_dict(pos.kind.name.lower(), pos.decimals, pos.values, pos.increments)
        table = fmt.render_table(("axis", "position", "increments"), fmt.positions_rows(data))
        return Output(data, f"{data['kind']} position\n\n{table}")

    return go


# -- parameters, diagnostics, macros --------------------------------------------------------


def _item_name(number: int, bit: int | None, axis: int) -> str:
    name = f"{number}" if bit is None else f"{number}.{bit}"
    return f"{name} axis {axis}" if axis else name


def _value_text(value: int, width: int) -> str:
    raw = value & ((1 << 8 * width) - 1)
    text = f"{value} (0x{raw:0{2 * width}X}"
    if width == 1:
        text += f", 0b{raw:08b}"
    return f"{text}), {width} byte{'s' if width > 1 else ''}"


def _param_output(
    number: int, bit: int | None, axis: int, pv: ParamValue
) -> tuple[dict[str, Any], str, str | None]:
    """The JSON data of a parameter read, its text, and the text of its bit (when one)."""
    data: dict[str, Any] = {"number": number, "axis": axis, "value": pv.value, "width": pv.width}
    whole = f"{_item_name(number, None, axis)} = {_value_text(pv.value, pv.width)}"
    if bit is None:
        return data, whole, None
    data["bit"] = bit
    data["bit_value"] = pv.value >> bit & 1
    return data, whole, f"{_item_name(number, bit, axis)} = {data['bit_value']}"


def _param_get(args: argparse.Namespace) -> Go:
    number, bit = fmt.parse_number_bit(args.number)

    async def go(cnc: FocasClient) -> Output:
        pv = await cnc.read_param_value(number, axis=args.axis)
        if bit is not None and not 0 <= bit < 8 * pv.width:
            raise ValueError(f"bit {bit} outside 0..{8 * pv.width - 1} of parameter {number}")
        data, whole, bit_text = _param_output(number, bit, args.axis, pv)
        return Output(data, whole if bit_text is None else bit_text)

    return go


def _param_set(args: argparse.Namespace) -> Go:
    number, bit = fmt.parse_number_bit(args.number)
    if bit is not None:
        if args.width is not None:
            raise ValueError("--width does not apply to a bit write (NUMBER.BIT)")
        bit_value = fmt.parse_bool(args.value)
    else:
        value = fmt.parse_int(args.value)

    async def go(cnc: FocasClient) -> Output:
        try:
            if bit is None:
                await cnc.write_param(number, value, axis=args.axis, width=args.width)
            else:
                await cnc.write_param_bit(number, bit, bit_value, axis=args.axis)
        except AccessDeniedError as exc:
            raise _HintedError(exc, _PASSWD_HINT) from exc
        pv = await cnc.read_param_value(number, axis=args.axis)
        data, whole, bit_text = _param_output(number, bit, args.axis, pv)
        text = whole if bit_text is None else f"{bit_text}; {whole}"
        return Output(data, f"{text} (written)")

    return go


def _diag(args: argparse.Namespace) -> Go:
    async def go(cnc: FocasClient) -> Output:
        value = await cnc.read_diag(args.number, axis=args.axis)
        data = {"number": args.number, "axis": args.axis, "value": value}
        return Output(data, f"{_item_name(args.number, None, args.axis)} = {value}")

    return go


def _macro_get(args: argparse.Namespace) -> Go:
    async def go(cnc: FocasClient) -> Output:
        value = await cnc.read_macro(args.number)
        data = {"number": args.number, "value": None if value is None else str(value)}
        return Output(data, f"#{args.number} = {fmt.macro_text(value)}")

    return go


def _macro_set(args: argparse.Namespace) -> Go:
    # A value that cannot be carried raises ValueError before anything is sent (exit 2).
    async def go(cnc: FocasClient) -> Output:
        await cnc.write_macro(args.number, args.value)
        value = await cnc.read_macro(args.number)
        data = {"number": args.number, "value": None if value is None else str(value)}
        return Output(data, f"#{args.number} = {fmt.macro_text(value)} (written)")

    return go


# -- PMC ------------------------------------------------------------------------------------


def _pmc_read(args: argparse.Namespace) -> Go:
    area: PmcArea = args.area

    async def go(cnc: FocasClient) -> Output:
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


def _pmc_write(args: argparse.Namespace) -> Go:
    area: PmcArea = args.area
    if args.hex is not None and args.values:
        raise ValueError("give the bytes either as values or with --hex, not both")
    if args.hex is not None:
        payload = fmt.parse_hex(args.hex)
    else:
        payload = fmt.parse_byte_list(args.values)

    async def go(cnc: FocasClient) -> Output:
        if args.force:
            await cnc.sim.set_pmc(area, args.start, payload)
        else:
            await cnc.write_pmc(area, args.start, payload)
        last = args.start + len(payload) - 1
        data = {"area": area.name, "start": args.start, "count": len(payload), "hex": payload.hex()}
        where = f"{area.name}{args.start}" + (f"..{area.name}{last}" if last > args.start else "")
        return Output(
            data,
            f"wrote {len(payload)} byte{'s' * (len(payload) > 1)} to {where}: {payload.hex(' ')}",
        )

    return go


def _parse_byte_bit(text: str) -> tuple[int, int]:
    byte, bit = fmt.parse_number_bit(text)
    if bit is None:
        raise ValueError(f"expected BYTE.BIT (e.g. 100.3), got {text!r}")
    if bit > 7:
        raise ValueError(f"bit {bit} outside 0..7")
    return byte, bit


def _pmc_bit(args: argparse.Namespace) -> Go:
    area: PmcArea = args.area
    byte, bit = _parse_byte_bit(args.address)
    value = None if args.value is None else fmt.parse_bool(args.value)

    async def go(cnc: FocasClient) -> Output:
        if value is not None:
            await cnc.write_pmc_bit(area, byte, bit, value)
        current = await cnc.read_pmc_bit(area, byte, bit)
        data = {"area": area.name, "byte": byte, "bit": bit, "value": int(current)}
        suffix = " (written)" if value is not None else ""
        return Output(data, f"{area.name}{byte}.{bit} = {int(current)}{suffix}")

    return go


# -- alarms ---------------------------------------------------------------------------------


def _alarms(args: argparse.Namespace) -> Go:
    if args.follow:
        return _alarms_follow(args)
    if args.count is not None or args.interval is not None:
        raise ValueError("--count and --interval apply to --follow")

    async def go(cnc: FocasClient) -> Output:
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

    async def go(cnc: FocasClient) -> None:
        projection = AlarmProjection(cnc, mode, interval=interval, depth=args.history or 50)
        loop = asyncio.get_running_loop()
        installed = []
        for signum in (signal.SIGINT, signal.SIGTERM):
            try:
                loop.add_signal_handler(signum, projection.stop)
            except (NotImplementedError, RuntimeError, ValueError):
                continue  # not the main thread, or no signal support: Ctrl-C still ends it
            installed.append(signum)
        try:
            printed = 0
            async for event in projection:
                out = _event_output(event)
                if args.json:
                    _write(json.dumps(out.data) + "\n")
                else:
                    _write(out.text + "\n")
                printed += 1
                if args.count is not None and printed >= args.count:
                    break
        finally:
            for signum in installed:
                loop.remove_signal_handler(signum)
            projection.stop()

    return go


# -- unlock and VersaMax --------------------------------------------------------------------


def _unlock(args: argparse.Namespace) -> Go:
    async def go(cnc: FocasClient) -> Output:
        await cnc.unlock(args.secret)
        return Output(
            {"unlocked": True},
            "password accepted (an unlock holds for one connection: give --password to "
            "the commands that write parameters)",
        )

    return go


def _versamax(args: argparse.Namespace) -> Go:
    async def go(cnc: FocasClient) -> Output:
        record = await cnc.read_module_config(args.rack, args.slot)
        return Output(
            fmt.module_dict(args.rack, args.slot, record),
            "\n\n".join(fmt.module_lines(args.rack, args.slot, record)),
        )

    return go


# -- simulator control ----------------------------------------------------------------------


def _sim_panel(args: argparse.Namespace) -> Go:
    mode = None if args.mode is None else fmt.parse_aut(args.mode)

    async def go(cnc: FocasClient) -> Output:
        before = await cnc.read_status()
        new_mode = before.aut if mode is None else mode
        emergency = before.emergency == 1 if args.emergency is None else args.emergency
        await cnc.sim.set_panel(new_mode, pwe=bool(args.pwe), emergency=emergency)
        st = await cnc.read_status()
        data = {
            "mode": new_mode,
            "pwe": int(bool(args.pwe)),
            "emergency": int(emergency),
            "status": fmt.status_dict(st),
        }
        return Output(data, f"{fmt.status_summary(st)} pwe={'on' if args.pwe else 'off'}")

    return go


def _sim_alarm(args: argparse.Namespace) -> Go:
    alm_type, alm_no = fmt.parse_alarm(args.alarm)
    msg = " ".join(args.message)
    kept = msg[:MAX_ALARM_MSG]  # the CNC keeps the first 32 characters of a message

    async def go(cnc: FocasClient) -> Output:
        await cnc.sim.raise_alarm(alm_type, alm_no, msg, axis_no=args.axis)
        code = fmt.alarm_code(alm_type, alm_no)
        data = {
            "raised": {
                "code": code,
                "axis_no": args.axis,
                "alm_type": alm_type,
                "alm_no": alm_no,
                "msg": kept,
            }
        }
        axis = f" (axis {args.axis})" if args.axis else ""
        return Output(data, f"raised {code}{axis} {kept}".rstrip())

    return go


def _sim_clear(args: argparse.Namespace) -> Go:
    alm_type, alm_no = fmt.parse_alarm_filter(args.alarm)

    async def go(cnc: FocasClient) -> Output:
        await cnc.sim.clear_alarms(alm_type, alm_no)
        remaining = await cnc.read_alarms()
        data = {"cleared": args.alarm or "all", "active": [fmt.alarm_dict(a) for a in remaining]}
        return Output(data, f"cleared {args.alarm or 'all alarms'}; {len(remaining)} still active")

    return go


_FAULT_KINDS: Final = {k.name.lower(): k for k in FaultKind}
_FAULT_SCOPES: Final = {s.name.lower(): s for s in FaultScope}


def _sim_fault(args: argparse.Namespace) -> Go:
    kind = _FAULT_KINDS[args.kind]
    scope = _FAULT_SCOPES[args.scope]
    if kind is FaultKind.ERROR:
        if args.arg is None:
            raise ValueError("an error fault needs --arg EW_CODE (e.g. --arg EW_BUSY)")
        arg = fmt.parse_ew(args.arg)
    elif kind is FaultKind.DELAY:
        if args.arg is None:
            raise ValueError("a delay fault needs --arg MILLISECONDS")
        arg = fmt.parse_int(args.arg)
    else:
        arg = 0 if args.arg is None else fmt.parse_int(args.arg)
    effect = {
        FaultKind.DELAY: f"delayed {arg} ms",
        FaultKind.ERROR: f"answered with {fmt.error_line(CncError(arg))}"
        if arg
        else "answered with EW 0",
        FaultKind.DROP: "dropped (connection closed)",
        FaultKind.SPLIT: "sent one byte per write",
    }[kind]
    whose = "of this machine" if scope is FaultScope.MACHINE else "on this connection"

    async def go(cnc: FocasClient) -> Output:
        await cnc.sim.inject_fault(kind, count=args.count, arg=arg, scope=scope)
        data = {
            "kind": kind.name.lower(),
            "scope": scope.name.lower(),
            "count": args.count,
            "arg": arg,
        }
        return Output(data, f"the next {args.count} answer(s) {whose}: {effect}")

    return go


# -- parsers --------------------------------------------------------------------------------


def _common(*, writes: bool = False) -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(add_help=False)
    g = p.add_argument_group("connection")
    g.add_argument("--host", default="127.0.0.1", help="CNC address (default %(default)s)")
    g.add_argument("--port", type=_PORT, default=8193, help="CNC port (default %(default)s)")
    g.add_argument(
        "--timeout",
        type=_SECONDS,
        default=3.0,
        metavar="SECONDS",
        help="per-call timeout (default %(default)s)",
    )
    g.add_argument("--json", action="store_true", help="print JSON instead of a table")
    if writes:
        g.add_argument(
            "--password",
            metavar="TEXT",
            help="parameter password, sent with cnc_wrunlockparam after connecting",
        )
    return p


def _add(
    sub: Any,
    name: str,
    command: Command,
    help_text: str,
    *,
    writes: bool = False,
) -> argparse.ArgumentParser:
    p: argparse.ArgumentParser = sub.add_parser(
        name,
        help=help_text,
        description=help_text[0].upper() + help_text[1:] + ".",
        epilog=_EPILOG,
        parents=[_common(writes=writes)],
    )
    p.set_defaults(func=_entry(command))
    return p


def _group(sub: Any, name: str, help_text: str) -> Any:
    p = sub.add_parser(name, help=help_text, description=help_text[0].upper() + help_text[1:])
    return p.add_subparsers(dest=f"{name}_command", required=True, metavar="ACTION")


def _axis_option(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--axis",
        type=_NON_NEGATIVE,
        default=0,
        metavar="N",
        help="axis 1..n for an axis item; 0 for a non-axis item (default 0)",
    )


def register(subparsers: Any) -> None:
    """Add the client commands to the ``focas-net`` parser."""
    _add(subparsers, "status", _status, "read the CNC status (cnc_rdcncstat, ODBST)")
    _add(subparsers, "sysinfo", _sysinfo, "read the CNC identity (cnc_sysinfo, ODBSYS)")

    _add(
        subparsers,
        "program",
        _program,
        "read the program numbers, feed and spindle speed (cnc_rdprgnum, cnc_actf, cnc_acts)",
    )
    p = _add(subparsers, "position", _position, "read axis positions (cnc_rdposition)")
    p.add_argument(
        "--kind",
        choices=("absolute", "machine", "relative", "distance"),
        default="absolute",
        help="which position; distance = distance to go (default %(default)s)",
    )
    p.add_argument(
        "--axis", type=_POSITIVE, metavar="N", help="only axis N (1..n; default every axis)"
    )

    param = _group(subparsers, "param", "read or write a CNC parameter")
    p = _add(param, "get", _param_get, "read a parameter (cnc_rdparam)")
    p.add_argument("number", metavar="NUMBER[.BIT]", help="parameter number, e.g. 1320 or 1815.4")
    _axis_option(p)
    p = _add(
        param,
        "set",
        _param_set,
        "write a parameter (cnc_wrparam); NUMBER.BIT writes one bit by read-modify-write",
        writes=True,
    )
    p.add_argument("number", metavar="NUMBER[.BIT]", help="parameter number, e.g. 1320 or 1815.4")
    p.add_argument("value", metavar="VALUE", help="integer (0x.. hex); 0/1 for a bit")
    _axis_option(p)
    p.add_argument(
        "--width",
        type=int,
        choices=(1, 2, 4),
        help="value width in bytes (default: the width the CNC reports)",
    )

    macro = _group(subparsers, "macro", "read or write a custom macro variable")
    p = _add(macro, "get", _macro_get, "read a macro variable (cnc_rdmacro)")
    p.add_argument("number", type=_INT, metavar="NUMBER", help="variable number, e.g. 100")
    p = _add(macro, "set", _macro_set, "write a macro variable (cnc_wrmacro)", writes=True)
    p.add_argument("number", type=_INT, metavar="NUMBER", help="variable number, e.g. 100")
    p.add_argument("value", metavar="VALUE", help="decimal value, e.g. 12.5")

    p = _add(subparsers, "diag", _diag, "read a diagnostic (cnc_rddiag)")
    p.add_argument("number", type=_INT, metavar="NUMBER", help="diagnostic number, e.g. 300")
    _axis_option(p)

    pmc = _group(subparsers, "pmc", "read or write PMC data")
    p = _add(pmc, "read", _pmc_read, "read PMC bytes (pmc_rdpmcrng)")
    p.add_argument("area", type=_AREA, metavar="AREA", help="area letter: X Y F G R T C D K A E")
    p.add_argument("start", type=_NON_NEGATIVE, metavar="START", help="first byte address")
    p.add_argument(
        "count", type=_POSITIVE, nargs="?", default=1, metavar="COUNT", help="bytes (default 1)"
    )
    p = _add(pmc, "write", _pmc_write, "write PMC bytes (pmc_wrpmcrng)", writes=True)
    p.add_argument("area", type=_AREA, metavar="AREA", help="area letter: X Y F G R T C D K A E")
    p.add_argument("start", type=_NON_NEGATIVE, metavar="START", help="first byte address")
    p.add_argument("values", nargs="*", metavar="BYTE", help="byte values: 1 2 0xff or 1,2,255")
    p.add_argument("--hex", metavar="HEX", help="the bytes as hex instead, e.g. 0102ff")
    p.add_argument(
        "--force",
        action="store_true",
        help="write through simulator control, ignoring write protection (drives X and F)",
    )
    p = _add(
        pmc,
        "bit",
        _pmc_bit,
        "read a PMC bit, or write it (read-modify-write of its byte) when VALUE is given",
        writes=True,
    )
    p.add_argument("area", type=_AREA, metavar="AREA", help="area letter: X Y F G R T C D K A E")
    p.add_argument("address", metavar="BYTE.BIT", help="e.g. 100.3")
    p.add_argument("value", nargs="?", metavar="VALUE", help="0/1 (on/off) to write")

    p = _add(
        subparsers,
        "alarms",
        _alarms,
        "read the active alarms (cnc_rdalmmsg) and the alarm history (cnc_rdalmhistry)",
    )
    p.add_argument(
        "--history",
        type=_arg(_history_depth, "depth"),
        default=0,
        metavar="N",
        help="also the N most recent history entries (1..250)",
    )
    p.add_argument(
        "--follow",
        action="store_true",
        help="poll and print alarm events until Ctrl-C (with --history: history entries too)",
    )
    p.add_argument(
        "--interval", type=_SECONDS, metavar="SECONDS", help="poll interval of --follow (1)"
    )
    p.add_argument("--count", type=_POSITIVE, metavar="N", help="stop --follow after N events")

    p = _add(
        subparsers,
        "unlock",
        _unlock,
        "check a parameter password (cnc_wrunlockparam); the unlock lasts one connection",
    )
    p.add_argument("secret", metavar="PASSWORD", help="the parameter password")

    p = _add(
        subparsers,
        "versamax",
        _versamax,
        "read a VersaMax module configuration record (versamax_rdconfig)",
    )
    p.add_argument("rack", type=_NON_NEGATIVE, metavar="RACK", help="rack 0..7")
    p.add_argument("slot", type=_NON_NEGATIVE, metavar="SLOT", help="slot 0..9")

    sim = _group(subparsers, "sim", "drive a simulated CNC (control commands; a real CNC refuses)")
    p = _add(sim, "panel", _sim_panel, "set the operator panel: mode, PWE, emergency stop")
    p.add_argument("--mode", metavar="MODE", help="MDI MEM EDIT HND JOG ... (default: unchanged)")
    p.add_argument(
        "--pwe",
        type=_BOOL,
        default=False,
        metavar="on|off",
        help="parameter write enable (default off: the panel's PWE cannot be read back)",
    )
    p.add_argument(
        "--emergency", type=_BOOL, metavar="on|off", help="emergency stop (default: unchanged)"
    )
    p = _add(sim, "alarm", _sim_alarm, "raise an alarm")
    p.add_argument("alarm", metavar="ALARM", help="alarm code, e.g. PS0100 (or TYPE:NO)")
    p.add_argument("message", nargs="*", metavar="MESSAGE", help="alarm message (ASCII)")
    _axis_option(p)
    p = _add(sim, "clear", _sim_clear, "clear active alarms (the history is kept)")
    p.add_argument(
        "alarm", nargs="?", metavar="ALARM", help="PS0100, or PS for a whole type (default all)"
    )
    p = _add(sim, "fault", _sim_fault, "make the next answers misbehave (fault injection)")
    p.add_argument("kind", choices=sorted(_FAULT_KINDS), help="what happens to the answers")
    p.add_argument(
        "--arg",
        metavar="VALUE",
        help="delay: milliseconds; error: EW code (number or name, e.g. EW_BUSY)",
    )
    p.add_argument("--count", type=_POSITIVE, default=1, metavar="N", help="answers (default 1)")
    p.add_argument(
        "--scope",
        choices=sorted(_FAULT_SCOPES),
        default="machine",
        help="machine: the next answers on any connection (default); "
        "connection: only this command's own connection",
    )


def _history_depth(text: str) -> int:
    value = fmt.parse_int(text)
    if not 1 <= value <= 250:
        raise ValueError(f"history depth must be 1..250, got {value}")
    return value
