"""Driving a simulated CNC: ``sim panel``, ``sim alarm``, ``sim clear`` and ``sim fault``.

These use the simulator's control commands (0x0E01..0x0E05); a real CNC, or a server started
with ``--no-control``, answers them with ``EW_FUNC``.
"""

from __future__ import annotations

import argparse
from typing import Final

from focas_net.client import FocasClient
from focas_net.errors import CncError
from focas_net.protocol import MAX_ALARM_MSG, FaultKind, FaultScope

from . import _format as fmt
from ._run import Go, Output

__all__ = ["FAULT_KINDS", "FAULT_SCOPES", "alarm", "clear", "fault", "panel"]

#: ``sim fault KIND``: the fault kinds by their command-line names.
FAULT_KINDS: Final = {k.name.lower(): k for k in FaultKind}
#: ``sim fault --scope``: the fault scopes by their command-line names.
FAULT_SCOPES: Final = {s.name.lower(): s for s in FaultScope}


def panel(args: argparse.Namespace) -> Go:
    mode = None if args.mode is None else fmt.parse_aut(args.mode)
    writes = mode is not None or args.pwe is not None or args.emergency is not None

    async def go(cnc: FocasClient) -> Output:
        # Only the switches given change (the others travel as -1, "unchanged"); with none
        # given nothing is written and the panel is only read.
        if writes:
            await cnc.sim.set_panel(mode, pwe=args.pwe, emergency=args.emergency)
        p = await cnc.sim.read_panel()
        st = await cnc.read_status()
        data = {
            "mode": int(p.mode),
            "pwe": int(p.pwe),
            "emergency": int(p.emergency),
            "status": fmt.status_dict(st),
        }
        return Output(data, f"{fmt.status_summary(st)} pwe={'on' if p.pwe else 'off'}")

    return go


def alarm(args: argparse.Namespace) -> Go:
    alm_type, alm_no = fmt.parse_alarm(args.alarm)
    msg = " ".join(args.message)
    kept = msg[:MAX_ALARM_MSG]  # the CNC keeps the first 32 characters of a message

    async def go(cnc: FocasClient) -> Output:
        # A CNC shows one entry per alarm: raised again while active, the alarm keeps its
        # message and nothing changes (docs/protocol.md section 8). Say so rather than "raised".
        code = fmt.alarm_code(alm_type, alm_no)
        axis = f" (axis {args.axis})" if args.axis else ""
        key = (args.axis, alm_type, alm_no)
        active = [a for a in await cnc.read_alarms(alm_type=alm_type) if a.key == key]
        if active:
            data = {"raised": None, "active": fmt.alarm_dict(active[0])}
            return Output(
                data,
                f"{code}{axis} is already active: {active[0].msg} (a CNC shows one entry per "
                "alarm: clear it first to raise it with another message)",
            )
        await cnc.sim.raise_alarm(alm_type, alm_no, msg, axis_no=args.axis)
        data = {
            "raised": {
                "code": code,
                "axis_no": args.axis,
                "alm_type": alm_type,
                "alm_no": alm_no,
                "msg": kept,
            }
        }
        return Output(data, f"raised {code}{axis} {kept}".rstrip())

    return go


def clear(args: argparse.Namespace) -> Go:
    alm_type, alm_no = fmt.parse_alarm_filter(args.alarm)

    async def go(cnc: FocasClient) -> Output:
        await cnc.sim.clear_alarms(alm_type, alm_no)
        remaining = await cnc.read_alarms()
        data = {"cleared": args.alarm or "all", "active": [fmt.alarm_dict(a) for a in remaining]}
        return Output(data, f"cleared {args.alarm or 'all alarms'}; {len(remaining)} still active")

    return go


def fault(args: argparse.Namespace) -> Go:
    kind = FAULT_KINDS[args.kind]
    scope = FAULT_SCOPES[args.scope]
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
