"""The typed asyncio client: :class:`FocasClient`.

One TCP connection carries many calls at once (matched by request id); every method is
awaited for a typed result (a coroutine function, or a plain method returning the request's
coroutine: see ``_awaitable``), and every EW answer raises :class:`CncError`. The wire protocol
is ``docs/protocol.md``, the client ``docs/client.md``.

The client is built from these parts of ``focas_net.client``:

* :mod:`.connection`: one pipelined connection (request ids, slots, deadlines);
* :mod:`._link`: the :class:`~._link.Link` every :class:`FocasClient` is: the connection's
  lifecycle (:mod:`._lifecycle`: the state machine, the reconnect backoff, deadlines), the
  unlock-and-retry and the one request path (``_request``) every call below takes;
* :mod:`._composite`: what both clients build on a few primitives (typed parameter reads,
  bit read-modify-write, PMC ranges and :class:`ChunkedWriteError`); :mod:`._pmc` gives the
  packed PMC primitives (32-byte chunks);
* :mod:`._values`: the checks of every argument and the value conversions;
* :mod:`.sim_control`: the simulator control commands, as ``client.sim``.
"""

# Every call takes a per-call ``timeout=`` by contract (a deadline is computed once per call and
# shared by its chunks, lock waits and reconnect waits), so ASYNC109 does not apply here.
# ruff: noqa: ASYNC109

from __future__ import annotations

import inspect
import ssl as _ssl
from collections.abc import AsyncIterator, Callable, Coroutine, Sequence
from contextlib import asynccontextmanager
from decimal import Decimal
from typing import Any, Final, TypeVar

from focas_net._refusals import (
    READ_ONLY,
    SEARCH,
    SPINDLE_DIAGS,
    mode_refusal,
    program_busy,
    program_missing,
    program_refusal,
    select_busy,
)
from focas_net.errors import EW, CncError, FocasError, PayloadError

