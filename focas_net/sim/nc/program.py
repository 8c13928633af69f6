"""Part programs: FANUC program text parsed into blocks, and the program store.

A program is ``O`` and its number (``:`` is accepted for ``O``), an optional name in
parentheses, then blocks, each ended by a new line or ``;`` (EOB). ``%`` lines are tape marks:
text before the first and after the second is ignored. In a block: spaces are ignored, text
in parentheses is a comment, a leading ``/`` marks the block for block delete, ``N`` and
digits is the sequence number. Letters outside comments are read in upper case.

Block content is parsed when the program is stored, but a malformed block is kept with its
alarm and raises it only when executed, as on a CNC.
"""

from __future__ import annotations

import functools
import re
from collections.abc import Callable, Collection
from dataclasses import dataclass, field
from typing import Final

from .alarms import AlarmRaised, ProgramError, ProgramErrorReason, number_text
from .macro import Cursor, Expr, Neg, Num, Var, bracketed, parse_expression, parse_number, variable

__all__ = [
    "Block",
    "Program",
    "ProgramInfo",
    "ProgramStore",
    "Word",
    "no_program",
    "parse_program",
]

#: Characters of a program's name in the directory: FANUC's ``cnc_rdprogdir3`` has 64 bytes
#: for the comment, its parentheses and a NUL; a longer O-line comment is cut there, as a
#: control's directory shows it.
DIRECTORY_NAME: Final = 61
#: Digits of a sequence number (N1..N99999, FANUC's five; more raise PS0003).
SEQUENCE_DIGITS: Final = 5
#: Word addresses a block may carry (O and N are handled apart).
ADDRESSES: Final = frozenset("ABCDEFGHIJKLMPQRSTUVWXYZ")
#: The digits, signs and point of a word's value as written.
_DIGITS: Final = re.compile(r"[-+]*[\d.]*")
#: The characters of a word an alarm's detail shows (a longer one is cut, with "...").
_SHOWN: Final = 23
#: The addresses whose number FANUC reads as a whole number, never with a decimal point
#: (``T1.``, ``M98 P1.`` raise PS0007, ILLEGAL USE OF DECIMAL POINT), and what each holds.
#: G takes one (G43.4); the axes, F, I, J, K, Q, R take one as a length, feed or time.
WHOLE_NUMBER_ADDRESSES: Final = {
    "D": "an offset number",
    "H": "an offset number",
    "L": "a repetition count",
    "M": "an M code",
    "P": "a program, sequence, path or time number",
    "S": "an S code",
    "T": "a T code",
}


@dataclass(frozen=True, slots=True)
class Word:
    """One address and its value; ``integer_literal`` is true for a literal number written
    without a decimal point (FANUC reads those in least input increments on axis words)."""

    address: str
    value: Expr
    integer_literal: bool


@dataclass(frozen=True, slots=True)
class Assign:
    target: Var
    value: Expr


@dataclass(frozen=True, slots=True)
class Goto:
    target: Expr


@dataclass(frozen=True, slots=True)
class IfGoto:
    condition: Expr
    target: Expr


@dataclass(frozen=True, slots=True)
class IfThen:
    condition: Expr
    then: Assign


@dataclass(frozen=True, slots=True)
class While:
    condition: Expr | None  #: ``None`` for a bare ``DO m`` (an endless loop)
    loop: int


@dataclass(frozen=True, slots=True)
class End:
    loop: int


@dataclass(frozen=True, slots=True)
class Words:
    words: tuple[Word, ...]


@dataclass(frozen=True, slots=True)
class Bad:
    """A block that could not be parsed: its alarm number and what was wrong."""

    alarm: int
    detail: str


Statement = Assign | Goto | IfGoto | IfThen | While | End | Words | Bad


@dataclass(frozen=True, slots=True)
class Block:
    """One block: its line in the program text (1-based), the sequence number written in it,
    whether it carries the block delete mark, its comment (the text of its first parenthesis,
    the message of ``#3000``), its statement and its text as written."""

    line: int
    sequence: int | None
    deletable: bool
    comment: str
    statement: Statement
    text: str

    @property
    def is_macro(self) -> bool:
        """Whether this is a macro statement rather than an NC block."""
        return not isinstance(self.statement, Words | Bad)


