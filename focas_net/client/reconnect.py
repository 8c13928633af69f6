"""The link of a client to one CNC: connecting, reconnecting, unlocking, and the request path.

:class:`Link` holds the one :class:`Connection` of a :class:`~focas_net.client.FocasClient`
(which is a :class:`Link` with the typed FOCAS calls on top) and everything that outlives it:

* the :class:`ClientState` machine (``DISCONNECTED``, ``CONNECTED``, ``RECONNECTING``,
  ``CLOSED``) and the state callbacks;
* the :class:`ReconnectPolicy` and its backoff, run by one reconnect task per loss (not after
  a protocol violation: a peer that is not a FOCAS server is not connected to again);
* the password: sent with ``cnc_wrunlockparam`` after every connect, and before the one retry
  of a call answered ``EW_PASSWD``;
* :meth:`Link._request`, the one path every call takes (connect or wait for the reconnect,
  send, decode, EW check, unlock and retry, send again on the next connection what never
  left), and the rules the batched PMC chunks share with it.

The wire protocol is ``docs/protocol.md``; the client's behaviour ``docs/client.md``.
"""

from __future__ import annotations

import asyncio
import enum
import logging
import random
import ssl as _ssl
import time
from collections.abc import Callable
from dataclasses import dataclass
from types import TracebackType
from typing import Any, Final, Self

from focas_net.errors import (
    EW,
    CncError,
    FocasConnectionError,
    FocasTimeoutError,
    PayloadError,
    ProtocolError,
)

from ..protocol import COMMANDS, CommandSpec, EwReply, Password
from ..protocol import Command as C
from .connection import (
    MAX_IN_FLIGHT,
    Connection,
    NotSentError,
    _address_text,
    _Pending,
    open_connection,
)

__all__ = ["ClientState", "ReconnectPolicy"]

# The client's documented logger (docs/client.md): state changes, losses and reconnects.
logger = logging.getLogger("focas_net.client.client")

_UNLOCK: Final = COMMANDS[C.WRUNLOCKPARAM]
#: What :meth:`Link._answer` gives for an ``EW_PASSWD`` answer to unlock and send again.
_UNLOCK_AND_RETRY: Final = object()
_CLOSE_GRACE: Final = 2.0


def _clock_of(loop: asyncio.AbstractEventLoop) -> Callable[[], float]:
    """``loop.time`` itself, or the clock it reads when that is the stock one (asyncio's
    ``BaseEventLoop.time`` is a Python method around ``time.monotonic``: one call less per
    deadline). A loop whose clock is its own (uvloop's, a test's) is asked every time."""
    if getattr(loop.time, "__func__", None) is asyncio.BaseEventLoop.time:
        return time.monotonic
    return loop.time


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


