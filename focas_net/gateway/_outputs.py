"""The gateway's outputs' settings: the MQTT publisher's (:class:`MqttSettings`) and the OPC UA
server's (:class:`OpcUaSettings`), each with :meth:`check`, every rule of them, which the
configuration file's reader (:mod:`.config`) and each output call. ``focas_net.gateway.config``
exports them.
"""

from __future__ import annotations

import os
import ssl
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Final
from urllib.parse import urlsplit

from focas_net._address import check_host, check_port
from focas_net._tls import ca_context
from focas_net._typed import is_loopback

from ._keys import At
from .model import ITEMS

__all__ = [
    "DEFAULT_GATEWAY",
    "MOST_CHARS",
    "MqttSettings",
    "OpcUaSettings",
    "OpcUaUser",
    "deadbands",
]

#: The gateway's name in its MQTT topics when ``[mqtt]`` gives neither ``gateway`` nor
#: ``client_id``.
DEFAULT_GATEWAY: Final = "focas-net"
#: The most characters of ``mqtt.prefix``, ``client_id`` and ``gateway``: each goes into every
#: message (a topic holds the prefix and the gateway's or a machine's name), and MQTT carries a
#: topic and a client id in at most 65535 bytes.
MOST_CHARS: Final = 1000
_PREFIX_TEXT: Final = (
    f"a topic prefix of at most {MOST_CHARS} printable characters without '+', '#', a '$' "
    "first or a '/' at either end"
)
#: The most bytes of a string MQTT carries (a user name, a password), in UTF-8.
_MQTT_STRING: Final = 65535
#: What a topic level may not hold: a level separator or a wildcard.
_NOT_IN_LEVEL: Final = "/+#"
#: The items whose numbers name something (a program, a block, a tool), not a quantity.
_NAMING: Final = ("program", "main_program", "sequence", "tool")
#: The items a deadband may name: quantities, numbers with a unit that name nothing.
_ANALOGUE: Final = tuple(
    n
    for n, i in ITEMS.items()
    if i.kind in (int, float) and i.unit is not None and n not in _NAMING
)


