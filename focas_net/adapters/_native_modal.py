"""The native adapter's modal data, operator messages and program pointers
(``docs/native-protocol.md``, "Modal data and pointers"; what a handler is:
:mod:`focas_net.adapters.native`).

Each answers for the path in its block's path word from the machine's protocol-free state:
:meth:`~focas_net.sim.Machine.modal_state`, :meth:`~focas_net.sim.Machine.program_pointer`
and :meth:`~focas_net.sim.Machine.operator_messages`, which follow the running program.

Rules of these commands (this project's, where FANUC's are not known; see the protocol
document):

* the machine reads no block ahead of the one it executes, so ``block`` 1 and 2 (the next
  blocks, which collectors such as the MTConnect adapter ask for the modal F and T) answer
  what ``block`` 0 answers: the modal state the next blocks start from. Any other ``block``
  answers EW_NUMBER, as does a group, an address slot or an axis the control has not;
* ``cnc_modal``'s one-shot codes (0x21 -2, -3 and 100..) answer EW_NUMBER: FANUC's table of
  the one-shot group is not known; ``cnc_rdgcode`` type -2 gives the one-shot code as text;
* operator messages: FANUC's library reads type 0 only with ``cnc_rdopmsg`` and
  ``cnc_rdopmsg2`` (another type is EW_ATTRIB, a length under 262 EW_LENGTH, both without
  sending), so every message is of type 0: the external ones (the PMC's A area) by number,
  then the program's ``#3006`` message; types 1..4 hold none. 0x34 of one type answers every
  message of it, or one entry of number -1 and length 0 when there is none; 0x34 -1 and
  0xD0 answer the messages alone (no entry when there is none), at most ``count``.
"""

from __future__ import annotations

from typing import Final

from focas_net.errors import EW
from focas_net.native import (
    ADDRESS_SLOTS,
    G_CODE_INDEX,
    MODAL_GROUPS,
    ActivePointer,
    BlockCounter,
    CommandRecord,
    CommandRequest,
    ExecutingPath,
    GCodeRecord,
    GCodeRequest,
    MdiPointer,
    ModalAux,
    ModalAuxRequest,
    ModalGCode,
    ModalGRequest,
    OperatorMessage3Request,
    OperatorMessageRecord,
    OperatorMessageRequest,
    RequestBlock,
)
from focas_net.sim import Machine, OperatorMessage, Session
from focas_net.sim.nc import ModalState

from ._common import Refused, need_room
from ._native_cnc import block_path

__all__ = ["MESSAGE_TYPES", "ModalHandlers"]

#: Operator message types (``cnc_rdopmsg3``'s 0..4); every message is of type 0.
MESSAGE_TYPES: Final = range(5)
#: Slots of a 0x22 -1 answer: A (0) .. Z (28).
_SLOTS: Final = 29
#: The letter of each slot of a 0x22 answer.
_LETTERS: Final[dict[int, str]] = {slot: letter for letter, slot in ADDRESS_SLOTS.items()}
#: Most modal answers kept (a poller's few requests per path).
_KEPT: Final = 64
#: The addresses 0x97 -1 answers: FANUC's modal data other than G codes.
_COMMANDED: Final = "BDEFHMNOST"


#: The blocks a modal read names: 0 the executing one, 1 and 2 the next ones (answered alike).
_BLOCKS: Final = range(3)


def _check_block(block: int) -> None:
    if block not in _BLOCKS:
        raise Refused(EW.NUMBER)


def _number(value: float) -> tuple[int, int]:
    """``(mantissa, decimals)`` of ``value`` (at most 7 decimals)."""
    entry = ModalAux.of(value, False)
    sign = -1 if value < 0 else 1
    return sign * entry.aux_data, entry.flag2


def _g_data(state: ModalState, kind: int) -> int:
    """``g_data`` of group type ``kind`` (FANUC's group ``kind + 1``): the code's index,
    bit 7 when commanded; a group the machine does not model is at its first code (0)."""
    g = state.group(kind + 1)
    if g is None:
        return 0
    index = G_CODE_INDEX.get(kind, {}).get(g.code, 0)
    return index | (0x80 if g.commanded else 0)