@dataclass(frozen=True, slots=True)
class Program:
    """A parsed program: number, name (the comment of the O line), the text as stored, the
    blocks, and the indices the interpreter jumps by."""

    number: int
    name: str
    text: str
    blocks: tuple[Block, ...]
    #: First block index of each sequence number.
    sequences: dict[int, int] = field(default_factory=dict)
    #: For each WHILE/DO block index its END index, and the reverse; ``-1`` when unmatched.
    loops: dict[int, int] = field(default_factory=dict)
    #: Block index -> alarm for DO/END blocks that do not pair (PS0124/PS0126).
    loop_errors: dict[int, tuple[int, str]] = field(default_factory=dict)

    @property
    def size(self) -> int:
        """Characters stored (the text with one EOB per line)."""
        return len(self.text)


@dataclass(frozen=True, slots=True)
class ProgramInfo:
    """One program directory entry."""

    number: int
    name: str
    size: int


def _strip_comments(line: str) -> tuple[str, str]:
    """Split a block into its code (spaces removed, upper case) and its first comment, whose
    tabs are disregarded as FANUC's ISO code disregards HT (``(A<tab>B)`` is ``AB``)."""
    code: list[str] = []
    comment: str | None = None
    depth = 0
    current: list[str] = []
    for c in line:
        if depth:
            if c == ")":
                depth = 0
                if comment is None:
                    comment = "".join(current).strip()
                current = []
            elif c != "\t":
                current.append(c)
        elif c == "(":
            depth = 1
        elif not c.isspace():
            code.append(c.upper())
    if depth and comment is None:
        comment = "".join(current).strip()
    return "".join(code), comment or ""


def _code_end(line: str, count: int) -> int:
    """The index in ``line`` just after its ``count``-th character of code (outside comments,
    spaces not counted: :func:`_strip_comments`'s code), so that ``(12)O12 G0`` goes on after
    ``O12``, not after the comment's ``12``."""
    depth = 0
    seen = 0
    for i, c in enumerate(line):
        if seen == count:
            return i
        if depth:
            depth = 0 if c == ")" else 1
        elif c == "(":
            depth = 1
        elif not c.isspace():
            seen += 1
    return len(line)


#: A block that opens a program: its number after O (or ``:``, FANUC's other program address).
_PROGRAM_NUMBER: Final = re.compile(r"[O:]\d", re.IGNORECASE)


def _opens(line: str) -> bool:
    """Whether ``line`` opens a program with its number."""
    return bool(_PROGRAM_NUMBER.match(_strip_comments(line)[0].lstrip()))


def _tape(lines: list[str]) -> range:
    """The indexes of the lines that hold the program, as a tape reader takes them: after
    the leader (what precedes the opening ``%``) up to the closing ``%`` (``%`` O1234 ...
    M30 ``%``); a text that starts with its program number may end with the closing ``%``
    alone (O1234 ... M30 ``%``). The trailer after the closing ``%`` is not read, but a
    program there would be lost: :class:`ProgramError` (FORMAT) names its line, as it names
    a program number on a ``%`` line (``%O1``), whose rest is not read either."""
    marks = [i for i, ln in enumerate(lines) if ln.strip().startswith("%")]
    if not marks:
        return range(len(lines))
    for i in marks:  # a tape reader skips the rest of the % line: a program there is lost
        line = lines[i].strip()
        if _opens(line[1:]):
            raise ProgramError(
                ProgramErrorReason.FORMAT,
                f"line {i + 1}: {line[:40]!r}: the rest of a % line is not read, so its "
                "program number is lost: write % and the O line on lines of their own",
            )
    leader = [ln for ln in lines[: marks[0]] if ln.strip()]
    if leader and _opens(leader[0]):  # O1234 ... M30 %: the mark closes the program
        start, end = 0, marks[0]
    elif len(marks) == 1:  # (leader) % O1234 ... M30, with no closing mark
        return range(marks[0] + 1, len(lines))
    else:
        start, end = marks[0] + 1, marks[1]
    for i in range(end + 1, len(lines)):
        if _opens(lines[i]):
            raise ProgramError(
                ProgramErrorReason.FORMAT,
                f"line {i + 1}: {lines[i].strip()[:40]!r} starts a second program after the "
                f"closing % (line {end + 1}): one program per text",
            )
    return range(start, end)


