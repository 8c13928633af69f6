"""A machine's nonvolatile memory in a file: the format, the durable write and the loading.

``serve --state DIR`` keeps one file per machine in ``DIR`` (:func:`state_path`: the machine's
name, quoted, with ``.state``). The file (``docs/machine-file.md``, "State files") is a
journal: one header line, then records, each a whole state::

    focas-net-state 2\n
    <length of the body> <SHA-256 of the body, hex>\n<body>\n
    <length of the body> <SHA-256 of the body, hex>\n<body>\n
    ...

and a body is one JSON document, ``{"machine": NAME, "shape": {...}, "kept": {...}}``:
``shape`` is what the kept data must fit (:func:`focas_net.sim.nonvolatile.shape`), ``kept``
what the machine keeps across power-off (:func:`focas_net.sim.nonvolatile.capture`). The
last whole record is the state.

A save appends one record and flushes the file (``fdatasync``): one flush, the folder left
alone. A crash in the middle of an append leaves a torn last record (shorter than its length,
or not matching its checksum), which loading ignores: the record before it is the state, and
the next save rewrites the file. When the journal has grown past :data:`COMPACT_AT` bytes (or
past eight records' worth) it is replaced by one record, never changed in place: the new
content goes to a temporary file in the same folder, which is flushed, renamed over the
journal, and the folder is flushed too. A crash at any instant leaves either the old journal
or the new one, whole; a temporary file it left behind is removed at the next start. The
first save of a machine creates its file the same way, so a file always holds a whole record.

Loading (:meth:`StateFile.load`) builds the machine from its machine file as before, then
puts the kept data back. Every refusal is a :class:`StateError` naming the file: not a state
file, a format version newer than this one reads, no whole record (truncated or corrupted),
a damaged record before the last, a state written for a machine of another shape (naming the
differences). The machine that was being restored is dropped, so no half-loaded machine is
ever served. A state file of an older format version loads (format 1: one header line with
the body's length and checksum, then the body); its document is brought up to date by
:data:`UPGRADES` and the next save writes the current format.
"""

from __future__ import annotations

import contextlib
import errno
import hashlib
import json
import os
from collections.abc import Callable, Iterable
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import TYPE_CHECKING, Any, Final
from urllib.parse import quote

from .nonvolatile import StateMismatch, capture, restore, shape, shape_differences

if TYPE_CHECKING:
    from .machine import Machine

__all__ = [
    "COMPACT_AT",
    "STATE_MAGIC",
    "STATE_SUFFIX",
    "STATE_VERSION",
    "UPGRADES",
    "StateError",
    "StateFile",
    "apply_state",
    "check_folder",
    "decode_state",
    "encode_body",
    "encode_record",
    "encode_state",
    "save_all",
    "state_path",
    "sync_folder",
]

#: The first word of a state file.
STATE_MAGIC: Final = "focas-net-state"
#: The format version this version of the project writes (and the newest it reads).
STATE_VERSION: Final = 2
#: The file name suffix of a state file.
STATE_SUFFIX: Final = ".state"
#: Format version -> the function that brings a document of that version to the next one.
UPGRADES: Final[dict[int, Callable[[dict[str, Any]], dict[str, Any]]]] = {
    1: lambda doc: doc,  # format 2 changed the file (a journal), not the document
}
#: A journal longer than this (and than eight of its records) is compacted into one record.
COMPACT_AT: Final = 1 << 20
#: Threads that write and flush the files of the machines one turn changed.
_FLUSH_THREADS: Final = 16
_TEMP_SUFFIX: Final = ".tmp"
_MAX_HEADER: Final = 200


class StateError(ValueError):
    """A state file that cannot be loaded; the message names the file and the reason."""


def state_path(directory: str | os.PathLike[str], name: str) -> Path:
    """The state file of the machine called ``name`` in ``directory``."""
    return Path(directory) / (quote(name, safe="") + STATE_SUFFIX)