@dataclass(frozen=True, slots=True)
class MqttSettings:
    """The MQTT publisher: broker address, topic prefix, session, QoS, the bound of the buffer
    kept while the broker is away (messages), and absolute deadbands by item name (analogue
    items: numbers with a unit). :meth:`check` is every rule of them, the file's and the
    publisher's."""

    host: str = "127.0.0.1"
    port: int = 1883
    prefix: str = "focas"
    client_id: str | None = None
    username: str | None = None
    password: str | None = None
    qos: int = 1
    keepalive: int = 30
    buffer: int = 10_000
    tls: bool = False
    deadbands: Mapping[str, float] = field(default_factory=dict)
    #: The gateway's name in its topics (``P/$gateway/G/state``) and messages (None:
    #: :attr:`gateway_name`'s default); ``--shard I/N`` (N > 1) appends ``-I``, so that no
    #: shard's will or clean stop says another is offline.
    gateway: str | None = None
    #: A PEM file of the certificate authorities the broker's certificate is checked against
    #: (None: the system's), with :attr:`tls`; a relative name is the current folder's (the
    #: file's reader makes it the configuration file's folder's).
    tls_ca: Path | None = None

    @property
    def gateway_name(self) -> str:
        """:attr:`gateway`, or else :attr:`client_id` (a broker holds one session per client
        id, so two gateways on one broker have distinct ones), or else ``focas-net``."""
        return self.gateway or self.client_id or DEFAULT_GATEWAY

    def tls_context(self, source: str = "") -> ssl.SSLContext | None:
        """The TLS context of the connection to the broker (None: plain MQTT), checking the
        broker's certificate against :attr:`tls_ca` or else the system's authorities; a
        ``tls_ca`` without ``tls = true``, or one that cannot be loaded, is a
        :class:`ConfigError` naming the key (after ``source``, the file, when given)."""
        at = At(source, "mqtt").key("tls_ca")
        ca = self.tls_ca
        if ca is not None:
            if not isinstance(ca, str | os.PathLike):
                at.expected(ca, "a PEM file of certificate authorities")
            if self.tls is not True:
                at.fail(
                    f"got {os.fspath(ca)!r} with tls = false; expected tls = true "
                    "(the CA file checks the broker's TLS certificate)"
                )
        if not self.tls:
            return None
        try:
            return ca_context(None if ca is None else os.fspath(ca))
        except ValueError as exc:
            at.fail(f"got {os.fspath(ca or '')!r}: {exc}")

    def check(self, source: str = "") -> None:
        """Raise :class:`ConfigError` naming the key (``mqtt.qos: got 3; ...``, after
        ``source``, the file, when given) for a value the publisher cannot use; the file's
        reader and :class:`~focas_net.gateway.mqtt.MqttSink` both call it."""
        at = At(source, "mqtt")
        at.key("host").checked(self.host, check_host, "a host name or address")
        at.key("port").checked(self.port, check_port, "a port 1..65535", why=False)
        prefix = self.prefix
        if (
            not isinstance(prefix, str)
            or not prefix
            or prefix[0] in "$/"
            or prefix.endswith("/")
            or any(c in prefix for c in "+#")
            or not prefix.isprintable()  # (a broker closes a CONNECT whose will topic is not)
            or len(prefix) > MOST_CHARS
        ):
            at.key("prefix").expected(prefix, _PREFIX_TEXT)
        for key, printable in (("username", True), ("password", False)):  # (MQTT: text, bytes)
            value = getattr(self, key)
            if value is not None and not _mqtt_string(value, printable=printable):
                kind = "printable characters" if printable else "characters"
                at.key(key).expected(
                    value, f"a non-empty string of {kind}, at most {_MQTT_STRING} bytes in UTF-8"
                )
        if self.password is not None and self.username is None:  # (the client would drop it)
            at.key("username").fail(
                "missing (MQTT sends a password only with a user name: give username too)"
            )
        for key in ("client_id", "gateway"):  # (a topic level, a payload's text: printable)
            value = getattr(self, key)
            if value is not None and (
                not isinstance(value, str)
                or not value
                or not value.isprintable()
                or len(value) > MOST_CHARS
            ):
                at.key(key).expected(
                    value, f"a non-empty string of printable characters, at most {MOST_CHARS}"
                )
        self._check_level(at)
        at.key("qos").integer(self.qos, 0, 2)
        at.key("keepalive").integer(self.keepalive, 1, 65535)
        at.key("buffer").integer(self.buffer, 1, 10_000_000)
        at.key("tls").boolean(self.tls)
        if self.tls_ca is not None:
            self.tls_context(source)
        bands = at.key("deadbands")
        for name, band in deadbands(bands, self.deadbands).items():
            bands.key(name).number(band)

    def _check_level(self, at: At) -> None:
        """The gateway's name is one level of its topics (``P/$gateway/G/state``): no level
        separator nor wildcard, refused under the key it comes from (``client_id`` when no
        ``gateway`` is given)."""
        key = "gateway" if self.gateway is not None else "client_id"
        name = getattr(self, key)
        if name is not None and any(c in name for c in _NOT_IN_LEVEL):
            given = "" if key == "gateway" else " (no mqtt.gateway given: give one)"
            at.key(key).expected(
                name,
                "one level of a topic, the gateway's name in its topics "
                f"(P/$gateway/NAME/state): no '/', '+' or '#'{given}",
            )


def _mqtt_string(value: object, *, printable: bool) -> bool:
    """Whether ``value`` is text MQTT carries as a string: non-empty, and at most
    :data:`_MQTT_STRING` bytes in UTF-8; ``printable``: without a control character (a broker
    closes a CONNECT whose text holds one, as MQTT's string rules allow)."""
    if not isinstance(value, str) or not value or (printable and not value.isprintable()):
        return False
    try:
        return len(value.encode()) <= _MQTT_STRING
    except UnicodeEncodeError:  # (a lone surrogate: no UTF-8)
        return False


@dataclass(frozen=True, slots=True)
class OpcUaUser:
    """A user the OPC UA server accepts, with its password."""

    name: str
    password: str


