"""The native client's reads of the CNC's information (``docs/native-client.md``):
:class:`NativeInfo` is the part of :class:`~focas_net.client.NativeClient` that sends what
FANUC's library sends for ``cnc_getfigure``, ``cnc_statinfo2``, ``cnc_rdsyssoft``,
``cnc_rdparanum``, ``cnc_rddiagnum``, ``cnc_rddiaginfo``, ``cnc_rdset``, ``cnc_rdsetinfo``,
``pmc_rdpmcinfo``, ``pmc_rdpmctitle``, ``cnc_rdetherinfo`` and ``cnc_rdprstrinfo``
(:mod:`focas_net.native.info`), and the typed results it makes of their answers. Each call's
arguments are checked in the caller's frame, before anything is sent.
"""

# Every call takes a per-call ``timeout=`` by contract, so ASYNC109 does not apply here.
# ruff: noqa: ASYNC109

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Final

from ..native import EtherInfo as _EtherInfo
from ..native import (
    Figures,
    ItemNumbers,
    LibraryCall,
    ParamInfo,
    PmcAreaInfos,
    PmcTitle,
    ResponseBlock,
    RestartValues,
    ScaledValues,
    SoftwareEdition,
    StatInfo2,
    SystemSoftware,
    info,
)
from ..protocol import ParamValue
from ._native_items import NativeItems, decoded, only_answer, text
from ._native_link import Handle
from ._values import I16_MAX, check_int, check_item

__all__ = [
    "EthernetInfo",
    "ItemAttributes",
    "ItemRange",
    "PmcAreaSpan",
    "PmcTitleInfo",
    "RestartInfo",
    "SoftwareInfo",
    "SoftwareSlot",
    "StatusInfo2",
    "ValidFigures",
]

#: ``cnc_getfigure``'s data types (the library refuses others before sending).
_FIGURE_TYPES: Final = len(info.FIGURE_TYPES) - 1
#: ``pmc_rdpmcinfo``'s data types: -1 (every type), 0 byte, 1 word, 2 long.
_PMC_TYPES: Final = (-1, 2)
#: Most entries ``cnc_rddiaginfo`` / ``cnc_rdsetinfo`` take (ODBPARAIF holds ten).
_MAX_INFO: Final = 10


@dataclass(frozen=True, slots=True)
class ValidFigures:
    """``cnc_getfigure``: the most valid figures of the data and, per axis, the decimal
    places of its input and output units."""

    valid: int
    input_decimals: tuple[int, ...]
    output_decimals: tuple[int, ...]


@dataclass(frozen=True, slots=True)
class StatusInfo2:
    """``cnc_statinfo2`` (ODBST2): the fields of ``cnc_statinfo``, then ``warning``,
    ``o3dchk``, ``ext_opt`` and ``restart``."""

    hdck: int
    tmmode: int
    aut: int
    run: int
    motion: int
    mstb: int
    emergency: int
    alarm: int
    edit: int
    warning: int
    o3dchk: int
    ext_opt: int
    restart: int


@dataclass(frozen=True, slots=True)
class SoftwareSlot:
    """One piece of the CNC's software of ``cnc_rdsyssoft``: its slot, its module and
    software IDs, its series and edition."""

    slot: int
    module_id: int
    soft_id: int
    series: str
    version: str


@dataclass(frozen=True, slots=True)
class SoftwareInfo:
    """``cnc_rdsyssoft`` (ODBSYSS): the CNC's software by slot, how many are installed, and
    the ``(series, edition)`` of the boot, servo, PMC and ladder software and of the other
    named modules the CNC reports (``others``: name -> edition, names as in ODBSYSS)."""

    software: tuple[SoftwareSlot, ...]
    installed: int
    boot: tuple[str, str]
    servo: tuple[str, str]
    pmc: tuple[str, str]
    ladder: tuple[str, str]
    others: tuple[tuple[str, tuple[str, str]], ...] = ()


@dataclass(frozen=True, slots=True)
class ItemRange:
    """``cnc_rdparanum`` / ``cnc_rddiagnum``: the lowest and highest number and how many."""

    minimum: int
    maximum: int
    total: int


@dataclass(frozen=True, slots=True)
class ItemAttributes:
    """``cnc_rddiaginfo`` / ``cnc_rdsetinfo`` (ODBDIAGIF / ODBSETIF): the numbers before and
    after the ones read (0 for none) and each one's ``(number, type)`` (the type in FOCAS's
    parameter numbering, 0 bit .. 3 two-word, as the library gives it)."""

    previous: int
    next: int
    items: tuple[tuple[int, int], ...]


@dataclass(frozen=True, slots=True)
class PmcAreaSpan:
    """One area of ``pmc_rdpmcinfo`` (ODBPMCINF): its letter, its attribute, its first and
    last address."""

    letter: str
    attribute: int
    first: int
    last: int


