"""Part programs and the cycle at the command line: ``program list|show|load|delete|select``
and ``sim cycle start|hold|reset`` (``docs/protocol.md`` section 8, "Extensions: part
programs" and "Simulator control: the cycle"). A bare ``program`` reads the program numbers,
feed and spindle speed (:func:`focas_net.cli.read_cmds.program`)."""

from __future__ import annotations

import argparse
import contextlib
from collections.abc import AsyncIterator
from pathlib import Path
from typing import Any, Final

from focas_net._typed import (
    os_reason,
    program_file_text,
    program_number,
    rapid_shown,
    rapid_text,
)
from focas_net.client import FocasClient
from focas_net.errors import EW, CncError, FocasError
from focas_net.protocol import COMMANDS, Command, ProgramText, cycle_action_of

from . import _format as fmt
from . import read_cmds
from ._args import ArgumentRefused, named
from ._run import Go, Output, PackedOnly
from .sim_cmds import SIM_CONTROLS

__all__ = [
    "CYCLE_ACTIONS",
    "PROGRAM_ACTIONS",
    "cycle",
    "cycle_action",
    "override",
    "program",
]

#: ``program ACTION``: what each action does (a bare ``program`` reads the numbers).
PROGRAM_ACTIONS: Final = ("list", "show", "load", "delete", "select")
#: ``sim cycle ACTION``.
CYCLE_ACTIONS: Final = ("start", "hold", "reset")
_WHY: Final = "the program store and the cycle are packed-protocol commands"


#: ``program``'s argument of a number or a file, as ``--help`` names it.
_TARGET: Final = "N|FILE"


def _number(action: str, target: str | None) -> int:
    """The O number of ``program show|delete|select`` (``1000``, ``O1000``): an
    :class:`~._args.ArgumentRefused` naming what was typed."""
    if target is None:
        raise ArgumentRefused(_TARGET, f"program {action} needs the program number, e.g. O1000")
    return named(_TARGET, program_number, target)


def _text_of(target: str | None) -> tuple[str, str]:
    """The program text of ``program load FILE`` and the file's name."""
    if target is None or not target.strip():
        given = "" if target is None else f" ({target!r} names none)"
        raise ArgumentRefused(
            _TARGET, f"program load needs the file of the program, e.g. o1000.nc{given}"
        )
    path = Path(target)
    try:
        raw = path.read_bytes()
    except OSError as exc:
        raise ArgumentRefused(_TARGET, f"cannot read {target!r}: {os_reason(exc)}") from None
    try:
        text = program_file_text(raw)
        _DOWNLOAD.request.encode(ProgramText(0, text))  # (one the request carries)
    except ValueError as exc:
        raise ArgumentRefused(_TARGET, f"{target!r}: {exc}") from None
    return text, target


#: ``cnc_download``, whose request carries the text of ``program load``.
_DOWNLOAD: Final = COMMANDS[Command.WRPROGRAM]


def program(args: argparse.Namespace) -> Go | PackedOnly:
    action: str | None = args.action
    if args.replace and action != "load":
        raise ArgumentRefused("--replace", "goes with program load only")
    if action is None:
        if args.target is not None:
            raise ArgumentRefused(
                "ACTION", f"{args.target!r} needs an action ({', '.join(PROGRAM_ACTIONS)})"
            )
        return read_cmds.program(args)
    if action == "list":
        if args.target is not None:
            raise ArgumentRefused(
                _TARGET,
                f"program list takes no program number or file, got {args.target!r} (program "
                "show N shows one)",
            )
        return _list()
    if action == "load":
        text, name = _text_of(args.target)
        return _load(text, name, args.replace)
    number = _number(action, args.target)
    if action == "show":
        return _show(args, number)
    if action == "delete":
        return _delete(args, number)
    return _select(args, number)


