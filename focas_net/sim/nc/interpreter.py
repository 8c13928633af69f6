"""The interpreter: one block at a time, from the program store to timed actions.

:meth:`Interpreter.step` executes the block at the program pointer and answers the actions
it asks of the machine (motion, dwell, an M/T function's wait, a stop, the program's end);
macro statements and modal changes take no time. It never raises anything but
:class:`~focas_net.sim.nc.alarms.AlarmRaised` (turned into an alarm by the engine). What the
parameters say is :mod:`.settings`; the actions it answers are :mod:`.actions`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Final

from .actions import Dwell, ProgramEnd, Step, Stop, Sync, Wait
from .alarms import AlarmKind, AlarmRaised, number_text, word_text
from .lathe import CSS, FEED_PER_REVOLUTION, spindle_speed
from .macro import Expr, NcVariables, Value, VariableRefused, evaluate, round_fanuc, variable_number
from .motion import ArcMove, LinearMove, RapidMove, Vector
from .program import Assign, Bad, End, Goto, IfGoto, IfThen, Program, While, Words
from .program import ProgramStore as _Store
from .settings import G_CODE_GROUPS, INCH, NcSettings

__all__ = ["Interpreter"]

_ADDRESSES_OTHER: Final = frozenset("FGHDILJKMPRST")
#: The letters FANUC's parameter 1020 may name an axis by (the others are no axis).
_AXIS_LETTERS: Final = frozenset("ABCEUVWXYZ")
#: What a dwell's alarms ask for.
_OWN_BLOCK: Final = "(program the move in a block of its own)"
#: the digits of an M, S and T code FANUC's controls allow by default (parameters 3030,
#: 3031 and 3032 set to 0); more is PS0003
CODE_DIGITS: Final = {"M": 8, "S": 5, "T": 8}
#: the largest axis word in least input increments: 9 digits, as a number may have
AXIS_WORD_MAX: Final = 999_999_999
_AXIS_WORD_RULE: Final = "an axis word has at most 9 digits (999999.999 mm, 99999.9999 inch)"
_LOCALS: Final = range(1, 34)
_COMMONS: Final = range(100, 200)
_PLANES: Final = {170: ("X", "Y", "I", "J"), 180: ("Z", "X", "K", "I"), 190: ("Y", "Z", "J", "K")}
_CENTER: Final = {"X": "I", "Y": "J", "Z": "K"}
#: The codes of the M series a lathe reads otherwise (FANUC's T series, G code system A)
#: and does not model: what each is there (PS0010 rather than a milling meaning).
_LATHE_CODES: Final = {
    900: "on a lathe the outer and inner diameter cutting cycle (not modelled)",
    910: "no code of a lathe's G code system A (U and W move incrementally)",
    940: "on a lathe the end face turning cycle (not modelled)",
}
#: The codes only a lathe's path models.
_MILL_CODES: Final = {CSS: "constant surface speed is modelled on a lathe's path only"}
#: G50 on a lathe: coordinate system setting and the spindle speed limit (one-shot).
_LATHE_G50: Final = 500
#: A lathe's incremental addresses (FANUC's G code system A, the T series' default): U moves X
#: by its value, W moves Z.
_STEP_WORDS: Final = {"U": "X", "W": "Z"}


@dataclass(slots=True)
class _Frame:
    program: Program
    index: int
    repeats: int = 1  #: runs left of this subprogram, this one included


class Interpreter:
    """Program pointer, modal state and variables of one control."""

    def __init__(
        self,
        settings: NcSettings,
        store: _Store,
        variables: NcVariables,
        work_offsets: list[list[float]],
        tool_offsets: Mapping[int, float],
    ) -> None:
        self.settings = settings
        self.store = store
        self.variables = variables
        #: [0] external offset, [1..6] G54..G59, each a list per axis (shared with the engine).
        self.work_offsets = work_offsets
        self.tool_offsets = tool_offsets
        n = len(settings.axes)
        self.axis_index = {name: i for i, name in enumerate(settings.axes)}
        self.length_axis = self.axis_index.get("Z", n - 1)
        self.position: list[float] = [0.0] * n  #: machine coordinates at the end of the block
        #: A lathe's G50 X/Z: the shift of the work coordinate system it set, per axis.
        self.shift: list[float] = [0.0] * n
        self.modal: dict[int, int] = settings.power_on_modal()
        self.feed = 0.0
        self.spindle_command = 0.0
        #: A lathe's ``G50 S``: the highest spindle speed, min^-1 (None: not given).
        self.spindle_limit: float | None = None
        self.spindle_override = 100.0  #: percent (the engine's, read by G96 and G99)
        self.spindle = 5  #: 3, 4 or 5 (M3/M4/M5)
        self.coolant = False
        self.tool = 0
        self.next_tool = 0
        self.h_number = 0
        self.tool_length = 0.0
        self.last_m = 0
        self.optional_stop = False
        self.block_delete = False
        self.locals: dict[int, float | None] = {}
        self.commons: dict[int, float | None] = {}
        self.frames: list[_Frame] = []
        self.sequence: int | None = None
        self.block: int | None = None  #: index of the block being executed
        self._hold: dict[int, float] = {}  #: axes kept at a work position this block
        self._steps: dict[int, float] = {}  #: a lathe's U and W this block: axis -> mm
        #: The executing NC block: its addresses but G with their values, its G codes (x10).
        self.block_words: dict[str, float] = {}
        self.block_codes: frozenset[int] = frozenset()
        #: The last value of each address but G, kept from block to block (modal D, E, B...).
        self.last_words: dict[str, float] = {}
        self.one_shot: int | None = None  #: the one-shot G code (x10) of the executing block
        self.blocks_run = 0  #: blocks executed since power-on (the block counter)
        #: ``#3006``'s stop with a message: (the number assigned, the message), until the
        #: next cycle start or reset.
        self.message: tuple[int, str] | None = None
        self._message_stop = False

    # --- program pointer ------------------------------------------------------------------

    @property
    def program(self) -> Program | None:
        return self.frames[-1].program if self.frames else None

    def programs_in_use(self) -> frozenset[int]:
        return frozenset(f.program.number for f in self.frames)

    def rewind(self, main: Program | None) -> None:
        """Back to the head of ``main``, subprogram calls forgotten; without ``main`` (a
        reset, a program's end) the locals and the commons #100-#199 vacant as well
        (parameter 6001 CLV/CCV = 0), where :class:`NcVariables` holds them too. A cycle
        start (with ``main``) keeps them: a value written between reset and cycle start is
        the one the program reads, as on a control."""
        self.frames = [_Frame(main, 0)] if main is not None else []
        self.block = None
        if main is not None:
            return
        self.locals.clear()
        self.commons.clear()
        for number in (*_LOCALS, *_COMMONS):
            try:
                if self.variables.read_variable(number) is not None:
                    self.variables.write_variable(number, None)
            except VariableRefused:
                continue  # a machine without that variable: the interpreter's own store

    def _own(self, number: int) -> dict[int, float | None] | None:
        """The interpreter's own store of a local or a common #100-#199, used where the
        variables (:class:`NcVariables`) lack the number; None for any other number."""
        if 1 <= number <= 33:
            return self.locals
        if 100 <= number <= 199:
            return self.commons
        return None

    # --- coordinates ----------------------------------------------------------------------

    def offset(self, axis: int) -> float:
        """Machine coordinate of the work zero on ``axis`` (work + external + tool length)."""
        total = self.work_offsets[0][axis] + self.work_offsets[self.modal[14] // 10 - 53][axis]
        total += self.shift[axis]
        return total + (self.tool_length if axis == self.length_axis else 0.0)

    def spindle_speed(self, work: Sequence[float]) -> float:
        """The spindle's min^-1 with the tool at ``work`` (work coordinates): see :mod:`.lathe`."""
        x = self.axis_index.get("X")
        return spindle_speed(self, None if x is None else work[x], self.settings.max_spindle_speed)

    def work_position(self) -> list[float]:
        return [p - self.offset(i) for i, p in enumerate(self.position)]

    # --- variables ------------------------------------------------------------------------

    def read(self, number: int) -> Value:
        if number == 0:
            return None
        own = self._own(number)
        if own is not None:  # the machine's, read by cnc_rdmacro, where it has the number
            try:
                return self.variables.read_variable(number)
            except VariableRefused as e:
                if e.alarm != 115:
                    raise AlarmRaised(e.alarm, str(e) or f"#{number}") from None
                return own.get(number)
        n = len(self.settings.axes)
        if 4001 <= number <= 4030:
            group = self.modal.get(number - 4000)
            return None if group is None else group / 10
        special = {
            4107: 0.0, 4109: self.feed, 4111: float(self.h_number), 4113: float(self.last_m),
            4114: float(self.sequence or 0),
            4115: float(self.program.number) if self.program else 0.0,
            4119: self.spindle_command, 4120: float(self.next_tool),
        }  # fmt: skip
        if number in special:
            return special[number]
        for base, values in (
            (5001, self.work_position()),
            (5021, self.position),
            (5041, self.work_position()),
        ):
            if base <= number < base + n:
                return values[number - base]
        offset = self._offset_variable(number)
        if offset is not None:
            return self.work_offsets[offset[0]][offset[1]]
        try:
            return self.variables.read_variable(number)
        except VariableRefused as e:
            raise AlarmRaised(e.alarm, str(e) or f"#{number}") from None

    def _offset_variable(self, number: int) -> tuple[int, int] | None:
        """#5201+: external offset; #5221+, #5241+ ... #5321+: G54..G59, 20 apart."""
        if 5201 <= number <= 5340:
            table, axis = divmod(number - 5201, 20)
            if axis < len(self.settings.axes):
                return table, axis
        return None

    def write(self, number: int, value: Value, comment: str) -> None:
        own = self._own(number)
        if own is not None:
            try:
                self.variables.write_variable(number, value)
            except VariableRefused as e:
                if e.alarm != 115:
                    raise AlarmRaised(e.alarm, str(e) or f"#{number}") from None
                own[number] = value
        elif number == 3000:
            n = 0 if value is None else round_fanuc(value)
            if not 0 <= n <= 200:
                raise AlarmRaised(119, f"#3000 = {n} is outside 0..200")
            raise AlarmRaised(3000 + n, comment, AlarmKind.MC)
        elif number == 3006:
            n = 0 if value is None else round_fanuc(value)
            if not 0 <= n <= 99999999:
                raise AlarmRaised(119, f"#3006 = {n} is outside 0..99999999")
            self.message = (n, comment)
            self._message_stop = True
        elif number == 0 or 4000 <= number <= 5200:
            raise AlarmRaised(116, f"#{number}")
        elif (offset := self._offset_variable(number)) is not None:
            self.work_offsets[offset[0]][offset[1]] = 0.0 if value is None else value
        else:
            try:
                self.variables.write_variable(number, value)
            except VariableRefused as e:
                raise AlarmRaised(e.alarm, str(e) or f"#{number}") from None

    # --- execution ------------------------------------------------------------------------

    def step(self) -> Step:
        """Execute the block at the pointer (the program's end when past the last one)."""
        frame = self.frames[-1]
        program = frame.program
        if frame.index >= len(program.blocks):
            self.block = None
            if len(self.frames) == 1:
                return Step([ProgramEnd(None)], True)
            self._return(None)
            return Step()
        index = frame.index
        block = program.blocks[index]
        frame.index += 1
        if block.deletable and self.block_delete:
            return Step()
        self.block = index
        self.blocks_run += 1
        if block.sequence is not None:
            self.sequence = block.sequence
        st = block.statement
        if isinstance(st, Bad):
            raise AlarmRaised(st.alarm, st.detail)
        if isinstance(st, Words):
            return self._words(st, block.comment)
        if index in program.loop_errors:
            number, detail = program.loop_errors[index]
            raise AlarmRaised(number, detail)
        if isinstance(st, Assign):
            self._assign(st, block.comment)
        elif isinstance(st, IfThen):
            if self._true(st.condition):
                self._assign(st.then, block.comment)
        elif isinstance(st, Goto | IfGoto):
            if isinstance(st, Goto) or self._true(st.condition):
                self._goto(frame, evaluate(st.target, self.read))
        elif isinstance(st, While):
            if st.condition is not None and not self._true(st.condition):
                frame.index = program.loops[index] + 1
        elif isinstance(st, End):
            frame.index = program.loops[index]
        if self._message_stop:  # #3006: the program stops with its message
            self._message_stop = False
            return Step([Stop(3006)])
        return Step()

    def _true(self, condition: Expr) -> bool:
        value = evaluate(condition, self.read)
        return value is not None and value != 0

    def _assign(self, st: Assign, comment: str) -> None:
        number = variable_number(evaluate(st.target.index, self.read))
        self.write(number, evaluate(st.value, self.read), comment)

    def _goto(self, frame: _Frame, target: Value) -> None:
        n = 0 if target is None else round_fanuc(target)
        if not 1 <= n <= 99999:
            given = "a vacant variable" if target is None else n
            raise AlarmRaised(128, f"GOTO {given}: a sequence number is 1..99999")
        index = frame.program.sequences.get(n)
        if index is None:
            raise AlarmRaised(128, f"GOTO {n}: no block N{n} in O{frame.program.number:04d}")
        frame.index = index

    def _return(self, sequence: int | None) -> None:
        frame = self.frames[-1]
        if frame.repeats > 1:
            frame.repeats -= 1
            frame.index = 0
            return
        self.frames.pop()
        if sequence is not None:
            caller = self.frames[-1]
            index = caller.program.sequences.get(sequence)
            if index is None:
                raise AlarmRaised(78, f"M99 P{sequence}: no N{sequence} in the calling program")
            caller.index = index

    def _words(self, st: Words, comment: str) -> Step:
        s = self.settings
        values: list[tuple[str, float, bool]] = []
        steps = self._step_words()
        # no axis nor another address: raised once the G codes are known good (PS0010 first)
        foreign: list[str] = []
        for word in st.words:
            if word.address not in self.axis_index and word.address not in _ADDRESSES_OTHER:
                foreign.append(word.address)
                if not (word.address in steps or (word.address == "U" and s.lathe)):
                    continue  # a lathe's U and W, and its G4 U: seen below
            value = evaluate(word.value, self.read)
            if value is not None:
                values.append((word.address, value, word.integer_literal))
        modal = dict(self.modal)
        one_shot: int | None = None
        self.one_shot = None
        self.block_words = {a: v for a, v, _ in values if a != "G"}
        last_s = self.last_words.get("S")  # a lathe's G50 S is no commanded S
        self.last_words.update(self.block_words)
        self.block_codes = frozenset(round_fanuc(v * 10) for a, v, _ in values if a == "G")
        for address, value, _ in values:
            if address == "G":
                code = round_fanuc(value * 10)
                group = G_CODE_GROUPS.get(code)
                if group is None or abs(code - value * 10) > 1e-6:
                    raise AlarmRaised(10, f"G{number_text(value)}")
                refused = (_LATHE_CODES if s.lathe else _MILL_CODES).get(code)
                if refused is not None:
                    raise AlarmRaised(10, f"G{number_text(value)}: {refused}")
                if group == 0 or (s.lathe and code == _LATHE_G50):
                    self.one_shot = one_shot = code
                else:
                    modal[group] = code
        dwell_u = s.lathe and one_shot == 40
        unread = next((a for a in foreign if a not in steps and not (a == "U" and dwell_u)), None)
        if unread is not None:
            if unread in _AXIS_LETTERS:
                raise AlarmRaised(9, f"address {unread} (axes are {''.join(s.axes)})")
            raise AlarmRaised(9, f"address {unread}: the interpreter reads no {unread}")
        inch = modal[6] == 200
        scale = INCH if inch else 1.0
        increment = s.increment_inch if inch else s.increment_mm
        axes: dict[int, float] = {}
        moves: dict[int, float] = {}
        other: dict[str, tuple[float, bool]] = {}
        m_codes: list[int] = []
        for address, value, literal in values:
            index = self.axis_index.get(address, steps.get(address))
            if index is not None and not (address == "U" and dwell_u):
                if abs(value if literal else value / increment) > AXIS_WORD_MAX + 0.5:
                    raise AlarmRaised(3, f"{address}{number_text(value)}: {_AXIS_WORD_RULE}")
                mm = (value * increment if literal else value) * scale
                (moves if address in steps else axes)[index] = mm
                other.setdefault(address, (value, literal))  # X of a dwell
            elif address == "M":
                m_codes.append(self._code(address, value))
            elif address != "G":
                other[address] = (value, literal)
        for index in moves:
            if index in axes:
                name = s.axes[index]
                by = next(w for w, a in _STEP_WORDS.items() if a == name)
                words = f"{word_text(name, *other[name])} {word_text(by, *other[by])}"
                raise AlarmRaised(
                    5074, f"{words}: {name} given twice in one block ({by} moves {name})"
                )
            axes[index] = moves[index]
        if "F" in other:
            feed = other["F"][0]
            if feed < 0:
                raise AlarmRaised(6, f"F{number_text(feed)}")
            per_revolution = s.lathe and modal[10] == FEED_PER_REVOLUTION
            self.feed = feed * scale if per_revolution else min(feed * scale, s.max_cutting_feed)
        if "S" in other:
            speed = float(self._code("S", other["S"][0]))
            if s.lathe and one_shot == _LATHE_G50:
                self.spindle_limit = speed
                self.last_words.pop("S")
                if last_s is not None:
                    self.last_words["S"] = last_s
            else:
                self.spindle_command = speed
        if "T" in other:
            self.next_tool = self._code("T", other["T"][0])
        length_changed = False
        work = self.work_position()
        if "H" in other or modal[8] != self.modal[8]:
            h = self._integer("H", other["H"][0]) if "H" in other else self.h_number
            if h > s.max_offset_number:
                raise AlarmRaised(30, f"H{h} (1..{s.max_offset_number})")
            self.h_number = h
            sign = {430: 1.0, 440: -1.0}.get(modal[8], 0.0)
            new_length = sign * self.tool_offsets.get(h, 0.0)
            length_changed = new_length != self.tool_length
            self.tool_length = new_length
        self.modal = modal
        self._hold = {}
        self._steps = moves
        if length_changed and self.length_axis not in axes and one_shot is None:
            # the compensation moves the axis; the program position stays
            self._hold[self.length_axis] = work[self.length_axis]
        step = Step(nc_block=True)
        waits = [m for m in m_codes if self._waiting(m)]
        sync = self._sync(waits[0], other.get("P")) if waits else None
        for m in m_codes:
            if m in (0, 1, 2, 30, 98, 99) or m in waits:
                continue
            self.last_m = m
            if m in (3, 4, 5):
                self.spindle = m
            elif m in (8, 9):
                self.coolant = m == 8
            if m == 6:
                self.tool = self.next_tool
                step.actions.append(Wait(s.tool_change_time, f"M6 T{self.tool}"))
            else:
                step.actions.append(Wait(s.m_function_time, f"M{m}"))
        self._motion(step, one_shot, axes, other)
        if sync is not None:  # the path waits once its block's motion is done
            self.last_m = sync.code
            step.actions.append(sync)
        for m in m_codes:
            if m in (0, 1, 2, 30, 98, 99):
                self.last_m = m
            if m == 0 or (m == 1 and self.optional_stop):
                step.actions.append(Stop(m))
            elif m in (2, 30):
                step.actions.append(ProgramEnd(m))
            elif m == 98:
                self._call(other)
            elif m == 99:
                p = other.get("P")
                sequence = self._integer("P", p[0]) if p else None
                if len(self.frames) > 1:
                    self._return(sequence)
                else:
                    frame = self.frames[0]
                    index = 0 if sequence is None else frame.program.sequences.get(sequence)
                    if index is None:
                        raise AlarmRaised(78, f"M99 P{sequence}: no N{sequence}")
                    frame.index = index
        return step

    def _step_words(self) -> dict[str, int]:
        """A lathe's U and W (:data:`_STEP_WORDS`): each with the index of the axis it moves,
        where the path has that axis and no axis named by the word itself."""
        if not self.settings.lathe:
            return {}
        ix = self.axis_index
        return {w: ix[a] for w, a in _STEP_WORDS.items() if a in ix and w not in ix}

    def _waiting(self, m: int) -> bool:
        codes = self.settings.waiting_m
        return codes is not None and codes[0] <= m <= codes[1]

    def _sync(self, m: int, p: tuple[float, bool] | None) -> Sync:
        """The wait of waiting M code ``m``: every path, or those P names by their digits
        (P12: paths 1 and 2; the digit 0 names path 10). PS0161 for a P that names a path
        the control has not, a path twice, not this path, or this path alone."""
        s = self.settings
        if p is None:
            return Sync(m, frozenset(range(1, s.path_count + 1)))
        value = p[0]
        if value < 0 or value != math.floor(value):
            raise AlarmRaised(161, f"M{m} P{number_text(value)}")
        digits = str(int(value))
        paths = [10 if d == "0" else int(d) for d in digits]
        named = frozenset(paths)
        if (
            len(named) != len(paths)
            or any(n > s.path_count for n in paths)
            or s.path_number not in named
            or len(named) < 2
        ):
            raise AlarmRaised(
                161,
                f"M{m} P{digits}: P names two or more paths of 1..{s.path_count} by their "
                f"digits, path {s.path_number} among them",
            )
        return Sync(m, named)

    @staticmethod
    def _integer(address: str, value: float) -> int:
        if value < 0:
            raise AlarmRaised(6, f"{address}{number_text(value)}")
        if value != math.floor(value):
            raise AlarmRaised(7, f"{address}{number_text(value)}")
        return int(value)

    @classmethod
    def _code(cls, address: str, value: float) -> int:
        """An M, S or T code: a whole number of at most FANUC's default digits (parameters
        3030, 3031 and 3032 left 0: 8 for M and T, 5 for S), else PS0003."""
        code = cls._integer(address, value)
        digits = CODE_DIGITS[address]
        if code >= 10**digits:
            article = "a" if address == "T" else "an"
            what = f"{article} {address} code has 1..{digits} digits"
            raise AlarmRaised(3, f"{address}{code}: {what}")
        return code

    def _call(self, other: Mapping[str, tuple[float, bool]]) -> None:
        if "P" not in other:
            raise AlarmRaised(76, "M98 without P")
        p = self._integer("P", other["P"][0])
        repeats = self._integer("L", other["L"][0]) if "L" in other else 1
        for address, value, digits in (("P", p, 8), ("L", repeats, 4)):
            if value >= 10**digits:  # P: 4 digits of repeats and 4 of the program number
                raise AlarmRaised(3, f"M98 {address}{value}: {address} has at most {digits} digits")
        written = p
        if "L" not in other and p > 9999:
            repeats, p = divmod(p, 10000)
        if repeats == 0:
            return
        program = self.store.find(p)
        if program is None:
            times = f" ({repeats} {'time' if repeats == 1 else 'times'})" if written != p else ""
            raise AlarmRaised(78, f"M98 P{written}: no program O{p:04d}{times}")
        if len(self.frames) > self.settings.max_subprogram_nesting:
            raise AlarmRaised(77, f"more than {self.settings.max_subprogram_nesting} levels")
        self.frames.append(_Frame(program, 0, repeats))

    def _dwell_seconds(self, other: Mapping[str, tuple[float, bool]]) -> float:
        """A dwell's time, ``G4 P`` (ms) or ``G4 X`` (s, or increments without a point), on a
        lathe (T series) ``G4 U`` as X, in a block of its own: another axis word raises
        PS0009, two of the time's words PS5074 (no move dropped)."""
        steps = self._step_words()
        moved = next(
            (a for a in other if (a in self.axis_index or a in steps) and a not in "XU"), None
        )
        if moved is not None:
            word = word_text(moved, *other[moved])
            raise AlarmRaised(9, f"G4 with {word}: a dwell moves no axis {_OWN_BLOCK}")
        times = "XUP" if self.settings.lathe else "XP"
        given = [a for a in times if a in other]
        if len(given) > 1:
            words = " ".join(word_text(a, *other[a]) for a in given)
            takes = " or ".join(", ".join(times).rsplit(", ", 1))
            raise AlarmRaised(5074, f"G4 {words}: a dwell takes its time in {takes} {_OWN_BLOCK}")
        if not given:
            return 0.0
        address = given[0]
        value, literal = other[address]
        if address == "P":
            return self._integer("P", value) / 1000.0
        if value < 0:
            raise AlarmRaised(6, f"G4 {word_text(address, value, literal)}")
        return value * self.settings.increment_mm if literal else value

    def _targets(self, axes: Mapping[int, float], incremental: bool) -> list[float]:
        target = list(self.position)
        for i, value in axes.items():
            target[i] = self.position[i] + value if incremental else value + self.offset(i)
        for i, value in self._hold.items():
            target[i] = value + self.offset(i)
        for i, value in self._steps.items():  # a lathe's U and W: from where the axis is
            target[i] = self.position[i] + value
        return target

    def _motion(
        self,
        step: Step,
        one_shot: int | None,
        axes: dict[int, float],
        other: Mapping[str, tuple[float, bool]],
    ) -> None:
        s = self.settings
        incremental = self.modal[3] == 910
        start = tuple(self.position)
        if one_shot == 40:
            step.actions.append(Dwell(self._dwell_seconds(other)))
            return
        if one_shot == 280:
            middle = self._targets(axes, incremental)
            home = list(middle)
            for i in axes:
                home[i] = s.reference[i]
            self._rapid(step, start, tuple(middle))
            self._rapid(step, tuple(middle), tuple(home))
            return
        if one_shot == _LATHE_G50:  # a lathe's coordinate system setting: no motion
            work = self.work_position()
            for i, value in axes.items():
                given = work[i] + value if i in self._steps else value
                self.shift[i] += work[i] - given
            return
        if one_shot == 530:
            target = list(self.position)
            for i, value in axes.items():
                target[i] = value
            self._rapid(step, start, tuple(target))
            return
        group1 = self.modal[1]
        circle = group1 in (20, 30) and any(w in other for w in _CENTER.values())
        if not axes and not self._hold and not circle:  # G2 I5.: a full circle
            return
        if group1 == 0:
            self._rapid(step, start, tuple(self._targets(axes, incremental)))
            return
        feed = self._cutting_feed()
        if group1 == 10:
            end = tuple(self._targets(axes, incremental))
            if end != start:
                step.actions.append(LinearMove.plan(start, end, feed))
            self.position = list(end)
            return
        self._arc(step, start, axes, other, incremental, feed, clockwise=group1 == 20)

    def _cutting_feed(self) -> float:
        """mm/min of a cutting move: F, on a lathe in G99 F times the spindle speed where the
        block starts (PS0011 with the spindle stopped, whose feed would be 0)."""
        if self.feed <= 0:
            raise AlarmRaised(11, "no feed rate (F) for cutting feed")
        if not (self.settings.lathe and self.modal[10] == FEED_PER_REVOLUTION):
            return self.feed
        speed = self.spindle_speed(self.work_position())
        if speed <= 0:
            raise AlarmRaised(
                11,
                f"G99 F{number_text(self.feed)}: feed per revolution with the spindle stopped "
                "(start it with M3 or M4 and S, or feed per minute with G98)",
            )
        return min(self.feed * speed, self.settings.max_cutting_feed)

    def _rapid(self, step: Step, start: Vector, end: Vector) -> None:
        if end != start:
            step.actions.append(RapidMove.plan(start, end, self.settings.rapid_rates))
        self.position = list(end)

    def _arc(
        self,
        step: Step,
        start: Vector,
        axes: Mapping[int, float],
        other: Mapping[str, tuple[float, bool]],
        incremental: bool,
        feed: float,
        *,
        clockwise: bool,
    ) -> None:
        s = self.settings
        plane = _PLANES[self.modal[2]]
        a_name, b_name, ca_word, cb_word = plane
        if a_name not in self.axis_index or b_name not in self.axis_index:
            raise AlarmRaised(21, f"plane G{self.modal[2] // 10} needs axes {a_name}{b_name}")
        a, b = self.axis_index[a_name], self.axis_index[b_name]
        for word in _CENTER.values():
            if word in other and word not in (ca_word, cb_word):
                raise AlarmRaised(21, f"{word} is not a center word of G{self.modal[2] // 10}")
        end = tuple(self._targets(axes, incremental))
        inch = self.modal[6] == 200
        scale = INCH if inch else 1.0
        increment = s.increment_inch if inch else s.increment_mm

        def length(word: str) -> float:
            value, literal = other[word]
            return (value * increment if literal else value) * scale

        sa, sb, ea, eb = start[a], start[b], end[a], end[b]
        if "R" in other:
            r = length("R")
            chord = math.hypot(ea - sa, eb - sb)
            if chord == 0:
                self.position = list(end)  # an arc of 0 degrees: no motion
                return
            if r == 0 or abs(r) * 2 < chord - 1e-9:
                raise AlarmRaised(
                    20,
                    f"R{number_text(abs(r))} is less than half of the chord {number_text(chord)}",
                )
            h = math.sqrt(max(r * r - chord * chord / 4, 0.0))
            ux, uy = (ea - sa) / chord, (eb - sb) / chord
            left = (r > 0) != clockwise  # small arc counter-clockwise: center to the left
            sign = 1.0 if left else -1.0
            center = ((sa + ea) / 2 - sign * h * uy, (sb + eb) / 2 + sign * h * ux)
        elif ca_word in other or cb_word in other:
            ci = length(ca_word) if ca_word in other else 0.0
            cj = length(cb_word) if cb_word in other else 0.0
            center = (sa + ci, sb + cj)
        else:
            raise AlarmRaised(22, f"G{2 if clockwise else 3} without R or {ca_word}/{cb_word}")
        r0 = math.hypot(sa - center[0], sb - center[1])
        r1 = math.hypot(ea - center[0], eb - center[1])
        if abs(r1 - r0) > s.arc_tolerance:
            raise AlarmRaised(20, f"start radius {r0:.4f} and end radius {r1:.4f} differ")
        t0 = math.atan2(sb - center[1], sa - center[0])
        t1 = math.atan2(eb - center[1], ea - center[0])
        full = math.tau
        if clockwise:
            sweep = -((t0 - t1) % full)
            if "R" not in other and abs(sweep) < 1e-9:
                sweep = -full
        else:
            sweep = (t1 - t0) % full
            if "R" not in other and abs(sweep) < 1e-9:
                sweep = full
        arc_length = abs(sweep) * (r0 + r1) / 2
        linear = math.sqrt(
            sum(
                (e - st) ** 2
                for i, (st, e) in enumerate(zip(start, end, strict=True))
                if i not in (a, b)
            )
        )
        path = arc_length if arc_length > 0 else linear
        duration = path / feed * 60.0
        if path > 0:
            step.actions.append(
                ArcMove(start, end, feed, duration, a, b, center, t0, sweep, r0, r1)
            )
        self.position = list(end)
