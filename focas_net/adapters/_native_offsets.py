"""The native adapter's handlers of tool offsets, work zero offsets and tool life management
(``docs/native-protocol.md``; what a handler is: :mod:`focas_net.adapters.native`).

Each block answers for the path in its path word, from the machine's per-path tables
(:meth:`~focas_net.sim.Machine.tool_offsets`, ``work_offsets``, ``tool_group``...): the
machine checks the numbers, types, axes and values, this module the wire's own rules:

* an offset value is one 8-byte record ``(value, 10, 3)`` (least input increments);
* a tool offset read of every type (-1) answers every type of each number in type order (a
  machining centre's 4, a lathe's 7): FANUC's library copies the records' values as they come,
  whatever the machine type and the offset memory [V];
* a work offset read of every axis (-1) answers the open answer's max axes records per number
  (the path's axes, then zeros), which FANUC's library needs;
* a write carries one value per number and type (0x09) or per number and axis (0x0C, max axes
  values for -1, of which the path's axes are taken); another count is EW_LENGTH.
"""

from __future__ import annotations

from typing import Final

from focas_net.errors import EW
from focas_net.native import (
    SCALED_SIZE,
    RequestBlock,
    ScaledNumber,
    ScaledValues,
    ToolEntry,
    ToolGroupRecord,
    ToolGroupRecords,
    ToolGroupRequest,
    ToolGroupsInUse,
    ToolGroupsInUseRequest,
    ToolLifeCounts,
    ToolNumberRequest,
    ToolNumbers,
    ToolOffsetInfoRequest,
    ToolOffsetMemory,
    ToolOffsetRequest,
    ToolOffsetWriteRequest,
    WorkOffsetRequest,
    WorkOffsetWriteRequest,
    offset_type_of,
)
from focas_net.sim import POSITION_DECIMALS, Machine, Session

from ._common import Refused, need_room
from ._native_cnc import block_path

__all__ = ["OffsetHandlers"]

#: ODBTLINF ``ofs_type`` of each machine type: tool offset memory C on a machining centre,
#: geometry and wear on a lathe.
_MEMORY_TYPES: Final = {"M": 2, "T": 1}
_EVERY: Final = -1


def _values(values: list[int]) -> bytes:
    return ScaledValues(tuple(ScaledNumber(v, POSITION_DECIMALS) for v in values)).encode()


class OffsetHandlers:
    """The handlers of offsets and tool life of one machine (see the module docstring)."""

    __slots__ = ("machine", "max_axis")

    def __init__(self, machine: Machine, max_axis: int) -> None:
        self.machine = machine
        #: Records per number of an all-axes work offset read: the open answer's max axes.
        self.max_axis = max_axis

    # -- tool offsets --------------------------------------------------------------------
    def read_tool_offsets(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0x08: the values of tool offsets ``first..last`` of one type or of every type
        (number by number, types in order)."""
        request = ToolOffsetRequest.from_block(block)
        path = block_path(block)
        offset_type = offset_type_of(request.type)
        info = self.machine.tool_offset_info(path=path)
        types = len(info.types) if offset_type is None else 1
        count = request.last - request.first + 1
        if count > 0:
            need_room(SCALED_SIZE * types * count, room)
        rows = self.machine.tool_offsets(request.first, request.last, offset_type, path=path)
        return _values([v for row in rows for v in row])

    def write_tool_offset(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0x09: one value per number ``first..last`` of one type."""
        request = ToolOffsetWriteRequest.from_block(block)
        path = block_path(block)
        offset_type = offset_type_of(request.type)
        if offset_type is None:
            raise Refused(EW.ATTRIB)
        numbers = range(request.first, request.last + 1)
        values = request.values.values
        self.machine.check_writable()
        if len(values) != len(numbers):
            raise Refused(EW.LENGTH)
        self.machine.write_tool_offsets(request.first, offset_type, values, path=path)
        return b""

    def read_tool_offset_info(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0x0A: the offset memory's type and how many numbers it has."""
        ToolOffsetInfoRequest.from_block(block)
        info = self.machine.tool_offset_info(path=block_path(block))
        return ToolOffsetMemory(info.count, _MEMORY_TYPES[info.kind]).encode()

    # -- work zero offsets -----------------------------------------------------------------
    def read_work_offsets(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0x0B: work zero offsets ``first..last`` of one axis, or of every axis padded to
        the max axes."""
        request = WorkOffsetRequest.from_block(block)
        path = block_path(block)
        every = request.axis == _EVERY
        count = request.last - request.first + 1
        if count > 0:
            need_room(SCALED_SIZE * count * (self.max_axis if every else 1), room)
        rows = self.machine.work_offsets(
            request.first, request.last, None if every else request.axis, path=path
        )
        out: list[int] = []
        for row in rows:
            out.extend(row)
            if every:
                out.extend([0] * (self.max_axis - len(row)))
        return _values(out)

    def write_work_offset(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0x0C: the values of work zero offsets ``first..last``, one axis or every axis."""
        request = WorkOffsetWriteRequest.from_block(block)
        path = block_path(block)
        every = request.axis == _EVERY
        values = request.values.values
        numbers = range(request.first, request.last + 1)
        self.machine.check_writable()
        axes = len(self.machine.path_info(path).axes)
        per = max(self.max_axis, axes) if every else 1
        if not numbers or len(values) != per * len(numbers):
            raise Refused(EW.LENGTH)
        rows = [values[i * per : i * per + (axes if every else 1)] for i in range(len(numbers))]
        axis = None if every else request.axis
        self.machine.write_work_offsets(request.first, axis, rows, path=path)
        return b""

    # -- tool life -----------------------------------------------------------------------
    def read_groups_in_use(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0x48: the group of the tool in use (next, in use and selected alike)."""
        ToolGroupsInUseRequest.from_block(block)
        selected = self.machine.tool_life_info(path=block_path(block)).selected
        return ToolGroupsInUse(selected, selected, selected).encode()

    def read_life_counts(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0x4A and 0x1C4: groups declared, the most groups and tools, the largest lives."""
        info = self.machine.tool_life_info(path=block_path(block))
        return ToolLifeCounts(
            info.groups, info.max_groups, info.max_tools, info.max_minutes, info.max_cycles
        ).encode()

    def read_tool_groups(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0x8B: each group ``first..last``: its tool count, life and counter."""
        request = ToolGroupRequest.from_block(block)
        path = block_path(block)
        count = request.last - request.first + 1
        if count < 1:
            raise Refused(EW.NUMBER)
        need_room(ToolGroupRecord.SIZE * count, room)
        records = []
        for number in range(request.first, request.last + 1):
            group = self.machine.tool_group(number, path=path)
            records.append(ToolGroupRecord(number, len(group.tools), 0, group.life, 0, group.count))
        return ToolGroupRecords(tuple(records)).encode()

    def read_tool_numbers(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0x4D: tools ``first..last`` (indexes from 1) of a group: T, H, D and state."""
        request = ToolNumberRequest.from_block(block)
        path = block_path(block)
        tools = self.machine.group_tools(request.group, request.first, request.last, path=path)
        need_room(8 + ToolEntry.SIZE * len(tools), room)
        return ToolNumbers(
            request.group, request.first, tuple(ToolEntry(*t) for t in tools)
        ).encode()
