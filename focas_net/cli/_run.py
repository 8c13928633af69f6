"""Running a client command: connect, run it, print its output or its failure as one line.

A command's handler is ``args -> Go``: it checks and converts its arguments (a
``ValueError`` is a usage error, reported before anything is sent), then returns the coroutine
function that talks to the CNC and returns what to print. A :data:`Go` takes a
:class:`~focas_net.client.CncClient` and runs on either transport (``--protocol packed``, the
default, or ``--protocol native``: FOCAS/2 Ethernet); a handler whose command needs calls only
the packed protocol carries (simulator control, the program store, ``cnc_wrunlockparam``,
VersaMax) returns a :class:`PackedOnly` instead, and with ``--protocol native`` the command
fails with one line naming the command and the transport (exit 2, before connecting).
"""

from __future__ import annotations

import argparse
import asyncio
import contextlib
import json
import os
import ssl
import sys
from collections.abc import Awaitable, Callable, Iterator
from dataclasses import dataclass
from typing import Any, Final

from focas_net._tls import ca_context, peer_alert, wants_client_certificate
from focas_net._typed import os_words
from focas_net.client import (
    ClientState,
    CncClient,
    FocasClient,
    NativeClient,
    NativeUnsupportedError,
    ReconnectPolicy,
)
from focas_net.errors import (
    EW,
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
    ArgumentRefused,
    print_error,
    typed_lead,
    usage_refusal,
)
from ._diagnose import diagnosis
from ._reasons import as_said, reason
from ._signals import on_first_signal

__all__ = [
    "FOLLOW_MAX_FAILURES",
    "FOLLOW_RECONNECT_ATTEMPTS",
    "NATIVE",
    "PACKED",
    "PROTOCOLS",
    "Go",
    "Handler",
    "HintedError",
    "Output",
    "PackedGo",
    "PackedOnly",
    "command_name",
    "report_state",
    "runner",
    "stopping_on_signals",
    "tls_context",
    "tls_context_wanted",
    "write",
]


@dataclass(frozen=True, slots=True)
class Output:
    """What a command prints: ``text`` normally, ``data`` (JSON) with ``--json``."""

    data: Any
    text: str


#: Talks to the CNC on either transport; returns what to print (None: the command printed as
#: it went).
Go = Callable[[CncClient], Awaitable[Output | None]]
#: Talks to the CNC with calls only the packed protocol carries.
PackedGo = Callable[[FocasClient], Awaitable[Output | None]]

#: ``--protocol``: the packed protocol (this project's servers) or FOCAS/2 Ethernet (real
#: controls, and ``focas-net serve`` on the same port).
PACKED: Final = "packed"
NATIVE: Final = "native"
PROTOCOLS: Final = (PACKED, NATIVE)


@dataclass(frozen=True, slots=True)
class PackedOnly:
    """A command's talk that only the packed transport carries, and why (the calls it needs);
    ``option`` names the option that asks for it when the command itself is carried
    (``--force`` of ``pmc write``)."""

    go: PackedGo
    why: str
    option: str = ""


#: The commands that run until told (Ctrl-C, SIGTERM), besides ``alarms --follow``.
UNTIL_TOLD: Final = frozenset({"watch"})

#: A client command: its parsed arguments -> the talk to the CNC.
Handler = Callable[[argparse.Namespace], Go | PackedOnly]


class HintedError(FocasError):
    """A failure with advice for the user appended to its one-line text."""

    def __init__(self, cause: FocasError, hint: str) -> None:
        super().__init__(f"{cause}; {hint}")
        self.cause = cause
        self.hint = hint


@contextlib.contextmanager
def stopping_on_signals(stop: Callable[[], object]) -> Iterator[None]:
    """``stop()``, in the running loop, on SIGINT or SIGTERM while the block runs (a command
    that runs until told: it ends cleanly, exit 0, no traceback, and a second Ctrl-C while it
    ends is ignored, :mod:`._signals`); the loop wakes at once, whichever of the process's
    threads the signal reaches. Off the main thread Ctrl-C still ends it as usual. Blocks
    nest: a signal calls the innermost block's ``stop``."""
    loop = asyncio.get_running_loop()

    def told() -> None:
        try:
            loop.call_soon_threadsafe(stop)
        except RuntimeError:  # pragma: no cover - the loop closed meanwhile
            pass

    with on_first_signal(told, loop):
        yield


