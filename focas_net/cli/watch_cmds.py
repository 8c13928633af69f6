"""``focas-net watch``: one machine's state, live, refreshed in place.

Every frame is one pipelined batch: the reads of :func:`poll` go out together on the one
connection (``asyncio.gather``), so a frame costs one round trip. What the frame shows is a
pure function of what was read (:func:`render_frame`, :func:`frame_dict`), tested without a
server. On a terminal each frame is drawn over the last (cursor home, the lines, clear to the
end of the screen) with the cursor hidden until the command ends; otherwise each frame is
printed as plain lines, frames separated by a blank line, so that the output can be piped.
``--json`` prints one JSON object per frame, one per line.

A lost connection does not end the command: the frame says so (with the last state read) and
the client's :class:`~focas_net.client.ReconnectPolicy` connects again. A first poll that
fails ends it as a one-shot command ends (the same diagnosis, exit 3 or 4): a peer that never
answered is no machine to wait for. Ctrl-C or SIGTERM end
it with exit 0, as does ``--count N`` after N frames.
"""

from __future__ import annotations

import argparse
import asyncio
import contextlib
import json
import sys
from collections.abc import Awaitable, Mapping, Sequence
from dataclasses import dataclass
from decimal import Decimal
from typing import Any, Final, TypeVar

from focas_net._typed import rapid_shown, rapid_text
from focas_net.client import FocasClient, Positions, ReconnectPolicy
from focas_net.errors import CncError, FocasConnectionError, FocasTimeoutError
from focas_net.protocol import (
    ActiveAlarm,
    AlarmState,
    AutMode,
    EmergencyState,
    LoadMeters,
    MotionState,
    MstbState,
    PositionKind,
    ProgramNumbers,
    RunInfo,
    RunState,
    StatusInfo,
)

from . import _format as fmt
from ._run import PackedOnly, stopping_on_signals, write

__all__ = [
    "CLEAR_TO_END",
    "CURSOR_HOME",
    "DEFAULT_INTERVAL",
    "HIDE_CURSOR",
    "PARTS_REQUIRED",
    "POSITION_KINDS",
    "SEQUENCE_VARIABLE",
    "SHOW_CURSOR",
    "WATCH_RECONNECT",
    "Frame",
    "WatchState",
    "duration_text",
    "frame_dict",
    "path_count",
    "poll",
    "poll_paths",
    "render_frame",
    "screen_text",
    "watch",
]

T = TypeVar("T")

#: ``--interval`` when none is given, in seconds.
DEFAULT_INTERVAL: Final = 0.5
#: Parameter of the parts required (FANUC 6713).
PARTS_REQUIRED: Final = 6713
#: System variable of the sequence number being executed (FANUC #4114).
SEQUENCE_VARIABLE: Final = 4114
#: The position kinds a frame shows, in column order, with their headings.
POSITION_KINDS: Final[tuple[tuple[PositionKind, str], ...]] = (
    (PositionKind.ABSOLUTE, "absolute"),
    (PositionKind.MACHINE, "machine"),
    (PositionKind.RELATIVE, "relative"),
    (PositionKind.DISTANCE, "distance"),
)
#: How ``watch`` reconnects: for ever, at most 2 s between attempts.
WATCH_RECONNECT: Final = ReconnectPolicy(initial_delay=0.1, max_delay=2.0, max_attempts=None)

#: ANSI control sequences of a refresh in place.
CURSOR_HOME: Final = "\x1b[H"
CLEAR_TO_END: Final = "\x1b[J"
_CLEAR_LINE: Final = "\x1b[K"
HIDE_CURSOR: Final = "\x1b[?25l"
SHOW_CURSOR: Final = "\x1b[?25h"


# -- what a frame holds ---------------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class WatchState:
    """What one poll read; None where the CNC refused that read (an EW code)."""

    status: StatusInfo | None = None
    numbers: ProgramNumbers | None = None
    program_name: str | None = None
    sequence: int | None = None
    positions: tuple[Positions | None, ...] = (None,) * len(POSITION_KINDS)
    feed: int | None = None
    spindle: int | None = None
    run_info: RunInfo | None = None
    parts_required: int | None = None
    alarms: tuple[ActiveAlarm, ...] | None = None
    loads: LoadMeters | None = None
    mt_type: str | None = None
    """ODBSYS ``mt_type``, which names ``tmmode`` (read once)."""


