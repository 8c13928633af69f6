"""The client commands of ``focas-net`` as one table, and the parsers built from it.

Each row is a :class:`Cmd` (name, help, handler, arguments; ``writes`` adds ``--password``) or
a :class:`Group` of them (``param get``, ``param set``, ...). An argument is an :func:`arg`:
the flags and keyword options of one ``add_argument`` call. Every command also gets the
``connection`` options (``--host``, ``--port``, ``--timeout``, ``--protocol``, ``--json``, the
TLS options), a description made from its help, and the exit codes as its epilog.
"""

from __future__ import annotations

import argparse
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from functools import partial
from typing import Any, Final, Literal, TypedDict, Unpack

from focas_net._typed import macro_number
from focas_net.protocol import fault_kind_of
from focas_net.server.faults import MAX_FAULT_COUNT

from . import program_cmds, read_cmds, sim_cmds, watch_cmds, write_cmds
from ._args import (
    ALARM_AXIS,
    AREA,
    BOOL,
    DIAG_AXIS,
    EXIT_CODES,
    FEED,
    FILE_NAME,
    HISTORY_DEPTH,
    HOST,
    INT,
    INTERVAL,
    PARAM_AXIS,
    PASSWORD,
    PATH,
    PORT,
    POSITIVE,
    RAPID,
    SECONDS,
    SPINDLE,
    USAGE_PROG,
    WIDTH,
    argument_type,
    choice,
    command_parser,
    parse_bounded,
)
from ._format import parse_aut
from ._run import PACKED, PROTOCOLS, Handler, runner

__all__ = ["COMMANDS", "Arg", "ArgOptions", "Cmd", "Group", "arg", "register"]


class ArgOptions(TypedDict, total=False):
    """The keyword options of ``add_argument`` that the table uses."""

    action: Literal["store_true"]
    choices: Sequence[Any]
    default: Any
    help: str
    metavar: str
    nargs: Literal["?", "*"]
    type: Callable[[str], Any]


@dataclass(frozen=True, slots=True)
class Arg:
    """One ``add_argument`` call: ``--axis`` or a positional name, and its options."""

    flags: tuple[str, ...]
    options: ArgOptions


def arg(*flags: str, **options: Unpack[ArgOptions]) -> Arg:
    """An argument, written like ``add_argument``: ``arg("--axis", type=..., help=...)``."""
    return Arg(flags, options)


@dataclass(frozen=True, slots=True)
class Cmd:
    """A command: ``focas-net NAME`` or, in a :class:`Group`, ``focas-net GROUP NAME``."""

    name: str
    help: str
    handler: Handler
    args: tuple[Arg, ...] = ()
    writes: bool = False  #: takes ``--password`` (sent with cnc_wrunlockparam after connecting)


@dataclass(frozen=True, slots=True)
class Group:
    """Commands under one name, chosen by an ACTION: ``focas-net param get``."""

    name: str
    help: str
    commands: tuple[Cmd, ...]


# -- shared arguments -----------------------------------------------------------------------

_CONNECTION: Final = (
    arg("--host", type=HOST, default="127.0.0.1", help="CNC address (default %(default)s)"),
    arg("--port", type=PORT, default=8193, help="CNC port (default %(default)s)"),
    arg(
        "--path",
        type=PATH,
        default=1,
        metavar="N",
        help="the CNC path (1..10) every per-path value is read from or written to "
        "(default %(default)s; watch shows every path)",
    ),
    arg(
        "--timeout",
        type=SECONDS,
        default=3.0,
        metavar="SECONDS",
        help="per-call timeout (default %(default)s)",
    ),
    arg(
        "--protocol",
        type=choice(PROTOCOLS, "protocol"),
        choices=PROTOCOLS,
        default=PACKED,
        help="packed: this project's protocol (default); native: FOCAS/2 Ethernet, as FANUC's "
        "library speaks it to a real control (and to focas-net serve on the same port)",
    ),
    arg("--json", action="store_true", help="print JSON instead of a table"),
    arg(
        "--tls",
        action="store_true",
        help="connect with TLS, checking the server's certificate against the system's CAs",
    ),
    arg(
        "--tls-ca",
        type=FILE_NAME,
        metavar="FILE",
        help="trust the certificates in FILE (PEM) to check the server's; implies --tls",
    ),
    arg(
        "--tls-insecure",
        action="store_true",
        help="TLS without checking the server's certificate (testing only); implies --tls",
    ),
)
_PASSWORD: Final = arg(
    "--password",
    type=PASSWORD,
    metavar="TEXT",
    help="parameter password, sent with cnc_wrunlockparam after connecting",
)
_EPILOG: Final = "exit status: " + ", ".join(f"{code} {text}" for code, text in EXIT_CODES)

