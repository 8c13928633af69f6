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
import sys
from collections.abc import Awaitable, Callable
from dataclasses import dataclass
from typing import Any

from focas_net.client import ClientState, FocasClient
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

__all__ = ["Go", "Handler", "HintedError", "Output", "runner", "write"]


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


async def _session(args: argparse.Namespace, go: Go, reconnect: bool) -> Output | None:
    client = FocasClient(
        args.host,
        args.port,
        timeout=args.timeout,
        password=getattr(args, "password", None),
        reconnect=reconnect,
    )
    if reconnect:
        client.add_state_callback(_report_state(client))
    async with client:
        return await go(client)


def _report_state(client: FocasClient) -> Callable[[ClientState], None]:
    lost = False

    def report(state: ClientState) -> None:
        nonlocal lost
        if state is ClientState.RECONNECTING:
            lost = True
            _print_one_line(f"connection to {client.host}:{client.port} lost; reconnecting")
        elif state is ClientState.CONNECTED and lost:
            lost = False
            _print_one_line(f"reconnected to {client.host}:{client.port}")

    return report


def _failure_text(args: argparse.Namespace, exc: BaseException) -> str:
    if isinstance(exc, HintedError):
        return f"{_failure_text(args, exc.cause)}; {exc.hint}"
    text = fmt.error_line(exc)
    if isinstance(exc, FocasTimeoutError):
        return f"timed out after {args.timeout:g} s ({args.host}:{args.port}): {text}"
    return text


def runner(handler: Handler) -> Callable[[argparse.Namespace], int]:
    """``args -> exit code``: parse, connect, run, print; failures become one line."""

    def run(args: argparse.Namespace) -> int:
        reconnect = bool(getattr(args, "follow", False))
        try:
            go = handler(args)
            out = asyncio.run(_session(args, go, reconnect))
        except (FocasError, ValueError, OSError) as exc:
            _print_one_line(_failure_text(args, exc))
            return _exit_code(exc)
        if out is not None:
            _emit(args, out)
        return EXIT_OK

    return run
