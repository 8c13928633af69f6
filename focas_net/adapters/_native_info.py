"""The native adapter's handlers of the CNC's information (``docs/native-protocol.md``; what a
handler is: :mod:`focas_net.adapters.native`): the figures of the data (0x1B), the status with
its warning (0xE2), the system software (0x41), the parameter and diagnostic numbers and
attributes (0x11, 0x32, 0x31), the setting data and their attributes (0x29, 0x90, 0x2B), the
PMC's areas and title (0x8003, 0x800B), the Ethernet board (0x159) and the program restart
information (0x43).

Every answer is the machine's (:class:`~focas_net.sim.Machine`'s information, its parameters,
diagnostics, PMC areas and programs), so it agrees with what the machine says through its
other answers: the software is the identity's series and version (``cnc_sysinfo``), the PMC
ranges are those ``pmc_rdpmcrng`` reads, the numbers are those ``cnc_rdparam`` and
``cnc_diagnoss`` answer, the setting data are parameters read as ``cnc_rdparam`` reads them.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Final

from focas_net.errors import EW
from focas_net.native import (
    RESTART_POSITIONS,
    SCALED_SIZE,
    AxisFigure,
    DiagInfoRequest,
    EtherInfo,
    FigureRequest,
    Figures,
    ItemNumbers,
    NativePmcArea,
    NativePositionRequest,
    ParamInfo,
    ParamInfoEntry,
    PmcAreaInfo,
    PmcAreaInfos,
    PmcInfoRequest,
    PmcTitle,
    RequestBlock,
    RestartInfoRequest,
    RestartValues,
    ScaledNumber,
    ScaledValues,
    SettingInfoRequest,
    SoftwareEdition,
    StatInfo2,
    SystemSoftware,
)
from focas_net.sim import POSITION_DECIMALS, DataItem, Machine, Session
from focas_net.sim import SoftwareVersion as MachineSoftware

from ._common import Refused, need_room
from ._native_cnc import CncHandlers, block_path
from ._native_data import DataHandlers, info_window, native_param_type

__all__ = ["InfoHandlers"]

#: ``cnc_getfigure``'s data type of the axes' positions (the only one the machine models).
_POSITION_FIGURES: Final = 0
#: The PMC data types ``pmc_rdpmcinfo`` takes: -1 (every type), 0 byte, 1 word, 2 long.
_PMC_TYPES: Final = range(-1, 3)
#: The software slot of the CNC's own software (its base board) and the order of the named
#: editions of the 0x41 answer.
_CNC_SLOT: Final = 0
_NAMED: Final = ("boot", "servo", "pmc", "ladder")


class InfoHandlers:
    """The handlers of the CNC's information of one machine (see the module docstring)."""

    __slots__ = ("_cnc", "_data", "machine")

    def __init__(self, machine: Machine, cnc: CncHandlers, data: DataHandlers) -> None:
        self.machine = machine
        self._cnc = cnc
        self._data = data

    def read_figures(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0x1B: the most valid figures and each axis's decimal places (input, output) of the
        positions (data type 0); another data type answers EW_ATTRIB."""
        req = FigureRequest.from_block(block)
        if req.data_type != _POSITION_FIGURES:
            raise Refused(EW.ATTRIB)
        valid, axes = self.machine.figures(path=block_path(block))
        data = Figures(valid, tuple(AxisFigure(i, o) for i, o in axes)).encode()
        need_room(len(data), room)
        return data

    def read_status2(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0xE2: the status of 0x19, then warning, o3dchk, ext_opt and restart, 0 (the
        machine has no warnings, no 3-D interference check, no program restart)."""
        return StatInfo2.of(self._cnc.status_info(block_path(block))).encode()

    def read_software(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0x41: the CNC's own software in slot 0, then boot, servo, PMC and ladder."""
        software = {s.name: s for s in self.machine.system_software()}
        own = software["cnc"]
        boot, servo, pmc, ladder = (_wire_edition(software[name]) for name in _NAMED)
        data = SystemSoftware(
            slots=(_CNC_SLOT,),
            module_ids=(0,),
            soft_ids=(0,),
            editions=(_wire_edition(own),),
            installed=1,
            boot=boot,
            servo=servo,
            pmc=pmc,
            ladder=ladder,
        ).encode()
        need_room(len(data), room)
        return data

    def read_param_numbers(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0x11: the lowest and highest parameter numbers and how many there are."""
        return _numbers(self.machine.param_numbers())

    def read_diag_numbers(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0x32: the lowest and highest diagnostic numbers and how many there are."""
        return _numbers(self.machine.diag_numbers())

    def read_diag_info(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0x31: as 0x10, over the diagnostics."""
        req = DiagInfoRequest.from_block(block)
        m = self.machine
        return _info(m.diag_numbers(), m.diag_item, req.first, req.count, room)

    def read_setting_info(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0x2B: as 0x10, over the setting data."""
        req = SettingInfoRequest.from_block(block)
        m = self.machine
        return _info(m.setting_numbers(), m.param_item, req.first, req.count, room)

    def read_settings(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0x29 (16i set): setting data as 0x0E records."""
        return self._settings(block, room, scaled=False)

    def read_settings_30i(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0x90 (30i set): setting data as 0x8D records."""
        return self._settings(block, room, scaled=True)

    def _settings(self, block: RequestBlock, room: int, *, scaled: bool) -> bytes:
        m = self.machine
        data = self._data
        return data._items(
            block, room, m.setting_numbers(), m.read_param, m.param_item, native_param_type, scaled
        )

    def read_pmc_info(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0x8003: every PMC area the machine has (in FOCAS's area order), its letter, 0 as
        the attribute, its first and last byte address; a data type other than -1..2 answers
        EW_ATTRIB."""
        req = PmcInfoRequest.from_block(block)
        if req.data_type not in _PMC_TYPES:
            raise Refused(EW.ATTRIB)
        ranges = {r.letter: r for r in self.machine.pmc_ranges()}
        areas = tuple(
            PmcAreaInfo(ord(area.name), 0, r.first, r.last)
            for area in NativePmcArea
            if (r := ranges.get(area.name)) is not None
        )
        data = PmcAreaInfos(areas).encode()
        need_room(len(data), room)
        return data

    def read_pmc_title(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0x800B: the PMC's title data."""
        t = self.machine.pmc_title()
        texts = (
            t.mtb,
            t.machine,
            t.pmc_type,
            t.program,
            t.edition,
            t.drawing,
            t.date,
            t.designer,
            t.writer,
            t.remarks,
        )
        raw = [text.encode("latin-1", "replace") for text in texts]
        widths = [size for _, size in _TITLE_WIDTHS]
        return PmcTitle(*(r[:w] for r, w in zip(raw, widths, strict=True))).encode()

    def read_ether_info(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0x159: the kind and the device of the CNC's Ethernet port."""
        board = self.machine.ethernet_board()
        return EtherInfo(board.kind, board.device).encode()

    def read_restart_info(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0x43 kinds 0..4: the machine keeps no program restart data, so each kind answers no
        value (``data_info`` 0 in ODBPRS); another kind answers EW_ATTRIB."""
        req = RestartInfoRequest.from_block(block)
        if req.kind not in range(5):
            raise Refused(EW.ATTRIB)
        self.machine.path_info(block_path(block))  # EW_PATH for a path the machine has not
        return RestartValues(()).encode()

    def read_positions(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0x26: kinds 13 and 14 (``cnc_rdprstrinfo``: the program restart point and the
        distance to it) answer zero for every axis (all: the open answer's max axes), the
        machine keeping no restart data; every other kind is the position read of
        :class:`~focas_net.adapters._native_cnc.CncHandlers`."""
        req = NativePositionRequest.from_block(block)
        if req.kind not in RESTART_POSITIONS:
            return self._cnc.read_positions(block, room, session)
        axes = self.machine.path_info(block_path(block)).axes  # EW_PATH first
        if req.axis == -1:
            count = self._cnc.max_axis
        elif 1 <= req.axis <= len(axes):
            count = 1
        else:
            raise Refused(EW.ATTRIB)
        need_room(SCALED_SIZE * count, room)
        return ScaledValues((ScaledNumber(0, POSITION_DECIMALS),) * count).encode()


#: The texts of 0x800B and their widths.
_TITLE_WIDTHS: Final = tuple((name, int(code[:-1])) for name, code in PmcTitle.layout())


def _wire_edition(edition: MachineSoftware) -> SoftwareEdition:
    """The 0x41 record of one of the machine's software editions."""
    return SoftwareEdition(edition.series.encode("ascii"), edition.version.encode("ascii"))


def _numbers(numbers: tuple[int, ...]) -> bytes:
    """0x11/0x32: ``(lowest, highest, count)``; all 0 for none."""
    if not numbers:
        return ItemNumbers(0, 0, 0).encode()
    return ItemNumbers(numbers[0], numbers[-1], len(numbers)).encode()


def _info(
    numbers: tuple[int, ...],
    item_of: Callable[[int], DataItem | None],
    first: int,
    count: int,
    room: int,
) -> bytes:
    """The 0x10 layout over ``numbers``: ``prev, next``, then from ``first`` on ``count``
    entries of number and attribute (the type in bits 0-1); EW_LENGTH for a count below 1,
    EW_NUMBER with none from ``first`` on."""
    prev_no, next_no, chosen = info_window(numbers, first, count)
    need_room(8 + ParamInfoEntry.SIZE * len(chosen), room)
    entries = []
    for number in chosen:
        item = item_of(number)
        assert item is not None  # one of the machine's own numbers
        entries.append(ParamInfoEntry(number, native_param_type(item) & 3))
    return ParamInfo(prev_no, next_no, tuple(entries)).encode()
