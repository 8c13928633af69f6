"""The typed asyncio client: :class:`FocasClient`.

One TCP connection carries many calls at once (matched by request id); every method is
awaited for a typed result (a coroutine function, or a plain method returning the request's
coroutine: see ``_awaitable``), and every EW answer raises :class:`CncError`. The wire protocol
is ``docs/protocol.md``, the client ``docs/client.md``.

The client is built from these parts of ``focas_net.client``:

* :mod:`.connection`: one pipelined connection (request ids, slots, deadlines);
* :mod:`.reconnect`: the :class:`~.reconnect.Link` every :class:`FocasClient` is: the
  connection's lifecycle, the state machine, the reconnect backoff, the unlock-and-retry and
  the one request path (``_request``) every call below takes;
* :mod:`._pmc`: PMC ranges over 32-byte chunks and :class:`ChunkedWriteError`;
* :mod:`.sim_control`: the simulator control commands, as ``client.sim``.
"""

# Every call takes a per-call ``timeout=`` by contract (a deadline is computed once per call and
# shared by its chunks, lock waits and reconnect waits), so ASYNC109 does not apply here.
# ruff: noqa: ASYNC109

from __future__ import annotations

import inspect
import math
import ssl as _ssl
from collections.abc import Callable, Coroutine
from dataclasses import dataclass
from decimal import Decimal, InvalidOperation
from typing import Any, Final, TypeVar

from focas_net.errors import EW, CncError, PayloadError

from ..protocol import (
    COMMANDS,
    DEFAULT_MAX_FRAME,
    MAX_CONFIG_CHUNK,
    MAX_DIRECTORY_ENTRIES,
    MAX_HISTORY_DEPTH,
    MAX_REAL_DECIMALS,
    ActiveAlarm,
    ActiveAlarmList,
    ActualValue,
    AlarmHistory,
    AlarmHistoryRequest,
    AlarmMsgRequest,
    AlarmType,
    DataRequest,
    DirectoryRequest,
    LoadMeters,
    MacroRequest,
    MacroValue,
    ParamAttributes,
    ParamAttributesRequest,
    ParamDataType,
    ParamValue,
    Password,
    PmcArea,
    PositionData,
    PositionKind,
    PositionRequest,
    ProgramChunk,
    ProgramChunkRequest,
    ProgramDirectory,
    ProgramEntry,
    ProgramNumber,
    ProgramNumbers,
    ProgramText,
    RunInfo,
    StatusInfo,
    SysInfo,
    VersaMaxReply,
    VersaMaxRequest,
)
from ..protocol import Command as C
from ..versamax import IOModuleRecord
from ._locks import KeyedLocks
from ._pmc import AreaLike, check_u16_range, read_pmc_chunk, read_pmc_range, write_pmc_range
from .reconnect import Link, ReconnectPolicy, StateCallback
from .sim_control import SimControl, alarm_type_number

__all__ = ["FocasClient", "Positions"]

_RDCNCSTAT: Final = COMMANDS[C.RDCNCSTAT]
_SYSINFO: Final = COMMANDS[C.SYSINFO]
_RDPARAM: Final = COMMANDS[C.RDPARAM]
_RDDIAG: Final = COMMANDS[C.RDDIAG]
_RDMACRO: Final = COMMANDS[C.RDMACRO]
_RDALMMSG: Final = COMMANDS[C.RDALMMSG]
_WRPARAM: Final = COMMANDS[C.WRPARAM]
_WRMACRO: Final = COMMANDS[C.WRMACRO]
_WRPMCRNG: Final = COMMANDS[C.WRPMCRNG]
_UNLOCK: Final = COMMANDS[C.WRUNLOCKPARAM]
_RDCONFIG: Final = COMMANDS[C.VERSAMAX_RDCONFIG]
_RDALMHISTRY: Final = COMMANDS[C.RDALMHISTRY]
_RDPRGNUM: Final = COMMANDS[C.RDPRGNUM]
_ACTF: Final = COMMANDS[C.ACTF]
_ACTS: Final = COMMANDS[C.ACTS]
_RDPOSITION: Final = COMMANDS[C.RDPOSITION]
_RDPARAINFO: Final = COMMANDS[C.RDPARAINFO]
_RDPROGDIR: Final = COMMANDS[C.RDPROGDIR]
_RDPROGRAM: Final = COMMANDS[C.RDPROGRAM]
_RDRUNINFO: Final = COMMANDS[C.RDRUNINFO]
_RDLOADS: Final = COMMANDS[C.RDLOADS]
_WRPROGRAM: Final = COMMANDS[C.WRPROGRAM]
_DELPROGRAM: Final = COMMANDS[C.DELPROGRAM]
_SELPROGRAM: Final = COMMANDS[C.SELPROGRAM]
#: Bounds of the paged reads of programs (a directory of 400 programs, 512,000 characters).
_MAX_DIRECTORY_PAGES: Final = 1024
_MAX_PROGRAM_CHUNKS: Final = 1024

