"""FANUC ``EW_*`` return codes, their OPC UA status mapping, and the exception tree.

Everything a caller needs to interpret an error lives here, in one table:

* :class:`EW` — the return codes of FANUC's ``fwlib32.h`` (aliases share a value);
* :data:`EW_TABLE` — for each code its canonical name, its aliases, its meaning and the
  OPC UA status a gateway should publish;
* the exceptions raised by the rest of the library.

Exception tree::

    FocasError
     +-- CncError                the CNC answered an EW code other than EW_OK
     |    +-- AccessDeniedError  EW_PASSWD (protection / password), OPC UA BadUserAccessDenied
     +-- ChunkedWriteError       a multi-call PMC write failed part way (says what was written)
     +-- ProtocolError           the peer broke the wire protocol
     |    +-- FrameError         framing violation: the connection must be closed
     |    +-- PayloadError       a payload that does not decode (wrong size, bad layout)
     +-- FocasConnectionError    the connection is down (also a builtin ``ConnectionError``)
     +-- FocasTimeoutError       no answer in time (also a builtin ``TimeoutError``)
"""

from __future__ import annotations

import enum
from dataclasses import dataclass
from typing import Any, Final

__all__ = [
    "EW",
    "EW_TABLE",
    "OPCUA_BAD_COMMUNICATION_ERROR",
    "OPCUA_BAD_TIMEOUT",
    "OPCUA_BAD_UNEXPECTED_ERROR",
    "OPCUA_GOOD",
    "AccessDeniedError",
    "ChunkedWriteError",
    "CncError",
    "EwInfo",
    "FocasConnectionError",
    "FocasError",
    "FocasTimeoutError",
    "FrameError",
    "OpcUaStatus",
    "PayloadError",
    "ProtocolError",
    "ew_info",
    "ew_label",
    "ew_name",
]


class EW(enum.IntEnum):
    """FANUC FOCAS return codes (``fwlib32.h``). Aliases share a value."""

    OK = 0
    FUNC = 1
    NOPMC = 1
    LENGTH = 2
    NUMBER = 3
    RANGE = 3
    ATTRIB = 4
    TYPE = 4
    DATA = 5
    NOOPT = 6
    PROT = 7
    OVRFLOW = 8
    PARAM = 9
    BUFFER = 10
    PATH = 11
    MODE = 12
    REJECT = 13
    DTSRVR = 14
    ALARM = 15
    STOP = 16
    PASSWD = 17
    BUSY = -1
    RESET = -2
    HANDLE = -8
    SOCKET = -16
    PROTOCOL = -17


@dataclass(frozen=True, slots=True)
class OpcUaStatus:
    """An OPC UA status code: its symbolic name and its 32-bit value."""

    name: str
    value: int

    def __str__(self) -> str:
        return f"{self.name} (0x{self.value:08X})"


OPCUA_GOOD: Final = OpcUaStatus("Good", 0x00000000)
_BAD_UNEXPECTED: Final = OpcUaStatus("BadUnexpectedError", 0x80010000)
_BAD_INTERNAL: Final = OpcUaStatus("BadInternalError", 0x80020000)
_BAD_OUT_OF_MEMORY: Final = OpcUaStatus("BadOutOfMemory", 0x80030000)
_BAD_RESOURCE_UNAVAILABLE: Final = OpcUaStatus("BadResourceUnavailable", 0x80040000)
_BAD_COMMUNICATION: Final = OpcUaStatus("BadCommunicationError", 0x80050000)
_BAD_DECODING: Final = OpcUaStatus("BadDecodingError", 0x80070000)
_BAD_TIMEOUT: Final = OpcUaStatus("BadTimeout", 0x800A0000)
_BAD_USER_ACCESS_DENIED: Final = OpcUaStatus("BadUserAccessDenied", 0x801F0000)
_BAD_NOT_WRITABLE: Final = OpcUaStatus("BadNotWritable", 0x803B0000)
_BAD_OUT_OF_RANGE: Final = OpcUaStatus("BadOutOfRange", 0x803C0000)
_BAD_NOT_SUPPORTED: Final = OpcUaStatus("BadNotSupported", 0x803D0000)
_BAD_TYPE_MISMATCH: Final = OpcUaStatus("BadTypeMismatch", 0x80740000)
_BAD_CONFIGURATION: Final = OpcUaStatus("BadConfigurationError", 0x80890000)
_BAD_INVALID_ARGUMENT: Final = OpcUaStatus("BadInvalidArgument", 0x80AB0000)
_BAD_INVALID_STATE: Final = OpcUaStatus("BadInvalidState", 0x80AF0000)
_BAD_OPERATION_ABANDONED: Final = OpcUaStatus("BadOperationAbandoned", 0x80B30000)
_BAD_REQUEST_NOT_ALLOWED: Final = OpcUaStatus("BadRequestNotAllowed", 0x80E40000)