class _Lifecycle:
    """What both clients' lifecycles share: the address, the reconnect policy, the
    :class:`ClientState` with its callbacks, and ``async with`` (``connect`` ... ``aclose``).
    A subclass sets ``_logger`` (state changes are logged there) and implements ``connect`` and
    ``aclose``."""

    _logger: logging.Logger = logger

    def __init__(
        self,
        host: str,
        port: int,
        reconnect: bool | ReconnectPolicy,
        on_state_change: StateCallback | None,
    ) -> None:
        self.host = host
        self.port = port
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
        self._loop: asyncio.AbstractEventLoop | None = None
        self._clock: Callable[[], float] | None = None  # the loop's clock, once connected
        #: Set while a call need not wait: connected, or no reconnect under way.
        self._ready: asyncio.Event | None = None
        self._reconnect_task: asyncio.Task[None] | None = None
        # Backoff step of the next reconnect attempt (reset by a connection that stayed up
        # ``stable_after`` seconds) and when the current connection was installed.
        self._backoff = 0
        self._up_since = 0.0

    def __repr__(self) -> str:
        return f"<{type(self).__name__} {self.host}:{self.port} {self._state.value}>"

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

    def _bind_loop(self) -> None:
        """Serve the running loop from now on: calls and deadlines use it and its clock."""
        self._loop = asyncio.get_running_loop()
        self._clock = _clock_of(self._loop)

    def _set_state(self, state: ClientState) -> None:
        if state is self._state:
            return
        self._state = state
        self._logger.info("%s:%s %s", self.host, self.port, state.value)
        for callback in tuple(self._callbacks):
            try:
                callback(state)
            except Exception:
                self._logger.exception("state callback %r failed", callback)

    # -- the reconnect, shared by both transports ----------------------------------------
    def _reconnecting(self, exc: BaseException | None) -> None:
        """The link was lost and the policy reconnects: RECONNECTING, calls wait on
        ``_ready``, and one reconnect task (the backoff starts again after a stable link)."""
        policy = self._policy
        assert policy is not None and self._ready is not None and self._loop is not None
        self._logger.warning(
            "connection to %s:%s lost (%s); reconnecting", self.host, self.port, exc or "closed"
        )
        if self._loop.time() - self._up_since >= policy.stable_after:
            self._backoff = 0  # a stable connection: the backoff starts again from the start
        self._ready.clear()
        self._set_state(ClientState.RECONNECTING)
        if self._reconnect_task is None or self._reconnect_task.done():
            self._reconnect_task = self._loop.create_task(
                self._reconnect(policy), name=f"focas-reconnect {self.host}:{self.port}"
            )

    async def _reconnect(self, policy: ReconnectPolicy) -> None:
        """Attempts after the policy's delays until one ends it (:meth:`_reconnect_attempt`)
        or the policy gives up (DISCONNECTED); then calls waiting on ``_ready`` go on."""
        attempt = 0
        try:
            while policy.max_attempts is None or attempt < policy.max_attempts:
                await asyncio.sleep(policy.delay(self._backoff))
                self._backoff += 1
                attempt += 1
                if await self._reconnect_attempt(attempt):
                    return
            self._logger.warning(
                "giving up reconnecting to %s:%s after %d attempts", self.host, self.port, attempt
            )
            self._set_state(ClientState.DISCONNECTED)
        finally:
            if self._state is ClientState.RECONNECTING and not self._linked():
                self._set_state(ClientState.DISCONNECTED)  # ended without a connection
            self._reconnect_ended()
            if self._ready is not None:
                self._ready.set()

    async def _reconnect_attempt(self, attempt: int) -> bool:
        """One attempt: True when it ended the reconnect (a link installed, or a reason not
        to go on), False to try again."""
        raise NotImplementedError

    def _linked(self) -> bool:
        """Whether a link is installed."""
        raise NotImplementedError

    def _reconnect_ended(self) -> None:
        """What a transport does when a reconnect ends, before waiting calls go on."""

    async def connect(self) -> None:
        raise NotImplementedError

    async def aclose(self) -> None:
        raise NotImplementedError

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


