"""The CNC's information over the native protocol: figures, status (2), system software, item
numbers and attributes, setting data, the PMC's areas and title, the Ethernet board and the program
restart information.

Each answer is one declaration that encodes and decodes (``docs/native-protocol.md``). The
layouts were read from what FANUC's library (libfwlib32 1.0.5) copies out of each answer into
its structure, and every one was seen filled by the library from this codec's answers: "[V]"
marks that, "[I]" what is inferred. The functions of FANUC's library that send each request are
named in its docstring; both command sets send the same blocks, except ``cnc_rdset`` (0x29 in
the 16i set, 0x90 in the 30i set).
"""

from __future__ import annotations

import struct
from dataclasses import dataclass
from typing import Any, ClassVar, Final, Self

from focas_net.errors import EW

from .axes import NativePositionRequest
from .base import NativePayloadError, NativeRecord, check_multiple
from .blocks import Device
from .calls import CommandSet, LibraryCall, _memoized, _one
from .items import ParamInfoRequest, ParamRead3Request, ParamReadRequest
from .records import StatInfo
from .requests import (
    HdckRequest,
    NativeCommand,
    NativeRequest,
    TmModeRequest,
    _ArgSpec,
    _register,
)

__all__ = [
    "FIGURE_TYPES",
    "MAX_PMC_AREAS",
    "RESTART_KINDS",
    "RESTART_POSITIONS",
    "SOFTWARE_SLOTS",
    "AxisFigure",
    "DiagInfoRequest",
    "DiagNumberRequest",
    "EtherInfo",
    "EtherInfoRequest",
    "FigureRequest",
    "Figures",
    "ItemNumbers",
    "ParamNumberRequest",
    "PmcAreaInfo",
    "PmcAreaInfos",
    "PmcInfoRequest",
    "PmcTitle",
    "PmcTitleRequest",
    "RestartInfoRequest",
    "RestartValues",
    "SettingInfoRequest",
    "SettingRead3Request",
    "SettingReadRequest",
    "SoftwareEdition",
    "StatInfo2",
    "StatInfo2Request",
    "SystemSoftware",
    "SystemSoftwareRequest",
]

#: ``cnc_getfigure``'s ``data_type`` 0..6 -> the argument FANUC's library sends [V] (a
#: negative one is sent as it is; above 6 the library refuses before sending).
FIGURE_TYPES: Final = (0, 1, 2, 5, 6, 3, 4)
#: The 0x43 kinds of ``cnc_rdprstrinfo``: 0 block counter, 1 M codes, 2 T codes, 3 S code,
#: 4 B code [V for what the library sends and where it copies each].
RESTART_KINDS: Final = range(5)
#: Software slots of the 0x41 answer.
SOFTWARE_SLOTS: Final = 16


# --------------------------------------------------------------------------------------------
# Records


@dataclass(frozen=True, slots=True)
class AxisFigure(NativeRecord):
    """One axis of 0x1B: ``i16`` decimal places of the input unit, then of the output unit."""

    FORMAT: ClassVar[str] = ">hh"
    input_decimals: int
    output_decimals: int


@dataclass(frozen=True, slots=True)
class Figures:
    """``cnc_getfigure`` (0x1B): ``i32`` most valid figures, then one :class:`AxisFigure` per
    axis [V]. The library keeps the low 16 bits of the first word and copies as many axes as
    the data holds ((length - 4) / 4) into the caller's two arrays, unchecked."""

    valid: int
    axes: tuple[AxisFigure, ...]

    def encode(self) -> bytes:
        try:
            head = struct.pack(">i", self.valid)
        except struct.error as exc:
            raise ValueError(f"Figures: {exc}") from None
        return head + AxisFigure.encode_many(self.axes)

    @classmethod
    def decode(cls, data: bytes) -> Self:
        if len(data) < 4:
            raise NativePayloadError(f"Figures: {len(data)} bytes", EW.LENGTH)
        (valid,) = struct.unpack_from(">i", data)
        return cls(valid, AxisFigure.decode_many(data[4:]))


