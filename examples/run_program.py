"""Run a part program on a CNC end to end: store it, select it, press cycle start, follow it.

    focas-net serve --speed 10 &
    python examples/run_program.py --host 127.0.0.1 --port 8193
    python examples/run_program.py --port 8193 --program my_part.nc --seconds 300

The script stores the program through the client (``cnc_download``, replacing a program of
the same number), makes it the main program (``cnc_search``), switches the panel to MEM when
it is not, and presses cycle start (simulator control). Then it polls, all reads of a poll at
once on one connection: the status, the absolute positions, the actual feed, the sequence
number (system variable #4114) and the run information (parts count, timers). It prints a
line whenever the block or the run state changes, and ends when the program's M30 has counted
a part. Exit code 0 then; 1 when an alarm stops the program, the CNC is already running a
program (or stopped in the middle of one), or the program does not finish within
``--seconds``.
"""

from __future__ import annotations

import argparse
import asyncio
import sys
import time
from decimal import Decimal
from pathlib import Path

from _options import positive, whole

from focas_net import FocasClient
from focas_net.errors import EW, CncError, FocasError
from focas_net.protocol import AutMode, RunInfo, RunState, StatusInfo, field_label
from focas_net.protocol import alarm_text as one_alarm
from focas_net.sim.nc import ProgramError, parse_program

#: A small part: face down 1 mm and cut a 30 mm square at F1800, about 6 s of machine time.
PROGRAM = """\
O7001 (EXAMPLE SQUARE)
N10 G90 G21 G17 G54
N20 S1500 M3
N30 G0 X0. Y0. Z2.
N40 G1 Z-1. F600
N50 X30. F1800
N60 Y30.
N70 X0.
N80 Y0.
N90 G0 Z2.
N100 M5
N110 M30
"""
#: System variable of the sequence number being executed.
SEQUENCE = 4114


class Failed(Exception):
    """The program did not run to its end; the message says why."""


def trace_line(
    machine_s: float, sequence: int, status: StatusInfo, axes: dict[str, Decimal], feed: int
) -> str:
    """``    1.25 s  N50    STRT  X    12.500  Y     0.000  Z    -1.000  F1800``."""
    where = "  ".join(f"{name} {value:>9}" for name, value in axes.items())
    run = field_label(RunState, status.run)[0]
    return f"{machine_s:8.2f} s  N{sequence:<5} {run:4}  {where}  F{feed}"


async def poll(cnc: FocasClient) -> tuple[StatusInfo, dict[str, Decimal], int, int, RunInfo]:
    """One poll: every read goes out at once."""
    status, positions, feed, sequence, info = await asyncio.gather(
        cnc.read_status(),
        cnc.read_positions("absolute"),
        cnc.read_feed(),
        cnc.read_macro(SEQUENCE),
        cnc.read_run_info(),
    )
    return status, positions.values, feed, int(sequence or 0), info


async def alarm_text(cnc: FocasClient) -> str:
    alarms = await cnc.read_alarms()
    return ", ".join(one_alarm(a.alm_type, a.alm_no, a.msg, a.axis_no) for a in alarms)