@dataclass(frozen=True, slots=True)
class PmcTitleInfo:
    """``pmc_rdpmctitle`` (ODBPMCTITLE): the ladder's title data."""

    mtb: str
    machine: str
    type: str
    prgno: str
    prgvers: str
    prgdraw: str
    date: str
    design: str
    written: str
    remarks: str


@dataclass(frozen=True, slots=True)
class EthernetInfo:
    """``cnc_rdetherinfo``: the kind and the device of the CNC's Ethernet port."""

    type: int
    device: int


@dataclass(frozen=True, slots=True)
class RestartInfo:
    """``cnc_rdprstrinfo`` (ODBPRS): the program restart data, each kind the values the CNC
    holds (none when it keeps none): block counter, M, T, S and B codes, and per axis the
    restart point and the distance to it (increments)."""

    block_counter: tuple[int, ...]
    m_codes: tuple[int, ...]
    t_codes: tuple[int, ...]
    s_codes: tuple[int, ...]
    b_codes: tuple[int, ...]
    point: tuple[int, ...]
    distance: tuple[int, ...]


def _edition(edition: SoftwareEdition) -> tuple[str, str]:
    return (text(edition.series), text(edition.version))


def _software(answer: SystemSoftware) -> SoftwareInfo:
    slots = tuple(
        SoftwareSlot(slot, module, soft, *_edition(edition))
        for slot, module, soft, edition in zip(
            answer.slots, answer.module_ids, answer.soft_ids, answer.editions, strict=True
        )
    )
    return SoftwareInfo(
        slots,
        answer.installed,
        _edition(answer.boot),
        _edition(answer.servo),
        _edition(answer.pmc),
        _edition(answer.ladder),
        tuple((name, _edition(e)) for name, e in answer.others),
    )


def _attributes(answer: ParamInfo) -> ItemAttributes:
    return ItemAttributes(
        answer.prev_no, answer.next_no, tuple((e.number, e.attribute & 3) for e in answer.entries)
    )


def _restart(
    handle: Handle, call: LibraryCall, blocks: tuple[ResponseBlock, ...], path: int
) -> RestartInfo:
    kinds: list[tuple[int, ...]] = []
    for i in range(len(info.RESTART_KINDS)):
        values: RestartValues = decoded(handle, call, blocks, i, handle.max_axes)
        kinds.append(values.values)
    axes = handle.axes_on(path)
    positions: list[tuple[int, ...]] = []
    for i in range(len(info.RESTART_KINDS), len(blocks)):
        scaled: ScaledValues = decoded(handle, call, blocks, i, handle.max_axes)
        positions.append(tuple(v.mantissa for v in scaled.values[:axes]))
    return RestartInfo(*kinds, *positions)


