"""The machine's VersaMax I/O station: a configuration record per occupied rack and slot."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Final

from focas_net.errors import EW
from focas_net.versamax import IOModuleRecord

from ._base import MachineError

__all__ = ["MAX_RACK", "MAX_SLOT", "Station"]

#: Highest rack and slot of a VersaMax station.
MAX_RACK: Final = 7
MAX_SLOT: Final = 9


class Station:
    """The records of a station by ``(rack, slot)``, and their bytes as a CNC reads them."""

    __slots__ = ("encoded", "records")

    def __init__(self, records: Mapping[tuple[int, int], IOModuleRecord]) -> None:
        self.records: dict[tuple[int, int], IOModuleRecord] = {}
        self.encoded: dict[tuple[int, int], bytes] = {}
        for (rack, slot), record in records.items():
            if not (0 <= rack <= MAX_RACK and 0 <= slot <= MAX_SLOT):
                raise ValueError(f"VersaMax rack {rack} slot {slot} is out of range")
            self.records[rack, slot] = record
            self.encoded[rack, slot] = record.encode()

    def config_record(self, rack: int, slot: int) -> bytes:
        """The bytes of a record: EW_NUMBER for an empty slot (or one out of range)."""
        record = self.encoded.get((rack, slot))
        if record is None:
            raise MachineError(EW.NUMBER, f"rack {rack} slot {slot} is empty")
        return record

    def read(self, rack: int, slot: int, offset: int, length: int) -> bytes:
        """Up to ``length`` bytes of a record from ``offset``: EW_NUMBER (empty slot), EW_NUMBER
        (offset outside the record)."""
        record = self.config_record(rack, slot)
        if length < 0:
            raise ValueError(f"a configuration read of {length} bytes")
        if not 0 <= offset < len(record):
            raise MachineError(EW.NUMBER, f"offset {offset} past the {len(record)}-byte record")
        return record[offset : offset + length]