def _split_blocks(text: str) -> list[tuple[int, str]]:
    """Lines of the program (:func:`_tape`), each split at ``;`` outside comments, with
    their line numbers in the text; a character other than printable ASCII and the tab, or
    a comment not closed in its line, is refused (:class:`ProgramError`, FORMAT), naming its
    line. The NULs that end a C string
    are not part of the text."""
    text = text.rstrip("\x00")
    lines = text.replace("\r\n", "\n").replace("\r", "\n").split("\n")
    blocks: list[tuple[int, str]] = []
    for i in _tape(lines):
        line = lines[i]
        bad = next((c for c in line if not (" " <= c <= "~" or c == "\t")), None)
        if bad is not None:
            raise ProgramError(
                ProgramErrorReason.FORMAT,
                f"line {i + 1}: character {bad!r} (U+{ord(bad):04X}) in {line.strip()[:40]!r}: "
                "a program is printable ASCII text",
            )
        depth = 0
        start = opened = 0
        for pos, c in enumerate(line):
            if c == "(" and not depth:
                depth, opened = 1, pos
            elif c == ")":
                depth = 0
            elif c == ";" and not depth:
                blocks.append((i + 1, line[start:pos]))
                start = pos + 1
        if depth:
            raise ProgramError(
                ProgramErrorReason.FORMAT,
                f"line {i + 1}: the comment {line[opened:].strip()[:40]!r} has no ')': a "
                "comment opened with ( is closed with ) in its line",
            )
        blocks.append((i + 1, line[start:]))
    return [(n, b) for n, b in blocks if b.strip()]


def parse_block(line: int, raw: str) -> Block:
    """One block of text (no EOB) as a :class:`Block`; never raises."""
    code, comment = _strip_comments(raw)
    cur = Cursor(code)
    deletable = cur.take("/")
    while cur.peek().isdigit():  # /1 .. /9: the switch number is not modelled
        cur.pos += 1
    sequence: int | None = None
    try:
        if cur.take("N"):
            value, point, digits = parse_number(cur)
            if point:
                raise AlarmRaised(7, f"N{value}")
            if digits > SEQUENCE_DIGITS:
                raise AlarmRaised(3, f"N{int(value)}: a sequence number has 1..5 digits")
            sequence = int(value)
        statement = _statement(cur)
    except AlarmRaised as e:
        statement = Bad(e.number, e.detail)
    return Block(line, sequence, deletable, comment, statement, raw.strip())


#: Custom macro B's external data output commands (not modelled).
_OUTPUT_COMMANDS: Final = ("POPEN", "BPRNT", "DPRNT", "PCLOS")


def _statement(cur: Cursor) -> Statement:
    if cur.at("#"):
        return _assignment(cur)
    for command in _OUTPUT_COMMANDS:  # read as addresses they told of a D or P with no value
        if cur.at(command):
            words = ", ".join(_OUTPUT_COMMANDS)
            raise AlarmRaised(114, f"{command}: external data output ({words}) is not modelled")
    if cur.take("GOTO"):
        target = parse_expression(cur)
        _end(cur)
        return Goto(target)
    if cur.take("IF"):
        condition = bracketed(cur)
        if cur.take("GOTO"):
            target = parse_expression(cur)
            _end(cur)
            return IfGoto(condition, target)
        if cur.take("THEN"):
            if not cur.at("#"):  # FANUC: THEN runs one macro statement, no NC words
                rest = repr(cur.text[cur.pos :]) if not cur.done() else "nothing"
                raise AlarmRaised(114, f"THEN takes one assignment (#i = ...), not {rest}")
            return IfThen(condition, _assignment(cur))
        raise AlarmRaised(114, f"IF without GOTO or THEN at {cur.text[cur.pos :]!r}")
    if cur.take("WHILE"):
        condition = bracketed(cur)
        cur.expect("DO")
        return While(condition, _loop_number(cur))
    if cur.take("DO"):
        return While(None, _loop_number(cur))
    if cur.take("END"):
        return End(_loop_number(cur))
    return Words(tuple(_words(cur)))


def _end(cur: Cursor) -> None:
    if not cur.done():
        raise AlarmRaised(114, f"unexpected {cur.text[cur.pos :]!r}")


