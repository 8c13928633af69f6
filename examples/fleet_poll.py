"""Poll a fleet of CNCs concurrently and print one table.

    python examples/fleet_poll.py                          # 24 simulated machines in-process
    python examples/fleet_poll.py --simulate 100 --rounds 5
    python examples/fleet_poll.py --host 10.0.0.5 --port 8193 --machines 20   # 8193..8212
    python examples/fleet_poll.py --ports 8193,8194,9000
    python examples/fleet_poll.py --protocol native --simulate 100   # over FOCAS/2 Ethernet

Each machine gets its own client (``FocasClient``, or ``NativeClient`` with ``--protocol
native``: FOCAS/2 Ethernet as real controls speak it; the simulated machines answer both on
their one port, and are prepared over the packed protocol's simulator control); a poll reads
the status, the parts count (parameter 6711) and the active alarms of every machine at once,
all machines concurrently. A machine that cannot be reached, or does not answer in time, shows
its error in the table and the others go on. With ``--simulate N`` (the default when no port is
given) the script starts N simulated machines itself on ephemeral ports and gives them
different modes, alarms and part counts. Exit code 0 when every poll succeeded, 1 otherwise.
"""

from __future__ import annotations

import argparse
import asyncio
import contextlib
import sys
import time
from collections.abc import AsyncIterator
from dataclasses import dataclass

from _options import number, ports, whole

from focas_net import CncClient, FocasClient, NativeClient
from focas_net.errors import FocasError
from focas_net.protocol import AutMode, RunState, alarm_code, field_label
from focas_net.server import FocasServer
from focas_net.sim import default_machine

PARTS_COUNT = 6711
MEM = AutMode.MEM


@dataclass
class Row:
    name: str
    address: str
    cnc: str = ""
    mode: str = ""
    run: str = ""
    alarm: str = ""
    parts: str = ""
    ms: str = ""
    error: str = ""


async def poll(cnc: CncClient, row: Row) -> bool:
    """One poll of one machine into ``row``; False when it failed."""
    started = time.perf_counter()
    try:
        status, parts, alarms = await asyncio.gather(
            cnc.read_status(), cnc.read_param(PARTS_COUNT), cnc.read_alarms()
        )
    except FocasError as exc:
        row.error = str(exc)
        return False
    row.ms = f"{(time.perf_counter() - started) * 1000:.1f}"
    row.mode = field_label(AutMode, status.aut)[0]
    row.run = field_label(RunState, status.run)[0]
    row.parts = str(parts)
    if alarms:
        a = alarms[0]
        more = f" +{len(alarms) - 1}" if len(alarms) > 1 else ""
        row.alarm = f"{alarm_code(a.alm_type, a.alm_no)}{more}"
    else:
        row.alarm = "-"
    row.error = ""
    return True


async def connect(cnc: CncClient, row: Row) -> bool:
    try:
        await cnc.connect()
        info = await cnc.read_sysinfo()
    except FocasError as exc:
        row.error = f"unreachable: {exc}"
        return False
    row.cnc = f"{info.series.decode('ascii').strip()}/{info.version.decode('ascii').strip()}"
    return True


#: Longest error text a row shows; a longer one is cut with "...".
ERROR_WIDTH = 60


def error_text(error: str) -> str:
    """``error`` on one line, at most :data:`ERROR_WIDTH` characters."""
    text = " ".join(error.split())
    return text if len(text) <= ERROR_WIDTH else text[: ERROR_WIDTH - 3] + "..."


def render(rows: list[Row]) -> str:
    """The table; a failed machine shows ERROR as its mode and its error in the last column,
    which is not padded, so an error never widens the columns of the other rows."""
    headers = ("machine", "address", "cnc", "mode", "run", "alarm", "parts", "ms")
    table = [headers] + [
        (r.name, r.address, r.cnc, r.mode, r.run, r.alarm, r.parts, r.ms)
        if not r.error
        else (r.name, r.address, r.cnc, "ERROR", "", "", "", error_text(r.error))
        for r in rows
    ]
    widths = [max(len(line[i]) for line in table) for i in range(len(headers) - 1)]
    return "\n".join(
        "  ".join(
            [*(c.ljust(w) for c, w in zip(line[:-1], widths, strict=True)), line[-1]]
        ).rstrip()
        for line in table
    )


def client(protocol: str, host: str, port: int, call_timeout: float) -> CncClient:
    """The packed client or the FOCAS/2 one: a poll makes the same calls on both."""
    if protocol == "native":
        return NativeClient(host, port, timeout=call_timeout)
    return FocasClient(host, port, timeout=call_timeout)


