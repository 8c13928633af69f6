"""The packed client's link to one CNC: connecting, reconnecting, unlocking, the request path.

:class:`Link` holds the one :class:`Connection` of a :class:`~focas_net.client.FocasClient`
(which is a :class:`Link` with the typed FOCAS calls on top) and what outlives it: its
:class:`~focas_net.client._lifecycle.Lifecycle` (state, reconnect, deadlines), the password
(sent with ``cnc_wrunlockparam`` after every connect, and before the one retry of a call
answered ``EW_PASSWD``), and :meth:`Link._request`, the one path every call takes (connect or
wait for the reconnect, send, decode, EW check, unlock and retry, send again on the next
connection what never left). A reconnect is not tried after a protocol violation: a peer that
is not a FOCAS server is not connected to again.

The wire protocol is ``docs/protocol.md``; the client's behaviour ``docs/client.md``.
"""

from __future__ import annotations

import asyncio
import logging
import ssl as _ssl
from typing import Any, Final

from focas_net._typed import os_reason
from focas_net.errors import (
    EW,
    CncError,
    FocasConnectionError,
    FocasError,
    FocasTimeoutError,
    PayloadError,
    ProtocolError,
)

from ..protocol import (
    COMMANDS,
    CommandSpec,
    EwReply,
    FaultScope,
    FaultsRequest,
    Password,
    PathSelection,
)
from ..protocol import Command as C
from ._composite import CompositeCalls
from ._failures import (
    code_reason,
    command_text,
    echo_error,
    path_refusal,
    undecodable_error,
)
from ._values import an_int, check_int
from .connection import MAX_IN_FLIGHT, Connection, NotSentError, _Pending, open_connection
from .reconnect import ClientState, ReconnectPolicy, StateCallback

__all__ = ["Link"]

# The client's documented logger (docs/client.md): state changes, losses and reconnects.
logger = logging.getLogger("focas_net.client.client")

_UNLOCK: Final = COMMANDS[C.WRUNLOCKPARAM]
_GETPATH: Final = COMMANDS[C.GETPATH]
#: The request a new connection of a reconnect must have answered before the link counts as
#: back: the listing of that connection's own faults, a control command no fault armed on the
#: server replaces or counts (the user's next request keeps the fault meant for it); an EW
#: code is an answer too (``serve --no-control``).
_ANSWERS: Final = COMMANDS[C.SIM_LIST_FAULTS]
_ANSWERS_PAYLOAD: Final = _ANSWERS.request.encode(FaultsRequest(int(FaultScope.CONNECTION)))
#: What :meth:`Link._answer` gives for an ``EW_PASSWD`` answer to unlock and send again.
UNLOCK_AND_RETRY: Final = object()
_CLOSE_GRACE: Final = 2.0