#: Status for a lost connection (no EW code involved).
OPCUA_BAD_COMMUNICATION_ERROR: Final = _BAD_COMMUNICATION
#: Status for a call that got no answer in time.
OPCUA_BAD_TIMEOUT: Final = _BAD_TIMEOUT
#: Status for an EW code this table does not know.
OPCUA_BAD_UNEXPECTED_ERROR: Final = _BAD_UNEXPECTED


@dataclass(frozen=True, slots=True)
class EwInfo:
    """One row of the EW table."""

    code: int
    name: str
    aliases: tuple[str, ...]
    meaning: str
    opcua: OpcUaStatus


def _row(code: EW, aliases: tuple[str, ...], meaning: str, opcua: OpcUaStatus) -> EwInfo:
    return EwInfo(int(code), f"EW_{code.name}", aliases, meaning, opcua)


#: The one table of EW codes: code -> name, aliases, meaning, OPC UA status.
EW_TABLE: Final[dict[int, EwInfo]] = {
    row.code: row
    for row in (
        _row(EW.OK, (), "success", OPCUA_GOOD),
        _row(EW.FUNC, ("EW_NOPMC",), "function not available", _BAD_NOT_SUPPORTED),
        _row(EW.LENGTH, (), "data block length error", _BAD_INVALID_ARGUMENT),
        _row(EW.NUMBER, ("EW_RANGE",), "data number / address range error", _BAD_OUT_OF_RANGE),
        _row(EW.ATTRIB, ("EW_TYPE",), "data attribute / data type error", _BAD_TYPE_MISMATCH),
        _row(EW.DATA, (), "data error", _BAD_INVALID_ARGUMENT),
        _row(EW.NOOPT, (), "option not installed", _BAD_NOT_SUPPORTED),
        _row(EW.PROT, (), "write-protected", _BAD_NOT_WRITABLE),
        _row(EW.OVRFLOW, (), "memory overflow", _BAD_OUT_OF_MEMORY),
        _row(EW.PARAM, (), "CNC parameter error", _BAD_CONFIGURATION),
        _row(EW.BUFFER, (), "buffer empty or full", _BAD_RESOURCE_UNAVAILABLE),
        _row(EW.PATH, (), "path number error", _BAD_OUT_OF_RANGE),
        _row(EW.MODE, (), "CNC mode error", _BAD_INVALID_STATE),
        _row(EW.REJECT, (), "execution rejected", _BAD_REQUEST_NOT_ALLOWED),
        _row(EW.DTSRVR, (), "data server error", _BAD_INTERNAL),
        _row(EW.ALARM, (), "alarm has occurred", _BAD_INVALID_STATE),
        _row(EW.STOP, (), "CNC not running", _BAD_INVALID_STATE),
        _row(EW.PASSWD, (), "protection / password error", _BAD_USER_ACCESS_DENIED),
        _row(EW.BUSY, (), "busy, retry", _BAD_RESOURCE_UNAVAILABLE),
        _row(EW.RESET, (), "reset or stop occurred", _BAD_OPERATION_ABANDONED),
        _row(EW.HANDLE, (), "handle invalid", _BAD_COMMUNICATION),
        _row(EW.SOCKET, (), "socket error", _BAD_COMMUNICATION),
        _row(EW.PROTOCOL, (), "protocol error", _BAD_DECODING),
    )
}


def ew_info(code: int) -> EwInfo:
    """The table row of ``code``; an unknown code gets a synthetic row (never raises)."""
    row = EW_TABLE.get(code)
    if row is None:
        return EwInfo(code, f"EW_UNKNOWN({code})", (), "unknown return code", _BAD_UNEXPECTED)
    return row


def ew_name(code: int) -> str:
    """The canonical name of ``code`` (``EW_PASSWD``), or ``EW_UNKNOWN(n)``."""
    return ew_info(code).name


def ew_label(code: int) -> str:
    """``code``'s name and number, each once: ``EW_PASSWD (17)``; ``EW_UNKNOWN(12345)`` for a
    code FOCAS does not define (its name already carries the number)."""
    name = ew_info(code).name
    return name if code not in EW_TABLE else f"{name} ({code})"


