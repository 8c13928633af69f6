"""The native client's modal data, operator messages and program pointers.

:class:`NativeModal` is the part of :class:`~focas_net.client.NativeClient` that sends the
frames FANUC's library sends for ``cnc_modal``, ``cnc_rdgcode``, ``cnc_rdcommand``,
``cnc_rdopmsg``/``cnc_rdopmsg3``, ``cnc_exeprgname2``, ``cnc_rdactpt``, ``cnc_rdblkcount``
and ``cnc_rdmdipntr`` (``docs/native-client.md``) and types their answers. Every argument is
checked here, in the caller's frame, as the library checks it.
"""

# Every call takes a per-call ``timeout=`` by contract, so ASYNC109 does not apply here.
# ruff: noqa: ASYNC109

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from decimal import Decimal
from typing import Any, Final

from focas_net.errors import EW, CncError

from ..native import (
    ADDRESS_SLOTS,
    MODAL_GROUPS,
    ActivePointer,
    BlockCounter,
    CommandRecords,
    ExecutingPath,
    GCodeRecords,
    LibraryCall,
    MdiPointer,
    ModalAuxData,
    ModalGCodes,
    OperatorMessageRecords,
    calls,
    g_code_of,
)
from ._native_items import only_answer, text
from ._native_link import NativeLink
from ._values import check_int

__all__ = ["CommandValue", "GCode", "ModalGroup", "ModalValue", "OperatorMessageText"]

#: The addresses of ``cnc_modal`` types 100..126, in type order.
_TYPE_ADDRESSES: Final = "BDEFHLMSTRPQACIJKNOUVWXYZ"
#: The letter of each slot of a ``cnc_modal`` -2 answer.
_SLOT_LETTERS: Final = {slot: letter for letter, slot in ADDRESS_SLOTS.items()}
#: Most operator messages one ``cnc_rdopmsg3`` call asks for.
_MAX_MESSAGES: Final = 10


@dataclass(frozen=True, slots=True)
class ModalGroup:
    """The G code of one group as ``cnc_modal`` gives it: the group (1 is FANUC's group 01),
    the code (``G01``; None when FANUC's table of the group is not known here), its index in
    that table and whether the block commands it."""

    group: int
    code: str | None
    index: int
    commanded: bool


@dataclass(frozen=True, slots=True)
class ModalValue:
    """The value of one address as ``cnc_modal`` gives it (None: no value) and whether the
    block commands it."""

    address: str
    value: float | None
    commanded: bool


@dataclass(frozen=True, slots=True)
class GCode:
    """One G code of ``cnc_rdgcode``: its group (0 one-shot), the code and whether the block
    commands it."""

    group: int
    code: str
    commanded: bool


@dataclass(frozen=True, slots=True)
class CommandValue:
    """One command value of ``cnc_rdcommand``: the address, the value and whether the block
    commands it."""

    address: str
    value: Decimal
    commanded: bool


@dataclass(frozen=True, slots=True)
class OperatorMessageText:
    """One operator message: its number (-1: none), its type and its text."""

    number: int
    type: int
    text: str


def _check_block(block: object) -> int:
    return check_int("block", block, 0, 2)


def _messages(records: OperatorMessageRecords) -> tuple[OperatorMessageText, ...]:
    return tuple(OperatorMessageText(r.number, r.type, text(r.message)) for r in records.records)


