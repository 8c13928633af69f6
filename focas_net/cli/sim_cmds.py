"""Driving a simulated CNC: ``sim panel``, ``sim alarm``, ``sim clear``, ``sim fault`` and
``sim faults``.

These use the simulator's control commands (0x0E01..0x0E21); a real CNC, or a server started
with ``--no-control``, answers them with ``EW_FUNC``.

Faults queue first in, first out in their scope: ``sim fault`` says which answers the new
fault applies to (``queued behind 2 pending faults: answers 4..5 of this machine from now``),
``sim faults`` lists the pending faults and ``sim faults --clear`` removes them.
"""

from __future__ import annotations

import argparse
from collections.abc import Callable
from typing import Any, Final

from focas_net.client import FocasClient
from focas_net.errors import CncError, FocasError
from focas_net.protocol import (
    MAX_ALARM_MSG,
    ArmedFault,
    FaultKind,
    FaultScope,
    alarm_active_already,
    alarm_filter_text,
    alarm_message,
    fault_arg_needed,
    nothing_cleared,
)
from focas_net.server.faults import fault_arg_text, fault_refusal, no_faults_cleared

from . import _format as fmt
from ._args import ArgumentRefused, named
from ._run import Output, PackedOnly
from .read_cmds import axis_past

__all__ = [
    "FAULT_KINDS",
    "FAULT_SCOPES",
    "SIM_CONTROLS",
    "NothingMatched",
    "alarm",
    "clear",
    "fault",
    "faults",
    "panel",
]


class NothingMatched(FocasError):
    """A command found nothing to act on (``sim clear PS9999`` with no such alarm): exit 1."""


#: ``sim fault KIND``: the fault kinds by their command-line names.
FAULT_KINDS: Final = {k.name.lower(): k for k in FaultKind}
#: ``sim fault --scope``: the fault scopes by their command-line names.
FAULT_SCOPES: Final = {s.name.lower(): s for s in FaultScope}
#: Why a simulator control command needs the packed transport.
SIM_CONTROLS: Final = "the simulator controls are packed-protocol commands"
#: ``sim alarm``'s other choice after an ``--axis`` past the path's.
_NO_AXIS: Final = " (or --axis 0: an alarm of no axis)"


def panel(args: argparse.Namespace) -> PackedOnly:
    mode = args.mode  # an AutMode, read by the parser (argument --mode)
    writes = mode is not None or args.pwe is not None or args.emergency is not None

    async def go(cnc: FocasClient) -> Output:
        # Only the switches given change (the others travel as -1, "unchanged"); with none
        # given nothing is written and the panel is only read.
        if writes:
            await cnc.sim.set_panel(mode, pwe=args.pwe, emergency=args.emergency)
        p = await cnc.sim.read_panel()
        st = await cnc.read_status()
        mt_type = fmt.mt_type_text(await cnc.read_sysinfo())  # names tmmode
        data = {
            "mode": int(p.mode),
            "pwe": int(p.pwe),
            "emergency": int(p.emergency),
            "status": fmt.status_dict(st, mt_type),
        }
        return Output(data, f"{fmt.status_summary(st)} pwe={'on' if p.pwe else 'off'}")

    return PackedOnly(go, SIM_CONTROLS)


def alarm(args: argparse.Namespace) -> PackedOnly:
    alm_type, alm_no = named("ALARM", fmt.parse_alarm, args.alarm)
    msg = " ".join(args.message)
    # the message by the rule its encoding keeps, before anything is read: one the machine
    # would refuse is refused also when the alarm is active already (nothing raised then)
    named("MESSAGE", alarm_message, msg)

    async def go(cnc: FocasClient) -> Output:
        # A CNC shows one entry per alarm: raised again while active, the alarm keeps its
        # message and nothing changes (docs/protocol.md section 8). Say so rather than "raised".
        code = fmt.alarm_code(alm_type, alm_no)
        axis = f" (axis {args.axis})" if args.axis else ""
        # on a machine of several paths the path, as sim clear names it
        on = f" on path {args.path}" if (await cnc.read_paths()).count > 1 else ""
        key = (args.axis, alm_type, alm_no)
        active = [a for a in await cnc.read_alarms(alm_type=alm_type) if a.key == key]
        if active:
            data = {"raised": None, "active": fmt.alarm_dict(active[0])}
            return Output(
                data, alarm_active_already(alm_type, alm_no, active[0].msg, args.axis, on=on)
            )
        try:
            await cnc.sim.raise_alarm(alm_type, alm_no, msg, axis_no=args.axis)
        except CncError as exc:  # an --axis past the path's: its axes, in the machine's words
            raise await axis_past(cnc, exc, args.axis, _NO_AXIS) from exc
        # what the machine kept: the message cut at 32, or its table's for one left out
        now = [a.msg for a in await cnc.read_alarms(alm_type=alm_type) if a.key == key]
        kept = now[0] if now else msg[:MAX_ALARM_MSG]
        data = {
            "raised": {
                "code": code,
                "axis_no": args.axis,
                "alm_type": alm_type,
                "alm_no": alm_no,
                "msg": kept,
            }
        }
        return Output(data, f"{f'raised {code}{axis} {kept}'.rstrip()}{on}")

    return PackedOnly(go, SIM_CONTROLS)


