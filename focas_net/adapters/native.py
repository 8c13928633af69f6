"""The native adapter: the open answer, and one data-request body in, the whole answer out.

Pure and synchronous, like :mod:`focas_net.adapters.packed` on the packed side: a
:class:`NativeAdapter` wraps one protocol-neutral :class:`~focas_net.sim.Machine` and speaks as
a real control of the machine's class does to FANUC's library (``libfwlib32``):

* **the command set** follows the machine's ``control_class``: a 16i, 18i, 21i or 0i-C answers
  with version 2 (the "16i set": parameters 0x0E/0x10/0x0F, diagnostics 0x30, base-2 macro
  writes), a 0i-D, 0i-F, 30i, 31i or 32i with version 3 (the "30i set": 0x8D/0xA0/0x8E, 0x93,
  0xA4/0xA3 wrapping, base-10 macro writes); see :class:`focas_net.native.CommandSet`;
* **the open answer** (:meth:`NativeAdapter.open_answer`) describes every path of the machine
  (its machine type, axes and spindles), the path count ``cnc_getpath`` reports and the CNC's
  max axes; the FOCAS option bits (bit 0, needed by ``cnc_rddynamic2``) are in the open answer
  at version 3 and in parameter 9968 at version 2. A multi-path machine's answer carries the
  library's whole table of :data:`~focas_net.native.PATH_RECORDS` path records, the absent
  ones empty, so that ``cnc_setpath`` past the last path fails in the library (EW_PATH), as
  against a real control; a single-path machine's carries its one record, as it always did;
* every request block is answered with a block, in order (device, path and command echoed, an
  EW code, the data). Every command of both sets is served whichever set the handle uses;
* part programs: directory, memory, delete, search and the blocks being executed are data
  requests; uploads and downloads are frames of their own (:meth:`NativeAdapter.transfer`),
  a download kept in the connection's :class:`ProgramTransfer` and stored at its end only.

Rules of this wire (the CNC's rules are the machine's, see :mod:`focas_net.sim.machine`):

* a block whose ``(device, command)`` is not served answers ``EW_FUNC``;
* a block answers for the path in its path word (``cnc_setpath`` writes it; 0 is the handle's
  default, path 1): every per-path read and write (status, motion figures, positions, axes,
  spindles, loads, alarms, programs, macro variables, parameters and diagnostics) asks the
  machine for that path, and a path the machine has not answers ``EW_PATH`` before any other
  check. The CNC ID, the PMC, the alarm history and the parameter information
  (:data:`PATH_INDEPENDENT`) are the machine's and ignore the path word;
* a refusal of the machine answers its EW code (``EW_NUMBER``, ``EW_ATTRIB``, ``EW_PROT``,
  ``EW_PASSWD``, ``EW_LENGTH``...), the code the packed protocol answers for the same request;
  a block whose data the wire cannot carry answers ``EW_DATA`` (a warning is logged; see
  :mod:`focas_net.adapters._common`);
  an ``EW_NUMBER`` block carries the detail words ``cnc_getdtailerr`` reads: 1 and the number
  asked (this project's choice);
* every answer fits the body size the answer's version allows (1450 bytes for version 2, 2910
  for 3): room for the 16-byte head of every later block is kept, and a block whose data would
  not fit what is left answers ``EW_LENGTH``. So PMC ranges are limited by one answer, not by
  the packed protocol's 32 bytes;
* a request with more blocks than the limit can answer even as bare heads is a framing
  violation (:class:`NativeFrameError`): the connection is closed;
* parameter and diagnostic records carry the machine's type (:attr:`DataItem.kind`) in the
  library's numbering (:func:`native_param_type`, :func:`native_diag_type`). A real value is
  FANUC's REALPRM, ``(mantissa, 10, decimals)``: one 8-byte slot in the 30i set, two 4-byte
  slots in the 16i set. A bit parameter travels as the byte of its bits (0xB0 for 10110000) and
  is written back as 0..255;
* the 16i set has no way to write a real parameter: 0x10 answers type bits 0-1 of the real type
  (0, a bit parameter), so ``cnc_wrparam`` refuses every length but 5 with EW_LENGTH itself, and
  a 0x0F record of a real parameter (1-byte or REAL slots) answers EW_LENGTH too: FANUC's
  library returns EW_LENGTH (2) for a real parameter in the 16i set, whatever the length;
* the parameters FANUC's library reads on its own, 9968 (its option bits, 16i set, while
  connecting; also the open answer's option bits in the 30i set) and 3115 (position display
  bits, ``cnc_rdposition`` in the 16i set), are the machine's own: every machine has them
  (:class:`~focas_net.sim.Machine` gives the defaults), so both protocols read the same values;
* figures the machine does not model (the CNC ID) answer the values
  the handlers document; the spindle and servo loads are the machine's
  (:meth:`~focas_net.sim.Machine.spindle_loads`, ``servo_loads``).

This module holds the adapter: the open and close answers, the loop that answers a data
request block by block, and the answers it keeps. A handler answers one block: ``(block, room
left in the answer, the connection's session) -> data``, raising one of
:data:`~focas_net.adapters._common.REFUSALS` for a block it refuses (the block then carries its
EW code). The handlers are by area: :mod:`._native_cnc` (identity, status, motion, axes, loads,
PMC, alarms), :mod:`._native_data` (macro variables, parameters, diagnostics),
:mod:`._native_programs` (part programs), :mod:`._native_offsets` (tool and work offsets,
tool life), :mod:`._native_files` (the program folders of a 30i-class control),
:mod:`._native_clock` (the clock, the panel's signals), :mod:`._native_modal` (modal data,
operator messages, program pointers) and :mod:`._native_info` (the CNC's information:
figures, status 2, system software, item numbers and attributes, setting data, the PMC's
areas and title, the Ethernet board, program restart).

Answers of reads are kept (:mod:`focas_net.adapters._common`, as the packed adapter keeps
its own): a request made of the reads in :data:`_COUNTERS` only, every block answered without
an EW code, is answered again from an :class:`~focas_net.adapters._common.AnswerMemo` keyed by
its body for as long as the machine counters those reads follow (``status_version``,
``data_version``, ``macro_version``, ``alarm_version``, ``pmc_version``, ``motion_version``;
none for what never changes) stay where they were before it was answered. A poller's repeated
frame then costs one look-up and a compare.

A macro value written as a double (0xA8) is the decimal
:func:`~focas_net.adapters.macro_from_double` makes of it, written with the machine's own
``write_macro`` (a vacant double, a NaN, makes the variable vacant; a double with no such
decimal is passed on as it is, for the machine to refuse).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, Final

from focas_net._memo import Memo
from focas_net.errors import EW
from focas_net.native import (
    MACHINE_LATHE,
    MACHINE_MILL,
    MAGIC_WORD,
    NATIVE_HEADER,
    OPTION_PARAMETER,
    PATH_RECORDS,
    RESPONSE_BLOCK_SIZE,
    BlockCount,
    CommandSet,
    Device,
    FrameType,
    NativeCommand,
    NativeFrameError,
    PathDescription,
    RequestBlock,
    ResponseBlockHead,
    StatInfo,
    build_open_answer,
    decode_request_body,
    encode_close_response,
    encode_open_response,
    max_response_body,
)
from focas_net.sim import CLASSES_16I, Machine, Session

from ._common import (
    REFUSALS,
    UNENCODABLE,
    AnswerMemo,
    Counters,
    counters_of,
    refusal_code,
    unencodable_code,
)
from ._native_clock import ClockHandlers
from ._native_cnc import CncHandlers
from ._native_data import DataHandlers
from ._native_files import FileHandlers
from ._native_info import InfoHandlers
from ._native_modal import ModalHandlers
from ._native_offsets import OffsetHandlers
from ._native_programs import ProgramHandlers, ProgramTransfer
from ._native_spindles import SpindleHandlers

__all__ = ["PATH_INDEPENDENT", "NativeAdapter", "command_set_of"]

#: Version word of the answers of each command set (a 16i answers 2, a 0i-D 3).
_SET_VERSIONS: Final = {CommandSet.FS16I: 2, CommandSet.FS30I: 3}
#: FOCAS option bits of a machine whose parameter 9968 is an axis parameter (otherwise the
#: open answer of the 30i set carries 9968's value): bit 0 is what ``cnc_rddynamic2`` needs.
OPTION_BITS: Final = 1
#: ``(device, command)`` of the blocks that answer whatever their path word: the CNC ID, the
#: alarm history, the parameter information and the PMC are the machine's, not a path's; so
#: are the system software, the Ethernet board, the item numbers and the item information.
PATH_INDEPENDENT: Final = frozenset(
    {
        (Device.CNC, NativeCommand.RDCNCID),
        (Device.CNC, NativeCommand.RDALMHISTRY),
        (Device.CNC, NativeCommand.RDPARAINFO),
        (Device.CNC, NativeCommand.RDPARAINFO3),
        (Device.CNC, NativeCommand.RDPDF_DRIVE),
        (Device.CNC, NativeCommand.RDPDF_INF),
        (Device.PMC, NativeCommand.PMC_RDPMCRNG),
        (Device.PMC, NativeCommand.PMC_WRPMCRNG),
        (Device.PMC, NativeCommand.PMC_RDPMCINFO),
        (Device.PMC, NativeCommand.PMC_RDPMCTITLE),
        (Device.CNC, NativeCommand.RDSYSSOFT),
        (Device.CNC, NativeCommand.RDETHERINFO),
        (Device.CNC, NativeCommand.RDPARANUM),
        (Device.CNC, NativeCommand.RDDIAGNUM),
        (Device.CNC, NativeCommand.RDDIAGINFO),
        (Device.CNC, NativeCommand.RDSETINFO),
    }
)
#: The machine counter the answer of each read block follows ("" for what never changes: the
#: identity, the axes): a request of these only is answered from a memo while those counters
#: hold. Absent are writes, and reads that move with time alone or with the program store
#: (timers, loads, servo meters, program directory and memory, the blocks being executed).
_COUNTERS: Final[dict[tuple[int, int], str]] = {
    (Device.CNC, NativeCommand.SYSINFO): "",
    (Device.CNC, NativeCommand.RDCNCID): "",
    (Device.CNC, NativeCommand.AXIS_NAME): "",
    (Device.CNC, NativeCommand.AXIS_UNIT): "",
    (Device.CNC, NativeCommand.AXIS_COUNT): "",
    (Device.CNC, NativeCommand.SPDLNAME): "",
    (Device.CNC, NativeCommand.AXIS_DISPLAY): "",
    (Device.CNC, NativeCommand.STATINFO): "status_version",
    (Device.CNC, NativeCommand.STAT_HDCK): "status_version",
    (Device.CNC, NativeCommand.STAT_TMMODE): "status_version",
    (Device.CNC, NativeCommand.RDPARAM): "data_version",
    (Device.CNC, NativeCommand.RDPARAINFO): "data_version",
    (Device.CNC, NativeCommand.RDPARAM3): "data_version",
    (Device.CNC, NativeCommand.RDPARAINFO3): "data_version",
    (Device.CNC, NativeCommand.RDDIAG): "data_version",
    (Device.CNC, NativeCommand.RDDIAG3): "data_version",
    (Device.CNC, NativeCommand.RDMACRO): "macro_version",
    (Device.CNC, NativeCommand.RDMACRO_DOUBLE): "macro_version",
    (Device.CNC, NativeCommand.ALARM): "alarm_version",
    (Device.CNC, NativeCommand.RDALMMSG): "alarm_version",
    (Device.CNC, NativeCommand.RDALMHISTRY): "alarm_version",
    (Device.PMC, NativeCommand.PMC_RDPMCRNG): "pmc_version",
    (Device.CNC, NativeCommand.RDPRGNUM): "motion_version",
    (Device.CNC, NativeCommand.RDSEQNUM): "motion_version",
    (Device.CNC, NativeCommand.EXEPRGNAME): "motion_version",
    (Device.CNC, NativeCommand.ACTF): "motion_version",
    (Device.CNC, NativeCommand.ACTS): "motion_version",
    (Device.CNC, NativeCommand.POSITION): "motion_version",
    (Device.CNC, NativeCommand.GETFIGURE): "",
    (Device.CNC, NativeCommand.RDSYSSOFT): "",
    (Device.CNC, NativeCommand.RDPARANUM): "",
    (Device.CNC, NativeCommand.RDDIAGNUM): "",
    (Device.CNC, NativeCommand.RDDIAGINFO): "",
    (Device.CNC, NativeCommand.RDSETINFO): "",
    (Device.CNC, NativeCommand.RDETHERINFO): "",
    (Device.CNC, NativeCommand.RDSET): "data_version",
    (Device.CNC, NativeCommand.RDSET3): "data_version",
    (Device.CNC, NativeCommand.STATINFO2): "status_version",
    (Device.PMC, NativeCommand.PMC_RDPMCINFO): "",
    (Device.PMC, NativeCommand.PMC_RDPMCTITLE): "",
}
#: Answers one adapter keeps: the request bodies a poller repeats. An answer is 1.5 KiB at most
#: (2.9 at version 3), so a machine keeps under 100 KiB of them at worst.
_KEPT_ANSWERS: Final = 32

#: data-request body -> its request blocks (a poll sends the same body again and again).
_REQUEST_BODIES: Final = Memo(512)

#: block, room for its data, the connection's session -> data; raises one of REFUSALS.
_Handler = Callable[[RequestBlock, int, Session], bytes]

_pack_block = ResponseBlockHead.STRUCT.pack
_pack_count = BlockCount.STRUCT.pack


def command_set_of(machine: Machine) -> CommandSet:
    """The command set a control of ``machine``'s class speaks to FANUC's library."""
    return CommandSet.FS16I if machine.control_class in CLASSES_16I else CommandSet.FS30I


def _i16(value: int) -> int:
    """``value`` as a signed 16-bit word (its low 16 bits)."""
    return ((value + 0x8000) & 0xFFFF) - 0x8000


class NativeAdapter:
    """Answers FANUC's library for one machine (see the module docstring).

    ``version`` overrides the version word the machine's control class picks (it also picks
    the command set: 16i up to 2, 30i from 3).
    """

    __slots__ = (
        "_cnc",
        "_handlers",
        "_kept",
        "_max_blocks",
        "_own_session",
        "_programs",
        "command_set",
        "limit",
        "machine",
        "max_axis",
        "version",
    )

    def __init__(self, machine: Machine, *, version: int | None = None) -> None:
        self.machine = machine
        if version is None:
            version = _SET_VERSIONS[command_set_of(machine)]
        #: Version word of every answer; it sets :attr:`limit` and :attr:`command_set`.
        self.version = version
        #: The command set FANUC's library uses with this adapter.
        self.command_set = CommandSet.for_version(version)
        #: Largest answer body (:func:`max_response_body` of the version).
        self.limit = max_response_body(version)
        self._max_blocks = (self.limit - 2) // RESPONSE_BLOCK_SIZE
        #: Value slots per parameter/diagnostic record and position records for all axes: the
        #: open answer's max axes (at least the axes of every path).
        most = max(len(machine.path_info(p).axes) for p in range(1, machine.path_count + 1))
        self.max_axis = max(machine.identity().max_axis, most, 1)
        #: request body -> (the counters its answer follows, their values then, the frame)
        self._kept = AnswerMemo(_KEPT_ANSWERS)
        self._own_session = machine.new_session()
        cnc = self._cnc = CncHandlers(machine, self.max_axis)
        data = DataHandlers(machine, self.max_axis)
        programs = self._programs = ProgramHandlers(machine, version)
        spindles = SpindleHandlers(machine)
        modal = ModalHandlers(machine)
        offsets = OffsetHandlers(machine, self.max_axis)
        clock = ClockHandlers(machine)
        files = FileHandlers(machine)
        info = InfoHandlers(machine, cnc, data)
        c = NativeCommand
        on_cnc: dict[int, _Handler] = {
            c.SYSINFO: cnc.read_sysinfo,
            c.STATINFO: cnc.read_status,
            c.STAT_HDCK: cnc.read_hdck,
            c.STAT_TMMODE: cnc.read_tmmode,
            c.RDCNCID: cnc.read_cnc_id,
            c.RDTIMER: cnc.read_timer,
            c.RDPRGNUM: cnc.read_program_numbers,
            c.RDSEQNUM: cnc.read_sequence,
            c.EXEPRGNAME: cnc.read_executing_program,
            c.ACTF: cnc.read_feed,
            c.ACTS: cnc.read_spindle,
            c.ALARM: cnc.read_alarm_bits,
            c.RDALMMSG: cnc.read_alarms,
            c.RDALMHISTRY: cnc.read_history,
            c.RDMACRO: data.read_macros,
            c.WRMACRO: data.write_macro,
            c.RDMACRO_DOUBLE: data.read_macro_doubles,
            c.WRMACRO_DOUBLE: data.write_macro_double,
            c.RDPARAM: data.read_params,
            c.RDPARAINFO: data.read_param_info,
            c.WRPARAM: data.write_param,
            c.RDPARAM3: data.read_params_30i,
            c.RDPARAINFO3: data.read_param_info_30i,
            c.WRPARAM3: data.write_param_30i,
            c.RDDIAG: data.read_diags,
            c.RDDIAG3: data.read_diags_30i,
            c.POSITION: info.read_positions,  # restart points, then CncHandlers'
            c.AXIS_NAME: cnc.read_axis_names,
            c.AXIS_UNIT: cnc.read_axis_units,
            c.AXIS_COUNT: cnc.read_axis_count,
            c.AXIS_DISPLAY: cnc.read_axis_display,
            c.RDSPLOAD: spindles.read_spindle_data,
            c.GETTIMER: clock.read_clock,
            c.SETTIMER: clock.write_clock,
            c.RDSVMETER: spindles.read_servo_data,
            c.SPDLNAME: spindles.read_spindle_names,
            c.RDOPNLSGNL: clock.read_panel_signals,
            c.RDPROGDIR: programs.read_program_directory,
            c.RDPROGINFO: programs.read_program_memory,
            c.DELETE: programs.delete_program,
            c.SEARCH: programs.search_program,
            c.RDEXECPROG: programs.read_executing_blocks,
            c.GMODAL: modal.read_modal_g,
            c.AMODAL: modal.read_modal_aux,
            c.RDGCODE: modal.read_g_codes,
            c.RDCOMMAND: modal.read_commands,
            c.RDOPMSG: modal.read_operator_messages,
            c.RDOPMSG3: modal.read_operator_messages3,
            c.EXEPRGNAME2: modal.read_executing_path,
            c.RDACTPT: modal.read_active_pointer,
            c.RDBLKCOUNT: modal.read_block_count,
            c.RDMDIPNTR: modal.read_mdi_pointer,
            c.RDTOFS: offsets.read_tool_offsets,
            c.WRTOFS: offsets.write_tool_offset,
            c.RDTOFSINFO: offsets.read_tool_offset_info,
            c.RDZOFS: offsets.read_work_offsets,
            c.WRZOFS: offsets.write_work_offset,
            c.RDUSEGRPID: offsets.read_groups_in_use,
            c.RDNGRP: offsets.read_life_counts,
            c.RDTLINFO: offsets.read_life_counts,
            c.RDTOOLGRP: offsets.read_tool_groups,
            c.TOOLNUM: offsets.read_tool_numbers,
            c.RDPDF_DRIVE: files.read_drives,
            c.RDPDF_INF: files.read_drive_info,
            c.RDPDF_CURDIR: files.read_current_folder,
            c.WRPDF_CURDIR: files.write_current_folder,
            c.RDPDF_SUBDIR: files.read_subfolders,
            c.RDPDF_ALLDIR: files.read_folder,
            c.RDPDF_SUBDIRN: files.read_folder_count,
            c.RDPDF_PRGINF: files.read_file_info,
            c.PDF_DEL: files.delete_file,
            c.PDF_RDMAIN: files.read_main_file,
            c.PDF_SLCTMAIN: files.select_main_file,
            c.GETFIGURE: info.read_figures,
            c.STATINFO2: info.read_status2,
            c.RDSYSSOFT: info.read_software,
            c.RDPARANUM: info.read_param_numbers,
            c.RDDIAGNUM: info.read_diag_numbers,
            c.RDDIAGINFO: info.read_diag_info,
            c.RDSETINFO: info.read_setting_info,
            c.RDSET: info.read_settings,
            c.RDSET3: info.read_settings_30i,
            c.RDETHERINFO: info.read_ether_info,
            c.RDPRSTRINFO: info.read_restart_info,
        }
        on_pmc: dict[int, _Handler] = {
            c.PMC_RDPMCRNG: cnc.read_pmc,
            c.PMC_WRPMCRNG: cnc.write_pmc,
            c.PMC_RDPMCINFO: info.read_pmc_info,
            c.PMC_RDPMCTITLE: info.read_pmc_title,
        }
        self._handlers: dict[tuple[int, int], _Handler] = {
            **{(Device.CNC, k): v for k, v in on_cnc.items()},
            **{(Device.PMC, k): v for k, v in on_pmc.items()},
        }

    def __repr__(self) -> str:
        return f"NativeAdapter({self.machine!r}, version={self.version})"

    @property
    def served(self) -> frozenset[tuple[int, int]]:
        """``(device, command)`` of every block this adapter answers with data."""
        return frozenset(self._handlers)

    # -- open and close ------------------------------------------------------------------

    def open_answer(self) -> bytes:
        """The body of the open answer: every path (its machine type, axes and spindles), the
        path count and the CNC's max axes; at version 3 the option bits. A multi-path machine
        fills the library's table of :data:`~focas_net.native.PATH_RECORDS` paths."""
        machine = self.machine
        paths = []
        for number in range(1, machine.path_count + 1):
            info = machine.path_info(number)
            machine_type = MACHINE_LATHE if info.kind == "T" else MACHINE_MILL
            paths.append(PathDescription(machine_type, len(info.axes), info.spindles))
        return build_open_answer(
            paths,
            self.max_axis,
            option_bits=self._option_bits(),
            version=self.version,
            records=1 if len(paths) == 1 else PATH_RECORDS,
        )

    def _option_bits(self) -> int:
        """The FOCAS option bits: parameter 9968 of the machine (read by the library itself in
        the 16i set)."""
        item = self.machine.param_item(OPTION_PARAMETER)
        if item is None or item.axis:
            return OPTION_BITS
        return item.values[0] & 0xFFFF

    def open_response(self) -> bytes:
        """The whole open-answer frame."""
        return encode_open_response(self.open_answer(), self.version)

    def close_response(self) -> bytes:
        """The whole close-answer frame."""
        return encode_close_response(self.version)

    def status_info(self, path: int = 1) -> StatInfo:
        """The status of ``path`` as a 0x19 answer carries it."""
        return self._cnc.status_info(path)

    # -- requests ------------------------------------------------------------------------

    def _blocks(self, data: bytes | bytearray | memoryview) -> tuple[RequestBlock, ...]:
        # a bytearray or a view is looked up as bytes: a memo key is immutable
        body = data if type(data) is bytes else bytes(data)
        blocks: tuple[RequestBlock, ...] | None = _REQUEST_BODIES.get(body)
        if blocks is None:
            blocks = decode_request_body(body)
            _REQUEST_BODIES.put(body, blocks)
        if len(blocks) > self._max_blocks:
            raise NativeFrameError(
                f"{len(blocks)} request blocks: at most {self._max_blocks} can be answered"
            )
        return blocks

    def _frame(self, parts: list[bytes]) -> bytes:
        """The data-response frame of ``parts`` (``parts[0]`` is the place of its header)."""
        length = sum(map(len, parts))
        parts[0] = NATIVE_HEADER.pack(MAGIC_WORD, self.version, FrameType.DATA_RESPONSE, length)
        return b"".join(parts)

    def answer(self, body: bytes | bytearray | memoryview, session: Session | None = None) -> bytes:
        """The whole data-response frame answering the data-request ``body``; ``session`` is
        the connection's (parameter writes), the adapter's own when None.

        Raises :class:`NativeFrameError` when the block list is broken or longer than an
        answer can hold; everything else is answered in its block. A request of no block is
        answered with one EW_FUNC block (FANUC's library refuses an answer of no block).

        The machine answers the whole frame at one instant (:meth:`Machine.instant`), as a CNC
        does: the blocks of one frame never carry figures of different moments.
        """
        with self.machine.instant():
            return self._answer_at_once(body, session)

    def _answer_at_once(
        self, body: bytes | bytearray | memoryview, session: Session | None
    ) -> bytes:
        key = body if type(body) is bytes else bytes(body)
        kept: tuple[Counters, Any, bytes] | None = self._kept.get(key)
        machine = self.machine
        if kept is not None and kept[0](machine) == kept[1]:
            return kept[2]  # a poller's request again, what it reads unchanged
        blocks = self._blocks(key)
        if not blocks:
            blocks = (RequestBlock(Device.CNC, 1, 0),)
        if session is None:
            session = self._own_session
        kinds = [_COUNTERS.get((b.device, b.command)) for b in blocks]
        if None in kinds:
            return self._answer(blocks, session)[0]
        counters = counters_of(k for k in kinds if k is not None)
        # Read before answering: a machine that moves meanwhile only makes the next miss.
        seen = counters(machine)
        frame, failed = self._answer(blocks, session)
        if not failed:
            self._kept.keep(key, counters, seen, frame)
        return frame

    def _answer(self, blocks: tuple[RequestBlock, ...], session: Session) -> tuple[bytes, bool]:
        """The answer frame of ``blocks``, and whether a block of it answered an EW code."""
        count = len(blocks)
        parts: list[bytes] = [b"", _pack_count(count)]
        left = self.limit - 2 - RESPONSE_BLOCK_SIZE * count
        handlers = self._handlers
        paths = self.machine.path_count
        failed = False
        for block in blocks:
            key = (block.device, block.command)
            handler = handlers.get(key)
            ew = 0
            data = b""
            if handler is None:
                ew = EW.FUNC
            elif block.path > paths and key not in PATH_INDEPENDENT:
                ew = EW.PATH
            else:
                try:
                    data = handler(block, left, session)
                except REFUSALS as exc:
                    ew = refusal_code(exc)
                except UNENCODABLE as exc:
                    what = f"block 0x{block.command:02X}"
                    ew = unencodable_code(self.machine, what, exc)
                else:
                    if len(data) > left:  # a handler's own check guards this already
                        ew, data = EW.LENGTH, b""
            size = len(data)
            left -= size
            detail1 = detail2 = 0
            if ew:
                failed = True
                if ew == EW.NUMBER:
                    detail1, detail2 = 1, _i16(block.args[0])
            parts.append(
                _pack_block(
                    RESPONSE_BLOCK_SIZE + size,
                    block.device,
                    block.path,
                    block.command,
                    ew,
                    detail1,
                    detail2,
                    size,
                )
            )
            if size:
                parts.append(data)
        return self._frame(parts), failed

    def forced_answer(self, body: bytes, ew: int) -> bytes:
        """The data-response frame answering ``body`` with ``ew`` and no data in every block
        (a forced EW code of fault injection: nothing runs). Raises :class:`NativeFrameError`
        as :meth:`answer` does."""
        blocks = self._blocks(body)
        parts: list[bytes] = [b"", _pack_count(len(blocks))]
        parts.extend(
            _pack_block(RESPONSE_BLOCK_SIZE, b.device, b.path, b.command, ew, 0, 0, 0)
            for b in blocks
        )
        return self._frame(parts)

    # -- part program transfers ----------------------------------------------------------

    def transfer(self, frame_type: int, body: bytes, state: ProgramTransfer) -> list[bytes] | None:
        """The frames answering one program-transfer frame of a connection whose transfer
        state is ``state`` (see :mod:`focas_net.native.programs`); None when ``frame_type``
        is not a transfer request (the connection's violation).

        * ``0x1501`` upload: ``0x1502``, the text as ``%``, newline, each program's text,
          ``%`` in ``0x1604`` frames of at most :data:`~focas_net.native.PROGRAM_CHUNK`
          bytes, then ``0x1701``; ``0x1702`` and ``0x1804`` (the library's end and abort)
          answer nothing;
        * ``0x1101`` download start: ``0x1102`` (EW_PROT on a read-only machine); ``0x1204``
          data is kept in ``state``; ``0x1301`` stores the program, ``0x1302``.

        A refusal is a ``0x..03`` frame carrying the EW code
        (:class:`~focas_net.native.TransferError`), the code the packed protocol gives for the
        same program operation.
        """
        return self._programs.transfer(frame_type, body, state)