async def run_program(args: argparse.Namespace, text: str) -> None:
    async with FocasClient(args.host, args.port, timeout=args.timeout) as cnc:
        status = await cnc.read_status()
        if status.run in (RunState.STRT, RunState.HOLD):
            raise Failed("the CNC is running a program: reset it first (focas-net sim cycle reset)")
        if status.alarm or status.emergency:  # cycle start would answer EW_ALARM
            why = f"an alarm is active: {await alarm_text(cnc)}" if status.alarm else ""
            why = why or "the emergency stop is on (focas-net sim panel --emergency off)"
            raise Failed(f"{why} (focas-net sim clear clears alarms)" if status.alarm else why)
        if status.run == RunState.STOP:  # M0, or an operator's stop: the program is in use
            raise Failed(
                "the CNC stopped in the middle of a program (run STOP): reset it first "
                "(focas-net sim cycle reset)"
            )
        try:
            number = await cnc.write_program(text, replace=True)
        except CncError as exc:
            if exc.ew in (EW.DATA, EW.NUMBER):  # the store's reason for the same text, once
                code = CncError.from_ew(exc.ew, exc.detail.partition(": ")[0])
                raise Failed(f"{code}; {refusal(args.program, text)}") from None
            raise
        if status.aut != AutMode.MEM:
            await cnc.sim.set_panel(mode=AutMode.MEM)
            print("panel switched to MEM")
        await cnc.select_program(number)
        before = await cnc.read_run_info()
        await cnc.sim.cycle_start()
        print(f"O{number:04d} stored and selected on {args.host}:{args.port}; cycle start")
        deadline = time.monotonic() + args.seconds
        last: tuple[int, int] | None = None
        while True:
            status, axes, feed, sequence, info = await poll(cnc)
            machine_s = (info.operating_ms - before.operating_ms) / 1000
            if (sequence, status.run) != last:
                print(trace_line(machine_s, sequence, status, axes, feed))
                last = (sequence, status.run)
            if status.alarm:
                raise Failed(f"O{number:04d} stopped by an alarm: {await alarm_text(cnc)}")
            if info.parts_count > before.parts_count and status.run != RunState.STRT:
                break
            if status.run == RunState.STOP:
                raise Failed(f"O{number:04d} stopped at N{sequence} before its end (M0 or M1)")
            if status.run == RunState.RESET:  # a part is counted by M02/M30 only
                raise Failed(
                    f"O{number:04d} ended in reset at N{sequence} with no part counted: it has "
                    "no M02 or M30 at its end, or the CNC was reset"
                )
            if time.monotonic() > deadline:
                raise Failed(f"O{number:04d} did not finish within {args.seconds:g} s")
            await asyncio.sleep(args.interval)
    print(
        f"O{number:04d} finished after {machine_s:.2f} s of machine time: parts "
        f"{before.parts_count} -> {info.parts_count}, cutting "
        f"{(info.cutting_ms - before.cutting_ms) / 1000:.2f} s"
    )


def refusal(path: Path | None, text: str) -> str:
    """Why a CNC refuses ``text`` (of the file ``path``), in the program store's words."""
    name = "the program" if path is None else str(path)
    try:
        parse_program(text)
    except ProgramError as exc:
        return f"{name}: {exc}"
    return f"{name} is not a program the CNC takes"


def read_program(path: Path) -> str:
    """The text of the program file ``path``; ValueError naming the line of a byte that is not
    ASCII (a program is printable ASCII text; the store names any other character)."""
    raw = path.read_bytes()
    try:
        return raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = raw.count(b"\n", 0, exc.start) + 1
        raise ValueError(
            f"{str(path)!r}: line {line}: byte 0x{raw[exc.start]:02X} is not text: a program is "
            "printable ASCII text"
        ) from None


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--host", default="127.0.0.1")
    parser.add_argument("--port", type=whole, default=8193)
    parser.add_argument("--timeout", type=positive, default=3.0, help="seconds per call")
    parser.add_argument("--program", type=Path, help="part program file (default: a square)")
    parser.add_argument(
        "--interval", type=positive, default=0.1, help="seconds between polls (default 0.1)"
    )
    parser.add_argument(
        "--seconds", type=positive, default=120.0, help="give up after this long (default 120)"
    )
    args = parser.parse_args()
    try:
        text = PROGRAM if args.program is None else read_program(args.program)
    except OSError as exc:
        why = (exc.strerror or str(exc)).lower()
        print(f"run_program: cannot read {str(args.program)!r}: {why}", file=sys.stderr)
        return 2
    except ValueError as exc:
        print(f"run_program: {exc}", file=sys.stderr)
        return 2
    try:
        asyncio.run(run_program(args, text))
    except KeyboardInterrupt:  # Ctrl-C: exit 130, as the command line, no traceback
        return 130
    except (Failed, FocasError) as exc:
        print(f"run_program: {exc}", file=sys.stderr)
        return 1
    except (ValueError, TypeError) as exc:  # an argument the client refuses, named
        print(f"run_program: {exc}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
