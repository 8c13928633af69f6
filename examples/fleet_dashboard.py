"""A terminal dashboard of a fleet of CNCs at work, refreshed once a second.

    python examples/fleet_dashboard.py                       # 8 simulated machines in-process
    python examples/fleet_dashboard.py --simulate 30 --count 0   # until Ctrl-C
    focas-net serve --fleet 20 --run --speed 10 &
    python examples/fleet_dashboard.py --port 8193 --machines 20     # ports 8193..8212
    python examples/fleet_dashboard.py --ports 8193,8194,9000 --interval 2

Each machine has its own FocasClient (reconnecting after a loss). Every ``--interval``
seconds all machines are polled at once, and each poll sends its reads at once on its
connection: the status, the program numbers, the sequence number (system variable #4114),
the actual feed and spindle speed, the run information (parts count) and the active alarms.
The table has one row per machine: address, run state, program, sequence, parts, feed,
spindle, alarm. On a terminal the table is redrawn in place; piped, the tables follow one
another separated by a blank line. A machine that does not answer shows its error and the
others go on. With ``--simulate N`` (the default when no port is given) the script starts N
simulated machines itself, running their demonstration program over and over at ``--speed``,
each at its own feed and rapid overrides. It ends after ``--count`` tables (default 10; 0: until
Ctrl-C) with exit code 0.
"""

from __future__ import annotations

import argparse
import asyncio
import contextlib
import signal
import sys
from collections.abc import AsyncIterator
from dataclasses import dataclass

from _options import ports, positive, whole

from focas_net import FocasClient
from focas_net.client import ClientState
from focas_net.errors import FocasError
from focas_net.protocol import RunState, alarm_code, field_label
from focas_net.server import FocasServer
from focas_net.sim import Machine, default_machine
from focas_net.sim.nc import RealTimeClock

#: System variable of the sequence number being executed.
SEQUENCE = 4114
HEADERS = ("machine", "run", "program", "seq", "parts", "feed", "spindle", "alarm")
#: ANSI: cursor home, clear to the end of the screen.
HOME, CLEAR = "\x1b[H", "\x1b[J"
#: Longest error text a row shows.
ERROR_WIDTH = 50


@dataclass
class Row:
    """What the table shows of one machine."""

    address: str
    cells: tuple[str, ...] = ()
    error: str = "not polled yet"


async def poll(cnc: FocasClient, row: Row) -> None:
    """One poll of one machine into ``row``: its reads all at once."""
    try:
        if cnc.state is ClientState.DISCONNECTED:  # never connected yet: the policy covers losses
            await cnc.connect()
        reads = asyncio.gather(
            cnc.read_status(),
            cnc.read_program_numbers(),
            cnc.read_macro(SEQUENCE),
            cnc.read_feed(),
            cnc.read_spindle_speed(),
            cnc.read_run_info(),
        )
        (status, numbers, sequence, feed, spindle, info), alarms = await asyncio.gather(
            reads, cnc.read_alarms()
        )
    except (FocasError, OSError) as exc:
        text = " ".join(str(exc).split()) or type(exc).__name__
        row.error = text if len(text) <= ERROR_WIDTH else text[: ERROR_WIDTH - 3] + "..."
        return
    alarm = "-"
    if alarms:
        a = alarms[0]
        more = f" +{len(alarms) - 1}" if len(alarms) > 1 else ""
        alarm = f"{alarm_code(a.alm_type, a.alm_no)}{more}"
    program = numbers.running or numbers.main
    row.cells = (
        field_label(RunState, status.run)[0],
        f"O{program:04d}" if program else "-",
        f"N{int(sequence or 0)}",
        str(info.parts_count),
        str(feed),
        str(spindle),
        alarm,
    )
    row.error = ""


