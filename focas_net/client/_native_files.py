"""The program folders of a 30i-class control through the native client
(``docs/native-client.md``, "Program folders").

:class:`NativeFiles` is the part of :class:`~focas_net.client.NativeClient` that reads the
drives and folders of the CNC's program memory (``cnc_rdpdf_*``), deletes a program by its
file name (``cnc_pdf_del``) and reads and selects the main program by its file
(``cnc_pdf_rdmain``, ``cnc_pdf_slctmain``). Each call sends the frames FANUC's library sends
(:mod:`focas_net.native.files`, the same in both command sets). A control of the 16i class
has no folders: it answers EW_FUNC, raised as :class:`~focas_net.errors.CncError`.

A name is checked and its frame encoded in the caller's frame, before anything is sent:
printable ASCII of at most 255 characters (243 for ``read_file_info``, 11 for a drive).
"""

# Every call takes a per-call ``timeout=`` by contract, so ASYNC109 does not apply here.
# ruff: noqa: ASYNC109

from __future__ import annotations

from dataclasses import dataclass
from datetime import datetime
from typing import Any, Final

from focas_net.errors import EW, CncError

from .._refusals import folder_refusal
from ..native import (
    MAX_FOLDER_ENTRIES,
    SIZE_UNITS,
    CommandSet,
    DriveInfo,
    DriveNames,
    FileInfo,
    FolderCount,
    FolderRecords,
    FolderText,
    LibraryCall,
    SubfolderRecords,
    cnc_pdf_del,
    cnc_pdf_rdmain,
    cnc_pdf_slctmain,
    cnc_rdpdf_alldir,
    cnc_rdpdf_curdir,
    cnc_rdpdf_drive,
    cnc_rdpdf_inf,
    cnc_rdpdf_prginf,
    cnc_rdpdf_subdir,
    cnc_rdpdf_subdirn,
    cnc_wrpdf_curdir,
)
from ._native_items import only_answer, text
from ._native_link import NativeLink
from ._values import check_int

__all__ = ["DriveUsage", "FolderCounts", "FolderEntry", "ProgramFileInfo"]

#: The set the folder frames are encoded in before the handle is known: both sets send the
#: same frames.
_ANY_SET: Final = CommandSet.FS30I
#: Most entries of a folder a listing reads (the library's per-request 20, many times).
_MOST_ENTRIES: Final = 10_000


@dataclass(frozen=True, slots=True)
class DriveUsage:
    """``cnc_rdpdf_inf``: the drive's pages used and all its pages (256 characters each on
    the simulator), its folders and files and the most it holds."""

    used_pages: int
    pages: int
    used_entries: int
    entries: int


@dataclass(frozen=True, slots=True)
class FolderEntry:
    """One entry of a folder (``cnc_rdpdf_alldir``): a folder or a file, its last change
    (None when the CNC gives no date), and for a file its size in the unit asked, its
    attribute word and its comment."""

    name: str
    is_folder: bool
    modified: datetime | None
    size: int
    attributes: int
    comment: str


@dataclass(frozen=True, slots=True)
class FolderCounts:
    """``cnc_rdpdf_subdirn``: the folders and the files a folder holds."""

    folders: int
    files: int


@dataclass(frozen=True, slots=True)
class ProgramFileInfo:
    """``cnc_rdpdf_prginf``: a program file's last change, size (in the unit asked),
    attribute word and comment."""

    modified: datetime | None
    size: int
    attributes: int
    comment: str


def _when(year: int, month: int, day: int, hour: int, minute: int, second: int) -> datetime | None:
    """The date of a record; None for no date (zeros) or one that is no date."""
    try:
        return datetime(year, month, day, hour, minute, second)
    except ValueError:
        return None


def _size_kind(size_kind: int) -> int:
    return check_int("size kind", size_kind, 0, len(SIZE_UNITS) - 1)


