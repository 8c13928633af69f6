"""Why a command's connection failed before the peer said anything, in the command line's
options: the probes of :mod:`focas_net.client._probes`, which the gateway asks too, run on
the command's own event loop once it ended."""

from __future__ import annotations

import asyncio

from focas_net.client._probes import COMMAND_LINE, PROBE_TIMEOUT, Findings, diagnosed
from focas_net.client._probes import advice as _advice

__all__ = ["PROBE_TIMEOUT", "Findings", "advice", "diagnosis"]


def advice(found: Findings, protocol: str, tls: bool, packed_only: str | None = None) -> str | None:
    """The advice for a command of ``protocol`` (``tls``: it asked for TLS) whose connection
    was closed before any answer, from what the probes ``found``, in the command line's
    options (None: nothing certain)."""
    return _advice(found, protocol, tls, packed_only, COMMAND_LINE)


def diagnosis(
    exc: BaseException,
    host: str,
    port: int,
    protocol: str,
    tls: bool,
    timeout: float,
    packed_only: str | None = None,
) -> tuple[BaseException, str | None]:
    """The error to report for ``exc`` and advice in the command line's options (None:
    none), probing ``host:port`` when ``exc`` says the peer said nothing
    (:func:`focas_net.client._probes.diagnosed`)."""
    return asyncio.run(diagnosed(exc, host, port, protocol, tls, timeout, packed_only))
