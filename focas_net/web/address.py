"""The ``[HOST:]PORT`` of the dashboard, parsed and checked (pure)."""

from __future__ import annotations

from typing import Final

from focas_net._address import check_host, url_address
from focas_net._typed import is_loopback, whole_number

__all__ = ["DEFAULT_WEB_HOST", "is_loopback", "parse_web_address"]

#: Where the dashboard listens when ``--web`` gives a port only.
DEFAULT_WEB_HOST: Final = "127.0.0.1"


def parse_web_address(text: str) -> tuple[str, int]:
    """``(host, port)`` of ``"PORT"``, ``"HOST:PORT"`` or ``"[IPv6]:PORT"`` (the port a whole
    number as ``--port`` reads it: ``8080``, ``0x1F90``); the host is
    :data:`DEFAULT_WEB_HOST` when not given, port 0 asks for an ephemeral one. ValueError,
    naming ``text``, for anything else."""
    raw = text.strip()
    url = url_address(raw)
    if url is not None:  # tcp://HOST:PORT, http://HOST/: the address without its scheme
        name, number = url
        host = name or DEFAULT_WEB_HOST
        bare = f"[{host}]:{number or 'PORT'}" if ":" in host else f"{host}:{number or 'PORT'}"
        raise ValueError(f"{text!r} is a URL: write [HOST:]PORT without a scheme ({bare})")
    host, sep, port_text = raw.rpartition(":")
    if not sep:
        host, port_text = DEFAULT_WEB_HOST, raw
    elif host.startswith("[") and host.endswith("]"):
        host = host[1:-1]
    elif ":" in host:
        raise ValueError(f"{text!r}: write an IPv6 host in brackets, [HOST]:PORT")
    if not host:
        raise ValueError(f"{text!r}: no host before ':' (write PORT or HOST:PORT)")
    try:  # a whole number as --port reads one (8080, 0x1F90)
        port = whole_number(port_text) if port_text.strip() else -1
    except ValueError:
        port = -1
    if not 0 <= port <= 65_535:
        raise ValueError(f"{text!r}: the port must be a number 0..65535 ([HOST:]PORT)")
    if any(c.isspace() for c in host):
        raise ValueError(f"{text!r}: a host name has no spaces")
    try:  # the host as every front end checks one (1.2.3.4.5 is no address)
        host = check_host(host)
    except ValueError as exc:
        raise ValueError(f"{text!r}: {exc}") from None
    return host, port