@dataclass(frozen=True, slots=True)
class StatInfo2(NativeRecord):
    """``cnc_statinfo2`` (0xE2): 11 x i16, ODBST2 from ``aut`` on: ``aut, run, motion, mstb,
    emergency, alarm, edit, warning, o3dchk, ext_opt, restart`` [V]. ``hdck`` and ``tmmode``
    come from 0xE1 and 0x98 in the same frame (each taken only when its block answers EW_OK);
    the library copies as many words as the data holds."""

    FORMAT: ClassVar[str] = ">11h"
    aut: int
    run: int
    motion: int
    mstb: int
    emergency: int
    alarm: int
    edit: int
    warning: int = 0
    o3dchk: int = 0
    ext_opt: int = 0
    restart: int = 0

    @classmethod
    def of(cls, status: StatInfo, warning: int = 0) -> Self:
        """The 0xE2 record of the 0x19 record ``status``."""
        s = status
        return cls(s.aut, s.run, s.motion, s.mstb, s.emergency, s.alarm, s.edit, warning)


@dataclass(frozen=True, slots=True)
class SoftwareEdition(NativeRecord):
    """A series and an edition, 4 + 4 bytes (``"D4F1"``, ``"32.0"``): the library copies each
    4 bytes into a 5-byte text of ODBSYSS, a byte 0xFF read as NUL [V]."""

    FORMAT: ClassVar[str] = ">4s4s"
    PADDED: ClassVar[frozenset[str]] = frozenset({"series", "version"})
    series: bytes = b""
    version: bytes = b""


_NO_SLOT: Final = 0xFF
#: The named editions after the CNC's software, in ODBSYSS order: four at data offset 0x150,
#: 21 at 0x1D8 (then three reserved) [V for the offsets].
_HEAD_EDITIONS: Final = ("boot", "servo", "pmc", "ladder")
_TAIL_EDITIONS: Final = (
    "mcrlib",
    "mcrapl",
    "spl1",
    "spl2",
    "spl3",
    "c_exelib",
    "c_exeapl",
    "int_vga",
    "out_vga",
    "pmm",
    "pmc_mng",
    "pmc_shin",
    "pmc_shout",
    "pmc_c",
    "pmc_edit",
    "lddr_mng",
    "lddr_apl",
    "spl4",
    "mcr2",
    "mcr3",
    "eth_boot",
)
#: Data offsets of the 0x41 answer.
_SLOTS_AT: Final = 0x00  # u8 physical slot per software, 0xFF ends the list
_MODULES_AT: Final = 0x10  # u16 module ID by physical slot (0x30 for slots >= 0x80)
_SOFT_IDS_AT: Final = 0x50  # u16 software ID by physical slot (0x70 for slots >= 0x80)
_LOGICAL_AT: Final = 0x90  # u16 per logical slot: the high byte is its physical slot
_SERIES_AT: Final = 0xD0  # SoftwareEdition by logical slot
_HEAD_AT: Final = 0x150
_INSTALLED_AT: Final = 0x1D1
_TAIL_AT: Final = 0x1D8
_SOFTWARE_SIZE: Final = _TAIL_AT + 24 * SoftwareEdition.SIZE


