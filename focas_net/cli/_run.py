"""Running a client command: connect, run it, print its output or its failure as one line.

A command's handler is ``args -> Go``: it checks and converts its arguments (a
``ValueError`` is a usage error, reported before anything is sent), then returns the coroutine
function that talks to the CNC and returns what to print.
"""

from __future__ import annotations

import argparse
import asyncio
import json
import os
import ssl
import sys
from collections.abc import Awaitable, Callable
from dataclasses import dataclass
from typing import Any, Final

from focas_net.client import ClientState, FocasClient, ReconnectPolicy
from focas_net.errors import (
    ChunkedWriteError,
    CncError,
    FocasConnectionError,
    FocasError,
    FocasTimeoutError,
    ProtocolError,
)

from . import _format as fmt
from ._args import (
    EXIT_CNC,
    EXIT_CONNECTION,
    EXIT_OK,
    EXIT_PROTOCOL,
    EXIT_USAGE,
    print_error,
)

__all__ = [
    "FOLLOW_MAX_FAILURES",
    "FOLLOW_RECONNECT_ATTEMPTS",
    "Go",
    "Handler",
    "HintedError",
    "Output",
    "runner",
    "tls_context",
    "tls_context_wanted",
    "write",
]


@dataclass(frozen=True, slots=True)
class Output:
    """What a command prints: ``text`` normally, ``data`` (JSON) with ``--json``."""

    data: Any
    text: str


#: Talks to the CNC; returns what to print (None: the command printed as it went).
Go = Callable[[FocasClient], Awaitable[Output | None]]
#: A client command: its parsed arguments -> the talk to the CNC.
Handler = Callable[[argparse.Namespace], Go]


class HintedError(FocasError):
    """A failure with advice for the user appended to its one-line text."""

    def __init__(self, cause: FocasError, hint: str) -> None:
        super().__init__(f"{cause}; {hint}")
        self.cause = cause
        self.hint = hint


def write(text: str) -> None:
    """``text`` on stdout, flushed; a reader that went away (``| head``) ends the output."""
    try:
        sys.stdout.write(text)
        sys.stdout.flush()
    except BrokenPipeError:
        # Stop writing without a traceback at exit.
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        os.close(devnull)


def _print_one_line(message: str) -> None:
    print_error(" ".join(message.split()))


def _emit(args: argparse.Namespace, out: Output) -> None:
    if args.json:
        write(json.dumps(out.data, indent=2) + "\n")
    elif out.text:
        write(out.text.rstrip("\n") + "\n")


def _exit_code(exc: BaseException) -> int:
    if isinstance(exc, HintedError | ChunkedWriteError):
        return _exit_code(exc.cause)
    if isinstance(exc, CncError):
        return EXIT_CNC
    if isinstance(exc, FocasConnectionError | FocasTimeoutError | OSError):
        return EXIT_CONNECTION
    if isinstance(exc, ProtocolError):
        return EXIT_PROTOCOL
    if isinstance(exc, ValueError):
        return EXIT_USAGE
    return EXIT_CNC


#: ``alarms --follow``: reconnect attempts after one loss before the follower gives up (with
#: the default backoff, about 40 s without a connection).
FOLLOW_RECONNECT_ATTEMPTS: Final = 10
#: ``alarms --follow``: polls failing in a row before the follower gives up.
FOLLOW_MAX_FAILURES: Final = 20


def tls_context(args: argparse.Namespace) -> ssl.SSLContext | None:
    """The client's TLS context from ``--tls``, ``--tls-ca`` and ``--tls-insecure`` (None:
    plain TCP); a CA file that cannot be loaded is a usage error (``ValueError``)."""
    ca, insecure = getattr(args, "tls_ca", None), getattr(args, "tls_insecure", False)
    if not (getattr(args, "tls", False) or ca is not None or insecure):
        return None
    if ca is not None and insecure:
        raise ValueError("--tls-ca and --tls-insecure exclude each other")
    if insecure:
        ctx = ssl.SSLContext(ssl.PROTOCOL_TLS_CLIENT)
        ctx.check_hostname = False
        ctx.verify_mode = ssl.CERT_NONE
        return ctx
    try:
        return ssl.create_default_context(cafile=ca)
    except (OSError, ssl.SSLError) as exc:
        reason = exc.strerror if isinstance(exc, OSError) and exc.strerror else str(exc)
        raise ValueError(f"--tls-ca {ca}: {reason}") from None


