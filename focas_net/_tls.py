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

__all__ = ["ca_context", "is_openssl_text", "openssl_words", "pem_holds", "ssl_error_text"]


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
