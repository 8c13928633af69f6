"""A machine's nonvolatile memory in a file: the format, the atomic write and the loading.

``serve --state DIR`` keeps one file per machine in ``DIR`` (:func:`state_path`: the machine's
name, quoted, with ``.state``). The file (``docs/machine-file.md``, "State files") is one
header line and one JSON document::

    focas-net-state 1 <length of the body> <SHA-256 of the body, hex>\\n
    {"machine": NAME, "shape": {...}, "kept": {...}}

``shape`` is what the kept data must fit (:func:`focas_net.sim.nonvolatile.shape`); ``kept`` is
what the machine keeps across power-off (:func:`focas_net.sim.nonvolatile.capture`).

A file is replaced, never changed in place: the new content goes to a temporary file in the
same directory, which is flushed to the disk (``fsync``), renamed over the old one, and the
directory is flushed too. A crash at any instant leaves either the old file or the new one,
whole; a temporary file it left behind is removed at the next start. The header's length and
checksum catch a file damaged some other way.

Loading (:meth:`StateFile.load`) builds the machine from its machine file as before, then
puts the kept data back. Every refusal is a :class:`StateError` naming the file: not a state
file, a format version newer than this one reads, a truncated or corrupted file, a state
written for a machine of another shape (naming the differences). The machine that was being
restored is dropped, so no half-loaded machine is ever served. A state file of an older format
version is brought up to date first (:data:`UPGRADES`; version 1 is the first).
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import os
from collections.abc import Callable, Iterable
from pathlib import Path
from typing import TYPE_CHECKING, Any, Final
from urllib.parse import quote

from .nonvolatile import StateMismatch, capture, restore, shape, shape_differences

if TYPE_CHECKING:
    from .machine import Machine

__all__ = [
    "STATE_MAGIC",
    "STATE_SUFFIX",
    "STATE_VERSION",
    "UPGRADES",
    "StateError",
    "StateFile",
    "decode_state",
    "encode_state",
    "save_all",
    "state_path",
    "sync_folder",
]

#: The first word of a state file.
STATE_MAGIC: Final = "focas-net-state"
#: The format version this version of the project writes (and the newest it reads).
STATE_VERSION: Final = 1
#: The file name suffix of a state file.
STATE_SUFFIX: Final = ".state"
#: Format version -> the function that brings a document of that version to the next one.
UPGRADES: Final[dict[int, Callable[[dict[str, Any]], dict[str, Any]]]] = {}
_TEMP_SUFFIX: Final = ".tmp"
_MAX_HEADER: Final = 200


class StateError(ValueError):
    """A state file that cannot be loaded; the message names the file and the reason."""


def state_path(directory: str | os.PathLike[str], name: str) -> Path:
    """The state file of the machine called ``name`` in ``directory``."""
    return Path(directory) / (quote(name, safe="") + STATE_SUFFIX)


def encode_state(machine: Machine) -> bytes:
    """The bytes of ``machine``'s state file, as it is now."""
    body = json.dumps(
        {"machine": machine.name, "shape": shape(machine), "kept": capture(machine)},
        separators=(",", ":"),
        sort_keys=True,
    ).encode()
    digest = hashlib.sha256(body).hexdigest()
    return f"{STATE_MAGIC} {STATE_VERSION} {len(body)} {digest}\n".encode() + body


