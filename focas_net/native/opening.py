"""The open answer (frame type ``0x0102``) FANUC's library needs, in its two layouts.

The library opens two TCP connections, A then B, and sends an open request on each. Both
answers must pass a size check (otherwise ``PDU size mismatch at initiate time``, EW_PROTOCOL);
only **B's** answer is read, and its **version word** picks the layout of the body and the
whole command set of the handle [V]:

* version <= 2, **"16i class"** (:class:`OpenHeadV2`, :class:`PathRecordV2`): a 16-byte head
  and 8 bytes per path; body = ``16 + 8 * n`` with n = u16 at body[8:10]. Parameters use
  0x0E/0x10/0x0F, diagnostics 0x30, ``cnc_wrmacro`` sends a binary record; the library then
  reads parameter 9968 (0x0E) for its "FOCAS option bits".
* version >= 3, **"30i class"** (:class:`OpenHeadV3`, :class:`PathRecordV3`): a 40-byte head
  and 32 bytes per path; body = ``40 + 32 * n`` with n = u16 at body[10:12]. Parameters use
  0x8D/0xA0/0x8E, diagnostics 0x93, spindle/servo/position reads come wrapped in 0xA4 blocks,
  ``cnc_wrmacro`` sends base 10; the option bits are body[28:30].

A path record whose machine-type characters are zero is no path. For every present path the
library sends one 0x18 (sysinfo) block while connecting (path word = record index + 1); with
n = 0 that request has no block, and the library refuses the zero-block answer, so an open
answer needs at least one path. Option bit 0 is required by ``cnc_rddynamic2`` (EW_NOOPT
otherwise) [V].

Paths, as FANUC's library handles them [V] (``tests/data/fwlib_paths.json``): the library
keeps a table of :data:`PATH_RECORDS` paths per handle, filled from the path records.
``cnc_getpath`` sends nothing and gives (the handle's path, the path-count word of the head);
``cnc_setpath(p)`` sends nothing either: p <= 0 selects path 1, and a p whose table entry has
no machine type returns EW_PATH (11) and keeps the path; otherwise every later block carries p
in its path word and ``cnc_sysinfo`` answers the 0x18 record of path p from connect time. Table
entries past the records are not cleared: with fewer than :data:`PATH_RECORDS` records,
``cnc_setpath`` past the last path is refused or accepted depending on what the handle's
memory holds there (with 2 records at version 3, 3 refused but 4 accepted; with one record, 2
to 5 accepted in both layouts). So a multi-path answer carries all :data:`PATH_RECORDS`
records, the absent ones with zero machine type, as a real 0i-D's 360-byte answer does: then
``cnc_setpath`` past the last path returns EW_PATH without sending anything.

:func:`build_open_answer` makes a body of exactly the checked size from path descriptions;
:func:`decode_open_answer` reads one back; :func:`open_answer_size` is the size the library
checks.
"""

from __future__ import annotations

import struct
from collections.abc import Sequence
from dataclasses import dataclass
from typing import ClassVar, Final

from .base import NativePayloadError, NativeRecord

__all__ = [
    "MACHINE_LATHE",
    "MACHINE_MILL",
    "NO_PATH",
    "PATH_RECORDS",
    "OpenAnswer",
    "OpenHeadV2",
    "OpenHeadV3",
    "PathDescription",
    "PathRecordV2",
    "PathRecordV3",
    "build_open_answer",
    "decode_open_answer",
    "open_answer_size",
]

#: Machine-type characters of a milling path and of a lathe path (the library marks " T" as a
#: lathe), and of "no path".
MACHINE_MILL: Final = " M"
MACHINE_LATHE: Final = " T"
NO_PATH: Final = "\x00\x00"
#: Paths in the library's table of a handle, and the path records a multi-path open answer
#: carries (absent paths with :data:`NO_PATH`), so that ``cnc_setpath`` past the last path
#: is refused by the library itself [V].
PATH_RECORDS: Final = 10


@dataclass(frozen=True, slots=True)
class OpenHeadV2(NativeRecord):
    """The 16-byte head of a version <= 2 open answer.

    ``max_axes`` (u16 at 4) is the CNC's max axes: the slot count of 0x0F write records
    (8 + 4 * max_axes) and the length check of ``cnc_rddynamic2(-1)`` (>= 28 + 16 * max_axes)
    [V]. ``paths`` (u16 at 8) is the number of path records [V]. ``max_paths`` (u16 at 10)
    is the path count ``cnc_getpath`` reports [V] (the word after it, u16 at 12, alone gives
    one less [V]; its meaning is not settled). ``kind`` (u16 at 2): 2 = FS15 family (other
    commands), 3 = option bits forced to 1 without reading parameter 9968, any other value the
    16i family [I]. The other words are stored by the library, use unknown; 0 works [V].
    """

    FORMAT: ClassVar[str] = ">8H"
    word0: int
    kind: int
    max_axes: int
    word3: int
    paths: int
    max_paths: int = 0
    word6: int = 0
    word7: int = 0