def clear(args: argparse.Namespace) -> PackedOnly:
    given: str | None = args.alarm
    if given is not None and given.strip().lower() == "all":
        given = None  # what leaving it out means, as --help and the JSON name it
    alm_type, alm_no = named("ALARM", fmt.parse_alarm_filter, given)
    # what was given, as the CNC names it (``ps100`` is PS0100, ``ps`` every PS alarm)
    if given is not None:
        given = alarm_filter_text(alm_type, alm_no)

    def matches(a: Any) -> bool:
        return alm_type in (-1, a.alm_type) and alm_no in (-1, a.alm_no)

    async def go(cnc: FocasClient) -> Output:
        # the alarms of the --path path, as a CNC's RESET clears the selected path's; on a
        # machine of several paths every line names that path, and a refusal where matches are
        paths = (await cnc.read_paths()).count
        on = f" on path {args.path}" if paths > 1 else ""
        before = await cnc.read_alarms()
        await cnc.sim.clear_alarms(alm_type, alm_no)
        remaining = await cnc.read_alarms()
        gone = [a for a in before if matches(a) and a not in remaining]
        if not gone:
            elsewhere = await _elsewhere(cnc, paths, args.path, matches)
            if given is not None:
                other = elsewhere[0][0] if elsewhere else 1
                advice = f": focas-net sim clear {given}" + (
                    f" --path {other}" if other != 1 else ""
                )
                raise NothingMatched(
                    nothing_cleared(given, on=on, elsewhere=elsewhere, advice=advice)
                )
        data = {
            "cleared": given or "all",
            "alarms": [fmt.alarm_dict(a) for a in gone],
            "active": [fmt.alarm_dict(a) for a in remaining],
        }
        if not gone:
            return Output(data, nothing_cleared(None, on=on, elsewhere=elsewhere))
        # each as sim alarm names it: two alarms of one code on two axes are two entries
        what = ", ".join(
            fmt.alarm_code(a.alm_type, a.alm_no) + (f" (axis {a.axis_no})" if a.axis_no else "")
            for a in gone
        )
        return Output(data, f"cleared {what}{on}; {len(remaining)} still active{on}")

    return PackedOnly(go, SIM_CONTROLS)


async def _elsewhere(
    cnc: FocasClient, paths: int, path: int, matches: Callable[[Any], bool]
) -> list[tuple[int, int]]:
    """The other paths of a machine with alarms ``matches`` takes, and how many each has."""
    found = []
    for other in range(1, paths + 1):
        if other != path:
            n = sum(1 for a in await cnc.read_alarms(path=other) if matches(a))
            if n:
                found.append((other, n))
    return found


def _whose(scope: FaultScope) -> str:
    return "of this machine" if scope is FaultScope.MACHINE else "on this connection"


def _answers(first: int, count: int) -> str:
    return f"answer {first}" if count == 1 else f"answers {first}..{first + count - 1}"


def _fault_rows(pending: tuple[ArmedFault, ...]) -> list[dict[str, Any]]:
    """The pending faults with the answers each applies to, counted from the next one."""
    rows = []
    first = 1
    for f in pending:
        kind = f.kind.name.lower() if isinstance(f.kind, FaultKind) else str(f.kind)
        rows.append(
            {
                "kind": kind,
                "arg": f.arg,
                "remaining": f.remaining,
                "first_answer": first,
                "last_answer": first + f.remaining - 1,
            }
        )
        first += f.remaining
    return rows


def parse_fault_count(text: str) -> int:
    """``--count`` of a fault: ValueError in the server's words for one it refuses."""
    count = fmt.parse_int(text)
    why = fault_refusal(int(FaultKind.DROP), int(FaultScope.MACHINE), count, 0)
    if why is not None:
        raise ValueError(why)
    return count