class NativeFiles(NativeLink):
    """The program folders over FOCAS/2 (see the module docstring)."""

    async def _one(
        self, call: LibraryCall, path: int | None, timeout: float | None, name: str | None = None
    ) -> Any:
        """The decoded answer of ``call`` (one frame, one block) on ``path``; a refusal of
        ``name`` (the drive, folder or file the call names) says what the CNC has not."""
        p = self._path_of(path)
        deadline = self._deadline(timeout)
        handle = self._handle_now() or await self._handle_for(deadline)
        try:
            return only_answer(handle, call, await self._exchange(handle, call, deadline, 0, p))
        except CncError as exc:
            why = None if name is None else folder_refusal(exc.ew, exc.detail, name)
            if why is None:
                raise
            raise CncError.from_ew(exc.ew, f"{exc.detail}: {why}") from None

    async def read_drives(
        self, *, path: int | None = None, timeout: float | None = None
    ) -> tuple[str, ...]:
        """``cnc_rdpdf_drive``: the drives of the program memory (``CNC_MEM``...)."""
        names: DriveNames = await self._one(cnc_rdpdf_drive(_ANY_SET), path, timeout)
        return tuple(text(r.name) for r in names.records)

    async def read_drive_usage(
        self, drive: str = "//CNC_MEM/", *, path: int | None = None, timeout: float | None = None
    ) -> DriveUsage:
        """``cnc_rdpdf_inf``: how much of ``drive`` is used."""
        info: DriveInfo = await self._one(cnc_rdpdf_inf(_ANY_SET, drive, 0), path, timeout, drive)
        return DriveUsage(info.used_pages, info.pages, info.used_entries, info.entries)

    async def read_current_folder(
        self, kind: int = 1, *, path: int | None = None, timeout: float | None = None
    ) -> str:
        """``cnc_rdpdf_curdir``: the path's current folder, ``kind`` 1 foreground (the
        default) or 2 background."""
        check_int("folder kind", kind, 1, 2)
        folder: FolderText = await self._one(cnc_rdpdf_curdir(_ANY_SET, kind), path, timeout)
        return folder.text

    async def write_current_folder(
        self, folder: str, kind: int = 1, *, path: int | None = None, timeout: float | None = None
    ) -> None:
        """``cnc_wrpdf_curdir``: make ``folder`` the path's current folder of ``kind``
        (EW_DATA for a folder the CNC has not)."""
        check_int("folder kind", kind, 1, 2)
        await self._one(cnc_wrpdf_curdir(_ANY_SET, kind, folder), path, timeout, folder)

    async def read_subfolders(
        self, folder: str, *, path: int | None = None, timeout: float | None = None
    ) -> list[tuple[str, bool]]:
        """``cnc_rdpdf_subdir``: the folders in ``folder``, each with whether it holds
        folders itself (20 a request, until the folder's last)."""
        out: list[tuple[str, bool]] = []
        while len(out) < _MOST_ENTRIES:
            call = cnc_rdpdf_subdir(_ANY_SET, folder, len(out), MAX_FOLDER_ENTRIES)
            records: SubfolderRecords | None = await self._listing(call, path, timeout, folder)
            if records is None:
                break
            out.extend((text(r.name), bool(r.has_folders & 0xFFFF)) for r in records.records)
            if len(records.records) < MAX_FOLDER_ENTRIES:
                break
        return out

    async def read_folder(
        self,
        folder: str,
        *,
        size_kind: int = 1,
        path: int | None = None,
        timeout: float | None = None,
    ) -> list[FolderEntry]:
        """``cnc_rdpdf_alldir``: every entry of ``folder`` (its folders, then its files), 20
        a request as FANUC's library asks, with sizes in ``size_kind``'s unit: 0 pages, 1
        bytes (the default), 2 kilobytes, 3 megabytes."""
        _size_kind(size_kind)
        out: list[FolderEntry] = []
        while len(out) < _MOST_ENTRIES:
            call = cnc_rdpdf_alldir(_ANY_SET, folder, len(out), MAX_FOLDER_ENTRIES, 1, size_kind)
            records: FolderRecords | None = await self._listing(call, path, timeout, folder)
            if records is None:
                break
            out.extend(
                FolderEntry(
                    text(r.name),
                    r.data_kind == 0,
                    _when(r.year, r.month, r.day, r.hour, r.minute, r.second),
                    r.size,
                    r.attr,
                    text(r.comment),
                )
                for r in records.records
            )
            if len(records.records) < MAX_FOLDER_ENTRIES:
                break
        return out

    async def _listing(
        self, call: LibraryCall, path: int | None, timeout: float | None, folder: str
    ) -> Any:
        """One request of a listing of ``folder``; None at its end (EW_NUMBER after the first
        entry, or for a folder with no entry)."""
        try:
            return await self._one(call, path, timeout, folder)
        except CncError as exc:
            if exc.ew == EW.NUMBER:
                return None
            raise

    async def read_folder_counts(
        self, folder: str, *, path: int | None = None, timeout: float | None = None
    ) -> FolderCounts:
        """``cnc_rdpdf_subdirn``: how many folders and files ``folder`` holds."""
        count: FolderCount = await self._one(
            cnc_rdpdf_subdirn(_ANY_SET, folder), path, timeout, folder
        )
        return FolderCounts(count.folders & 0xFFFF, count.files & 0xFFFF)

    async def read_file_info(
        self,
        name: str,
        *,
        size_kind: int = 1,
        path: int | None = None,
        timeout: float | None = None,
    ) -> ProgramFileInfo:
        """``cnc_rdpdf_prginf``: a program file's date, size (in ``size_kind``'s unit, as
        :meth:`read_folder`), attributes and comment (EW_DATA for no such file)."""
        _size_kind(size_kind)
        call = cnc_rdpdf_prginf(_ANY_SET, name, size_kind, 1)
        info: FileInfo = await self._one(call, path, timeout, name)
        return ProgramFileInfo(
            _when(info.year, info.month, info.day, info.hour, info.minute, info.second),
            info.size,
            info.attr,
            text(info.comment),
        )

    async def delete_file(
        self, name: str, *, path: int | None = None, timeout: float | None = None
    ) -> None:
        """``cnc_pdf_del``: delete the program of file ``name`` (a full name such as
        ``//CNC_MEM/USER/PATH1/O0001``, or one of the current folder): EW_DATA for no such
        file, EW_PROT on a protected CNC, EW_REJECT while it is being executed."""
        await self._one(cnc_pdf_del(_ANY_SET, name), path, timeout, name)

    async def read_main_file(self, *, path: int | None = None, timeout: float | None = None) -> str:
        """``cnc_pdf_rdmain``: the file of the path's main program ("" when none is)."""
        main: FolderText = await self._one(cnc_pdf_rdmain(_ANY_SET), path, timeout)
        return main.text

    async def select_main_file(
        self, name: str, *, path: int | None = None, timeout: float | None = None
    ) -> None:
        """``cnc_pdf_slctmain``: make the program of file ``name`` the path's main program
        (EW_DATA for no file of the path's folder; EW_MODE outside MEM and EDIT)."""
        await self._one(cnc_pdf_slctmain(_ANY_SET, name), path, timeout, name)
