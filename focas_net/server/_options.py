"""The checks of :class:`~focas_net.server.FocasServer`'s arguments given from Python: each
one of a wrong type is a :class:`TypeError`, NaN a :class:`ValueError`, naming the argument and
the value given, before a machine is touched or a socket made; the machines served and the
fixed ports, each one's own. The ranges are the server's own checks (``_server.py``)."""

from __future__ import annotations

import math
import ssl as _ssl
from collections.abc import Iterable, Mapping, Sequence
from collections.abc import Set as AbstractSet

from focas_net._address import check_host
from focas_net._typed import nan_refused
from focas_net.sim import Machine

__all__ = [
    "check_distinct_ports",
    "check_fleet_ports",
    "check_server_options",
    "server_machines",
]

#: Arguments that are an ``int`` (None allowed for the second group).
_INTS = (
    "max_frame", "max_connections", "max_delayed", "write_buffer_high", "backlog",
    "native_max_body",
)  # fmt: skip
_OPTIONAL_INTS = ("port", "native_port", "native_version")
#: Arguments that are a number of seconds.
_SECONDS = ("idle_timeout", "grace_period")
#: Arguments that are True, False or None.
_SWITCHES = ("read_only", "control")
#: The most connections a listening socket's backlog may ask for (a C ``int``).
_MAX_BACKLOG = 2**31 - 1
_MAX_PORT = 65_535


def _is_int(value: object) -> bool:
    return isinstance(value, int) and not isinstance(value, bool)


def check_server_options(options: dict[str, object]) -> None:
    """Check ``options`` (the keyword arguments of ``FocasServer``, by name) for their
    types: TypeError or ValueError naming the first one that is wrong."""
    host = options["host"]
    if not isinstance(host, str):
        raise TypeError(f"host must be a str (an address or a name), got {host!r}")
    check_host(host, 0)  # the clients' and the command line's words for a host that is none
    for name in _INTS:
        if not _is_int(options[name]):
            raise TypeError(f"{name} must be an integer, got {options[name]!r}")
    for name in _OPTIONAL_INTS:
        value = options[name]
        if value is not None and not _is_int(value):
            raise TypeError(f"{name} must be an integer or None, got {value!r}")
    for name in ("port", "native_port"):
        value = options[name]
        if isinstance(value, int) and not 0 <= value <= _MAX_PORT:
            raise ValueError(f"{name} {value} is outside 0..{_MAX_PORT} (0: any free port)")
    backlog = options["backlog"]
    assert isinstance(backlog, int)
    if not 0 <= backlog <= _MAX_BACKLOG:
        raise ValueError(f"backlog {backlog} is outside 0..{_MAX_BACKLOG}")
    ports = options["ports"]
    if ports is not None:
        if isinstance(ports, str | bytes) or not isinstance(ports, Sequence):
            raise TypeError(f"ports must be a list of port numbers or None, got {ports!r}")
        for i, p in enumerate(ports):
            if not _is_int(p):
                raise TypeError(f"ports[{i}] must be an integer, got {p!r}")
    for name in _SECONDS:
        value = options[name]
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise TypeError(f"{name} must be a number of seconds, got {value!r}")
        if math.isnan(value):
            raise ValueError(nan_refused(name))
    for name in _SWITCHES:
        value = options[name]
        if value is not None and not isinstance(value, bool):
            raise TypeError(f"{name} must be True, False or None, got {value!r}")
    ssl = options["ssl"]
    if ssl is not None and not isinstance(ssl, _ssl.SSLContext):
        raise TypeError(f"ssl must be an ssl.SSLContext or None, got {ssl!r}")
    durable = options["durable"]
    if durable is not None and not callable(durable):
        raise TypeError(f"durable must be callable or None, got {durable!r}")


def check_fleet_ports(first: int | None, ports: Sequence[int] | None, name: str) -> None:
    """A fleet's ``ports`` from ``first`` (the ``name=`` given) within 0..65535: ValueError
    naming the fleet and its last port otherwise, in the command line's words for ``--fleet``
    and ``--port`` (a first port outside the range is refused as itself)."""
    if not ports or ports[-1] <= 65_535 or first is None or not 0 <= first <= 65_535:
        return
    raise ValueError(
        f"{len(ports)} machines from {name}={first} run past 65535 (the last machine would get "
        f"port {ports[-1]})"
    )


def server_machines(machines: Machine | Iterable[Machine] | None) -> list[Machine]:
    if machines is None:
        from focas_net.sim import default_machine

        return [default_machine()]
    if isinstance(machines, Machine):
        return [machines]
    words = "machines must be a Machine or a list of them, got"
    if isinstance(machines, str | bytes) or not isinstance(machines, Iterable):
        raise TypeError(f"{words} {machines!r}")
    if isinstance(machines, Mapping):  # (its keys would be taken for machines)
        raise TypeError(
            f"{words} a {type(machines).__name__} (its machines in order: list(machines.values()))"
        )
    if isinstance(machines, AbstractSet):  # machine i's port would be anyone's
        raise TypeError(
            f"{words} a {type(machines).__name__}, which has no order (machine i listens on "
            "port + i): make it a list"
        )
    result = list(machines)
    if not result:
        raise ValueError("FocasServer needs at least one machine")
    seen: dict[int, int] = {}
    for i, m in enumerate(result):
        if not isinstance(m, Machine):
            raise TypeError(f"machines[{i}] must be a Machine, got {m!r}")
        first = seen.setdefault(id(m), i)
        if first != i:
            # two ports onto one state would look like two CNCs where a write on one
            # shows on the other
            raise ValueError(
                f"machines[{i}] is machines[{first}] ({m!r}): each machine served is a CNC "
                "of its own, with its own port and state; make another Machine for another "
                "CNC (native_port serves one machine on a second port)"
            )
    return result


def check_distinct_ports(ports: list[int] | None, native_ports: list[int] | None) -> None:
    """Each fixed port the server would listen on is one port's only: ValueError naming the
    two it would be (``native port 8194 of machine 0 is the port of machine 1``) before
    anything listens, rather than the system's ``address already in use`` for the server's
    own port. Port 0 (any free port) repeats freely."""
    taken: dict[int, str] = {}
    named = [(p, f"the port of machine {i}") for i, p in enumerate(ports or [])]
    named += [(p, f"the native port of machine {i}") for i, p in enumerate(native_ports or [])]
    for port, what in named:
        if port == 0:
            continue
        if port in taken:
            raise ValueError(
                f"port {port} would be both {taken[port]} and {what}: each listens on a port "
                "of its own"
            )
        taken[port] = what
