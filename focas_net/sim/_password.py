"""The parameter password and the per-connection sessions it unlocks.

The password is 1..4 ASCII characters; only an exact match unlocks (a longer password offered
is wrong, never cut to a prefix). It is compared in constant time and never logged or shown.
"""

from __future__ import annotations

import hashlib
import hmac
from dataclasses import dataclass

from focas_net._typed import PASSWORD_SIZE, WRONG_PASSWORD, password_bytes
from focas_net.errors import EW

from ._base import MachineError

__all__ = ["ParamLock", "Session", "need_session"]


@dataclass(slots=True)
class Session:
    """Per-connection state: whether this connection unlocked the parameter password (and
    under which password: ``epoch`` counts :meth:`Machine.set_param_password` calls)."""

    unlocked: bool = False
    epoch: int = 0


def need_session(session: object) -> Session:
    """``session`` when it is a :class:`Session` (``machine.new_session()``): TypeError naming
    what was given otherwise, before the lock is asked."""
    if not isinstance(session, Session):
        raise TypeError(f"session must be a Session (machine.new_session()), got {session!r}")
    return session


def _password(text: str | bytes) -> bytes:
    """A parameter password as the CNC keeps it: the one rule of every front end
    (:func:`~focas_net._typed.password_bytes`, the codec's too)."""
    return password_bytes(text)


def _offered(text: str | bytes) -> bytes | None:
    """The 4 bytes a password offered to :meth:`Machine.unlock` stands for, or None when it can
    match no password (longer than 4 bytes: never cut to a prefix)."""
    raw = text.encode("latin-1", "replace") if isinstance(text, str) else bytes(text)
    if len(raw) > PASSWORD_SIZE:
        return None
    return raw.ljust(PASSWORD_SIZE, b"\x00")


class ParamLock:
    """The machine's parameter password (None: none) and its epoch, which moves with every
    change of the password so that sessions unlocked under an older one are locked again."""

    __slots__ = ("_password", "epoch")

    def __init__(self, password: str | bytes | None) -> None:
        self._password = None if password is None else _password(password)
        self.epoch = 0

    def __repr__(self) -> str:
        return f"ParamLock(set={self._password is not None})"

    @property
    def is_set(self) -> bool:
        return self._password is not None

    def set(self, password: str | bytes | None) -> None:
        self._password = None if password is None else _password(password)
        self.epoch += 1

    def admits(self, session: Session) -> bool:
        """No password, or ``session`` unlocked under the current one."""
        need_session(session)
        return self._password is None or (session.unlocked and session.epoch == self.epoch)

    def unlock(self, session: Session, password: str | bytes) -> None:
        """Unlock ``session`` (any password when there is none); EW_PASSWD, the session locked
        again, on a mismatch, and for text that is no password (not 1..4 ASCII characters:
        ``""``, ``"aé"``, ``"12345"``), which no front end may offer, with that reason. Bytes
        are the wire's 4 (or more) bytes: a longer payload is a mismatch. TypeError for a
        session that is none or a password that is neither text nor bytes."""
        need_session(session)
        if not isinstance(password, str | bytes | bytearray):
            raise TypeError(f"a parameter password is text or bytes, got {password!r}")
        expected = self._password
        session.epoch = self.epoch
        if isinstance(password, str):
            try:
                _password(password)
            except ValueError as exc:
                session.unlocked = False
                raise MachineError(EW.PASSWD, str(exc)) from None
        if expected is None:
            session.unlocked = True
            return
        offered = _offered(password)
        if offered is not None and hmac.compare_digest(offered, expected):
            session.unlocked = True
            return
        session.unlocked = False
        raise MachineError(EW.PASSWD, WRONG_PASSWORD)

    def digest(self) -> str:
        """A digest of the password, for the machine's state digest."""
        return hashlib.sha256(self._password or b"").hexdigest()
