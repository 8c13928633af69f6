"""What both clients' lifecycles share: :class:`Lifecycle`.

The address, the :class:`~focas_net.client.ClientState` with its callbacks, ``async with``
(``connect`` ... ``aclose``), the reconnect loop with its backoff (each transport gives only its
attempt), every call's deadline, and the wait for the connection while reconnecting. A
transport subclasses it with its link (the packed :class:`~focas_net.client._link.Link`, the
native :class:`~focas_net.client._native_link.NativeLink`).
"""

from __future__ import annotations

import asyncio
import logging
import time
from collections.abc import Callable
from types import TracebackType
from typing import Self

from focas_net._address import address_text, check_host, check_port
from focas_net._typed import os_reason
from focas_net.errors import FocasConnectionError

from ._values import check_path, check_timeout
from .reconnect import ClientState, ReconnectPolicy, StateCallback

__all__ = ["Lifecycle", "clock_of"]

logger = logging.getLogger("focas_net.client.client")


def clock_of(loop: asyncio.AbstractEventLoop) -> Callable[[], float]:
    """``loop.time`` itself, or the clock it reads when that is the stock one (asyncio's
    ``BaseEventLoop.time`` is a Python method around ``time.monotonic``: one call less per
    deadline). A loop whose clock is its own (uvloop's, a test's) is asked every time."""
    if getattr(loop.time, "__func__", None) is asyncio.BaseEventLoop.time:
        return time.monotonic
    return loop.time


def _callback(what: str, callback: object) -> StateCallback:
    """A state callback: anything callable; TypeError, naming ``what``, otherwise."""
    if not callable(callback):
        raise TypeError(f"{what} must be callable with the new ClientState, got {callback!r}")
    return callback