@dataclass(frozen=True, slots=True)
class SystemSoftware:
    """``cnc_rdsyssoft`` (0x41), 664 bytes [V]: the CNC's software by slot (the slot, its
    module and software IDs, its series and edition), how many are installed, and the series
    and edition of the boot, servo, PMC and ladder software and of the other named modules of
    ODBSYSS (``others``: name -> edition, names as in ODBSYSS without ``_ser``/``_ver``).

    The library reads the slot list up to a 0xFF byte, finds each slot's logical place in the
    table at 0x90 and copies the IDs by slot and the editions by logical place; bytes it does
    not read are zero here. Software ``i`` of this record is at physical slot ``slots[i]`` and
    logical place ``i``.
    """

    slots: tuple[int, ...]
    module_ids: tuple[int, ...]
    soft_ids: tuple[int, ...]
    editions: tuple[SoftwareEdition, ...]
    installed: int
    boot: SoftwareEdition = SoftwareEdition()
    servo: SoftwareEdition = SoftwareEdition()
    pmc: SoftwareEdition = SoftwareEdition()
    ladder: SoftwareEdition = SoftwareEdition()
    others: tuple[tuple[str, SoftwareEdition], ...] = ()

    def encode(self) -> bytes:
        n = len(self.slots)
        if not n <= SOFTWARE_SLOTS or {len(self.module_ids), len(self.soft_ids)} != {n}:
            raise ValueError(f"SystemSoftware: {n} slots, at most {SOFTWARE_SLOTS}, one ID each")
        if len(self.editions) != n or len(set(self.slots)) != n:
            raise ValueError("SystemSoftware: one edition per slot, each slot once")
        out = bytearray(_SOFTWARE_SIZE)
        out[_SLOTS_AT : _SLOTS_AT + SOFTWARE_SLOTS] = bytes([_NO_SLOT]) * SOFTWARE_SLOTS
        out[_LOGICAL_AT : _LOGICAL_AT + 2 * SOFTWARE_SLOTS] = b"\xff\x00" * SOFTWARE_SLOTS
        try:
            for i, slot in enumerate(self.slots):
                if not 0 <= slot < _NO_SLOT or slot & 0x70:
                    raise ValueError(f"SystemSoftware: slot {slot:#x} (0x00-0x0F, 0x80-0x8F)")
                high = 0x20 if slot & 0x80 else 0
                out[_SLOTS_AT + i] = slot
                struct.pack_into(
                    ">H", out, _MODULES_AT + high + 2 * (slot & 0xF), self.module_ids[i]
                )
                struct.pack_into(
                    ">H", out, _SOFT_IDS_AT + high + 2 * (slot & 0xF), self.soft_ids[i]
                )
                out[_LOGICAL_AT + 2 * i : _LOGICAL_AT + 2 * i + 2] = bytes([slot, 0])
                out[_SERIES_AT + 8 * i : _SERIES_AT + 8 * i + 8] = self.editions[i].encode()
            out[_INSTALLED_AT] = self.installed
        except struct.error as exc:
            raise ValueError(f"SystemSoftware: {exc}") from None
        for i, name in enumerate(_HEAD_EDITIONS):
            edition: SoftwareEdition = getattr(self, name)
            out[_HEAD_AT + 8 * i : _HEAD_AT + 8 * i + 8] = edition.encode()
        others = dict(self.others)
        unknown = set(others) - set(_TAIL_EDITIONS)
        if unknown:
            raise ValueError(f"SystemSoftware: no software named {sorted(unknown)}")
        for i, name in enumerate(_TAIL_EDITIONS):
            if name in others:
                out[_TAIL_AT + 8 * i : _TAIL_AT + 8 * i + 8] = others[name].encode()
        return bytes(out)

    @classmethod
    def decode(cls, data: bytes) -> Self:
        if len(data) < _SOFTWARE_SIZE:
            raise NativePayloadError(f"SystemSoftware: {len(data)} bytes", EW.LENGTH)
        slots: list[int] = []
        for slot in data[_SLOTS_AT : _SLOTS_AT + SOFTWARE_SLOTS]:
            if slot == _NO_SLOT:
                break
            slots.append(slot)
        logical = [data[_LOGICAL_AT + 2 * j] for j in range(SOFTWARE_SLOTS)]
        module_ids, soft_ids, editions = [], [], []
        for slot in slots:
            high = 0x20 if slot & 0x80 else 0
            (module,) = struct.unpack_from(">H", data, _MODULES_AT + high + 2 * (slot & 0xF))
            (soft,) = struct.unpack_from(">H", data, _SOFT_IDS_AT + high + 2 * (slot & 0xF))
            module_ids.append(module)
            soft_ids.append(soft)
            place = logical.index(slot) if slot in logical else None
            if place is None:
                raise NativePayloadError(f"SystemSoftware: slot {slot:#x} has no place", EW.DATA)
            editions.append(SoftwareEdition.decode_from(data, _SERIES_AT + 8 * place))
        boot, servo, pmc, ladder = (
            SoftwareEdition.decode_from(data, _HEAD_AT + 8 * i) for i in range(4)
        )
        others = tuple(
            (name, edition)
            for i, name in enumerate(_TAIL_EDITIONS)
            if (edition := SoftwareEdition.decode_from(data, _TAIL_AT + 8 * i)) != SoftwareEdition()
        )
        return cls(
            tuple(slots),
            tuple(module_ids),
            tuple(soft_ids),
            tuple(editions),
            data[_INSTALLED_AT],
            boot,
            servo,
            pmc,
            ladder,
            others=others,
        )


@dataclass(frozen=True, slots=True)
class ItemNumbers(NativeRecord):
    """``cnc_rdparanum`` (0x11) and ``cnc_rddiagnum`` (0x32): ``i32 minimum, i32 maximum,
    i32 total`` [V]; ODBPARANUM / ODBDIAGNUM keep the low 16 bits of each."""

    FORMAT: ClassVar[str] = ">iii"
    minimum: int
    maximum: int
    total: int


