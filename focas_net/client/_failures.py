"""The words of a connection that failed, the same for both clients: a peer that does not
speak the protocol, a connection lost, a connect refused."""

from __future__ import annotations

import ssl as _ssl
from typing import Final

from focas_net.errors import FocasConnectionError, FrameError, ProtocolError

__all__: list[str] = []

#: The first byte of a TLS record (change_cipher_spec, alert, handshake, application_data),
#: which a TLS peer sends where a frame's length should be; its second byte is 3 (TLS 1.x).
_TLS_RECORD_TYPES: Final = frozenset({0x14, 0x15, 0x16, 0x17})


def violation_error(peer: str, exc: FrameError, head: bytes) -> ProtocolError:
    """The error of a framing violation by ``peer``: it does not speak the FOCAS protocol.

    ``head`` (the first bytes of the offending chunk) is shown as text, so that an HTTP
    answer reads as one; a TLS record is named as such.
    """
    if len(head) >= 2 and head[0] in _TLS_RECORD_TYPES and head[1] == 3:
        what = "it sent a TLS record: the server expects TLS"
    else:
        what = f"it sent {head[:8]!r}"
    reason = str(exc).removesuffix("; closing the connection")
    return ProtocolError(f"{peer} does not speak the FOCAS protocol ({reason}; {what})")


def lost_error(peer: str, exc: BaseException | None) -> FocasConnectionError:
    if isinstance(exc, FocasConnectionError):
        return exc
    text = f"connection to {peer} lost" + (f": {exc}" if exc else "")
    err = FocasConnectionError(text)
    err.__cause__ = exc
    return err


def connect_reason(exc: BaseException, ssl: _ssl.SSLContext | None) -> str:
    """Why a connect failed, never empty; a failed TLS handshake says so."""
    text = str(exc)
    if isinstance(exc, _ssl.SSLCertVerificationError):
        return f"TLS certificate not trusted: {exc.verify_message or text}"
    if ssl is not None and isinstance(exc, _ssl.SSLError | ConnectionError):
        detail = text if isinstance(exc, _ssl.SSLError) and text else "the peer closed it"
        return f"TLS handshake failed ({detail}): the peer may not speak TLS"
    if not text:
        return type(exc).__name__
    return text
