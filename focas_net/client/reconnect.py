"""The states of a client and its reconnect policy: :class:`ClientState`,
:class:`ReconnectPolicy`.

Both clients share them (their lifecycle is :class:`~focas_net.client._lifecycle.Lifecycle`):
a lost connection is opened again after the policy's backoff, and every state change is told
to the client's state callbacks. The client's behaviour is ``docs/client.md``.
"""

from __future__ import annotations

import enum
import random
from collections.abc import Callable
from dataclasses import dataclass

from focas_net._typed import nan_refused

__all__ = ["ClientState", "ReconnectPolicy"]


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
        for what in ("initial_delay", "max_delay", "factor", "jitter", "stable_after"):
            value = getattr(self, what)
            if isinstance(value, bool) or not isinstance(value, int | float):
                raise TypeError(f"{what} must be a number, got {value!r}")
            if value != value:
                raise ValueError(nan_refused(what, "a number"))
        for what in ("initial_delay", "factor"):
            if getattr(self, what) == float("inf"):
                raise ValueError(f"{what} must be finite, got {getattr(self, what)!r}")
        for what in ("initial_delay", "max_delay"):
            if getattr(self, what) < 0:
                raise ValueError(
                    f"reconnect delays must not be negative: {what} {getattr(self, what)!r}"
                )
        if self.initial_delay > self.max_delay:
            raise ValueError(
                f"initial_delay {self.initial_delay!r} must not exceed max_delay "
                f"{self.max_delay!r} (the cap of every delay)"
            )
        attempts = self.max_attempts
        if attempts is not None and (isinstance(attempts, bool) or not isinstance(attempts, int)):
            raise TypeError(f"max_attempts must be an integer or None, got {attempts!r}")
        if self.factor < 1:
            raise ValueError(f"factor must be at least 1, got {self.factor}")
        if not 0 <= self.jitter <= 1:
            raise ValueError(f"jitter must be within 0..1, got {self.jitter}")
        if self.max_attempts is not None and self.max_attempts < 1:
            raise ValueError(f"max_attempts must be at least 1 (or None), got {self.max_attempts}")
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