@dataclass(frozen=True, slots=True)
class OpcUaSettings:
    """The OPC UA server: its endpoint, its namespace URI, whether anonymous sessions are
    accepted (never on an endpoint beyond the loopback nor with writes; None: wherever they
    may be, see :attr:`anonymous_sessions`), its users, its certificate and key (PEM or DER
    files; both or neither; needed beyond the loopback), and whether the write methods exist
    at all (read-only by default; each machine's :class:`WriteGates` still applies).
    :meth:`check` is every rule of them, the file's and the server's."""

    endpoint: str = "opc.tcp://127.0.0.1:4840/focas_net/"
    namespace: str = "urn:focas-net:gateway"
    anonymous: bool | None = None
    users: tuple[OpcUaUser, ...] = ()
    certificate: Path | None = None
    private_key: Path | None = None
    writes: bool = False

    @property
    def host(self) -> str:
        """The endpoint's host ('' when the endpoint has none)."""
        try:
            return urlsplit(self.endpoint).hostname or ""
        except (TypeError, ValueError, AttributeError):
            return ""

    @property
    def loopback(self) -> bool:
        """Whether the endpoint is on the loopback."""
        return is_loopback(self.host)

    @property
    def anonymous_sessions(self) -> bool:
        """Whether anonymous sessions are accepted: :attr:`anonymous`, or when None, on a
        loopback endpoint while writes are off."""
        if self.anonymous is None:
            return self.loopback and not self.writes
        return self.anonymous

    def check(self, source: str = "") -> None:
        """Raise :class:`ConfigError` naming the key (``opcua.anonymous: got true; ...``,
        after ``source``, the file, when given) for settings no client could use safely; the
        file's reader and :class:`~focas_net.gateway.opcua.OpcUaSink` both call it."""
        at = At(source, "opcua")
        try:
            parts = urlsplit(self.endpoint)
        except (TypeError, ValueError, AttributeError):
            parts = None
        try:
            port = None if parts is None else parts.port
        except ValueError:  # a port beyond 65535, or not digits
            at.key("endpoint").expected(
                self.endpoint, "opc.tcp://HOST:PORT/PATH with a PORT of 0..65535"
            )
        if parts is None or parts.scheme != "opc.tcp" or not parts.hostname or port is None:
            at.key("endpoint").expected(self.endpoint, "opc.tcp://HOST:PORT/PATH")
        if (
            parts.username is not None
            or parts.query
            or parts.fragment
            or any(c.isspace() for c in self.endpoint)
        ):  # (what the server would not serve as typed: it advertises HOST:PORT/PATH alone)
            at.key("endpoint").expected(
                self.endpoint,
                "opc.tcp://HOST:PORT/PATH without a user (users: [[opcua.users]]), a '?' query, "
                "a '#' fragment or a space",
            )
        try:  # (the host rule of every front end: a machine's host, the command line's --host)
            check_host(parts.hostname)
        except ValueError as exc:
            at.key("endpoint").expected(self.endpoint, f"opc.tcp://HOST:PORT/PATH ({exc})")
        at.key("namespace").text(self.namespace, "a namespace URI")
        at.key("writes").boolean(self.writes)
        users = at.key("users")
        if not isinstance(self.users, tuple | list):
            users.expected(self.users, "a tuple of OpcUaUser")
        names: set[object] = set()
        for i, user in enumerate(self.users):
            one = users.index(i)
            if not isinstance(user, OpcUaUser):
                one.expected(user, "an OpcUaUser(name, password)")
            name = one.key("name").text(user.name, "a user name")
            one.key("password").text(user.password, "a password")
            if name in names:
                one.key("name").fail(f"user {name!r} is given twice")
            names.add(name)
        host, loopback = self.host, self.loopback
        if self.anonymous is not None:
            at.key("anonymous").boolean(self.anonymous)
        if self.anonymous and not loopback:
            at.key("anonymous").fail(
                f"got true; expected false: the endpoint's host {host} is beyond the loopback, "
                "where anonymous sessions are refused (give [[opcua.users]])"
            )
        if self.anonymous and self.writes:
            at.key("anonymous").fail(
                "got true; expected false: with writes = true only users may write "
                "(give [[opcua.users]])"
            )
        if not self.anonymous_sessions and not self.users:
            why = "beyond the loopback" if not loopback else "with writes = true"
            if loopback and not self.writes:
                why = "anonymous = false"
            at.fail(f"no way in: anonymous access is off ({why}) and there is no [[opcua.users]]")
        if (self.certificate is None) != (self.private_key is None):
            missing = "private_key" if self.private_key is None else "certificate"
            at.key(missing).fail("missing: give certificate and private_key both, or neither")
        if self.certificate is None and not loopback:
            at.key("certificate").fail(
                f"missing: the endpoint's host {host} is beyond the loopback, where the server "
                "needs its certificate and private_key"
            )


def deadbands(at: At, value: object) -> Mapping[str, Any]:
    """``value`` as a table of deadbands by item name: an item that is no quantity (no number
    with a unit, or a number that names something) is named as such, a name that is no item
    as an unknown key (with the closest one)."""
    if isinstance(value, Mapping):
        for name in value:
            if name in ITEMS and name not in _ANALOGUE:
                why = (
                    "is a number that names a program, a block or a tool, not a quantity: a "
                    "deadband would hide a change of it"
                    if name in _NAMING
                    else "is not a number with a unit"
                )
                at.key(name).fail(
                    f"{name} {why} (the items a deadband is for: {', '.join(sorted(_ANALOGUE))})"
                )
    return at.table(value, _ANALOGUE)