_AXIS_HELP: Final = "axis 1..n for an axis item; 0 for a non-axis item (default 0)"
_AXIS: Final = arg(
    "--axis",
    type=ALARM_AXIS,
    default=0,
    metavar="N",
    help="the alarm's axis 1..n; 0: an alarm of no axis (default 0)",
)
_PARAM_AXIS: Final = arg("--axis", type=PARAM_AXIS, default=0, metavar="N", help=_AXIS_HELP)
_DIAG_AXIS: Final = arg("--axis", type=DIAG_AXIS, default=0, metavar="N", help=_AXIS_HELP)
_PARAM_NUMBER: Final = arg(
    "number", metavar="NUMBER[.BIT]", help="parameter number, e.g. 1320 or 1815.4"
)
_MACRO_NUMBER: Final = arg(
    "number",
    type=argument_type(macro_number, "integer"),
    metavar="NUMBER",
    help="variable number, e.g. 100 or #100",
)
_AREA: Final = arg("area", type=AREA, metavar="AREA", help="area letter: X Y F G R T C D K A E")
#: (a whole number: one no request carries, -1 or 70000, is the client's to refuse, in the
#: words every front end gives)
_START: Final = arg("start", type=INT, metavar="START", help="first byte address")


def _bounded(low: int, high: int, what: str) -> Callable[[str], int]:
    """An integer argument within ``low..high``."""
    return argument_type(partial(parse_bounded, low=low, high=high), what)


def _range_arg(name: str, low: int, high: int) -> Arg:
    """A positional integer argument ``NAME`` within ``low..high``."""
    what = _bounded(low, high, name)
    return arg(name, type=what, metavar=name.upper(), help=f"{name} {low}..{high}")


#: ``position --kind``, as cnc_rdposition numbers them (0..3).
_POSITION_KINDS: Final = ("absolute", "machine", "relative", "distance")
#: ``sim fault --scope``, sorted (a KIND is read by :func:`fault_kind_of`).
_FAULT_SCOPES: Final = tuple(sorted(sim_cmds.FAULT_SCOPES))

#: A VersaMax station's racks and slots.
_RACKS: Final = (0, 7)
_SLOTS: Final = (0, 9)


# -- the table ------------------------------------------------------------------------------

