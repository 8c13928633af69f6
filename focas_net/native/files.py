"""The program folders of a 30i-class control over the native protocol
(``docs/native-protocol.md``, "Program folders").

FANUC's library (libfwlib32 1.0.5) sends the same frames in both command sets [V]:

* 0xAE ``cnc_rdpdf_drive``, no arguments: the drive names, 12 bytes each; the library counts
  them from the data length (``max_num`` = length / 12, not capped at 16: send 16 at most);
* 0xAF ``cnc_rdpdf_inf(path, info)``: ``(info)`` and the drive name in 12 extra bytes (the
  caller's text cut or NUL-padded to 12): four i32, ODBPDFINF;
* 0xB0 ``cnc_rdpdf_curdir(kind)``: ``(kind)``, the current folder as text (the library
  copies at most 256 bytes); 0xB1 ``cnc_wrpdf_curdir(kind, folder)``: ``(kind)`` and the
  folder in 256 extra bytes, no data;
* 0xB2 ``cnc_rdpdf_subdir``: ``(first, count)`` and the folder in 256 extra bytes; 40-byte
  records (``i32 sub_exist``, the name in 36 bytes), counted from the data length;
* 0xB3 ``cnc_rdpdf_alldir``: ``(first, count, type, size_kind)`` (the library asks at most
  20 and refuses a count of 0 with EW_LENGTH itself) and the folder in 256 extra bytes;
  128-byte records in ODBPDFADIR's order, counted from the data length (more than asked are
  copied all: send ``count`` at most); EW_NUMBER past the last entry;
* 0xB4 ``cnc_rdpdf_subdirn``: the folder in 256 extra bytes; ``i32 folders, i32 files``;
* 0x2B1 ``cnc_rdpdf_prginf``: ``(size_kind, 1 when type is 0)`` and the file in 244 extra
  bytes; one 84-byte record in ODBPDFPRG's order;
* 0xB6 ``cnc_pdf_del(name)`` and 0xBA ``cnc_pdf_slctmain(name)``: the name in 256 extra
  bytes (a longer one cut to 256, no NUL), no data; 0xB9 ``cnc_pdf_rdmain``, no arguments:
  the main program's file as text.

A name travels NUL-padded in its fixed extra bytes; a text answer is the text and one NUL.
"""

from __future__ import annotations

from dataclasses import dataclass
from datetime import datetime
from typing import Any, ClassVar, Final

from focas_net.errors import EW

from .base import NativePayloadError, NativeRecord, RecordArray
from .calls import CommandSet, LibraryCall
from .records import NoData
from .requests import EXTRA_LENGTH, NativeCommand, NativeRequest, _register

__all__ = [
    "DRIVE_NAME_SIZE",
    "FILE_NAME_SIZE",
    "FOLDER_NAME_SIZE",
    "LISTING_DETAILS",
    "MAX_DRIVES",
    "MAX_FOLDER_ENTRIES",
    "SIZE_UNITS",
    "CurrentFolderRequest",
    "CurrentFolderWriteRequest",
    "DriveInfo",
    "DriveInfoRequest",
    "DriveListRequest",
    "DriveName",
    "DriveNames",
    "FileDeleteRequest",
    "FileInfo",
    "FileInfoRequest",
    "FolderCount",
    "FolderCountRequest",
    "FolderListRequest",
    "FolderRecord",
    "FolderRecords",
    "FolderText",
    "MainFileRequest",
    "MainSelectRequest",
    "SubfolderRecord",
    "SubfolderRecords",
    "SubfolderRequest",
    "check_detail",
    "cnc_pdf_del",
    "cnc_pdf_rdmain",
    "cnc_pdf_slctmain",
    "cnc_rdpdf_alldir",
    "cnc_rdpdf_curdir",
    "cnc_rdpdf_drive",
    "cnc_rdpdf_inf",
    "cnc_rdpdf_prginf",
    "cnc_rdpdf_subdir",
    "cnc_rdpdf_subdirn",
    "cnc_wrpdf_curdir",
    "size_in",
    "stamp_fields",
]