async def _until_told(session: Awaitable[Output | None]) -> Output | None:
    """Run the session of a command that runs until told (``watch``, ``alarms --follow``):
    SIGINT or SIGTERM at any moment, while it connects or makes its first read too, ends it
    as Ctrl-C ends its polling (None: nothing more to print, exit 0)."""
    task = asyncio.ensure_future(session)
    with stopping_on_signals(task.cancel):
        try:
            return await task
        except asyncio.CancelledError:
            current = asyncio.current_task()
            if task.cancelled() and (current is None or not current.cancelling()):
                return None
            raise


def write(text: str) -> bool:
    """``text`` on stdout, flushed; a reader that went away (``| head``) ends the output:
    False from then on. Output that cannot be written (a full disk) is one line on stderr
    and exit 1 (:class:`SystemExit`)."""
    try:
        sys.stdout.write(text)
        sys.stdout.flush()
    except BrokenPipeError:
        _stdout_to_devnull()
        return False
    except OSError as exc:
        _stdout_to_devnull()
        print_error(f"cannot write the output: {os_words(exc)}")
        raise SystemExit(EXIT_CNC) from None
    return True


def _stdout_to_devnull() -> None:
    """Stop writing without a traceback at exit (the final flush goes nowhere)."""
    devnull = os.open(os.devnull, os.O_WRONLY)
    os.dup2(devnull, sys.stdout.fileno())
    os.close(devnull)


def _print_one_line(message: str) -> None:
    print_error(fmt.one_line(message))


def _emit(args: argparse.Namespace, out: Output) -> None:
    if args.json:
        write(json.dumps(out.data, indent=2) + "\n")
    elif out.text:
        write(out.text.rstrip("\n") + "\n")


def _exit_code(exc: BaseException) -> int:
    if isinstance(exc, HintedError | ChunkedWriteError):
        return _exit_code(exc.cause)
    if isinstance(exc, NativeUnsupportedError):
        return EXIT_USAGE
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
        raise ArgumentRefused("--tls-insecure", "not allowed with --tls-ca")
    if insecure:
        ctx = ssl.SSLContext(ssl.PROTOCOL_TLS_CLIENT)
        ctx.check_hostname = False
        ctx.verify_mode = ssl.CERT_NONE
        return ctx
    try:
        return ca_context(ca)
    except ValueError as exc:
        raise ArgumentRefused("--tls-ca", f"{ca}: {exc}") from None


async def _session(
    args: argparse.Namespace, go: Go | PackedOnly, follow: bool, context: ssl.SSLContext | None
) -> Output | None:
    # A command's handler may set its own policy (``watch`` reconnects for ever).
    policy: ReconnectPolicy | None = getattr(args, "reconnect_policy", None)
    if policy is None and follow:
        policy = ReconnectPolicy(max_attempts=FOLLOW_RECONNECT_ATTEMPTS)
    reconnect: ReconnectPolicy | bool = policy if policy is not None else False
    if isinstance(go, PackedOnly) or _protocol(args) == PACKED:
        packed = FocasClient(
            args.host,
            args.port,
            timeout=args.timeout,
            password=getattr(args, "password", None),
            reconnect=reconnect,
            ssl=context,
            path=getattr(args, "path", 1),
        )
        async with packed:
            await _check_path(packed, args)
            return await (go.go(packed) if isinstance(go, PackedOnly) else go(packed))
    native = NativeClient(
        args.host,
        args.port,
        timeout=args.timeout,
        reconnect=reconnect,
        path=getattr(args, "path", 1),
    )
    async with native:
        await _check_path(native, args)
        return await go(native)


async def _check_path(client: CncClient, args: argparse.Namespace) -> None:
    """``--path N`` (N above 1) on a CNC with fewer paths is EW_PATH for every command, as
    ``cnc_setpath`` refuses it, also for the reads no path changes (``sysinfo``, ``pmc``,
    the history), which would otherwise answer as though the path were there."""
    path = getattr(args, "path", 1)
    if path == 1:
        return
    args.path_count = (await client.read_paths()).count  # for the refusal's words (_reasons)
    if path > args.path_count:
        raise CncError.from_ew(EW.PATH, "cnc_setpath")


def _protocol(args: argparse.Namespace) -> str:
    return str(getattr(args, "protocol", PACKED))


