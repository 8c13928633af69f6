"""The typed asyncio client: :class:`FocasClient`.

One TCP connection carries many calls at once (matched by request id); every method is a
coroutine with a typed result, and every EW answer raises :class:`CncError`. See
``docs/client.md``.
"""

# Every call takes a per-call ``timeout=`` by contract (a deadline is computed once per call and
# shared by its chunks, lock waits and reconnect waits), so ASYNC109 does not apply here.
# ruff: noqa: ASYNC109

from __future__ import annotations

import asyncio
import enum
import logging
import math
import random
import ssl as _ssl
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from decimal import Decimal, InvalidOperation
from types import TracebackType
from typing import Any, Final, Self

from focas_net.errors import (
    EW,
    ChunkedWriteError,
    CncError,
    FocasConnectionError,
    FocasTimeoutError,
    PayloadError,
)

from ..protocol import (
    COMMANDS,
    DEFAULT_MAX_FRAME,
    MAX_CONFIG_CHUNK,
    MAX_HISTORY_DEPTH,
    MAX_PMC_CHUNK,
    ActiveAlarm,
    ActiveAlarmList,
    ActualValue,
    AlarmHistory,
    AlarmHistoryRequest,
    AlarmMsgRequest,
    AutMode,
    ClearAlarms,
    CommandSpec,
    DataRequest,
    EwReply,
    FaultKind,
    FaultScope,
    InjectFault,
    MacroRequest,
    MacroValue,
    ParamValue,
    Password,
    PmcArea,
    PmcData,
    PmcRange,
    PositionData,
    PositionKind,
    PositionRequest,
    ProgramNumbers,
    RaiseAlarm,
    SetPanel,
    StatusInfo,
    SysInfo,
    VersaMaxReply,
    VersaMaxRequest,
)
from ..protocol import Command as C
from ..versamax import IOModuleRecord
from ._locks import KeyedLocks
from .connection import MAX_IN_FLIGHT, Connection, NotSentError, open_connection

__all__ = [
    "ClientState",
    "FaultKind",
    "FaultScope",
    "FocasClient",
    "Positions",
    "ReconnectPolicy",
    "SimControl",
]

logger = logging.getLogger(__name__)

_RDCNCSTAT: Final = COMMANDS[C.RDCNCSTAT]
_SYSINFO: Final = COMMANDS[C.SYSINFO]
_RDPARAM: Final = COMMANDS[C.RDPARAM]
_RDDIAG: Final = COMMANDS[C.RDDIAG]
_RDMACRO: Final = COMMANDS[C.RDMACRO]
_RDALMMSG: Final = COMMANDS[C.RDALMMSG]
_RDPMCRNG: Final = COMMANDS[C.RDPMCRNG]
_WRPARAM: Final = COMMANDS[C.WRPARAM]
_WRMACRO: Final = COMMANDS[C.WRMACRO]
_WRPMCRNG: Final = COMMANDS[C.WRPMCRNG]
_UNLOCK: Final = COMMANDS[C.WRUNLOCKPARAM]
_RDCONFIG: Final = COMMANDS[C.VERSAMAX_RDCONFIG]
_SET_PANEL: Final = COMMANDS[C.SIM_SET_PANEL]
_RAISE_ALARM: Final = COMMANDS[C.SIM_RAISE_ALARM]
_CLEAR_ALARMS: Final = COMMANDS[C.SIM_CLEAR_ALARMS]
_SET_PMC: Final = COMMANDS[C.SIM_SET_PMC]
_INJECT_FAULT: Final = COMMANDS[C.SIM_INJECT_FAULT]
_RDALMHISTRY: Final = COMMANDS[C.RDALMHISTRY]
_RDPRGNUM: Final = COMMANDS[C.RDPRGNUM]
_ACTF: Final = COMMANDS[C.ACTF]
_ACTS: Final = COMMANDS[C.ACTS]
_RDPOSITION: Final = COMMANDS[C.RDPOSITION]
_STATUS_COMMAND: Final = int(C.RDCNCSTAT)
_decode_status: Final = _RDCNCSTAT.response.decode

_EMPTY: Final = b""
_MAX_ACTIVE_ALARMS: Final = 32
_I32_MIN: Final = -(2**31)
_I32_MAX: Final = 2**31 - 1
_MAX_MACRO_DECIMALS: Final = 9
_U16_LIMIT: Final = 0x10000
_CLOSE_GRACE: Final = 2.0

AreaLike = str | int | PmcArea


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


class ClientState(enum.Enum):
    """Where a :class:`FocasClient` stands."""

    #: Not connected: before :meth:`FocasClient.connect`, or after a loss without reconnect.
    DISCONNECTED = "disconnected"
    #: Connected; calls are sent at once.
    CONNECTED = "connected"
    #: The connection was lost and the reconnect policy is trying again; calls wait.
    RECONNECTING = "reconnecting"
    #: :meth:`FocasClient.aclose` was called; final.
    CLOSED = "closed"


