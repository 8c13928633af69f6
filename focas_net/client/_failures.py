"""The words of a connection that failed, the same for both clients: a peer that does not
speak the protocol, a connection lost or closed, a connect refused, a peer that says nothing.

Both transports say the same thing the same way, and raise the same kind of error for it: a
peer that breaks the framing is a :class:`ProtocolError` (``does not speak the FOCAS
protocol``); a connection the peer ends, by an end of stream or a reset (which of the two a
peer closing at once gives is a race), is a :class:`FocasConnectionError` ``connection closed
by HOST:PORT``; one lost otherwise reads ``connection to HOST:PORT lost: <why>``; both with
``before any answer`` when the peer never sent a byte. A call whose connection ended says the
connection's words alone once its request was sent, and adds :data:`NEVER_SENT` when it was
not. A call left unanswered is ``no answer to <its FOCAS function>`` (:func:`no_answer_error`),
and says so when the connection never received a byte (:data:`NOTHING_RECEIVED`). An
operating system error reads as its text (``connection refused``), never as Python shows the
exception.
"""

from __future__ import annotations

import asyncio
import errno
import ipaddress
import ssl as _ssl
from typing import Final

from focas_net._address import address_text
from focas_net._refusals import NO_CONTROL, READ_ONLY, axis_past, no_path
from focas_net._tls import alert_text, peer_alert, ssl_error_text, wants_client_certificate
from focas_net._typed import WRONG_PASSWORD, os_reason
from focas_net.errors import (
    EW,
    CncError,
    FocasConnectionError,
    FocasTimeoutError,
    FrameError,
    PayloadError,
    ProtocolError,
)
from focas_net.protocol import Command
from focas_net.protocol.codecs import COMMANDS
from focas_net.protocol.frame import DEFAULT_MAX_FRAME, is_tls_record

__all__ = [
    "BEFORE_ANY_ANSWER",
    "ECHOED",
    "NEVER_SENT",
    "NOTHING_RECEIVED",
    "WANTS_CERTIFICATE",
    "axis_refusal",
    "closed_error",
    "code_reason",
    "command_text",
    "connect_error",
    "connect_reason",
    "echo_error",
    "lost_error",
    "native_call_text",
    "no_answer_error",
    "not_focas_error",
    "path_refusal",
    "timeout_error",
    "undecodable_error",
    "violation_error",
]

#: What a connection that ended says when the peer never sent a byte on it.
BEFORE_ANY_ANSWER: Final = "before any answer"
#: What a timeout says when the connection never received a byte.
NOTHING_RECEIVED: Final = "nothing received since connecting"
#: What a failed call adds when its request never left (a call safe to send again).
NEVER_SENT: Final = "(the request was never sent)"
#: The operating system's errors of a peer that ended the connection: a reset (a peer that
#: closes with data unread, or closes at once and meets the request), a write after its close.
_PEER_ENDED: Final = (ConnectionResetError, BrokenPipeError, asyncio.IncompleteReadError)


def command_text(command: int) -> str:
    """A packed command by its FOCAS name and its id: ``cnc_rdcncstat (0x0001)``,
    ``sim_set_pmc (0x0E04)``; an id the protocol does not have by its id alone."""
    spec = COMMANDS.get(command)
    return f"0x{command:04X}" if spec is None else f"{spec.focas_name} (0x{command:04X})"


def code_reason(command: int, ew: int) -> str | None:
    """Why a packed ``command`` was answered ``ew``, where the code alone tells it, in the
    words of the machine and the command line: EW_PASSWD of ``cnc_wrunlockparam`` (the
    password is not the CNC's); of a simulator control command (0x0Exx), EW_FUNC (the server
    serves no control commands) and EW_PROT (the machine is read-only; a vacated macro
    variable's is its own); None for another command or code."""
    if command == Command.WRUNLOCKPARAM and ew == EW.PASSWD:
        return WRONG_PASSWORD
    if not 0x0E00 <= command <= 0x0EFF:
        return None
    if ew == EW.FUNC:
        return NO_CONTROL
    if ew == EW.PROT and command != Command.SIM_VACATE_MACRO:
        return READ_ONLY
    return None


def native_call_text(function: str, command: int) -> str:
    """A FOCAS/2 request by the library function that sent it and its command id:
    ``cnc_statinfo (0x19)``."""
    return f"{function} (0x{command:02X})"


def undecodable_error(peer: str, call: str, exc: Exception) -> PayloadError:
    """The error of an answer of ``peer`` to ``call`` (:func:`command_text` of a packed
    command, :func:`native_call_text` of a FOCAS/2 one) that does not decode: the peer, the
    call and why (an answer too short for its EW code, or for its record), in the same words
    on both transports."""
    err = PayloadError(f"{peer} sent an answer to {call} that does not decode: {exc}")
    err.__cause__ = exc
    return err


