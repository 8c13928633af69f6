"""The native adapter's part programs (``docs/native-protocol.md``, "Programs"): the handlers
of the program store's data requests (directory, memory, delete, search, the blocks being
executed; what a handler is: :mod:`focas_net.adapters.native`) and the transfer frames of
uploads and downloads, a download kept in the connection's :class:`ProgramTransfer` and stored
at its end only.

A data request answers for the programs of the path in its block's path word (0 is path 1);
an upload or a download is of the path its start frame names (:class:`TransferStart`'s
``path``, the handle's path; 0 is path 1), or, on a control with program folders, of the path
whose folder ``cnc_upstart4``'s file or ``cnc_dwnstart4``'s folder is
(``//CNC_MEM/USER/PATH2/`` is path 2's; a folder of no path is EW_DATA).
"""

from __future__ import annotations

import re
from typing import Final

from focas_net.errors import EW
from focas_net.native import (
    PROGRAM_CHUNK,
    ExecutingBlocks,
    ExecutingBlocksRequest,
    ProgramDeleteRequest,
    ProgramDirEntry,
    ProgramDirRequest,
    ProgramMemory,
    ProgramSearchRequest,
    RequestBlock,
    TransferError,
    TransferFrame,
    TransferStart,
    encode_native_frame,
    error_frame_type,
    parse_program_range,
)
from focas_net.sim import Machine, MachineError, Session

from ._common import REFUSALS, Refused, refusal_code
from ._native_cnc import block_path

__all__ = ["MAX_DOWNLOAD", "ProgramHandlers", "ProgramTransfer"]

#: The sequence number a block starts with.
_SEQUENCE: Final = re.compile(r"\s*N(\d+)")

#: Most bytes of one download (a larger one answers EW_OVRFLOW at its end).
MAX_DOWNLOAD: Final = 1 << 20


class ProgramTransfer:
    """One connection's program download (``cnc_dwnstart``... ``cnc_dwnend``): whether one
    is under way and the text received so far. The server keeps one per connection, so a
    connection dropped in the middle of a download stores nothing; the machine sees only the
    whole program, at the download's end."""

    __slots__ = ("downloading", "overflow", "path", "received")

    def __init__(self) -> None:
        #: Whether a download was started and not ended.
        self.downloading = False
        #: The path whose programs the download goes to.
        self.path = 1
        #: Whether the download went past :data:`MAX_DOWNLOAD` (its bytes were dropped).
        self.overflow = False
        #: The download's bytes so far.
        self.received = bytearray()

    def reset(self) -> None:
        self.downloading = False
        self.path = 1
        self.overflow = False
        self.received.clear()