from ..protocol import (
    COMMANDS,
    DEFAULT_MAX_FRAME,
    MAX_CONFIG_CHUNK,
    MAX_DIRECTORY_ENTRIES,
    MAX_PMC_CHUNK,
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
    PathSelection,
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
from ._composite import ChunkOutcome, macro_named, with_reason
from ._failures import axis_refusal
from ._link import UNLOCK_AND_RETRY, Link
from ._pmc import read_pmc_range, write_pmc_chunks
from ._started import StartedCall
from ._values import (
    I32_MAX,
    REAL_WIDTH,
    Paths,
    Positions,
    alarm_type_number,
    check_axis,
    check_int,
    check_item,
    check_macro,
    history_depth,
    int_to_wire,
    macro_from_wire,
    macro_write,
    param_int,
    real_to_wire,
    width_refused,
)
from .connection import NotSentError
from .reconnect import ReconnectPolicy, StateCallback
from .sim_control import SimControl, mode_of

__all__ = ["FocasClient"]

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
#: The bytes of a parameter of each type (IODBPSD: cdata, idata, ldata, rdata).
_TYPE_WIDTHS: Final = {
    ParamDataType.BIT: 1,
    ParamDataType.BYTE: 1,
    ParamDataType.WORD: 2,
    ParamDataType.TWO_WORD: 4,
    ParamDataType.REAL: REAL_WIDTH,
}
_RDPROGDIR: Final = COMMANDS[C.RDPROGDIR]
_RDPROGRAM: Final = COMMANDS[C.RDPROGRAM]
_RDRUNINFO: Final = COMMANDS[C.RDRUNINFO]
_RDLOADS: Final = COMMANDS[C.RDLOADS]
_WRPROGRAM: Final = COMMANDS[C.WRPROGRAM]
_DELPROGRAM: Final = COMMANDS[C.DELPROGRAM]
_SELPROGRAM: Final = COMMANDS[C.SELPROGRAM]
_GETPATH: Final = COMMANDS[C.GETPATH]
#: Bounds of the paged reads of programs (a directory of 400 programs, 512,000 characters).
_MAX_DIRECTORY_PAGES: Final = 1024
_MAX_PROGRAM_CHUNKS: Final = 1024

_EMPTY: Final = b""
_MAX_ACTIVE_ALARMS: Final = 32
_U8_MAX: Final = 0xFF
_U16_LIMIT: Final = 0x10000


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


def _integral(number: int, value: int | Decimal | str) -> bool:
    """Whether ``value`` reads as an integer parameter's value (no decimals but zeros)."""
    try:
        param_int(number, value)
    except ValueError:
        return False
    return True


@asynccontextmanager
async def _program_named(
    number: int, busy: Callable[[int], str] | None = None
) -> AsyncIterator[None]:
    """A refusal of a call of program ``number`` told as the store tells it (EW_NUMBER: ``no
    program O1234``; EW_BUSY: ``busy(number)``; EW_PROT: a read-only machine): the packed
    answer carries the code only."""
    try:
        yield
    except CncError as exc:
        why = None
        if exc.ew == EW.NUMBER:
            why = program_missing(number)
        elif exc.ew == EW.BUSY and busy is not None:
            why = busy(number)
        elif exc.ew == EW.PROT:
            why = READ_ONLY
        raise with_reason(exc, why) from None


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
        path: int = 1,
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
            path=path,
        )
        self._param_types: dict[int, ParamDataType | None] = {}
        self._path_count: int | None = None
        self.sim = SimControl(self)

    # -- status --------------------------------------------------------------------------
    # The reads whose answer is their result are plain methods that return the request's
    # coroutine (see _awaitable): awaiting one is awaiting an ``async def``, one coroutine
    # less per call.
    @_awaitable
    def read_status(
        self, *, path: int | None = None, timeout: float | None = None
    ) -> Coroutine[Any, Any, StatusInfo]:
        """``cnc_rdcncstat``: the ODBST status (mode, run state, alarm, emergency, ...)."""
        return self._request(_RDCNCSTAT, _EMPTY, timeout, self._path_of(path))

    def start_read_status(
        self, *, path: int | None = None, timeout: float | None = None
    ) -> StartedCall[StatusInfo]:
        """:meth:`read_status` started now (its request sent at once on the live connection
        when a slot is free, else run as the call itself in a task of its own) and finished by
        awaiting :meth:`StartedCall.result` (see :func:`~focas_net.client.read_status_all`).
        A request that never left, or one answered ``EW_PASSWD`` while a password is known,
        is made again the usual way within what is left of its deadline."""
        p = self._path_of(path)
        deadline = self._deadline(timeout)
        sent = self._start(_RDCNCSTAT, _EMPTY, deadline, p)
        if sent is None:
            return StartedCall.running(self.read_status(path=p, timeout=timeout))
        conn, entry = sent

        async def finish() -> StatusInfo:
            try:
                raw = await entry[0]
            except NotSentError:
                raw = None
            if raw is not None:
                value = self._answer(_RDCNCSTAT, raw, sent=_EMPTY)
                if value is not UNLOCK_AND_RETRY:
                    result: StatusInfo = value
                    return result
            again: StatusInfo = await self._request_at(_RDCNCSTAT, _EMPTY, deadline, path=p)
            return again

        return StartedCall(finish, lambda: conn.finish(entry), entry[0])

    @_awaitable
    def read_sysinfo(self, *, timeout: float | None = None) -> Coroutine[Any, Any, SysInfo]:
        """``cnc_sysinfo``: ODBSYS (CNC type, series, version, axes)."""
        return self._request(_SYSINFO, _EMPTY, timeout)

    # -- program, feed, spindle, positions ------------------------------------------------
    @_awaitable
    def read_program_numbers(
        self, *, path: int | None = None, timeout: float | None = None
    ) -> Coroutine[Any, Any, ProgramNumbers]:
        """``cnc_rdprgnum``: the running and the main program numbers (0 = none)."""
        return self._request(_RDPRGNUM, _EMPTY, timeout, self._path_of(path))

    async def read_feed(self, *, path: int | None = None, timeout: float | None = None) -> int:
        """``cnc_actf``: the actual feed rate (the machine's feed unit, e.g. mm/min)."""
        value: ActualValue = await self._request(_ACTF, _EMPTY, timeout, self._path_of(path))
        return value.data

    async def read_spindle_speed(
        self, *, path: int | None = None, timeout: float | None = None
    ) -> int:
        """``cnc_acts``: the actual spindle speed (min^-1)."""
        value: ActualValue = await self._request(_ACTS, _EMPTY, timeout, self._path_of(path))
        return value.data

    async def read_paths(self, *, timeout: float | None = None) -> Paths:
        """``cnc_getpath``: the path this connection's per-path requests are answered for
        (the last one a call selected: 1 on a new connection; 0 after the CNC refused the
        last selection) and the number of paths of the CNC."""
        value: PathSelection = await self._request(_GETPATH, _EMPTY, timeout)
        self._path_count = value.max
        return Paths(value.current, value.max)

    @property
    def path_count(self) -> int | None:
        """The number of paths of the CNC as the last :meth:`read_paths` read it (None
        before the first)."""
        return self._path_count

    async def read_positions(
        self,
        kind: str | int | PositionKind = PositionKind.ABSOLUTE,
        *,
        axis: int | None = None,
        path: int | None = None,
        timeout: float | None = None,
    ) -> Positions:
        """``cnc_rdposition``: positions of every axis (``axis=None``) or of axis ``axis``
        (1..n). ``kind``: ``"absolute"``, ``"machine"``, ``"relative"``, ``"distance"``
        (to go), a :class:`PositionKind` or 0..3.

        An unknown ``kind`` or an ``axis`` below 1 raises :class:`ValueError` before anything
        is sent; an axis the CNC does not have answers EW_ATTRIB (:class:`CncError`).
        """
        which = PositionKind.parse(kind)
        check_axis(axis)
        p = self._path_of(path)
        deadline = self._deadline(timeout)
        payload = _RDPOSITION.request.encode(PositionRequest(which, -1 if axis is None else axis))
        try:
            data: PositionData = await self._request_at(_RDPOSITION, payload, deadline, path=p)
        except CncError as exc:
            raise await self._axis_refusal(exc, axis, p, deadline) from None
        dec = data.dec
        return Positions(
            which,
            dec,
            {a.name: Decimal(a.value).scaleb(-dec) for a in data.axes},
            {a.name: a.value for a in data.axes},
        )

    # -- parameters and diagnostics ------------------------------------------------------
    async def _axis_count(self, path: int, deadline: float | None) -> int | None:
        """The number of axes of ``path`` (one ``cnc_rdposition`` of every axis); None when
        it cannot be read."""
        payload = _RDPOSITION.request.encode(PositionRequest(PositionKind.ABSOLUTE, -1))
        try:
            data: PositionData = await self._request_at(_RDPOSITION, payload, deadline, path=path)
        except FocasError:
            return None
        return len(data.axes)

    async def _axis_refusal(
        self, exc: CncError, axis: int | None, path: int, deadline: float | None
    ) -> CncError:
        """``exc``, or for EW_ATTRIB or EW_NUMBER with an ``axis`` beyond ``path``'s axes
        EW_ATTRIB naming the axis and the count as the native client does before sending
        (``cnc_rdparam: axis 9 is outside 1..3: the path has 3 axes``): a packed answer
        carries the code only, and the packed contract checks the number first, so the count
        is read after the refusal, within the call's deadline. A refusal with an axis the
        path has stays as it came."""
        if exc.ew not in (EW.ATTRIB, EW.NUMBER):
            return exc
        return await self._axis_past(exc.detail, axis, path, deadline) or exc

    async def _axis_past(
        self, function: str, axis: int | None, path: int, deadline: float | None
    ) -> CncError | None:
        """EW_ATTRIB naming ``axis`` and the count (``axis 9 is outside 1..3: ...``) when
        ``axis`` is past ``path``'s axes, as FANUC's library checks the axis before anything
        else; None when it is not (or the count cannot be read)."""
        if axis is None or axis < 1:
            return None
        count = await self._axis_count(path, deadline)
        if count is None or axis <= count:
            return None
        return axis_refusal(function, axis, count)

    async def _read_param_value(
        self, number: int, axis: int, deadline: float | None, path: int
    ) -> ParamValue:
        payload = _RDPARAM.request.encode(DataRequest(number, axis))
        try:
            value: ParamValue = await self._request_at(_RDPARAM, payload, deadline, path=path)
        except CncError as exc:
            raise await self._axis_refusal(exc, axis, path, deadline) from None
        self._param_widths[number] = value.width
        return value

    async def _is_bit(self, number: int, value: ParamValue, deadline: float | None) -> bool:
        return value.width == 1 and await self._param_type(number, deadline) is ParamDataType.BIT

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
        check_item(number, 0, "parameter")
        return await self._read_param_attributes(number, self._deadline(timeout))

    async def _write_param(
        self,
        number: int,
        value: int | Decimal | str,
        axis: int,
        width: int | None,
        deadline: float | None,
        path: int,
    ) -> None:
        """With ``width=None`` the width is the one of the parameter's type, asked once with
        ``cnc_rdparainfo``, which needs no axis (as FOCAS/2's ``cnc_wrparam`` asks the type
        first): a value that does not fit the type is refused before anything is written,
        and a missing ``axis`` is the write's EW_ATTRIB, alike on both transports; a CNC
        that cannot tell the type gives the width of one read. A refusal of what the write
        asks first is the write's refusal, named ``cnc_wrparam`` (FOCAS/2 asks the same in
        the first frame of ``cnc_wrparam``)."""
        learnt = False
        given = width
        try:
            if width is None:
                cached = self._param_widths.get(number)
                if cached is None:
                    learnt = number not in self._param_types  # (asked now, not kept before)
                    told = await self._param_type(number, deadline)
                    width = (
                        _TYPE_WIDTHS[told]
                        if told is not None
                        else (await self._read_param_value(number, axis, deadline, path)).width
                    )
                else:
                    width = cached
            # the type is asked for a 1-byte width (bit or byte), and for a value with
            # decimals given an integer width: a real parameter's is then the width refused
            asks = width == 1 or (given is not None and not _integral(number, value))
            kind = await self._param_type(number, deadline) if asks else None
        except CncError as exc:
            past = await self._axis_past(_WRPARAM.function, axis, path, deadline)
            raise past or CncError.from_ew(exc.ew, _WRPARAM.function) from None
        if given is not None and kind is not None and _TYPE_WIDTHS[kind] != given:
            raise width_refused(number, _TYPE_WIDTHS[kind], given)  # as FOCAS/2 refuses it
        if width == REAL_WIDTH:
            mantissa, decimals = real_to_wire(number, value)
            pv = ParamValue(number, axis, mantissa, width, decimals)
        else:
            raw = param_int(number, value, kind)
            pv = ParamValue(number, axis, int_to_wire(number, raw, width, kind), width)
        payload = _WRPARAM.request.encode(pv)
        try:
            await self._request_at(_WRPARAM, payload, deadline, path=path)
        except CncError as exc:
            if exc.ew == EW.LENGTH and not learnt:
                self._param_widths.pop(number, None)  # stale width: learn it again next time
                self._param_types.pop(number, None)  # (the type it came from)
            if exc.ew == EW.LENGTH and given is not None:
                raise await self._width_refusal(exc, number, given, deadline) from None
            raise await self._axis_refusal(exc, axis, path, deadline) from None

    async def _width_refusal(
        self, exc: CncError, number: int, width: int, deadline: float | None
    ) -> CncError:
        """The EW_LENGTH of a write given ``width``, naming the parameter's own width as
        FOCAS/2's ``cnc_wrparam`` does (one ``cnc_rdparainfo``, after the refusal)."""
        try:
            kind = await self._param_type(number, deadline)
        except CncError:
            return exc
        if kind is None or _TYPE_WIDTHS[kind] == width:
            return exc
        return width_refused(number, _TYPE_WIDTHS[kind], width)

    async def _write_param_bits(
        self, number: int, axis: int, bits: int, width: int, deadline: float | None, path: int
    ) -> None:
        size = 8 * width
        raw = bits - (1 << size) if bits >= 1 << (size - 1) else bits
        payload = _WRPARAM.request.encode(ParamValue(number, axis, raw, width))
        try:
            await self._request_at(_WRPARAM, payload, deadline, path=path)
        except CncError as exc:
            raise await self._axis_refusal(exc, axis, path, deadline) from None

    async def read_diag(
        self,
        number: int,
        *,
        axis: int = 0,
        path: int | None = None,
        timeout: float | None = None,
    ) -> int:
        """``cnc_diagnoss`` (this protocol's ``cnc_rddiag``): the value of diagnostic ``number``."""
        check_item(number, axis, "diagnostic")
        p = self._path_of(path)
        deadline = self._deadline(timeout)
        payload = _RDDIAG.request.encode(DataRequest(number, axis))
        try:
            value: ParamValue = await self._request_at(_RDDIAG, payload, deadline, path=p)
        except CncError as exc:
            if number in SPINDLE_DIAGS:  # its axis is the spindle: the code says it
                raise
            raise await self._axis_refusal(exc, axis, p, deadline) from None
        return value.value

    # -- macros --------------------------------------------------------------------------
    async def read_macro(
        self, number: int, *, path: int | None = None, timeout: float | None = None
    ) -> Decimal | None:
        """``cnc_rdmacro``: the value of ``#number`` as a Decimal, or None when vacant."""
        check_macro(number)
        p = self._path_of(path)
        payload = _RDMACRO.request.encode(MacroRequest(number))
        value: MacroValue = await self._request(_RDMACRO, payload, timeout, p)
        return macro_from_wire(value.mcr_val, value.dec_val)

    async def write_macro(
        self,
        number: int,
        value: int | Decimal | float | str,
        *,
        path: int | None = None,
        timeout: float | None = None,
    ) -> None:
        """``cnc_wrmacro``: write ``#number``; see
        :func:`~focas_net._typed.macro_to_wire` for the scaling.

        A value that cannot be carried raises :class:`ValueError` naming ``#number`` before
        anything is sent.
        """
        mcr_val, dec_val = macro_write(number, value)
        p = self._path_of(path)
        payload = _WRMACRO.request.encode(MacroValue(number, 8, mcr_val, dec_val))
        async with macro_named(number, value):
            await self._request(_WRMACRO, payload, timeout, p)

    # -- PMC -----------------------------------------------------------------------------
    async def _read_pmc(
        self, area: PmcArea, start: int, count: int, deadline: float | None
    ) -> bytes:
        return await read_pmc_range(self, area, start, count, deadline)

    def _pmc_write_chunk(self) -> int:
        return MAX_PMC_CHUNK

    async def _write_pmc_chunks(
        self, area: PmcArea, chunks: Sequence[tuple[int, bytes]], deadline: float | None
    ) -> list[ChunkOutcome]:
        return await write_pmc_chunks(self, _WRPMCRNG, area, chunks, deadline)

    # -- alarms --------------------------------------------------------------------------
    async def read_alarms(
        self,
        *,
        alm_type: AlarmType | str | int = -1,
        path: int | None = None,
        timeout: float | None = None,
    ) -> tuple[ActiveAlarm, ...]:
        """``cnc_rdalmmsg``: the active alarms (all types, -1, or only ``alm_type``: by name,
        ``"PS"``, an :class:`AlarmType` or a number), oldest first. An error answer
        (count = -1) raises :class:`CncError`."""
        t = alarm_type_number(alm_type, every=True)
        p = self._path_of(path)
        payload = _RDALMMSG.request.encode(AlarmMsgRequest(t, _MAX_ACTIVE_ALARMS))
        result: ActiveAlarmList = await self._request(_RDALMMSG, payload, timeout, p)
        if result.ew:
            refused = CncError.from_ew(result.ew, _RDALMMSG.function)
            raise await self._path_refusal(refused, _RDALMMSG, p, self._deadline(timeout))
        return result.entries

    async def read_alarm_history(
        self, depth: int = 10, *, timeout: float | None = None
    ) -> AlarmHistory:
        """``cnc_rdalmhistry``: up to ``depth`` (1.., above 250 read as 250) latest entries,
        newest first. An error answer (a negative count) raises :class:`CncError`, like
        :meth:`read_alarms`: a failed read is never mistaken for an empty history."""
        depth = history_depth(depth)
        payload = _RDALMHISTRY.request.encode(AlarmHistoryRequest(depth))
        result: AlarmHistory = await self._request(_RDALMHISTRY, payload, timeout)
        if result.ew:
            raise CncError.from_ew(result.ew, _RDALMHISTRY.function)
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
        self, *, first: int = 0, path: int | None = None, timeout: float | None = None
    ) -> tuple[ProgramEntry, ...]:
        """``cnc_rdprogdir``: every stored program from O number ``first`` on (number, size in
        characters, name), by number, read 64 entries per request."""
        check_int("first program number", first, 0, I32_MAX)
        p = self._path_of(path)
        deadline = self._deadline(timeout)
        entries: list[ProgramEntry] = []
        for _ in range(_MAX_DIRECTORY_PAGES):
            request = _RDPROGDIR.request.encode(DirectoryRequest(first, MAX_DIRECTORY_ENTRIES))
            page: ProgramDirectory = await self._request_at(_RDPROGDIR, request, deadline, path=p)
            entries.extend(page.entries)
            if len(page.entries) < MAX_DIRECTORY_ENTRIES or page.entries[-1].number >= I32_MAX:
                break
            first = page.entries[-1].number + 1
        return tuple(entries)

    async def read_program(
        self, number: int, *, path: int | None = None, timeout: float | None = None
    ) -> str:
        """``cnc_upload``: the text of program ``number`` as stored (EW_NUMBER: no such
        program), read 4096 characters per request and joined."""
        check_int("program number", number, 0, I32_MAX)
        p = self._path_of(path)
        deadline = self._deadline(timeout)
        parts: list[str] = []
        offset = 0
        for _ in range(_MAX_PROGRAM_CHUNKS):
            request = _RDPROGRAM.request.encode(ProgramChunkRequest(number, offset))
            async with _program_named(number):
                chunk: ProgramChunk = await self._request_at(_RDPROGRAM, request, deadline, path=p)
            parts.append(chunk.text)
            offset += len(chunk.text)
            if not chunk.text or offset >= chunk.total:
                break
        return "".join(parts)

    async def write_program(
        self,
        text: str,
        *,
        replace: bool = False,
        path: int | None = None,
        timeout: float | None = None,
    ) -> int:
        """``cnc_download``: store one O-number program; returns its number. A number already
        stored answers EW_REJECT unless ``replace``; a program being executed EW_BUSY; text
        that is not one program EW_DATA; a full memory EW_OVRFLOW. A ``replace`` other than
        True or False is a TypeError, as the machine says it."""
        if not isinstance(text, str):
            raise TypeError(f"a program is text, got {text!r}")
        if not isinstance(replace, bool):
            raise TypeError(f"replace must be True or False, got {replace!r}")
        p = self._path_of(path)
        payload = _WRPROGRAM.request.encode(ProgramText(int(bool(replace)), text))
        try:
            stored: ProgramNumber = await self._request(_WRPROGRAM, payload, timeout, p)
        except CncError as exc:
            why = program_refusal(exc.ew, text)  # the store's reason: the wire has the code
            if why is None:
                raise
            if exc.ew == EW.REJECT:
                why += " (replace=True replaces it)"
            raise CncError.from_ew(exc.ew, f"{exc.detail}: {why}") from None
        return stored.number

    async def delete_program(
        self, number: int, *, path: int | None = None, timeout: float | None = None
    ) -> None:
        """``cnc_delete``: delete program ``number`` (EW_NUMBER: none; EW_BUSY: executing)."""
        check_int("program number", number, 0, I32_MAX)
        p = self._path_of(path)
        payload = _DELPROGRAM.request.encode(ProgramNumber(number))
        async with _program_named(number, program_busy):
            await self._request(_DELPROGRAM, payload, timeout, p)

    async def select_program(
        self, number: int, *, path: int | None = None, timeout: float | None = None
    ) -> None:
        """``cnc_search``: make ``number`` the main program (EW_NUMBER: none; EW_MODE: not MEM
        or EDIT, the mode read after the refusal; EW_BUSY: another program is executing)."""
        check_int("program number", number, 0, I32_MAX)
        p = self._path_of(path)
        deadline = self._deadline(timeout)
        payload = _SELPROGRAM.request.encode(ProgramNumber(number))
        try:
            async with _program_named(number, select_busy):
                await self._request_at(_SELPROGRAM, payload, deadline, path=p)
        except CncError as exc:
            if exc.ew != EW.MODE:
                raise
            status = await self._status_now(p, deadline)
            mode = None if status is None else mode_of(status)
            raise with_reason(exc, mode_refusal(SEARCH, "MEM or EDIT", mode)) from None

    async def _status_now(self, path: int, deadline: float | None) -> StatusInfo | None:
        """``path``'s status, read within ``deadline`` for the reason of a refusal the answer
        tells by its code alone (the mode, the emergency stop); None when it cannot be read."""
        try:
            status: StatusInfo = await self._request_at(_RDCNCSTAT, _EMPTY, deadline, path=path)
        except FocasError:
            return None
        return status

    @_awaitable
    def read_run_info(
        self, *, path: int | None = None, timeout: float | None = None
    ) -> Coroutine[Any, Any, RunInfo]:
        """Overrides (%), parts count and total parts, and the power-on, operating, cutting
        and cycle timers (ms) of the simulated machine."""
        return self._request(_RDRUNINFO, _EMPTY, timeout, self._path_of(path))

    @_awaitable
    def read_loads(
        self, *, path: int | None = None, timeout: float | None = None
    ) -> Coroutine[Any, Any, LoadMeters]:
        """The load of each spindle and the servo load of each axis, in percent
        (``cnc_rdspload`` and ``cnc_rdsvmeter`` in one request)."""
        return self._request(_RDLOADS, _EMPTY, timeout, self._path_of(path))

    # -- VersaMax ------------------------------------------------------------------------
    async def _config_chunk(
        self, rack: int, slot: int, offset: int, deadline: float | None
    ) -> bytes:
        check_int("rack", rack, 0, _U8_MAX)
        check_int("slot", slot, 0, _U8_MAX)
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