def _assignment(cur: Cursor) -> Assign:
    target = variable(cur)
    cur.expect("=")
    value = parse_expression(cur)
    _end(cur)
    return Assign(target, value)


def _loop_number(cur: Cursor) -> int:
    if not cur.peek().isdigit():
        raise AlarmRaised(126, f"loop number missing at {cur.text[cur.pos :]!r}")
    value, point, _ = parse_number(cur)
    _end(cur)
    if point or not 1 <= value <= 3:
        raise AlarmRaised(126, f"loop number {number_text(value)} is not 1, 2 or 3")
    return int(value)


def _words(cur: Cursor) -> list[Word]:
    words: list[Word] = []
    written: dict[str, str] = {}  # each address but G: the word as written
    while not cur.done():
        c = cur.peek()
        if c == "#":
            raise AlarmRaised(127, f"an assignment after NC words at {cur.text[cur.pos :]!r}")
        if c == ".":
            raise AlarmRaised(7, f"a second decimal point at {cur.text[cur.pos :]!r}")
        if c.isdigit() or c in "+-":
            raise AlarmRaised(4, f"a value without an address at {cur.text[cur.pos :]!r}")
        if c not in ADDRESSES:
            raise AlarmRaised(9, _no_address(cur))
        start = cur.pos
        cur.pos += 1
        words.append(_word_value(cur, c))
        if c != "G":
            word = _shown(cur.text[start : cur.pos])
            if c in written:
                raise AlarmRaised(5074, f"{c} given twice in one block ({written[c]} and {word})")
            written[c] = word
    return words


def _no_address(cur: Cursor) -> str:
    """Why the character at ``cur`` starts no word: an N after the block's head, the
    ``,C``/``,R`` of chamfering and corner R (FANUC's option, not modelled), or no address."""
    c = cur.peek()
    head = cur.pos + (2 if c == "," else 1)
    digits = _DIGITS.match(cur.text, head)
    word = _shown(cur.text[cur.pos : digits.end() if digits else head])
    if c == "N":
        return f"{word}: a sequence number opens its block"
    if c == ",":
        return f"{word}: chamfering and corner R (,C and ,R) are not modelled"
    return f"{c!r} is no address (A..Z but N and O)"


def _shown(written: str) -> str:
    return written if len(written) <= _SHOWN else written[: _SHOWN - 3] + "..."


#: The signs and number of a word with more than one sign (``--1.``), as written.
_SIGNED: Final = re.compile(r"[-+]+[\d.]*")


def _word_value(cur: Cursor, address: str) -> Word:
    start = cur.pos
    negative = cur.take("-")
    if not negative:
        cur.take("+")
    c = cur.peek()
    value: Expr
    literal = False
    if c == "#":
        value = variable(cur)
    elif c == "[":
        value = bracketed(cur)
    elif c.isdigit() or c == ".":
        try:
            number, point, _ = parse_number(cur)
        except AlarmRaised as e:  # name the word, not the digits alone
            written = f"{address}{cur.text[start : cur.pos]}"
            if len(written) > _SHOWN:
                written = written[: _SHOWN - 3] + "..."
            what = (
                "a number has at most 9 digits" if e.number == 3 else f"no digits after {address}"
            )
            raise AlarmRaised(e.number, f"{written}: {what}") from None
        held = WHOLE_NUMBER_ADDRESSES.get(address)
        if point and held is not None:
            written = f"{address}{cur.text[start : cur.pos]}"
            raise AlarmRaised(7, f"{written}: {held} takes no decimal point")
        value = Num(number)
        literal = not point
    elif c and c in "+-":  # a sign after the sign: FANUC's PS0006, naming the word as written
        signs = _SIGNED.match(cur.text, start)
        written = f"{address}{signs.group() if signs else c}"
        raise AlarmRaised(6, f"{written}: a value takes one sign")
    else:
        raise AlarmRaised(5, f"{address} has no value")
    if negative:
        value = Num(-value.value) if isinstance(value, Num) else Neg(value)
    return Word(address, value, literal)


def no_program(number: int, max_number: int = 9999) -> str:
    """Why a store of programs O1..O``max_number`` has no program ``number``, in the words
    of every front end: ``no program O1234``, or for a number no program can have, the range
    (``program number 10000 outside 1..9999``)."""
    if 1 <= number <= max_number:
        return f"no program O{number:04d}"
    return f"program number {number} outside 1..{max_number}"


