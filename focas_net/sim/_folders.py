"""The program folders of a 30i-class control: the data server's tree on the drive ``CNC_MEM``.

A FANUC 30i, 31i, 32i, 0i-D or 0i-F keeps its part programs as files in folders::

    //CNC_MEM/
        SYSTEM/   MTB1/   MTB2/          the control's and the machine builder's (empty here)
        USER/
            PATH1/ ... PATHn/            the programs of each path, files O0001 ...
            LIBRARY/                     programs every path may call (empty here)

The programs a path stores (its :class:`~focas_net.sim.nc.ProgramStore`) are the files of
its folder ``//CNC_MEM/USER/PATHn/``, named ``O`` and the O number in at least four digits,
with the program's characters as their size, its name as their comment and the time it was
last stored as their date (a program the machine was built with: the time its folder was
first read; the clock is not read while the machine is built). Each path has a current
folder for the foreground and one for the background (both its own folder until changed),
and a main program, which is a file of its folder.

A 16i, 18i, 21i or 0i-C has no program folders: every operation here refuses it with
EW_FUNC, as such a control answers the functions of the folders.

The checks, in order: EW_FUNC (a control without folders), EW_PATH (a path the machine has
not), EW_NUMBER (an entry past a folder's last), EW_DATA (a name that is no folder or no file
of the tree), then the program store's own (EW_PROT on a read-only machine first, for what
writes). A file deleted through its folder is a program deleted: while it is being executed
the control refuses with EW_REJECT, as a CNC in operation refuses a folder operation.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from datetime import datetime
from typing import TYPE_CHECKING, Final

from focas_net.errors import EW

from ._base import MachineError, need_int, need_text
from ._identity import CLASSES_16I
from ._operations import PathOperations

if TYPE_CHECKING:
    from .nc import ProgramInfo

__all__ = [
    "DRIVE",
    "FOLDERLESS_CLASSES",
    "FolderEntry",
    "FolderOperations",
    "FolderUsage",
    "path_folder",
]

#: The one drive of the simulated control: its program memory.
DRIVE: Final = "CNC_MEM"
#: Control classes that have no program folders (they answer EW_FUNC).
FOLDERLESS_CLASSES: Final = CLASSES_16I
#: Folders the control keeps for itself and the machine builder: always empty here.
_SYSTEM_FOLDERS: Final = ("SYSTEM", "MTB1", "MTB2")
#: Most characters of a folder or file name, a full name (``//CNC_MEM/USER/PATH1/O0001``)
#: included.
MAX_NAME: Final = 255
#: Foreground (1) and background (2) current folders.
_KINDS: Final = (1, 2)

_FILE: Final = re.compile(r"O(\d{1,8})")


def path_folder(path: int) -> str:
    """The folder of path ``path``'s programs: ``//CNC_MEM/USER/PATH1/``."""
    return f"//{DRIVE}/USER/PATH{path}/"


def _name(name: object, what: str) -> str:
    """``name`` when it is text; TypeError naming what was given otherwise, as every call of
    the machine refuses a value of another type."""
    return need_text(what, name)


def file_name(number: int) -> str:
    """The file name of program ``number``: ``O0001``, ``O12345``."""
    return f"O{number:04d}"


@dataclass(frozen=True, slots=True)
class FolderEntry:
    """One entry of a folder: a folder (``is_folder``, ``has_folders`` when it holds folders
    itself) or a program's file (its characters, its name as the comment, its date)."""

    name: str
    is_folder: bool
    size: int = 0
    comment: str = ""
    stamped: datetime | None = None
    has_folders: bool = False


@dataclass(frozen=True, slots=True)
class FolderUsage:
    """A drive's use: characters stored and its capacity, entries (folders and files) and
    the most it holds."""

    used: int
    capacity: int
    entries: int
    most_entries: int


