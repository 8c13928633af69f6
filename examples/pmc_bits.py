"""Concurrent PMC bit writes of one client, which never lose one another.

    python examples/pmc_bits.py --port 8193 --area R --start 100 --bytes 4
    python examples/pmc_bits.py --port 8193 --protocol native

Every bit of ``--bytes`` consecutive bytes is written by its own concurrent call of
``write_pmc_bit`` (a read-modify-write of the byte). The client serialises the calls that touch
the same byte with a per-byte lock, and lets different bytes proceed in parallel, so the final
bytes are exactly the pattern written. The script starts from the inverted pattern, writes, and
checks the result with one range read. With ``--protocol native`` the same calls go over
FOCAS/2 Ethernet (``NativeClient``), whose bit writes take the same per-byte locks. The locks
are the client's: bit writes of two clients to one byte can undo each other's, which is why
the calls share one client.
"""

from __future__ import annotations

import argparse
import asyncio
import sys

from _options import number, whole

from focas_net import CncClient, FocasClient, NativeClient
from focas_net.errors import EW, CncError, FocasError


def pattern(n: int) -> bytes:
    """A different, mixed bit pattern for each byte."""
    return bytes((0b1010_0101 ^ (37 * i)) & 0xFF for i in range(n))


def client(args: argparse.Namespace) -> CncClient:
    """The packed client or the FOCAS/2 one: the calls below are the same on both."""
    if args.protocol == "native":
        return NativeClient(args.host, args.port, timeout=args.timeout)
    return FocasClient(args.host, args.port, timeout=args.timeout)


async def write_bits(args: argparse.Namespace) -> int:
    async with client(args) as cnc:
        # read the bytes first: the client checks --start and --bytes as typed, and the CNC
        # that it has them, before anything is written
        await cnc.read_pmc(args.area, args.start, args.bytes)
        target = pattern(args.bytes)
        await cnc.write_pmc(args.area, args.start, bytes(~b & 0xFF for b in target))
        writes = [
            cnc.write_pmc_bit(args.area, args.start + i, bit, bool(byte >> bit & 1))
            for i, byte in enumerate(target)
            for bit in range(8)
        ]
        await asyncio.gather(*writes)
        result = await cnc.read_pmc(args.area, args.start, args.bytes)
    print(f"{len(writes)} concurrent bit writes to {args.area}{args.start}..")
    print("address   expected  read")
    for i, (want, got) in enumerate(zip(target, result, strict=True)):
        mark = "" if want == got else "  MISMATCH"
        print(f"{args.area}{args.start + i:<8} {want:08b}  {got:08b}{mark}")
    if result != target:
        print("some bits were lost", file=sys.stderr)
        return 1
    print("every bit as written")
    return 0


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--host", default="127.0.0.1")
    parser.add_argument("--port", type=whole, default=8193)
    parser.add_argument("--timeout", type=number, default=5.0, help="seconds per call")
    parser.add_argument("--area", default="R", help="PMC area letter (R)")
    parser.add_argument("--start", type=whole, default=100, help="first byte (100)")
    parser.add_argument("--bytes", type=whole, default=4, help="number of bytes (4)")
    parser.add_argument(
        "--protocol",
        choices=("packed", "native"),
        default="packed",
        help="packed (default) or native: FOCAS/2 Ethernet, as a real control speaks it",
    )
    args = parser.parse_args()
    try:
        return asyncio.run(write_bits(args))
    except KeyboardInterrupt:  # Ctrl-C: exit 130, as the command line, no traceback
        return 130
    except CncError as exc:  # (the client's error names why: what to give instead, here)
        advice = {
            int(EW.NOOPT): "give --area of one it has",
            int(EW.NUMBER): "give --start and --bytes within it",
        }.get(exc.ew)
        print(f"pmc_bits: {exc}" + (f"; {advice}" if advice else ""), file=sys.stderr)
        return 1
    except FocasError as exc:
        print(f"pmc_bits: {exc}", file=sys.stderr)
        return 1
    except (ValueError, TypeError) as exc:  # an argument the client refuses, named
        print(f"pmc_bits: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