@dataclass(frozen=True, slots=True)
class PathRecordV2(NativeRecord):
    """One 8-byte path record of a version <= 2 open answer [V]: the machine-type characters
    (``" M"``, ``" T"``; two NULs = no path), a stored word of unknown use, the number of axes
    of the path (the axis count of every per-axis read and check) and its number of spindles
    (``cnc_rdspload``)."""

    FORMAT: ClassVar[str] = ">2sHHH"
    TEXT: ClassVar[frozenset[str]] = frozenset({"machine_type"})
    machine_type: str
    word1: int
    axes: int
    spindles: int


@dataclass(frozen=True, slots=True)
class OpenHeadV3(NativeRecord):
    """The 40-byte head of a version >= 3 open answer.

    ``record_format`` (u16 at 4, 1..3): how many optional path-record words the library reads
    [I]. ``max_axes`` (u16 at 6): the per-path axis limit of every read and write length
    (all-axes ``cnc_rdparam``/``cnc_diagnoss``/``cnc_wrparam`` need 4 + size * max_axes) [V].
    ``max_spindles`` (u16 at 8) [I]. ``paths`` (u16 at 10) [V]. ``option_bits`` (u16 at 28):
    the FOCAS option bits, bit 0 needed by ``cnc_rddynamic2`` [V]. ``max_paths`` (u16 at 22)
    is the path count ``cnc_getpath`` reports [V]. ``controlled_spindles`` (u16 at 20) is the
    CNC's number of controlled spindles (ODBSYSEX ``ctrl_spdl`` of ``cnc_sysinfo_ex``):
    ``cnc_rdspmeter`` (and ``cnc_rdaxisdata`` of the spindle classes) returns EW_NOOPT without
    sending anything while it is 0 [V]. ``words`` are body[12:20] (``cnc_sysinfo_ex`` reads
    them as max_mchn, a stored word, ctrl_axis and ctrl_srvo; the u16 at 18, controlled servo
    axes, caps ``cnc_rdsvmeter`` when not 0 [I]), ``words2`` body[24:28]; ``tail`` is
    body[30:40] (30..33 stored [I]).
    """

    FORMAT: ClassVar[str] = ">HHHHHH8sHH4sH10s"
    word0: int
    word1: int
    record_format: int
    max_axes: int
    max_spindles: int
    paths: int
    words: bytes = bytes(8)
    controlled_spindles: int = 0
    max_paths: int = 0
    words2: bytes = bytes(4)
    option_bits: int = 0
    tail: bytes = bytes(10)


@dataclass(frozen=True, slots=True)
class PathRecordV3(NativeRecord):
    """One 32-byte path record of a version >= 3 open answer: machine-type characters (not
    zero = path present) [V], ``path_type`` (1 M, 2 T) [I], a stored word [I], the number of
    axes of the path (u16 at 6) [V], a word at 8 [I], the number of spindles (u16 at 10) [V],
    and 20 bytes read depending on the record format [I]."""

    FORMAT: ClassVar[str] = ">2sHHHHH20s"
    TEXT: ClassVar[frozenset[str]] = frozenset({"machine_type"})
    machine_type: str
    path_type: int
    word2: int
    axes: int
    word4: int
    spindles: int
    reserved: bytes = bytes(20)


_V2_COUNT: Final = struct.Struct(">H")


def open_answer_size(body: bytes, version: int) -> int | None:
    """The body size FANUC's library requires of an open answer with ``version`` whose body
    starts like ``body``: ``16 + 8 * n`` (n = u16 at 8) up to version 2, ``40 + 32 * n``
    (n = u16 at 10) above; None when ``body`` is too short to hold n."""
    if version <= 2:
        if len(body) < 10:
            return None
        (count,) = _V2_COUNT.unpack_from(body, 8)
        return OpenHeadV2.SIZE + PathRecordV2.SIZE * int(count)
    if len(body) < 12:
        return None
    (count,) = _V2_COUNT.unpack_from(body, 10)
    return OpenHeadV3.SIZE + PathRecordV3.SIZE * int(count)


@dataclass(frozen=True, slots=True)
class PathDescription:
    """What the open answer says of one path: machine type (``" M"``, ``" T"``), axes and
    spindles."""

    machine_type: str = MACHINE_MILL
    axes: int = 3
    spindles: int = 1

    @property
    def lathe(self) -> bool:
        return self.machine_type == MACHINE_LATHE