def command_name(args: argparse.Namespace) -> str:
    """The command as typed: ``param set``, ``status``, ``program list``, ``sim cycle start``."""
    name = str(getattr(args, "command", "?"))
    words = [name, getattr(args, f"{name}_command", None), getattr(args, "action", None)]
    return " ".join(w for w in words if isinstance(w, str))


def _check_native(args: argparse.Namespace, go: Go | PackedOnly) -> None:
    """With ``--protocol native``: a ``ValueError`` (exit 2) naming the command, or the option,
    that FOCAS/2 Ethernet cannot carry."""
    if _protocol(args) != NATIVE:
        return
    where = "with --protocol native (FOCAS/2 Ethernet)"
    if isinstance(go, PackedOnly):
        what = " ".join(w for w in (command_name(args), go.option) if w)
        raise ValueError(f"{what} is not available {where}: {go.why}")
    if tls_context_wanted(args):
        flag = next(
            f
            for f, on in (
                ("--tls", getattr(args, "tls", False)),
                ("--tls-ca", getattr(args, "tls_ca", None) is not None),
                ("--tls-insecure", getattr(args, "tls_insecure", False)),
            )
            if on
        )
        raise ValueError(
            f"{flag} does not apply {where}: FOCAS/2 has no TLS; use --protocol packed for TLS"
        )
    if getattr(args, "password", None) is not None:
        raise ValueError(
            f"{command_name(args)} --password is not available {where}: "
            "FOCAS/2 has no cnc_wrunlockparam"
        )


def report_state(client: CncClient) -> Callable[[ClientState], None]:
    """A state callback of a command that follows the CNC (``alarms --follow``): a line on
    stderr when the connection is lost and when it is back (added once the CNC answered:
    before that, a failure is the command's, as a one-shot command's)."""
    lost = False
    where = fmt.address_text(client.host, client.port)

    def report(state: ClientState) -> None:
        nonlocal lost
        if state is ClientState.RECONNECTING:
            lost = True
            why = client.lost_reason
            _print_one_line(f"connection to {where} lost{f': {why}' if why else ''}; reconnecting")
        elif state is ClientState.CONNECTED and lost:
            lost = False
            _print_one_line(f"reconnected to {where}")

    return report


def _ssl_cause(exc: BaseException) -> BaseException | None:
    """The SSL error ``exc`` was raised for, through the errors it was passed on as (a call
    fails with its connection's error as its cause)."""
    for _ in range(4):  # (a chain of a few links at most)
        cause = exc.__cause__
        if cause is None or isinstance(cause, ssl.SSLError):
            return cause
        exc = cause
    return None


def _tls_hint(args: argparse.Namespace, exc: BaseException) -> str | None:
    """Advice when ``exc`` itself shows TLS on one side only (the probes of
    :func:`._diagnose.diagnosis` found nothing certain)."""
    tls = tls_context_wanted(args)
    cause = exc.__cause__
    if isinstance(cause, ssl.SSLCertVerificationError):
        if cause.verify_code in _NAME_MISMATCH:  # trusted, but for another name
            return (
                f"the certificate does not name {args.host}: connect by a name it holds "
                "(--host NAME), or give --tls-insecure"
            )
        ca = getattr(args, "tls_ca", None)
        if ca is not None:  # the file given trusts another certificate
            return (
                f"the server's certificate is neither in --tls-ca {ca} nor signed by a "
                "certificate there: give its own certificate or its CA's, or --tls-insecure"
            )
        return "give --tls-ca FILE (the server's certificate or its CA) or --tls-insecure"
    alert = _ssl_cause(exc)
    if wants_client_certificate(alert) is not False:  # (the server's alert says so)
        return _NO_CLIENT_CERTIFICATE  # (what the command line cannot give)
    if peer_alert(alert):
        return None  # (a server that refused the handshake speaks TLS)
    text = str(exc)
    if tls and isinstance(exc, FocasConnectionError) and "TLS handshake failed" in text:
        return "if the server is plain TCP, drop --tls"
    if not tls and isinstance(exc, ProtocolError) and "TLS record" in text:
        return "the server uses TLS: give --tls (with --tls-ca FILE or --tls-insecure)"
    return None


#: The advice for a server that wants a client certificate (or may: a TLS 1.2 alert).
_NO_CLIENT_CERTIFICATE: Final = (
    "the command line sends no client certificate: connect from Python, with FocasClient's "
    "ssl= a context holding one (SSLContext.load_cert_chain)"
)

#: OpenSSL's verify codes of a certificate that holds another host name, or IP address.
_NAME_MISMATCH: Final = frozenset({62, 64})


