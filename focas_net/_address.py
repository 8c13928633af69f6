"""An address typed, checked once for every front end: :func:`check_host` (the clients, the
server's bind address, the command line's ``--host``, the gateway's file, the dashboard's
``--web``), :func:`check_port` and :func:`address_text`. It knows no protocol and no
machine.

A host is a name (at most 253 characters, parts of 1..63 between dots), an IPv4 address or an
IPv6 address (``::1``, or ``[::1]`` in brackets). A host with a port (``127.0.0.1:8193``,
``[::1]:8193``) is refused with the port named, for it is given apart, and so is a URL
(``tcp://127.0.0.1:8193``), with its host and port named.
"""

from __future__ import annotations

import ipaddress
import re
from typing import Final

__all__ = [
    "address_text",
    "check_host",
    "check_port",
    "host_and_port",
    "port_words",
    "split_advice",
    "url_address",
    "url_advice",
]

#: A part of a host name between dots: letters (any script, for an international name),
#: digits, hyphens and the underscores some local names have.
_LABEL: Final = re.compile(r"[\w-]+")
#: A URL (``tcp://127.0.0.1:8193/``): its scheme, then its host and port up to a path.
_URL: Final = re.compile(r"[A-Za-z][A-Za-z0-9+.-]*://([^/?#]*)(?:[/?#].*)?", re.DOTALL)
#: ``[::1]:8193``: an IPv6 address in brackets, a colon and what follows (a port, or not).
_BRACKETED_PORT: Final = re.compile(r"\[([^\]]*)\]:(.*)", re.DOTALL)


def check_port(port: object) -> int:
    """The port a client connects to: 1..65535 (0 means "any port" only to a server that
    listens). TypeError unless an integer, ValueError outside, each naming what was given."""
    if isinstance(port, bool) or not isinstance(port, int):
        raise TypeError(f"port must be an integer 1..65535, got {port!r}")
    if not 1 <= port <= 0xFFFF:
        raise ValueError(f"port {port} is outside 1..65535 (a client connects to a port)")
    return port


def address_text(host: str, port: int) -> str:
    """``host:port``, an IPv6 address in brackets (``[::1]:8193``)."""
    return f"[{host}]:{port}" if ":" in host else f"{host}:{port}"


def shown(text: str, limit: int = 40) -> str:
    """``text`` as typed (its repr), cut after ``limit`` characters."""
    return repr(text) if len(text) <= limit else f"{text[:limit]!r}... ({len(text)} characters)"


def url_address(text: str) -> tuple[str, str | None] | None:
    """``(host, port)`` of a URL (``tcp://127.0.0.1:8193``, ``http://[::1]/``: port None
    when it has none; host empty when it has none), else None."""
    url = _URL.fullmatch(text)
    if url is None:
        return None
    where = url[1].rpartition("@")[2]  # (without a user part)
    split = host_and_port(where)
    if split:
        return split
    return where.removeprefix("[").removesuffix("]"), None


def host_and_port(text: str) -> tuple[str, str] | None:
    """``(host, port)`` when ``text`` is a host, a colon and what a port would be
    (``127.0.0.1:8193``, ``[::1]:8193``, but also ``localhost:``, ``127.0.0.1:99999``,
    ``localhost:abc``: the port as typed, which :func:`port_words` judges), else None
    (``::1`` is an IPv6 address, no port)."""
    bracketed = _BRACKETED_PORT.fullmatch(text)
    if bracketed:
        return bracketed[1], bracketed[2]
    name, colon, port = text.rpartition(":")
    if colon and name and ":" not in name:
        return name, port
    return None


def port_words(port: str, lowest: int = 1) -> str | None:
    """Why ``port``, typed after a host's colon, is no port a client connects to (None: it
    is one, 1..65535 in ASCII digits; ``lowest`` 0 for a server, which listens on port 0
    too)."""
    if not port:
        return "with nothing after its colon"
    if port.isascii() and port.isdigit():
        if lowest <= int(port) <= 0xFFFF:
            return None
        return f"and a port outside {lowest}..65535"
    return f"a colon and {shown(port, 12)}, which is no port number"