@dataclass(frozen=True, slots=True)
class OpenAnswer:
    """A decoded open answer: its version, its head (:class:`OpenHeadV2` or
    :class:`OpenHeadV3`) and its path records."""

    version: int
    head: OpenHeadV2 | OpenHeadV3
    paths: tuple[PathRecordV2, ...] | tuple[PathRecordV3, ...]

    @property
    def max_axes(self) -> int:
        return self.head.max_axes

    @property
    def option_bits(self) -> int | None:
        """The FOCAS option bits (version >= 3); None at version <= 2 (parameter 9968)."""
        return self.head.option_bits if isinstance(self.head, OpenHeadV3) else None

    def present(self) -> tuple[PathDescription, ...]:
        """The paths the library sees (machine-type characters not zero), in order."""
        return tuple(
            PathDescription(p.machine_type, p.axes, p.spindles)
            for p in self.paths
            if p.machine_type != NO_PATH
        )

    def encode(self) -> bytes:
        records: Sequence[NativeRecord] = self.paths
        return self.head.encode() + b"".join(r.encode() for r in records)


def build_open_answer(
    paths: Sequence[PathDescription],
    max_axes: int,
    *,
    option_bits: int = 1,
    version: int = 2,
    max_spindles: int | None = None,
    controlled_spindles: int | None = None,
    kind: int = 0,
    record_format: int = 1,
    records: int | None = None,
) -> bytes:
    """The body of an open answer FANUC's library accepts, for an answer carrying ``version``.

    ``paths`` describe the paths (at least one, or the library fails to connect), ``max_axes``
    the CNC's max axes (at least each path's axes); their count is also the path count
    ``cnc_getpath`` reports. At version >= 3 ``option_bits`` go to
    body[28:30], ``max_spindles`` (default: the most spindles of a path) to body[8:10] and
    ``controlled_spindles`` (default: the spindles of all paths) to body[20:22] (the
    controlled spindles; ``cnc_rdspmeter`` refuses itself while they are 0); at
    version <= 2 the option bits are not in the open answer (the library reads them from
    parameter 9968 unless ``kind`` is 3) and ``kind`` goes to body[2:4].

    ``records`` is the number of path records (default: one per path): the paths, then
    records with :data:`NO_PATH` up to ``records`` (:data:`PATH_RECORDS` makes
    ``cnc_setpath`` past the last path fail in the library itself).
    """
    if not paths:
        raise ValueError("an open answer needs at least one path")
    if records is None:
        records = len(paths)
    if not len(paths) <= records <= PATH_RECORDS:
        raise ValueError(
            f"{records} path records for {len(paths)} paths: between {len(paths)} and "
            f"{PATH_RECORDS}"
        )
    absent = records - len(paths)
    for p in paths:
        if p.axes > max_axes:
            raise ValueError(f"a path of {p.axes} axes exceeds max_axes {max_axes}")
    if version <= 2:
        head2 = OpenHeadV2(0, kind, max_axes, 0, records, len(paths))
        recs2 = tuple(PathRecordV2(p.machine_type, 0, p.axes, p.spindles) for p in paths)
        recs2 += (PathRecordV2(NO_PATH, 0, 0, 0),) * absent
        return OpenAnswer(version, head2, recs2).encode()
    spindles = max(p.spindles for p in paths) if max_spindles is None else max_spindles
    controlled = controlled_spindles
    if controlled is None:
        controlled = sum(p.spindles for p in paths)
    head3 = OpenHeadV3(
        0, 0, record_format, max_axes, spindles, records, max_paths=len(paths),
        option_bits=option_bits, controlled_spindles=controlled,
    )  # fmt: skip
    recs3 = tuple(
        PathRecordV3(p.machine_type, 2 if p.lathe else 1, 0, p.axes, 0, p.spindles) for p in paths
    )
    recs3 += (PathRecordV3(NO_PATH, 0, 0, 0, 0, 0),) * absent
    return OpenAnswer(version, head3, recs3).encode()


def decode_open_answer(body: bytes, version: int) -> OpenAnswer:
    """The open answer ``body`` received with ``version``; :class:`NativePayloadError` when its
    size is not the one the library checks."""
    size = open_answer_size(body, version)
    what = f"open answer of {len(body)} bytes at version {version}"
    if size is None:
        holds = 10 if version <= 2 else 12
        raise NativePayloadError(f"{what}, shorter than the {holds} bytes that hold its path count")
    if size != len(body):
        count = (size - OpenHeadV2.SIZE) // PathRecordV2.SIZE
        if version > 2:
            count = (size - OpenHeadV3.SIZE) // PathRecordV3.SIZE
        raise NativePayloadError(f"{what}, not the {size} bytes its path count of {count} makes")
    if version <= 2:
        head2 = OpenHeadV2.decode_from(body)
        return OpenAnswer(version, head2, PathRecordV2.decode_many(body[OpenHeadV2.SIZE :]))
    head3 = OpenHeadV3.decode_from(body)
    return OpenAnswer(version, head3, PathRecordV3.decode_many(body[OpenHeadV3.SIZE :]))