@dataclass(frozen=True, slots=True)
class PmcAreaInfo(NativeRecord):
    """One area of 0x8003: ``u16`` the area's letter (ASCII, ``"G"``), ``u16`` its attribute,
    ``i32`` its first and ``i32`` its last address; ODBPMCINF keeps the low byte of the first
    two and the low 16 bits of the addresses [V]."""

    FORMAT: ClassVar[str] = ">HHii"
    letter: int
    attribute: int
    first: int
    last: int


#: Most areas ODBPMCINF holds (the library copies as many as the answer counts, unchecked).
MAX_PMC_AREAS: Final = 64


@dataclass(frozen=True, slots=True)
class PmcAreaInfos:
    """``pmc_rdpmcinfo`` (0x8003): ``i32`` the number of areas, then one :class:`PmcAreaInfo`
    each [V]. The library copies as many areas as the count says, whatever the data length,
    into a structure of 64, so the count must be the records sent and at most 64."""

    areas: tuple[PmcAreaInfo, ...]

    def encode(self) -> bytes:
        if len(self.areas) > MAX_PMC_AREAS:
            raise ValueError(f"PmcAreaInfos: {len(self.areas)} areas, at most {MAX_PMC_AREAS}")
        return struct.pack(">i", len(self.areas)) + PmcAreaInfo.encode_many(self.areas)

    @classmethod
    def decode(cls, data: bytes) -> Self:
        if len(data) < 4:
            raise NativePayloadError(f"PmcAreaInfos: {len(data)} bytes", EW.LENGTH)
        (count,) = struct.unpack_from(">i", data)
        if not 0 <= count <= MAX_PMC_AREAS or len(data) != 4 + count * PmcAreaInfo.SIZE:
            raise NativePayloadError(f"PmcAreaInfos: {count} areas in {len(data)} bytes", EW.LENGTH)
        return cls(PmcAreaInfo.decode_many(data[4:]))


@dataclass(frozen=True, slots=True)
class PmcTitle(NativeRecord):
    """``pmc_rdpmctitle`` (0x800B), 246 bytes of NUL-padded texts [V]: ``mtb`` 32, ``machine``
    32, ``type`` 32, ``prgno`` 4, ``prgvers`` 2, ``prgdraw`` 32, ``date`` 16, ``design`` 32,
    ``written`` 32, ``remarks`` 32. The library zeroes ODBPMCTITLE and copies each field into
    its wider place (48 bytes for the 32-byte texts, 8 for ``prgno``, 4 for ``prgvers``)."""

    FORMAT: ClassVar[str] = ">32s32s32s4s2s32s16s32s32s32s"
    PADDED: ClassVar[frozenset[str]] = frozenset(
        {
            "mtb",
            "machine",
            "type",
            "prgno",
            "prgvers",
            "prgdraw",
            "date",
            "design",
            "written",
            "remarks",
        }
    )
    mtb: bytes
    machine: bytes
    type: bytes
    prgno: bytes
    prgvers: bytes
    prgdraw: bytes = b""
    date: bytes = b""
    design: bytes = b""
    written: bytes = b""
    remarks: bytes = b""


@dataclass(frozen=True, slots=True)
class EtherInfo(NativeRecord):
    """``cnc_rdetherinfo`` (0x159): ``i16 type, i16 device`` [V]."""

    FORMAT: ClassVar[str] = ">hh"
    type: int
    device: int


@dataclass(frozen=True, slots=True)
class RestartValues:
    """One 0x43 answer of ``cnc_rdprstrinfo``: a run of ``i32`` values; the library counts
    them (data length / 4) into ``data_info`` and copies them, unchecked, into the place of
    the kind (1 block counter, 35 M codes, 2 T codes, 1 S code, 1 B code) [V]."""

    values: tuple[int, ...]

    def encode(self) -> bytes:
        try:
            return struct.pack(f">{len(self.values)}i", *self.values)
        except struct.error as exc:
            raise ValueError(f"RestartValues: {exc}") from None

    @classmethod
    def decode(cls, data: bytes) -> Self:
        check_multiple(data, 4, "RestartValues")
        return cls(struct.unpack(f">{len(data) // 4}i", data))


# --------------------------------------------------------------------------------------------
# Requests


@dataclass(frozen=True, slots=True)
class FigureRequest(NativeRequest):
    """0x1B, args ``data_type`` (``cnc_getfigure(type)`` sends :data:`FIGURE_TYPES` [type])
    [V]: :class:`Figures`."""

    COMMAND: ClassVar[int] = NativeCommand.GETFIGURE
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = ("data_type",)
    ANSWER: ClassVar[Any] = Figures
    data_type: int = 0