def encode_body(machine: Machine) -> bytes:
    """The body of a record of ``machine``'s state, as it is now."""
    return json.dumps(
        {"machine": machine.name, "shape": shape(machine), "kept": capture(machine)},
        separators=(",", ":"),
        sort_keys=True,
    ).encode()


def encode_record(body: bytes) -> bytes:
    """One journal record of ``body``."""
    return f"{len(body)} {hashlib.sha256(body).hexdigest()}\n".encode() + body + b"\n"


def encode_state(machine: Machine) -> bytes:
    """The bytes of a state file holding ``machine``'s state as it is now (one record)."""
    return _HEADER + encode_record(encode_body(machine))


_HEADER: Final = f"{STATE_MAGIC} {STATE_VERSION}\n".encode()


def decode_state(data: bytes, source: str = "state") -> dict[str, Any]:
    """The document of a state file's bytes (its last whole record), brought to
    :data:`STATE_VERSION`: StateError (naming ``source``) for anything but a state file this
    version reads."""
    return _scan(data, source)[0]


def _scan(data: bytes, source: str) -> tuple[dict[str, Any], int, bool]:
    """The document of the last whole record, the end of that record, and whether a torn
    record follows it."""
    end = data.find(b"\n", 0, _MAX_HEADER)
    words = data[:end].split() if end >= 0 else []
    if len(words) not in (2, 4) or words[0] != STATE_MAGIC.encode():
        raise StateError(f"{source}: not a focas-net state file")
    try:
        version = int(words[1])
    except ValueError:
        raise StateError(f"{source}: not a focas-net state file") from None
    if version > STATE_VERSION:
        raise StateError(
            f"{source}: written by a newer focas-net (state format {version}; this version "
            f"reads formats 1..{STATE_VERSION})"
        )
    if version < 1 or (len(words) == 4) != (version == 1):
        raise StateError(f"{source}: not a focas-net state file")
    if version == 1:
        body, good, torn = _format1(data, end, words, source), len(data), False
    else:
        body, good, torn = _records(data, end + 1, source)
    try:
        doc = json.loads(body)
    except (UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise StateError(f"{source}: corrupted ({exc})") from None
    if (
        not isinstance(doc, dict)
        or not {"machine", "shape", "kept"} <= doc.keys()
        or not isinstance(doc["shape"], dict)
        or not isinstance(doc["kept"], dict)
    ):
        raise StateError(f"{source}: malformed (no machine, shape and kept data)")
    kept: dict[str, Any] = doc
    while version < STATE_VERSION:
        kept = UPGRADES[version](kept)
        version += 1
    return kept, good, torn


def _format1(data: bytes, end: int, words: list[bytes], source: str) -> bytes:
    """The body of a format 1 file: the header's length and checksum, then the body."""
    body = data[end + 1 :]
    try:
        length = int(words[2])
    except ValueError:
        raise StateError(f"{source}: not a focas-net state file") from None
    if len(body) != length:
        raise StateError(
            f"{source}: truncated or corrupted ({len(body)} bytes of body, the header says "
            f"{length})"
        )
    if hashlib.sha256(body).hexdigest().encode() != words[3]:
        raise StateError(f"{source}: corrupted (the checksum does not match)")
    return body


def _records(data: bytes, at: int, source: str) -> tuple[bytes, int, bool]:
    """The body of the last whole record from ``at``, the end of that record, and whether a
    torn record follows it. A damaged record that is not the last is corruption."""
    last: bytes | None = None
    good = at
    size = len(data)
    problem = ""
    while at < size:
        eol = data.find(b"\n", at, at + _MAX_HEADER)
        words = data[at:eol].split() if eol >= 0 else []
        body_at = eol + 1
        length = int(words[0]) if len(words) == 2 and words[0].isdigit() else -1
        stop = body_at + length + 1
        if eol < 0 or length < 0 or stop > size:
            problem = "its last record is cut short" if eol < 0 or stop > size else ""
            if not problem:
                raise StateError(f"{source}: corrupted (a record's header at byte {at})")
            break
        body = data[body_at : stop - 1]
        if (
            data[stop - 1 : stop] != b"\n"
            or hashlib.sha256(body).hexdigest().encode() != (words[1])
        ):
            if stop < size:
                raise StateError(
                    f"{source}: corrupted (the record at byte {at} does not match its "
                    "checksum, and records follow it)"
                )
            problem = "its last record does not match its checksum"
            break
        last, good, at = body, stop, stop
    if last is None:
        why = problem or "it holds no record"
        raise StateError(f"{source}: truncated or corrupted ({why})")
    return last, good, good < size


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

    __slots__ = ("_last", "_replace", "_size", "_token", "path", "read_only", "writes")

    def __init__(self, path: str | os.PathLike[str], *, read_only: bool = False) -> None:
        self.path = Path(path)
        self.read_only = read_only
        #: The body last written or read (a save of the same body writes nothing).
        self._last: bytes | None = None
        self._token: object = None
        #: The journal's size in bytes; whether the next save replaces it (a new file, a
        #: torn or older-format one).
        self._size = 0
        self._replace = True
        #: How many times the file was written.
        self.writes = 0

    def load(self, build: Callable[[], Machine]) -> Machine:
        """A machine built by ``build`` with the kept data of the file put back (the file
        missing: as ``build`` made it, the first start). StateError as :func:`decode_state`
        and :func:`apply_state` say; OSError when the file cannot be read."""
        if not self.read_only:
            with contextlib.suppress(FileNotFoundError):
                self._temp().unlink()  # what a crash in the middle of a compaction left
        try:
            data = self.path.read_bytes()
        except FileNotFoundError:
            machine = build()
            self._replace = True
        else:
            source = str(self.path)
            doc, good, torn = _scan(data, source)
            machine = build()
            apply_state(machine, doc, source)
            self._size = good
            self._replace = torn or not data.startswith(_HEADER)
        self._last = encode_body(machine)
        self._token = _token(machine)
        return machine

    def save(self, machine: Machine) -> bool:
        """Write the file when what ``machine`` keeps changed since the last write; True when
        it wrote. The change is durable when this returns (see the module docstring)."""
        written = self.stage(machine)
        if written == "replaced":
            try:
                sync_folder(self.path.parent)
            except OSError:
                self.forget()
                raise
        return written is not None

    def stage(self, machine: Machine) -> str | None:
        """:meth:`save` but for the flush of the folder: None when nothing changed,
        ``"appended"`` when a record was appended (durable now), ``"replaced"`` when the
        file was replaced (durable once its folder is flushed: :func:`sync_folder`;
        :func:`save_all` flushes each folder once)."""
        change = self.change(machine)
        return None if change is None else self.commit(*change)

    def change(self, machine: Machine) -> tuple[bytes, object] | None:
        """What :meth:`commit` must write for ``machine`` (its new body and version
        token), None when what it keeps has not changed (or the file is read-only). Reads
        the machine: call it from the machine's thread."""
        if self.read_only:
            return None
        token = _token(machine)
        if token == self._token:
            return None
        body = encode_body(machine)
        token = _token(machine)  # capture() brought the engines to the clock's time
        if body == self._last:
            self._token = token
            return None
        return body, token

    def commit(self, body: bytes, token: object) -> str:
        """Write ``body`` (from :meth:`change`): ``"appended"`` or ``"replaced"`` as
        :meth:`stage` says. Touches this file only, so the commits of several files may run
        in threads at once."""
        try:
            done = self._put(encode_record(body))
        except BaseException:
            self._replace = True  # a part of a record may be there: the next save replaces
            raise
        self._last, self._token = body, token
        self.writes += 1
        return done

    def forget(self) -> None:
        """The last write may not be durable (its folder could not be flushed): the next save
        replaces the file, whatever changed."""
        self._replace = True
        self._last = self._token = None

    def _put(self, record: bytes) -> str:
        if self._replace or self._size + len(record) > max(COMPACT_AT, 8 * len(record)):
            self._write(_HEADER + record)
            self._size = len(_HEADER) + len(record)
            self._replace = False
            return "replaced"
        fd = os.open(self.path, os.O_WRONLY | os.O_APPEND)
        try:
            _write_all(fd, record)
            os.fdatasync(fd)
        finally:
            os.close(fd)
        self._size += len(record)
        return "appended"

    def _temp(self) -> Path:
        return self.path.with_name(self.path.name + _TEMP_SUFFIX)

    def _write(self, data: bytes) -> None:
        directory = self.path.parent
        directory.mkdir(parents=True, exist_ok=True)
        temp = self._temp()
        fd = os.open(temp, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o644)
        try:
            _write_all(fd, data)
            os.fsync(fd)
        finally:
            os.close(fd)
        os.replace(temp, self.path)


def _write_all(fd: int, data: bytes) -> None:
    view = memoryview(data)
    while view:
        view = view[os.write(fd, view) :]


def check_folder(folder: str | os.PathLike[str]) -> None:
    """Make sure the state files can be written in ``folder`` (made if missing): a file is
    created, flushed and removed there. OSError when it cannot be, so that a server is
    refused at its start rather than unable to keep its first write."""
    where = Path(folder)
    if where.exists() and not where.is_dir():
        raise NotADirectoryError(errno.ENOTDIR, os.strerror(errno.ENOTDIR), str(where))
    where.mkdir(parents=True, exist_ok=True)
    probe = where / f".focas-net-probe-{os.getpid()}{_TEMP_SUFFIX}"
    fd = os.open(probe, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o644)
    try:
        _write_all(fd, _HEADER)
        os.fsync(fd)
    finally:
        os.close(fd)
        probe.unlink()
    sync_folder(where)


def sync_folder(folder: Path) -> None:
    """Flush ``folder`` to the disk (the renames in it are durable then)."""
    fd = os.open(folder, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def save_all(states: Iterable[tuple[StateFile, Machine]]) -> int:
    """Save every machine that changed, then flush once each folder in which a file was
    replaced. The files of several changed machines are written and flushed in threads at
    once (a flush waits for the disk without holding the interpreter), so a turn that changed
    many machines waits for about one flush, not one per machine. Returns how many files
    were written; all of them are durable when it returns (OSError: the first failure, after
    every write ended; a file whose folder could not be flushed is replaced at the next
    save)."""
    changes = [
        (state, change)
        for state, machine in states
        if (change := state.change(machine)) is not None
    ]
    outcomes: list[str | Exception] = []
    if len(changes) == 1:
        state, (body, token) = changes[0]
        try:
            outcomes.append(state.commit(body, token))
        except Exception as exc:
            outcomes.append(exc)
    else:
        # every commit ends before this returns or raises (no thread writes a file after)
        submitted = [_pool().submit(s.commit, *change) for s, change in changes]
        for future in submitted:
            try:
                outcomes.append(future.result())
            except Exception as exc:
                outcomes.append(exc)
    failure = next((o for o in outcomes if isinstance(o, Exception)), None)
    replaced = [s for (s, _), o in zip(changes, outcomes, strict=True) if o == "replaced"]
    try:
        for folder in {s.path.parent for s in replaced}:
            sync_folder(folder)
    except OSError:
        for state in replaced:
            state.forget()  # the rename may not be durable: the next save replaces again
        raise
    if failure is not None:
        raise failure
    return len(changes)


_POOL: list[ThreadPoolExecutor] = []


def _pool() -> ThreadPoolExecutor:
    """The threads :func:`save_all` writes several files with (made on first use)."""
    if not _POOL:
        _POOL.append(ThreadPoolExecutor(_FLUSH_THREADS, thread_name_prefix="focas-state"))
    return _POOL[0]


def _token(machine: Machine) -> tuple[int, ...]:
    """What moves whenever the machine's kept data may have changed: its version counter
    and the program stores' (read without bringing the engines to the clock's time)."""
    return (machine._counters.version, *(p.programs.version for p in machine._paths.all))