def render(rows: list[Row]) -> list[str]:
    """The table: a header and one row per machine; an error fills a row after its address."""
    table = [HEADERS] + [
        (r.address, *r.cells) if not r.error else (r.address, "ERROR", r.error) for r in rows
    ]
    ok = [t for t in table if len(t) == len(HEADERS)]
    widths = [max(len(t[i]) for t in ok) for i in range(len(HEADERS))]
    lines = []
    for t in table:
        if len(t) == len(HEADERS):
            lines.append("  ".join(c.ljust(w) for c, w in zip(t, widths, strict=True)).rstrip())
        else:
            lines.append(f"{t[0].ljust(widths[0])}  {t[1]}: {t[2]}")
    return lines


async def dashboard(targets: list[tuple[str, int]], args: argparse.Namespace) -> None:
    rows = [Row(f"[{h}]:{p}" if ":" in h else f"{h}:{p}") for h, p in targets]
    clients = [FocasClient(h, p, timeout=args.timeout, reconnect=True) for h, p in targets]
    tty = sys.stdout.isatty()
    stop = asyncio.Event()
    loop = asyncio.get_running_loop()
    for signum in (signal.SIGINT, signal.SIGTERM):
        with contextlib.suppress(NotImplementedError, RuntimeError, ValueError):
            loop.add_signal_handler(signum, stop.set)
    try:
        frame = 0
        while args.count == 0 or frame < args.count:
            frame += 1
            await asyncio.gather(*(poll(c, r) for c, r in zip(clients, rows, strict=True)))
            lines = render(rows)
            if tty:
                print(HOME + "\n".join(line + "\x1b[K" for line in lines) + "\n" + CLEAR, end="")
            else:
                print(("" if frame == 1 else "\n") + "\n".join(lines))
            sys.stdout.flush()
            if args.count and frame >= args.count:
                break
            with contextlib.suppress(TimeoutError):
                await asyncio.wait_for(stop.wait(), args.interval)
            if stop.is_set():
                break
    finally:
        await asyncio.gather(*(c.aclose() for c in clients))


@contextlib.asynccontextmanager
async def simulated_fleet(n: int, speed: float) -> AsyncIterator[list[tuple[str, int]]]:
    """N machines running their demonstration program for ever, each at its own feed and
    rapid overrides, on ephemeral ports of 127.0.0.1."""
    clock = RealTimeClock(speed)
    machines: list[Machine] = []
    for i in range(n):
        machine = default_machine(f"sim-{i + 1:03d}", sim_clock=clock)
        machine.set_overrides(feed=60 + (i * 10) % 90, rapid=(25, 50, 100)[i % 3])
        machine.cycle_start(repeat=True)
        machines.append(machine)
    async with FocasServer(machines, host="127.0.0.1", port=0, grace_period=1.0) as server:
        yield [lst.address for lst in server.listeners]


async def run(args: argparse.Namespace) -> None:
    if args.ports:
        targets = [(args.host, p) for p in args.ports]
    elif args.port is not None:
        targets = [(args.host, args.port + i) for i in range(args.machines)]
    else:
        async with simulated_fleet(args.simulate, args.speed) as simulated:
            await dashboard(simulated, args)
        return
    await dashboard(targets, args)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--host", default="127.0.0.1")
    parser.add_argument("--port", type=whole, help="first port (with --machines)")
    parser.add_argument("--machines", type=whole, default=1, help="consecutive ports from --port")
    parser.add_argument("--ports", type=ports, help="comma-separated ports on --host")
    parser.add_argument("--simulate", type=whole, default=8, help="simulated machines (default 8)")
    parser.add_argument("--speed", type=positive, default=10.0, help="simulated machine time")
    parser.add_argument("--interval", type=positive, default=1.0, help="seconds between tables")
    parser.add_argument("--count", type=whole, default=10, help="tables to show (0: until Ctrl-C)")
    parser.add_argument("--timeout", type=positive, default=2.0, help="seconds per call")
    args = parser.parse_args()
    if args.count < 0 or args.machines < 1 or args.simulate < 1:
        parser.error("--count must be 0 or more, --machines and --simulate at least 1")
    try:
        asyncio.run(run(args))
    except KeyboardInterrupt:
        pass
    except (FocasError, OSError, ValueError) as exc:
        print(f"fleet_dashboard: {exc}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