class Link(CompositeCalls):
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
        path: int = 1,
    ) -> None:
        an_int("max_in_flight", max_in_flight)  # a TypeError, naming it (its range: below)
        check_int("max_frame", max_frame, 4, 0xFFFF_FFFF)
        if ssl is not None and not isinstance(ssl, _ssl.SSLContext):
            raise TypeError(f"ssl must be an ssl.SSLContext or None, got {ssl!r}")
        if server_hostname is not None and not isinstance(server_hostname, str):
            raise TypeError(f"server_hostname must be a str or None, got {server_hostname!r}")
        if server_hostname is not None and ssl is None:
            raise ValueError(
                f"server_hostname={server_hostname!r} is the name a TLS certificate is checked "
                "against, without ssl there is none: give ssl= too, or leave it out"
            )
        check_int("max_in_flight", max_in_flight, 1, MAX_IN_FLIGHT)
        super().__init__(
            host,
            port,
            timeout=timeout,
            reconnect=reconnect,
            on_state_change=on_state_change,
            path=path,
        )
        self._init_composite()
        self.max_in_flight = max_in_flight
        self.max_frame = max_frame
        self._ssl = ssl
        self._server_hostname = server_hostname
        self._password = password
        self._conn: Connection | None = None
        # Why the client stopped without reconnecting, when the peer broke the protocol.
        self._violation: ProtocolError | None = None

    @property
    def in_flight(self) -> int:
        """Calls waiting for an answer on the live connection (0 when there is none)."""
        conn = self._conn
        return 0 if conn is None else conn.in_flight

    @property
    def connection(self) -> Connection | None:
        """The client's :class:`~focas_net.client.connection.Connection` (its ``closed``
        is True once it is going away), None while there is none (not connected,
        reconnecting, closed). For looking at (``in_flight``, ``abandoned``,
        ``slots_taken``...): calls go through the client."""
        return self._conn

    # -- lifecycle -----------------------------------------------------------------------
    async def connect(self) -> None:
        """Open the connection (and unlock when a password was given).

        Raises :class:`FocasConnectionError` (or :class:`FocasTimeoutError`) when the server
        cannot be reached, :class:`AccessDeniedError` when the password is refused. The
        first connection is not retried; the reconnect policy applies to later losses.
        """
        if self._state is ClientState.CLOSED:
            raise self._closed()
        if self._conn is not None and not self._conn.closed:
            return
        self._bind_loop()
        try:
            conn = await self._open(self._deadline(None), strict=True)
        except FocasError as exc:
            self._connect_failed(exc)
            raise
        self._violation = None
        if self.state is ClientState.CLOSED:  # closed while connecting
            conn.close()
            await conn.wait_closed()
            raise self._closed()
        current = self._conn
        if current is not None and not current.closed:  # a concurrent connect() won
            conn.close()
            await conn.wait_closed()
            return
        self._install(conn)

    async def aclose(self) -> None:
        """Close the connection; pending calls fail with :class:`FocasConnectionError`."""
        await self._stop_reconnecting()
        conn, self._conn = self._conn, None
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
                self._logger.warning("%s: unlock after reconnect refused: %s", self.address, exc)
            except BaseException:
                conn.close()
                raise
        return conn

    # -- the state machine and the reconnect ----------------------------------------------
    def _install(self, conn: Connection) -> None:
        self._conn = conn
        self._linked_now()

    def _on_lost(self, conn: Connection, exc: BaseException | None) -> None:
        if conn is not self._conn:
            return
        self._conn = None
        if self._state is ClientState.CLOSED:
            return
        if conn.violation is not None:
            # Not a lost connection: the peer is not a FOCAS server, and connecting again
            # would meet the same peer. The reconnect policy does not apply.
            self._logger.warning("%s; not reconnecting", conn.violation)
            self._violation = conn.violation
            self._set_state(ClientState.DISCONNECTED)
            return
        if self._policy is None:
            # (the words its calls get, as the FOCAS/2 client logs them)
            self._lost_why = conn.end or exc
            self._logger.warning(
                "connection to %s lost: %s", self.address, self._lost_why or "closed"
            )
            self._set_state(ClientState.DISCONNECTED)
            return
        self._reconnecting(conn.end or exc)

    async def _answered_on(self, conn: Connection, deadline: float | None) -> None:
        """A request answered on ``conn`` (:data:`_ANSWERS`), as the open of FOCAS/2 is
        answered before its client counts as connected: a peer that accepts the TCP connect
        and then says nothing (an HTTP server) or no FOCAS frame is no link. ``conn`` is
        closed when it fails."""
        try:
            raw = await conn.request(_ANSWERS.command, _ANSWERS_PAYLOAD, deadline)
            self._decoded(_ANSWERS, raw)
        except BaseException:
            conn.close()
            raise

    async def _reconnect_attempt(self, attempt: int) -> bool:
        try:
            conn = await self._open(self._deadline(None), strict=False)
            if self._password is None:  # (an unlock was answered already)
                await self._answered_on(conn, self._deadline(None))
        except (FocasConnectionError, FocasTimeoutError) as exc:
            logger.debug("reconnect attempt %d to %s: %s", attempt, self.address, exc)
            self._attempt_error = exc
            return False
        except ProtocolError as exc:
            if isinstance(exc, PayloadError):  # an unlock answer that does not decode
                self._logger.warning(
                    "reconnect attempt %d to %s: %s", attempt, self.address, os_reason(exc)
                )
                return False
            self._logger.warning("%s; not reconnecting", exc)  # not a FOCAS server
            self._violation = exc
            self._set_state(ClientState.DISCONNECTED)
            return True
        except Exception as exc:  # e.g. an unlock answer that does not decode
            self._logger.warning(
                "reconnect attempt %d to %s: %s", attempt, self.address, os_reason(exc)
            )
            return False
        if conn.closed:
            return False
        self._install(conn)
        return True

    def _linked(self) -> bool:
        conn = self._conn
        if conn is not None and conn.closed:
            self._on_lost(conn, None)  # closing, its connection_lost not run yet
            conn = self._conn
        return conn is not None

    def _nothing_to_wait_for(self) -> Exception:
        if self._violation is not None:
            return ProtocolError(str(self._violation))
        return super()._nothing_to_wait_for()

    async def _connection(self, deadline: float | None) -> Connection:
        """The live connection, waiting (until ``deadline``) while reconnecting.

        Raises :class:`FocasConnectionError` when there is none to wait for (not connected
        and no reconnect under way, or closed) or when ``deadline`` passes first;
        :class:`ProtocolError` when the connection ended because the peer broke the protocol.
        """
        conn = self._conn
        if conn is None or conn.closed:
            await self._wait_linked(deadline)
            conn = self._conn
            assert conn is not None
        return conn

    # -- the request path ----------------------------------------------------------------
    async def _request(
        self, spec: CommandSpec, payload: bytes, call_timeout: float | None, path: int = 0
    ) -> Any:
        """Send one request and return its decoded answer: the one path of every call of one
        request. Its deadline is ``call_timeout`` (the call's ``timeout=``; None: the
        client's) from now. A call of several requests shares one deadline:
        :meth:`_request_at`. ``path`` is a per-path request's checked path (0: a request of
        no path): when the connection's selection is another at the moment the request
        leaves, a ``cnc_setpath`` leaves right before it
        (:meth:`~focas_net.client.connection.Connection.select_path`).

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
        deadline = self._deadline(call_timeout)
        conn = self._conn
        if conn is not None:
            # The usual call, a slot free on the live connection: sent at once, its answer
            # decoded here. Anything else (no connection, closed, no slot, not sent, an EW
            # code) is the general path's below, which starts over from the state it finds.
            try:
                if path and path != conn.path:
                    conn.select_path(path, deadline)
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
                    return await self._request_at(spec, payload, deadline, path=path)
                except BaseException:
                    conn.finish(entry)  # a timeout, a cancellation, a failure
                    raise
                try:
                    value = spec.response.decode_bytes(raw)  # the connection's are bytes
                except PayloadError as exc:
                    raise self._echoed(spec, raw, payload) or undecodable_error(
                        self.address, command_text(spec.command), exc
                    ) from exc
                if type(value) is not EwReply:
                    return value
                try:
                    self._raise_unless_unlock(spec, value.ew, False, raw, payload)
                except CncError as exc:
                    raise await self._path_refusal(exc, spec, path, deadline) from None
                await self._unlock_for_retry(conn, deadline)
                return await self._request_at(spec, payload, deadline, True, path)
        return await self._request_at(spec, payload, deadline, path=path)

    async def _request_at(
        self,
        spec: CommandSpec,
        payload: bytes,
        deadline: float | None,
        retried: bool = False,
        path: int = 0,
    ) -> Any:
        """:meth:`_request` by ``deadline`` (in the loop's clock; None: none): the path of a
        call of several requests, which share one deadline, and the general path of
        :meth:`_request` (``retried``: the answer to come is the one to a retry after an
        unlock; ``path``: as :meth:`_request`'s)."""
        while True:
            conn = self._conn
            if conn is None or conn.closed:
                conn = await self._connection(deadline)
            try:
                # Connection.request without its coroutine when a slot is free (the usual
                # case): one coroutine less per call.
                if path and path != conn.path:
                    conn.select_path(path, deadline)
                entry = conn.try_send(spec.command, payload, deadline)
                if entry is None:
                    raw = await conn.request(spec.command, payload, deadline, path)
                else:
                    try:
                        raw = await entry[0]
                    finally:
                        conn.finish(entry)
            except NotSentError:
                if self._policy is None:
                    raise
                continue  # never reached the peer: safe to send on the next connection
            try:
                value = self._answer(spec, raw, retried, payload)
            except CncError as exc:
                raise await self._path_refusal(exc, spec, path, deadline) from None
            if value is not UNLOCK_AND_RETRY:
                return value
            await self._unlock_for_retry(conn, deadline)
            retried = True

    async def _path_refusal(
        self, refused: CncError, spec: CommandSpec, path: int, deadline: float | None
    ) -> CncError:
        """``refused`` (a call of ``spec`` for ``path``; 0: of no path), or for EW_PATH of a
        path beyond the CNC's the same refusal in the native client's words (``the CNC has no
        path 3: it has path 1 only``): a packed answer carries the code only, so the count is read
        after the refusal (``cnc_getpath``), within the call's deadline."""
        if refused.ew != EW.PATH or not path:
            return refused
        try:
            paths: PathSelection = await self._request_at(_GETPATH, b"", deadline)
        except FocasError:
            return refused
        if not 0 < paths.max < path:
            return refused
        return path_refusal(spec.function, path, paths.max)

    def _start(
        self, spec: CommandSpec, payload: bytes, deadline: float | None, path: int = 0
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
            if path and path != conn.path:
                conn.select_path(path, deadline)
            entry = conn.try_send(spec.command, payload, deadline)
        except NotSentError:
            return None
        return None if entry is None else (conn, entry)

    def _answer(
        self, spec: CommandSpec, raw: bytes, retried: bool = False, sent: bytes | None = None
    ) -> Any:
        """The decoded answer of a call of ``spec``: its value, :class:`CncError` raised for
        an EW code, or ``UNLOCK_AND_RETRY`` for an ``EW_PASSWD`` answer to unlock and send
        once more (never after ``retried``, the answer to that retry). The one rule of
        :meth:`_request` and of those awaiting many answers in one task. ``sent``: the
        request's payload, when known, to tell an echo server (:func:`echo_error`)."""
        value = self._decoded(spec, raw, sent)
        if type(value) is not EwReply:
            return value
        self._raise_unless_unlock(spec, value.ew, retried, raw, sent)
        return UNLOCK_AND_RETRY

    def _decoded(self, spec: CommandSpec, raw: bytes, sent: bytes | None = None) -> Any:
        """``raw`` decoded as an answer of ``spec``; an answer that does not decode is the
        peer's :class:`PayloadError`, naming it and the call (a :class:`ProtocolError` when
        it is the request ``sent`` back)."""
        try:
            return spec.response.decode(raw)
        except PayloadError as exc:
            raise self._echoed(spec, raw, sent) or undecodable_error(
                self.address, command_text(spec.command), exc
            ) from exc

    def _echoed(self, spec: CommandSpec, raw: bytes, sent: bytes | None) -> ProtocolError | None:
        """The error of a peer that answered ``spec``'s request with its own payload
        ``sent`` (None: not known, or not an echo)."""
        return None if sent is None else echo_error(self.address, spec.command, raw, sent)

    def _raise_unless_unlock(
        self,
        spec: CommandSpec,
        ew: int,
        retried: bool,
        raw: bytes = b"",
        sent: bytes | None = None,
    ) -> None:
        """Raise :class:`CncError` for a call of ``spec`` answered ``ew``, unless it is to be
        unlocked and sent once more (never after ``retried``); :class:`ProtocolError` when
        the answer ``raw`` is the request's payload ``sent`` back (an echo server)."""
        echoed = self._echoed(spec, raw, sent)
        if echoed is not None:
            raise echoed
        if retried or not self._retries_after_unlock(spec, ew):
            why = code_reason(spec.command, ew)  # (the code alone tells it)
            raise CncError.from_ew(ew, spec.function + (f": {why}" if why else ""))

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
        sent = _UNLOCK.request.encode(Password.from_text(password))
        raw = await conn.request(_UNLOCK.command, sent, deadline)
        value = self._decoded(_UNLOCK, raw, sent)
        if type(value) is EwReply:
            self._raise_unless_unlock(_UNLOCK, value.ew, True, raw, sent)