def parse_program(text: str, max_number: int = 9999) -> Program:
    """Parse one program; raises :class:`ProgramError` (FORMAT or RANGE) when the text does
    not start with an O-number in 1..``max_number``, holds a second program (a block opening
    with an O-number, or text after the closing ``%``) or is empty."""
    blocks_text = _split_blocks(text)
    if not blocks_text:
        raise ProgramError(ProgramErrorReason.FORMAT, "the program text is empty")
    line, first = blocks_text[0]
    code, name = _strip_comments(first)
    if not code or code[0] not in "O:":
        shown = first.strip()[:40]
        raise ProgramError(
            ProgramErrorReason.FORMAT, f"a program starts with O and its number, not {shown!r}"
        )
    digits = ""
    pos = 1
    while pos < len(code) and code[pos].isdigit():
        digits += code[pos]
        pos += 1
    if not digits:
        raise ProgramError(
            ProgramErrorReason.FORMAT, f"no program number after O in {first.strip()[:40]!r}"
        )
    width = len(str(max_number))
    if pos < len(code) and not code[pos].isalpha():  # O1.5, O1-2: no whole number
        what = "no decimal point" if code[pos] in ".," else f"no {code[pos]!r} after its digits"
    elif len(digits) > width and int(digits) <= max_number:  # O00001: digits too many
        what = f"not {len(digits)}"
    else:
        what = ""
    if what:
        raise ProgramError(
            ProgramErrorReason.FORMAT,
            f"{first.strip()[:40]!r}: a program number is O and 1..{width} digits, {what} "
            f"(O1..O{max_number})",
        )
    number = int(digits)
    if not 1 <= number <= max_number:
        raise ProgramError(
            ProgramErrorReason.RANGE,
            f"program number O{digits} is outside O1..O{max_number}",
            number,
        )
    rest = first[_code_end(first, pos) :]
    # the program's name is the comment right after the number (or before the O): it is the
    # O line's, as FANUC's directory shows it, not a comment of the block the line goes on with
    lead = len(rest) - len(rest.lstrip())
    cut = 0
    if rest[lead : lead + 1] == "(":
        close = rest.find(")", lead)
        cut = len(rest) if close < 0 else close + 1
    # the comment after the number, else one before the O (``(12)O12``)
    _, name = _strip_comments(rest[:cut] if cut else first[: len(first) - len(rest)])
    rest = rest[cut:]
    rest_code, _ = _strip_comments(rest)
    if _opens(rest):  # O1O2: the O line's block would be a second program's O line
        raise ProgramError(
            ProgramErrorReason.FORMAT,
            f"line {line}: {first.strip()[:40]!r}: {rest.strip()[:40]!r} starts a second "
            "program: one program per text",
        )
    for n, b in blocks_text[1:]:
        if _opens(b):
            raise ProgramError(
                ProgramErrorReason.FORMAT,
                f"line {n}: {b.strip()[:40]!r} starts a second program: one program per text",
            )
    parsed: list[Block] = []
    if rest_code:
        parsed.append(parse_block(line, rest))
    parsed.extend(parse_block(n, b) for n, b in blocks_text[1:])
    lines = [f"O{number:04d}" + (f" ({name})" if name else "")]
    lines.extend(b.text for b in parsed)
    return _indexed(number, name, "\n".join(lines) + "\n", tuple(parsed))


def _indexed(number: int, name: str, text: str, blocks: tuple[Block, ...]) -> Program:
    sequences: dict[int, int] = {}
    loops: dict[int, int] = {}
    errors: dict[int, tuple[int, str]] = {}
    open_loops: list[tuple[int, int]] = []  # (loop number, block index)
    for i, block in enumerate(blocks):
        if block.sequence is not None:
            sequences.setdefault(block.sequence, i)
        st = block.statement
        if isinstance(st, While):
            if any(m == st.loop for m, _ in open_loops) or len(open_loops) >= 3:
                errors[i] = (126, f"DO{st.loop} nested in a loop of the same number or too deep")
            open_loops.append((st.loop, i))
        elif isinstance(st, End):
            if open_loops and open_loops[-1][0] == st.loop:
                _, start = open_loops.pop()
                loops[start] = i
                loops[i] = start
            else:
                errors[i] = (124, f"END{st.loop} without its DO{st.loop}")
    for m, start in open_loops:
        errors[start] = (124, f"DO{m} without END{m}")
    return Program(number, name, text, blocks, sequences, loops, errors)