class Lifecycle:
    """The state, the reconnect and the deadlines of a client (see the module docstring).

    A subclass sets ``_logger`` (state changes are logged there) and implements ``connect``,
    ``aclose``, :meth:`_linked` and :meth:`_reconnect_attempt`.
    """

    _logger: logging.Logger = logger

    def __init__(
        self,
        host: str,
        port: int,
        *,
        timeout: float | None,
        reconnect: bool | ReconnectPolicy,
        on_state_change: StateCallback | None,
        path: int = 1,
    ) -> None:
        host = check_host(host)
        self._path = check_path(path)
        port = check_port(port)
        #: The default ``timeout`` of every call, seconds (None: none).
        self.timeout = check_timeout(timeout)
        self.host = host
        self.port = port
        if reconnect is True:
            self._policy: ReconnectPolicy | None = ReconnectPolicy()
        elif reconnect is False:
            self._policy = None
        elif isinstance(reconnect, ReconnectPolicy):
            self._policy = reconnect
        else:
            raise TypeError(f"reconnect must be a bool or a ReconnectPolicy, got {reconnect!r}")
        self._state = ClientState.DISCONNECTED
        self._callbacks: list[StateCallback] = []
        if on_state_change is not None:
            self._callbacks.append(_callback("on_state_change", on_state_change))
        self._loop: asyncio.AbstractEventLoop | None = None
        self._clock: Callable[[], float] | None = None  # the loop's clock, once connected
        #: Set while a call need not wait: connected, or no reconnect under way.
        self._ready: asyncio.Event | None = None
        self._reconnect_task: asyncio.Task[None] | None = None
        # Backoff step of the next reconnect attempt (reset by a connection that stayed up
        # ``stable_after`` seconds) and when the current connection was installed.
        self._backoff = 0
        self._up_since = 0.0
        #: whether a link was ever up (a client never connected closes without a word)
        self._opened = False
        #: a loss was told at WARNING: the return is told too (``reconnected to H:P``)
        self._told_lost = False
        #: Why the last reconnect attempt failed (None: none failed since the last link).
        self._attempt_error: BaseException | None = None
        #: Why the last link was lost (None: connected, or never lost), with or without a
        #: reconnect policy.
        self._lost_why: BaseException | None = None
        #: Why the last connect() failed (None: none failed since the last link).
        self._connect_error: BaseException | None = None

    def __repr__(self) -> str:
        return f"<{type(self).__name__} {self.address} {self._state.value}>"

    @property
    def address(self) -> str:
        """``host:port`` (an IPv6 host in brackets)."""
        return address_text(self.host, self.port)

    @property
    def state(self) -> ClientState:
        """The current :class:`ClientState`."""
        return self._state

    @property
    def connected(self) -> bool:
        return self._state is ClientState.CONNECTED

    @property
    def lost_reason(self) -> BaseException | None:
        """Why the connection was last lost (``connection closed by HOST:PORT``), from when it
        was until a connection is back; None while connected or before any loss."""
        return self._lost_why

    @property
    def reconnect_error(self) -> BaseException | None:
        """Why the last reconnect attempt failed, while the policy reconnects (a connection
        lost, then refused: the refusal); None before an attempt failed and once connected."""
        return self._attempt_error if self._state is ClientState.RECONNECTING else None

    @property
    def reconnect_policy(self) -> ReconnectPolicy | None:
        return self._policy

    def add_state_callback(self, callback: StateCallback) -> None:
        """Call ``callback(state)`` on every state change (exceptions are logged)."""
        self._callbacks.append(_callback("callback", callback))

    def remove_state_callback(self, callback: StateCallback) -> None:
        """Stop calling ``callback``: ValueError, naming it, when it was never added."""
        try:
            self._callbacks.remove(callback)
        except ValueError:
            raise ValueError(f"{callback!r} is not a state callback of this client") from None

    def _bind_loop(self) -> None:
        """Serve the running loop from now on: calls and deadlines use it and its clock."""
        self._loop = asyncio.get_running_loop()
        self._clock = clock_of(self._loop)
        if self._ready is None:
            self._ready = asyncio.Event()

    def _set_state(self, state: ClientState) -> None:
        if state is self._state:
            return
        self._state = state
        if state is not ClientState.CLOSED or self._opened:  # (never open: nothing closed)
            self._logger.info("%s %s", self.address, state.value)
        for callback in tuple(self._callbacks):
            try:
                callback(state)
            except Exception:
                self._logger.exception("state callback %r failed", callback)

    @property
    def path(self) -> int:
        """The path every per-path call reads or writes when it is given no ``path=`` (1..10;
        set it to change it, checked like a call's ``path=``)."""
        return self._path

    @path.setter
    def path(self, path: int) -> None:
        self._path = check_path(path)

    def _path_of(self, path: int | None) -> int:
        """The path of a call given ``path=`` (None: the client's :attr:`path`), checked in
        the caller's frame: :class:`TypeError` or :class:`ValueError` naming what was given."""
        return self._path if path is None else check_path(path)

    # -- deadlines and the wait for the link -------------------------------------------------
    def _deadline(self, timeout: float | None) -> float | None:
        """The deadline (the loop's clock) of a call given ``timeout=`` (None: the client's),
        or None for none; :class:`TypeError` or :class:`ValueError` for a ``timeout`` that is
        not a positive number."""
        t = self.timeout if timeout is None else check_timeout(timeout)
        if t is None:
            return None
        clock = self._clock
        if clock is None:
            clock = asyncio.get_running_loop().time
        return clock() + t

    def _linked(self) -> bool:
        """Whether a link is installed and open."""
        raise NotImplementedError

    def _nothing_to_wait_for(self) -> Exception:
        """What a call raises when there is no link and none coming: how to connect when the
        client never was, else why the link was lost and why the last reconnect attempt
        failed (each when known)."""
        text = f"not connected to {self.address}"
        if self._loop is None:
            return FocasConnectionError(f"{text}: call connect() first, or use `async with`")
        causes = [str(self._lost_why)] if self._lost_why is not None else []
        if self._attempt_error is not None:
            causes.append(f"the last reconnect attempt failed: {self._attempt_error}")
        if self._connect_error is not None:
            causes.append(f"connect() failed: {self._connect_error}")
        if causes:
            text += f" ({'; '.join(causes)})"
        err = FocasConnectionError(text)
        err.__cause__ = self._attempt_error or self._connect_error  # (what a caller may look into)
        return err

    def _closed(self) -> FocasConnectionError:
        """What a call or a connect() on a closed client raises."""
        return FocasConnectionError(
            f"not connected to {self.address}: the client is closed (a closed client does not "
            "connect again: make a new one)"
        )

    def _connect_failed(self, exc: BaseException) -> None:
        """connect() failed with ``exc``: a call made next tells it."""
        self._connect_error = exc

    async def _wait_linked(self, deadline: float | None) -> None:
        """Return once a link is open, waiting (until ``deadline``) while reconnecting.

        :raises FocasConnectionError: closed, not connected with no reconnect under way, or
            still reconnecting when ``deadline`` passed.
        """
        while not self._linked():
            state = self._state
            if state is ClientState.CLOSED:
                raise self._closed()
            task = self._reconnect_task
            if (
                state is not ClientState.RECONNECTING
                or self._ready is None
                or task is None
                or task.done()
            ):
                raise self._nothing_to_wait_for()
            try:
                async with asyncio.timeout_at(deadline):
                    await self._ready.wait()
            except TimeoutError:
                # (its cause: the last reconnect attempt's failure, None before one failed)
                raise FocasConnectionError(self._still_reconnecting()) from self._attempt_error

    def _still_reconnecting(self) -> str:
        """What a call says whose time was up while reconnecting: why the link was lost, and
        why the last reconnect attempt failed (once one did)."""
        causes = [str(self._lost_why)] if self._lost_why is not None else []
        if self._attempt_error is not None:
            causes.append(f"the last reconnect attempt failed: {self._attempt_error}")
        why = f" ({'; '.join(causes)})" if causes else ""
        return f"still reconnecting to {self.address} when the call timed out{why}"

    # -- the reconnect, shared by both transports ----------------------------------------
    def _reconnecting(self, exc: BaseException | None) -> None:
        """The link was lost and the policy reconnects: RECONNECTING, calls wait on
        ``_ready``, and one reconnect task (the backoff starts again after a stable link)."""
        policy = self._policy
        assert policy is not None and self._ready is not None and self._loop is not None
        # (the command line's words of the same event: ``alarms --follow``, ``watch``)
        self._logger.warning(
            "connection to %s lost: %s; reconnecting", self.address, exc or "closed"
        )
        self._told_lost = True
        self._lost_why = exc
        if self._loop.time() - self._up_since >= policy.stable_after:
            self._backoff = 0  # a stable connection: the backoff starts again from the start
        self._ready.clear()
        self._set_state(ClientState.RECONNECTING)
        if self._reconnect_task is None or self._reconnect_task.done():
            self._reconnect_task = self._loop.create_task(
                self._reconnect(policy), name=f"focas-reconnect {self.address}"
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
                "giving up reconnecting to %s after %d attempts", self.address, attempt
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

    def _reconnect_ended(self) -> None:
        """What a transport does when a reconnect ends, before waiting calls go on."""

    def _linked_now(self) -> None:
        """A link was installed: CONNECTED, and calls waiting go on (a reconnect still under
        way, from a ``connect()`` that won, is cancelled)."""
        task = self._reconnect_task
        if task is not None and not task.done() and task is not asyncio.current_task():
            task.cancel()
        loop = self._loop or asyncio.get_running_loop()
        self._up_since = loop.time()
        self._opened = True
        self._attempt_error = None
        self._lost_why = None
        self._connect_error = None
        self._set_state(ClientState.CONNECTED)
        if self._told_lost:
            self._told_lost = False
            self._logger.warning("reconnected to %s", self.address)
        if self._ready is not None:
            self._ready.set()

    async def _stop_reconnecting(self) -> None:
        """CLOSED, and the reconnect task (if any) ended and its failure logged."""
        self._set_state(ClientState.CLOSED)
        task, self._reconnect_task = self._reconnect_task, None
        if task is not None:
            if not task.done():
                task.cancel()
                await asyncio.wait([task])
            failed = None if task.cancelled() else task.exception()
            if failed is not None:
                self._logger.warning("reconnect to %s failed: %s", self.address, os_reason(failed))
        if self._ready is not None:
            self._ready.set()

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
