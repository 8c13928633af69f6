"""Why the CNC refused a command, in the machine's words: one table per command family.

The wire carries a refusal's EW code only; the reason stays in the machine (the dashboard,
which calls the machine itself, shows it). What a command knows, itself, its arguments and the
code, is enough to say it: each family's table maps an EW code to the reason, written from the
arguments, with what to do about it. :func:`reason` finds the table of a command by its name
as typed (``sim cycle start``); a code the table does not have gets no reason.
"""

from __future__ import annotations

import argparse
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Final

from focas_net._refusals import (
    NO_CONTROL,
    O_LINE,
    PARAM_GATE,
    READ_ONLY,
    SEARCH,
    cycle_refusal,
    item_named,
    macro_refusal,
    mode_refusal,
    no_path,
    param_refusal,
    pmc_refusal,
    program_busy,
    program_refusal,
    select_busy,
)
from focas_net._typed import WRONG_PASSWORD
from focas_net.errors import EW, CncError
from focas_net.server.faults import fault_refusal
from focas_net.sim.nc import ProgramError, no_program, parse_program

from . import _format as fmt

__all__ = ["FAMILIES", "Table", "Why", "as_said", "reason"]

#: The reason of a refusal, from the command's arguments.
Why = Callable[[argparse.Namespace], str]
#: A family's reasons by EW code.
Table = Mapping[int, Why]


def _read_only(args: argparse.Namespace) -> str:
    return READ_ONLY


def _no_control(args: argparse.Namespace) -> str:
    return NO_CONTROL


def _item(kind: str, args: argparse.Namespace) -> str:
    """``parameter 1420 axis 1``."""
    return item_named(kind, str(args.number).partition(".")[0], getattr(args, "axis", 0) or 0)


def _on(args: argparse.Namespace) -> str:
    """`` --path N`` for the advice of a command refused on path N (a per-path command
    acts on path 1 without it), nothing on path 1."""
    path = getattr(args, "path", 1)
    return "" if path in (None, 1) else f" --path {path}"


def _next(args: argparse.Namespace, command: str) -> str:
    """``focas-net COMMAND`` to run next, on the path the refused command named."""
    return f"focas-net {command}{_on(args)}"


def _param_gate(args: argparse.Namespace) -> str:
    gate = f"{PARAM_GATE} ({_next(args, 'sim panel --mode MDI --pwe on')})"
    if getattr(args, "protocol", "packed") == "native":
        return (
            f"{gate}; FOCAS/2 cannot send a parameter password: on a CNC that has one, write "
            "with --protocol packed --password"
        )
    if getattr(args, "password", None) is not None:
        return f"{gate}, and the --password given must be the CNC's"
    return f"{gate} and, when the CNC has a parameter password, --password"


def _param_password(args: argparse.Namespace, exc: CncError) -> str | None:
    """EW_PASSWD of a parameter write given ``--password``: the unlock refused it (the
    password is not the CNC's), or the unlock took it and the gate refused the write."""
    if getattr(args, "password", None) is None:
        return None
    if exc.detail.startswith("cnc_wrunlockparam"):
        return (
            f"--password {args.password} is not the CNC's parameter password (nothing was "
            "written; focas-net unlock PASSWORD tries one)"
        )
    return (
        f"the --password was accepted; {PARAM_GATE} too "
        f"({_next(args, 'sim panel --mode MDI --pwe on')})"
    )


def _param_length(args: argparse.Namespace, exc: CncError) -> str | None:
    """EW_LENGTH of a parameter write: with ``--width``, the client's words of the width the
    parameter has (``parameter 6711 is 4 bytes wide, not 2``, as the machine says it) and
    what to do; without, the CNC refused the width the client sent, the width of the
    parameter's own information."""
    if getattr(args, "width", None) is not None:
        said = exc.detail.partition(": ")[2]
        width = args.width
        said = said or f"parameter {args.number} is not {width} byte{'s' * (width > 1)} wide"
        return f"{said}: leave out --width (the CNC's own width is used)"
    return _param_refusal(args, EW.LENGTH)


def _param_refusal(args: argparse.Namespace, ew: int) -> str:
    """The words of the machine's refusal ``ew`` of ``param set`` as typed."""
    number, _, bit = str(args.number).partition(".")
    why = param_refusal(
        ew,
        number.strip(),
        args.value,
        axis=getattr(args, "axis", 0) or 0,
        bit=bit,
        protocol=getattr(args, "protocol", "packed"),
    )
    assert why is not None
    return why