#: The EW codes a CNC answers (an answer of another is no CNC's).
_KNOWN_EW: Final = frozenset(int(ew) for ew in EW)
#: Why a peer that sent back the request it was sent does not speak FOCAS.
ECHOED: Final = "it sent back the request it was sent, as an echo server does"


def echo_error(peer: str, command: int, raw: bytes, sent: bytes) -> ProtocolError | None:
    """The error of ``peer`` answering a packed ``command`` with ``raw``, the very payload
    ``sent`` in its request, or None when that may be a FOCAS answer: a known EW code alone
    (2 bytes) can equal a request's 2 bytes (``cnc_rdmacro`` of #5 refused ``EW_DATA``, 5),
    but no answer repeats a longer request or an empty one (every answer has its EW code,
    and an EW code other than 0 is its whole payload). Asked only of an answer that does
    not decode or carries an EW code."""
    if raw != sent:
        return None
    if len(raw) == 2 and int.from_bytes(raw, "little", signed=True) in _KNOWN_EW:
        return None
    return not_focas_error(peer, f"{ECHOED}: {command_text(command)}")


def not_focas_error(peer: str, why: str) -> ProtocolError:
    """The error of ``peer`` that does not speak the FOCAS protocol (``why``: what it did)."""
    return ProtocolError(f"{peer} does not speak the FOCAS protocol ({why})")


def violation_error(
    peer: str, reason: str | BaseException, head: bytes, max_frame: int = DEFAULT_MAX_FRAME
) -> ProtocolError:
    """The error of a framing violation by ``peer``: it does not speak the FOCAS protocol.

    ``reason`` says which rule it broke; ``head`` (the first bytes of the offending chunk) is
    shown as text, so that an HTTP answer reads as one; a TLS record is named as such. A
    frame refused only for the client's own ``max_frame``, lower than the default, is named
    as that, not as a peer of another protocol.
    """
    length = reason.length if isinstance(reason, FrameError) else None
    if length is not None and max_frame < length <= DEFAULT_MAX_FRAME:
        return ProtocolError(
            f"{peer} sent a frame of {length} bytes, more than this client's "
            f"max_frame={max_frame} takes (a FOCAS answer may be up to "
            f"{DEFAULT_MAX_FRAME} bytes: give a larger max_frame)"
        )
    if is_tls_record(head):
        what = "it sent a TLS record: the server expects TLS"
    else:
        what = f"it sent {bytes_text(head[:8])}"
    rule = str(reason).removesuffix("; closing the connection")
    return not_focas_error(peer, f"{rule}; {what}")


def bytes_text(data: bytes) -> str:
    """A peer's bytes as a user reads them: quoted text when all are printable ASCII
    (``'HTTP/1.1'``), else hexadecimal bytes (``A0 A0 00 03``), never a Python repr."""
    if data and all(0x20 <= b < 0x7F for b in data):
        return f"'{data.decode('ascii')}'"
    return data.hex(" ").upper()


#: What a TLS connection closed before any answer adds: a server that wants a client
#: certificate and got none ends it so, once the client's handshake is done (TLS 1.3), and a
#: server of asyncio's (``focas-net``'s among them) drops the alert that would say so; a
#: server at its connection limit may close so too, after the handshake.
WANTS_CERTIFICATE: Final = (
    "(a TLS server closes so when it wants a client certificate and gets none, or at its "
    "connection limit)"
)


def closed_error(peer: str, answered: bool, tls: bool = False) -> FocasConnectionError:
    """The error of a connection ``peer`` closed (``answered``: it had sent a byte; ``tls``:
    a TLS connection, which a server that wants a client certificate closes so)."""
    text = f"connection closed by {peer}"
    if not answered:
        text += f" {BEFORE_ANY_ANSWER}" + (f" {WANTS_CERTIFICATE}" if tls else "")
    return FocasConnectionError(text)


def lost_error(
    peer: str, exc: BaseException | None, answered: bool = True, tls: bool = False
) -> FocasConnectionError:
    """The error of a connection to ``peer`` that ended for ``exc`` (None: the peer closed
    it; a reset reads the same; ``tls``: over TLS); an error of this package is its own. An
    SSL error reads in OpenSSL's words without their tags (a server's alert that it wants a
    client certificate says so)."""
    if isinstance(exc, FocasConnectionError):
        return exc
    if exc is None or isinstance(exc, _PEER_ENDED):
        err = closed_error(peer, answered, tls)
    else:
        when = "" if answered else f" {BEFORE_ANY_ANSWER}"
        why = alert_text(exc) if isinstance(exc, _ssl.SSLError) else os_reason(exc)
        err = FocasConnectionError(f"connection to {peer} lost{when}: {why}")
    err.__cause__ = exc
    return err