#: Parsed programs are immutable: a fleet of machines storing the same text shares one parse.
_parse_shared: Final = functools.lru_cache(maxsize=32)(parse_program)


class ProgramStore:
    """Programs keyed by O-number, with a CNC's checks: number range, duplicates, capacity
    (characters and count), and no deleting or replacing a program in use. ``in_use`` answers
    the numbers being executed (the engine's call stack); the main program is the one
    selected for cycle start."""

    def __init__(
        self,
        *,
        max_number: int = 9999,
        capacity: int = 512_000,
        max_programs: int = 400,
        in_use: Callable[[], Collection[int]] = frozenset,
    ) -> None:
        self.max_number = max_number
        self.capacity = capacity
        self.max_programs = max_programs
        self.in_use = in_use
        self._programs: dict[int, Program] = {}
        self.main: int | None = None
        #: Incremented on every change; a cache of the directory compares it.
        self.version = 0

    def __contains__(self, number: object) -> bool:
        return number in self._programs

    def __len__(self) -> int:
        return len(self._programs)

    def directory(self) -> list[ProgramInfo]:
        """Every stored program, by number, named by the first :data:`DIRECTORY_NAME`
        characters of its O line's comment (the text keeps the whole comment)."""
        return [
            ProgramInfo(p.number, p.name[:DIRECTORY_NAME], p.size)
            for _, p in sorted(self._programs.items())
        ]

    def get(self, number: int) -> Program:
        """The program ``number``; :class:`ProgramError` NOT_FOUND when absent (a number no
        program can have named as given: ``program number -1 outside 1..9999``)."""
        try:
            return self._programs[number]
        except KeyError:
            text = no_program(number, self.max_number)
            raise ProgramError(ProgramErrorReason.NOT_FOUND, text, number) from None

    def find(self, number: int) -> Program | None:
        return self._programs.get(number)

    def text(self, number: int) -> str:
        """The program's text as stored (from its O line, one block per line, no ``%``)."""
        return self.get(number).text

    def store(self, text: str, *, replace: bool = False) -> Program:
        """Parse and store one program; refuses a number already stored unless ``replace``
        (and never one in use), and text beyond the capacity or count."""
        program = _parse_shared(text, self.max_number)
        number = program.number
        old = self._programs.get(number)
        if old is not None and not replace:
            raise ProgramError(
                ProgramErrorReason.DUPLICATE, f"program O{number:04d} is already stored", number
            )
        if old is not None and number in self.in_use():
            raise ProgramError(
                ProgramErrorReason.IN_USE, f"program O{number:04d} is being executed", number
            )
        if old is None and len(self._programs) >= self.max_programs:
            raise ProgramError(
                ProgramErrorReason.TOO_MANY,
                f"the store holds its maximum of {self.max_programs} programs",
                number,
            )
        used = sum(p.size for p in self._programs.values()) - (old.size if old else 0)
        if used + program.size > self.capacity:
            raise ProgramError(
                ProgramErrorReason.NO_SPACE,
                f"O{number:04d} needs {program.size} characters, "
                f"{self.capacity - used} of {self.capacity} are free",
                number,
            )
        self._programs[number] = program
        self.version += 1
        return program

    def delete(self, number: int) -> None:
        """Delete one program (not one in use); deleting the main program unselects it."""
        self.get(number)
        if number in self.in_use():
            raise ProgramError(
                ProgramErrorReason.IN_USE, f"program O{number:04d} is being executed", number
            )
        del self._programs[number]
        if self.main == number:
            self.main = None
        self.version += 1

    def select(self, number: int) -> Program:
        """Make ``number`` the main program (not while another one is executing)."""
        program = self.get(number)
        busy = self.in_use()
        if busy and number not in busy:
            raise ProgramError(
                ProgramErrorReason.IN_USE,
                f"cannot select O{number:04d} while a program is being executed",
                number,
            )
        self.main = number
        self.version += 1
        return program