#: ``param get``'s: a read has no value, no write gate and no ``--width`` to blame.
_PARAM_READ: Final[Table] = {
    EW.NUMBER: lambda a: f"the CNC has no {_item('parameter', a)}",
}
_PARAM: Final[Table] = {
    **_PARAM_READ,
    EW.PASSWD: _param_gate,
    EW.DATA: lambda a: _param_refusal(a, EW.DATA),
    EW.PROT: _read_only,
}
_DIAG: Final[Table] = {EW.NUMBER: lambda a: f"the CNC has no {_item('diagnostic', a)}"}
#: ``macro get``'s (``cnc_rdmacro``: no value to name, and no simulator control command).
_MACRO_READ: Final[Table] = {EW.NUMBER: lambda a: _macro_refusal(a, EW.NUMBER)}
_MACRO: Final[Table] = {
    **_MACRO_READ,
    EW.PROT: lambda a: _macro_refusal(a, EW.PROT),
    EW.DATA: lambda a: _macro_refusal(a, EW.DATA),
}


def _macro_refusal(args: argparse.Namespace, ew: int) -> str:
    """The words of the machine's refusal ``ew`` of ``macro get``, ``set`` or ``clear``."""
    why = macro_refusal(ew, args.number, getattr(args, "value", None))
    assert why is not None
    return why


#: ``macro clear``'s: ``sim_vacate_macro`` is a simulator control command.
_MACRO_CLEAR: Final[Table] = {
    **_MACRO_READ,
    EW.PROT: _MACRO[EW.PROT],
    EW.FUNC: _no_control,
}


# -- PMC ------------------------------------------------------------------------------------


def _pmc_span(args: argparse.Namespace) -> tuple[int, int]:
    """The first and the last byte address the command asked for."""
    if hasattr(args, "address"):  # pmc bit
        byte = fmt.parse_number_bit(args.address)[0]
        return byte, byte
    if hasattr(args, "count"):  # pmc read
        return args.start, args.start + args.count - 1
    data = fmt.parse_hex(args.hex) if args.hex is not None else fmt.parse_byte_list(args.values)
    return args.start, args.start + len(data) - 1


def _pmc_refusal(args: argparse.Namespace, ew: int) -> str:
    """The words of the machine's refusal ``ew`` of ``pmc read``, ``write`` or ``bit``."""
    why = pmc_refusal(ew, args.area.name, *_pmc_span(args))
    assert why is not None
    return why


def _pmc_protected(args: argparse.Namespace) -> str:
    area = args.area.name
    if getattr(args, "force", False):
        return _read_only(args)
    what = _pmc_refusal(args, EW.PROT)
    native = getattr(args, "protocol", "packed") == "native"
    if hasattr(args, "address"):  # pmc bit
        byte = fmt.parse_number_bit(args.address)[0]
        return (
            f"{what}; pmc bit has no --force: focas-net pmc write {area} {byte} VALUE --force "
            + "(with --protocol packed) " * native
            + "writes the whole byte as the simulator"
        )
    if native:
        return f"{what}; writing it as the simulator (--force) needs --protocol packed"
    return f"{what}: --force writes it as the simulator, unless the machine is read-only"


_PMC: Final[Table] = {
    EW.NUMBER: lambda a: _pmc_refusal(a, EW.NUMBER),
    EW.NOOPT: lambda a: _pmc_refusal(a, EW.NOOPT),
    EW.PROT: _pmc_protected,
}


def _pmc_forced(args: argparse.Namespace, exc: CncError) -> str | None:
    """``EW_FUNC`` of ``pmc write --force``, a simulator control command (None: another
    write, ``pmc_wrpmcrng``, which no simulator control setting refuses)."""
    return _no_control(args) if getattr(args, "force", False) else None


# -- part programs and the cycle --------------------------------------------------------------


def _loaded_text(args: argparse.Namespace) -> str:
    """The text of the file of ``program load`` (none when it cannot be read again)."""
    try:
        return Path(args.target).read_text("ascii", errors="replace")
    except OSError:
        return ""


def _loaded(args: argparse.Namespace) -> str:
    """``O1000``, the program of the file of ``program load``, or ``the program``."""
    m = O_LINE.match(_loaded_text(args))
    return f"O{int(m[1]):04d}" if m else "the program"


def _number(args: argparse.Namespace) -> int | None:
    """The program number the command named (``O1000`` or ``1000``), None for another text."""
    text = str(args.target).strip().upper().removeprefix("O")
    return int(text) if text.isdigit() else None


def _program_busy(args: argparse.Namespace) -> str:
    number = _number(args)
    return program_busy(number) if number is not None else f"{args.target} is being executed"


def _selected_busy(args: argparse.Namespace) -> str:
    number = _number(args)
    return select_busy(number) if number is not None else "a program is being executed"


def _searched(args: argparse.Namespace, exc: CncError) -> str:
    """EW_MODE of ``program select``: the client's words of the machine's reason (the mode,
    read after the refusal), else what the code alone says, with what to do."""
    said = exc.detail.partition(": ")[2] or mode_refusal(SEARCH, "MEM or EDIT")
    return f"{said} ({_next(args, 'sim panel --mode MEM')})"