@dataclass(frozen=True, slots=True)
class Frame:
    """One refresh: its number (from 1), the machine's address, the state last read (None
    before the first successful poll) and, when the poll failed, why."""

    number: int
    address: str
    state: WatchState | None
    problem: str | None = None
    paths: tuple[WatchState, ...] = ()
    """On a machine of several paths, the state of each, path 1 first (``state`` is then
    path 1's); empty on a machine of one path."""


# -- rendering (pure) -----------------------------------------------------------------------


def duration_text(ms: int | None) -> str:
    """``1:02:03.4`` (hours, minutes, seconds to a tenth) of a time in milliseconds."""
    if ms is None:
        return "-"
    tenths = max(ms, 0) // 100
    hours, rest = divmod(tenths, 36_000)
    minutes, rest = divmod(rest, 600)
    seconds, tenth = divmod(rest, 10)
    return f"{hours}:{minutes:02d}:{seconds:02d}.{tenth}"


def _label(values: fmt.FieldValues, value: int) -> str:
    return fmt.field_name(values, value)[0]


def _o(number: int | None) -> str:
    if number is None:
        return "-"
    return f"O{number:04d}" if number else "none"


def _text(value: object) -> str:
    return "-" if value is None else str(value)


def _status_line(st: StatusInfo | None) -> str:
    if st is None:
        return "run -"
    return (
        f"run {_label(RunState, st.run)}  mode {_label(AutMode, st.aut)}  "
        f"motion {_label(MotionState, st.motion)}  mstb {_label(MstbState, st.mstb)}  "
        f"emergency {_label(EmergencyState, st.emergency)}  alarm {_label(AlarmState, st.alarm)}"
    )


def _program_line(s: WatchState) -> str:
    running = None if s.numbers is None else s.numbers.running
    main = None if s.numbers is None else s.numbers.main
    name = f" ({s.program_name})" if s.program_name else ""
    sequence = "-" if s.sequence is None else f"N{s.sequence}"
    return f"program {_o(running)}{name}  main {_o(main)}  sequence {sequence}"


def _axis_names(positions: Sequence[Positions | None]) -> list[str]:
    names: list[str] = []
    for p in positions:
        if p is not None:
            names += [n for n in p.values if n not in names]
    return names


def _position_lines(positions: Sequence[Positions | None]) -> list[str]:
    names = _axis_names(positions)
    if not names:
        return ["positions -"]
    header = ["axis", *(title for _, title in POSITION_KINDS)]
    rows = [header]
    for name in names:
        row = [name]
        for p in positions:
            value = None if p is None else p.values.get(name)
            row.append(_text(value))
        rows.append(row)
    widths = [max(len(r[i]) for r in rows) for i in range(len(header))]
    lines = []
    for r in rows:
        cells = [c.rjust(w) for c, w in zip(r[1:], widths[1:], strict=True)]
        lines.append("  ".join([r[0].ljust(widths[0]), *cells]))
    return lines


def _loads_text(loads: LoadMeters, axes: Sequence[str]) -> str:
    """``spindle 42 %  servo X 7 %  Z 0 %``: servo loads named by the axes the positions gave
    (by number past them); a percentage written as every front end writes it."""
    spindles = "  ".join(f"{v} %" for v in loads.spindle) or "-"
    servos = "  ".join(
        f"{axes[i] if i < len(axes) else i + 1} {v} %" for i, v in enumerate(loads.servo)
    )
    return f"spindle {spindles}  servo {servos or '-'}"


def _state_lines(s: WatchState) -> list[str]:
    info = s.run_info
    lines = [_status_line(s.status), _program_line(s), *_position_lines(s.positions)]
    lines.append(f"feed {_text(s.feed)} mm/min  spindle {_text(s.spindle)} min^-1")
    if info is None:
        lines += ["override -", f"parts -  required {_text(s.parts_required)}", "time -"]
    else:
        lines += [
            f"override feed {info.feed} %  rapid {rapid_text(info.rapid)}  "
            f"spindle {info.spindle} %",
            f"parts {info.parts_count}  total {info.parts_total}  "
            f"required {_text(s.parts_required)}",
            f"time cycle {duration_text(info.cycle_ms)}  cutting {duration_text(info.cutting_ms)}"
            f"  operating {duration_text(info.operating_ms)}"
            f"  power on {duration_text(info.power_on_ms)}",
        ]
    if s.loads is not None:
        lines.append(f"load {_loads_text(s.loads, _axis_names(s.positions))}")
    if s.alarms is None:
        lines.append("alarms -")
    elif not s.alarms:
        lines.append("alarms none")
    else:
        lines.append(f"alarms {len(s.alarms)}")
        lines += [f"  {fmt.format_active_alarm(a)}" for a in s.alarms]
    return lines


