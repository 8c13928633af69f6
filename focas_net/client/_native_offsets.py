"""The native client's calls of tool offsets, work zero offsets and tool life management
(``cnc_rdtofs``, ``cnc_rdzofs``, ``cnc_rdtoolgrp``...), a part of
:class:`~focas_net.client.NativeClient`.

Each call checks and encodes its arguments in the caller's frame and sends the frames FANUC's
library sends (:mod:`focas_net.native.offsets`); values are in least input increments (0.001
mm on a metric machine), as the CNC keeps them.
"""

# Every call takes a per-call ``timeout=`` by contract, so ASYNC109 does not apply here.
# ruff: noqa: ASYNC109

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Final

from focas_net.errors import PayloadError

from ..native import (
    LibraryCall,
    ResponseBlock,
    ScaledValues,
    ToolEntry,
    ToolGroupRecords,
    ToolGroupsInUse,
    ToolLifeCounts,
    ToolNumbers,
    ToolOffsetMemory,
)
from ..native import offsets as calls
from ._native_items import only_answer
from ._native_link import Handle, NativeLink, check_axis_of
from ._values import I16_MAX, I32_MAX, I32_MIN, check_int

__all__ = ["ToolGroupData"]

#: The offset types a call may name (a machining centre has 0..3, a lathe 0..6).
_MAX_TYPE: Final = 99
#: Work zero offsets: 0 external, 1..6 G54..G59.
_MAX_WORK: Final = 6


@dataclass(frozen=True, slots=True)
class ToolGroupData:
    """``cnc_rdtoolgrp``: a tool life group, its life and the counter of the tool in use,
    and each tool (T number, H and D codes, state 0 unused, 1 in use, 2 expired, 3
    skipped)."""

    group: int
    life: int
    count: int
    tools: tuple[ToolEntry, ...]


def _check_values(values: object, what: str) -> tuple[int, ...]:
    if not isinstance(values, list | tuple):
        raise TypeError(f"{what} must be a list of integers, got {values!r}")
    return tuple(check_int(what, v, I32_MIN, I32_MAX) for v in values)


