"""Why a CNC refused a parameter, a macro or a PMC write, in words, from what the write named:
the reasons the command line (``cli/_reasons.py``, which adds what to type next) and the gateway's
write methods (``gateway/writer.py``) both give; and why a program folder call was refused, the
native client's.

The wire carries a refusal's EW code only; the reason stays in the machine. What the write
knows, the item, the value sent and the code, is enough to say it. A code these words do not
cover gets None (the front end says the code alone).
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from typing import Final

from focas_net.errors import EW

__all__ = [
    "AXIS_NAME_PARAM",
    "CYCLE_START",
    "DRIVEN_AREAS",
    "FANUC_SPANS",
    "NO_CONTROL",
    "O_LINE",
    "PARAM_GATE",
    "READ_ONLY",
    "READ_ONLY_MACHINE",
    "SEARCH",
    "SPINDLE_DIAGS",
    "axis_misfit",
    "axis_past",
    "cycle_refusal",
    "folder_refusal",
    "item_named",
    "macro_refusal",
    "mode_refusal",
    "no_item",
    "no_path",
    "not_ready",
    "param_refusal",
    "parts_refusal",
    "path_axes",
    "pmc_protected",
    "pmc_refusal",
    "program_busy",
    "program_missing",
    "program_refusal",
    "select_busy",
    "system_read_only",
]

#: Parameter 1020, each axis's name (FANUC's number): the machine reads it, the reasons name it.
AXIS_NAME_PARAM: Final = 1020
#: FANUC's diagnostics of the serial spindle (400 link .. 4902 power), read with the spindle
#: number as the axis: the machine answers them by spindle, and the clients name a spindle the
#: path has not as a spindle, never as an axis.
SPINDLE_DIAGS: Final = frozenset(
    {400, 401, 403, 408, 410, 411, 417, 418, 425, 445, 710, 712, 1520, 1521, 4902}
)
#: EW_PROT of a read-only machine, in the machine's words (which every front end carries).
READ_ONLY_MACHINE: Final = "the machine is read-only"
#: EW_PROT of a write no setting of the CNC refuses: the server was started read-only.
READ_ONLY: Final = f"{READ_ONLY_MACHINE} (a server started with --read-only)"
#: EW_FUNC of a simulator control command: the server serves none.
NO_CONTROL: Final = (
    "the server takes no simulator control commands (a real CNC, or serve --no-control)"
)
#: EW_PASSWD of a parameter write: FANUC's write gate (the setting screen's PWE, in MDI mode).
PARAM_GATE: Final = "parameter writes need MDI mode and PWE on"


#: FANUC's valid data range of the parameters the machine keeps a count or a timer in: the
#: parts counts (6711..6713), the timers' minutes (6750, 6752, ...) and the ms past them
#: (6751, 6753, ...). The machine takes them when a builder gives no range; a refusal names them.
FANUC_SPANS: Final[Mapping[int, tuple[int, int]]] = {
    **dict.fromkeys((6711, 6712, 6713), (0, 999_999_999)),
    **dict.fromkeys(range(6750, 6759, 2), (0, 999_999_999)),
    **dict.fromkeys(range(6751, 6759, 2), (0, 59_999)),
}

#: FANUC's system variables that a program and a FOCAS client only read, by range, with what
#: they hold (a FANUC CNC answers a write of one with EW_PROT, a program's with an alarm).
_SYSTEM_READ_ONLY: Final = (
    (0, 0, "always vacant"),
    (4001, 4130, "modal information"),
    (3011, 3012, "the CNC's clock: its date and time"),
    (5001, 5120, "position information"),
)


def _whole(text: object) -> int | None:
    """``text`` as a whole number written as a command line takes it (``6711``, ``0x1A37``);
    None when it is none."""
    raw = str(text).strip()
    for base in (10, 0):
        try:
            return int(raw, base)
        except ValueError:
            continue
    return None


def system_read_only(number: int | str) -> str | None:
    """Why macro variable ``number`` is not written when it is one of FANUC's read-only system
    variables, in the words of every front end (the machine's refusal, the command line's and
    the gateway's reason for EW_PROT): ``macro variable #5001 is read-only (FANUC's
    #5001..#5120: position information)``; None for another variable."""
    known = _whole(number)
    for first, last, holds in _SYSTEM_READ_ONLY:
        if known is not None and first <= known <= last:
            span = f"#{first}" if first == last else f"#{first}..#{last}"
            return f"macro variable #{known} is read-only (FANUC's {span}: {holds})"
    return None


#: FANUC's parts count and total parts, as macro variables.
_PARTS_VARIABLES: Final = (3901, 3902)


def parts_refusal(number: int | str, value: object) -> str:
    """Why parts count ``#number`` (3901 or 3902) does not take ``value`` (None: made vacant),
    in the words of the machine, the command line and the gateway."""
    if value is None:
        return f"#{number} is a parts count, which always holds a number (write 0 to reset it)"
    return f"#{number} is a parts count: it holds a whole number of 0 or more, not {value}"


def no_path(path: int | Sequence[int], count: int) -> str:
    """Why a CNC of ``count`` paths has no path ``path`` (or none of several), in the words of
    the machine (the page shows them), the command line (which adds the ``--path`` to give)
    and the gateway (which adds the key that named them): ``the CNC has no path 3: it has
    path 1 only``, ``the CNC has no paths 2, 3: it has path 1 only``."""
    has = "path 1 only" if count == 1 else f"paths 1..{count}"
    named = [path] if isinstance(path, int) else list(path)
    which = f"path {named[0]}" if len(named) == 1 else f"paths {', '.join(map(str, named))}"
    return f"the CNC has no {which}: it has {has}"


def path_axes(axes: int) -> str:
    """``the path has 3 axes``: the count an axis past the path's is told with (the command
    line adds ``give --axis 1..3``, the gateway ``give Axis 1..3``)."""
    return f"the path has {axes} ax{'is' if axes == 1 else 'es'}"


def axis_past(axis: int, axes: int) -> str:
    """Why ``axis`` is none of a path of ``axes`` axes, in the words of the machine and both
    clients (which check it before sending, as FANUC's library does): ``axis 9 is outside
    1..3: the path has 3 axes``."""
    return f"axis {axis} is outside 1..{axes}: {path_axes(axes)}"


def mode_refusal(refused: str, modes: str, mode: str | None = None) -> str:
    """EW_MODE of ``refused`` (``cycle start refused``), which runs in ``modes`` (``MEM``) only,
    in ``mode``, as the machine says it (``cycle start refused: the mode is JOG, not MEM``)
    and a front end that knows not the mode (None, the wire's code alone: ``cycle start
    refused: the mode is not MEM``); what to type is the front end's to add."""
    return (
        f"{refused}: the mode is {mode}, not {modes}"
        if mode
        else f"{refused}: the mode is not {modes}"
    )


#: A cycle start the CNC refused, as the machine and every front end begin its reason.
CYCLE_START: Final = "cycle start refused"


def not_ready(
    refused: str, ew: int, *, mode: str | None = None, emergency: bool | None = None
) -> str | None:
    """Why automatic operation did not start (``refused``: what did not, ``cycle start
    refused``), in the machine's words: EW_MODE (the mode, ``mode``, is not MEM), EW_ALARM
    (``emergency``: the emergency stop is on; False: an alarm is active; None, a front end
    that cannot tell: either), EW_DATA (no main program is selected); None for another code.
    What to type next is the front end's to add."""
    if ew == EW.MODE:
        return mode_refusal(refused, "MEM", mode)
    if ew == EW.ALARM:
        if emergency is None:
            return f"{refused}: an alarm is active or the emergency stop is on"
        return f"{refused}: {'the emergency stop is on' if emergency else 'an alarm is active'}"
    if ew == EW.DATA:
        return f"{refused}: no main program is selected"
    return None


def cycle_refusal(ew: int, *, mode: str | None = None, emergency: bool | None = None) -> str | None:
    """Why the CNC answered ``ew`` to a cycle start (:func:`not_ready`)."""
    return not_ready(CYCLE_START, ew, mode=mode, emergency=emergency)


def no_item(kind: str, number: int | str, axis: int = 0) -> str:
    """EW_NUMBER of an item the CNC has not, in the words of the machine (so the page) and the
    command line: ``the CNC has no parameter 1234``, ``the CNC has no macro variable #50``."""
    return f"the CNC has no {item_named(kind, number, axis)}"


def item_named(kind: str, number: int | str, axis: int = 0) -> str:
    """``parameter 1420 axis 1`` (``axis`` 0: an item of no axis)."""
    return f"{kind} {number}" + (f" axis {axis}" if axis else "")


def axis_misfit(kind: str, number: int | str, axis: int) -> str:
    """EW_ATTRIB of an axis the item does not take: ``parameter 1420 is an axis parameter``
    (written or read with no axis, ``axis`` 0), ``parameter 6711 is not an axis parameter``
    (with one); what to give instead is the front end's to add."""
    return f"{kind} {number} is {'an' if axis == 0 else 'not an'} axis {kind}"


def _param_range(
    number: int | str, value: object, axis: int, bit: str, span: tuple[int, int] | None
) -> str:
    what = item_named("parameter", number, axis)
    if bit:  # a bit written by read-modify-write: the value it makes is out of range
        return (
            f"the CNC refused {what} with bit {bit} set to {value}: the value that makes is "
            "outside the parameter's range"
        )
    said = f"the CNC refused {value} for {what}: outside its range"
    span = span or FANUC_SPANS.get(_whole(number) or -1)  # the machine's, else FANUC's
    typed = _whole(value)
    if span is not None and typed is not None and not span[0] <= typed <= span[1]:
        said += f" {span[0]}..{span[1]}"
    if "." in str(value):
        said += ", or more decimals than the parameter keeps"
    if str(number).strip() == str(AXIS_NAME_PARAM):
        said += (
            ", or a letter other than the axis's own (a focas-net machine's axes are fixed "
            "when it is built; a control takes a new name at its next power-on)"
        )
    return said


def _param_width(number: int | str, axis: int, protocol: str) -> str:
    """EW_LENGTH of a write at the width of the parameter's own information."""
    said = (
        f"the CNC refused the value of {item_named('parameter', number, axis)} at the width it gave"
    )
    if protocol == "native":
        said += (
            ": FOCAS/2 at a 16i-class CNC gives a real parameter as a bit parameter and "
            "cannot write it (write it with --protocol packed, or at the CNC)"
        )
    return said


def param_refusal(
    ew: int,
    number: int | str,
    value: object,
    *,
    axis: int = 0,
    bit: str = "",
    protocol: str = "packed",
    span: tuple[int, int] | None = None,
) -> str | None:
    """Why the CNC answered ``ew`` to ``cnc_wrparam`` of ``value`` (as typed or sent) for
    parameter ``number`` (``axis`` 0: no axis; ``bit``: the bit written, by
    read-modify-write, as typed), at the width of the parameter's own information, through
    ``protocol``; None for a code these words do not cover. EW_PASSWD is the CNC's gate
    (:data:`PARAM_GATE`); what unlocks it is the front end's to add. ``span``: the range the
    machine itself refused the value for (a front end that has the code alone names FANUC's
    range of the parameters the machine keeps a count or a timer in, :data:`FANUC_SPANS`)."""
    if ew == EW.NUMBER:
        return no_item("parameter", number, axis)
    if ew == EW.PASSWD:
        return PARAM_GATE
    if ew == EW.DATA:
        return _param_range(number, value, axis, bit, span)
    if ew == EW.PROT:
        return READ_ONLY
    if ew == EW.LENGTH:
        return _param_width(number, axis, protocol)
    return None


def macro_refusal(ew: int, number: int | str, value: object = None) -> str | None:
    """Why the CNC answered ``ew`` to ``cnc_wrmacro`` of ``value`` (None: a read or a
    vacating) for ``#number``; None for a code these words do not cover."""
    if ew == EW.NUMBER:
        return no_item("macro variable", f"#{number}")
    if ew == EW.PROT:
        return (
            system_read_only(number)
            or f"macro variable #{number} is read-only, or the machine is read-only"
        )
    if ew == EW.DATA and value is not None:
        if _whole(number) in _PARTS_VARIABLES:
            return parts_refusal(number, value)
        return f"#{number} cannot hold {value}"
    return None


#: The PMC areas a CNC's own PMC writes (the machine's inputs X and the CNC's signals F),
#: write-protected on every simulated machine.
DRIVEN_AREAS: Final = ("X", "F")


def pmc_protected(area: str) -> str:
    """Why PMC area ``area`` (its letter) takes no write: ``PMC area X is write-protected (the
    machine drives it)`` for an area the CNC drives, in the words of the machine and, with
    what else EW_PROT may mean, of every front end that has the code alone."""
    driven = " (the machine drives it)" if area in DRIVEN_AREAS else ""
    return f"PMC area {area} is write-protected{driven}"


def pmc_refusal(ew: int, area: str, first: int, last: int) -> str | None:
    """Why the CNC answered ``ew`` to ``pmc_wrpmcrng`` (or a read) of bytes ``first..last``
    of PMC area ``area`` (its letter); None for a code these words do not cover. EW_PROT is
    the area's protection; writing it as the simulator is the front end's to add."""
    if ew == EW.NUMBER:
        span = f"{area}{first}" + (f"..{area}{last}" if last != first else "")
        return f"{span} goes past the end of PMC area {area}"
    if ew == EW.NOOPT:
        return f"the CNC has no PMC area {area}"
    if ew == EW.PROT:
        if area in DRIVEN_AREAS:
            return f"{pmc_protected(area)}, or the machine is read-only"
        return f"the machine is read-only, or its machine file write-protects PMC area {area}"
    return None


#: What the name of each of FANUC's program folder calls must name, which EW_DATA says the CNC
#: has not: a drive, a folder, a program file (of the path's own folder, for the main program).
_FOLDER_NAMES: Final[Mapping[str, str]] = {
    "cnc_rdpdf_inf": "drive",
    **dict.fromkeys(
        ("cnc_rdpdf_alldir", "cnc_rdpdf_subdir", "cnc_rdpdf_subdirn", "cnc_wrpdf_curdir"),
        "folder",
    ),
    **dict.fromkeys(("cnc_rdpdf_prginf", "cnc_pdf_del"), "program file"),
}


def folder_refusal(ew: int, function: str, name: str) -> str | None:
    """Why the CNC answered ``ew`` to ``function`` (``cnc_pdf_del``...), one of the program
    folder calls of a 30i-class control, of ``name``: EW_DATA is a name of nothing the CNC has
    (``no folder 'NOPE'``, ``no program file '5'``, ``no program file 'O7777' in the path's
    folder`` for ``cnc_pdf_slctmain``), as the machine says it; None for another code or
    call."""
    if ew != EW.DATA:
        return None
    if function == "cnc_pdf_slctmain":
        return f"no program file {name!r} in the path's folder"
    what = _FOLDER_NAMES.get(function)
    return None if what is None else f"no {what} {name!r}"


#: What a part program the store takes is, when the text is not one.
_ONE_PROGRAM: Final = (
    "the text is not one part program: it must hold one program, whose first block is the O "
    "line with the program number (e.g. O1000)"
)
#: The program number of a program's text: its O line (``:`` in ISO code), after a ``%`` line.
O_LINE: Final = re.compile(r"\s*(?:%[^\n]*\n\s*)?[O:](\d+)", re.IGNORECASE)


def _first_block(text: str) -> str | None:
    """The first block of ``text`` (blank lines and ``%`` lines left out) when the text is
    plain: printable ASCII with no comment and no ``;``, which the store splits as it does;
    ``""`` when there is none; None for another text."""
    if any(not (" " <= c <= "~" or c in "\t\r\n") for c in text.rstrip("\x00")):
        return None
    blocks = [line.strip() for line in text.rstrip("\x00").splitlines()]
    first = next((b for b in blocks if b and not b.startswith("%")), "")
    return None if "(" in first or ";" in first else first


def program_refusal(ew: int, text: str) -> str | None:
    """Why the CNC answered ``ew`` to ``cnc_download`` of part program ``text``, in the words
    of the machine's program store where the text says it plainly (``the program text is
    empty``, ``a program starts with O and its number, not 'G01 X1'``), else what a program
    must be; a number already stored (EW_REJECT), a program being executed (EW_BUSY) and a
    full store (EW_OVRFLOW) name the program; None for a code these words do not cover (the
    command line, which reads the file with the store's own rules, names the store's reason
    instead)."""
    if ew == EW.DATA:
        first = _first_block(text)
        if first == "":
            return "the program text is empty"
        if first is not None and first[:1].upper() not in ("O", ":"):
            return f"a program starts with O and its number, not {first[:40]!r}"
        return _ONE_PROGRAM
    m = O_LINE.match(text)
    if ew == EW.NUMBER:
        what = f"program number O{m[1]}" if m else "the program number"
        return f"{what} is outside the program store's range"
    program = f"program O{int(m[1]):04d}" if m else "the program"
    if ew == EW.REJECT:
        return f"{program} is already stored"
    if ew == EW.BUSY:
        return program_busy(int(m[1])) if m else f"{program} is being executed"
    if ew == EW.OVRFLOW:
        return f"the program store has no room for {program}"
    if ew == EW.PROT:
        return READ_ONLY
    return None


def program_busy(number: int) -> str:
    """Why a CNC answered EW_BUSY to a call of program ``number`` (``cnc_delete``,
    ``cnc_download``), in the store's words: ``program O0001 is being executed``."""
    return f"program O{number:04d} is being executed"


#: A program search (``cnc_search``) the CNC refused, as the machine and every front end begin
#: its reason.
SEARCH: Final = "program search refused"


def select_busy(number: int) -> str:
    """Why a CNC answered EW_BUSY to ``cnc_search`` of program ``number``, in the store's
    words: ``cannot select O0002 while a program is being executed``."""
    return f"cannot select O{number:04d} while a program is being executed"


def program_missing(number: int) -> str:
    """Why a CNC answered EW_NUMBER to a call of program ``number`` (``cnc_search``,
    ``cnc_delete``, ``cnc_upload``), in the store's words: ``no program O1234``."""
    return f"no program O{number:04d}"