def render_frame(frame: Frame) -> list[str]:
    """The lines of one frame: a heading, the problem of a failed poll, then the state (on a
    machine of several paths, a section per path headed ``path N``, its lines indented)."""
    heading = f"{frame.address}  frame {frame.number}"
    if frame.paths:
        heading += f"  {len(frame.paths)} paths"
    lines = [heading]
    if frame.problem is not None:
        lines.append(f"! {frame.problem}")
    if frame.state is None:
        lines.append("no state read yet")
    elif not frame.paths:
        lines += _state_lines(frame.state)
    else:
        for number, state in enumerate(frame.paths, 1):
            lines.append(f"path {number}")
            lines += [f"  {line}" for line in _state_lines(state)]
    return lines


def screen_text(lines: Sequence[str], *, tty: bool, first: bool) -> str:
    """What to write for a frame of ``lines``: on a terminal, drawn over the last frame
    (cursor home, each line cleared to its end, then the rest of the screen cleared); else
    plain lines, after a blank line unless it is the ``first`` frame."""
    if tty:
        return CURSOR_HOME + "".join(f"{line}{_CLEAR_LINE}\n" for line in lines) + CLEAR_TO_END
    body = "".join(f"{line}\n" for line in lines)
    return body if first else "\n" + body


def _positions_dict(p: Positions | None) -> dict[str, str] | None:
    return None if p is None else {name: str(v) for name, v in p.values.items()}


