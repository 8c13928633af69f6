"""The modal state of a control and its program pointer, as FANUC's screens show them (no
protocol): the G code of each group in FANUC's group numbering, the one-shot G code, the
value of each address and which of them the executing block commands; the program, the
block and the block counter.

FANUC numbers the G code groups of the M series 1 (G00-G03), 2 (G17-G19), 3 (G90/G91), 4
(G22/G23), 5 (G94/G95), 6 (G20/G21), 7 (G40-G42), 8 (G43/G44/G49), 9 (canned cycles, G80),
10 (G98/G99), 11 (G50/G51), 12 (G66/G67), 13 (G96/G97), 14 (G54-G59), 15 (G61-G64), 16
(G68/G69), 17 (G15/G16), 18 (G40.1-G42.1) and 22 (G50.1/G51.1), as the interpreter does
(:data:`FANUC_GROUPS`: the group of every modal code it accepts).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Final

from .interpreter import Interpreter
from .settings import G_CODE_GROUPS

__all__ = [
    "FANUC_GROUPS",
    "ModalAddress",
    "ModalG",
    "ModalState",
    "ProgramPointer",
    "g_code_text",
    "modal_state",
    "program_pointer",
]

#: FANUC's G code group (M series) of each modal G code the interpreter accepts (x10).
FANUC_GROUPS: Final[dict[int, int]] = {
    code: group for code, group in G_CODE_GROUPS.items() if group != 0
}

#: The addresses whose last value stays from block to block (FANUC's modal "other" data).
_MODAL_ADDRESSES: Final = frozenset("BDEFHMNOST")


def g_code_text(code: int) -> str:
    """``G01``, ``G54``, ``G50.1`` for a code x10 (10, 540, 501)."""
    whole, tenth = divmod(code, 10)
    return f"G{whole:02d}" + (f".{tenth}" if tenth else "")


@dataclass(frozen=True, slots=True)
class ModalG:
    """The G code of one group: FANUC's group number, the code x10 (``10`` for G01), and
    whether the executing block commands it."""

    group: int
    code: int
    commanded: bool

    @property
    def text(self) -> str:
        return g_code_text(self.code)


@dataclass(frozen=True, slots=True)
class ModalAddress:
    """One address but G: its letter, its value (as written; None: never given), and whether
    the executing block commands it."""

    address: str
    value: float | None
    commanded: bool


@dataclass(frozen=True, slots=True)
class ModalState:
    """What the control holds for the executing block: the G code of every group (by FANUC's
    group number), the block's one-shot G code (x10, None without one), and each address but
    G (by letter: the modal ones keep their last value, the others carry the block's value
    only)."""

    groups: tuple[ModalG, ...]
    one_shot: int | None
    addresses: tuple[ModalAddress, ...]

    def group(self, number: int) -> ModalG | None:
        """The G code of FANUC group ``number``; None for a group the control has not."""
        for g in self.groups:
            if g.group == number:
                return g
        return None

    def address(self, letter: str) -> ModalAddress:
        """The value of ``letter`` (a vacant entry for a letter never given)."""
        for a in self.addresses:
            if a.address == letter:
                return a
        return ModalAddress(letter, None, False)


@dataclass(frozen=True, slots=True)
class ProgramPointer:
    """Where the control is in its program: the program executed (0: none), the executing
    block's number from the program's head (1 the first, 0 before any), the character offset
    of that block and of the next in the program text, and the blocks executed since
    power-on (the block counter)."""

    program: int
    block: int
    offset: int
    next_offset: int
    blocks_run: int


def modal_state(it: Interpreter) -> ModalState:
    """The modal state of ``it`` now."""
    codes = it.block_codes
    by_group = {FANUC_GROUPS[code]: code for code in it.modal.values() if code in FANUC_GROUPS}
    groups = tuple(ModalG(g, c, c in codes) for g, c in sorted(by_group.items()))
    program = it.program
    own: dict[str, float | None] = {
        "F": it.last_words.get("F"),
        "H": float(it.h_number) if "H" in it.last_words else None,
        "M": float(it.last_m) if "M" in it.last_words else None,
        "N": float(it.sequence) if it.sequence is not None else None,
        "O": float(program.number) if program is not None else None,
        "S": it.last_words.get("S"),
        "T": it.last_words.get("T"),
    }
    words = dict(it.block_words)
    if program is not None and it.block is not None:
        sequence = program.blocks[it.block].sequence
        if sequence is not None:
            words["N"] = float(sequence)
    addresses = []
    for letter in "ABCDEFHIJKLMNOPQRSTUVWXYZ":
        if letter in own:
            value = own[letter]
        elif letter in _MODAL_ADDRESSES:
            value = it.last_words.get(letter)
        else:
            value = words.get(letter)
        addresses.append(ModalAddress(letter, value, letter in words and value is not None))
    return ModalState(groups, it.one_shot, tuple(addresses))


def program_pointer(it: Interpreter, main: int | None) -> ProgramPointer:
    """The program pointer of ``it``; ``main`` is the program shown while none runs."""
    program = it.program
    if program is None or it.block is None:
        return ProgramPointer(program.number if program else main or 0, 0, 0, 0, it.blocks_run)
    lines = program.text.splitlines(keepends=True)
    starts = [0]
    for line in lines:
        starts.append(starts[-1] + len(line))

    def offset(index: int) -> int:
        if index >= len(program.blocks):
            return starts[-1]
        return starts[min(program.blocks[index].line - 1, len(lines))]

    return ProgramPointer(
        program.number, it.block + 1, offset(it.block), offset(it.block + 1), it.blocks_run
    )