def _store_reason(args: argparse.Namespace) -> str | None:
    """The reason the machine's program store gives for the text of ``program load FILE``
    (None when it takes it, or the file cannot be read again)."""
    try:
        parse_program(Path(args.target).read_text("ascii", errors="replace"))
    except ProgramError as exc:
        return f"{args.target}: {exc}"
    except OSError:
        pass
    return None


def _not_one_program(args: argparse.Namespace) -> str:
    """Why a CNC answered EW_DATA to the text of ``program load FILE``: the store's reason
    for the same text (a character that is not printable ASCII on line n, a second program,
    no O line ...), else what a program must be."""
    return _store_reason(args) or (
        f"{args.target} is not one part program: it must hold one program, whose first block "
        "is the O line with the program number (e.g. O1000)"
    )


def _beyond_the_store(args: argparse.Namespace) -> str:
    """Why a CNC answered EW_NUMBER to ``program load FILE``: the number as written and the
    range, in the store's words (``program number O0 is outside O1..O9999``)."""
    return _store_reason(args) or (
        f"the number of {_loaded(args)} is outside the program store's range"
    )


def _reset_first(args: argparse.Namespace) -> str:
    return f"({_next(args, 'sim cycle reset')} ends it)"


_PROGRAM_LOAD: Final[Table] = {
    EW.REJECT: lambda a: (
        f"{program_refusal(EW.REJECT, _loaded_text(a))}: give --replace to replace it"
    ),
    EW.DATA: _not_one_program,
    EW.NUMBER: _beyond_the_store,
    EW.OVRFLOW: lambda a: f"the program store is full ({_next(a, 'program delete N')} makes room)",
    EW.BUSY: lambda a: f"{program_refusal(EW.BUSY, _loaded_text(a))} {_reset_first(a)}",
    EW.PROT: _read_only,
}


def _no_program(args: argparse.Namespace) -> str:
    """The store's words for the program number given (``no program O1234``, or for one no
    program can have ``program number 10000 outside 1..9999``), as the dashboard says it."""
    text = str(args.target).strip().upper().removeprefix("O")
    what = no_program(int(text)) if text.isdigit() else f"no program {args.target}"
    other: int | None = getattr(args, "program_path", None)
    if other is None:
        return f"{what} ({_next(args, 'program list')})"
    # (found in another path's store: the same command there)
    program = f"O{int(text):04d}"
    command = f"focas-net program {args.action} {program}" + (f" --path {other}" * (other != 1))
    path = getattr(args, "path", 1)
    return f"{what} on path {path} ({program} is on path {other}: {command})"


_PROGRAM_SELECT: Final[Table] = {
    EW.NUMBER: _no_program,
    EW.BUSY: lambda a: f"{_selected_busy(a)} {_reset_first(a)}",
    EW.PROT: _read_only,
}
_PROGRAM_DELETE: Final[Table] = {
    EW.NUMBER: _no_program,
    EW.BUSY: lambda a: f"{_program_busy(a)} {_reset_first(a)}",
    EW.PROT: _read_only,
}
_SIM: Final[Table] = {EW.FUNC: _no_control, EW.PROT: _read_only}
#: What to do about a cycle start refused, by EW code.
_CYCLE_ADVICE: Final[Table] = {
    EW.MODE: lambda a: _next(a, "sim panel --mode MEM"),
    EW.ALARM: lambda a: f"{_alarm_advice(a)}, sim panel --emergency off{_on(a)} releases the stop",
    EW.DATA: lambda a: _next(a, "program select N"),
}


def _cycle_start(args: argparse.Namespace, exc: CncError) -> str | None:
    """Why a cycle start was refused, in the client's words of the machine's reason (the mode,
    or whether the emergency stop is on, which it read after the refusal), else in what the
    code alone says, with what to do."""
    advice = _CYCLE_ADVICE.get(exc.ew)
    said = exc.detail.partition(": ")[2] or cycle_refusal(exc.ew)
    if advice is None or said is None:
        return None
    if said == cycle_refusal(EW.ALARM, emergency=True):  # (the advice of the one it was)
        return f"{said} ({_next(args, 'sim panel --emergency off')} releases it)"
    if said == cycle_refusal(EW.ALARM, emergency=False):
        return f"{said} ({_alarm_advice(args)})"
    return f"{said} ({advice(args)})"


def _alarm_advice(args: argparse.Namespace) -> str:
    """What to do about the active alarms of the path ``args`` named."""
    return (
        f"{_next(args, 'alarms')} lists them; {_next(args, 'sim clear')} or sim cycle "
        f"reset{_on(args)} clears them"
    )


