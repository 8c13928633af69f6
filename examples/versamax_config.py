"""Read the configuration of a VersaMax I/O station behind a Genius NIU.

    python examples/versamax_config.py --port 8193            # every slot of rack 0
    python examples/versamax_config.py --port 8193 --rack 0 --slot 3

For each slot the record is read with versamax_rdconfig (128 bytes at a time, reassembled
by the client) and decoded: the module label, its board ids and point counts, and the
reference descriptions that say where its data lives in the PLC's %I / %Q / %AI / %AQ tables.
An empty slot answers EW_NUMBER and is listed as empty.
"""

from __future__ import annotations

import argparse
import asyncio
import sys

from _options import number, whole

from focas_net import FocasClient
from focas_net.errors import EW, CncError, FocasError
from focas_net.versamax import IOModuleRecord

REF_NAMES = {16: "%I", 18: "%Q", 10: "%AI", 12: "%AQ"}
MAX_RACK = 7
MAX_SLOT = 9


async def read_slot(cnc: FocasClient, rack: int, slot: int) -> IOModuleRecord | None:
    try:
        return await cnc.read_module_config(rack, slot)
    except CncError as exc:
        if exc.ew == EW.NUMBER:
            return None  # empty slot
        raise


def show(rack: int, slot: int, record: IOModuleRecord | None) -> None:
    if record is None:
        print(f"rack {rack} slot {slot}: empty")
        return
    p, s = record.primary_id, record.secondary_id
    print(
        f"rack {rack} slot {slot}: {record.label}  primary 0x{p.value:04X} "
        f"secondary 0x{s.value:04X}  {record.inputs} inputs, {record.outputs} outputs"
    )
    for ref in record.references:
        name = REF_NAMES.get(ref.ref_type, str(ref.ref_type))
        print(f"    reference {ref.sequence}: {name} offset {ref.offset}, {ref.byte_length} bytes")
    if record.setup & 1:
        print(
            f"    defaults: inputs {record.default_inputs.hex(' ')}, "
            f"outputs {record.default_outputs.hex(' ')}"
        )
    if record.module_data:
        print(f"    module data: {record.module_data.hex(' ')}")


async def read_station(args: argparse.Namespace) -> int:
    slots = range(MAX_SLOT + 1) if args.slot is None else [args.slot]
    async with FocasClient(args.host, args.port, timeout=args.timeout) as cnc:
        records = await asyncio.gather(*(read_slot(cnc, args.rack, s) for s in slots))
    for slot, record in zip(slots, records, strict=True):
        show(args.rack, slot, record)
    found = sum(r is not None for r in records)
    print(f"{found} module(s) configured in rack {args.rack}")
    return 0 if found else 1


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--host", default="127.0.0.1")
    parser.add_argument("--port", type=whole, default=8193)
    parser.add_argument("--timeout", type=number, default=3.0, help="seconds per call")
    parser.add_argument("--rack", type=whole, default=0, help="rack 0..7 (0)")
    parser.add_argument("--slot", type=whole, help="one slot 0..9 (default: every slot)")
    args = parser.parse_args()
    for what, value, most in (("rack", args.rack, MAX_RACK), ("slot", args.slot, MAX_SLOT)):
        if value is not None and not 0 <= value <= most:  # one line and exit 2, as below
            print(f"versamax_config: {what} {value} is outside 0..{most}", file=sys.stderr)
            return 2
    try:
        return asyncio.run(read_station(args))
    except KeyboardInterrupt:  # Ctrl-C: exit 130, as the command line, no traceback
        return 130
    except FocasError as exc:
        print(f"versamax_config: {exc}", file=sys.stderr)
        return 1
    except (ValueError, TypeError) as exc:  # an argument the client refuses, named
        print(f"versamax_config: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
