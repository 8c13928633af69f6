"""The modal state, the program pointer and the operator messages of a machine's paths, a
part of :class:`~focas_net.sim.Machine` (no protocol).

* :meth:`ModalOperations.modal_state` and :meth:`ModalOperations.program_pointer` read a
  path's interpreter (:mod:`focas_net.sim.nc.modal`), brought to the clock's time first, so
  they follow the running program.
* Operator messages, as on a FANUC control: a program's ``#3006 = n (MESSAGE)`` stops it
  with the message until the next cycle start or reset (the path's own), and **external
  operator messages**: each bit of the PMC's A area may be given a message number and text
  (:class:`ExternalMessage`, the machine file's ``[[operator_messages]]``); while the bit is
  1 the message is shown on every path. FANUC numbers them 2000-2999 (2000-2099 shown with
  their number, 2100-2999 the text alone); 1000-1999 are external *alarm* messages, which
  this machine does not model, so they are refused.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Final

from focas_net.errors import EW

from ._base import MachineError
from ._paths import Paths
from .nc import ModalState, ProgramPointer, modal_state, program_pointer

__all__ = [
    "EXTERNAL_MESSAGE_NUMBERS",
    "MAX_MESSAGE_LENGTH",
    "ExternalMessage",
    "ModalOperations",
    "OperatorMessage",
]

#: Numbers of the external operator messages (FANUC: 2000-2999).
EXTERNAL_MESSAGE_NUMBERS: Final = range(2000, 3000)
#: Longest message text (FANUC's message screen: 255 characters).
MAX_MESSAGE_LENGTH: Final = 255


@dataclass(frozen=True, slots=True)
class ExternalMessage:
    """An external operator message: the A-area bit that shows it (``byte``, ``bit``), its
    number (:data:`EXTERNAL_MESSAGE_NUMBERS`) and its text."""

    byte: int
    bit: int
    number: int
    text: str


@dataclass(frozen=True, slots=True)
class OperatorMessage:
    """A message on the operator message screen: its number (an external message's number,
    or the value ``#3006`` was given), its text, and whether it is external (from the PMC)
    rather than the program's ``#3006``."""

    number: int
    text: str
    external: bool


def message_problem(text: object) -> str | None:
    """Why ``text`` cannot be a message (None when it can): printable ASCII, 1..255."""
    if not isinstance(text, str):
        return f"a message is text, got {text!r}"
    if not 1 <= len(text) <= MAX_MESSAGE_LENGTH:
        return f"a message is 1..{MAX_MESSAGE_LENGTH} characters, got {len(text)}"
    if not all(" " <= c <= "~" for c in text):
        return f"a message is printable ASCII, got {text!r}"
    return None


def _whole(value: object) -> bool:
    return isinstance(value, int) and not isinstance(value, bool)


class ModalOperations:
    """The modal state, the program pointer and the operator messages (a base of
    :class:`~focas_net.sim.Machine`, which builds :attr:`_paths` and the PMC)."""

    _paths: Paths
    _external_messages: tuple[ExternalMessage, ...] = ()
    #: path -> (what the state was made of, the state): made again only after a block.
    _modal_kept: dict[int, tuple[tuple[object, ...], ModalState]] | None = None

    def read_pmc(self, letter: str, start: int, length: int) -> bytes:  # pragma: no cover
        raise NotImplementedError

    def pmc_area(self, letter: str) -> tuple[int, bool] | None:  # pragma: no cover
        raise NotImplementedError

    def modal_state(self, *, path: int = 1) -> ModalState:
        """The G code of each group, the one-shot G code and the value of each address of
        ``path``'s executing block (the power-on state before a program ran)."""
        p = self._paths.at(path)
        if p.live:
            p.sync()
        it = p.engine.interpreter
        # the state changes only when a block runs, a reset rewinds or the program changes
        key = (it, it.blocks_run, it.block, it.program, it.sequence)
        kept = self._modal_kept
        if kept is None:
            kept = self._modal_kept = {}
        known = kept.get(path)
        if known is not None and known[0] == key:
            return known[1]
        state = modal_state(it)
        kept[path] = (key, state)
        return state

    def program_pointer(self, *, path: int = 1) -> ProgramPointer:
        """The program ``path`` executes (the main program while none runs), the executing
        block and the block counter."""
        p = self._paths.at(path)
        if p.live:
            p.sync()
        return program_pointer(p.engine.interpreter, p.programs.main)

    @property
    def external_messages(self) -> tuple[ExternalMessage, ...]:
        """The external operator messages defined, by number."""
        return self._external_messages

    def set_external_messages(self, messages: Sequence[ExternalMessage]) -> None:
        """Define the external operator messages (replacing those defined). ValueError, and
        nothing changes, for a bit outside the A area or 0..7, a number outside 2000-2999
        (1000-1999, external alarm messages, are not modelled), a number or a bit given
        twice, or a text that is not 1..255 printable ASCII characters; TypeError for messages
        that are no list of :class:`ExternalMessage`."""
        if isinstance(messages, str | bytes) or not isinstance(messages, Sequence):
            raise TypeError(f"messages must be a list of ExternalMessage, got {messages!r}")
        for i, m in enumerate(messages):
            if not isinstance(m, ExternalMessage):
                raise TypeError(f"messages[{i}] must be an ExternalMessage, got {m!r}")
        area = self.pmc_area("A")
        size = 0 if area is None else area[0]
        if size == 0 and messages:
            raise ValueError("the machine has no A area for external operator messages")
        numbers: set[int] = set()
        bits: dict[tuple[int, int], int] = {}  # each bit's message number
        out = []
        for m in messages:
            for name in ("byte", "bit", "number"):
                if not _whole(getattr(m, name)):
                    raise ValueError(f"{m!r}: the {name} is not an integer")
            where = f"A{m.byte}.{m.bit}"
            if not 0 <= m.byte < size or not 0 <= m.bit <= 7:
                raise ValueError(f"{where} is outside the A area (A0.0..A{size - 1}.7)")
            if m.number not in EXTERNAL_MESSAGE_NUMBERS:
                raise ValueError(
                    f"message {m.number} of {where}: external operator messages are "
                    "2000..2999 (1000..1999, external alarm messages, are not modelled)"
                )
            if m.number in numbers:
                raise ValueError(
                    f"message {m.number} of {where}: message {m.number} is given twice"
                )
            if (m.byte, m.bit) in bits:
                other = bits[m.byte, m.bit]
                raise ValueError(
                    f"message {m.number} of {where}: {where} shows message {other} already"
                )
            problem = message_problem(m.text)
            if problem is not None:
                raise ValueError(f"message {m.number} of {where}: {problem}")
            numbers.add(m.number)
            bits[m.byte, m.bit] = m.number
            out.append(m)
        self._external_messages = tuple(sorted(out, key=lambda m: m.number))

    def operator_messages(self, *, path: int = 1) -> tuple[OperatorMessage, ...]:
        """The messages shown for ``path``: the external ones whose A bit is 1, by number,
        then the program's ``#3006`` message while its stop lasts."""
        p = self._paths.at(path)
        if p.live:
            p.sync()
        shown = []
        if self._external_messages:
            size = max(m.byte for m in self._external_messages) + 1
            try:
                area = self.read_pmc("A", 0, size)
            except MachineError as exc:  # pragma: no cover - checked when defined
                raise MachineError(EW.NOOPT, str(exc)) from None
            shown = [
                OperatorMessage(m.number, m.text, True)
                for m in self._external_messages
                if area[m.byte] >> m.bit & 1
            ]
        message = p.engine.interpreter.message
        if message is not None:
            shown.append(OperatorMessage(message[0], message[1], False))
        return tuple(shown)