_CYCLE_START: Final[Table] = {**_SIM}


# -- the simulator's alarms and faults, VersaMax, the password ----------------------------------

_SIM_ALARM: Final[Table] = {
    **_SIM,
    # EW_ATTRIB: an --axis past the path's, told with the path's axes (sim_cmds.alarm)
    EW.DATA: lambda a: (
        f"the CNC cannot hold alarm {a.alarm}: its type, number or message is out of range"
    ),
}


def _fault_refused(args: argparse.Namespace) -> str:
    """EW_DATA of ``sim fault``: why, in the server's words (``fault_refusal``) where this
    package's server would refuse the same numbers."""
    why = fault_refusal(*args.fault_numbers) if hasattr(args, "fault_numbers") else None
    return "the server refused the fault" + (
        f": {why}" if why else ": its numbers are outside this server's ranges"
    )


_SIM_FAULT: Final[Table] = {**_SIM, EW.DATA: _fault_refused}
_VERSAMAX: Final[Table] = {EW.NUMBER: lambda a: f"rack {a.rack} slot {a.slot} holds no module"}
_UNLOCK: Final[Table] = {EW.PASSWD: lambda a: WRONG_PASSWORD}

#: The table of each command, by its name as typed.
FAMILIES: Final[Mapping[str, Table]] = {
    "param get": _PARAM_READ,
    "param set": _PARAM,
    "diag": _DIAG,
    "macro get": _MACRO_READ,
    "macro set": _MACRO,
    "macro clear": _MACRO_CLEAR,
    "pmc read": _PMC,
    "pmc write": _PMC,
    "pmc bit": _PMC,
    "program load": _PROGRAM_LOAD,
    "program select": _PROGRAM_SELECT,
    "program delete": _PROGRAM_DELETE,
    "program show": {EW.NUMBER: _no_program},
    "sim panel": _SIM,
    "sim alarm": _SIM_ALARM,
    "sim clear": _SIM,
    "sim cycle start": _CYCLE_START,
    "sim cycle hold": _SIM,
    "sim cycle reset": _SIM,
    "sim override": _SIM,
    "sim fault": _SIM_FAULT,
    "sim faults": _SIM,
    "versamax": _VERSAMAX,
    "unlock": _UNLOCK,
}


#: Reasons that need the refusal itself (which call of the command refused), before the
#: tables: None from one of them leaves the reason to the table.
_BY_REFUSAL: Final[
    Mapping[tuple[str, int], Callable[[argparse.Namespace, CncError], str | None]]
] = {
    ("param set", EW.PASSWD): _param_password,
    ("param set", EW.LENGTH): _param_length,
    ("pmc write", EW.FUNC): _pmc_forced,
    **{("sim cycle start", ew): _cycle_start for ew in _CYCLE_ADVICE},
    ("program select", EW.MODE): _searched,
}


#: Commands whose reasons say what the client's error says and more (the program file read
#: with the store's rules, what to run next): theirs replace the client's words.
_OWN_WORDS: Final = frozenset(
    {
        "param set",
        "macro set",
        "program load",
        "program select",
        "program delete",
        "program show",
        "pmc read",
        "pmc write",
        "pmc bit",
        "macro clear",
        "sim cycle start",
    }
)


def as_said(command: str, exc: CncError, hint: str = "") -> CncError:
    """``exc`` as the command line shows it next to :func:`reason`'s words, ``hint``: of a
    command whose reason replaces the client's (:data:`_OWN_WORDS`), or one whose reason
    holds the client's words of it, the code and the call alone (``cnc_download``), so that a
    reason is said once."""
    said = exc.detail.partition(": ")[2]
    if command not in _OWN_WORDS and not (said and said in hint):
        return exc
    return CncError.from_ew(exc.ew, exc.detail.partition(": ")[0])


def reason(command: str, args: argparse.Namespace, exc: CncError) -> str | None:
    """Why ``command`` (its name as typed) with ``args`` was refused with ``exc``'s EW code;
    None when its table does not say."""
    by_refusal = _BY_REFUSAL.get((command, exc.ew))
    said = None if by_refusal is None else by_refusal(args, exc)
    if said is not None:
        return said
    why = FAMILIES.get(command, {}).get(exc.ew)
    if why is None and exc.ew == EW.PATH and getattr(args, "path", None) is not None:
        return _no_path(args)  # any command of a path
    return None if why is None else why(args)


def _no_path(args: argparse.Namespace) -> str:
    """The machine's paths, as the command read them before it refused ``--path``."""
    count: int | None = getattr(args, "path_count", None)
    if count is None:
        return f"the CNC has no path {args.path} (--path names one of its paths)"
    give = "leave out --path" if count == 1 else f"give --path 1..{count}"
    return f"{no_path(args.path, count)} ({give})"