_EMPTY: Final = b""
_MAX_ACTIVE_ALARMS: Final = 32
_I32_MIN: Final = -(2**31)
_I32_MAX: Final = 2**31 - 1
_MAX_MACRO_DECIMALS: Final = 9
_U16_LIMIT: Final = 0x10000
_I16_MAX: Final = 0x7FFF
_U8_MAX: Final = 0xFF
#: The IODBPSD width of a real parameter's REALPRM.
_REAL_WIDTH: Final = 8


_F = TypeVar("_F", bound=Callable[..., Any])
#: inspect.markcoroutinefunction, from Python 3.12 on.
_MARK: Final[Callable[[Any], Any] | None] = getattr(inspect, "markcoroutinefunction", None)


def _awaitable(method: _F) -> _F:
    """Mark ``method``, a plain method returning a coroutine, as a coroutine function for
    ``inspect.iscoroutinefunction`` where Python can (3.12 on): it is awaited, scheduled and
    gathered as an ``async def`` is, with one coroutine frame less per call."""
    if _MARK is not None:
        _MARK(method)
    return method


@dataclass(frozen=True, slots=True)
class Positions:
    """The answer of :meth:`FocasClient.read_positions`.

    ``values`` maps each axis name to its position (``increments / 10**decimals``, a Decimal
    with ``decimals`` places); ``increments`` holds the raw least-input-increment counts. Both
    keep the CNC's axis order.
    """

    kind: PositionKind
    decimals: int
    values: dict[str, Decimal]
    increments: dict[str, int]


def _check_bit(bit: int, width: int = 1) -> None:
    if not 0 <= bit < 8 * width:
        raise ValueError(f"bit {bit} outside 0..{8 * width - 1}")


def _check_item(number: int, axis: int, what: str) -> None:
    """ValueError, in the caller's terms, for a number or an axis the wire cannot carry."""
    if isinstance(number, bool) or not isinstance(number, int) or not 0 <= number <= _I16_MAX:
        raise ValueError(f"{what} number {number!r} is outside 0..{_I16_MAX}")
    if isinstance(axis, bool) or not isinstance(axis, int) or not 0 <= axis <= _I16_MAX:
        raise ValueError(f"axis {axis!r} is outside 0..{_I16_MAX} (0: not an axis {what})")


def _check(what: str, value: int, low: int, high: int) -> None:
    if isinstance(value, bool) or not isinstance(value, int) or not low <= value <= high:
        raise ValueError(f"{what} {value!r} is outside {low}..{high}")


def _check_macro(number: int) -> None:
    _check("macro variable number", number, -_I16_MAX - 1, _I16_MAX)


def _param_int(number: int, value: int | Decimal | str) -> int:
    """An integer parameter value from ``value`` (text: decimal, ``0x``, ``0b`` or ``0o``)."""
    if isinstance(value, str):
        try:
            return int(value.strip().replace("_", ""), 0)
        except ValueError:
            raise ValueError(f"parameter {number}: not an integer: {value!r}") from None
    if isinstance(value, bool) or not isinstance(value, int | Decimal):
        raise ValueError(f"parameter {number}: a value is an integer, got {value!r}")
    if isinstance(value, Decimal):
        if value != value.to_integral_value():
            raise ValueError(f"parameter {number} is not a real parameter: {value} is no integer")
        return int(value)
    return value


def _byte_to_wire(number: int, value: int, kind: ParamDataType | None) -> int:
    """The signed byte of a 1-byte parameter's ``value``: a bit parameter's 0..255 as the byte
    of the same eight bits, a byte parameter's -128..127 as it is."""
    if kind is ParamDataType.BIT:
        if not 0 <= value <= 0xFF:
            raise ValueError(
                f"bit parameter {number} holds 0..255 (0b00000000..0b11111111), got {value}"
            )
        return value - 0x100 if value > 0x7F else value
    if not -0x80 <= value <= 0x7F:
        raise ValueError(f"parameter {number} is a byte parameter: {value} is outside -128..127")
    return value


