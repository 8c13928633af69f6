"""The three subjects measured side by side: the floor, focas_net and the pymodbus peer.

Each has a server command (run in its own process) and a client connector (run in the worker
process) with the same two-method surface: ``read_status()`` and ``close()``.
"""

from __future__ import annotations

import importlib.util
import sys
from collections.abc import Awaitable, Callable
from contextlib import AsyncExitStack
from typing import Any, Protocol

from benchmarks import peer
from benchmarks.floor import FloorClient
from benchmarks.report import FLOOR, FOCAS, PEER

#: ``focas-net: <name> listening on HOST:PORT`` and the floor's / peer's equivalent.
LISTEN_PATTERN = r"listening on (?P<host>[0-9.]+|\[[0-9a-fA-F:]+\]|[\w.-]+):(?P<port>\d+)"


class StatusConn(Protocol):
    @property
    def read_status(self) -> Callable[[], Awaitable[object]]: ...

    async def close(self) -> None: ...


class FocasConn:
    """A :class:`focas_net.client.FocasClient` entered as an async context manager."""

    def __init__(self, client: Any, stack: AsyncExitStack) -> None:
        self.client = client
        self._stack = stack
        # the client's own method, so that a call costs what a user's call costs (the other
        # subjects' connectors add no coroutine of their own either)
        self.read_status: Callable[[], Awaitable[object]] = client.read_status

    @classmethod
    async def connect(cls, host: str, port: int) -> FocasConn:
        from focas_net.client import FocasClient

        stack = AsyncExitStack()
        client = await stack.enter_async_context(FocasClient(host, port))
        return cls(client, stack)

    async def close(self) -> None:
        await self._stack.aclose()


def focas_available() -> str | None:
    """None when focas_net's client and server can be imported, else why not."""
    for module in ("focas_net.client", "focas_net.server"):
        try:
            found = importlib.util.find_spec(module)
        except ImportError as exc:
            return f"{module}: {exc}"
        if found is None:
            return f"{module} is not there yet"
    try:
        from focas_net.client import FocasClient  # noqa: F401
    except ImportError as exc:
        return f"focas_net.client.FocasClient: {exc}"
    return None


def peer_available() -> str | None:
    return None if peer.available() else "pymodbus is not installed (pip install focas-net[bench])"


def connector(subject: str) -> Callable[[str, int], Awaitable[StatusConn]]:
    if subject == FLOOR:
        return FloorClient.connect
    if subject == FOCAS:
        return FocasConn.connect
    if subject == PEER:
        return peer.PeerClient.connect
    raise ValueError(f"unknown subject {subject!r}")


_FOCAS_UVLOOP = (
    "import asyncio, sys, uvloop; asyncio.set_event_loop_policy(uvloop.EventLoopPolicy()); "
    "from focas_net.cli import main; sys.exit(main(sys.argv[1:]))"
)


def server_argv(subject: str, *, use_uvloop: bool, extra: tuple[str, ...] = ()) -> list[str]:
    """The command line of ``subject``'s server on 127.0.0.1, port 0."""
    py = sys.executable
    if subject == FLOOR:
        return [py, "-m", "benchmarks.floor", "--port", "0", *(["--uvloop"] * use_uvloop), *extra]
    if subject == PEER:
        return [py, "-m", "benchmarks.peer", "--port", "0", *(["--uvloop"] * use_uvloop)]
    if subject == FOCAS:
        args = ["serve", "--host", "127.0.0.1", "--port", "0", *extra]
        if use_uvloop:
            return [py, "-c", _FOCAS_UVLOOP, *args]
        return [py, "-m", "focas_net", *args]
    raise ValueError(f"unknown subject {subject!r}")
