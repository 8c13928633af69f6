"""Who may open a session on the gateway's OPC UA server, and what the server's log says of a
session refused: :class:`Users` (the configuration's users, passwords compared in constant
time; anonymous sessions when allowed) tells each refusal once, in the gateway's words
naming the user (``OPC UA: user 'op' refused: wrong password``), at WARNING;
:class:`RefusedSessions` keeps out of asyncua's log its own lines of the same refusals
(``ERROR ... sending service fault response: ... (BadUserAccessDenied)``), which name
nobody."""

from __future__ import annotations

import hmac
import logging
from typing import Any, Final

from asyncua.crypto.permission_rules import User, UserRole
from asyncua.server.internal_server import InternalServer

from focas_net.gateway.config import OpcUaSettings

__all__ = ["SESSION_LOGGERS", "RefusedSessions", "Users"]

log = logging.getLogger("focas_net.gateway.opcua")

#: The asyncua loggers that tell a refused session.
SESSION_LOGGERS: Final = ("asyncua.server.uaprocessor", "asyncua.server.internal_session")
#: What they say of one: the fault sent for a user refused (which :class:`Users` told), for
#: an identity the server does not offer, and the session's rejection before it.
_FAULT: Final = "sending service fault response"
_DENIED: Final = "(BadUserAccessDenied)"
_REJECTED: Final = "(BadIdentityTokenRejected)"
_NOT_OFFERED: Final = "Rejected active session UserIdentityToken not supported"


class Users:
    """The configuration's users, and anonymous sessions when ``anonymous``."""

    def __init__(self, settings: OpcUaSettings, anonymous: bool) -> None:
        self._users = {u.name: u.password for u in settings.users}
        self._anonymous = anonymous

    def get_user(
        self,
        iserver: InternalServer,
        username: str | None = None,
        password: str | None = None,
        certificate: Any = None,
    ) -> User | None:
        # only anonymous and user name tokens are offered: no user name is an anonymous session
        # (``certificate`` is then the secure channel's, not an identity)
        if username is None:
            if self._anonymous:
                return User(role=UserRole.User)
            log.warning("OPC UA: an anonymous session refused: give a user name and password")
            return None
        expected = self._users.get(username)
        if expected is None:
            log.warning("OPC UA: user %r refused: no such user", username)
            return None
        if password is None or not hmac.compare_digest(expected.encode(), password.encode()):
            log.warning("OPC UA: user %r refused: wrong password", username)
            return None
        return User(role=UserRole.User, name=username)


class RefusedSessions(logging.Filter):
    """Leaves out asyncua's lines of a refused session, telling one that :class:`Users`
    never saw (an identity the server does not offer: anonymous when it is off) in the
    gateway's words."""

    def filter(self, record: logging.LogRecord) -> bool:
        text = record.getMessage()
        if text.startswith(_NOT_OFFERED):
            return False
        if _FAULT in text and text.endswith(_DENIED):
            return False
        if _FAULT in text and text.endswith(_REJECTED):
            log.warning(
                "OPC UA: a session refused: its identity is not offered here (anonymous "
                "access is off: give a user name and password)"
            )
            return False
        return True
