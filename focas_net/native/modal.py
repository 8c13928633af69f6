"""Modal data, operator messages and program pointers over the native protocol
(``docs/native-protocol.md``, "Modal data and pointers").

What FANUC's library (libfwlib32 1.0.5) sends, the same in both command sets unless said [V]:

* ``cnc_modal(type, block)`` is two commands. G codes go as **0x21** ``(kind, block)``: type
  0..99 (a group: type 0 is FANUC's group 01) as it is, -1 (all groups) as -1, -4 (every
  one-shot code) as -2, -5 as -3, 300.. (one one-shot code) as type - 200. The other data go
  as **0x22** ``(kind, block)``: type 100..126 (an address) as its slot in
  :data:`ADDRESS_SLOTS` (A 0, B 1, ... Z 28), -2 (every address) as -1, -3 (every axis) as
  -2, 200.. (one axis) as type - 100; type 127 or more, or -6 and less, is EW_NUMBER without
  sending. The answer of 0x21 is two bytes per group, of which the library keeps the first
  (``g_data``: the code's index in FANUC's table of the group, bit 7 set when the block
  commands it); that of 0x22 an 8-byte :class:`ModalAux` per entry; for -1 the library
  takes the entry of each type 100..126 from its slot.
* ``cnc_rdgcode(type, block, num)`` sends **0x96** ``(type, block)``: 12-byte
  :class:`GCodeRecord` entries (the library prints ``G%02d`` of the number and puts a point
  before its last ``decimals`` digits), at most ``num`` kept.
* ``cnc_rdcommand(type, block, num)`` sends **0x97** ``(type, block)``: 12-byte
  :class:`CommandRecord` entries; more entries than ``num`` is EW_LENGTH in the library.
* ``cnc_rdopmsg(type, length)`` and ``cnc_rdopmsg2`` send **0x34** ``(type)``; type -1 is
  EW_ATTRIB without sending. ``cnc_rdopmsg3(type, num)`` sends 0x34 ``(-1)`` in the 16i set
  and **0xD0** ``(0, type, num)`` in the 30i set. Every answer is a run of 268-byte
  :class:`OperatorMessageRecord` entries, which the library counts from the data length.
* ``cnc_exeprgname2`` sends **0xFC**: the text of the executing program's full path, of
  which the library copies up to 256 bytes; ``cnc_rdactpt`` **0x162**: ``i32 program, i32
  block``; ``cnc_rdblkcount`` **0x35**: ``i32``; ``cnc_rdmdipntr`` (``cnc_rdmdipntro8``)
  **0x38**: four i32, of which the library keeps the low 16 bits of the two program numbers.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar, Final

from .base import NativeRecord, RecordArray
from .requests import NativeCommand, NativeRequest, _register

__all__ = [
    "ADDRESS_SLOTS",
    "EXECUTING_PATH_SIZE",
    "G_CODE_INDEX",
    "MODAL_GROUPS",
    "OPERATOR_MESSAGE_TEXT",
    "ActivePointer",
    "ActivePointerRequest",
    "BlockCounter",
    "BlockCounterRequest",
    "CommandRecord",
    "CommandRecords",
    "CommandRequest",
    "ExecutingPath",
    "ExecutingPathRequest",
    "GCodeRecord",
    "GCodeRecords",
    "GCodeRequest",
    "MdiPointer",
    "MdiPointerRequest",
    "ModalAux",
    "ModalAuxData",
    "ModalAuxRequest",
    "ModalGCode",
    "ModalGCodes",
    "ModalGRequest",
    "OperatorMessage3Request",
    "OperatorMessageRecord",
    "OperatorMessageRecords",
    "OperatorMessageRequest",
    "g_code_of",
]

#: The slot of each address in a 0x22 answer (the argument of a single address) [V]: the
#: library sends type 100 B as 1, 101 D 3, 102 E 4, 103 F 5, 104 H 6, 105 L 10, 106 M 11,
#: 107 S 21, 108 T 22, 109 R 20, 110 P 18, 111 Q 19, 112 A 0, 113 C 2, 114 I 7, 115 J 8,
#: 116 K 9, 117 N 16, 118 O 17, 119 U 23, 120 V 24, 121 W 25, 122 X 26, 123 Y 27, 124 Z 28,
#: 125 (the second M code) 12, 126 (the third) 13. Slots 14 and 15 are no address.
ADDRESS_SLOTS: Final[dict[str, int]] = {
    **{c: i for i, c in enumerate("ABCDEF")},
    **{c: i + 6 for i, c in enumerate("HIJKLM")},
    **{c: i + 16 for i, c in enumerate("NOPQRSTUVWXYZ")},
}
#: Bytes of an operator message's text field in a 0x34 / 0xD0 entry [V].
OPERATOR_MESSAGE_TEXT: Final = 256
#: Bytes of the 0xFC answer: the path text, NUL padded (the library copies up to 256) [I].
EXECUTING_PATH_SIZE: Final = 256


# --------------------------------------------------------------------------------------------
# cnc_modal


@dataclass(frozen=True, slots=True)
class ModalGRequest(NativeRequest):
    """0x21 ``(kind, block)``: G codes (``cnc_modal`` types 0..99, -1, -4, -5, 300..) [V];
    ``block`` 0 is the executing block, 1 and 2 the next ones. Answered with
    :class:`ModalGCodes`."""

    COMMAND: ClassVar[int] = NativeCommand.GMODAL
    ARGS: ClassVar[tuple[str, ...]] = ("kind", "block")
    ANSWER: ClassVar[Any] = None  # ModalGCodes, set below
    kind: int
    block: int = 0


@dataclass(frozen=True, slots=True)
class ModalGCode(NativeRecord):
    """One group of a 0x21 answer, 2 bytes: ``g_data`` (the code's index in FANUC's table of
    the group, bit 7 set when the block commands it), which the library copies into
    ODBMDL, then a byte it skips [V] (0 here)."""

    FORMAT: ClassVar[str] = ">BB"
    g_data: int
    spare: int = 0

    @property
    def index(self) -> int:
        return self.g_data & 0x7F

    @property
    def commanded(self) -> bool:
        return bool(self.g_data & 0x80)


@dataclass(frozen=True, slots=True)
class ModalGCodes(RecordArray[ModalGCode]):
    """0x21 answer: one :class:`ModalGCode` per group asked (the library copies length / 2
    bytes into ``g_data``/``g_rdata``/``g_1shot``) [V]."""

    ITEM: ClassVar[type[NativeRecord]] = ModalGCode
    records: tuple[ModalGCode, ...]


ModalGRequest.ANSWER = ModalGCodes


@dataclass(frozen=True, slots=True)
class ModalAuxRequest(NativeRequest):
    """0x22 ``(kind, block)``: data other than G codes (``cnc_modal`` types 100..126 as their
    :data:`ADDRESS_SLOTS`, -2 as -1, -3 as -2, 200.. as 100..) [V]. Answered with
    :class:`ModalAuxData`."""

    COMMAND: ClassVar[int] = NativeCommand.AMODAL
    ARGS: ClassVar[tuple[str, ...]] = ("kind", "block")
    ANSWER: ClassVar[Any] = None  # ModalAuxData, set below
    kind: int
    block: int = 0


@dataclass(frozen=True, slots=True)
class ModalAux(NativeRecord):
    """One 8-byte entry of 0x22: ``i32 aux_data, i16 flag1, i16 flag2``; the library keeps
    the low byte of each flag [V]. FANUC's meaning: ``aux_data`` the absolute value,
    ``flag1`` bit 7 commanded in the block, bit 6 a decimal point, bit 5 negative, bits 0-3
    the digits; ``flag2`` bits 0-2 the digits after the point [I]."""

    FORMAT: ClassVar[str] = ">ihh"
    aux_data: int
    flag1: int
    flag2: int

    @classmethod
    def of(cls, value: float | None, commanded: bool) -> ModalAux:
        """The entry of ``value`` (None: never given, all zero)."""
        if value is None:
            return cls(0, 0, 0)
        decimals = 0
        scaled = abs(value)
        while decimals < 7 and abs(scaled - round(scaled)) > 1e-9 * max(1.0, scaled):
            scaled *= 10
            decimals += 1
        magnitude = min(round(scaled), 2**31 - 1)
        flag1 = min(len(str(magnitude)), 15)
        if commanded:
            flag1 |= 0x80
        if decimals:
            flag1 |= 0x40
        if value < 0:
            flag1 |= 0x20
        return cls(magnitude, flag1, decimals)

    @property
    def commanded(self) -> bool:
        return bool(self.flag1 & 0x80)

    @property
    def value(self) -> float:
        """The value the entry carries (its sign and decimals applied)."""
        sign = -1 if self.flag1 & 0x20 else 1
        return float(sign * self.aux_data / 10 ** (self.flag2 & 0x07))


@dataclass(frozen=True, slots=True)
class ModalAuxData(RecordArray[ModalAux]):
    """0x22 answer: one :class:`ModalAux` per entry asked; for -1 every slot 0..28 of
    :data:`ADDRESS_SLOTS`, for -2 one per axis of the path [V] (the layout)."""

    ITEM: ClassVar[type[NativeRecord]] = ModalAux
    records: tuple[ModalAux, ...]


ModalAuxRequest.ANSWER = ModalAuxData


# --------------------------------------------------------------------------------------------
# cnc_rdgcode, cnc_rdcommand


@dataclass(frozen=True, slots=True)
class GCodeRequest(NativeRequest):
    """0x96 ``(type, block)`` (``cnc_rdgcode``) [V]: type -1 every modal group, -2 the
    one-shot code, 0.. one group (0 is FANUC's group 01, as in ``cnc_modal``) [I]."""

    COMMAND: ClassVar[int] = NativeCommand.RDGCODE
    ARGS: ClassVar[tuple[str, ...]] = ("type", "block")
    ANSWER: ClassVar[Any] = None  # GCodeRecords, set below
    type: int
    block: int = 0


@dataclass(frozen=True, slots=True)
class GCodeRecord(NativeRecord):
    """One 12-byte entry of 0x96: ``u16 group, u16 flag, i32 number, i32 decimals`` [V];
    ODBGCD's ``code`` is ``G%02d`` of ``number`` with a point before its last ``decimals``
    digits (501, 1: ``G50.1``) [V]. ``flag`` bit 0: commanded in the block [I]."""

    FORMAT: ClassVar[str] = ">HHii"
    group: int
    flag: int
    number: int
    decimals: int

    @property
    def code(self) -> str:
        """The code as the library writes it into ODBGCD."""
        digits = f"{self.number:02d}"
        if self.decimals > 0:
            cut = len(digits) - self.decimals
            digits = digits[:cut] + "." + digits[cut:]
        return "G" + digits


@dataclass(frozen=True, slots=True)
class GCodeRecords(RecordArray[GCodeRecord]):
    """0x96 answer: the library keeps min(length / 12, num) entries [V]."""

    ITEM: ClassVar[type[NativeRecord]] = GCodeRecord
    records: tuple[GCodeRecord, ...]


GCodeRequest.ANSWER = GCodeRecords


@dataclass(frozen=True, slots=True)
class CommandRequest(NativeRequest):
    """0x97 ``(type, block)`` (``cnc_rdcommand``) [V]: type -1 the modal addresses that have
    a value, 0.. one address by its :data:`ADDRESS_SLOTS` slot [I]."""

    COMMAND: ClassVar[int] = NativeCommand.RDCOMMAND
    ARGS: ClassVar[tuple[str, ...]] = ("type", "block")
    ANSWER: ClassVar[Any] = None  # CommandRecords, set below
    type: int
    block: int = 0


@dataclass(frozen=True, slots=True)
class CommandRecord(NativeRecord):
    """One 12-byte entry of 0x97: ODBCMD as it is, big-endian: ``char adrs, u8 num, i16
    flag, i32 cmd_val, i32 dec_val`` [V]. ``flag`` bit 0: commanded in the block [I]."""

    FORMAT: ClassVar[str] = ">1sBhii"
    TEXT: ClassVar[frozenset[str]] = frozenset({"address"})
    address: str
    number: int
    flag: int
    value: int
    decimals: int


@dataclass(frozen=True, slots=True)
class CommandRecords(RecordArray[CommandRecord]):
    """0x97 answer: more entries than the caller's ``num`` is EW_LENGTH in the library [V]."""

    ITEM: ClassVar[type[NativeRecord]] = CommandRecord
    records: tuple[CommandRecord, ...]


CommandRequest.ANSWER = CommandRecords


# --------------------------------------------------------------------------------------------
# Operator messages


@dataclass(frozen=True, slots=True)
class OperatorMessageRequest(NativeRequest):
    """0x34 ``(type)``: ``cnc_rdopmsg`` / ``cnc_rdopmsg2`` (type 0..4) and, in the 16i set,
    ``cnc_rdopmsg3`` (-1) [V]."""

    COMMAND: ClassVar[int] = NativeCommand.RDOPMSG
    ARGS: ClassVar[tuple[str, ...]] = ("type",)
    ANSWER: ClassVar[Any] = None  # OperatorMessageRecords, set below
    type: int


@dataclass(frozen=True, slots=True)
class OperatorMessage3Request(NativeRequest):
    """0xD0 ``(mode, type, count)``: ``cnc_rdopmsg3(type, num)`` in the 30i set sends
    ``(0, type, num)`` [V]."""

    COMMAND: ClassVar[int] = NativeCommand.RDOPMSG3
    ARGS: ClassVar[tuple[str, ...]] = ("mode", "type", "count")
    ANSWER: ClassVar[Any] = None  # OperatorMessageRecords, set below
    mode: int
    type: int
    count: int


@dataclass(frozen=True, slots=True)
class OperatorMessageRecord(NativeRecord):
    """One 268-byte entry of 0x34 / 0xD0: ``i32 number, i32 type, i32 length``, then the
    text in 256 NUL-padded bytes [V]; OPMSG gets ``datano``, ``type``, ``char_num`` (16 bits
    each) and the text. ``number`` -1 and length 0: no message [I]."""

    FORMAT: ClassVar[str] = ">iii256s"
    PADDED: ClassVar[frozenset[str]] = frozenset({"text"})
    number: int
    type: int
    length: int
    text: bytes

    @property
    def message(self) -> bytes:
        """The first ``length`` bytes of the text."""
        return self.text[: max(self.length, 0)]


@dataclass(frozen=True, slots=True)
class OperatorMessageRecords(RecordArray[OperatorMessageRecord]):
    """0x34 / 0xD0 answer: entries counted from the data length (length / 268) [V]."""

    ITEM: ClassVar[type[NativeRecord]] = OperatorMessageRecord
    records: tuple[OperatorMessageRecord, ...]


OperatorMessageRequest.ANSWER = OperatorMessageRecords
OperatorMessage3Request.ANSWER = OperatorMessageRecords


# --------------------------------------------------------------------------------------------
# Program pointers


@dataclass(frozen=True, slots=True)
class ExecutingPath(NativeRecord):
    """0xFC answer: the full path of the executing program (``//CNC_MEM/USER/PATH1/O0001``
    on a 30i [I]) in :data:`EXECUTING_PATH_SIZE` NUL-padded bytes; the library copies up to
    256 bytes into the caller's text [V]."""

    FORMAT: ClassVar[str] = f">{EXECUTING_PATH_SIZE}s"
    PADDED: ClassVar[frozenset[str]] = frozenset({"path"})
    path: bytes

    @property
    def text(self) -> bytes:
        """The path: the bytes before the first NUL."""
        return self.path.split(b"\x00", 1)[0]


@dataclass(frozen=True, slots=True)
class ExecutingPathRequest(NativeRequest):
    """0xFC, no arguments (``cnc_exeprgname2``) [V]."""

    COMMAND: ClassVar[int] = NativeCommand.EXEPRGNAME2
    ANSWER: ClassVar[Any] = ExecutingPath


@dataclass(frozen=True, slots=True)
class ActivePointer(NativeRecord):
    """0x162 answer: ``i32 program, i32 block`` (``cnc_rdactpt``'s prog_no, blk_no) [V]."""

    FORMAT: ClassVar[str] = ">ii"
    program: int
    block: int


@dataclass(frozen=True, slots=True)
class ActivePointerRequest(NativeRequest):
    """0x162, no arguments (``cnc_rdactpt``) [V]."""

    COMMAND: ClassVar[int] = NativeCommand.RDACTPT
    ANSWER: ClassVar[Any] = ActivePointer


@dataclass(frozen=True, slots=True)
class BlockCounter(NativeRecord):
    """0x35 answer: ``i32`` block counter (``cnc_rdblkcount``) [V]."""

    FORMAT: ClassVar[str] = ">i"
    count: int


@dataclass(frozen=True, slots=True)
class BlockCounterRequest(NativeRequest):
    """0x35, no arguments (``cnc_rdblkcount``) [V]."""

    COMMAND: ClassVar[int] = NativeCommand.RDBLKCOUNT
    ANSWER: ClassVar[Any] = BlockCounter


@dataclass(frozen=True, slots=True)
class MdiPointer(NativeRecord):
    """0x38 answer: ODBMDIPO8 ``i32 mdiprog, mdipntr, crntprog, crntpntr`` (the program and
    pointer executed, the program and pointer prepared) [V]; the library keeps the low 16
    bits of the two program numbers."""

    FORMAT: ClassVar[str] = ">iiii"
    mdiprog: int
    mdipntr: int
    crntprog: int
    crntpntr: int


@dataclass(frozen=True, slots=True)
class MdiPointerRequest(NativeRequest):
    """0x38, no arguments (``cnc_rdmdipntr``, ``cnc_rdmdipntro8``) [V]."""

    COMMAND: ClassVar[int] = NativeCommand.RDMDIPNTR
    ANSWER: ClassVar[Any] = MdiPointer


#: The requests of this module join the codec's table of typed requests.
_register(
    ModalGRequest,
    ModalAuxRequest,
    GCodeRequest,
    CommandRequest,
    OperatorMessageRequest,
    OperatorMessage3Request,
    ExecutingPathRequest,
    ActivePointerRequest,
    BlockCounterRequest,
    MdiPointerRequest,
)


#: Groups ``cnc_modal`` answers: types 0..21 (FANUC's groups 01..22) [I].
MODAL_GROUPS: Final = 22

#: The index of each G code (x10) in FANUC's table of its group, as ``cnc_modal`` gives it in
#: ``g_data`` (0i-D/F and 30i, M series), keyed by the type (the group - 1) [I].
G_CODE_INDEX: Final[dict[int, dict[int, int]]] = {
    0: {0: 0, 10: 1, 20: 2, 30: 3},
    1: {170: 0, 190: 4, 180: 8},
    2: {900: 0, 910: 1},
    3: {230: 0, 220: 1},
    4: {940: 0, 950: 1, 930: 2},
    5: {200: 0, 210: 1},
    6: {400: 0, 410: 1, 420: 2},
    7: {490: 0, 430: 1, 440: 2},
    8: {800: 0, 810: 1, 820: 2, 830: 3, 840: 4, 850: 5, 860: 6, 870: 7, 880: 8, 890: 9},
    9: {980: 0, 990: 1},
    10: {500: 0, 510: 1},
    11: {670: 0, 660: 1},
    12: {970: 0, 960: 1},
    13: {540: 0, 550: 1, 560: 2, 570: 3, 580: 4, 590: 5},
    14: {640: 0, 610: 1, 620: 2, 630: 3},
    15: {690: 0, 680: 1},
    16: {150: 0, 160: 1},
    17: {401: 0, 411: 1, 421: 2},
    21: {501: 0, 511: 1},
}


def g_code_of(kind: int, g_data: int) -> int | None:
    """The G code (x10) of ``g_data`` in group type ``kind``; None when the table does not
    hold it."""
    index = g_data & 0x7F
    for code, i in G_CODE_INDEX.get(kind, {}).items():
        if i == index:
            return code
    return None