def decode_state(data: bytes, source: str = "state") -> dict[str, Any]:
    """The document of a state file's bytes, brought to :data:`STATE_VERSION`: StateError
    (naming ``source``) for anything but a whole state file this version reads."""
    end = data.find(b"\n", 0, _MAX_HEADER)
    words = data[:end].split() if end >= 0 else []
    if len(words) != 4 or words[0] != STATE_MAGIC.encode():
        raise StateError(f"{source}: not a focas-net state file")
    try:
        version, length = int(words[1]), int(words[2])
    except ValueError:
        raise StateError(f"{source}: not a focas-net state file") from None
    if version > STATE_VERSION:
        raise StateError(
            f"{source}: written by a newer focas-net (state format {version}; this version "
            f"reads formats 1..{STATE_VERSION})"
        )
    if version < 1:
        raise StateError(f"{source}: state format {version} does not exist")
    body = data[end + 1 :]
    if len(body) != length:
        raise StateError(
            f"{source}: truncated or corrupted ({len(body)} bytes of body, the header says "
            f"{length})"
        )
    if hashlib.sha256(body).hexdigest().encode() != words[3]:
        raise StateError(f"{source}: corrupted (the checksum does not match)")
    try:
        doc = json.loads(body)
    except (UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise StateError(f"{source}: corrupted ({exc})") from None
    if not isinstance(doc, dict) or not {"machine", "shape", "kept"} <= doc.keys():
        raise StateError(f"{source}: malformed (no machine, shape and kept data)")
    kept: dict[str, Any] = doc
    while version < STATE_VERSION:
        kept = UPGRADES[version](kept)
        version += 1
    return kept


def apply_state(machine: Machine, doc: dict[str, Any], source: str = "state") -> None:
    """Put the kept data of ``doc`` into ``machine`` (just built): StateError when the state
    was written for a machine of another shape (naming the differences) or is malformed
    (``machine`` must then be dropped)."""
    differences = shape_differences(doc["shape"], shape(machine))
    if differences:
        raise StateError(
            f"{source}: the state was written for another machine than "
            f"{machine.name!r} is now (its machine file changed): " + "; ".join(differences)
        )
    try:
        restore(machine, doc["kept"])
    except StateMismatch as exc:
        raise StateError(f"{source}: {exc}") from None


class StateFile:
    """The state file of one machine: :meth:`load` at the start, :meth:`save` after changes.

    ``read_only``: the file is read and never written (``serve --read-only``)."""

    __slots__ = ("_last", "_token", "path", "read_only", "writes")

    def __init__(self, path: str | os.PathLike[str], *, read_only: bool = False) -> None:
        self.path = Path(path)
        self.read_only = read_only
        #: The bytes last written or read (a save of the same bytes writes nothing).
        self._last: bytes | None = None
        self._token: object = None
        #: How many times the file was written.
        self.writes = 0

    def load(self, build: Callable[[], Machine]) -> Machine:
        """A machine built by ``build`` with the kept data of the file put back (the file
        missing: as ``build`` made it, the first start). StateError as :func:`decode_state`
        and :func:`apply_state` say; OSError when the file cannot be read."""
        if not self.read_only:
            with contextlib.suppress(FileNotFoundError):
                self._temp().unlink()  # what a crash in the middle of a write left
        try:
            data = self.path.read_bytes()
        except FileNotFoundError:
            machine = build()
        else:
            source = str(self.path)
            doc = decode_state(data, source)
            machine = build()
            apply_state(machine, doc, source)
        self._last = encode_state(machine)
        self._token = _token(machine)
        return machine

    def save(self, machine: Machine) -> bool:
        """Write the file when what ``machine`` keeps changed since the last write; True when
        it wrote. The new file is durable when this returns (see the module docstring)."""
        if not self.stage(machine):
            return False
        sync_folder(self.path.parent)
        return True

    def stage(self, machine: Machine) -> bool:
        """:meth:`save` but for the flush of the folder: the new file's content is on the
        disk and renamed over the old one, the rename itself is durable once the folder is
        flushed (:func:`sync_folder`; :func:`save_all` flushes each folder once)."""
        if self.read_only:
            return False
        token = _token(machine)
        if token == self._token:
            return False
        data = encode_state(machine)
        self._token = _token(machine)
        if data == self._last:
            return False
        self._write(data)
        self._last = data
        self.writes += 1
        return True

    def _temp(self) -> Path:
        return self.path.with_name(self.path.name + _TEMP_SUFFIX)

    def _write(self, data: bytes) -> None:
        directory = self.path.parent
        directory.mkdir(parents=True, exist_ok=True)
        temp = self._temp()
        fd = os.open(temp, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o644)
        try:
            view = memoryview(data)
            while view:
                view = view[os.write(fd, view) :]
            os.fsync(fd)
        finally:
            os.close(fd)
        os.replace(temp, self.path)


def sync_folder(folder: Path) -> None:
    """Flush ``folder`` to the disk (the renames in it are durable then)."""
    fd = os.open(folder, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def save_all(states: Iterable[tuple[StateFile, Machine]]) -> int:
    """Save every machine that changed (:meth:`StateFile.stage`), then flush each folder
    once: the changes of many machines cost one ``fsync`` each and one per folder. Returns
    how many files were written; all of them are durable when it returns."""
    folders: set[Path] = set()
    written = 0
    for state, machine in states:
        if state.stage(machine):
            folders.add(state.path.parent)
            written += 1
    for folder in folders:
        sync_folder(folder)
    return written


def _token(machine: Machine) -> tuple[int, ...]:
    """What moves whenever the machine's kept data may have changed: its version counter
    and the program stores' (read without bringing the engines to the clock's time)."""
    return (machine._counters.version, *(p.programs.version for p in machine._paths.all))
