"""Read the status, identity and active alarms of a CNC.

    python examples/read_status.py --host 127.0.0.1 --port 8193
    python examples/read_status.py --host 192.168.1.10 --protocol native

The three reads go out at once on one connection (``asyncio.gather``): on the packed protocol
the client matches the answers by request id; on FOCAS/2 (``--protocol native``, what a real
control speaks on port 8193) the native client sends them as one frame of three blocks.
"""

from __future__ import annotations

import argparse
import asyncio
import sys

from _options import number, whole

from focas_net import CncClient, FocasClient, NativeClient
from focas_net.errors import FocasError
from focas_net.protocol import (
    AlarmState,
    AutMode,
    EmergencyState,
    RunState,
    alarm_text,
    field_label,
)


def client(protocol: str, host: str, port: int, call_timeout: float) -> CncClient:
    """The packed client or the FOCAS/2 one: the reads below are the same calls on both."""
    if protocol == "native":
        return NativeClient(host, port, timeout=call_timeout)
    return FocasClient(host, port, timeout=call_timeout)


async def read_status(host: str, port: int, call_timeout: float, protocol: str) -> None:
    async with client(protocol, host, port, call_timeout) as cnc:
        status, info, alarms = await asyncio.gather(
            cnc.read_status(), cnc.read_sysinfo(), cnc.read_alarms()
        )
    series = info.series.decode("ascii").strip()
    version = info.version.decode("ascii").strip()
    print(f"CNC {host}:{port}: series {series} version {version}, {info.axes_count} axes")
    # the labels a FANUC screen shows, from the table the command line and the dashboard use
    fields = (
        ("mode", AutMode, status.aut),
        ("run", RunState, status.run),
        ("emergency", EmergencyState, status.emergency),
        ("alarm", AlarmState, status.alarm),
    )
    print(" ".join(f"{name}={field_label(values, value)[0]}" for name, values, value in fields))
    print(f"active alarms: {len(alarms)}")
    for a in alarms:
        print(f"  {alarm_text(a.alm_type, a.alm_no, a.msg, a.axis_no)}")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--host", default="127.0.0.1")
    parser.add_argument("--port", type=whole, default=8193)
    parser.add_argument("--timeout", type=number, default=3.0, help="seconds per call")
    parser.add_argument(
        "--protocol",
        choices=("packed", "native"),
        default="packed",
        help="packed (default) or native: FOCAS/2 Ethernet, as a real control speaks it",
    )
    args = parser.parse_args()
    try:
        asyncio.run(read_status(args.host, args.port, args.timeout, args.protocol))
    except KeyboardInterrupt:  # Ctrl-C: exit 130, as the command line, no traceback
        return 130
    except FocasError as exc:
        print(f"read_status: {exc}", file=sys.stderr)
        return 1
    except (ValueError, TypeError) as exc:  # an argument the client refuses, named
        print(f"read_status: {exc}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