async def _session(
    args: argparse.Namespace, go: Go, follow: bool, context: ssl.SSLContext | None
) -> Output | None:
    # A command's handler may set its own policy (``watch`` reconnects for ever).
    policy: ReconnectPolicy | None = getattr(args, "reconnect_policy", None)
    if policy is None and follow:
        policy = ReconnectPolicy(max_attempts=FOLLOW_RECONNECT_ATTEMPTS)
    client = FocasClient(
        args.host,
        args.port,
        timeout=args.timeout,
        password=getattr(args, "password", None),
        reconnect=policy if policy is not None else False,
        ssl=context,
    )
    if follow:
        client.add_state_callback(_report_state(client))
    async with client:
        return await go(client)


def _report_state(client: FocasClient) -> Callable[[ClientState], None]:
    lost = False
    where = fmt.address_text(client.host, client.port)

    def report(state: ClientState) -> None:
        nonlocal lost
        if state is ClientState.RECONNECTING:
            lost = True
            _print_one_line(f"connection to {where} lost; reconnecting")
        elif state is ClientState.CONNECTED and lost:
            lost = False
            _print_one_line(f"reconnected to {where}")

    return report


def _tls_hint(args: argparse.Namespace, exc: BaseException) -> str | None:
    """Advice when TLS on one side only is the likely cause of ``exc``."""
    tls = tls_context_wanted(args)
    cause = exc.__cause__
    if isinstance(cause, ssl.SSLCertVerificationError):
        return "give --tls-ca FILE (the server's certificate or its CA) or --tls-insecure"
    text = str(exc)
    if tls and isinstance(exc, FocasConnectionError) and "TLS handshake failed" in text:
        return "if the server is plain TCP, drop --tls"
    if not tls and (
        (isinstance(exc, FocasConnectionError) and "before any answer" in text)
        or (isinstance(exc, ProtocolError) and "TLS record" in text)
    ):
        return "if the server uses TLS, give --tls (with --tls-ca FILE or --tls-insecure)"
    return None


def tls_context_wanted(args: argparse.Namespace) -> bool:
    """Whether the TLS options ask for TLS."""
    return bool(
        getattr(args, "tls", False)
        or getattr(args, "tls_ca", None) is not None
        or getattr(args, "tls_insecure", False)
    )


def _failure_text(args: argparse.Namespace, exc: BaseException) -> str:
    if isinstance(exc, HintedError):
        return f"{_failure_text(args, exc.cause)}; {exc.hint}"
    text = fmt.error_line(exc)
    if isinstance(exc, FocasTimeoutError):
        where = fmt.address_text(args.host, args.port)
        return f"timed out after {args.timeout:g} s ({where}): {text}"
    hint = _tls_hint(args, exc)
    return text if hint is None else f"{text}; {hint}"


def runner(handler: Handler) -> Callable[[argparse.Namespace], int]:
    """``args -> exit code``: parse, connect, run, print; failures become one line."""

    def run(args: argparse.Namespace) -> int:
        follow = bool(getattr(args, "follow", False))
        try:
            go = handler(args)
            context = tls_context(args)
            out = asyncio.run(_session(args, go, follow, context))
        except (FocasError, ValueError, OSError) as exc:
            _print_one_line(_failure_text(args, exc))
            return _exit_code(exc)
        if out is not None:
            _emit(args, out)
        return EXIT_OK

    return run