COMMANDS: Final[tuple[Cmd | Group, ...]] = (
    Cmd("status", "read the CNC status (cnc_statinfo, ODBST)", read_cmds.status),
    Cmd("sysinfo", "read the CNC identity (cnc_sysinfo, ODBSYS)", read_cmds.sysinfo),
    Cmd(
        "program",
        "read the program numbers, feed and spindle speed (cnc_rdprgnum, cnc_actf, cnc_acts), "
        "or list, show, load, delete or select part programs",
        program_cmds.program,
        (
            arg(
                "action",
                nargs="?",
                type=choice(program_cmds.PROGRAM_ACTIONS, "action"),
                choices=program_cmds.PROGRAM_ACTIONS,
                metavar="ACTION",
                help="list: the program directory; show N: a program's text; load FILE: store "
                "a program; delete N; select N: make N the main program (default: read the "
                "numbers, feed and spindle speed)",
            ),
            arg("target", nargs="?", metavar="N|FILE", help="program number (O1000) or file"),
            arg(
                "--replace",
                action="store_true",
                help="load: replace a stored program of the same number",
            ),
        ),
    ),
    Cmd(
        "position",
        "read axis positions (cnc_rdposition)",
        read_cmds.position,
        (
            arg(
                "--kind",
                type=choice(_POSITION_KINDS, "kind"),
                choices=_POSITION_KINDS,
                default="absolute",
                help="which position; distance = distance to go (default %(default)s)",
            ),
            arg(
                "--axis", type=POSITIVE, metavar="N", help="only axis N (1..n; default every axis)"
            ),
        ),
    ),
    Group(
        "param",
        "read or write a CNC parameter",
        (
            Cmd(
                "get",
                "read a parameter (cnc_rdparam)",
                read_cmds.param_get,
                (_PARAM_NUMBER, _PARAM_AXIS),
            ),
            Cmd(
                "set",
                "write a parameter (cnc_wrparam); NUMBER.BIT writes one bit by read-modify-write",
                write_cmds.param_set,
                (
                    _PARAM_NUMBER,
                    arg("value", metavar="VALUE", help="integer (0x.. hex); 0/1 for a bit"),
                    _PARAM_AXIS,
                    arg(
                        "--width",
                        type=WIDTH,
                        choices=(1, 2, 4),
                        help="value width in bytes (default: the width the CNC reports)",
                    ),
                ),
                writes=True,
            ),
        ),
    ),
    Group(
        "macro",
        "read or write a custom macro variable",
        (
            Cmd(
                "get", "read a macro variable (cnc_rdmacro)", read_cmds.macro_get, (_MACRO_NUMBER,)
            ),
            Cmd(
                "set",
                "write a macro variable (cnc_wrmacro)",
                write_cmds.macro_set,
                (_MACRO_NUMBER, arg("value", metavar="VALUE", help="decimal value, e.g. 12.5")),
                writes=True,
            ),
            Cmd(
                "clear",
                "make a macro variable vacant (simulator control 0x0E11; a real CNC has none)",
                write_cmds.macro_clear,
                (_MACRO_NUMBER,),
            ),
        ),
    ),
    Cmd(
        "diag",
        "read a diagnostic (cnc_diagnoss)",
        read_cmds.diag,
        (
            arg("number", type=INT, metavar="NUMBER", help="diagnostic number, e.g. 300"),
            _DIAG_AXIS,
        ),
    ),
    Group(
        "pmc",
        "read or write PMC data",
        (
            Cmd(
                "read",
                "read PMC bytes (pmc_rdpmcrng)",
                read_cmds.pmc_read,
                (
                    _AREA,
                    _START,
                    arg(
                        "count",
                        # (a whole number: one no request carries, 0 or 100000, is the
                        # client's to refuse, as START's)
                        type=INT,
                        nargs="?",
                        default=1,
                        metavar="COUNT",
                        help="bytes (default 1)",
                    ),
                ),
            ),
            Cmd(
                "write",
                "write PMC bytes (pmc_wrpmcrng)",
                write_cmds.pmc_write,
                (
                    _AREA,
                    _START,
                    arg(
                        "values",
                        nargs="*",
                        default=[],  # (not one of the required: --hex gives the bytes too)
                        metavar="BYTE",
                        help="byte values: 1 2 0xff or 1,2,255",
                    ),
                    arg("--hex", metavar="HEX", help="the bytes as hex instead, e.g. 0102ff"),
                    arg(
                        "--force",
                        action="store_true",
                        help="write through simulator control, ignoring write protection "
                        "(drives X and F)",
                    ),
                ),
                writes=True,
            ),
            Cmd(
                "bit",
                "read a PMC bit, or write it (read-modify-write of its byte) when VALUE is given",
                write_cmds.pmc_bit,
                (
                    _AREA,
                    arg("address", metavar="BYTE.BIT", help="e.g. 100.3"),
                    arg(
                        "value",
                        nargs="?",
                        type=BOOL,
                        metavar="VALUE",
                        help="0/1 (on/off) to write",
                    ),
                ),
                writes=True,
            ),
        ),
    ),
    Cmd(
        "alarms",
        "read the active alarms (cnc_rdalmmsg) and the alarm history (cnc_rdalmhistry)",
        read_cmds.alarms,
        (
            arg(
                "--history",
                type=HISTORY_DEPTH,
                default=0,
                metavar="N",
                help="also the N most recent history entries (1 or more; above 250 read as 250)",
            ),
            arg(
                "--follow",
                action="store_true",
                help="poll and print alarm events until Ctrl-C (with --history: history entries "
                "too)",
            ),
            arg(
                "--interval",
                type=INTERVAL,
                metavar="SECONDS",
                help="poll interval of --follow, 0.05..3600 (default 1)",
            ),
            arg("--count", type=POSITIVE, metavar="N", help="stop --follow after N events"),
        ),
    ),
    Cmd(
        "watch",
        "show the machine's state live (run state, program, positions, feed, spindle, "
        "overrides, parts, timers, alarms), refreshed in place, until Ctrl-C",
        watch_cmds.watch,
        (
            arg(
                "--interval",
                type=INTERVAL,
                default=watch_cmds.DEFAULT_INTERVAL,
                metavar="SECONDS",
                help="seconds between frames, 0.05..3600 (default %(default)s)",
            ),
            arg("--count", type=POSITIVE, metavar="N", help="stop after N frames"),
        ),
    ),
    Cmd(
        "unlock",
        "check a parameter password (cnc_wrunlockparam); the unlock lasts one connection",
        write_cmds.unlock,
        (arg("secret", type=PASSWORD, metavar="PASSWORD", help="the parameter password"),),
    ),
    Cmd(
        "versamax",
        "read a VersaMax module configuration record (versamax_rdconfig)",
        read_cmds.versamax,
        (
            _range_arg("rack", *_RACKS),
            _range_arg("slot", *_SLOTS),
        ),
    ),
    Group(
        "sim",
        "drive a simulated CNC (control commands; a real CNC refuses)",
        (
            Cmd(
                "panel",
                "set the operator panel's switches given (mode, PWE, emergency stop), or "
                "show them when none is given",
                sim_cmds.panel,
                (
                    arg(
                        "--mode",
                        type=argument_type(parse_aut, "mode"),
                        metavar="MODE",
                        help="MDI MEM EDIT HND JOG ... (default: unchanged)",
                    ),
                    arg(
                        "--pwe",
                        type=BOOL,
                        metavar="on|off",
                        help="parameter write enable (default: unchanged)",
                    ),
                    arg(
                        "--emergency",
                        type=BOOL,
                        metavar="on|off",
                        help="emergency stop (default: unchanged)",
                    ),
                ),
            ),
            Cmd(
                "alarm",
                "raise an alarm",
                sim_cmds.alarm,
                (
                    arg("alarm", metavar="ALARM", help="alarm code, e.g. PS0100 (or TYPE:NO)"),
                    arg(
                        "message",
                        nargs="*",
                        default=[],  # (may be left out: not one of the required)
                        metavar="MESSAGE",
                        help="alarm message (ASCII)",
                    ),
                    _AXIS,
                ),
            ),
            Cmd(
                "clear",
                "clear active alarms (the history is kept)",
                sim_cmds.clear,
                (
                    arg(
                        "alarm",
                        nargs="?",
                        metavar="ALARM",
                        help="PS0100, PS (or its number, 3) for a whole type, or all (the default)",
                    ),
                ),
            ),
            Cmd(
                "cycle",
                "cycle start, feed hold or reset of the part program",
                program_cmds.cycle,
                (
                    arg(
                        "action",
                        type=argument_type(program_cmds.cycle_action, "action"),
                        metavar="ACTION",
                        help="what to press: start, hold or reset",
                    ),
                ),
            ),
            Cmd(
                "override",
                "set the overrides given (percent), or show them when none is given",
                program_cmds.override,
                (
                    arg("--feed", type=FEED, metavar="PCT", help="feed override 0..254"),
                    arg(
                        "--rapid",
                        type=RAPID,
                        metavar="PCT",
                        help="rapid override F0 (0), 25, 50 or 100",
                    ),
                    arg(
                        "--spindle",
                        type=SPINDLE,
                        metavar="PCT",
                        help="spindle override 0..254",
                    ),
                ),
            ),
            Cmd(
                "fault",
                "make the next answers misbehave (fault injection)",
                sim_cmds.fault,
                (
                    arg(
                        "kind",
                        type=argument_type(fault_kind_of, "kind"),
                        metavar="KIND",
                        help="what happens to the answers: delay, drop, error or split",
                    ),
                    arg(
                        "--arg",
                        metavar="VALUE",
                        help="delay: milliseconds; error: EW code (number or name, e.g. EW_BUSY)",
                    ),
                    arg(
                        "--count",
                        type=argument_type(sim_cmds.parse_fault_count, "count"),
                        default=1,
                        metavar="N",
                        help=f"answers, 1..{MAX_FAULT_COUNT} (default 1)",
                    ),
                    arg(
                        "--scope",
                        type=choice(_FAULT_SCOPES, "scope"),
                        choices=_FAULT_SCOPES,
                        default="machine",
                        help="machine: the next answers on any connection (default); "
                        "connection: only this command's own connection",
                    ),
                ),
            ),
            Cmd(
                "faults",
                "list the pending faults, first to apply first (or remove them with --clear)",
                sim_cmds.faults,
                (
                    arg(
                        "--clear",
                        action="store_true",
                        help="remove every pending fault of the scope",
                    ),
                    arg(
                        "--scope",
                        type=choice(_FAULT_SCOPES, "scope"),
                        choices=_FAULT_SCOPES,
                        default="machine",
                        help="machine: the machine's queue (default); connection: this "
                        "command's own connection (always empty)",
                    ),
                ),
            ),
        ),
    ),
)