class NativeInfo(NativeItems):
    """The reads of the CNC's information over FOCAS/2 (see the module docstring)."""

    async def read_figures(
        self, data_type: int = 0, *, path: int | None = None, timeout: float | None = None
    ) -> ValidFigures:
        """``cnc_getfigure``: the most valid figures and each axis's decimal places of the
        input and output units of ``data_type`` (0 the positions, 0..6)."""
        check_int("figure data type", data_type, 0, _FIGURE_TYPES)
        handle, call, blocks = await self._only(info.cnc_getfigure, path, timeout, data_type)
        figures: Figures = only_answer(handle, call, blocks)
        return ValidFigures(
            _signed16(figures.valid),
            tuple(a.input_decimals for a in figures.axes),
            tuple(a.output_decimals for a in figures.axes),
        )

    async def read_status2(
        self, *, path: int | None = None, timeout: float | None = None
    ) -> StatusInfo2:
        """``cnc_statinfo2``: the status with its warning (hdck and tmmode read 0 when the CNC
        refuses them, as the library reads them)."""
        handle, call, blocks = await self._only(info.cnc_statinfo2, path, timeout)
        stat: StatInfo2 = decoded(handle, call, blocks, 0, handle.max_axes)
        hdck = 0 if blocks[1].ew else decoded(handle, call, blocks, 1, 0).hdck
        tmmode = 0 if blocks[2].ew else decoded(handle, call, blocks, 2, 0).tmmode
        return StatusInfo2(
            hdck, tmmode, stat.aut, stat.run, stat.motion, stat.mstb, stat.emergency,
            stat.alarm, stat.edit, stat.warning, stat.o3dchk, stat.ext_opt, stat.restart,
        )  # fmt: skip

    async def read_system_software(
        self, *, path: int | None = None, timeout: float | None = None
    ) -> SoftwareInfo:
        """``cnc_rdsyssoft``: the CNC's system software, series and editions."""
        handle, call, blocks = await self._only(info.cnc_rdsyssoft, path, timeout)
        return _software(only_answer(handle, call, blocks))

    async def read_param_numbers(
        self, *, path: int | None = None, timeout: float | None = None
    ) -> ItemRange:
        """``cnc_rdparanum``: the lowest and highest parameter number, and how many."""
        handle, call, blocks = await self._only(info.cnc_rdparanum, path, timeout)
        n: ItemNumbers = only_answer(handle, call, blocks)
        return ItemRange(n.minimum, n.maximum, n.total)

    async def read_diag_numbers(
        self, *, path: int | None = None, timeout: float | None = None
    ) -> ItemRange:
        """``cnc_rddiagnum``: the lowest and highest diagnostic number, and how many."""
        handle, call, blocks = await self._only(info.cnc_rddiagnum, path, timeout)
        n: ItemNumbers = only_answer(handle, call, blocks)
        return ItemRange(n.minimum, n.maximum, n.total)

    async def read_diag_attributes(
        self,
        first: int = 0,
        count: int = _MAX_INFO,
        *,
        path: int | None = None,
        timeout: float | None = None,
    ) -> ItemAttributes:
        """``cnc_rddiaginfo``: the types of up to ``count`` (1..10) diagnostics from number
        ``first`` on."""
        return await self._attributes(
            info.cnc_rddiaginfo, "diagnostic", first, count, path, timeout
        )

    async def read_setting_attributes(
        self,
        first: int = 0,
        count: int = _MAX_INFO,
        *,
        path: int | None = None,
        timeout: float | None = None,
    ) -> ItemAttributes:
        """``cnc_rdsetinfo``: the types of up to ``count`` (1..10) setting data from number
        ``first`` on."""
        return await self._attributes(info.cnc_rdsetinfo, "setting", first, count, path, timeout)

    async def _attributes(
        self,
        call_of: Callable[..., LibraryCall],
        what: str,
        first: int,
        count: int,
        path: int | None,
        timeout: float | None,
    ) -> ItemAttributes:
        """The types of up to ``count`` items of kind ``what`` from number ``first`` on."""
        check_int(f"{what} number", first, 0, I16_MAX)
        check_int("count", count, 1, _MAX_INFO)
        return _attributes(only_answer(*await self._only(call_of, path, timeout, first, count)))

    async def read_setting(
        self,
        number: int,
        *,
        axis: int = 0,
        path: int | None = None,
        timeout: float | None = None,
    ) -> ParamValue:
        """``cnc_rdset``: setting data ``number`` as an IODBPSD (a bit setting's byte, a real
        one's REALPRM with its decimals), read as ``cnc_rdparam`` reads a parameter."""
        check_item(number, axis, "setting")
        p = self._path_of(path)
        return await self._read_item(
            number, axis, self._deadline(timeout), p, diagnostic=False, setting=True
        )

    async def read_pmc_areas(
        self, data_type: int = -1, *, timeout: float | None = None
    ) -> tuple[PmcAreaSpan, ...]:
        """``pmc_rdpmcinfo``: the PMC's areas (letter, attribute, first and last address) for
        ``data_type`` (-1 every type, 0 byte, 1 word, 2 long)."""
        check_int("PMC data type", data_type, *_PMC_TYPES)
        handle, call, blocks = await self._only(info.pmc_rdpmcinfo, None, timeout, data_type)
        areas: PmcAreaInfos = only_answer(handle, call, blocks)
        return tuple(
            PmcAreaSpan(chr(a.letter & 0xFF), a.attribute & 0xFF, a.first, a.last)
            for a in areas.areas
        )

    async def read_pmc_title(self, *, timeout: float | None = None) -> PmcTitleInfo:
        """``pmc_rdpmctitle``: the PMC's title data."""
        handle, call, blocks = await self._only(info.pmc_rdpmctitle, None, timeout)
        t: PmcTitle = only_answer(handle, call, blocks)
        return PmcTitleInfo(
            text(t.mtb), text(t.machine), text(t.type), text(t.prgno), text(t.prgvers),
            text(t.prgdraw), text(t.date), text(t.design), text(t.written), text(t.remarks),
        )  # fmt: skip

    async def read_ethernet_info(self, *, timeout: float | None = None) -> EthernetInfo:
        """``cnc_rdetherinfo``: the kind and the device of the CNC's Ethernet port."""
        handle, call, blocks = await self._only(info.cnc_rdetherinfo, None, timeout)
        e: _EtherInfo = only_answer(handle, call, blocks)
        return EthernetInfo(e.type, e.device)

    async def read_restart_info(
        self, *, path: int | None = None, timeout: float | None = None
    ) -> RestartInfo:
        """``cnc_rdprstrinfo``: the program restart data of the path."""
        p = self._path_of(path)
        handle, call, blocks = await self._only(info.cnc_rdprstrinfo, p, timeout)
        return _restart(handle, call, blocks, p)


def _signed16(value: int) -> int:
    """The low 16 bits of ``value`` as a signed word (as the library keeps them)."""
    return ((value + 0x8000) & 0xFFFF) - 0x8000