@dataclass(frozen=True, slots=True)
class ReconnectPolicy:
    """Exponential backoff with jitter and a cap.

    The delay before attempt ``n`` (0-based) is ``min(max_delay, initial_delay * factor**n)``,
    reduced by a random fraction of at most ``jitter`` so that many clients of one server do
    not reconnect in lock step. ``n`` goes back to 0 only once a connection has stayed up
    ``stable_after`` seconds: after a connection lost sooner (a server that accepts and closes
    at once) the backoff goes on where it was. ``max_attempts`` bounds the attempts made after
    one loss; ``None`` retries for ever.
    """

    initial_delay: float = 0.1
    max_delay: float = 10.0
    factor: float = 2.0
    jitter: float = 0.25
    max_attempts: int | None = None
    stable_after: float = 5.0

    def __post_init__(self) -> None:
        if self.initial_delay < 0 or self.max_delay < 0:
            raise ValueError("reconnect delays must not be negative")
        if self.factor < 1:
            raise ValueError(f"factor must be at least 1, got {self.factor}")
        if not 0 <= self.jitter <= 1:
            raise ValueError(f"jitter must be within 0..1, got {self.jitter}")
        if self.max_attempts is not None and self.max_attempts < 1:
            raise ValueError("max_attempts must be at least 1 (or None)")
        if not self.stable_after >= 0:  # also refuses NaN
            raise ValueError(f"stable_after must not be negative, got {self.stable_after}")

    def delay(self, attempt: int) -> float:
        """Seconds to wait before attempt ``attempt`` (0-based)."""
        try:
            base = min(self.max_delay, self.initial_delay * self.factor**attempt)
        except OverflowError:
            base = self.max_delay
        return base * (1.0 - self.jitter * random.random())


StateCallback = Callable[[ClientState], None]


def _check_u16_range(start: int, count: int) -> None:
    if not 0 <= start < _U16_LIMIT:
        raise ValueError(f"start address {start} outside 0..65535")
    if count < 1 or start + count > _U16_LIMIT:
        raise ValueError(f"count {count} at {start}: must be at least 1 and end by 65535")


def _check_bit(bit: int, width: int = 1) -> None:
    if not 0 <= bit < 8 * width:
        raise ValueError(f"bit {bit} outside 0..{8 * width - 1}")


def _chunks(start: int, count: int) -> list[tuple[int, int]]:
    """``(first, count)`` of consecutive chunks of at most 32 bytes."""
    return [(a, min(MAX_PMC_CHUNK, start + count - a)) for a in range(start, start + count, 32)]


def _merge(spans: list[tuple[int, int]]) -> list[tuple[int, int]]:
    """Merge sorted inclusive ``(first, last)`` spans that touch."""
    merged: list[tuple[int, int]] = []
    for first, last in spans:
        if merged and merged[-1][1] + 1 == first:
            merged[-1] = (merged[-1][0], last)
        else:
            merged.append((first, last))
    return merged


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