class ModalHandlers:
    """Modal data, operator messages and program pointers of one machine."""

    __slots__ = ("_kept", "machine")

    def __init__(self, machine: Machine) -> None:
        self.machine = machine
        #: (command, path, arguments) -> (the modal state answered, the answer): the machine
        #: gives the same state object until a block runs, so a poll encodes it once.
        self._kept: dict[tuple[int, int, tuple[int, ...]], tuple[ModalState, bytes]] = {}

    def _state(self, block: RequestBlock, room: int) -> tuple[ModalState, bytes | None]:
        """The modal state of the block's path, and the answer made of it before, if any
        (EW_LENGTH when it does not fit the ``room`` left)."""
        state = self.machine.modal_state(path=block_path(block))
        known = self._kept.get((block.command, block.path, block.args))
        if known is None or known[0] is not state:
            return state, None
        need_room(len(known[1]), room)
        return state, known[1]

    def _keep(self, block: RequestBlock, state: ModalState, data: bytes) -> bytes:
        if len(self._kept) >= _KEPT:
            self._kept.clear()
        self._kept[(block.command, block.path, block.args)] = (state, data)
        return data

    # -- cnc_modal -------------------------------------------------------------------------

    def read_modal_g(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0x21: the G code of group type ``kind`` (0..21), or every group (-1)."""
        req = ModalGRequest.from_block(block)
        _check_block(req.block)
        kind = req.kind
        if kind != -1 and not 0 <= kind < MODAL_GROUPS:
            raise Refused(EW.NUMBER)
        kinds = range(MODAL_GROUPS) if kind == -1 else (kind,)
        need_room(ModalGCode.SIZE * len(kinds), room)
        state, known = self._state(block, room)
        if known is not None:
            return known
        data = bytes(pair for k in kinds for pair in (_g_data(state, k), 0))
        return self._keep(block, state, data)

    def read_modal_aux(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0x22: an address by slot (0..28), every slot (-1), every axis (-2) or one axis
        (100..)."""
        req = ModalAuxRequest.from_block(block)
        _check_block(req.block)
        path = block_path(block)
        kind = req.kind
        state, known = self._state(block, room)
        if known is not None:
            return known
        if kind == -1 or 0 <= kind < _SLOTS:
            slots = range(_SLOTS) if kind == -1 else (kind,)
            entries = []
            for slot in slots:
                letter = _LETTERS.get(slot)
                if letter is None:
                    if kind != -1:
                        raise Refused(EW.NUMBER)
                    entries.append(ModalAux(0, 0, 0))
                    continue
                a = state.address(letter)
                entries.append(ModalAux.of(a.value, a.commanded))
        else:
            axes = self.machine.path_info(path).axes
            if kind == -2:
                chosen = list(axes)
            elif 100 <= kind < 100 + len(axes):
                chosen = [axes[kind - 100]]
            else:
                raise Refused(EW.NUMBER)
            entries = []
            for name in chosen:
                a = state.address(name)
                entries.append(ModalAux.of(a.value, a.commanded))
        need_room(ModalAux.SIZE * len(entries), room)
        return self._keep(block, state, b"".join(e.encode() for e in entries))

    # -- cnc_rdgcode, cnc_rdcommand --------------------------------------------------------

    def read_g_codes(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0x96: every modal group (-1), the one-shot code (-2, none: no entry) or one group
        (its type, 0..)."""
        req = GCodeRequest.from_block(block)
        _check_block(req.block)
        state, known = self._state(block, room)
        if known is not None:
            return known
        entries = []
        if req.type == -2:
            if state.one_shot is not None:
                entries.append(_g_record(0, state.one_shot, True))
        elif req.type == -1:
            entries = [_g_record(g.group, g.code, g.commanded) for g in state.groups]
        else:
            g = state.group(req.type + 1) if req.type >= 0 else None
            if g is None:
                raise Refused(EW.NUMBER)
            entries.append(_g_record(g.group, g.code, g.commanded))
        need_room(GCodeRecord.SIZE * len(entries), room)
        return self._keep(block, state, b"".join(e.encode() for e in entries))

    def read_commands(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0x97: the modal addresses with a value (-1) or one address by slot."""
        req = CommandRequest.from_block(block)
        _check_block(req.block)
        state, known = self._state(block, room)
        if known is not None:
            return known
        if req.type == -1:
            letters = [c for c in _COMMANDED if state.address(c).value is not None]
        else:
            letter = _LETTERS.get(req.type)
            if letter is None:
                raise Refused(EW.NUMBER)
            letters = [letter]
        entries = []
        for letter in letters:
            a = state.address(letter)
            value, decimals = (0, 0) if a.value is None else _number(a.value)
            entries.append(CommandRecord(letter, 0, int(a.commanded), value, decimals))
        need_room(CommandRecord.SIZE * len(entries), room)
        return self._keep(block, state, b"".join(e.encode() for e in entries))

    # -- operator messages -----------------------------------------------------------------

    def read_operator_messages(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0x34: the messages of one type (0..4), or of every type (-1)."""
        req = OperatorMessageRequest.from_block(block)
        return self._messages(block, req.type, None, room)

    def read_operator_messages3(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0xD0: at most ``count`` messages of one type (0..4) or of every type (-1)."""
        req = OperatorMessage3Request.from_block(block)
        if req.count < 0:
            raise Refused(EW.LENGTH)
        return self._messages(block, req.type, req.count, room)

    def _messages(self, block: RequestBlock, kind: int, count: int | None, room: int) -> bytes:
        if kind != -1 and kind not in MESSAGE_TYPES:
            raise Refused(EW.NUMBER)
        shown = self.machine.operator_messages(path=block_path(block))
        entries = [_message_record(m) for m in shown] if kind in (-1, 0) else []
        if count is not None:
            entries = entries[:count]
        elif kind != -1:
            entries = entries[:1] or [OperatorMessageRecord(-1, kind, 0, b"")]
        most = room // OperatorMessageRecord.SIZE
        if kind == -1 or count is not None:
            entries = entries[:most]
        need_room(OperatorMessageRecord.SIZE * len(entries), room)
        return b"".join(e.encode() for e in entries)

    # -- program pointers ------------------------------------------------------------------

    def read_executing_path(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0xFC: ``//CNC_MEM/USER/PATH<n>/O<number>`` of the executing program (the main
        program while none runs); no program is the empty text."""
        path = block_path(block)
        program = self.machine.program_pointer(path=path).program
        text = f"//CNC_MEM/USER/PATH{path}/O{program:04d}" if program else ""
        need_room(256, room)
        return ExecutingPath(text.encode("ascii")).encode()

    def read_active_pointer(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0x162: the executing program and block (from the program's head, 1 the first)."""
        p = self.machine.program_pointer(path=block_path(block))
        return ActivePointer(p.program, p.block).encode()

    def read_block_count(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0x35: the blocks executed since power-on."""
        p = self.machine.program_pointer(path=block_path(block))
        return BlockCounter(p.blocks_run).encode()

    def read_mdi_pointer(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0x38: the program executed and the character offset of its executing block, the
        same program and the offset of the block it prepares next."""
        p = self.machine.program_pointer(path=block_path(block))
        return MdiPointer(p.program, p.offset, p.program, p.next_offset).encode()


def _g_record(group: int, code: int, commanded: bool) -> GCodeRecord:
    """The 0x96 entry of ``code`` (x10) in FANUC group ``group`` (0: one-shot)."""
    whole, tenth = divmod(code, 10)
    number, decimals = (code, 1) if tenth else (whole, 0)
    return GCodeRecord(group, int(commanded), number, decimals)


def _message_record(m: OperatorMessage) -> OperatorMessageRecord:
    text = m.text.encode("ascii")[:256]
    return OperatorMessageRecord(m.number, 0, len(text), text)