def _real_to_wire(number: int, value: int | Decimal | str) -> tuple[int, int]:
    """``(prm_val, dec_val)`` of a real parameter's value."""
    if isinstance(value, bool) or not isinstance(value, int | Decimal | str):
        raise ValueError(f"parameter {number}: a real value is a number, got {value!r}")
    try:
        return macro_to_wire(value)
    except ValueError:
        raise ValueError(
            f"real parameter {number}: {value!r} cannot be carried as an i32 mantissa with "
            f"0..{MAX_REAL_DECIMALS} decimals"
        ) from None


def macro_to_wire(value: int | Decimal | float | str) -> tuple[int, int]:
    """``(mcr_val, dec_val)`` for ``value``; :class:`ValueError` when it cannot be carried.

    An ``int`` keeps ``dec_val = 0``; a ``Decimal`` or string keeps the digits it was given
    (``"1.50"`` -> ``(150, 2)``) when they fit, else the fewest that represent it exactly; a
    ``float`` uses its shortest decimal form (``0.1`` -> ``(1, 1)``). ``dec_val`` is 0..9 and
    ``mcr_val`` an i32.
    """
    if isinstance(value, bool):
        raise ValueError("a macro value must be a number, not a bool")
    if isinstance(value, int):
        if not _I32_MIN <= value <= _I32_MAX:
            raise ValueError(f"macro value {value} does not fit mcr_val (i32)")
        return value, 0
    if isinstance(value, float):
        if not math.isfinite(value):
            raise ValueError(f"macro value {value} is not finite")
        dec = Decimal(repr(value))
    elif isinstance(value, Decimal):
        dec = value
    elif isinstance(value, str):
        try:
            dec = Decimal(value.strip())
        except InvalidOperation:
            raise ValueError(f"not a number: {value!r}") from None
    else:
        raise ValueError(f"a macro value must be int, Decimal, float or str, not {value!r}")
    if not dec.is_finite():
        raise ValueError(f"macro value {value} is not finite")
    for candidate in (dec, dec.normalize()):
        exponent = candidate.as_tuple().exponent
        assert isinstance(exponent, int)
        places = max(0, -exponent)
        if places > _MAX_MACRO_DECIMALS:
            continue
        mcr = int(candidate.scaleb(places))
        if _I32_MIN <= mcr <= _I32_MAX:
            return mcr, places
    raise ValueError(f"macro value {value} cannot be carried as mcr_val (i32) / 10**dec_val (0..9)")


def macro_from_wire(mcr_val: int, dec_val: int) -> Decimal | None:
    """The value of an ODBM: ``mcr_val / 10**dec_val``, or None when vacant."""
    if mcr_val == 0 and dec_val == -1:
        return None
    return Decimal(mcr_val).scaleb(-dec_val)


