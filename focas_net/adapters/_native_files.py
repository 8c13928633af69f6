"""The native adapter's program folders (``docs/native-protocol.md``, "Program folders"): the
handlers of the folder requests of a 30i-class control (:mod:`focas_net.native.files`; what
a handler is: :mod:`focas_net.adapters.native`), answered from the machine's folder tree
(:mod:`focas_net.sim._folders`: the drive ``CNC_MEM``, the paths' programs as files of
``//CNC_MEM/USER/PATHn/``).

A block answers for the path in its path word (0 is path 1): a relative name is of that
path's current folder, the current folder and the main program are that path's. A machine of
the 16i class has no folders and answers EW_FUNC (the machine's refusal), as such a control
does. The wire's own checks: a listing's count below 1 is EW_LENGTH, its ``type`` and
``size_kind`` outside those FANUC gives are EW_DATA; a listing holds at most what was asked
and what the answer has room for; a first entry past the folder's last is EW_NUMBER.
"""

from __future__ import annotations

from typing import Final

from focas_net.errors import EW
from focas_net.native import (
    MAX_DRIVES,
    CurrentFolderRequest,
    CurrentFolderWriteRequest,
    DriveInfo,
    DriveInfoRequest,
    DriveName,
    FileDeleteRequest,
    FileInfo,
    FileInfoRequest,
    FolderCount,
    FolderCountRequest,
    FolderListRequest,
    FolderRecord,
    FolderText,
    MainSelectRequest,
    RequestBlock,
    SubfolderRecord,
    SubfolderRequest,
    check_detail,
    size_in,
    stamp_fields,
)
from focas_net.sim import Machine, Session

from ._common import Refused
from ._native_cnc import block_path

__all__ = ["FileHandlers"]

#: ``size_kind`` of pages (a drive's capacity is told in pages).
_PAGES: Final = 0


def _text(value: str) -> bytes:
    return value.encode("latin-1", "replace")


class FileHandlers:
    """The program folders of one machine (see the module docstring)."""

    __slots__ = ("machine",)

    def __init__(self, machine: Machine) -> None:
        self.machine = machine

    def read_drives(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0xAE: the drives' names, 12 bytes each (at most 16, ODBPDFDRV's room)."""
        drives = self.machine.program_drives()[:MAX_DRIVES]
        return b"".join(DriveName(_text(d)).encode() for d in drives)

    def read_drive_info(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0xAF: characters used and the capacity in pages, entries used and the most."""
        req = DriveInfoRequest.from_block(block)
        usage = self.machine.drive_usage(req.name)
        return DriveInfo(
            size_in(usage.used, _PAGES),
            size_in(usage.capacity, _PAGES),
            usage.entries,
            usage.most_entries,
        ).encode()

    def read_current_folder(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0xB0: the path's current folder of ``kind`` (1 foreground, 2 background)."""
        kind = CurrentFolderRequest.from_block(block).kind
        return FolderText.of(self.machine.current_folder(kind, path=block_path(block))).encode()

    def write_current_folder(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0xB1: the machine's ``set_current_folder`` (EW_DATA for no such folder)."""
        req = CurrentFolderWriteRequest.from_block(block)
        self.machine.set_current_folder(req.name, req.kind, path=block_path(block))
        return b""

    def read_subfolders(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0xB2: the folders of a folder from entry ``first`` on, 40 bytes each."""
        req = SubfolderRequest.from_block(block)
        entries = self.machine.folder_entries(req.name, path=block_path(block))
        folders = [e for e in entries if e.is_folder]
        chosen = _window(len(folders), req.first, req.count, room // SubfolderRecord.SIZE)
        return b"".join(
            SubfolderRecord(int(e.has_folders), _text(e.name)).encode() for e in folders[chosen]
        )

    def read_folder(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0xB3: the entries of a folder (its folders, then its files) from ``first`` on,
        128 bytes each: a folder's kind 0, a file's 1 with its date; with ``type`` 1 the
        file's size in ``size_kind``'s unit and its comment."""
        req = FolderListRequest.from_block(block)
        check_detail(req.detail)
        size_in(0, req.size_kind)  # EW_DATA for a unit there is not
        entries = self.machine.folder_entries(req.name, path=block_path(block))
        chosen = _window(len(entries), req.first, req.count, room // FolderRecord.SIZE)
        out = []
        for e in entries[chosen]:
            full = req.detail == 1 and not e.is_folder
            out.append(
                FolderRecord(
                    0 if e.is_folder else 1,
                    *stamp_fields(e.stamped),
                    0,
                    0,
                    size_in(e.size, req.size_kind) if full else 0,
                    0,
                    _text(e.name),
                    _text(e.comment[:51]) if full else b"",
                    b"",
                ).encode()
            )
        return b"".join(out)

    def read_folder_count(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0xB4: how many folders and files a folder holds."""
        name = FolderCountRequest.from_block(block).name
        entries = self.machine.folder_entries(name, path=block_path(block))
        folders = sum(e.is_folder for e in entries)
        return FolderCount(folders, len(entries) - folders).encode()

    def read_file_info(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0x2B1: a file's date, its size in ``size_kind``'s unit and its comment (``type``
        1; ``type`` 0 without them)."""
        req = FileInfoRequest.from_block(block)
        check_detail(req.detail)
        size_in(0, req.size_kind)
        e = self.machine.file_entry(req.name, path=block_path(block))
        full = req.detail == 1
        return FileInfo(
            *stamp_fields(e.stamped),
            size_in(e.size, req.size_kind) if full else 0,
            0,
            _text(e.comment[:51]) if full else b"",
            b"",
        ).encode()

    def delete_file(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0xB6: the machine's ``delete_file`` (EW_DATA, EW_PROT, EW_REJECT)."""
        name = FileDeleteRequest.from_block(block).name
        self.machine.delete_file(name, path=block_path(block))
        return b""

    def read_main_file(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0xB9: the file of the path's main program (empty when none is)."""
        return FolderText.of(self.machine.main_file(path=block_path(block))).encode()

    def select_main_file(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0xBA: the machine's ``select_main_file`` (EW_DATA, then the program search's
        EW_PROT, EW_MODE, EW_BUSY)."""
        name = MainSelectRequest.from_block(block).name
        self.machine.select_main_file(name, path=block_path(block))
        return b""


def _window(total: int, first: int, count: int, room: int) -> slice:
    """The entries from ``first`` on, at most ``count`` and ``room`` of them: EW_LENGTH for
    a count below 1, EW_NUMBER for a first entry outside the folder."""
    if count < 1:
        raise Refused(EW.LENGTH)
    if not 0 <= first < total:
        raise Refused(EW.NUMBER)
    return slice(first, first + min(count, room))