@dataclass(frozen=True, slots=True)
class StatInfo2Request(NativeRequest):
    """0xE2, no arguments: :class:`StatInfo2` (``cnc_statinfo2`` sends it with 0xE1 and 0x98;
    its call fails when 0xE2 fails) [V]."""

    COMMAND: ClassVar[int] = NativeCommand.STATINFO2
    ANSWER: ClassVar[Any] = StatInfo2


@dataclass(frozen=True, slots=True)
class SystemSoftwareRequest(NativeRequest):
    """0x41, no arguments: :class:`SystemSoftware` (``cnc_rdsyssoft``) [V]."""

    COMMAND: ClassVar[int] = NativeCommand.RDSYSSOFT
    ANSWER: ClassVar[Any] = SystemSoftware


@dataclass(frozen=True, slots=True)
class ParamNumberRequest(NativeRequest):
    """0x11, no arguments: :class:`ItemNumbers` of the parameters (``cnc_rdparanum``) [V]."""

    COMMAND: ClassVar[int] = NativeCommand.RDPARANUM
    ANSWER: ClassVar[Any] = ItemNumbers


@dataclass(frozen=True, slots=True)
class DiagNumberRequest(NativeRequest):
    """0x32, no arguments: :class:`ItemNumbers` of the diagnostics (``cnc_rddiagnum``) [V]."""

    COMMAND: ClassVar[int] = NativeCommand.RDDIAGNUM
    ANSWER: ClassVar[Any] = ItemNumbers


@dataclass(frozen=True, slots=True)
class DiagInfoRequest(ParamInfoRequest):
    """0x31, args ``first, count`` (``cnc_rddiaginfo(s, n)``): :class:`ParamInfo` of the
    diagnostics (the library decodes it as 0x10's answer) [V]."""

    COMMAND: ClassVar[int] = NativeCommand.RDDIAGINFO


@dataclass(frozen=True, slots=True)
class SettingInfoRequest(ParamInfoRequest):
    """0x2B, args ``first, count`` (``cnc_rdsetinfo(s, n)``): :class:`ParamInfo` of the
    setting data (decoded as 0x10's answer) [V]."""

    COMMAND: ClassVar[int] = NativeCommand.RDSETINFO


@dataclass(frozen=True, slots=True)
class SettingReadRequest(ParamReadRequest):
    """0x29, args ``first, last, axis`` (``cnc_rdset(n, axis)``, 16i set): :class:`ItemValues`
    of setting data, read as 0x0E's records (parameter type numbering) [V]."""

    COMMAND: ClassVar[int] = NativeCommand.RDSET


@dataclass(frozen=True, slots=True)
class SettingRead3Request(ParamRead3Request):
    """0x90, args ``first, last, axis`` (``cnc_rdset``, 30i set): 8-byte slots as 0x8D's [V]."""

    COMMAND: ClassVar[int] = NativeCommand.RDSET3


@dataclass(frozen=True, slots=True)
class PmcInfoRequest(NativeRequest):
    """Device PMC, 0x8003, args ``data_type`` (``pmc_rdpmcinfo(type)``) [V]:
    :class:`PmcAreaInfos`."""

    DEVICE: ClassVar[int] = Device.PMC
    COMMAND: ClassVar[int] = NativeCommand.PMC_RDPMCINFO
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = ("data_type",)
    ANSWER: ClassVar[Any] = PmcAreaInfos
    data_type: int = 0


@dataclass(frozen=True, slots=True)
class PmcTitleRequest(NativeRequest):
    """Device PMC, 0x800B, no arguments: :class:`PmcTitle` (``pmc_rdpmctitle``) [V]."""

    DEVICE: ClassVar[int] = Device.PMC
    COMMAND: ClassVar[int] = NativeCommand.PMC_RDPMCTITLE
    ANSWER: ClassVar[Any] = PmcTitle


@dataclass(frozen=True, slots=True)
class EtherInfoRequest(NativeRequest):
    """0x159, no arguments: :class:`EtherInfo` (``cnc_rdetherinfo``) [V]."""

    COMMAND: ClassVar[int] = NativeCommand.RDETHERINFO
    ANSWER: ClassVar[Any] = EtherInfo