class ProgramHandlers:
    """The part programs of one machine, answered at one version word (see the module
    docstring)."""

    __slots__ = ("machine", "version")

    def __init__(self, machine: Machine, version: int) -> None:
        self.machine = machine
        #: The version word of the transfer frames.
        self.version = version

    def read_program_directory(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0x06: the programs from O number ``top`` on, by number, at most ``count`` (and what
        the answer holds), 72 bytes each; none from ``top`` on is no data (the end)."""
        req = ProgramDirRequest.from_block(block)
        if req.count < 1:
            raise Refused(EW.LENGTH)
        most = min(req.count, room // ProgramDirEntry.SIZE)
        directory = self.machine.program_directory(path=block_path(block))
        entries = [e for e in directory if e.number >= req.top][:most]
        return b"".join(
            ProgramDirEntry(e.number, e.size, _program_comment(e.name)).encode() for e in entries
        )

    def read_program_memory(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0x07: programs stored and the room for more, characters used and free (the
        machine's program store: its directory, capacity and most programs)."""
        machine = self.machine
        path = block_path(block)
        directory = machine.program_directory(path=path)
        store = machine.path_programs(path)
        used = sum(e.size for e in directory)
        return ProgramMemory(
            len(directory),
            max(store.max_programs - len(directory), 0),
            used,
            max(store.capacity - used, 0),
        ).encode()

    def delete_program(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0x05: the machine's ``delete_program`` (EW_PROT, EW_NUMBER, EW_BUSY)."""
        number = ProgramDeleteRequest.from_block(block).number
        self.machine.delete_program(number, path=block_path(block))
        return b""

    def search_program(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0x03: the machine's ``select_program`` (EW_PROT, EW_MODE, EW_NUMBER, EW_BUSY)."""
        number = ProgramSearchRequest.from_block(block).number
        self.machine.select_program(number, path=block_path(block))
        return b""

    def read_executing_blocks(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0x20: the blocks of the running program from the one being executed on (the block
        of the sequence number the machine shows, else the program's first block), whole
        blocks of at most ``length`` characters and what the answer holds; the block count
        first. No running program is no block."""
        req = ExecutingBlocksRequest.from_block(block)
        if req.length < 1:
            raise Refused(EW.LENGTH)
        path = block_path(block)
        motion = self.machine.path_motion(path=path)
        try:
            text = self.machine.program_text(motion.program_running, path=path)
        except MachineError:
            return ExecutingBlocks(0, b"").encode()
        lines = text.splitlines()[1:]  # after the O line
        start = 0
        if motion.sequence > 0:
            for i, line in enumerate(lines):
                match = _SEQUENCE.match(line)
                if match is not None and int(match.group(1)) == motion.sequence:
                    start = i
                    break
        most = min(req.length, room - 4)
        out: list[bytes] = []
        size = 0
        for line in lines[start:]:
            raw = (line + "\n").encode("latin-1", "replace")
            if size + len(raw) > most:
                break
            out.append(raw)
            size += len(raw)
        return ExecutingBlocks(len(out), b"".join(out)).encode()

    def transfer(self, frame_type: int, body: bytes, state: ProgramTransfer) -> list[bytes] | None:
        """:meth:`NativeAdapter.transfer <focas_net.adapters.NativeAdapter.transfer>`."""
        try:
            kind = TransferFrame(frame_type)
        except ValueError:
            return None
        try:
            if kind is TransferFrame.UPLOAD_START:
                return self._upload(body)
            if kind is TransferFrame.DOWNLOAD_START:
                start = TransferStart.decode(body)
                path = start.path or 1
                state.reset()
                self.machine.check_writable()
                self.machine.path_info(path)  # EW_PATH for a path the machine has not
                path = self.machine.transfer_path(_transfer_name(start.name), path=path)
                state.downloading = True
                state.path = path
                return [self._transfer_frame(TransferFrame.DOWNLOAD_START_ANSWER)]
            if kind is TransferFrame.DOWNLOAD_DATA:
                if state.downloading and not state.overflow:
                    if len(state.received) + len(body) > MAX_DOWNLOAD:
                        state.overflow = True
                        state.received.clear()
                    else:
                        state.received += body
                return []
            if kind is TransferFrame.DOWNLOAD_END:
                return self._download_end(state)
        except REFUSALS as exc:
            return [self._transfer_refusal(frame_type, refusal_code(exc))]
        if kind in (TransferFrame.UPLOAD_END_ANSWER, TransferFrame.UPLOAD_ABORT):
            return []
        return None  # an answer type: never sent to a CNC

    def _transfer_frame(self, frame_type: int, body: bytes = b"") -> bytes:
        return encode_native_frame(frame_type, body, self.version)

    def _transfer_refusal(self, frame_type: int, ew: int) -> bytes:
        return self._transfer_frame(
            error_frame_type(frame_type), TransferError(0, ew, 0, 0).encode()
        )

    def _upload(self, body: bytes) -> list[bytes]:
        start = TransferStart.decode(body)
        path = start.path or 1
        machine = self.machine
        machine.path_info(path)  # EW_PATH for a path the machine has not
        first, last = parse_program_range(start.name)
        path = machine.transfer_path(_transfer_name(start.name), path=path)
        if first == last:
            texts = [machine.program_text(first, path=path)]  # EW_NUMBER when there is none
        else:
            directory = machine.program_directory(path=path)
            numbers = [e.number for e in directory if first <= e.number <= last]
            if not numbers:
                raise Refused(EW.NUMBER)
            texts = [machine.program_text(n, path=path) for n in numbers]
        data = ("%\n" + "".join(texts) + "%").encode("latin-1", "replace")
        frames = [self._transfer_frame(TransferFrame.UPLOAD_START_ANSWER)]
        frames.extend(
            self._transfer_frame(TransferFrame.UPLOAD_DATA, data[i : i + PROGRAM_CHUNK])
            for i in range(0, len(data), PROGRAM_CHUNK)
        )
        frames.append(self._transfer_frame(TransferFrame.UPLOAD_END))
        return frames

    def _download_end(self, state: ProgramTransfer) -> list[bytes]:
        """Store the downloaded program: EW_FUNC when no download was started, EW_OVRFLOW
        past :data:`MAX_DOWNLOAD`, then the machine's ``store_program`` refusals (EW_PROT,
        EW_DATA, EW_NUMBER, EW_REJECT, EW_OVRFLOW): the machine reads the text as a tape,
        from its opening ``%`` to its closing one, and refuses what is not printable ASCII."""
        downloading, overflow, path = state.downloading, state.overflow, state.path
        raw = bytes(state.received)
        state.reset()
        if not downloading:
            raise Refused(EW.FUNC)
        if overflow:
            raise Refused(EW.OVRFLOW)
        self.machine.store_program(raw.decode("latin-1"), path=path)
        return [self._transfer_frame(TransferFrame.DOWNLOAD_END_ANSWER)]


def _transfer_name(name: bytes) -> str:
    """The folder or file a transfer's start names after ``N:`` (``cnc_upstart4``,
    ``cnc_dwnstart4``); empty for the other forms."""
    text = name.decode("latin-1")
    return text[2:] if text.startswith("N:") else ""


def _program_comment(name: str) -> bytes:
    """A directory entry's comment: the program's name in parentheses, as a control shows it
    (at most 63 bytes, so a NUL always ends it); empty without a name."""
    if not name:
        return b""
    return f"({name[:61]})".encode("latin-1", "replace")