class NativeOffsets(NativeLink):
    """Tool and work offsets and tool life over FOCAS/2 (see the module docstring)."""

    # -- tool offsets --------------------------------------------------------------------
    async def read_tool_offset(
        self,
        number: int,
        offset_type: int,
        *,
        path: int | None = None,
        timeout: float | None = None,
    ) -> int:
        """``cnc_rdtofs``: tool offset ``number`` of type ``offset_type`` (machining centre:
        0 radius wear, 1 radius geometry, 2 length wear, 3 length geometry; lathe: 0/1 X, 2/3
        Z, 4/5 nose radius wear/geometry, 6 tip)."""
        check_int("tool offset number", number, 1, I16_MAX)
        check_int("offset type", offset_type, 0, _MAX_TYPE)
        done = await self._only(calls.cnc_rdtofs, path, timeout, number, offset_type)
        value: ScaledValues = only_answer(*done)
        return value.values[0].mantissa

    async def read_tool_offsets(
        self,
        first: int,
        last: int,
        offset_type: int = -1,
        *,
        path: int | None = None,
        timeout: float | None = None,
    ) -> tuple[tuple[int, ...], ...]:
        """``cnc_rdtofsr``: tool offsets ``first..last``, each its value of ``offset_type``
        or (-1) of every type in type order (a machining centre's four)."""
        check_int("first tool offset", first, 1, I16_MAX)
        check_int("last tool offset", last, first, I16_MAX)
        if offset_type != -1:
            check_int("offset type", offset_type, 0, _MAX_TYPE)
        done = await self._only(calls.cnc_rdtofsr, path, timeout, first, offset_type, last)
        value: ScaledValues = only_answer(*done)
        return _rows(value, last - first + 1, None)

    async def write_tool_offset(
        self,
        number: int,
        offset_type: int,
        value: int,
        *,
        path: int | None = None,
        timeout: float | None = None,
    ) -> None:
        """``cnc_wrtofs``: set one tool offset value (least input increments)."""
        check_int("tool offset number", number, 1, I16_MAX)
        check_int("offset type", offset_type, 0, _MAX_TYPE)
        check_int("tool offset value", value, I32_MIN, I32_MAX)
        only_answer(*await self._only(calls.cnc_wrtofs, path, timeout, number, offset_type, value))

    async def read_tool_offset_memory(
        self, *, path: int | None = None, timeout: float | None = None
    ) -> ToolOffsetMemory:
        """``cnc_rdtofsinfo``: the kind of tool offset memory (``type``) and its count."""
        memory: ToolOffsetMemory = only_answer(
            *await self._only(calls.cnc_rdtofsinfo, path, timeout)
        )
        return memory

    # -- work zero offsets -----------------------------------------------------------------
    async def read_work_offsets(
        self,
        first: int,
        last: int,
        axis: int = -1,
        *,
        path: int | None = None,
        timeout: float | None = None,
    ) -> tuple[tuple[int, ...], ...]:
        """``cnc_rdzofsr``: work zero offsets ``first..last`` (0 external, 1..6 G54..G59),
        each the value of every axis of the path (``axis=-1``) or of axis ``axis``."""
        check_int("first work offset", first, 0, _MAX_WORK)
        check_int("last work offset", last, first, _MAX_WORK)
        _check_axis(axis)
        handle, call, blocks = await self._per_axis(
            calls.cnc_rdzofsr, path, timeout, axis, first, axis, last
        )
        value: ScaledValues = only_answer(handle, call, blocks)
        keep = handle.axes_on(self._path_of(path)) if axis == -1 else 1
        return _rows(value, last - first + 1, keep)

    async def read_work_offset(
        self,
        number: int,
        axis: int = -1,
        *,
        path: int | None = None,
        timeout: float | None = None,
    ) -> tuple[int, ...]:
        """``cnc_rdzofs``: work zero offset ``number`` of every axis (-1) or of one."""
        check_int("work offset", number, 0, _MAX_WORK)
        _check_axis(axis)
        handle, call, blocks = await self._per_axis(
            calls.cnc_rdzofs, path, timeout, axis, number, axis
        )
        value: ScaledValues = only_answer(handle, call, blocks)
        keep = handle.axes_on(self._path_of(path)) if axis == -1 else 1
        return tuple(v.mantissa for v in value.values[:keep])

    async def write_work_offset(
        self,
        number: int,
        values: list[int] | tuple[int, ...],
        axis: int = -1,
        *,
        path: int | None = None,
        timeout: float | None = None,
    ) -> None:
        """``cnc_wrzofs``: set work zero offset ``number``: one value per axis of the path
        (``axis=-1``; sent as the max axes values the library sends, zeros after them) or the
        value of axis ``axis``."""
        p = self._path_of(path)
        check_int("work offset", number, 0, _MAX_WORK)
        _check_axis(axis)
        given = _check_values(values, "work offset value")
        deadline = self._deadline(timeout)
        handle = self._handle_now() or await self._handle_for(deadline)
        check_axis_of(handle, axis, "cnc_wrzofs", p)
        want = handle.axes_on(p) if axis == -1 else 1
        if len(given) != want:
            raise ValueError(f"{len(given)} work offset values for {want} axes")
        if axis == -1:
            given += (0,) * (max(handle.max_axes, want) - want)
        call = calls.cnc_wrzofs(handle.command_set, number, axis, given)
        only_answer(handle, call, await self._exchange(handle, call, deadline, 0, p))

    async def _per_axis(
        self,
        call_of: Callable[..., LibraryCall],
        path: int | None,
        timeout: float | None,
        axis: int,
        *args: Any,
    ) -> tuple[Handle, LibraryCall, tuple[ResponseBlock, ...]]:
        """:meth:`_only` of a call of ``axis`` (-1: every axis), checked against the path's
        axes before anything is sent."""
        p = self._path_of(path)
        deadline = self._deadline(timeout)
        handle = self._handle_now() or await self._handle_for(deadline)
        check_axis_of(handle, axis, call_of.__name__, p)
        call = call_of(handle.command_set, *args)
        return handle, call, await self._exchange(handle, call, deadline, 0, p)

    # -- tool life -----------------------------------------------------------------------
    async def read_tool_life_info(
        self, *, path: int | None = None, timeout: float | None = None
    ) -> ToolLifeCounts:
        """``cnc_rdtlinfo`` and ``cnc_rdngrp``: the groups declared, the most groups and
        tools per group, and the largest lives (minutes and uses)."""
        counts: ToolLifeCounts = only_answer(*await self._only(calls.cnc_rdtlinfo, path, timeout))
        return counts

    async def read_tool_group_in_use(
        self, *, path: int | None = None, timeout: float | None = None
    ) -> int:
        """``cnc_rdusegrpid``: the tool life group of the tool in use (0: none)."""
        groups: ToolGroupsInUse = only_answer(
            *await self._only(calls.cnc_rdusegrpid, path, timeout)
        )
        return groups.use

    async def read_tool_group(
        self, group: int, *, path: int | None = None, timeout: float | None = None
    ) -> ToolGroupData:
        """``cnc_rdtoolgrp``: tool life group ``group`` with its tools (0x8B, then 0x4D for
        as many tools as it has, as FANUC's library asks)."""
        check_int("tool group", group, 1, I16_MAX)
        records: ToolGroupRecords = only_answer(
            *await self._only(calls.cnc_rdtoolgrp, path, timeout, group)
        )
        if not records.records:
            raise PayloadError("cnc_rdtoolgrp: the answer carries no group")
        head = records.records[0]
        tools: tuple[ToolEntry, ...] = ()
        if head.tools > 0:
            numbers: ToolNumbers = only_answer(
                *await self._only(calls.cnc_rdtoolgrp, path, timeout, head.group, head.tools)
            )
            tools = numbers.tools
        return ToolGroupData(head.group, head.life, head.count, tools)

    async def read_tool_number(
        self,
        group: int,
        index: int,
        *,
        path: int | None = None,
        timeout: float | None = None,
    ) -> int:
        """``cnc_toolnum``: the T number of tool ``index`` (1..) of tool life group
        ``group``."""
        check_int("tool group", group, 1, I16_MAX)
        check_int("tool index", index, 1, I16_MAX)
        numbers: ToolNumbers = only_answer(
            *await self._only(calls.cnc_toolnum, path, timeout, group, index)
        )
        if not numbers.tools:
            raise PayloadError("cnc_toolnum: the answer carries no tool")
        return numbers.tools[0].number


def _check_axis(axis: int) -> None:
    """An axis of a work offset call: -1 (every axis) or 1.."""
    if axis != -1:
        check_int("axis", axis, 1, I16_MAX)


def _rows(value: ScaledValues, count: int, keep: int | None) -> tuple[tuple[int, ...], ...]:
    """The values of ``count`` numbers, each its first ``keep`` (None: all of its)."""
    flat = [v.mantissa for v in value.values]
    per = max(len(flat) // count, 1)
    return tuple(
        tuple(flat[i : i + (per if keep is None else keep)]) for i in range(0, len(flat), per)
    )
