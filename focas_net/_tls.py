"""The client side of TLS shared by every front end: a context that trusts the certificate
authorities of one CA file (the command line's ``--tls-ca`` and the gateway's
``mqtt.tls_ca``), refused in the same words wherever it was named, and OpenSSL's words
without their library tags."""

from __future__ import annotations

import re
import ssl
from pathlib import Path
from typing import Final

from focas_net._typed import os_reason

__all__ = [
    "alert_text",
    "ca_context",
    "is_openssl_text",
    "openssl_words",
    "peer_alert",
    "pem_holds",
    "ssl_error_text",
    "wants_client_certificate",
]


def pem_holds(path: str, label: str) -> bool | None:
    """Whether the PEM file ``path`` has a block whose label ends with ``label``
    (``CERTIFICATE``, ``PRIVATE KEY``); None when it cannot be read."""
    try:
        text = Path(path).read_text("ascii", errors="replace")
    except OSError:
        return None
    return re.search(rf"-----BEGIN [A-Z0-9 ]*{label}-----", text) is not None


#: OpenSSL's library tag and the source line Python adds: ``[SSL: WRONG_VERSION_NUMBER] ``,
#: `` (_ssl.c:1006)``.
_OPENSSL_TAGS: Final = re.compile(r"^\[[A-Z0-9_: ]+\] | \(_ssl\.c:\d+\)$")


def ssl_error_text(exc: OSError) -> str:
    """OpenSSL's words for ``exc`` without its library tag and source line (``[X509: ...]``,
    ``(_ssl.c:4154)``)."""
    if not isinstance(exc, ssl.SSLError):
        return os_reason(exc)  # (a file that cannot be read: the system's words)
    return openssl_words(str(exc.strerror or exc))


#: OpenSSL's reason of TLS 1.3's alert of a server that wants a client certificate and got
#: none (sent after the client's handshake is done: read on the connection's first read).
_CERTIFICATE_REQUIRED: Final = "TLSV13_ALERT_CERTIFICATE_REQUIRED"
#: OpenSSL's reason of TLS 1.2's alert of a server that ends a handshake it will not complete
#: (a client certificate it wants and did not get, or no version or cipher in common).
_HANDSHAKE_FAILURE: Final = "SSLV3_ALERT_HANDSHAKE_FAILURE"


def peer_alert(exc: BaseException | None) -> bool:
    """Whether ``exc`` is a TLS alert the peer sent (a peer that speaks TLS and refused)."""
    return isinstance(exc, ssl.SSLError) and "_ALERT_" in str(exc.reason)


def wants_client_certificate(exc: BaseException | None) -> bool | None:
    """Whether the TLS alert ``exc`` says the server wants a client certificate: True
    (TLS 1.3's alert), None (TLS 1.2's handshake failure, which may say so), False (no)."""
    reason = str(exc.reason) if isinstance(exc, ssl.SSLError) else ""
    if reason == _CERTIFICATE_REQUIRED:
        return True
    return None if reason == _HANDSHAKE_FAILURE else False


def alert_text(exc: ssl.SSLError) -> str:
    """The words of an SSL error ``exc`` of a connection: OpenSSL's without their tags, led
    by what a server that wants a client certificate means by its alert."""
    words = ssl_error_text(exc)
    if wants_client_certificate(exc):
        return f"the server wants a client certificate ({words})"
    return words


def openssl_words(text: str) -> str:
    """``text`` (an SSL error as a string, as a library passes it on) without OpenSSL's tag
    and source line; other text as it is."""
    return _OPENSSL_TAGS.sub("", text)


def is_openssl_text(text: str) -> bool:
    """Whether ``text`` is an SSL error as a string (``[SSL: ...] ...``, ``... (_ssl.c:2426)``)."""
    return _OPENSSL_TAGS.search(text) is not None


def ca_context(cafile: str | None) -> ssl.SSLContext:
    """A client context checking the peer's certificate and host name against the
    certificate authorities of the PEM file ``cafile`` (None: the system's). A file that
    cannot be loaded is a ``ValueError`` saying why (``no PEM certificate in it``, the
    system's words for a file that cannot be read), without the file's name."""
    try:
        return ssl.create_default_context(cafile=cafile)
    except (OSError, ssl.SSLError) as exc:
        reason = ssl_error_text(exc)
        if isinstance(exc, ssl.SSLError) and cafile is not None:
            reason = (
                f"a certificate in it cannot be read ({reason})"
                if pem_holds(cafile, "CERTIFICATE")
                else "no PEM certificate in it"
            )
        raise ValueError(reason) from None