class FocasError(Exception):
    """Base class of every exception raised by focas_net."""


class CncError(FocasError):
    """The CNC answered an EW code other than ``EW_OK``.

    ``ew`` is the code, ``name`` its canonical name, ``meaning`` a short text and
    ``opcua_status`` the OPC UA status a gateway should publish. Construct it with
    :meth:`from_ew`, which returns :class:`AccessDeniedError` for ``EW_PASSWD``.
    """

    def __init__(self, ew: int, detail: str = "") -> None:
        info = ew_info(ew)
        self.ew: int = ew
        self.name: str = info.name
        self.meaning: str = info.meaning
        self.opcua_status: OpcUaStatus = info.opcua
        self.detail: str = detail
        text = f"{ew_label(ew)}: {info.meaning}"
        super().__init__(f"{text}: {detail}" if detail else text)

    def __reduce__(self) -> tuple[type[CncError], tuple[int, str]]:
        return (type(self), (self.ew, self.detail))

    @property
    def access_denied(self) -> bool:
        """True when the CNC refused for protection or password (``EW_PASSWD``)."""
        return self.ew == EW.PASSWD

    @staticmethod
    def from_ew(ew: int, detail: str = "") -> CncError:
        """The exception for ``ew``: :class:`AccessDeniedError` for ``EW_PASSWD``."""
        if ew == EW.PASSWD:
            return AccessDeniedError(ew, detail)
        return CncError(ew, detail)


class AccessDeniedError(CncError):
    """``EW_PASSWD``: protection or password error (OPC UA ``BadUserAccessDenied``)."""


class ChunkedWriteError(FocasError):
    """A PMC write split into several calls failed part way.

    ``written``, ``not_written`` and ``uncertain`` are lists of inclusive ``(first, last)``
    byte address ranges: confirmed by the CNC, refused or never sent, and sent but unanswered
    (a timeout or a lost connection: the CNC may or may not have applied them). ``cause`` is
    the exception of the first chunk that failed.
    """

    def __init__(
        self,
        area: str,
        written: list[tuple[int, int]],
        not_written: list[tuple[int, int]],
        cause: BaseException,
        uncertain: list[tuple[int, int]] | None = None,
    ) -> None:
        self.area = area
        self.written = written
        self.not_written = not_written
        self.uncertain = uncertain or []
        self.cause = cause

        def ranges(spans: list[tuple[int, int]]) -> str:
            return ", ".join(f"{area}{a}..{area}{b}" for a, b in spans) or "none"

        text = (
            f"PMC write to {area} failed ({cause}); written: {ranges(written)}; "
            f"not written: {ranges(not_written)}"
        )
        if self.uncertain:
            text += f"; unconfirmed: {ranges(self.uncertain)}"
        super().__init__(text)

    def __reduce__(self) -> tuple[type[ChunkedWriteError], tuple[Any, ...]]:
        return (
            type(self),
            (self.area, self.written, self.not_written, self.cause, self.uncertain),
        )

    @property
    def opcua_status(self) -> OpcUaStatus:
        """The OPC UA status of the cause."""
        return getattr(self.cause, "opcua_status", _BAD_UNEXPECTED)


class ProtocolError(FocasError):
    """The peer sent something the wire protocol does not allow."""

    opcua_status: OpcUaStatus = _BAD_DECODING


class FrameError(ProtocolError):
    """A framing violation (bad length prefix): the connection must be closed.

    ``frames`` holds the whole frames the same ``feed`` call decoded before the violation, in
    order, so that a receiver can still answer them before it closes.
    """

    def __init__(
        self, message: str, frames: list[Any] | None = None, length: int | None = None
    ) -> None:
        super().__init__(message)
        self.frames: list[Any] = frames if frames is not None else []
        #: the length prefix refused, when the violation is one
        self.length: int | None = length

    def __reduce__(self) -> tuple[type[FrameError], tuple[str]]:
        return (type(self), (str(self),))


class PayloadError(ProtocolError):
    """A payload that does not decode for its command (wrong size, bad layout)."""


class FocasConnectionError(FocasError, ConnectionError):
    """The connection to the CNC is down or was lost."""

    opcua_status: OpcUaStatus = _BAD_COMMUNICATION


class FocasTimeoutError(FocasError, TimeoutError):
    """The CNC did not answer in time."""

    opcua_status: OpcUaStatus = _BAD_TIMEOUT