@contextlib.asynccontextmanager
async def _looked_up(
    cnc: FocasClient, args: argparse.Namespace, number: int
) -> AsyncIterator[None]:
    """A call on program ``number`` of the ``--path`` path; when the CNC has no such program
    there (EW_NUMBER) the other paths' stores are looked in, and the path that holds it kept
    for the refusal's words (``args.program_path``, :mod:`._reasons`), as ``sim clear``
    names the path where an alarm is."""
    try:
        yield
    except CncError as exc:
        if exc.ew == EW.NUMBER:
            path = getattr(args, "path", 1)
            with contextlib.suppress(FocasError):
                for other in range(1, (await cnc.read_paths()).count + 1):
                    entries = () if other == path else await cnc.read_program_directory(path=other)
                    if any(e.number == number for e in entries):
                        args.program_path = other
                        break
        raise


def _list() -> PackedOnly:
    async def go(cnc: FocasClient) -> Output:
        entries = await cnc.read_program_directory()
        main = (await cnc.read_program_numbers()).main
        data: dict[str, Any] = {
            "programs": [
                {"number": e.number, "name": e.name, "size": e.size, "main": e.number == main}
                for e in entries
            ]
        }
        rows = [
            (f"O{e.number:04d}", e.name, str(e.size), "main" if e.number == main else "")
            for e in entries
        ]
        if not rows:
            return Output(data, "no programs")
        return Output(data, fmt.render_table(("program", "name", "size", ""), rows))

    return PackedOnly(go, _WHY)


def _show(args: argparse.Namespace, number: int) -> PackedOnly:
    async def go(cnc: FocasClient) -> Output:
        async with _looked_up(cnc, args, number):
            text = await cnc.read_program(number)
        return Output({"number": number, "text": text}, text)

    return PackedOnly(go, _WHY)


def _load(text: str, name: str, replace: bool) -> PackedOnly:
    async def go(cnc: FocasClient) -> Output:
        try:  # the text is checked and encoded before anything is sent
            number = await cnc.write_program(text, replace=replace)
        except ValueError as exc:
            raise ValueError(f"program load: {name!r}: {exc}") from None
        verb = "stored or replaced" if replace else "stored"
        return Output({"number": number, "file": name}, f"{verb} O{number:04d} from {name}")

    return PackedOnly(go, _WHY)


def _delete(args: argparse.Namespace, number: int) -> PackedOnly:
    async def go(cnc: FocasClient) -> Output:
        async with _looked_up(cnc, args, number):
            await cnc.delete_program(number)
        return Output({"deleted": number}, f"deleted O{number:04d}")

    return PackedOnly(go, _WHY)


def _select(args: argparse.Namespace, number: int) -> PackedOnly:
    async def go(cnc: FocasClient) -> Output:
        async with _looked_up(cnc, args, number):
            await cnc.select_program(number)
        return Output({"main": number}, f"O{number:04d} is the main program")

    return PackedOnly(go, _WHY)


def cycle_action(text: str) -> str:
    """``sim cycle ACTION`` as every front end reads it (:func:`cycle_action_of`: ``Start``,
    `` reset ``), by its name in lower case (``start``), as the command's words name it."""
    return cycle_action_of(text).name.lower()


def cycle(args: argparse.Namespace) -> PackedOnly:
    action: str = args.action

    async def go(cnc: FocasClient) -> Output:
        if action == "start":
            await cnc.sim.cycle_start()
        elif action == "hold":
            await cnc.sim.feed_hold()
        else:
            await cnc.sim.reset()
        st = await cnc.read_status()
        mt_type = fmt.mt_type_text(await cnc.read_sysinfo())  # names tmmode
        return Output(
            {"action": action, "status": fmt.status_dict(st, mt_type)},
            f"{action}: {fmt.status_summary(st)}",
        )

    return PackedOnly(go, _WHY)


def override(args: argparse.Namespace) -> PackedOnly:
    async def go(cnc: FocasClient) -> Output:
        if args.feed is not None or args.rapid is not None or args.spindle is not None:
            await cnc.sim.set_overrides(feed=args.feed, rapid=args.rapid, spindle=args.spindle)
        info = await cnc.read_run_info()
        data = {"feed": info.feed, "rapid": rapid_shown(info.rapid), "spindle": info.spindle}
        rapid = rapid_text(info.rapid)
        return Output(data, f"feed {info.feed} %, rapid {rapid}, spindle {info.spindle} %")

    return PackedOnly(go, SIM_CONTROLS)