def split_advice(split: tuple[str, str], options: bool, lowest: int = 1) -> str:
    """What to say of a host typed with a colon and a port, ``split``, and what to give
    instead: as the command line's options (``options``) or as a client's arguments. A
    port that is none (``localhost:``, ``127.0.0.1:99999``) is never suggested; ``lowest``
    as :func:`port_words`'s."""
    name, port = split
    why = port_words(port, lowest)
    ports = f"{lowest}..65535"
    if why is None:
        if options:
            return f"is a host and a port: give --host {name} --port {port}"
        return f"is a host and a port: give the host {name!r} and the port {port} apart"
    what = f"is a host {why}" if not why.startswith("a colon") else f"is a host, {why}"
    if options:
        return f"{what}: give --host {name} and --port {ports}"
    return f"{what}: give the host {name!r} and a port {ports} apart"


def url_advice(url: tuple[str, str | None], options: bool) -> str:
    """What to give instead of a URL whose host and port are ``url``: as the command line's
    options (``options``: ``give --host 127.0.0.1 --port 8193``) or as a client's
    arguments."""
    name, number = url
    if number is not None and port_words(number) is not None:
        number = None  # no port (``tcp://host:``, ``:99999``): none to suggest
    if not name:
        return "give a host name or address alone, without a scheme (127.0.0.1)"
    if options:
        given = f"--host {name}" + ("" if number is None else f" --port {number}")
    else:
        given = f"the host {name!r}" + ("" if number is None else f" and the port {number} apart")
    return f"give {given}, without a scheme"


def check_host(text: object, lowest: int = 1) -> str:
    """The host ``text`` names (an IPv6 address without its brackets); ``lowest``: the
    lowest port a host typed with one is told to give apart (0 for a server).

    :raises TypeError: not a ``str``.
    :raises ValueError: empty, a host with a port, or not a name or an address (each naming
        what was given).
    """
    if not isinstance(text, str):
        raise TypeError(f"host must be a str, got {text!r}")
    url = url_address(text)
    if url is not None:
        raise ValueError(f"host {shown(text)} is a URL: {url_advice(url, False)}")
    split = host_and_port(text)
    if split:
        raise ValueError(f"host {shown(text)} {split_advice(split, False, lowest)}")
    host = text
    if host.startswith("[") and host.endswith("]"):
        host = host[1:-1]
        if ":" not in host:
            raise ValueError(f"brackets are for IPv6 addresses, got host {shown(text)}")
    if not host:
        raise ValueError(f"empty host {text!r}: give a name or an address (127.0.0.1)")
    if ":" in host:
        try:
            ipaddress.IPv6Address(host)
        except ValueError:
            raise ValueError(f"not an IPv6 address: host {shown(text)}") from None
        return host
    if len(host) > 253:
        raise ValueError(f"host name too long: {shown(text)}; at most 253 characters")
    if all(c.isdigit() or c == "." for c in host.removesuffix(".")):
        odd = next((c for c in host if not c.isascii()), None)
        if odd is not None:  # which the name service would read as ASCII digits
            raise ValueError(
                f"not an IPv4 address: host {shown(text)} holds a digit beyond ASCII ({odd!r}, "
                f"U+{ord(odd):04X}): write 0-9"
            )
        try:  # a name is never all digits and dots: it is an address, or a mistake
            ipaddress.IPv4Address(host)
        except ValueError:
            raise ValueError(f"not an IPv4 address: host {shown(text)}") from None
        return host
    for label in host.removesuffix(".").split("."):
        if not 1 <= len(label) <= 63:
            raise ValueError(
                f"host name {shown(text)} has a part of {len(label)} characters; "
                "each part between dots must have 1..63"
            )
        if not _LABEL.fullmatch(label):
            raise ValueError(
                f"not a host name: {shown(text)} (a name is letters, digits and hyphens, in "
                "parts between dots)"
            )
    return host