def fault(args: argparse.Namespace) -> PackedOnly:
    kind: FaultKind = args.kind  # read by fault_kind_of, as every front end reads it
    scope = FAULT_SCOPES[args.scope]
    arg = _fault_arg(kind, args.arg)
    #: the numbers sent, for the words of a refusal (cli._reasons)
    args.fault_numbers = (int(kind), int(scope), args.count, arg)
    effect = _effect(kind, arg)
    whose = _whose(scope)

    async def go(cnc: FocasClient) -> Output:
        await cnc.sim.inject_fault(kind, count=args.count, arg=arg, scope=scope)
        pending = _fault_rows(await cnc.sim.list_faults(scope))
        ahead = pending[:-1]  # the new fault is the last of its queue
        first = pending[-1]["first_answer"] if pending else 1
        data = {
            "kind": kind.name.lower(),
            "scope": scope.name.lower(),
            "count": args.count,
            "arg": arg,
            "queued_behind": len(ahead),
            "first_answer": first,
            "last_answer": first + args.count - 1,
        }
        if not ahead:
            which = "the next answer" if args.count == 1 else f"the next {args.count} answers"
            return Output(data, f"{which} {whose}: {effect}")
        behind = f"queued behind {len(ahead)} pending fault{'s' * (len(ahead) > 1)}"
        return Output(data, f"{behind}: {_answers(first, args.count)} {whose} from now: {effect}")

    return PackedOnly(go, SIM_CONTROLS)


def _fault_arg(kind: FaultKind, text: str | None) -> int:
    """``--arg`` of a fault of ``kind``, in the range the server takes: an
    :class:`~._args.ArgumentRefused` naming it, in the server's words
    (:func:`~focas_net.server.faults.fault_refusal`)."""
    if kind is FaultKind.ERROR or kind is FaultKind.DELAY:
        if text is None:  # in the words of every front end, after the option's name
            raise ArgumentRefused("--arg", str(fault_arg_needed(int(kind))))
        try:
            value = fmt.parse_ew(text) if kind is FaultKind.ERROR else fmt.parse_int(text)
        except ValueError as exc:
            raise ArgumentRefused("--arg", str(exc)) from None
        why = fault_refusal(int(kind), int(FaultScope.MACHINE), 1, value)
        if why is not None:
            raise ArgumentRefused("--arg", why)
        return value
    if text is not None:
        raise ArgumentRefused("--arg", f"does not apply to a {kind.name.lower()} fault")
    return 0


def _effect(kind: FaultKind, arg: int) -> str:
    if kind is FaultKind.DELAY:
        return f"delayed {arg} ms"
    if kind is FaultKind.ERROR:
        return f"answered with {fmt.error_line(CncError(arg))}" if arg else "answered with EW 0"
    if kind is FaultKind.DROP:
        return "dropped (connection closed)"
    return "sent one byte per write"


def faults(args: argparse.Namespace) -> PackedOnly:
    scope = FAULT_SCOPES[args.scope]
    whose = _whose(scope)

    async def go(cnc: FocasClient) -> Output:
        if args.clear:
            cleared = await cnc.sim.clear_faults(scope)
            data: dict[str, Any] = {"scope": scope.name.lower(), "cleared": cleared}
            if not cleared:
                return Output(data, no_faults_cleared(whose))
            return Output(data, f"cleared {cleared} pending fault{'s' * (cleared > 1)} {whose}")
        pending = await cnc.sim.list_faults(scope)
        rows = _fault_rows(pending)
        data = {"scope": scope.name.lower(), "faults": rows}
        if not rows:
            return Output(data, f"no pending faults {whose}")
        table = fmt.render_table(
            ("#", "kind", "arg", "remaining", "applies to"),
            [
                (
                    str(i),
                    r["kind"],
                    _arg_text(r["kind"], r["arg"]),
                    str(r["remaining"]),
                    _answers(r["first_answer"], r["remaining"]),
                )
                for i, r in enumerate(rows, 1)
            ],
        )
        head = f"{len(rows)} pending fault{'s' * (len(rows) > 1)} {whose}, first in, first out:"
        return Output(data, f"{head}\n{table}")

    return PackedOnly(go, SIM_CONTROLS)


def _arg_text(kind: str, arg: int) -> str:
    known = FaultKind.__members__.get(kind.upper())
    return fault_arg_text(int(known), arg) if known is not None else "-"