def path_refusal(function: str, path: int, paths: int) -> CncError:
    """EW_PATH of a call of ``function`` for ``path``, which a CNC of ``paths`` paths does not
    have, in the words of both clients, the machine and the command line: ``cnc_statinfo: the
    CNC has no path 3: it has path 1 only``."""
    return CncError.from_ew(EW.PATH, f"{function}: {no_path(path, paths)}")


def axis_refusal(function: str, axis: int, axes: int) -> CncError:
    """EW_ATTRIB of a call of ``function`` for ``axis``, past the ``axes`` of the path, in the
    words of both clients (which check it before sending, as FANUC's library does) and the
    machine: ``cnc_wrparam: axis 9 is outside 1..3: the path has 3 axes``."""
    return CncError.from_ew(EW.ATTRIB, f"{function}: {axis_past(axis, axes)}")


def no_answer_error(call: str, peer: str | None, sent: bool = True) -> FocasTimeoutError:
    """The error of ``call`` (its FOCAS function's name) left unanswered by its deadline;
    ``peer`` when the connection to it never received a byte; ``sent``: its request left."""
    return timeout_error(f"no answer to {call}" + ("" if sent else f" {NEVER_SENT}"), peer)


def timeout_error(what: str, peer: str | None) -> FocasTimeoutError:
    """The error of ``what`` unanswered in time; ``peer`` when the connection to it never
    received a byte (a peer that is not a FOCAS server, an HTTP server for one, may wait for
    more and say nothing)."""
    if peer is None:
        return FocasTimeoutError(what)
    return FocasTimeoutError(f"{what}: {NOTHING_RECEIVED} to {peer}")


def _unscoped_link_local(host: str) -> bool:
    try:
        address = ipaddress.ip_address(host)
    except ValueError:
        return False
    return isinstance(address, ipaddress.IPv6Address) and (
        address.is_link_local and address.scope_id is None
    )


def connect_error(
    host: str, port: int, exc: BaseException, ssl: _ssl.SSLContext | None
) -> FocasConnectionError:
    """The error of a connect to ``host:port`` that failed for ``exc``: ``cannot connect to
    HOST:PORT: <why>``, but for a reset without TLS, which is a peer that accepted the
    connection and closed it at once (whether its reset meets the connect or the request is
    a race): ``connection closed by HOST:PORT before any answer``, as it reads after the
    connect."""
    where = address_text(host, port)
    if ssl is None and isinstance(exc, ConnectionResetError):
        err = closed_error(where, answered=False)
    else:
        err = FocasConnectionError(f"cannot connect to {where}: {connect_reason(exc, ssl, host)}")
    err.__cause__ = exc
    return err


def _handshake_why(exc: BaseException) -> str:
    """Why a TLS handshake failed with ``exc``: a peer that sent an alert speaks TLS and
    refused it (a client certificate it wants, maybe), another may not speak TLS."""
    if not peer_alert(exc):
        return "the peer may not speak TLS"
    wants = wants_client_certificate(exc)
    if wants:
        return "the server wants a client certificate"
    if wants is None:
        return (
            "the server refused it: it may want a client certificate, or share no TLS "
            "version or cipher with this client"
        )
    return "the server refused it"


def connect_reason(exc: BaseException, ssl: _ssl.SSLContext | None, host: str = "") -> str:
    """Why a connect to ``host`` failed, never empty; a failed TLS handshake says so, and so
    does a link-local IPv6 address without its interface (which no connect can reach)."""
    text = str(exc)
    if isinstance(exc, OSError) and exc.errno == errno.EINVAL and _unscoped_link_local(host):
        return (
            f"{os_reason(exc)}: {host} is a link-local address, which needs its interface "
            f"({host}%eth0, the interface's name or number after %)"
        )
    if isinstance(exc, _ssl.SSLCertVerificationError):
        return f"TLS certificate not trusted: {(exc.verify_message or text).rstrip('.')}"
    # a refused connect never reached the handshake: it reads as without TLS
    handshake = isinstance(exc, _ssl.SSLError) or (
        isinstance(exc, ConnectionError) and not isinstance(exc, ConnectionRefusedError)
    )
    if ssl is not None and handshake:
        # (OpenSSL's words without its library tag and source line)
        detail = ssl_error_text(exc) if isinstance(exc, _ssl.SSLError) else ""
        detail = detail or "the peer closed it"
        return f"TLS handshake failed ({detail}): {_handshake_why(exc)}"
    return os_reason(exc)
