"""The gateway's MQTT output: a :class:`~.model.Sink` that publishes to one broker through
aiomqtt (the ``mqtt`` extra). The topics, payloads, change filter and buffer are
:mod:`._mqtt_messages`'s; this shell only connects and moves messages.

The poller's calls turn into messages at once and wait in a bounded buffer; one task publishes
them. It connects with the gateway's last will (``P/$gateway/G/state`` = ``offline``,
retained), sends the birth (``online``, retained) first on every connection, and after a lost
broker connects again with a growing delay, the buffer kept (within its bound: the oldest are
dropped and counted, and the count is published on ``P/$gateway/G/dropped``). Messages taken
from the buffer and not confirmed when the connection broke go back to its front: delivery is
at least once (an alarm event may come twice after a broker loss, never not at all within the
bound). On every connection after the first, and after drops, the whole retained state
(every machine's latest ``$model``, availability, values and active alarm lists, which
:class:`~._mqtt_messages.Publication` keeps) is published again, as a rebirth: a broker that
restarted without its retained messages gets them back, and drops lose only superseded values
and alarm events. A clean stop publishes what waits (for at most ``close_timeout`` seconds, if the
broker is there), then ``offline`` itself, then disconnects.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import os
import re
import ssl
import time
from collections import deque
from collections.abc import AsyncIterator, Callable, Sequence
from dataclasses import replace
from types import TracebackType
from typing import Any, Final

import aiomqtt
from aiomqtt.exceptions import MqttConnectError

from focas_net._tls import is_openssl_text, openssl_words, ssl_error_text

from ._mqtt_messages import Buffer, Message, Publication
from .config import MqttSettings
from .model import AlarmChange, MachineShape, Sample

__all__ = ["MqttSink", "broker_reason"]

_log = logging.getLogger("focas_net.gateway.mqtt")

#: ``[Errno 104] Connection reset by peer``: what the MQTT client keeps of a socket's error.
_ERRNO: Final = re.compile(r"\[Errno (-?\d+)\] ")
#: aiomqtt's words for a connection that broke while it waited for messages, and for an
#: acknowledgement (or CONNACK) that did not come within its timeout.
_LOST: Final = "Disconnected during message iteration"
_TIMED_OUT: Final = "Operation timed out"
#: Why a connection attempt ended before the broker answered MQTT's CONNECT: the connection
#: ended (:func:`_ended_early`).
_BEFORE_CONNACK: Final = "before any answer to MQTT's CONNECT"
_ENDED_EARLY: Final = f"connection ended {_BEFORE_CONNACK}"
#: A socket's words for a connection the peer ended (a reset; a write after it).
_ENDED: Final = frozenset({"connection reset by peer", "broken pipe"})
#: What paho-mqtt logs of its socket's errors (then it drops the connection).
_SOCKET_ERRORS: Final = frozenset({"failed to receive on socket: %s", "timeout on socket: %s"})
#: The port MQTT over TLS listens on by convention (and 1883 plain MQTT).
_TLS_PORT: Final = 8883


def broker_reason(
    exc: BaseException,
    settings: MqttSettings,
    *,
    connected: bool = False,
    reached: bool = False,
    socket_error: str | None = None,
) -> str:
    """Why the broker of ``settings`` could not be reached or dropped the connection, as
    words (``connection refused``, never ``[Errno 111] ...``), with a hint where the settings
    may be the cause: TLS to a plain port or plain MQTT to a TLS one, a peer that never
    answers MQTT's CONNECT, a broker that refused the client (its reason code).

    ``connected``: the connection was up when ``exc`` ended it (a lost connection, or a
    message the broker did not acknowledge in time); ``reached``: a connection to this broker
    was up before (so a silent port is that broker, not some other program);
    ``socket_error``: what the MQTT client's socket said before the connection was up (its
    log, ``[Errno 104] Connection reset by peer``)."""
    if isinstance(exc, MqttConnectError):
        words = str(exc).partition("] ")[2] or str(exc)
        code = getattr(exc.rc, "value", exc.rc)
        return f"the broker refused: {words[:1].lower() + words[1:]} (MQTT reason code {code})"
    cause = exc.__cause__ or exc.__context__
    if isinstance(cause, ssl.SSLCertVerificationError):  # (the clients' words, and why)
        why = (cause.verify_message or str(cause)).rstrip(".")
        trusted = "the system" if settings.tls_ca is None else f"tls_ca {settings.tls_ca}"
        return (
            f"TLS certificate not trusted: {why} (the gateway trusts the certificate "
            f"authorities of {trusted})"
        )
    text = str(exc)
    if connected or getattr(exc, "rc", None) is not None or text == _LOST:
        if text == _TIMED_OUT:
            return "the broker acknowledged no message in time: the connection is taken as lost"
        return "the connection to the broker was lost"
    if isinstance(cause, ssl.SSLError) or is_openssl_text(text):  # (the clients' words)
        detail = ssl_error_text(cause) if isinstance(cause, ssl.SSLError) else ""
        text = f"TLS handshake failed ({detail or openssl_words(text)})"
    elif text in (_TIMED_OUT, _ENDED_EARLY) and socket_error:
        text = f"{_words(socket_error)} before any answer to MQTT's CONNECT"
    elif text == _ENDED_EARLY:  # (closed without a word of the socket: the peer closed it)
        text = "connection closed by peer before any answer to MQTT's CONNECT"
    else:
        text = _words(text)
        if text in _ENDED:  # (the connecting thread met it: in TLS's handshake, or the same end)
            tls_met = settings.tls  # (the handshake is the connecting thread's)
            text += " during the TLS handshake" if tls_met else f" {_BEFORE_CONNACK}"
    tls = settings.tls
    if tls and ("reset" in text or "TLS handshake" in text or "eof" in text):
        return f"{text} (tls = true: is that the broker's TLS port?)"
    if not tls and settings.port == _TLS_PORT:
        return f"{text} (port {_TLS_PORT} is MQTT over TLS by convention: tls = true?)"
    if text == "operation timed out":
        text = "no answer to MQTT's CONNECT in time"
        return text if reached else f"{text} (is that a broker's port?)"
    if text.endswith("before any answer to MQTT's CONNECT") and not reached:
        return f"{text} (is that a broker's port?)"
    return text


def _words(text: str) -> str:
    """A socket's error as words: ``[Errno 104] Connection reset by peer`` is ``connection
    reset by peer`` (a resolver's negative error numbers keep their own words)."""
    found = _ERRNO.match(text)
    if found:
        errno = int(found[1])
        text = os.strerror(errno) if errno > 0 else text[found.end() :]
    return text[:1].lower() + text[1:]


class _SocketErrors(logging.Filter):
    """Keeps out of the MQTT client's log (aiomqtt's ``mqtt`` logger) its socket's errors,
    which :func:`broker_reason` tells in words, and holds the last one."""

    def __init__(self) -> None:
        super().__init__()
        self.last: str | None = None

    def filter(self, record: logging.LogRecord) -> bool:
        if record.msg in _SOCKET_ERRORS and record.args:
            self.last = str(record.args[0] if isinstance(record.args, tuple) else record.args)
            return False
        return True


def _forget(client: aiomqtt.Client) -> None:
    """A client whose connection attempt failed (its CONNECT not answered in time) may still
    connect when the broker answers late: it is disconnected cleanly, so that the broker
    drops its last will, and its end is no news (asyncio would log its exception as never
    retrieved)."""
    client._disconnected.add_done_callback(_retrieved)
    with contextlib.suppress(Exception):  # (no socket: nothing to disconnect)
        client._client.disconnect()


def _attempt(client: aiomqtt.Client) -> asyncio.Future[None] | None:
    """The future of ``client``'s connection attempt (aiomqtt 2's own, which it sets when the
    broker answers MQTT's CONNECT), or None where a release keeps it otherwise: then an attempt
    ends as aiomqtt ends it (``pyproject.toml`` bounds aiomqtt below 3, a test checks the
    attribute)."""
    connected = getattr(client, "_connected", None)
    return connected if isinstance(connected, asyncio.Future) else None


def _ended_early(client: aiomqtt.Client) -> None:
    """A connection that ends before the broker answered MQTT's CONNECT (the peer closed it,
    or reset it) fails ``client``'s connection attempt at once with :data:`_ENDED_EARLY`, as
    it ends: aiomqtt would wait out its timeout and say the CONNECT was not answered in time.
    (What the socket said, a reset, is in the MQTT client's log before this is called.)"""
    paho = getattr(client, "_client", None)
    if paho is None or _attempt(client) is None:  # (another release: its own timeout)
        return
    theirs = paho.on_disconnect
    loop = asyncio.get_running_loop()

    def fail() -> None:
        connected = _attempt(client)
        if connected is not None and not connected.done():
            connected.set_exception(aiomqtt.MqttError(_ENDED_EARLY))
            _retrieved(connected)  # (an attempt given up already awaits it no more)

    def on_disconnect(*args: Any) -> None:
        connected = _attempt(client)
        if connected is not None and not connected.done():
            loop.call_soon_threadsafe(fail)  # (paho may call from the connecting thread)
        if theirs is not None:
            theirs(*args)

    paho.on_disconnect = on_disconnect


def _retrieved(future: asyncio.Future[None]) -> None:
    if not future.cancelled():
        future.exception()


@contextlib.asynccontextmanager
async def _entered(client: aiomqtt.Client) -> AsyncIterator[aiomqtt.Client]:
    """``client``, connected already, left as ``async with client`` leaves it."""
    try:
        yield client
    except BaseException as exc:
        await client.__aexit__(type(exc), exc, exc.__traceback__)
        raise
    await client.__aexit__(None, None, None)


#: Messages published at once (each waits for its acknowledgement at QoS 1 and 2).
WINDOW: Final = 64


class MqttSink:
    """Publishes the gateway's machines to the broker of ``settings``; an async context manager
    (the publishing task runs inside it). Its :class:`~.model.Sink` methods only queue and
    never raise; what they could not turn into messages is logged and counted in
    :attr:`errors`.

    Settings it cannot use raise :class:`~.config.ConfigError` naming the key:
    :meth:`MqttSettings.check <focas_net.gateway.config.MqttSettings.check>`, the file's own
    check.

    ``reconnect`` is the first and the longest delay between connection attempts (doubling
    from one to the other, back to the first once connected); ``timeout`` how long the broker
    may take to answer the connection and to acknowledge a message (then the connection is
    taken as lost and made again).

    While it runs, the MQTT client's log (``mqtt``) leaves out its socket's errors: the sink's
    warning tells them, in words (:func:`broker_reason`). After a warning, the next connection
    made is told too (``connected again``)."""

    def __init__(
        self,
        settings: MqttSettings,
        *,
        gateway_name: str | None = None,
        reconnect: tuple[float, float] = (0.5, 30.0),
        close_timeout: float = 5.0,
        timeout: float = 10.0,
    ) -> None:
        if not isinstance(settings, MqttSettings):
            raise TypeError(f"settings must be an MqttSettings, got {settings!r}")
        if gateway_name is not None:  # (checked as the file's mqtt.gateway)
            settings = replace(settings, gateway=gateway_name)
        settings.check()
        self.publication = Publication(settings.prefix, settings.gateway_name, settings.deadbands)
        self._buffer = Buffer(settings.buffer)
        self.settings = settings
        self._reconnect = reconnect
        self._close_timeout = close_timeout
        self._timeout = timeout
        self._socket_errors = _SocketErrors()
        #: whether a warning was given since the last connection
        self._warned = False
        self._wake = asyncio.Event()
        self._closing = asyncio.Event()
        self._task: asyncio.Task[None] | None = None
        self._dropped_published = 0
        #: the drop count when the retained state was last queued again in full
        self._dropped_resynced = 0
        #: the retained state still to publish again after drops (before the buffer)
        self._resync: deque[Message] = deque()
        #: whether a connection to the broker is up now
        self.connected = False
        #: connections made so far
        self.connections = 0
        #: messages the broker confirmed (QoS 1, 2) or took (QoS 0)
        self.published = 0
        #: calls whose messages could not be made (logged)
        self.errors = 0

    @property
    def dropped(self) -> int:
        """Messages dropped because the buffer was full (the oldest go first)."""
        return self._buffer.dropped

    @property
    def coalesced(self) -> int:
        """Retained messages replaced in the buffer by a newer one for the same topic."""
        return self._buffer.coalesced

    @property
    def pending(self) -> int:
        """Messages waiting in the buffer."""
        return len(self._buffer)

    # --- the sink -----------------------------------------------------------------------------

    def described(self, shape: MachineShape) -> None:
        self._queue(lambda: self.publication.described(shape))

    def online(self, machine: str, online: bool, reason: str, time: float) -> None:
        self._queue(lambda: self.publication.online(machine, online, reason, time))

    def samples(self, samples: Sequence[Sample]) -> None:
        self._queue(lambda: self.publication.samples(samples))

    def alarms(self, changes: Sequence[AlarmChange]) -> None:
        self._queue(lambda: self.publication.alarms(changes))

    def _queue(self, make: Callable[[], list[Message]]) -> None:
        try:
            messages = make()
            self._buffer.extend(messages)
        except Exception:
            self.errors += 1
            _log.exception("MQTT: no message made")
            return
        if messages:
            self._wake.set()

    # --- the task -----------------------------------------------------------------------------

    async def __aenter__(self) -> MqttSink:
        aiomqtt.client.MQTT_LOGGER.addFilter(self._socket_errors)
        self._task = asyncio.create_task(self._run(), name="focas_net mqtt publisher")
        return self

    async def __aexit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        await self.close()

    async def close(self) -> None:
        """Publish what waits (if connected), then ``offline``, then disconnect; give up after
        ``close_timeout`` seconds."""
        task = self._task
        if task is None:
            return
        self._closing.set()
        self._wake.set()
        try:
            await asyncio.wait_for(asyncio.shield(task), self._close_timeout)
        except TimeoutError:
            task.cancel()
            await asyncio.gather(task, return_exceptions=True)
        finally:
            self._task = None
            aiomqtt.client.MQTT_LOGGER.removeFilter(self._socket_errors)

    async def _run(self) -> None:
        first, longest = self._reconnect
        delay = first
        while not self._closing.is_set():
            self._socket_errors.last = None
            reached = self.connections > 0
            try:
                await self._connection()
                return
            except aiomqtt.MqttError as exc:
                if self.connected:
                    delay = first
                self._warned = True
                _log.warning(
                    "MQTT broker %s:%d: %s",
                    self.settings.host,
                    self.settings.port,
                    broker_reason(
                        exc,
                        self.settings,
                        connected=self.connected,
                        reached=reached,
                        socket_error=self._socket_errors.last,
                    ),
                )
            except Exception:
                self.errors += 1
                _log.exception("MQTT publisher")
            finally:
                self.connected = False
            try:
                await asyncio.wait_for(self._closing.wait(), delay)
            except TimeoutError:
                delay = min(delay * 2, longest)

    def _client(self) -> aiomqtt.Client:
        s = self.settings
        will = self.publication.will()
        client = aiomqtt.Client(
            s.host,
            s.port,
            identifier=s.client_id,
            username=s.username,
            password=s.password,
            keepalive=s.keepalive,
            will=aiomqtt.Will(will.topic, will.payload, s.qos, retain=will.retain),
            tls_context=s.tls_context(),
            max_inflight_messages=WINDOW,
            timeout=self._timeout,
        )
        # a full window is the normal state of a busy publisher, not a concern to log
        client.pending_calls_threshold = WINDOW + 1
        _ended_early(client)
        return client

    async def _connection(self) -> None:
        """One connection: birth, then the buffer until the connection breaks (MqttError) or
        the sink closes (then ``offline`` and a clean disconnect)."""
        s = self.settings
        attempt = self._client()
        try:
            await attempt.__aenter__()
        except BaseException:
            _forget(attempt)
            raise
        async with _entered(attempt) as client:
            self.connected = True
            self.connections += 1
            if self._warned:
                self._warned = False
                _log.warning("MQTT broker %s:%d: connected again", s.host, s.port)
            await self._publish(client, self.publication.birth())
            if self.connections > 1 or self._buffer.dropped != self._dropped_resynced:
                # connected again (the broker may have restarted without its retained
                # messages) or messages were dropped: publish the whole retained state again,
                # in place of the retained messages waiting (the state holds them too)
                self._dropped_resynced = self._buffer.dropped
                self._buffer.discard_retained()
                self._resync = deque(self.publication.retained())
            watcher = asyncio.create_task(self._watch(client))
            drainer = asyncio.create_task(self._drain(client))
            try:
                await asyncio.wait({watcher, drainer}, return_when=asyncio.FIRST_COMPLETED)
            finally:
                for task in (watcher, drainer):
                    task.cancel()
                await asyncio.gather(watcher, drainer, return_exceptions=True)
            for task in (watcher, drainer):
                error = None if task.cancelled() else task.exception()
                if error is not None:
                    raise error
            await self._publish(client, self.publication.will())  # drained: a clean stop

    @staticmethod
    async def _watch(client: aiomqtt.Client) -> None:
        """Returns (with MqttError) when the connection breaks: the sink subscribes to nothing,
        so the message iterator only ends."""
        async for _ in client.messages:
            pass

    async def _drain(self, client: aiomqtt.Client) -> None:
        """Publish the buffer with up to :data:`WINDOW` messages in flight (a sliding window:
        each confirmation lets the next message go); return once the buffer is empty, nothing
        is in flight and the sink closes. Whatever is in flight when the connection breaks goes
        back to the front of the buffer."""
        flying: dict[asyncio.Task[None], Message] = {}
        failed: list[tuple[Message, BaseException]] = []
        landed = asyncio.Event()

        def land(task: asyncio.Task[None]) -> None:
            message = flying.pop(task, None)
            if message is None or task.cancelled():
                return
            error = task.exception()
            if error is None:
                self.published += 1
            else:
                failed.append((message, error))
            landed.set()

        qos = self.settings.qos
        try:
            while True:  # until the connection breaks or the sink closes
                if failed:
                    raise failed[0][1]
                if self._buffer.dropped != self._dropped_published:
                    count = self._buffer.dropped
                    await self._publish(client, self.publication.dropped(count, time.time()))
                    self._dropped_published = count
                room = WINDOW - len(flying)
                if room > 0:
                    resync = self._resync
                    batch = [resync.popleft() for _ in range(min(room, len(resync)))]
                    batch += self._buffer.take(room - len(batch))
                    for m in batch:
                        task = asyncio.create_task(
                            client.publish(m.topic, m.payload, qos, m.retain)
                        )
                        flying[task] = m
                        task.add_done_callback(land)
                if flying:
                    landed.clear()
                    await landed.wait()
                elif self._closing.is_set():
                    return
                else:
                    self._wake.clear()
                    await self._wake.wait()
        finally:
            tasks = list(flying)
            self._buffer.restore([m for m, _ in failed] + list(flying.values()))
            flying.clear()
            for task in tasks:
                task.cancel()
            await asyncio.gather(*tasks, return_exceptions=True)

    async def _publish(self, client: aiomqtt.Client, message: Message) -> None:
        await client.publish(message.topic, message.payload, self.settings.qos, message.retain)
        self.published += 1