#: Extra bytes of a drive name (0xAF), a folder or file name (0xB1-0xBA), a file (0x2B1).
DRIVE_NAME_SIZE: Final = 12
FOLDER_NAME_SIZE: Final = 256
FILE_NAME_SIZE: Final = 244
#: Most entries ``cnc_rdpdf_alldir`` asks in one request [V].
MAX_FOLDER_ENTRIES: Final = 20
#: Drives ODBPDFDRV holds.
MAX_DRIVES: Final = 16


#: Characters of each size unit a size is asked in (``size_kind``): 0 pages of 256, 1 bytes,
#: 2 kilobytes, 3 megabytes [I].
SIZE_UNITS: Final = (256, 1, 1024, 1024 * 1024)
#: A folder listing's ``type``: 0 names and dates, 1 with sizes, comments and time stamps.
LISTING_DETAILS: Final = (0, 1)


def size_in(chars: int, size_kind: int) -> int:
    """``chars`` characters in the unit ``size_kind`` asks (:data:`SIZE_UNITS`), rounded up;
    :class:`NativePayloadError` (EW_DATA) for a unit there is not."""
    if not 0 <= size_kind < len(SIZE_UNITS):
        raise NativePayloadError(f"size kind {size_kind}: 0..{len(SIZE_UNITS) - 1}", EW.DATA)
    unit = SIZE_UNITS[size_kind]
    return -(-chars // unit)


def check_detail(detail: int) -> None:
    """:class:`NativePayloadError` (EW_DATA) unless ``detail`` is a listing's ``type``."""
    if detail not in LISTING_DETAILS:
        raise NativePayloadError(f"listing type {detail}: 0 or 1", EW.DATA)


def stamp_fields(when: datetime | None) -> tuple[int, int, int, int, int, int]:
    """Year, month, day, hour, minute and second of ``when``; zeros for no date."""
    if when is None:
        return (0, 0, 0, 0, 0, 0)
    return (when.year, when.month, when.day, when.hour, when.minute, when.second)


class _NamedRequest(NativeRequest):
    """A request carrying a name NUL-padded in ``NAME_SIZE`` extra bytes (``name``). The
    name is printable ASCII of at most ``NAME_SIZE - 1`` characters (TypeError for no text,
    ValueError for text that does not fit, when built;
    a received one up to ``NAME_SIZE`` bytes is read to its first NUL)."""

    __slots__ = ()
    NAME_SIZE: ClassVar[int] = FOLDER_NAME_SIZE
    name: str

    def extra(self) -> bytes:
        if not isinstance(self.name, str):
            raise TypeError(f"name must be text, got {self.name!r}")
        raw = self.name.encode("latin-1", "replace")
        if len(raw) >= self.NAME_SIZE or not self.name.isascii() or not self.name.isprintable():
            raise ValueError(
                f"name {self.name[:40]!r}: printable ASCII of at most {self.NAME_SIZE - 1} "
                "characters"
            )
        return raw.ljust(self.NAME_SIZE, b"\0")

    @classmethod
    def _extra_fields(cls, extra: bytes) -> dict[str, Any]:
        if len(extra) > cls.NAME_SIZE:
            raise NativePayloadError(
                f"a name of {len(extra)} bytes, at most {cls.NAME_SIZE}",
                EW.LENGTH,
            )
        return {"name": bytes(extra).split(b"\0", 1)[0].decode("latin-1")}


@dataclass(frozen=True, slots=True)
class FolderText:
    """A folder's or a file's name as text (0xB0, 0xB9): the bytes as they came (the text
    and one NUL, as the simulator sends it: :meth:`of`); :attr:`text` reads to the first NUL
    [V: the library copies the text]."""

    raw: bytes

    @classmethod
    def of(cls, text: str) -> FolderText:
        """The answer carrying ``text``: its bytes and one NUL."""
        return cls(text.encode("latin-1", "replace") + b"\0")

    @property
    def text(self) -> str:
        return self.raw.split(b"\0", 1)[0].decode("latin-1")

    def encode(self) -> bytes:
        return self.raw

    @classmethod
    def decode(cls, data: bytes) -> FolderText:
        return cls(bytes(data))


# -- drives ------------------------------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class DriveName(NativeRecord):
    """One drive of 0xAE: its name NUL-padded in 12 bytes (``CNC_MEM``) [V]."""

    FORMAT: ClassVar[str] = ">12s"
    PADDED: ClassVar[frozenset[str]] = frozenset({"name"})
    name: bytes


@dataclass(frozen=True, slots=True)
class DriveNames(RecordArray[DriveName]):
    """0xAE answer: the drives, counted by the library from the length [V]."""

    ITEM: ClassVar[type[NativeRecord]] = DriveName
    records: tuple[DriveName, ...]


@dataclass(frozen=True, slots=True)
class DriveListRequest(NativeRequest):
    """0xAE, no arguments (``cnc_rdpdf_drive``) [V]."""

    COMMAND: ClassVar[int] = NativeCommand.RDPDF_DRIVE
    ANSWER: ClassVar[Any] = DriveNames


@dataclass(frozen=True, slots=True)
class DriveInfo(NativeRecord):
    """0xAF answer, ODBPDFINF: ``i32 used_page, all_page, used_dir, all_dir`` [V]."""

    FORMAT: ClassVar[str] = ">iiii"
    used_pages: int
    pages: int
    used_entries: int
    entries: int


@dataclass(frozen=True, slots=True)
class DriveInfoRequest(_NamedRequest):
    """0xAF ``(info)`` and the drive name in 12 extra bytes (``cnc_rdpdf_inf``) [V]."""

    COMMAND: ClassVar[int] = NativeCommand.RDPDF_INF
    ARGS: ClassVar[tuple[Any, ...]] = ("info", 0, 0, 0, EXTRA_LENGTH)
    ANSWER: ClassVar[Any] = DriveInfo
    NAME_SIZE: ClassVar[int] = DRIVE_NAME_SIZE
    name: str
    info: int = 0


# -- the current folder and the main program ---------------------------------------------------


@dataclass(frozen=True, slots=True)
class CurrentFolderRequest(NativeRequest):
    """0xB0 ``(kind)``: 1 foreground, 2 background (``cnc_rdpdf_curdir``) [V]."""

    COMMAND: ClassVar[int] = NativeCommand.RDPDF_CURDIR
    ARGS: ClassVar[tuple[Any, ...]] = ("kind",)
    ANSWER: ClassVar[Any] = FolderText
    kind: int = 1


@dataclass(frozen=True, slots=True)
class CurrentFolderWriteRequest(_NamedRequest):
    """0xB1 ``(kind)`` and the folder in 256 extra bytes (``cnc_wrpdf_curdir``) [V]."""

    COMMAND: ClassVar[int] = NativeCommand.WRPDF_CURDIR
    ARGS: ClassVar[tuple[Any, ...]] = ("kind", 0, 0, 0, EXTRA_LENGTH)
    ANSWER: ClassVar[Any] = NoData
    WRITE: ClassVar[bool] = True
    name: str
    kind: int = 1


@dataclass(frozen=True, slots=True)
class MainFileRequest(NativeRequest):
    """0xB9, no arguments: the main program's file (``cnc_pdf_rdmain``) [V]."""

    COMMAND: ClassVar[int] = NativeCommand.PDF_RDMAIN
    ANSWER: ClassVar[Any] = FolderText


@dataclass(frozen=True, slots=True)
class MainSelectRequest(_NamedRequest):
    """0xBA, the file in 256 extra bytes (``cnc_pdf_slctmain``) [V]."""

    COMMAND: ClassVar[int] = NativeCommand.PDF_SLCTMAIN
    ARGS: ClassVar[tuple[Any, ...]] = (0, 0, 0, 0, EXTRA_LENGTH)
    WRITE: ClassVar[bool] = True
    name: str


@dataclass(frozen=True, slots=True)
class FileDeleteRequest(_NamedRequest):
    """0xB6, the file in 256 extra bytes (``cnc_pdf_del``) [V]."""

    COMMAND: ClassVar[int] = NativeCommand.PDF_DEL
    ARGS: ClassVar[tuple[Any, ...]] = (0, 0, 0, 0, EXTRA_LENGTH)
    WRITE: ClassVar[bool] = True
    name: str


# -- folder listings ---------------------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class SubfolderRecord(NativeRecord):
    """One folder of 0xB2: ``i32 sub_exist`` (the library keeps the low 16 bits), the name
    in 36 bytes [V]."""

    FORMAT: ClassVar[str] = ">i36s"
    PADDED: ClassVar[frozenset[str]] = frozenset({"name"})
    has_folders: int
    name: bytes


@dataclass(frozen=True, slots=True)
class SubfolderRecords(RecordArray[SubfolderRecord]):
    """0xB2 answer: the folders, counted from the length [V]."""

    ITEM: ClassVar[type[NativeRecord]] = SubfolderRecord
    records: tuple[SubfolderRecord, ...]


@dataclass(frozen=True, slots=True)
class SubfolderRequest(_NamedRequest):
    """0xB2 ``(first, count)``, the folder in 256 extra bytes (``cnc_rdpdf_subdir``) [V]."""

    COMMAND: ClassVar[int] = NativeCommand.RDPDF_SUBDIR
    ARGS: ClassVar[tuple[Any, ...]] = ("first", "count", 0, 0, EXTRA_LENGTH)
    ANSWER: ClassVar[Any] = SubfolderRecords
    name: str
    first: int = 0
    count: int = 1


@dataclass(frozen=True, slots=True)
class FolderRecord(NativeRecord):
    """One entry of 0xB3, 128 bytes in ODBPDFADIR's order: ``i16 data_kind`` (0 folder, 1
    file), ``i16 year, month, day, hour, minute, second``, 2 bytes and an i32 the library
    skips, ``i32 size, u32 attr``, the name in 36 bytes, the comment in 52, the machining
    time stamp in 12 [V]."""

    FORMAT: ClassVar[str] = ">hhhhhhhhiiI36s52s12s"
    PADDED: ClassVar[frozenset[str]] = frozenset({"name", "comment", "o_time"})
    data_kind: int
    year: int
    month: int
    day: int
    hour: int
    minute: int
    second: int
    pad: int
    pad2: int
    size: int
    attr: int
    name: bytes
    comment: bytes
    o_time: bytes


@dataclass(frozen=True, slots=True)
class FolderRecords(RecordArray[FolderRecord]):
    """0xB3 answer: the entries, counted from the length [V]."""

    ITEM: ClassVar[type[NativeRecord]] = FolderRecord
    records: tuple[FolderRecord, ...]


@dataclass(frozen=True, slots=True)
class FolderListRequest(_NamedRequest):
    """0xB3 ``(first, count, type, size_kind)``, the folder in 256 extra bytes
    (``cnc_rdpdf_alldir``; IDBPDFADIR's ``req_num``, the caller's count up to 20, ``type``,
    ``size_kind``) [V]."""

    COMMAND: ClassVar[int] = NativeCommand.RDPDF_ALLDIR
    ARGS: ClassVar[tuple[Any, ...]] = ("first", "count", "detail", "size_kind", EXTRA_LENGTH)
    ANSWER: ClassVar[Any] = FolderRecords
    name: str
    first: int = 0
    count: int = 1
    detail: int = 0
    size_kind: int = 1


@dataclass(frozen=True, slots=True)
class FolderCount(NativeRecord):
    """0xB4 answer: ``i32 folders, i32 files`` (ODBPDFNFIL keeps the low 16 bits) [V]."""

    FORMAT: ClassVar[str] = ">ii"
    folders: int
    files: int


@dataclass(frozen=True, slots=True)
class FolderCountRequest(_NamedRequest):
    """0xB4, the folder in 256 extra bytes (``cnc_rdpdf_subdirn``) [V]."""

    COMMAND: ClassVar[int] = NativeCommand.RDPDF_SUBDIRN
    ARGS: ClassVar[tuple[Any, ...]] = (0, 0, 0, 0, EXTRA_LENGTH)
    ANSWER: ClassVar[Any] = FolderCount
    name: str


@dataclass(frozen=True, slots=True)
class FileInfo(NativeRecord):
    """0x2B1 answer, 84 bytes in ODBPDFPRG's order: ``i16 year, month, day, hour, minute,
    second, i32 size, u32 attr``, the comment in 52 bytes, the machining time stamp in 12
    [V]."""

    FORMAT: ClassVar[str] = ">hhhhhhiI52s12s"
    PADDED: ClassVar[frozenset[str]] = frozenset({"comment", "o_time"})
    year: int
    month: int
    day: int
    hour: int
    minute: int
    second: int
    size: int
    attr: int
    comment: bytes
    o_time: bytes


@dataclass(frozen=True, slots=True)
class FileInfoRequest(_NamedRequest):
    """0x2B1 ``(size_kind, brief)``, the file in 244 extra bytes (``cnc_rdpdf_prginf``):
    the library sends ``brief`` 1 for IDBPDFPRG's ``type`` 0 and 0 for any other ``type``
    [V]. ``detail`` is the ``type`` a server reads (0 or 1)."""

    COMMAND: ClassVar[int] = NativeCommand.RDPDF_PRGINF
    ARGS: ClassVar[tuple[Any, ...]] = ("size_kind", "brief", 0, 0, EXTRA_LENGTH)
    ANSWER: ClassVar[Any] = FileInfo
    NAME_SIZE: ClassVar[int] = FILE_NAME_SIZE
    name: str
    size_kind: int = 1
    brief: int = 0

    @property
    def detail(self) -> int:
        return 0 if self.brief else 1


_register(
    DriveListRequest,
    DriveInfoRequest,
    CurrentFolderRequest,
    CurrentFolderWriteRequest,
    SubfolderRequest,
    FolderListRequest,
    FolderCountRequest,
    FileDeleteRequest,
    MainFileRequest,
    MainSelectRequest,
    FileInfoRequest,
)


# -- what each function sends (the same in both command sets) ----------------------------------


def _one(function: str, request: NativeRequest) -> LibraryCall:
    return LibraryCall(function, ((request,),))


def cnc_rdpdf_drive(cs: CommandSet) -> LibraryCall:
    """0xAE, no arguments [V]."""
    return _one("cnc_rdpdf_drive", DriveListRequest())


def cnc_rdpdf_inf(cs: CommandSet, drive: str, info: int) -> LibraryCall:
    """0xAF ``(info)``, the drive name in 12 extra bytes [V]."""
    return _one("cnc_rdpdf_inf", DriveInfoRequest(drive, info))


def cnc_rdpdf_curdir(cs: CommandSet, kind: int) -> LibraryCall:
    """0xB0 ``(kind)`` [V]."""
    return _one("cnc_rdpdf_curdir", CurrentFolderRequest(kind))


def cnc_wrpdf_curdir(cs: CommandSet, kind: int, folder: str) -> LibraryCall:
    """0xB1 ``(kind)``, the folder in 256 extra bytes [V]."""
    return _one("cnc_wrpdf_curdir", CurrentFolderWriteRequest(folder, kind))


def cnc_rdpdf_subdir(cs: CommandSet, folder: str, first: int, count: int) -> LibraryCall:
    """0xB2 ``(first, count)``, the folder in 256 extra bytes [V]."""
    return _one("cnc_rdpdf_subdir", SubfolderRequest(folder, first, count))


def cnc_rdpdf_alldir(
    cs: CommandSet, folder: str, first: int, count: int, detail: int, size_kind: int
) -> LibraryCall:
    """0xB3 ``(first, count, type, size_kind)``, the folder in 256 extra bytes [V]."""
    return _one("cnc_rdpdf_alldir", FolderListRequest(folder, first, count, detail, size_kind))


def cnc_rdpdf_subdirn(cs: CommandSet, folder: str) -> LibraryCall:
    """0xB4, the folder in 256 extra bytes [V]."""
    return _one("cnc_rdpdf_subdirn", FolderCountRequest(folder))


def cnc_rdpdf_prginf(cs: CommandSet, name: str, size_kind: int, detail: int) -> LibraryCall:
    """0x2B1 ``(size_kind, 1 for type 0 else 0)``, the file in 244 extra bytes [V]."""
    return _one("cnc_rdpdf_prginf", FileInfoRequest(name, size_kind, int(detail == 0)))


def cnc_pdf_del(cs: CommandSet, name: str) -> LibraryCall:
    """0xB6, the file in 256 extra bytes [V]."""
    return _one("cnc_pdf_del", FileDeleteRequest(name))


def cnc_pdf_rdmain(cs: CommandSet) -> LibraryCall:
    """0xB9, no arguments [V]."""
    return _one("cnc_pdf_rdmain", MainFileRequest())


def cnc_pdf_slctmain(cs: CommandSet, name: str) -> LibraryCall:
    """0xBA, the file in 256 extra bytes [V]."""
    return _one("cnc_pdf_slctmain", MainSelectRequest(name))