class FolderOperations(PathOperations):
    """The program folders of the machine (a base of :class:`~focas_net.sim.Machine`, see
    the module docstring)."""

    control_class: str
    _folder_built: datetime | None
    _folder_stamps: dict[tuple[int, int], datetime]
    _folder_current: dict[tuple[int, int], str]

    def now(self) -> datetime:  # pragma: no cover - the machine's
        raise NotImplementedError

    def _init_folders(self) -> None:
        #: The date of the programs the machine was built with: the clock's time when a
        #: folder is first read (the clock is not read while the machine is built).
        self._folder_built = None
        self._folder_stamps = {}
        self._folder_current = {}

    # -- the tree ------------------------------------------------------------------------
    def _check_folders(self) -> None:
        if self.control_class in FOLDERLESS_CLASSES:
            raise MachineError(EW.FUNC, f"a {self.control_class} has no program folders")

    def _folder_key(self, name: str, path: int) -> tuple[str, ...]:
        """The parts of folder ``name`` (``("USER", "PATH1")``; ``()`` the drive): absolute
        (``//CNC_MEM/...``, the final ``/`` optional) or relative to ``path``'s current
        folder. EW_DATA for a folder the tree has not."""
        parts = self._parts(name, path)
        if self._folder_children(parts) is None:
            raise MachineError(EW.DATA, f"no folder {name!r}")
        return parts

    def _parts(self, name: str, path: int) -> tuple[str, ...]:
        text = _name(name, "folder or file name").strip()
        if not text or len(text) > MAX_NAME or not text.isascii() or not text.isprintable():
            raise MachineError(
                EW.DATA,
                f"folder or file name {text[:40]!r}: 1..{MAX_NAME} printable ASCII characters",
            )
        if not text.startswith("//"):
            text = self._folder_current.get((path, 1), path_folder(path)) + text
        drive, _, rest = text[2:].partition("/")
        if drive.upper() != DRIVE:
            raise MachineError(EW.DATA, f"no drive {drive!r}: the control has {DRIVE}")
        return tuple(p.upper() for p in rest.split("/") if p)

    def _folder_children(self, parts: tuple[str, ...]) -> list[str] | None:
        """The folders in folder ``parts``; None when there is no such folder."""
        if not parts:
            return [*_SYSTEM_FOLDERS, "USER"]
        if len(parts) == 1 and parts[0] in _SYSTEM_FOLDERS:
            return []
        if parts == ("USER",):
            count = self._paths.count
            return [*(f"PATH{p}" for p in range(1, count + 1)), "LIBRARY"]
        paths = range(1, self._paths.count + 1)
        if len(parts) == 2 and parts[0] == "USER":
            if parts[1] == "LIBRARY" or parts[1] in {f"PATH{p}" for p in paths}:
                return []
        return None

    def _folder_path(self, parts: tuple[str, ...]) -> int | None:
        """The path whose programs folder ``parts`` holds (None: no path's, ``PATH01`` and
        ``PATHX`` included: the tree's folders are ``PATH1`` ... ``PATHn``)."""
        if len(parts) == 2 and parts[0] == "USER":
            for p in range(1, self._paths.count + 1):
                if parts[1] == f"PATH{p}":
                    return p
        return None

    def _file_entry(self, path: int, info: ProgramInfo) -> FolderEntry:
        stamped = self._folder_stamps.get((path, info.number))
        if stamped is None:
            if self._folder_built is None:
                self._folder_built = self.now()
            stamped = self._folder_built
        return FolderEntry(file_name(info.number), False, info.size, info.name, stamped)

    # -- reads ---------------------------------------------------------------------------
    def program_drives(self) -> tuple[str, ...]:
        """The drives of the control's programs (``cnc_rdpdf_drive``): ``CNC_MEM``."""
        self._check_folders()
        return (DRIVE,)

    def folder_entries(self, folder: str, *, path: int = 1) -> list[FolderEntry]:
        """The entries of ``folder`` (``cnc_rdpdf_alldir``): its folders, then its files by
        number. A relative name is of ``path``'s current folder."""
        self._check_folders()
        self._paths.at(path)
        parts = self._folder_key(folder, path)
        children = self._folder_children(parts) or []
        out = [
            FolderEntry(name, True, has_folders=bool(self._folder_children((*parts, name))))
            for name in children
        ]
        owner = self._folder_path(parts)
        if owner is not None:
            out.extend(self._file_entry(owner, e) for e in self.program_directory(path=owner))
        return out

    def file_entry(self, name: str, *, path: int = 1) -> FolderEntry:
        """The entry of file ``name`` (``cnc_rdpdf_prginf``): EW_DATA when there is none."""
        owner, number = self._file_of(name, path)
        for info in self.program_directory(path=owner):
            if info.number == number:
                return self._file_entry(owner, info)
        raise MachineError(EW.DATA, f"no file {name!r}")

    def _file_of(self, name: str, path: int) -> tuple[int, int]:
        """``(path, number)`` of the program file ``name`` (EW_DATA for no file's name)."""
        self._check_folders()
        self._paths.at(path)
        parts = self._parts(name, path)
        owner = self._folder_path(parts[:-1]) if parts else None
        match = _FILE.fullmatch(parts[-1]) if parts else None
        if owner is None or match is None:
            raise MachineError(EW.DATA, f"no program file {name!r}")
        return owner, int(match.group(1))

    def drive_usage(self, drive: str) -> FolderUsage:
        """What drive ``drive`` holds (``cnc_rdpdf_inf``): the characters of every path's
        programs and the paths' capacity; the folders and files and the most of them."""
        self._check_folders()
        if _name(drive, "drive").strip().strip("/").upper() != DRIVE:
            raise MachineError(EW.DATA, f"no drive {drive!r}: the control has {DRIVE}")
        used = capacity = files = most = 0
        for p in range(1, self._paths.count + 1):
            store = self._paths.at(p).programs
            directory = store.directory()
            used += sum(e.size for e in directory)
            capacity += store.capacity
            files += len(directory)
            most += store.max_programs
        folders = len(_SYSTEM_FOLDERS) + 2 + self._paths.count  # and USER, LIBRARY
        return FolderUsage(used, capacity, folders + files, folders + most)

    def current_folder(self, kind: int = 1, *, path: int = 1) -> str:
        """``path``'s current folder (``cnc_rdpdf_curdir``): ``kind`` 1 foreground, 2
        background (EW_DATA otherwise)."""
        need_int("current folder kind", kind)
        self._check_folders()
        self._paths.at(path)
        if kind not in _KINDS:
            raise MachineError(EW.DATA, f"current folder kind {kind!r}: 1 or 2")
        return self._folder_current.get((path, kind), path_folder(path))

    def main_file(self, *, path: int = 1) -> str:
        """The file of ``path``'s main program (``cnc_pdf_rdmain``); empty when none is."""
        self._check_folders()
        main = self.path_motion(path=path).program_main
        if main <= 0 or main not in self._paths.at(path).programs:
            return ""
        return path_folder(path) + file_name(main)

    def transfer_path(self, name: str, *, path: int = 1) -> int:
        """The path whose programs a transfer named ``name`` moves (``cnc_upstart4`` gives a
        file, ``cnc_dwnstart4`` a folder): the path of the ``PATHn`` folder ``name`` is or
        holds. A name of no folder (``O0001``, empty) is ``path``'s, and so is every name on
        a control without folders. EW_DATA for a folder that is not a path's (the simulator
        keeps programs in the paths' folders only) or no folder of the tree."""
        self._paths.at(path)
        text = _name(name, "folder or file name").strip()
        if self.control_class in FOLDERLESS_CLASSES or not text.startswith("//"):
            return path
        parts = self._parts(text, path)
        if _FILE.fullmatch(parts[-1] if parts else ""):
            parts = parts[:-1]
        owner = self._folder_path(parts)
        if owner is None:
            raise MachineError(EW.DATA, f"no folder of a path's programs: {name[:60]!r}")
        return owner

    # -- writes --------------------------------------------------------------------------
    def set_current_folder(self, folder: str, kind: int = 1, *, path: int = 1) -> None:
        """Make ``folder`` ``path``'s current folder (``cnc_wrpdf_curdir``)."""
        need_int("current folder kind", kind)
        self._check_folders()
        self._paths.at(path)
        if kind not in _KINDS:
            raise MachineError(EW.DATA, f"current folder kind {kind!r}: 1 or 2")
        parts = self._folder_key(folder, path)
        self._folder_current[(path, kind)] = f"//{DRIVE}/" + "".join(p + "/" for p in parts)

    def delete_file(self, name: str, *, path: int = 1) -> None:
        """Delete the program of file ``name`` (``cnc_pdf_del``): EW_DATA (no such file, or
        a folder: the control's folders stay), EW_PROT (read-only machine), EW_REJECT (the
        program is being executed)."""
        owner, number = self._file_of(name, path)
        self.check_writable()
        if number not in self._paths.at(owner).programs:
            raise MachineError(EW.DATA, f"no file {name!r}")
        try:
            self.delete_program(number, path=owner)
        except MachineError as exc:
            if exc.ew == EW.BUSY:
                raise MachineError(EW.REJECT, exc.detail) from None
            raise

    def select_main_file(self, name: str, *, path: int = 1) -> None:
        """Make the program of file ``name`` ``path``'s main program (``cnc_pdf_slctmain``):
        EW_DATA for no file of ``path``'s folder, then the program search's refusals."""
        owner, number = self._file_of(name, path)
        if owner != path or number not in self._paths.at(owner).programs:
            raise MachineError(EW.DATA, f"no file {name!r} in {path_folder(path)}")
        self.select_program(number, path=path)

    # -- the dates of the files ----------------------------------------------------------
    def store_program(self, text: str, *, path: int = 1, replace: bool = False) -> int:
        number = super().store_program(text, path=path, replace=replace)
        self._folder_stamps[(path, number)] = self.now()
        return number

    def delete_program(self, number: int, *, path: int = 1) -> None:
        super().delete_program(number, path=path)
        self._folder_stamps.pop((path, number), None)