# -- building the parsers -------------------------------------------------------------------


def _add_argument(container: argparse._ActionsContainer, a: Arg) -> None:
    container.add_argument(*a.flags, **a.options)


def _add_command(subparsers: Any, cmd: Cmd) -> None:
    p = command_parser(
        subparsers,
        cmd.name,
        help=cmd.help,
        description=cmd.help[0].upper() + cmd.help[1:] + ".",
        epilog=_EPILOG,
    )
    connection = p.add_argument_group("connection")
    for a in (*_CONNECTION, _PASSWORD) if cmd.writes else _CONNECTION:
        _add_argument(connection, a)
    for a in cmd.args:
        _add_argument(p, a)
    p.set_defaults(func=runner(cmd.handler), **{USAGE_PROG: p.prog})


def _add_group(subparsers: Any, group: Group) -> None:
    p = subparsers.add_parser(
        group.name, help=group.help, description=group.help[0].upper() + group.help[1:]
    )
    actions = p.add_subparsers(dest=f"{group.name}_command", required=True, metavar="ACTION")
    for cmd in group.commands:
        _add_command(actions, cmd)


def register(subparsers: Any, commands: Sequence[Cmd | Group] = COMMANDS) -> None:
    """Add ``commands`` (by default every client command) to the ``focas-net`` parser."""
    for row in commands:
        if isinstance(row, Group):
            _add_group(subparsers, row)
        else:
            _add_command(subparsers, row)