class Link(_Lifecycle):
    """The connection of a client, its state machine, its reconnects and its request path.

    The arguments are those of :class:`~focas_net.client.FocasClient`, which is a
    :class:`Link` with the FOCAS calls on top and documents them.
    """

    def __init__(
        self,
        host: str,
        port: int,
        *,
        timeout: float | None,
        max_in_flight: int,
        password: str | bytes | None,
        reconnect: bool | ReconnectPolicy,
        max_frame: int,
        ssl: _ssl.SSLContext | None,
        server_hostname: str | None,
        on_state_change: StateCallback | None,
    ) -> None:
        if not 1 <= max_in_flight <= MAX_IN_FLIGHT:
            raise ValueError(
                f"max_in_flight must be within 1..{MAX_IN_FLIGHT}, got {max_in_flight}"
            )
        if timeout is not None and timeout <= 0:
            raise ValueError(f"timeout must be positive, got {timeout}")
        super().__init__(host, port, reconnect, on_state_change)
        self.timeout = timeout
        self.max_in_flight = max_in_flight
        self.max_frame = max_frame
        self._ssl = ssl
        self._server_hostname = server_hostname
        self._password = password
        self._conn: Connection | None = None
        # Why the client stopped without reconnecting, when the peer broke the protocol.
        self._violation: ProtocolError | None = None

    # -- lifecycle -----------------------------------------------------------------------
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
        self._bind_loop()
        if self._ready is None:
            self._ready = asyncio.Event()
        conn = await self._open(self._deadline(None), strict=True)
        self._violation = None
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
        """A new connection, unlocked when a password is known. A refused password raises
        with ``strict`` (the first connect) and is logged otherwise (a reconnect)."""
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

    # -- the state machine and the reconnect ----------------------------------------------
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
        if conn.violation is not None:
            # Not a lost connection: the peer is not a FOCAS server, and connecting again
            # would meet the same peer. The reconnect policy does not apply.
            logger.warning("%s; not reconnecting", conn.violation)
            self._violation = conn.violation
            self._set_state(ClientState.DISCONNECTED)
            return
        if self._policy is None:
            logger.warning("connection to %s:%s lost: %s", self.host, self.port, exc or "closed")
            self._set_state(ClientState.DISCONNECTED)
            return
        self._reconnecting(exc)

    async def _reconnect_attempt(self, attempt: int) -> bool:
        try:
            conn = await self._open(self._deadline(None), strict=False)
        except (FocasConnectionError, FocasTimeoutError) as exc:
            logger.debug("reconnect attempt %d to %s:%s: %s", attempt, *self._addr, exc)
            return False
        except ProtocolError as exc:
            if isinstance(exc, PayloadError):  # an unlock answer that does not decode
                logger.warning("reconnect attempt %d to %s:%s: %r", attempt, *self._addr, exc)
                return False
            logger.warning("%s; not reconnecting", exc)  # not a FOCAS server
            self._violation = exc
            self._set_state(ClientState.DISCONNECTED)
            return True
        except Exception as exc:  # e.g. an unlock answer that does not decode
            logger.warning("reconnect attempt %d to %s:%s: %r", attempt, *self._addr, exc)
            return False
        if conn.closed:
            return False
        self._install(conn)
        return True

    def _linked(self) -> bool:
        return self._conn is not None

    async def _connection(self, deadline: float | None) -> Connection:
        """The live connection, waiting (until ``deadline``) while reconnecting.

        Raises :class:`FocasConnectionError` when there is none to wait for (not connected
        and no reconnect under way, or closed) or when ``deadline`` passes first;
        :class:`ProtocolError` when the connection ended because the peer broke the protocol.
        """
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
                if self._violation is not None:
                    raise ProtocolError(str(self._violation))
                raise FocasConnectionError(f"not connected to {_address_text(*self._addr)}")
            try:
                async with asyncio.timeout_at(deadline):
                    await self._ready.wait()
            except TimeoutError:
                raise FocasConnectionError(
                    f"still reconnecting to {_address_text(*self._addr)} when the call timed out"
                ) from None

    # -- the request path ----------------------------------------------------------------
    def _deadline(self, timeout: float | None) -> float | None:
        """The deadline (``loop.time()`` units) of a call given ``timeout=``, or None."""
        t = self.timeout if timeout is None else timeout
        if t is None:
            return None
        clock = self._clock
        if clock is None:
            clock = asyncio.get_running_loop().time
        return clock() + t

    async def _request(self, spec: CommandSpec, payload: bytes, call_timeout: float | None) -> Any:
        """Send one request and return its decoded answer: the one path of every call of one
        request. Its deadline is ``call_timeout`` (the call's ``timeout=``; None: the
        client's) from now, as :meth:`_deadline` gives it, worked out here: one call less per
        request. A call of several requests shares one deadline: :meth:`_request_at`.

        * The live connection is used at once; while reconnecting the call waits for the next
          one (until the deadline); with no connection to wait for it raises
          :class:`FocasConnectionError`.
        * A request that never left (:class:`NotSentError`) goes out again on the next
          connection when a reconnect policy is set, and is raised otherwise.
        * An answer carrying an EW code raises :class:`CncError`, except ``EW_PASSWD`` when a
          password is known: the password is sent (:meth:`_unlock_for_retry`) and the call
          is sent once more; that retry's answer is final.

        Every other failure (a timeout, a connection lost after the request left, an answer
        that does not decode) is raised as it is.
        """
        t = self.timeout if call_timeout is None else call_timeout
        if t is None:
            deadline = None
        else:
            clock = self._clock
            deadline = (asyncio.get_running_loop().time if clock is None else clock)() + t
        conn = self._conn
        if conn is not None:
            # The usual call, a slot free on the live connection: sent at once, its answer
            # decoded here. Anything else (no connection, closed, no slot, not sent, an EW
            # code) is the general path's below, which starts over from the state it finds.
            try:
                entry = conn.try_send(spec.command, payload, deadline)
            except NotSentError:
                entry = None
            if entry is not None:
                try:
                    raw = await entry[0]
                except NotSentError:
                    conn.finish(entry)
                    if self._policy is None:
                        raise
                    # never reached the peer: sent again on the next connection
                    return await self._request_at(spec, payload, deadline)
                except BaseException:
                    conn.finish(entry)  # a timeout, a cancellation, a failure
                    raise
                value = spec.response.decode_bytes(raw)  # the connection's are bytes
                if type(value) is not EwReply:
                    return value
                self._raise_unless_unlock(spec, value.ew, False)
                await self._unlock_for_retry(conn, deadline)
                return await self._request_at(spec, payload, deadline, True)
        return await self._request_at(spec, payload, deadline)

    async def _request_at(
        self, spec: CommandSpec, payload: bytes, deadline: float | None, retried: bool = False
    ) -> Any:
        """:meth:`_request` by ``deadline`` (in the loop's clock; None: none): the path of a
        call of several requests, which share one deadline, and the general path of
        :meth:`_request` (``retried``: the answer to come is the one to a retry after an
        unlock)."""
        while True:
            conn = self._conn
            if conn is None or conn.closed:
                conn = await self._connection(deadline)
            try:
                # Connection.request without its coroutine when a slot is free (the usual
                # case): one coroutine less per call.
                entry = conn.try_send(spec.command, payload, deadline)
                if entry is None:
                    raw = await conn.request(spec.command, payload, deadline)
                else:
                    try:
                        raw = await entry[0]
                    finally:
                        conn.finish(entry)
            except NotSentError:
                if self._policy is None:
                    raise
                continue  # never reached the peer: safe to send on the next connection
            value = self._answer(spec, raw, retried)
            if value is not _UNLOCK_AND_RETRY:
                return value
            await self._unlock_for_retry(conn, deadline)
            retried = True

    def _start(
        self, spec: CommandSpec, payload: bytes, deadline: float | None
    ) -> tuple[Connection, _Pending] | None:
        """The first half of :meth:`_request` for a caller awaiting many answers in one task:
        the request sent at once on the live connection, or None (nothing sent) when it
        cannot be: not connected, reconnecting, closed, or no request slot free. The caller
        awaits the entry's future, calls ``Connection.finish(entry)`` and hands the answer
        to :meth:`_answer`."""
        conn = self._conn
        if conn is None or conn.closed:
            return None
        try:
            entry = conn.try_send(spec.command, payload, deadline)
        except NotSentError:
            return None
        return None if entry is None else (conn, entry)

    def _answer(self, spec: CommandSpec, raw: bytes, retried: bool = False) -> Any:
        """The decoded answer of a call of ``spec``: its value, :class:`CncError` raised for
        an EW code, or ``_UNLOCK_AND_RETRY`` for an ``EW_PASSWD`` answer to unlock and send
        once more (never after ``retried``, the answer to that retry). The one rule of
        :meth:`_request` and of those awaiting many answers in one task."""
        value = spec.response.decode(raw)
        if type(value) is not EwReply:
            return value
        self._raise_unless_unlock(spec, value.ew, retried)
        return _UNLOCK_AND_RETRY

    def _raise_unless_unlock(self, spec: CommandSpec, ew: int, retried: bool) -> None:
        """Raise :class:`CncError` for a call of ``spec`` answered ``ew``, unless it is to be
        unlocked and sent once more (never after ``retried``)."""
        if retried or not self._retries_after_unlock(spec, ew):
            raise CncError.from_ew(ew, spec.focas_name)

    def _retries_after_unlock(self, spec: CommandSpec, ew: int) -> bool:
        """Whether a call of ``spec`` answered ``ew`` is unlocked and sent once more."""
        return ew == EW.PASSWD and self._password is not None and spec is not _UNLOCK

    async def _unlock_for_retry(self, conn: Connection, deadline: float | None) -> None:
        """Send the password on ``conn`` before retrying calls answered ``EW_PASSWD``.

        If the connection is lost around the unlock and a reconnect policy is set, this
        returns and the retry waits for the next connection instead (which the reconnect
        unlocks first). Every other failure, a refused password among them, is raised.
        """
        password = self._password
        assert password is not None
        try:
            await self._unlock_on(conn, password, deadline)
        except FocasConnectionError:
            if self._policy is None:
                raise

    async def _unlock_on(
        self, conn: Connection, password: str | bytes, deadline: float | None
    ) -> None:
        """``cnc_wrunlockparam`` on ``conn`` itself: no wait, no retry, EW -> CncError."""
        raw = await conn.request(
            _UNLOCK.command, _UNLOCK.request.encode(Password.from_text(password)), deadline
        )
        value = _UNLOCK.response.decode(raw)
        if type(value) is EwReply:
            raise CncError.from_ew(value.ew, _UNLOCK.focas_name)