async def poll_fleet(targets: list[tuple[str, str, int]], args: argparse.Namespace) -> int:
    rows = [
        Row(name, f"[{host}]:{port}" if ":" in host else f"{host}:{port}")
        for name, host, port in targets
    ]
    clients = [client(args.protocol, host, port, args.timeout) for _, host, port in targets]
    failures = 0
    started = time.perf_counter()
    try:
        up = await asyncio.gather(*(connect(c, r) for c, r in zip(clients, rows, strict=True)))
        live = [(c, r) for c, r, ok in zip(clients, rows, up, strict=True) if ok]
        failures += (len(rows) - len(live)) * args.rounds  # each poll of one unreachable
        for round_no in range(args.rounds):
            if round_no:
                await asyncio.sleep(args.interval)
            results = await asyncio.gather(*(poll(c, r) for c, r in live))
            failures += results.count(False)
    finally:
        await asyncio.gather(*(c.aclose() for c in clients))
    elapsed = time.perf_counter() - started
    print(render(rows))
    polls = len(rows) * args.rounds
    print(
        f"{len(rows)} machines, {args.rounds} round(s): {polls} polls of 3 calls each, "
        f"{failures} failed, {elapsed:.2f} s"
    )
    return 0 if failures == 0 else 1


async def prepare(cnc: FocasClient, i: int) -> None:
    """Give simulated machine ``i`` its own mode, part count and perhaps an alarm; every third
    machine in MEM runs its program (cycle start runs only in MEM, and an alarm stops it)."""
    await cnc.sim.set_panel(0, pwe=True)  # MDI + PWE: parameters writable
    await cnc.write_param(PARTS_COUNT, 100 * i + 7)
    mode = (MEM, MEM, 0, 3, 5)[i % 5]  # mostly MEM, some MDI / EDIT / JOG
    await cnc.sim.set_panel(mode)
    if i % 6 == 5:
        await cnc.sim.raise_alarm(3, 100 + i, "SIMULATED ALARM")
    elif i % 3 == 0 and mode == MEM:
        await cnc.sim.cycle_start()  # the demo program: about 25 s a part


@contextlib.asynccontextmanager
async def simulated_fleet(n: int, call_timeout: float) -> AsyncIterator[list[tuple[str, str, int]]]:
    machines = [default_machine(f"sim-{i + 1:03d}") for i in range(n)]
    async with FocasServer(machines, host="127.0.0.1", port=0, grace_period=1.0) as server:
        targets = [(lst.label, lst.host, lst.port) for lst in server.listeners]
        async with contextlib.AsyncExitStack() as stack:
            clients = [
                await stack.enter_async_context(FocasClient(h, p, timeout=call_timeout))
                for _, h, p in targets
            ]
            await asyncio.gather(*(prepare(c, i) for i, c in enumerate(clients)))
        yield targets


async def run(args: argparse.Namespace) -> int:
    if args.ports is not None or args.port is not None:
        ports = args.ports or [args.port + i for i in range(args.machines)]
        targets = [(f"cnc-{i + 1:03d}", args.host, p) for i, p in enumerate(ports)]
        return await poll_fleet(targets, args)
    async with simulated_fleet(args.simulate, args.timeout) as targets:
        return await poll_fleet(targets, args)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--host", default="127.0.0.1")
    parser.add_argument("--port", type=whole, help="port of the first machine")
    parser.add_argument("--machines", type=whole, default=20, help="with --port: how many (20)")
    parser.add_argument("--ports", type=ports, help="explicit ports, e.g. 8193,8194")
    parser.add_argument(
        "--simulate", type=whole, default=24, help="simulated machines when no port is given (24)"
    )
    parser.add_argument("--rounds", type=whole, default=3, help="polls of the whole fleet (3)")
    parser.add_argument("--interval", type=number, default=0.5, help="seconds between rounds")
    parser.add_argument("--timeout", type=number, default=3.0, help="seconds per call")
    parser.add_argument(
        "--protocol",
        choices=("packed", "native"),
        default="packed",
        help="packed (default) or native: FOCAS/2 Ethernet, as real controls speak it",
    )
    args = parser.parse_args()
    if args.rounds < 1 or args.machines < 1 or args.simulate < 1:
        parser.error("--rounds, --machines and --simulate must be at least 1")
    if args.interval < 0:
        parser.error(f"--interval must be 0 or more seconds, got {args.interval:g}")
    try:
        return asyncio.run(run(args))
    except KeyboardInterrupt:  # Ctrl-C: exit 130, as the command line, no traceback
        return 130
    except (FocasError, OSError) as exc:
        print(f"fleet_poll: {exc}", file=sys.stderr)
        return 1
    except (ValueError, TypeError) as exc:  # an argument the client refuses, named
        print(f"fleet_poll: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