def tls_context_wanted(args: argparse.Namespace) -> bool:
    """Whether the TLS options ask for TLS."""
    return bool(
        getattr(args, "tls", False)
        or getattr(args, "tls_ca", None) is not None
        or getattr(args, "tls_insecure", False)
    )


def _failure_text(args: argparse.Namespace, exc: BaseException, hint: str | None = None) -> str:
    if isinstance(exc, HintedError):
        return f"{_failure_text(args, exc.cause)}; {exc.hint}"
    if hint is None and isinstance(exc, CncError):
        hint = reason(command_name(args), args, exc)
        if hint is not None:
            exc = as_said(command_name(args), exc, hint)  # (its reason said once: the hint's)
    text = fmt.error_line(exc)
    if isinstance(exc, ValueError):  # a number the command read, named as typed
        text = typed_lead(text, args)
    if isinstance(exc, FocasTimeoutError):
        after = f"timed out after {args.timeout:g} s"
        if "timed out" in text:  # (the client's words say so: once, with the time)
            text = text.replace("timed out", after, 1)
        else:
            where = fmt.address_text(args.host, args.port)
            # the peer once: the client's words name it when it was connected to
            shown = "" if where in text else f" ({where})"
            text = f"{after}{shown}: {text}"
    if hint is None and _protocol(args) != NATIVE:
        hint = _tls_hint(args, exc)
    return text if hint is None else f"{text}; {hint}"


def _diagnosed(
    args: argparse.Namespace, go: Go | PackedOnly, exc: BaseException
) -> tuple[BaseException, str | None]:
    """``exc`` of a command's connection, or what the probes of the port found it was, and
    advice (:mod:`._diagnose`)."""
    if not isinstance(exc, FocasError):
        return exc, None
    protocol = PACKED if isinstance(go, PackedOnly) else _protocol(args)
    tls = protocol == PACKED and tls_context_wanted(args)
    packed_only = _packed_only(args, go)
    if isinstance(exc, HintedError):  # (alarms --follow gave up): its cause diagnosed
        # while reconnecting, the cause's own cause is why the last attempt failed: that is
        # what the port did (an HTTP server in place of the CNC is found as on a first connect)
        attempt = exc.cause.__cause__
        diagnosed = attempt if isinstance(attempt, FocasError) else exc.cause
        cause, advice = diagnosis(
            diagnosed, args.host, args.port, protocol, tls, args.timeout, packed_only
        )
        if cause is diagnosed:
            cause = exc.cause  # (no other error found: the one the follower gave up on)
        if not isinstance(cause, FocasError) or (cause is exc.cause and advice is None):
            return exc, None
        return HintedError(cause, exc.hint if advice is None else f"{advice}; {exc.hint}"), None
    return diagnosis(exc, args.host, args.port, protocol, tls, args.timeout, packed_only)


def _packed_only(args: argparse.Namespace, go: Go | PackedOnly) -> str | None:
    """What the command needs that FOCAS/2 cannot carry: the command itself, or its
    ``--password`` (None: it runs on either transport)."""
    if isinstance(go, PackedOnly):
        return command_name(args)
    if getattr(args, "password", None) is not None:
        return "--password"
    return None


def runner(handler: Handler) -> Callable[[argparse.Namespace], int]:
    """``args -> exit code``: parse, connect, run, print; failures become one line."""

    def run(args: argparse.Namespace) -> int:
        follow = bool(getattr(args, "follow", False))
        try:
            go = handler(args)
            _check_native(args, go)
            context = tls_context(args)
        except ValueError as exc:  # judged without the CNC: in the parser's words
            usage_refusal(exc, args)
            return EXIT_USAGE
        except (FocasError, OSError) as exc:
            _print_one_line(_failure_text(args, exc))
            return _exit_code(exc)
        try:
            session = _session(args, go, follow, context)
            until_told = follow or command_name(args) in UNTIL_TOLD
            main = _until_told(session) if until_told else session
            try:
                out = asyncio.run(main)
            finally:  # Ctrl-C before the loop ran them: no warning of coroutines never awaited
                main.close()
                session.close()
        except (FocasError, ValueError, OSError) as exc:
            failure, hint = _diagnosed(args, go, exc)
            _print_one_line(_failure_text(args, failure, hint))
            return _exit_code(failure)
        if out is not None:
            _emit(args, out)
        return EXIT_OK

    return run
