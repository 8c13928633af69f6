"""Part programs over the native protocol (``docs/native-protocol.md``, "Programs").

Two kinds of exchange, both verified with FANUC's library (libfwlib32 1.0.5) in both command
sets (the same frames in the 16i and the 30i set):

* **data requests** on the data connection: 0x06 program directory (``cnc_rdprogdir``,
  ``cnc_rdprogdir2``, ``cnc_rdprogdir3``), 0x07 program memory (``cnc_rdproginfo``), 0x05
  delete (``cnc_delete``), 0x03 search (``cnc_search``), 0x20 the blocks being executed
  (``cnc_rdexecprog``);
* **transfer frames** on the library's first connection (connection A), frame types of their
  own: upload (``cnc_upstart``/``cnc_upload``/``cnc_upend`` and the ``3``/``4`` forms)
  ``0x1501`` -> ``0x1502``, then the CNC sends ``0x1604`` data frames and ``0x1701``, which the
  library answers ``0x1702``; ``cnc_upend`` before the end sends ``0x1804`` (8 zero bytes) and
  waits for nothing. Download (``cnc_dwnstart``/``cnc_download``/``cnc_dwnend``) ``0x1101`` ->
  ``0x1102``, then ``0x1204`` data frames (no answer), then ``0x1301`` -> ``0x1302``. A refusal
  answers the request's kind with direction 3 (``0x1503``, ``0x1103``, ``0x1303``) and a
  :class:`TransferError` body: the function returns its ``code``.
"""

from __future__ import annotations

import enum
import re
import struct
from dataclasses import dataclass
from typing import Any, ClassVar, Final

from ..errors import EW
from .base import NativePayloadError, NativeRecord, RecordArray
from .records import NoData
from .requests import NativeCommand, NativeRequest, _register

__all__ = [
    "PROGRAM_CHUNK",
    "ExecutingBlocks",
    "ExecutingBlocksRequest",
    "ProgramDeleteRequest",
    "ProgramDirEntries",
    "ProgramDirEntry",
    "ProgramDirRequest",
    "ProgramMemory",
    "ProgramMemoryRequest",
    "ProgramSearchRequest",
    "TransferError",
    "TransferFrame",
    "TransferStart",
    "error_frame_type",
    "parse_program_range",
]

_I32: Final = struct.Struct(">i")

#: Most program bytes one upload data frame (``0x1604``) carries.
PROGRAM_CHUNK: Final = 1280


class TransferFrame(enum.IntEnum):
    """Frame types of a program transfer, on the library's first connection [V]."""

    DOWNLOAD_START = 0x1101
    DOWNLOAD_START_ANSWER = 0x1102
    DOWNLOAD_DATA = 0x1204
    DOWNLOAD_END = 0x1301
    DOWNLOAD_END_ANSWER = 0x1302
    UPLOAD_START = 0x1501
    UPLOAD_START_ANSWER = 0x1502
    UPLOAD_DATA = 0x1604
    UPLOAD_END = 0x1701
    UPLOAD_END_ANSWER = 0x1702
    UPLOAD_ABORT = 0x1804


def error_frame_type(request_type: int) -> int:
    """The refusal frame type of a transfer request: its kind, direction 3 (``0x1501`` ->
    ``0x1503``) [V]."""
    return (request_type & 0xFF00) | 0x03


@dataclass(frozen=True, slots=True)
class ProgramDirRequest(NativeRequest):
    """0x06 ``(top, count, kind)``: programs from O number ``top`` on, at most ``count``;
    ``kind`` is the caller's type (0 numbers, 1 with comments, 2 with sizes), which changes
    nothing in the answer: the library picks the fields itself [V]. ``cnc_rdprogdir`` (any
    range) sends ``(start, 19, type)``."""

    COMMAND: ClassVar[int] = NativeCommand.RDPROGDIR
    ARGS: ClassVar[tuple[str, ...]] = ("top", "count", "kind")
    ANSWER: ClassVar[Any] = None  # ProgramDirEntries, set below
    top: int
    count: int
    kind: int


@dataclass(frozen=True, slots=True)
class ProgramDirEntry(NativeRecord):
    """One 72-byte entry of 0x06: ``i32 number, i32 length`` (characters), then the comment
    in 64 NUL-padded bytes [V] (the layout; a real control's comment keeps its parentheses,
    ``(DEMO)`` [I])."""

    FORMAT: ClassVar[str] = ">ii64s"
    PADDED: ClassVar[frozenset[str]] = frozenset({"comment"})
    number: int
    length: int
    comment: bytes


@dataclass(frozen=True, slots=True)
class ProgramDirEntries(RecordArray[ProgramDirEntry]):
    """0x06 answer: one :class:`ProgramDirEntry` per program, by number; the library counts
    them from the data length, and no entry is the end of the directory [V]."""

    ITEM: ClassVar[type[NativeRecord]] = ProgramDirEntry
    records: tuple[ProgramDirEntry, ...]


ProgramDirRequest.ANSWER = ProgramDirEntries