def _json_value(value: object) -> Any:
    if value is None or isinstance(value, bool | int | float | str):
        return value
    if isinstance(value, Decimal):
        return str(value)
    if isinstance(value, Mapping):
        return {str(k): _json_value(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_json_value(v) for v in value]
    return str(value)


def frame_dict(frame: Frame) -> dict[str, Any]:
    """``--json``: one frame as JSON-ready values (positions as decimal strings). On a machine
    of several paths ``state`` is path 1's and ``paths`` lists every path's, as
    ``{"path": N, "state": ...}``; a machine of one path has no ``paths``."""
    data: dict[str, Any] = {
        "frame": frame.number,
        "address": frame.address,
        "problem": frame.problem,
    }
    s = frame.state
    if s is None:
        data["state"] = None
        return data
    data["state"] = _state_dict(s)
    if frame.paths:
        data["paths"] = [
            {"path": number, "state": _state_dict(state)}
            for number, state in enumerate(frame.paths, 1)
        ]
    return data


def _state_dict(s: WatchState) -> dict[str, Any]:
    """One path's state as JSON-ready values."""
    info = s.run_info
    state: dict[str, Any] = {
        "status": None if s.status is None else fmt.status_dict(s.status, s.mt_type),
        "program_running": None if s.numbers is None else s.numbers.running,
        "program_main": None if s.numbers is None else s.numbers.main,
        "program_name": s.program_name,
        "sequence": s.sequence,
        "positions": {
            title: _positions_dict(p)
            for (_, title), p in zip(POSITION_KINDS, s.positions, strict=True)
        },
        "feed": s.feed,
        "spindle_speed": s.spindle,
        "overrides": None
        if info is None
        else {"feed": info.feed, "rapid": rapid_shown(info.rapid), "spindle": info.spindle},
        "parts": {
            "count": None if info is None else info.parts_count,
            "total": None if info is None else info.parts_total,
            "required": s.parts_required,
        },
        "times_ms": None
        if info is None
        else {
            "cycle": info.cycle_ms,
            "cutting": info.cutting_ms,
            "operating": info.operating_ms,
            "power_on": info.power_on_ms,
        },
        "alarms": None if s.alarms is None else [fmt.alarm_dict(a) for a in s.alarms],
        "loads": None
        if s.loads is None
        else {"spindle": list(s.loads.spindle), "servo": list(s.loads.servo)},
    }
    return state


# -- polling --------------------------------------------------------------------------------

#: A failure that is the connection's, shown in the frame while the client reconnects.
_CONNECTION_ERRORS: Final = (FocasConnectionError, FocasTimeoutError, OSError)


async def _or_none(read: Awaitable[T]) -> T | None:
    """What ``read`` answered, None when it was an EW code (the field shows ``-``)."""
    try:
        return await read
    except CncError:
        return None


async def poll(
    cnc: FocasClient,
    names: dict[int, str],
    *,
    directory: bool,
    mt_type: str | None = None,
    path: int | None = None,
) -> WatchState:
    """One frame's reads of ``path`` (None: the client's), all sent at once. ``names``
    caches the path's program names by number; the program directory is read in the same
    batch when ``directory`` (the first frame, or a program whose name is not cached). The
    identity is read too until its ``mt_type`` is known (given as ``mt_type``). An EW answer
    leaves its field None; a connection failure is raised (and the other reads are
    cancelled)."""
    task = asyncio.ensure_future
    status = task(_or_none(cnc.read_status(path=path)))
    numbers = task(_or_none(cnc.read_program_numbers(path=path)))
    sequence = task(_or_none(cnc.read_macro(SEQUENCE_VARIABLE, path=path)))
    positions = [task(_or_none(cnc.read_positions(kind, path=path))) for kind, _ in POSITION_KINDS]
    feed = task(_or_none(cnc.read_feed(path=path)))
    spindle = task(_or_none(cnc.read_spindle_speed(path=path)))
    run_info = task(_or_none(cnc.read_run_info(path=path)))
    required = task(_or_none(cnc.read_param(PARTS_REQUIRED, path=path)))
    alarms = task(_or_none(cnc.read_alarms(path=path)))
    entries = task(_or_none(cnc.read_program_directory(path=path))) if directory else None
    loads = task(_or_none(cnc.read_loads(path=path)))
    sysinfo = task(_or_none(cnc.read_sysinfo())) if mt_type is None else None
    reads: list[asyncio.Future[Any]] = [
        status, numbers, sequence, *positions, feed, spindle, run_info, required, alarms,
        loads, *([] if entries is None else [entries]), *([] if sysinfo is None else [sysinfo]),
    ]  # fmt: skip
    try:
        await asyncio.gather(*reads)
    except BaseException:
        for r in reads:
            r.cancel()
        raise
    listed = None if entries is None else entries.result()
    if listed is not None:
        names.clear()
        names.update((e.number, e.name) for e in listed)
    nums = numbers.result()
    seq = sequence.result()
    active = alarms.result()
    info = None if sysinfo is None else sysinfo.result()
    if info is not None:
        mt_type = fmt.mt_type_text(info)
    return WatchState(
        status=status.result(),
        numbers=nums,
        program_name=None if nums is None else names.get(nums.running or nums.main),
        sequence=None if seq is None else int(seq),
        positions=tuple(p.result() for p in positions),
        feed=feed.result(),
        spindle=spindle.result(),
        run_info=run_info.result(),
        parts_required=required.result(),
        alarms=None if active is None else tuple(active),
        loads=loads.result(),
        mt_type=mt_type,
    )


async def path_count(cnc: FocasClient) -> int:
    """The number of paths of the CNC (``cnc_getpath``); 1 when it cannot tell (it answers
    the command with an EW code: a server without paths)."""
    try:
        return (await cnc.read_paths()).count or 1
    except CncError:
        return 1


async def poll_paths(
    cnc: FocasClient,
    names: dict[int, dict[int, str]],
    paths: int,
    *,
    directory: Sequence[bool],
    mt_type: str | None = None,
) -> tuple[WatchState, ...]:
    """:func:`poll` of every path 1..``paths`` in one batch: every read of every path is sent
    before the first answer is awaited (the client selects each path, in order, on the one
    connection). ``names`` holds each path's program names, ``directory`` whether to read
    each path's directory. A connection failure is raised (and the other reads cancelled)."""
    polls = [
        asyncio.ensure_future(
            poll(
                cnc,
                names.setdefault(path, {}),
                directory=directory[path - 1],
                mt_type=mt_type,
                path=path,
            )
        )
        for path in range(1, paths + 1)
    ]
    try:
        return tuple(await asyncio.gather(*polls))
    except BaseException:
        for p in polls:
            p.cancel()
        raise


# -- the command ----------------------------------------------------------------------------


def _is_tty() -> bool:
    try:
        return sys.stdout.isatty()
    except (AttributeError, ValueError):
        return False


async def _unless_stopped(aw: Awaitable[T], stop: asyncio.Event) -> tuple[bool, T | None]:
    """``(True, result)`` of ``aw``, or ``(False, None)`` when ``stop`` is set first (``aw``
    is then cancelled)."""
    task = asyncio.ensure_future(aw)
    stopper = asyncio.ensure_future(stop.wait())
    try:
        await asyncio.wait({task, stopper}, return_when=asyncio.FIRST_COMPLETED)
    finally:
        stopper.cancel()
        if not task.done():
            task.cancel()
            with contextlib.suppress(asyncio.CancelledError):
                await task
    if task.cancelled() or not task.done():
        return False, None
    return True, task.result()


def _problem(exc: BaseException, address: str) -> str:
    return f"connection to {address} lost: {fmt.error_line(exc)}; reconnecting"


async def _poll_or_problem(
    cnc: FocasClient,
    names: dict[int, dict[int, str]],
    last: tuple[WatchState, ...],
    *,
    address: str,
) -> tuple[WatchState, ...] | str:
    """The state of each path after the ``last`` poll (none before the first), or the line
    saying why the connection failed; before any state was read (``last`` empty) the failure
    is raised."""
    mt_type = last[0].mt_type if last else None
    try:
        paths = len(last) if last else await path_count(cnc)
        directory = [
            not last or _needs_directory(last[i], names.get(i + 1, {})) for i in range(paths)
        ]
        return await poll_paths(cnc, names, paths, directory=directory, mt_type=mt_type)
    except _CONNECTION_ERRORS as exc:
        if not last:
            # nothing read yet: the peer may never answer (TLS on one side only, a peer that
            # is no FOCAS server); the command fails as a one-shot command does, diagnosed
            raise
        return _problem(exc, address)


def watch(args: argparse.Namespace) -> PackedOnly:
    """``focas-net watch``: frames every ``--interval`` seconds until Ctrl-C or ``--count``."""
    interval: float = args.interval
    count: int | None = args.count
    # The client of this command reconnects for ever (read by the runner's session).
    args.reconnect_policy = WATCH_RECONNECT

    async def go(cnc: FocasClient) -> None:
        address = fmt.address_text(cnc.host, cnc.port)
        tty = _is_tty() and not args.json
        stop = asyncio.Event()
        loop = asyncio.get_running_loop()
        names: dict[int, dict[int, str]] = {}
        states: tuple[WatchState, ...] = ()
        number = 0
        with stopping_on_signals(stop.set):
            if tty:
                write(HIDE_CURSOR)
            try:
                next_at = loop.time()
                while count is None or number < count:
                    reading = _poll_or_problem(cnc, names, states, address=address)
                    done, polled = await _unless_stopped(reading, stop)
                    if not done or polled is None:
                        break
                    number += 1
                    problem = polled if isinstance(polled, str) else None
                    if not isinstance(polled, str):
                        states = polled
                    state = states[0] if states else None
                    frame = Frame(
                        number, address, state, problem, states if len(states) > 1 else ()
                    )
                    if not _show(frame, tty=tty, json_lines=args.json, first=number == 1):
                        break
                    if count is not None and number >= count:
                        break
                    next_at = max(next_at + interval, loop.time())
                    waited, _ = await _unless_stopped(asyncio.sleep(next_at - loop.time()), stop)
                    if not waited:
                        break
            finally:
                if tty:
                    write(SHOW_CURSOR)

    return PackedOnly(
        go, "it reads the run info, the program directory and the load meters (packed only)"
    )


def _needs_directory(state: WatchState | None, names: Mapping[int, str]) -> bool:
    if state is None or state.numbers is None:
        return False
    number = state.numbers.running or state.numbers.main
    return number != 0 and number not in names


def _show(frame: Frame, *, tty: bool, json_lines: bool, first: bool) -> bool:
    if json_lines:
        return write(json.dumps(frame_dict(frame)) + "\n")
    return write(screen_text(render_frame(frame), tty=tty, first=first))