class NativeModal(NativeLink):
    """Modal data, operator messages and program pointers over FOCAS/2."""

    async def _asked(
        self,
        asked: str,
        call_of: Callable[..., LibraryCall],
        path: int | None,
        timeout: float | None,
        *args: int,
    ) -> Any:
        """The answer of one call of one frame; the CNC's EW_NUMBER names what was ``asked``
        (a group, an address or a type the control has not, or a block it does not read)."""
        try:
            return only_answer(*await self._only(call_of, path, timeout, *args))
        except CncError as exc:
            if exc.ew != EW.NUMBER:
                raise
            block = args[-1]
            raise CncError.from_ew(
                EW.NUMBER, f"{exc.detail or call_of.__name__}: {asked}, block {block}"
            ) from None

    async def read_modal_groups(
        self,
        group: int | None = None,
        block: int = 0,
        *,
        path: int | None = None,
        timeout: float | None = None,
    ) -> tuple[ModalGroup, ...]:
        """``cnc_modal`` of the G codes: every group (``group`` None, type -1) or FANUC group
        ``group`` (1..22), of the executing block (``block`` 0) or the next ones (1, 2:
        the simulated machine reads no block ahead, so they answer as the executing one)."""
        kind = -1 if group is None else check_int("group", group, 1, MODAL_GROUPS) - 1
        b = _check_block(block)
        asked = "every group" if group is None else f"group {group}"
        codes: ModalGCodes = await self._asked(asked, calls.cnc_modal, path, timeout, kind, b)
        first = 0 if kind == -1 else kind
        out = []
        for i, entry in enumerate(codes.records):
            t = first + i
            code = g_code_of(t, entry.g_data)
            name = (
                None
                if code is None
                else f"G{code // 10:02d}" + (f".{code % 10}" if code % 10 else "")
            )
            out.append(ModalGroup(t + 1, name, entry.index, entry.commanded))
        return tuple(out)

    async def read_modal_values(
        self,
        address: str | None = None,
        block: int = 0,
        *,
        path: int | None = None,
        timeout: float | None = None,
    ) -> tuple[ModalValue, ...]:
        """``cnc_modal`` of the data other than G codes: every address (``address`` None,
        type -2) or one (``"F"``...: its type 100..124)."""
        b = _check_block(block)
        if address is None:
            kind = -2
        else:
            if not isinstance(address, str):
                raise TypeError(f"address must be a letter (str) or None, got {address!r}")
            if len(address) != 1 or address not in _TYPE_ADDRESSES:
                raise ValueError(f"address {address!r} is not one of {', '.join(_TYPE_ADDRESSES)}")
            kind = 100 + _TYPE_ADDRESSES.index(address)
        asked = "every address" if address is None else f"address {address}"
        data: ModalAuxData = await self._asked(asked, calls.cnc_modal, path, timeout, kind, b)
        if address is not None:
            if not data.records:
                return ()
            entry = data.records[0]
            return (ModalValue(address, entry.value if entry.flag1 else None, entry.commanded),)
        out = []
        for slot, entry in enumerate(data.records):
            letter = _SLOT_LETTERS.get(slot)
            if letter is not None:
                value = entry.value if entry.flag1 else None
                out.append(ModalValue(letter, value, entry.commanded))
        return tuple(out)

    async def read_g_codes(
        self,
        kind: int = -1,
        block: int = 0,
        *,
        path: int | None = None,
        timeout: float | None = None,
    ) -> tuple[GCode, ...]:
        """``cnc_rdgcode``: every modal group (-1), the one-shot code (-2) or one group (0 is
        FANUC's group 01)."""
        k = check_int("type", kind, -2, MODAL_GROUPS - 1)
        b = _check_block(block)
        records: GCodeRecords = await self._asked(
            f"type {k}", calls.cnc_rdgcode, path, timeout, k, b
        )
        return tuple(GCode(r.group, r.code, bool(r.flag & 1)) for r in records.records)

    async def read_commands(
        self,
        kind: int = -1,
        block: int = 0,
        *,
        path: int | None = None,
        timeout: float | None = None,
    ) -> tuple[CommandValue, ...]:
        """``cnc_rdcommand``: the modal addresses with a value (-1) or one address by its
        slot (A 0 .. Z 28)."""
        k = check_int("type", kind, -1, 28)
        b = _check_block(block)
        records: CommandRecords = await self._asked(
            f"type {k}", calls.cnc_rdcommand, path, timeout, k, b
        )
        return tuple(
            CommandValue(r.address, Decimal(r.value).scaleb(-r.decimals), bool(r.flag & 1))
            for r in records.records
        )

    async def read_operator_message(
        self, *, path: int | None = None, timeout: float | None = None
    ) -> OperatorMessageText:
        """``cnc_rdopmsg`` (type 0, the only type FANUC's library reads): the first operator
        message (number -1 when there is none)."""
        records: OperatorMessageRecords = only_answer(
            *await self._only(calls.cnc_rdopmsg, path, timeout)
        )
        found = _messages(records)
        return found[0] if found else OperatorMessageText(-1, 0, "")

    async def read_operator_messages(
        self,
        kind: int = -1,
        count: int = 5,
        *,
        path: int | None = None,
        timeout: float | None = None,
    ) -> tuple[OperatorMessageText, ...]:
        """``cnc_rdopmsg3``: at most ``count`` (1..10) messages of type ``kind`` (0..4) or of
        every type (-1)."""
        k = check_int("type", kind, -1, 4)
        n = check_int("count", count, 1, _MAX_MESSAGES)
        records: OperatorMessageRecords = only_answer(
            *await self._only(calls.cnc_rdopmsg3, path, timeout, k, n)
        )
        return _messages(records)[:n]

    async def read_program_path(
        self, *, path: int | None = None, timeout: float | None = None
    ) -> str:
        """``cnc_exeprgname2``: the full path of the executing program."""
        value: ExecutingPath = only_answer(*await self._only(calls.cnc_exeprgname2, path, timeout))
        return text(value.text)

    async def read_active_pointer(
        self, *, path: int | None = None, timeout: float | None = None
    ) -> ActivePointer:
        """``cnc_rdactpt``: the executing program and its block number."""
        value: ActivePointer = only_answer(*await self._only(calls.cnc_rdactpt, path, timeout))
        return value

    async def read_block_count(
        self, *, path: int | None = None, timeout: float | None = None
    ) -> int:
        """``cnc_rdblkcount``: the block counter."""
        value: BlockCounter = only_answer(*await self._only(calls.cnc_rdblkcount, path, timeout))
        return value.count

    async def read_mdi_pointer(
        self, *, path: int | None = None, timeout: float | None = None
    ) -> MdiPointer:
        """``cnc_rdmdipntr``: the program and pointer executed, the program and pointer
        prepared."""
        value: MdiPointer = only_answer(*await self._only(calls.cnc_rdmdipntr, path, timeout))
        return value
