"""Follow a CNC's alarms as a stream of events with AlarmProjection.

    python examples/alarm_watch.py --port 8193 --events 6
    python examples/alarm_watch.py --port 8193 --watch-only --events 1 --seconds 60
    python examples/alarm_watch.py --port 8193 --protocol native

The projection polls the active alarm list and the alarm history and yields "raised", "cleared"
and "history" events, each history entry exactly once. Unless ``--watch-only`` is given, the
script also drives the simulated CNC: it raises two alarms and clears them again through
simulator control (a packed-protocol client of its own; with ``--protocol native`` the
projection follows over FOCAS/2 Ethernet, as it would a real control). It stops after
``--events`` events, or with exit code 1 when they do not all arrive within ``--seconds``.
"""

from __future__ import annotations

import argparse
import asyncio
import sys

from _options import number, positive, whole

from focas_net.client import (
    AlarmCleared,
    AlarmEvent,
    AlarmHistoryEvent,
    AlarmProjection,
    AlarmRaised,
    CncClient,
    FocasClient,
    NativeClient,
    ProjectionMode,
)
from focas_net.errors import FocasError
from focas_net.protocol import alarm_text

#: (alm_type, alm_no, message, axis_no) raised by the demonstration.
DEMO_ALARMS = [
    (3, 100, "PARAMETER WRITE ENABLE", 0),
    (4, 500, "+ OVERTRAVEL ( SOFT 1 )", 1),
]


def describe(event: AlarmEvent) -> str:
    if isinstance(event, AlarmHistoryEvent):
        e = event.entry
        when = e.occurred_at.strftime("%Y-%m-%d %H:%M:%S")
        return f"history  {when} UTC {alarm_text(e.alm_type, e.alm_no, e.msg, e.axis_no)}"
    kind = "raised " if isinstance(event, AlarmRaised) else "cleared"
    assert isinstance(event, AlarmRaised | AlarmCleared)
    a = event.alarm
    return f"{kind}  {alarm_text(a.alm_type, a.alm_no, a.msg, a.axis_no)}"


async def drive(host: str, port: int, call_timeout: float, pause: float) -> None:
    """Raise the demonstration alarms, then clear them, a few polls apart (simulator control,
    on a packed-protocol connection)."""
    async with FocasClient(host, port, timeout=call_timeout) as cnc:
        await _drive(cnc, pause)


async def _drive(cnc: FocasClient, pause: float) -> None:
    raised: list[tuple[int, int]] = []
    try:
        for alm_type, alm_no, msg, axis in DEMO_ALARMS:
            raised.append((alm_type, alm_no))
            await cnc.sim.raise_alarm(alm_type, alm_no, msg, axis_no=axis)
            await asyncio.sleep(pause)
        while raised:
            await cnc.sim.clear_alarms(*raised[0])
            raised.pop(0)
            await asyncio.sleep(pause)
    finally:  # stopped early (--events reached, Ctrl-C): leave none of its alarms behind
        for alm_type, alm_no in raised:
            await cnc.sim.clear_alarms(alm_type, alm_no)


def client(args: argparse.Namespace) -> CncClient:
    """The packed client or the FOCAS/2 one: the projection polls either."""
    if args.protocol == "native":
        return NativeClient(args.host, args.port, timeout=args.timeout, reconnect=True)
    return FocasClient(args.host, args.port, timeout=args.timeout, reconnect=True)


async def watch(args: argparse.Namespace) -> int:
    seen = 0
    async with client(args) as cnc:
        projection = AlarmProjection(
            cnc,
            ProjectionMode.ACTIVE_PLUS_HISTORY,
            interval=args.interval,
            depth=20,
            replay_history=False,  # only history entries that appear from now on
        )
        driver = None
        try:
            async with asyncio.timeout(args.seconds), projection:
                # The first poll learns what is already there (active alarms are reported,
                # older history is not); only then does the demonstration start.
                events = await projection.poll()
                if not args.watch_only:
                    driver = asyncio.create_task(
                        drive(args.host, args.port, args.timeout, 2 * args.interval)
                    )
                for event in events:
                    seen += 1
                    print(f"{seen:3d}  {describe(event)}", flush=True)
                async for event in projection:
                    if seen >= args.events:
                        break
                    seen += 1
                    print(f"{seen:3d}  {describe(event)}", flush=True)
                    if seen >= args.events:
                        break
        except TimeoutError:
            print(f"only {seen} of {args.events} events in {args.seconds} s", file=sys.stderr)
            return 1
        finally:
            if driver is not None:
                if not driver.done():
                    driver.cancel()
                await asyncio.gather(driver, return_exceptions=True)
    print(f"{seen} events; polls: {projection.polls}, failed polls: {projection.failed_polls}")
    return 0


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--host", default="127.0.0.1")
    parser.add_argument("--port", type=whole, default=8193)
    parser.add_argument("--timeout", type=number, default=3.0, help="seconds per call")
    parser.add_argument("--interval", type=positive, default=0.2, help="poll interval (0.2 s)")
    parser.add_argument("--events", type=whole, default=6, help="stop after this many (6)")
    parser.add_argument("--seconds", type=positive, default=20.0, help="give up after (20 s)")
    parser.add_argument("--watch-only", action="store_true", help="do not raise alarms, only watch")
    parser.add_argument(
        "--protocol",
        choices=("packed", "native"),
        default="packed",
        help="packed (default) or native: FOCAS/2 Ethernet, as a real control speaks it",
    )
    args = parser.parse_args()
    if args.events < 1:
        parser.error(f"--events must be at least 1, got {args.events}")
    try:
        return asyncio.run(watch(args))
    except KeyboardInterrupt:  # Ctrl-C: exit 130, as the command line, no traceback
        return 130
    except FocasError as exc:
        print(f"alarm_watch: {exc}", file=sys.stderr)
        return 1
    except (ValueError, TypeError) as exc:  # an argument the client refuses, named
        print(f"alarm_watch: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