class FocasClient:
    """An asyncio client of the packed FOCAS protocol.

    Use it as ``async with FocasClient(host) as cnc: ...`` or call :meth:`connect` and
    :meth:`aclose`. Every method accepts ``timeout=`` (seconds) overriding the default for
    that call; the timeout covers the whole call (waiting for a free request slot, for a
    reconnect, for a bit lock, and every chunk of a chunked PMC call).

    ``reconnect`` is ``False`` (a lost connection stays lost), ``True`` (the default
    :class:`ReconnectPolicy`) or a :class:`ReconnectPolicy`. ``password`` is sent with
    ``cnc_wrunlockparam`` after every connect and again, followed by one retry, when a call
    answers ``EW_PASSWD``.
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
        if not 1 <= max_in_flight <= MAX_IN_FLIGHT:
            raise ValueError(
                f"max_in_flight must be within 1..{MAX_IN_FLIGHT}, got {max_in_flight}"
            )
        if timeout is not None and timeout <= 0:
            raise ValueError(f"timeout must be positive, got {timeout}")
        self.host = host
        self.port = port
        self.timeout = timeout
        self.max_in_flight = max_in_flight
        self.max_frame = max_frame
        self._ssl = ssl
        self._server_hostname = server_hostname
        self._password = password
        if reconnect is True:
            self._policy: ReconnectPolicy | None = ReconnectPolicy()
        elif reconnect is False:
            self._policy = None
        else:
            self._policy = reconnect
        self._state = ClientState.DISCONNECTED
        self._callbacks: list[StateCallback] = []
        if on_state_change is not None:
            self._callbacks.append(on_state_change)
        self._conn: Connection | None = None
        self._loop: asyncio.AbstractEventLoop | None = None
        self._ready: asyncio.Event | None = None
        self._reconnect_task: asyncio.Task[None] | None = None
        # Backoff step of the next reconnect attempt (reset by a connection that stayed up
        # ``stable_after`` seconds) and when the current connection was installed.
        self._backoff = 0
        self._up_since = 0.0
        self._param_widths: dict[int, int] = {}
        self._pmc_locks: KeyedLocks[tuple[int, int]] = KeyedLocks()
        self._param_locks: KeyedLocks[tuple[int, int]] = KeyedLocks()
        self.sim = SimControl(self)

    def __repr__(self) -> str:
        return f"<FocasClient {self.host}:{self.port} {self._state.value}>"

    # -- lifecycle -----------------------------------------------------------------------
    @property
    def state(self) -> ClientState:
        """The current :class:`ClientState`."""
        return self._state

    @property
    def connected(self) -> bool:
        return self._state is ClientState.CONNECTED

    @property
    def reconnect_policy(self) -> ReconnectPolicy | None:
        return self._policy

    def add_state_callback(self, callback: StateCallback) -> None:
        """Call ``callback(state)`` on every state change (exceptions are logged)."""
        self._callbacks.append(callback)

    def remove_state_callback(self, callback: StateCallback) -> None:
        self._callbacks.remove(callback)

    def _set_state(self, state: ClientState) -> None:
        if state is self._state:
            return
        self._state = state
        logger.info("%s:%s %s", self.host, self.port, state.value)
        for callback in tuple(self._callbacks):
            try:
                callback(state)
            except Exception:
                logger.exception("state callback %r failed", callback)

    async def __aenter__(self) -> Self:
        await self.connect()
        return self

    async def __aexit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        await self.aclose()

    async def connect(self) -> None:
        """Open the connection (and unlock when a password was given).

        Raises :class:`FocasConnectionError` (or :class:`FocasTimeoutError`) when the server
        cannot be reached, :class:`AccessDeniedError` when the password is refused. The
        first connection is not retried; the reconnect policy applies to later losses.
        """
        if self._state is ClientState.CLOSED:
            raise FocasConnectionError("client is closed")
        if self._conn is not None and not self._conn.closed:
            return
        self._loop = asyncio.get_running_loop()
        if self._ready is None:
            self._ready = asyncio.Event()
        conn = await self._open(self._deadline(None), strict=True)
        if self.state is ClientState.CLOSED:  # closed while connecting
            conn.close()
            await conn.wait_closed()
            raise FocasConnectionError("client is closed")
        current = self._conn
        if current is not None and not current.closed:  # a concurrent connect() won
            conn.close()
            await conn.wait_closed()
            return
        self._install(conn)

    async def aclose(self) -> None:
        """Close the connection; pending calls fail with :class:`FocasConnectionError`."""
        self._set_state(ClientState.CLOSED)
        task, self._reconnect_task = self._reconnect_task, None
        if task is not None:
            if not task.done():
                task.cancel()
                await asyncio.wait([task])
            if not task.cancelled() and task.exception() is not None:
                logger.warning("reconnect to %s:%s failed: %r", *self._addr, task.exception())
        conn, self._conn = self._conn, None
        if self._ready is not None:
            self._ready.set()
        if conn is not None:
            conn.close()
            try:
                async with asyncio.timeout(_CLOSE_GRACE):
                    await conn.wait_closed()
            except TimeoutError:
                conn.abort()

    async def _open(self, deadline: float | None, *, strict: bool) -> Connection:
        conn = await open_connection(
            self.host,
            self.port,
            deadline=deadline,
            max_in_flight=self.max_in_flight,
            max_frame=self.max_frame,
            ssl=self._ssl,
            server_hostname=self._server_hostname,
            on_lost=self._on_lost,
        )
        if self._password is not None:
            try:
                await self._unlock_on(conn, self._password, deadline)
            except CncError as exc:
                if strict:
                    conn.close()
                    await conn.wait_closed()
                    raise
                logger.warning("%s:%s: unlock after reconnect refused: %s", *self._addr, exc)
            except BaseException:
                conn.close()
                raise
        return conn

    @property
    def _addr(self) -> tuple[str, int]:
        return (self.host, self.port)

    def _install(self, conn: Connection) -> None:
        task = self._reconnect_task
        if task is not None and not task.done() and task is not asyncio.current_task():
            task.cancel()  # connect() succeeded while the policy was reconnecting
        self._conn = conn
        self._up_since = (self._loop or asyncio.get_running_loop()).time()
        self._set_state(ClientState.CONNECTED)
        if self._ready is not None:
            self._ready.set()

    def _on_lost(self, conn: Connection, exc: BaseException | None) -> None:
        if conn is not self._conn:
            return
        self._conn = None
        if self._state is ClientState.CLOSED:
            return
        if self._policy is None:
            logger.warning("connection to %s:%s lost: %s", self.host, self.port, exc or "closed")
            self._set_state(ClientState.DISCONNECTED)
            return
        logger.warning("connection to %s:%s lost (%s); reconnecting", *self._addr, exc or "closed")
        assert self._ready is not None and self._loop is not None
        if self._loop.time() - self._up_since >= self._policy.stable_after:
            self._backoff = 0  # a stable connection: the backoff starts again from the start
        self._ready.clear()
        self._set_state(ClientState.RECONNECTING)
        if self._reconnect_task is None or self._reconnect_task.done():
            self._reconnect_task = self._loop.create_task(
                self._reconnect(self._policy), name=f"focas-reconnect {self.host}:{self.port}"
            )

    async def _reconnect(self, policy: ReconnectPolicy) -> None:
        attempt = 0
        try:
            while policy.max_attempts is None or attempt < policy.max_attempts:
                await asyncio.sleep(policy.delay(self._backoff))
                self._backoff += 1
                attempt += 1
                try:
                    conn = await self._open(self._deadline(None), strict=False)
                except (FocasConnectionError, FocasTimeoutError) as exc:
                    logger.debug("reconnect attempt %d to %s:%s: %s", attempt, *self._addr, exc)
                    continue
                except Exception as exc:  # e.g. an unlock answer that does not decode
                    logger.warning("reconnect attempt %d to %s:%s: %r", attempt, *self._addr, exc)
                    continue
                if conn.closed:
                    continue
                self._install(conn)
                return
            logger.warning(
                "giving up reconnecting to %s:%s after %d attempts", *self._addr, attempt
            )
            self._set_state(ClientState.DISCONNECTED)
        finally:
            if self._state is ClientState.RECONNECTING and self._conn is None:
                self._set_state(ClientState.DISCONNECTED)  # ended without a connection
            if self._ready is not None:
                self._ready.set()

    async def _connection(self, deadline: float | None) -> Connection:
        """The live connection, waiting (until ``deadline``) while reconnecting."""
        while True:
            conn = self._conn
            if conn is not None:
                if not conn.closed:
                    return conn
                self._on_lost(conn, None)  # closing but connection_lost not run yet
                continue
            state = self._state
            if state is ClientState.CLOSED:
                raise FocasConnectionError("client is closed")
            task = self._reconnect_task
            if (
                state is not ClientState.RECONNECTING
                or self._ready is None
                or task is None
                or task.done()
            ):
                raise FocasConnectionError(f"not connected to {self.host}:{self.port}")
            try:
                async with asyncio.timeout_at(deadline):
                    await self._ready.wait()
            except TimeoutError:
                raise FocasConnectionError(
                    f"still reconnecting to {self.host}:{self.port} when the call timed out"
                ) from None

    # -- the request path ----------------------------------------------------------------
    def _deadline(self, timeout: float | None) -> float | None:
        t = self.timeout if timeout is None else timeout
        if t is None:
            return None
        loop = self._loop or asyncio.get_running_loop()
        return loop.time() + t

    async def _request(self, spec: CommandSpec, payload: bytes, deadline: float | None) -> Any:
        """Send one request (through reconnects) and decode its answer; EW -> CncError."""
        conn = self._conn
        if conn is None or conn.closed:
            return await self._request_loop(spec, payload, deadline, False)
        # Connected (the usual case): one attempt inline, the loop only for what is left.
        try:
            raw = await conn.request(spec.command, payload, deadline)
        except NotSentError:
            if self._policy is None:
                raise
            return await self._request_loop(spec, payload, deadline, False)
        value = spec.response.decode(raw)
        if type(value) is EwReply:
            return await self._ew_answer(spec, payload, deadline, conn, value, False)
        return value

    async def _ew_answer(
        self,
        spec: CommandSpec,
        payload: bytes,
        deadline: float | None,
        conn: Connection,
        value: EwReply,
        retried_unlock: bool,
    ) -> Any:
        """An EW answer: unlock and try once more on EW_PASSWD (when a password is known),
        else raise :class:`CncError`.

        If the connection is lost around the unlock and a reconnect policy is set, the one
        retry waits for the next connection instead (the reconnect sends the password first).
        """
        password = self._password
        if (
            value.ew == EW.PASSWD
            and password is not None
            and not retried_unlock
            and spec is not _UNLOCK
        ):
            try:
                await self._unlock_on(conn, password, deadline)
            except FocasConnectionError:
                if self._policy is None:
                    raise
            return await self._request_loop(spec, payload, deadline, True)
        raise CncError.from_ew(value.ew, spec.focas_name)

    async def _request_loop(
        self, spec: CommandSpec, payload: bytes, deadline: float | None, retried_unlock: bool
    ) -> Any:
        while True:
            conn = self._conn
            if conn is None or conn.closed:
                conn = await self._connection(deadline)
            try:
                raw = await conn.request(spec.command, payload, deadline)
            except NotSentError:
                if self._policy is None:
                    raise
                continue  # never reached the peer: safe to send on the next connection
            value = spec.response.decode(raw)
            if type(value) is EwReply:
                return await self._ew_answer(spec, payload, deadline, conn, value, retried_unlock)
            return value

    async def _unlock_on(
        self, conn: Connection, password: str | bytes, deadline: float | None
    ) -> None:
        raw = await conn.request(
            _UNLOCK.command, _UNLOCK.request.encode(Password.from_text(password)), deadline
        )
        value = _UNLOCK.response.decode(raw)
        if type(value) is EwReply:
            raise CncError.from_ew(value.ew, _UNLOCK.focas_name)

    async def _call(self, spec: CommandSpec, payload: bytes, timeout: float | None) -> Any:
        return await self._request(spec, payload, self._deadline(timeout))

    # -- status --------------------------------------------------------------------------
    async def read_status(self, *, timeout: float | None = None) -> StatusInfo:
        """``cnc_rdcncstat``: the ODBST status (mode, run state, alarm, emergency, ...)."""
        conn = self._conn
        loop = self._loop
        if conn is None or conn.closed or loop is None:
            result: StatusInfo = await self._request(_RDCNCSTAT, _EMPTY, self._deadline(timeout))
            return result
        # The polling path, inlined: connected, one attempt, a non-EW answer.
        t = self.timeout if timeout is None else timeout
        deadline = None if t is None else loop.time() + t
        try:
            raw = await conn.request(_STATUS_COMMAND, _EMPTY, deadline)
        except NotSentError:
            if self._policy is None:
                raise
            result = await self._request_loop(_RDCNCSTAT, _EMPTY, deadline, False)
            return result
        value = _decode_status(raw)
        if type(value) is EwReply:
            result = await self._ew_answer(_RDCNCSTAT, _EMPTY, deadline, conn, value, False)
            return result
        result = value
        return result

    async def read_sysinfo(self, *, timeout: float | None = None) -> SysInfo:
        """``cnc_sysinfo``: ODBSYS (CNC type, series, version, axes)."""
        result: SysInfo = await self._call(_SYSINFO, _EMPTY, timeout)
        return result

    # -- program, feed, spindle, positions ------------------------------------------------
    async def read_program_numbers(self, *, timeout: float | None = None) -> ProgramNumbers:
        """``cnc_rdprgnum``: the running and the main program numbers (0 = none)."""
        result: ProgramNumbers = await self._call(_RDPRGNUM, _EMPTY, timeout)
        return result

    async def read_feed(self, *, timeout: float | None = None) -> int:
        """``cnc_actf``: the actual feed rate (the machine's feed unit, e.g. mm/min)."""
        value: ActualValue = await self._call(_ACTF, _EMPTY, timeout)
        return value.data

    async def read_spindle_speed(self, *, timeout: float | None = None) -> int:
        """``cnc_acts``: the actual spindle speed (min^-1)."""
        value: ActualValue = await self._call(_ACTS, _EMPTY, timeout)
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
        if axis is not None and not 1 <= axis <= 0x7FFF:
            raise ValueError(f"axis must be 1..n (None for every axis), got {axis}")
        payload = _RDPOSITION.request.encode(PositionRequest(which, -1 if axis is None else axis))
        data: PositionData = await self._call(_RDPOSITION, payload, timeout)
        dec = data.dec
        return Positions(
            which,
            dec,
            {a.name: Decimal(a.value).scaleb(-dec) for a in data.axes},
            {a.name: a.value for a in data.axes},
        )

    # -- parameters and diagnostics ------------------------------------------------------
    async def _read_param_value(self, number: int, axis: int, deadline: float | None) -> ParamValue:
        payload = _RDPARAM.request.encode(DataRequest(number, axis))
        value: ParamValue = await self._request(_RDPARAM, payload, deadline)
        self._param_widths[number] = value.width
        return value

    async def read_param_value(
        self, number: int, *, axis: int = 0, timeout: float | None = None
    ) -> ParamValue:
        """``cnc_rdparam`` as an IODBPSD: the value and its width (1, 2 or 4 bytes)."""
        return await self._read_param_value(number, axis, self._deadline(timeout))

    async def read_param(self, number: int, *, axis: int = 0, timeout: float | None = None) -> int:
        """``cnc_rdparam``: the value of parameter ``number`` (``axis`` 1..n for axis items)."""
        value = await self._read_param_value(number, axis, self._deadline(timeout))
        return value.value

    async def write_param(
        self,
        number: int,
        value: int,
        *,
        axis: int = 0,
        width: int | None = None,
        timeout: float | None = None,
    ) -> None:
        """``cnc_wrparam``: write ``value`` with ``width`` bytes (1, 2 or 4).

        With ``width=None`` the width is the one the CNC reported for this parameter; the
        first time it is learnt by one read and then cached.
        """
        deadline = self._deadline(timeout)
        learnt = False
        if width is None:
            cached = self._param_widths.get(number)
            if cached is None:
                width = (await self._read_param_value(number, axis, deadline)).width
                learnt = True
            else:
                width = cached
        elif width not in (1, 2, 4):
            raise ValueError(f"parameter width must be 1, 2 or 4, got {width}")
        payload = _WRPARAM.request.encode(ParamValue(number, axis, value, width))
        try:
            await self._request(_WRPARAM, payload, deadline)
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
            _check_bit(bit, width)
            bits = 8 * width
            raw = current.value & ((1 << bits) - 1)
            raw = raw | (1 << bit) if value else raw & ~(1 << bit)
            if raw >= 1 << (bits - 1):
                raw -= 1 << bits
            payload = _WRPARAM.request.encode(ParamValue(number, axis, raw, width))
            await self._request(_WRPARAM, payload, deadline)

    async def read_diag(self, number: int, *, axis: int = 0, timeout: float | None = None) -> int:
        """``cnc_rddiag``: the value of diagnostic ``number``."""
        payload = _RDDIAG.request.encode(DataRequest(number, axis))
        value: ParamValue = await self._call(_RDDIAG, payload, timeout)
        return value.value

    # -- macros --------------------------------------------------------------------------
    async def read_macro(self, number: int, *, timeout: float | None = None) -> Decimal | None:
        """``cnc_rdmacro``: the value of ``#number`` as a Decimal, or None when vacant."""
        payload = _RDMACRO.request.encode(MacroRequest(number))
        value: MacroValue = await self._call(_RDMACRO, payload, timeout)
        return macro_from_wire(value.mcr_val, value.dec_val)

    async def write_macro(
        self, number: int, value: int | Decimal | float | str, *, timeout: float | None = None
    ) -> None:
        """``cnc_wrmacro``: write ``#number``; see :func:`macro_to_wire` for the scaling.

        A value that cannot be carried raises :class:`ValueError` before anything is sent.
        """
        mcr_val, dec_val = macro_to_wire(value)
        payload = _WRMACRO.request.encode(MacroValue(number, 8, mcr_val, dec_val))
        await self._call(_WRMACRO, payload, timeout)

    # -- PMC -----------------------------------------------------------------------------
    async def _read_pmc_chunk(
        self, area: PmcArea, start: int, count: int, deadline: float | None
    ) -> bytes:
        payload = _RDPMCRNG.request.encode(PmcRange(area, 0, start, start + count - 1))
        value: PmcData = await self._request(_RDPMCRNG, payload, deadline)
        if len(value.data) != count or value.datano_s != start:
            raise PayloadError(
                f"pmc_rdpmcrng answer: {len(value.data)} bytes from {value.datano_s}, "
                f"asked {count} from {start}"
            )
        return value.data

    async def read_pmc(
        self, area: AreaLike, start: int, count: int, *, timeout: float | None = None
    ) -> bytes:
        """``pmc_rdpmcrng``: ``count`` bytes of ``area`` (``"R"`` or :class:`PmcArea`) from
        ``start``. Ranges over 32 bytes are read as 32-byte calls sent as one batch."""
        a = PmcArea.parse(area)
        _check_u16_range(start, count)
        deadline = self._deadline(timeout)
        if count <= MAX_PMC_CHUNK:
            return await self._read_pmc_chunk(a, start, count, deadline)
        conn = self._conn
        if conn is not None and not conn.closed:
            data = await self._read_pmc_batch(conn, a, start, count, deadline)
            if data is not None:
                return data
        parts = await _all_or_first_error(
            [self._read_pmc_chunk(a, s, n, deadline) for s, n in _chunks(start, count)]
        )
        return b"".join(parts)

    async def _read_pmc_batch(
        self, conn: Connection, area: PmcArea, start: int, count: int, deadline: float | None
    ) -> bytes | None:
        """Every chunk of a chunked read in one batch on ``conn``; None when the read must go
        through the per-chunk path instead (the batch was not sent and a reconnect is due, or a
        chunk answered ``EW_PASSWD`` and a password is known): reads are safe to repeat."""
        chunks = _chunks(start, count)
        encode = _RDPMCRNG.request.encode
        payloads = [encode(PmcRange(area, 0, s, s + n - 1)) for s, n in chunks]
        try:
            answers = await conn.request_all(_RDPMCRNG.command, payloads, deadline, _ew_not_ok)
        except NotSentError:
            if self._policy is None:
                raise
            return None
        decode = _RDPMCRNG.response.decode
        parts: list[bytes] = []
        for (first, n), raw in zip(chunks, answers, strict=True):
            if raw is None:
                continue  # given up after another chunk failed; that one is raised below
            value = decode(raw)
            if type(value) is EwReply:
                if value.ew == EW.PASSWD and self._password is not None:
                    return None
                raise CncError.from_ew(value.ew, _RDPMCRNG.focas_name)
            if len(value.data) != n or value.datano_s != first:
                raise PayloadError(
                    f"pmc_rdpmcrng answer: {len(value.data)} bytes from {value.datano_s}, "
                    f"asked {n} from {first}"
                )
            parts.append(value.data)
        if len(parts) != len(chunks):  # not reached: a chunk given up implies one raised
            raise PayloadError("pmc_rdpmcrng: a chunked read ended with chunks missing")
        return b"".join(parts)

    async def _write_pmc_range(
        self, spec: CommandSpec, area: AreaLike, start: int, data: bytes, deadline: float | None
    ) -> None:
        a = PmcArea.parse(area)
        data = bytes(data)
        _check_u16_range(start, len(data))
        if len(data) <= MAX_PMC_CHUNK:
            payload = spec.request.encode(PmcData(a, 0, start, start + len(data) - 1, data))
            await self._request(spec, payload, deadline)
            return
        chunks = _chunks(start, len(data))
        encode = spec.request.encode
        payloads = [
            encode(PmcData(a, 0, first, first + n - 1, data[first - start : first - start + n]))
            for first, n in chunks
        ]
        errors, unanswered = await self._write_chunks(spec, payloads, deadline)
        cause = next((e for e in errors if e is not None), None)
        if cause is None:
            return
        written: list[tuple[int, int]] = []
        not_written: list[tuple[int, int]] = []
        uncertain: list[tuple[int, int]] = []
        for (first, n), error, unsure in zip(chunks, errors, unanswered, strict=True):
            span = (first, first + n - 1)
            if error is None:
                written.append(span)
            elif unsure:
                uncertain.append(span)  # sent, never answered: the CNC may have applied it
            else:
                not_written.append(span)
        raise ChunkedWriteError(
            a.name, _merge(written), _merge(not_written), cause, _merge(uncertain)
        ) from cause

    async def _write_chunks(
        self, spec: CommandSpec, payloads: list[bytes], deadline: float | None
    ) -> tuple[list[Exception | None], list[bool]]:
        """Send the chunks of a chunked write as batches and wait for every chunk.

        Returns, per chunk, the exception it ended with (None: confirmed written) and whether
        it was sent and left unanswered (a timeout, or the connection lost after it left).
        Chunks never sent go out again on the next connection when a reconnect policy is set;
        chunks answered ``EW_PASSWD`` are sent once more after one unlock when a password is
        known (on the next connection, with a reconnect policy, if this one is lost around the
        unlock); every other chunk's outcome is final after one batch.
        """
        count = len(payloads)
        errors: list[Exception | None] = [None] * count
        unanswered = [False] * count
        retried = [False] * count  # sent again after an unlock already
        decode = spec.response.decode
        todo = list(range(count))
        while todo:
            conn = self._conn
            try:
                if conn is None or conn.closed:
                    conn = await self._connection(deadline)
                results = await conn.request_each(
                    spec.command, [payloads[i] for i in todo], deadline
                )
            except NotSentError as exc:
                if self._policy is not None:
                    continue  # nothing left: every chunk goes out on the next connection
                for i in todo:
                    errors[i] = exc
                break
            except (FocasConnectionError, FocasTimeoutError) as exc:
                # Nothing of this batch was sent: not connected (or still reconnecting when
                # the deadline passed), or no request slot free in time.
                for i in todo:
                    errors[i] = exc
                break
            again: list[int] = []
            locked: list[int] = []
            for i, result in zip(todo, results, strict=True):
                if isinstance(result, bytes):
                    try:
                        value = decode(result)
                    except Exception as exc:  # an answer that does not decode
                        errors[i] = exc
                        continue
                    if type(value) is EwReply:
                        if value.ew == EW.PASSWD and self._password is not None and not retried[i]:
                            locked.append(i)
                        else:
                            errors[i] = CncError.from_ew(value.ew, spec.focas_name)
                elif not isinstance(result, Exception):
                    raise result
                elif isinstance(result, NotSentError):
                    if self._policy is not None:
                        again.append(i)  # never reached the peer: sent on the next connection
                    else:
                        errors[i] = result
                else:
                    errors[i] = result
                    unanswered[i] = isinstance(result, (FocasTimeoutError, FocasConnectionError))
            if locked:
                password = self._password
                assert password is not None
                try:
                    await self._unlock_on(conn, password, deadline)
                except Exception as exc:
                    # Lost around the unlock with a reconnect policy: the chunks go out once
                    # more on the next connection (which the reconnect unlocks), like chunks
                    # never sent. Otherwise each chunk was refused: not written.
                    if self._policy is None or not isinstance(exc, FocasConnectionError):
                        for i in locked:
                            errors[i] = exc
                        locked = []
                for i in locked:
                    retried[i] = True
                again.extend(locked)
                again.sort()
            todo = again
        return errors, unanswered

    async def write_pmc(
        self, area: AreaLike, start: int, data: bytes, *, timeout: float | None = None
    ) -> None:
        """``pmc_wrpmcrng``: write ``data`` to ``area`` from ``start``.

        Over 32 bytes the write is split into 32-byte calls sent as one batch; if any fails,
        :class:`ChunkedWriteError` lists the byte ranges written, not written and uncertain.
        """
        await self._write_pmc_range(_WRPMCRNG, area, start, data, self._deadline(timeout))

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
        _check_u16_range(byte, 1)
        deadline = self._deadline(timeout)
        async with self._pmc_locks.hold((a.value, byte), deadline):
            current = (await self._read_pmc_chunk(a, byte, 1, deadline))[0]
            new = current | (1 << bit) if value else current & ~(1 << bit)
            payload = _WRPMCRNG.request.encode(PmcData(a, 0, byte, byte, bytes((new,))))
            await self._request(_WRPMCRNG, payload, deadline)

    # -- alarms --------------------------------------------------------------------------
    async def read_alarms(
        self, *, alm_type: int = -1, timeout: float | None = None
    ) -> tuple[ActiveAlarm, ...]:
        """``cnc_rdalmmsg``: the active alarms (all types, or only ``alm_type``), oldest
        first. An error answer (count = -1) raises :class:`CncError`."""
        payload = _RDALMMSG.request.encode(AlarmMsgRequest(alm_type, _MAX_ACTIVE_ALARMS))
        result: ActiveAlarmList = await self._call(_RDALMMSG, payload, timeout)
        if result.ew:
            raise CncError.from_ew(result.ew, _RDALMMSG.focas_name)
        return result.entries

    async def read_alarm_history(
        self, depth: int = 10, *, timeout: float | None = None
    ) -> AlarmHistory:
        """``cnc_rdalmhistry``: up to ``depth`` (clamped to 1..250) most recent entries,
        newest first. A negative count gives no entries and ``ew`` set; it never raises for
        the content of the answer."""
        depth = min(max(int(depth), 1), MAX_HISTORY_DEPTH)
        payload = _RDALMHISTRY.request.encode(AlarmHistoryRequest(depth))
        result: AlarmHistory = await self._call(_RDALMHISTRY, payload, timeout)
        return result

    # -- unlock --------------------------------------------------------------------------
    async def unlock(self, password: str | bytes, *, timeout: float | None = None) -> None:
        """``cnc_wrunlockparam``: unlock parameter writes on this connection.

        On success the password is kept and sent again after every reconnect. A refused
        password raises :class:`AccessDeniedError` (and the connection is locked).
        """
        payload = _UNLOCK.request.encode(Password.from_text(password))
        await self._call(_UNLOCK, payload, timeout)
        self._password = password

    # -- VersaMax ------------------------------------------------------------------------
    async def _config_chunk(
        self, rack: int, slot: int, offset: int, deadline: float | None
    ) -> bytes:
        request = VersaMaxRequest(rack, MAX_CONFIG_CHUNK, slot, offset)
        reply: VersaMaxReply = await self._request(
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


def _ew_not_ok(raw: bytes) -> bool:
    """True for an answer that is not a success (an EW code, or too short for one)."""
    return len(raw) < 2 or raw[0] != 0 or raw[1] != 0


async def _all_or_first_error(coros: Sequence[Any]) -> list[Any]:
    """Run ``coros`` concurrently; on the first failure cancel the rest and raise it."""
    loop = asyncio.get_running_loop()
    tasks = [loop.create_task(c) for c in coros]
    try:
        await asyncio.wait(tasks, return_when=asyncio.FIRST_EXCEPTION)
    finally:
        unfinished = [t for t in tasks if not t.done()]
        for t in unfinished:
            t.cancel()
        if unfinished:
            await asyncio.wait(unfinished)
        # Retrieve every failure (also when this call is being cancelled), so that none is
        # reported as never retrieved; the first, in order, is raised.
        failures = [t.exception() for t in tasks if not t.cancelled()]
    first = next((e for e in failures if e is not None), None)
    if first is not None:
        raise first
    return [t.result() for t in tasks]


class SimControl:
    """The simulator control commands (0x0E01..0x0E05), as ``client.sim``.

    A real CNC, or a server with control disabled, answers them with ``EW_FUNC``.
    """

    __slots__ = ("_client",)

    def __init__(self, client: FocasClient) -> None:
        self._client = client

    async def set_panel(
        self,
        mode: AutMode | str | int,
        *,
        pwe: bool = False,
        emergency: bool = False,
        timeout: float | None = None,
    ) -> None:
        """Set the operator panel: ``mode`` (an ``aut`` value or name: ``"MDI"``, ``AutMode.MEM``,
        ``3``...), parameter write enable and emergency stop (all three are set)."""
        aut = AutMode.parse(mode)
        payload = _SET_PANEL.request.encode(SetPanel(int(aut), int(pwe), int(emergency)))
        await self._client._call(_SET_PANEL, payload, timeout)

    async def raise_alarm(
        self,
        alm_type: int,
        alm_no: int,
        msg: str = "",
        *,
        axis_no: int = 0,
        timeout: float | None = None,
    ) -> None:
        """Raise an alarm (a no-op when the same ``(axis_no, alm_type, alm_no)`` is active)."""
        try:
            raw = msg.encode("ascii")
        except UnicodeEncodeError:
            raise ValueError(f"alarm message must be ASCII: {msg!r}") from None
        payload = _RAISE_ALARM.request.encode(RaiseAlarm(axis_no, alm_type, alm_no, raw))
        await self._client._call(_RAISE_ALARM, payload, timeout)

    async def clear_alarms(
        self, alm_type: int = -1, alm_no: int = -1, *, timeout: float | None = None
    ) -> None:
        """Clear the matching active alarms (-1 matches any); the history is kept."""
        payload = _CLEAR_ALARMS.request.encode(ClearAlarms(alm_type, alm_no))
        await self._client._call(_CLEAR_ALARMS, payload, timeout)

    async def set_pmc(
        self, area: AreaLike, start: int, data: bytes, *, timeout: float | None = None
    ) -> None:
        """Write PMC bytes ignoring write protection (to drive X and F inputs); chunked like
        :meth:`FocasClient.write_pmc`."""
        client = self._client
        await client._write_pmc_range(_SET_PMC, area, start, data, client._deadline(timeout))

    async def inject_fault(
        self,
        kind: FaultKind | int,
        *,
        count: int = 1,
        arg: int = 0,
        scope: FaultScope | int = FaultScope.CONNECTION,
        timeout: float | None = None,
    ) -> None:
        """Make the next ``count`` answers misbehave (see :class:`FaultKind`)."""
        payload = _INJECT_FAULT.request.encode(InjectFault(int(kind), int(scope), count, arg))
        await self._client._call(_INJECT_FAULT, payload, timeout)