@dataclass(frozen=True, slots=True)
class RestartInfoRequest(NativeRequest):
    """0x43, args ``kind`` (``cnc_rdprstrinfo`` sends kinds 0..4, then 0x26 kinds 13 and 14
    for every axis, in one frame) [V]: :class:`RestartValues`."""

    COMMAND: ClassVar[int] = NativeCommand.RDPRSTRINFO
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = ("kind",)
    ANSWER: ClassVar[Any] = RestartValues
    kind: int = 0


_register(
    FigureRequest,
    StatInfo2Request,
    SystemSoftwareRequest,
    ParamNumberRequest,
    DiagNumberRequest,
    DiagInfoRequest,
    SettingInfoRequest,
    SettingReadRequest,
    SettingRead3Request,
    PmcInfoRequest,
    PmcTitleRequest,
    EtherInfoRequest,
    RestartInfoRequest,
)

#: The position kinds (0x26) of ``cnc_rdprstrinfo``: the restart point and the distance to it.
RESTART_POSITIONS: Final = (13, 14)


# --------------------------------------------------------------------------------------------
# What each function of FANUC's library sends (both command sets unless said)


@_memoized
def cnc_getfigure(cs: CommandSet, data_type: int) -> LibraryCall:
    """0x1B ``(FIGURE_TYPES[data_type])`` [V]."""
    wire = FIGURE_TYPES[data_type] if 0 <= data_type < len(FIGURE_TYPES) else data_type
    return _one("cnc_getfigure", FigureRequest(wire))


@_memoized
def cnc_statinfo2(cs: CommandSet) -> LibraryCall:
    """0xE2, 0xE1, 0x98 in one frame [V]."""
    return _one("cnc_statinfo2", StatInfo2Request(), HdckRequest(), TmModeRequest())


@_memoized
def cnc_rdsyssoft(cs: CommandSet) -> LibraryCall:
    """0x41 [V]."""
    return _one("cnc_rdsyssoft", SystemSoftwareRequest())


@_memoized
def cnc_rdparanum(cs: CommandSet) -> LibraryCall:
    """0x11 [V]."""
    return _one("cnc_rdparanum", ParamNumberRequest())


@_memoized
def cnc_rddiagnum(cs: CommandSet) -> LibraryCall:
    """0x32 [V]."""
    return _one("cnc_rddiagnum", DiagNumberRequest())


@_memoized
def cnc_rddiaginfo(cs: CommandSet, first: int, count: int) -> LibraryCall:
    """0x31 ``(first, count)`` [V]."""
    return _one("cnc_rddiaginfo", DiagInfoRequest(first, count))


@_memoized
def cnc_rdsetinfo(cs: CommandSet, first: int, count: int) -> LibraryCall:
    """0x2B ``(first, count)`` [V]."""
    return _one("cnc_rdsetinfo", SettingInfoRequest(first, count))


@_memoized
def cnc_rdset(cs: CommandSet, number: int, axis: int) -> LibraryCall:
    """0x29 ``(n, n, axis)`` in the 16i set, 0x90 in the 30i set [V]."""
    if cs is CommandSet.FS16I:
        return _one("cnc_rdset", SettingReadRequest(number, number, axis))
    return _one("cnc_rdset", SettingRead3Request(number, number, axis))


@_memoized
def pmc_rdpmcinfo(cs: CommandSet, data_type: int) -> LibraryCall:
    """Device PMC, 0x8003 ``(type)`` [V]."""
    return _one("pmc_rdpmcinfo", PmcInfoRequest(data_type))


@_memoized
def pmc_rdpmctitle(cs: CommandSet) -> LibraryCall:
    """Device PMC, 0x800B [V]."""
    return _one("pmc_rdpmctitle", PmcTitleRequest())


@_memoized
def cnc_rdetherinfo(cs: CommandSet) -> LibraryCall:
    """0x159 [V]."""
    return _one("cnc_rdetherinfo", EtherInfoRequest())


@_memoized
def cnc_rdprstrinfo(cs: CommandSet) -> LibraryCall:
    """0x43 kinds 0..4, then 0x26 ``(13, -1)`` and ``(14, -1)``, in one frame [V]."""
    restart: tuple[NativeRequest, ...] = tuple(RestartInfoRequest(k) for k in RESTART_KINDS)
    positions = tuple(NativePositionRequest(kind, -1) for kind in RESTART_POSITIONS)
    return _one("cnc_rdprstrinfo", *restart, *positions)
