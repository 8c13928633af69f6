"""The gateway as one object: :class:`Gateway` (the clients, the poller, the writer) and
:func:`outputs` (the MQTT and OPC UA sinks a configuration asks for).

::

    gateway = Gateway(config)
    async with AsyncExitStack() as stack:
        for output in outputs(config, gateway.writer):
            gateway.add_sink(await stack.enter_async_context(output))
        async with gateway:
            ...  # polling, until the block ends

The outputs' modules (:mod:`focas_net.gateway.mqtt`, :mod:`focas_net.gateway.opcua`) and their
extras (aiomqtt, asyncua) are imported only when the configuration has their section, so the
package imports without them; :class:`MissingExtra` says what to install.
"""

from __future__ import annotations

import asyncio
import importlib
import time
from collections.abc import Callable, Sequence
from contextlib import AbstractAsyncContextManager
from types import TracebackType
from typing import Any, Self

from focas_net.client import ReconnectPolicy

from ._keys import ConfigError
from .config import GatewayConfig, MachineConfig, check_machines, check_outputs
from .model import Sink
from .poller import DEFAULT_POLICY, Client, Poller, client_for
from .writer import GatedWriter

__all__ = ["EXTRA", "Gateway", "MissingExtra", "outputs"]

#: What installs the outputs' packages.
EXTRA = "pip install 'focas-net[gateway]'"


class MissingExtra(ConfigError):
    """The configuration asks for an output whose package is not installed."""


def _output_class(module: str, name: str, section: str) -> Any:
    """``focas_net.gateway.<module>.<name>``; :class:`MissingExtra` when it (or what it needs)
    cannot be imported."""
    try:
        return getattr(importlib.import_module(f"focas_net.gateway.{module}"), name)
    except ImportError as exc:
        missing = getattr(exc, "name", None) or str(exc)
        raise MissingExtra(f"[{section}] needs {missing}, not installed: {EXTRA}") from None


def outputs(config: GatewayConfig, writer: GatedWriter) -> list[AbstractAsyncContextManager[Sink]]:
    """The sinks ``config`` asks for, to be entered: ``MqttSink(settings)`` for ``[mqtt]``,
    ``OpcUaSink(settings, writer)`` for ``[opcua]``. Raises :class:`MissingExtra`."""
    _check_config(config)
    made: list[AbstractAsyncContextManager[Sink]] = []
    if config.mqtt is not None:
        made.append(_output_class("mqtt", "MqttSink", "mqtt")(config.mqtt))
    if config.opcua is not None:
        made.append(_output_class("opcua", "OpcUaSink", "opcua")(config.opcua, writer))
    return made


def _check_config(config: GatewayConfig) -> None:
    """Raise ``TypeError`` for a ``config`` that is no :class:`GatewayConfig`, or whose
    outputs are not their settings' class."""
    if not isinstance(config, GatewayConfig):
        raise TypeError(
            f"config must be a GatewayConfig (load_config(path) reads a file), got {config!r}"
        )
    check_outputs(config)


class Gateway:
    """The machines of ``config`` polled (:class:`~focas_net.gateway.poller.Poller`) for
    ``sinks`` (more may be added before entering), with :attr:`writer` writing through the
    write gates. ``async with`` runs the poll loop in a task until the block ends, then
    closes every client. ``clock``, ``policy`` and ``client_of`` are the poller's."""

    def __init__(
        self,
        config: GatewayConfig,
        sinks: Sequence[Sink] = (),
        *,
        clock: Callable[[], float] = time.time,
        policy: ReconnectPolicy = DEFAULT_POLICY,
        client_of: Callable[[MachineConfig, ReconnectPolicy], Client] = client_for,
    ) -> None:
        _check_config(config)
        check_machines(config.machines, name="config.machines")
        if not config.machines:
            raise ValueError("a gateway needs at least one machine (config.machines is empty)")
        if isinstance(sinks, str | bytes) or not isinstance(sinks, Sequence):
            raise TypeError(f"sinks must be a list of sinks, got {sinks!r}")
        for i, sink in enumerate(sinks):
            _check_sink(f"sinks[{i}]", sink)
        if not isinstance(policy, ReconnectPolicy):
            raise TypeError(f"policy must be a ReconnectPolicy, got {policy!r}")
        if not callable(clock):
            raise TypeError(f"clock must be callable (time.time), got {clock!r}")
        self.config = config
        self.poller = Poller(
            config.machines, sinks, clock=clock, policy=policy, client_of=client_of
        )
        self.writer = GatedWriter(self.machine)
        self._task: asyncio.Task[None] | None = None

    def machine(self, name: str) -> tuple[MachineConfig, Client]:
        """The configuration and the client of machine ``name`` (``KeyError`` naming an
        unknown one)."""
        return self.poller.config(name), self.poller.client(name)

    def add_sink(self, sink: Sink) -> None:
        """Tell ``sink`` too (before entering)."""
        _check_sink("sink", sink)
        if self._task is not None:
            raise RuntimeError("add sinks before the gateway runs")
        self.poller.sinks.append(sink)

    async def __aenter__(self) -> Self:
        if self._task is not None:
            raise RuntimeError("the gateway is running already: enter it once")
        if self.poller.closed:
            raise RuntimeError("the gateway has run and closed its clients: make a new Gateway")
        self._task = asyncio.get_running_loop().create_task(
            self.poller.run(), name="focas-net gateway poller"
        )
        return self

    async def __aexit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        task, self._task = self._task, None
        try:
            if task is not None:
                task.cancel()
                await asyncio.gather(task, return_exceptions=True)
        finally:
            await self.poller.aclose()

    @property
    def running(self) -> bool:
        """Whether the poll loop runs (a failure of it ends it: see :meth:`wait`)."""
        return self._task is not None and not self._task.done()

    async def wait(self) -> None:
        """Until the poll loop ends (it ends only by a failure, raised here)."""
        if self._task is None:
            raise RuntimeError("the gateway is not running")
        await asyncio.shield(self._task)


#: The methods a :class:`~focas_net.gateway.Sink` has.
_SINK_METHODS = ("described", "online", "samples", "alarms")


def _check_sink(what: str, sink: object) -> None:
    """TypeError, naming ``what`` and the method missing, for an object that is no sink."""
    for method in _SINK_METHODS:
        if not callable(getattr(sink, method, None)):
            raise TypeError(
                f"{what} must be a sink (with {', '.join(_SINK_METHODS)}), got {sink!r}: "
                f"it has no {method}()"
            )
