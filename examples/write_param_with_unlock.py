"""Write a CNC parameter the way an operator would, then read it back.

    python examples/write_param_with_unlock.py --port 8193 --param 1320 --axis 1 --value 5000
    python examples/write_param_with_unlock.py --port 8193 --password 1234

A parameter write is refused (EW_PASSWD) unless the CNC is in MDI mode with parameter write
enable (PWE) on and, when it has a parameter password, the connection is unlocked. The script
switches the simulated panel to MDI with PWE on (simulator control), writes, unlocks with
``--password`` if the CNC refuses and writes again, reads the value back, and puts the panel
back to its previous mode with PWE off. ``--axis 0`` addresses a parameter that is not an
axis parameter (1001, 6711, ...); the script asks the CNC which kind the parameter is first.
"""

from __future__ import annotations

import argparse
import asyncio
import sys

from _options import number, whole

from focas_net import FocasClient
from focas_net.errors import EW, AccessDeniedError, CncError, FocasError
from focas_net.protocol import Password

MDI = 0


async def write_param(args: argparse.Namespace) -> int:
    async with FocasClient(args.host, args.port, timeout=args.timeout) as cnc:
        before = await cnc.read_status()
        attributes = await cnc.read_param_attributes(args.param)
        axes = len((await cnc.read_positions()).values)
        if attributes.axis and not 1 <= args.axis <= axes:
            print(
                f"parameter {args.param} is an axis parameter: give --axis 1..{axes}, "
                f"got {args.axis}",
                file=sys.stderr,
            )
            return 2
        if not attributes.axis and args.axis != 0:
            print(
                f"parameter {args.param} is not an axis parameter: give --axis 0", file=sys.stderr
            )
            return 2
        old = await cnc.read_param(args.param, axis=args.axis)
        print(f"parameter {args.param} axis {args.axis}: {old}")
        await cnc.sim.set_panel(MDI, pwe=True, emergency=before.emergency == 1)
        print("panel: MDI, PWE on")
        try:
            try:
                await cnc.write_param(args.param, args.value, axis=args.axis)
            except AccessDeniedError:
                if args.password is None:
                    print("the CNC has a parameter password: give --password", file=sys.stderr)
                    return 1
                try:
                    await cnc.unlock(args.password)
                except AccessDeniedError as exc:
                    why = f"--password {args.password!r} is not the CNC's parameter password"
                    print(f"write_param_with_unlock: {exc}; {why}", file=sys.stderr)
                    return 1
                print("unlocked with the parameter password")
                await cnc.write_param(args.param, args.value, axis=args.axis)
            new = await cnc.read_param(args.param, axis=args.axis)
            print(f"wrote {args.value}, read back {new}")
        finally:
            await cnc.sim.set_panel(before.aut, pwe=False, emergency=before.emergency == 1)
            print("panel: mode restored, PWE off")
    if new != args.value:
        print("read back differs from the value written", file=sys.stderr)
        return 1
    return 0


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--host", default="127.0.0.1")
    parser.add_argument("--port", type=whole, default=8193)
    parser.add_argument("--timeout", type=number, default=3.0, help="seconds per call")
    parser.add_argument("--param", type=whole, default=1320, help="parameter number (1320)")
    parser.add_argument("--axis", type=whole, default=1, help="axis, 0 for non-axis (1)")
    parser.add_argument("--value", type=whole, default=500_000, help="value to write (500000)")
    parser.add_argument("--password", help="parameter password, used when the CNC asks")
    args = parser.parse_args()
    try:
        if args.password is not None:  # checked as the client checks it, before any change
            Password.from_text(args.password)
        return asyncio.run(write_param(args))
    except KeyboardInterrupt:  # Ctrl-C: exit 130, as the command line, no traceback
        return 130
    except CncError as exc:
        why = f"the CNC has no parameter {args.param} (give --param N)"
        print(
            f"write_param_with_unlock: {exc}" + (f"; {why}" if exc.ew == EW.NUMBER else ""),
            file=sys.stderr,
        )
        return 1
    except FocasError as exc:
        print(f"write_param_with_unlock: {exc}", file=sys.stderr)
        return 1
    except (ValueError, TypeError) as exc:  # a value or a number the parameter cannot take
        print(f"write_param_with_unlock: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