class FocasClient(Link):
    """An asyncio client of the packed FOCAS protocol.

    Use it as ``async with FocasClient(host) as cnc: ...`` or call :meth:`connect` and
    :meth:`aclose`. Every method accepts ``timeout=`` (seconds) overriding the default for
    that call; the timeout covers the whole call (waiting for a free request slot, for a
    reconnect, for a bit lock, and every chunk of a chunked PMC call).

    ``reconnect`` is ``False`` (a lost connection stays lost), ``True`` (the default
    :class:`ReconnectPolicy`) or a :class:`ReconnectPolicy`. ``password`` is sent with
    ``cnc_wrunlockparam`` after every connect and again, followed by one retry, when a call
    answers ``EW_PASSWD``; it is 1..4 ASCII characters (:class:`ValueError` otherwise).
    """

    def __init__(
        self,
        host: str,
        port: int = 8193,
        *,
        timeout: float | None = 3.0,
        max_in_flight: int = 64,
        password: str | bytes | None = None,
        reconnect: bool | ReconnectPolicy = False,
        max_frame: int = DEFAULT_MAX_FRAME,
        ssl: _ssl.SSLContext | None = None,
        server_hostname: str | None = None,
        on_state_change: StateCallback | None = None,
    ) -> None:
        if password is not None:
            Password.from_text(password)  # ValueError, naming it, unless 1..4 ASCII characters
        super().__init__(
            host,
            port,
            timeout=timeout,
            max_in_flight=max_in_flight,
            password=password,
            reconnect=reconnect,
            max_frame=max_frame,
            ssl=ssl,
            server_hostname=server_hostname,
            on_state_change=on_state_change,
        )
        self._param_widths: dict[int, int] = {}
        self._param_types: dict[int, ParamDataType | None] = {}
        self._pmc_locks: KeyedLocks[tuple[int, int]] = KeyedLocks()
        self._param_locks: KeyedLocks[tuple[int, int]] = KeyedLocks()
        self.sim = SimControl(self)

    # -- status --------------------------------------------------------------------------
    # The reads whose answer is their result are plain methods that return the request's
    # coroutine (see _awaitable): awaiting one is awaiting an ``async def``, one coroutine
    # less per call.
    @_awaitable
    def read_status(self, *, timeout: float | None = None) -> Coroutine[Any, Any, StatusInfo]:
        """``cnc_rdcncstat``: the ODBST status (mode, run state, alarm, emergency, ...)."""
        return self._request(_RDCNCSTAT, _EMPTY, timeout)

    @_awaitable
    def read_sysinfo(self, *, timeout: float | None = None) -> Coroutine[Any, Any, SysInfo]:
        """``cnc_sysinfo``: ODBSYS (CNC type, series, version, axes)."""
        return self._request(_SYSINFO, _EMPTY, timeout)

    # -- program, feed, spindle, positions ------------------------------------------------
    @_awaitable
    def read_program_numbers(
        self, *, timeout: float | None = None
    ) -> Coroutine[Any, Any, ProgramNumbers]:
        """``cnc_rdprgnum``: the running and the main program numbers (0 = none)."""
        return self._request(_RDPRGNUM, _EMPTY, timeout)

    async def read_feed(self, *, timeout: float | None = None) -> int:
        """``cnc_actf``: the actual feed rate (the machine's feed unit, e.g. mm/min)."""
        value: ActualValue = await self._request(_ACTF, _EMPTY, timeout)
        return value.data

    async def read_spindle_speed(self, *, timeout: float | None = None) -> int:
        """``cnc_acts``: the actual spindle speed (min^-1)."""
        value: ActualValue = await self._request(_ACTS, _EMPTY, timeout)
        return value.data

    async def read_positions(
        self,
        kind: str | int | PositionKind = PositionKind.ABSOLUTE,
        *,
        axis: int | None = None,
        timeout: float | None = None,
    ) -> Positions:
        """``cnc_rdposition``: positions of every axis (``axis=None``) or of axis ``axis``
        (1..n). ``kind``: ``"absolute"``, ``"machine"``, ``"relative"``, ``"distance"``
        (to go), a :class:`PositionKind` or 0..3.

        An unknown ``kind`` or an ``axis`` below 1 raises :class:`ValueError` before anything
        is sent; an axis the CNC does not have answers EW_ATTRIB (:class:`CncError`).
        """
        which = PositionKind.parse(kind)
        if axis is not None and not 1 <= axis <= _I16_MAX:
            raise ValueError(f"axis {axis} is outside 1..{_I16_MAX} (or leave it out: every axis)")
        payload = _RDPOSITION.request.encode(PositionRequest(which, -1 if axis is None else axis))
        data: PositionData = await self._request(_RDPOSITION, payload, timeout)
        dec = data.dec
        return Positions(
            which,
            dec,
            {a.name: Decimal(a.value).scaleb(-dec) for a in data.axes},
            {a.name: a.value for a in data.axes},
        )

    # -- parameters and diagnostics ------------------------------------------------------
    async def _read_param_value(self, number: int, axis: int, deadline: float | None) -> ParamValue:
        _check_item(number, axis, "parameter")
        payload = _RDPARAM.request.encode(DataRequest(number, axis))
        value: ParamValue = await self._request_at(_RDPARAM, payload, deadline)
        self._param_widths[number] = value.width
        return value

    async def _param_type(self, number: int, deadline: float | None) -> ParamDataType | None:
        """The type of parameter ``number`` (``cnc_rdparainfo``, asked once, then cached);
        None when the CNC cannot tell (it answers ``cnc_rdparainfo`` with EW_FUNC)."""
        if number in self._param_types:
            return self._param_types[number]
        try:
            attrs = await self._read_param_attributes(number, deadline)
        except CncError as exc:
            if exc.ew != EW.FUNC:
                raise
            kind = None
        else:
            kind = attrs.type
        self._param_types[number] = kind
        return kind

    async def _read_param_attributes(self, number: int, deadline: float | None) -> ParamAttributes:
        _check_item(number, 0, "parameter")
        payload = _RDPARAINFO.request.encode(ParamAttributesRequest(number))
        attrs: ParamAttributes = await self._request_at(_RDPARAINFO, payload, deadline)
        self._param_types[number] = attrs.type
        return attrs

    async def read_param_attributes(
        self, number: int, *, timeout: float | None = None
    ) -> ParamAttributes:
        """``cnc_rdparainfo``: the type of parameter ``number`` (:class:`ParamDataType`: bit,
        byte, word, two-word, real), whether it is an axis parameter, the decimals of a real
        one and the range it accepts."""
        return await self._read_param_attributes(number, self._deadline(timeout))

    async def read_param_value(
        self, number: int, *, axis: int = 0, timeout: float | None = None
    ) -> ParamValue:
        """``cnc_rdparam`` as an IODBPSD: the value as the wire carries it and its width (1, 2,
        4 bytes, or 8 for a real parameter's REALPRM with its ``decimals``)."""
        return await self._read_param_value(number, axis, self._deadline(timeout))

    async def read_param(self, number: int, *, axis: int = 0, timeout: float | None = None) -> int:
        """``cnc_rdparam``: the value of parameter ``number`` (``axis`` 1..n for axis items).

        A bit parameter reads as its eight bits, 0..255 (``0b10110000`` is 176); the others as
        the signed integer they hold. The type of a 1-byte parameter is asked once
        (``cnc_rdparainfo``) and cached. A real parameter raises :class:`ValueError` (its value
        has decimals: read it with :meth:`read_param_real`).
        """
        deadline = self._deadline(timeout)
        value = await self._read_param_value(number, axis, deadline)
        if value.width == _REAL_WIDTH:
            raise ValueError(
                f"parameter {number} is a real parameter ({value.real}): read it with "
                "read_param_real"
            )
        if value.width == 1 and await self._param_type(number, deadline) is ParamDataType.BIT:
            return value.bits
        return value.value

    async def read_param_real(
        self, number: int, *, axis: int = 0, timeout: float | None = None
    ) -> Decimal:
        """``cnc_rdparam``: the value of parameter ``number`` as a :class:`~decimal.Decimal`:
        a real parameter with its decimals (``12.345``), any other as its integer value."""
        deadline = self._deadline(timeout)
        value = await self._read_param_value(number, axis, deadline)
        if value.width == _REAL_WIDTH:
            return value.real
        if value.width == 1 and await self._param_type(number, deadline) is ParamDataType.BIT:
            return Decimal(value.bits)
        return Decimal(value.value)

    async def write_param(
        self,
        number: int,
        value: int | Decimal | str,
        *,
        axis: int = 0,
        width: int | None = None,
        timeout: float | None = None,
    ) -> None:
        """``cnc_wrparam``: write ``value`` with ``width`` bytes (1, 2 or 4; 8 for a real
        parameter).

        With ``width=None`` the width is the one the CNC reported for this parameter; the
        first time it is learnt by one read and then cached. A bit parameter takes 0..255 or its
        bits as text, #7 first (``"0b10110000"``, the same as 176); a real parameter a number
        with decimals (``Decimal("12.345")``, ``"12.345"``, an ``int``); text is an integer
        (``"42"``, ``"0x2A"``) otherwise. A value that cannot be carried raises
        :class:`ValueError`, naming it, before anything is sent.
        """
        _check_item(number, axis, "parameter")
        deadline = self._deadline(timeout)
        learnt = False
        if width is None:
            cached = self._param_widths.get(number)
            if cached is None:
                width = (await self._read_param_value(number, axis, deadline)).width
                learnt = True
            else:
                width = cached
        elif width not in (1, 2, 4, _REAL_WIDTH):
            raise ValueError(f"parameter width must be 1, 2, 4 or 8 (real), got {width}")
        if width == _REAL_WIDTH:
            mantissa, decimals = _real_to_wire(number, value)
            pv = ParamValue(number, axis, mantissa, width, decimals)
        else:
            raw = _param_int(number, value)
            if width == 1:
                kind = await self._param_type(number, deadline)
                raw = _byte_to_wire(number, raw, kind)
            pv = ParamValue(number, axis, raw, width)
        payload = _WRPARAM.request.encode(pv)
        try:
            await self._request_at(_WRPARAM, payload, deadline)
        except CncError as exc:
            if exc.ew == EW.LENGTH and not learnt:
                self._param_widths.pop(number, None)  # stale width: learn it again next time
            raise

    async def write_param_bit(
        self,
        number: int,
        bit: int,
        value: bool,
        *,
        axis: int = 0,
        timeout: float | None = None,
    ) -> None:
        """Set or clear one bit of a bit-type parameter (``1815.0``) by read-modify-write.

        Writes to the same ``(number, axis)`` are serialised by a lock; others run in
        parallel.
        """
        _check_bit(bit, 4)
        deadline = self._deadline(timeout)
        async with self._param_locks.hold((number, axis), deadline):
            current = await self._read_param_value(number, axis, deadline)
            width = current.width
            if width == _REAL_WIDTH:
                raise ValueError(f"parameter {number} is a real parameter: it has no bits")
            _check_bit(bit, width)
            bits = 8 * width
            raw = current.value & ((1 << bits) - 1)
            raw = raw | (1 << bit) if value else raw & ~(1 << bit)
            if raw >= 1 << (bits - 1):
                raw -= 1 << bits
            payload = _WRPARAM.request.encode(ParamValue(number, axis, raw, width))
            await self._request_at(_WRPARAM, payload, deadline)

    async def read_diag(self, number: int, *, axis: int = 0, timeout: float | None = None) -> int:
        """``cnc_rddiag``: the value of diagnostic ``number``."""
        _check_item(number, axis, "diagnostic")
        payload = _RDDIAG.request.encode(DataRequest(number, axis))
        value: ParamValue = await self._request(_RDDIAG, payload, timeout)
        return value.value

    # -- macros --------------------------------------------------------------------------
    async def read_macro(self, number: int, *, timeout: float | None = None) -> Decimal | None:
        """``cnc_rdmacro``: the value of ``#number`` as a Decimal, or None when vacant."""
        _check_macro(number)
        payload = _RDMACRO.request.encode(MacroRequest(number))
        value: MacroValue = await self._request(_RDMACRO, payload, timeout)
        return macro_from_wire(value.mcr_val, value.dec_val)

    async def write_macro(
        self, number: int, value: int | Decimal | float | str, *, timeout: float | None = None
    ) -> None:
        """``cnc_wrmacro``: write ``#number``; see :func:`macro_to_wire` for the scaling.

        A value that cannot be carried raises :class:`ValueError` before anything is sent.
        """
        _check_macro(number)
        mcr_val, dec_val = macro_to_wire(value)
        payload = _WRMACRO.request.encode(MacroValue(number, 8, mcr_val, dec_val))
        await self._request(_WRMACRO, payload, timeout)

    # -- PMC -----------------------------------------------------------------------------
    async def read_pmc(
        self, area: AreaLike, start: int, count: int, *, timeout: float | None = None
    ) -> bytes:
        """``pmc_rdpmcrng``: ``count`` bytes of ``area`` (``"R"`` or :class:`PmcArea`) from
        ``start``. Ranges over 32 bytes are read as 32-byte calls sent as one batch."""
        a = PmcArea.parse(area)
        check_u16_range(start, count)
        return await read_pmc_range(self, a, start, count, self._deadline(timeout))

    async def write_pmc(
        self, area: AreaLike, start: int, data: bytes, *, timeout: float | None = None
    ) -> None:
        """``pmc_wrpmcrng``: write ``data`` to ``area`` from ``start``.

        Over 32 bytes the write is split into 32-byte calls sent as one batch; if any fails,
        :class:`ChunkedWriteError` lists the byte ranges written, not written and uncertain.
        """
        await write_pmc_range(self, _WRPMCRNG, area, start, data, self._deadline(timeout))

    async def read_pmc_bit(
        self, area: AreaLike, byte: int, bit: int, *, timeout: float | None = None
    ) -> bool:
        """One bit of a PMC byte (``R100.3`` is ``read_pmc_bit("R", 100, 3)``)."""
        _check_bit(bit)
        data = await self.read_pmc(area, byte, 1, timeout=timeout)
        return bool(data[0] >> bit & 1)

    async def write_pmc_bit(
        self,
        area: AreaLike,
        byte: int,
        bit: int,
        value: bool,
        *,
        timeout: float | None = None,
    ) -> None:
        """Set or clear one PMC bit: read the byte, change the bit, write the byte back,
        under a lock of ``(area, byte)`` so that concurrent bit writes never lose one another."""
        a = PmcArea.parse(area)
        _check_bit(bit)
        check_u16_range(byte, 1)
        deadline = self._deadline(timeout)
        async with self._pmc_locks.hold((a.value, byte), deadline):
            current = (await read_pmc_chunk(self, a, byte, 1, deadline))[0]
            new = current | (1 << bit) if value else current & ~(1 << bit)
            await write_pmc_range(self, _WRPMCRNG, a, byte, bytes((new,)), deadline)

    # -- alarms --------------------------------------------------------------------------
    async def read_alarms(
        self, *, alm_type: AlarmType | str | int = -1, timeout: float | None = None
    ) -> tuple[ActiveAlarm, ...]:
        """``cnc_rdalmmsg``: the active alarms (all types, -1, or only ``alm_type``: by name,
        ``"PS"``, an :class:`AlarmType` or a number), oldest first. An error answer
        (count = -1) raises :class:`CncError`."""
        if isinstance(alm_type, str):
            t = alarm_type_number(alm_type)
        else:
            _check("alarm type", alm_type, -1, _I16_MAX)
            t = int(alm_type)
        payload = _RDALMMSG.request.encode(AlarmMsgRequest(t, _MAX_ACTIVE_ALARMS))
        result: ActiveAlarmList = await self._request(_RDALMMSG, payload, timeout)
        if result.ew:
            raise CncError.from_ew(result.ew, _RDALMMSG.focas_name)
        return result.entries

    async def read_alarm_history(
        self, depth: int = 10, *, timeout: float | None = None
    ) -> AlarmHistory:
        """``cnc_rdalmhistry``: up to ``depth`` (clamped to 1..250) most recent entries,
        newest first. An error answer (a negative count) raises :class:`CncError`, like
        :meth:`read_alarms`: a failed read is never mistaken for an empty history."""
        depth = min(max(int(depth), 1), MAX_HISTORY_DEPTH)
        payload = _RDALMHISTRY.request.encode(AlarmHistoryRequest(depth))
        result: AlarmHistory = await self._request(_RDALMHISTRY, payload, timeout)
        if result.ew:
            raise CncError.from_ew(result.ew, _RDALMHISTRY.focas_name)
        return result

    # -- unlock --------------------------------------------------------------------------
    async def unlock(self, password: str | bytes, *, timeout: float | None = None) -> None:
        """``cnc_wrunlockparam``: unlock parameter writes on this connection.

        On success the password is kept and sent again after every reconnect. A refused
        password raises :class:`AccessDeniedError` (and the connection is locked); one that is
        not 1..4 ASCII characters raises :class:`ValueError` before anything is sent.
        """
        payload = _UNLOCK.request.encode(Password.from_text(password))
        await self._request(_UNLOCK, payload, timeout)
        self._password = password

    # -- part programs -------------------------------------------------------------------
    async def read_program_directory(
        self, *, first: int = 0, timeout: float | None = None
    ) -> tuple[ProgramEntry, ...]:
        """``cnc_rdprogdir``: every stored program from O number ``first`` on (number, size in
        characters, name), by number, read 64 entries per request."""
        _check("first program number", first, 0, _I32_MAX)
        deadline = self._deadline(timeout)
        entries: list[ProgramEntry] = []
        for _ in range(_MAX_DIRECTORY_PAGES):
            request = _RDPROGDIR.request.encode(DirectoryRequest(first, MAX_DIRECTORY_ENTRIES))
            page: ProgramDirectory = await self._request_at(_RDPROGDIR, request, deadline)
            entries.extend(page.entries)
            if len(page.entries) < MAX_DIRECTORY_ENTRIES or page.entries[-1].number >= _I32_MAX:
                break
            first = page.entries[-1].number + 1
        return tuple(entries)

    async def read_program(self, number: int, *, timeout: float | None = None) -> str:
        """``cnc_upload``: the text of program ``number`` as stored (EW_NUMBER: no such
        program), read 4096 characters per request and joined."""
        _check("program number", number, 0, _I32_MAX)
        deadline = self._deadline(timeout)
        parts: list[str] = []
        offset = 0
        for _ in range(_MAX_PROGRAM_CHUNKS):
            request = _RDPROGRAM.request.encode(ProgramChunkRequest(number, offset))
            chunk: ProgramChunk = await self._request_at(_RDPROGRAM, request, deadline)
            parts.append(chunk.text)
            offset += len(chunk.text)
            if not chunk.text or offset >= chunk.total:
                break
        return "".join(parts)

    async def write_program(
        self, text: str, *, replace: bool = False, timeout: float | None = None
    ) -> int:
        """``cnc_download``: store one O-number program; returns its number. A number already
        stored answers EW_REJECT unless ``replace``; a program being executed EW_BUSY; text
        that is not one program EW_DATA; a full memory EW_OVRFLOW."""
        payload = _WRPROGRAM.request.encode(ProgramText(int(replace), text))
        stored: ProgramNumber = await self._request(_WRPROGRAM, payload, timeout)
        return stored.number

    async def delete_program(self, number: int, *, timeout: float | None = None) -> None:
        """``cnc_delete``: delete program ``number`` (EW_NUMBER: none; EW_BUSY: executing)."""
        _check("program number", number, 0, _I32_MAX)
        payload = _DELPROGRAM.request.encode(ProgramNumber(number))
        await self._request(_DELPROGRAM, payload, timeout)

    async def select_program(self, number: int, *, timeout: float | None = None) -> None:
        """``cnc_search``: make ``number`` the main program (EW_NUMBER: none; EW_MODE: not MEM
        or EDIT; EW_BUSY: another program is executing)."""
        _check("program number", number, 0, _I32_MAX)
        payload = _SELPROGRAM.request.encode(ProgramNumber(number))
        await self._request(_SELPROGRAM, payload, timeout)

    @_awaitable
    def read_run_info(self, *, timeout: float | None = None) -> Coroutine[Any, Any, RunInfo]:
        """Overrides (%), parts count and total parts, and the power-on, operating, cutting
        and cycle timers (ms) of the simulated machine."""
        return self._request(_RDRUNINFO, _EMPTY, timeout)

    @_awaitable
    def read_loads(self, *, timeout: float | None = None) -> Coroutine[Any, Any, LoadMeters]:
        """The load of each spindle and the servo load of each axis, in percent
        (``cnc_rdspload`` and ``cnc_rdsvmeter`` in one request)."""
        return self._request(_RDLOADS, _EMPTY, timeout)

    # -- VersaMax ------------------------------------------------------------------------
    async def _config_chunk(
        self, rack: int, slot: int, offset: int, deadline: float | None
    ) -> bytes:
        _check("rack", rack, 0, _U8_MAX)
        _check("slot", slot, 0, _U8_MAX)
        request = VersaMaxRequest(rack, MAX_CONFIG_CHUNK, slot, offset)
        reply: VersaMaxReply = await self._request_at(
            _RDCONFIG, _RDCONFIG.request.encode(request), deadline
        )
        if (reply.rack, reply.slot, reply.offset) != (rack, slot, offset):
            raise PayloadError(
                f"versamax_rdconfig answer for rack {reply.rack} slot {reply.slot} offset "
                f"{reply.offset}, asked rack {rack} slot {slot} offset {offset}"
            )
        return reply.data

    async def read_config_record(
        self, rack: int, slot: int, *, timeout: float | None = None
    ) -> bytes:
        """The whole configuration record of ``rack``/``slot``, read 128 bytes at a time by
        offset and reassembled."""
        deadline = self._deadline(timeout)
        parts: list[bytes] = []
        offset = 0
        while offset < _U16_LIMIT:
            try:
                chunk = await self._config_chunk(rack, slot, offset, deadline)
            except CncError as exc:
                if offset and exc.ew == EW.NUMBER:
                    break  # the record ended exactly at a chunk boundary
                raise
            parts.append(chunk)
            if len(chunk) < MAX_CONFIG_CHUNK:
                break
            offset += MAX_CONFIG_CHUNK
        return b"".join(parts)

    async def read_module_config(
        self, rack: int, slot: int, *, timeout: float | None = None
    ) -> IOModuleRecord:
        """``versamax_rdconfig``: the decoded configuration record of an I/O module."""
        return IOModuleRecord.decode(await self.read_config_record(rack, slot, timeout=timeout))