@dataclass(frozen=True, slots=True)
class ProgramMemory(NativeRecord):
    """0x07 answer (ODBNC ``bin``): ``i32 registered, i32 unregistered`` (programs stored and
    room for more), ``i32 used, i32 unused`` (characters) [V]. ODBNC keeps the program
    counts in shorts; the text form (type 1) is the library's own, made of these."""

    FORMAT: ClassVar[str] = ">iiii"
    registered: int
    unregistered: int
    used: int
    unused: int


@dataclass(frozen=True, slots=True)
class ProgramMemoryRequest(NativeRequest):
    """0x07, no arguments (``cnc_rdproginfo`` of either type) [V]."""

    COMMAND: ClassVar[int] = NativeCommand.RDPROGINFO
    ANSWER: ClassVar[Any] = ProgramMemory


@dataclass(frozen=True, slots=True)
class ProgramDeleteRequest(NativeRequest):
    """0x05 ``(number)``: delete one program; no data [V]."""

    COMMAND: ClassVar[int] = NativeCommand.DELETE
    ARGS: ClassVar[tuple[str, ...]] = ("number",)
    ANSWER: ClassVar[Any] = NoData
    WRITE: ClassVar[bool] = True
    number: int


@dataclass(frozen=True, slots=True)
class ProgramSearchRequest(NativeRequest):
    """0x03 ``(number)``: make one program the main program; no data [V]."""

    COMMAND: ClassVar[int] = NativeCommand.SEARCH
    ARGS: ClassVar[tuple[str, ...]] = ("number",)
    ANSWER: ClassVar[Any] = NoData
    WRITE: ClassVar[bool] = True
    number: int


@dataclass(frozen=True, slots=True)
class ExecutingBlocksRequest(NativeRequest):
    """0x20 ``(length)``: the blocks being executed, at most ``length`` characters
    (``cnc_rdexecprog``) [V]."""

    COMMAND: ClassVar[int] = NativeCommand.RDEXECPROG
    ARGS: ClassVar[tuple[str, ...]] = ("length",)
    ANSWER: ClassVar[Any] = None  # ExecutingBlocks, set below
    length: int


@dataclass(frozen=True, slots=True)
class ExecutingBlocks:
    """0x20 answer: ``i32 blocks`` (``blknum``), then the text; the library gives the text's
    length as ``length`` [V]."""

    blocks: int
    text: bytes

    def encode(self) -> bytes:
        return _I32.pack(self.blocks) + self.text

    @classmethod
    def decode(cls, data: bytes) -> ExecutingBlocks:
        if len(data) < _I32.size:
            raise NativePayloadError(
                f"ExecutingBlocks: {len(data)} bytes, at least {_I32.size}", EW.LENGTH
            )
        (blocks,) = _I32.unpack_from(data)
        return cls(blocks, bytes(data[_I32.size :]))


ExecutingBlocksRequest.ANSWER = ExecutingBlocks


@dataclass(frozen=True, slots=True)
class TransferStart(NativeRecord):
    """Body of ``0x1501`` and ``0x1101``, 516 bytes: ``u16 data_type`` (0, NC programs, as
    sent by ``cnc_upstart(3)`` and ``cnc_dwnstart(3)`` with type 0), ``u16 path``, the
    handle's path (1, or what ``cnc_setpath`` selected: 2 after ``cnc_setpath(2)``, in both
    command sets), then 512 NUL-padded bytes: the programs of an upload, ``O1-O1`` for
    ``cnc_upstart(1)``; empty for a download [V]."""

    FORMAT: ClassVar[str] = ">HH512s"
    PADDED: ClassVar[frozenset[str]] = frozenset({"name"})
    data_type: int
    path: int
    name: bytes


@dataclass(frozen=True, slots=True)
class TransferError(NativeRecord):
    """Body of a refused transfer request (``0x1503``, ``0x1103``, ``0x1303``): ``i16 loc,
    code, detail1, detail2``; the library returns ``code`` [V]."""

    FORMAT: ClassVar[str] = ">hhhh"
    loc: int
    code: int
    detail1: int
    detail2: int


#: The program requests join the codec's table of typed requests.
_register(
    ProgramDirRequest,
    ProgramMemoryRequest,
    ProgramDeleteRequest,
    ProgramSearchRequest,
    ExecutingBlocksRequest,
)

_RANGE: Final = re.compile(r"O(\d{1,8})(?:-O(\d{1,8}))?")


def parse_program_range(name: bytes) -> tuple[int, int]:
    """``(first, last)`` of an upload's program range: ``O1-O1`` (``cnc_upstart``,
    ``cnc_upstart3``) or a file name ``N:O0001``, maybe with a folder (``cnc_upstart4`` sends
    ``N:`` and the name given) [V]. Raises :class:`NativePayloadError` (EW_DATA) naming the
    text received otherwise."""
    text = name.decode("latin-1")
    program = text.strip()
    if program.startswith("N:"):
        program = program[2:].rsplit("/", 1)[-1]
    match = _RANGE.fullmatch(program)
    if match is None:
        raise NativePayloadError(f"upload range {text[:40]!r}: expected O<n>-O<m>", EW.DATA)
    first = int(match.group(1))
    last = int(match.group(2)) if match.group(2) else first
    if last < first:
        raise NativePayloadError(
            f"upload range {text[:40]!r}: the end is before the start", EW.DATA
        )
    return first, last
