"""Payloads of the PMC range commands (``docs/protocol.md`` sections 3 and 4): ``pmc_rdpmcrng``
(0x0010), ``pmc_wrpmcrng`` (0x0104) and the simulator's ``set_pmc`` (0x0E04), all IODBPMC, and
the ``type_a`` codes of the PMC areas."""

from __future__ import annotations

import enum
import struct
from dataclasses import dataclass
from typing import ClassVar, Final, Self

from .._typed import field_unfit
from ..errors import PayloadError
from ._base import FixedPayload, field_error

__all__ = [
    "MAX_PMC_CHUNK",
    "PmcArea",
    "PmcData",
    "PmcRange",
    "pmc_address_unfit",
    "pmc_bit_refusal",
]

#: Most data bytes one PMC range call carries.
MAX_PMC_CHUNK: Final = 32
#: The highest PMC address a request carries (``datano_s`` and ``datano_e`` are ``u16``).
_MAX_PMC_ADDRESS: Final = 0xFFFF


class PmcArea(enum.IntEnum):
    """``type_a`` codes of this protocol (not FWLIB's adr_type numbers)."""

    X = 1
    Y = 2
    F = 3
    G = 4
    R = 5
    T = 6
    C = 7
    D = 8
    K = 10
    A = 11
    E = 12

    @classmethod
    def parse(cls, area: str | int | PmcArea) -> PmcArea:
        """``"R"``, ``PmcArea.R`` or ``5`` -> ``PmcArea.R``; ValueError for a letter or a number
        that is no area, TypeError (naming it) for anything else (``b"R"``, ``True``)."""
        if isinstance(area, PmcArea):
            return area
        if isinstance(area, str):
            try:
                return cls[area.strip().upper()]
            except KeyError:
                letters = ", ".join(a.name for a in cls)  # as the machine and the page say it
                raise ValueError(f"unknown PMC area {area!r} (one of {letters})") from None
        if isinstance(area, bool) or not isinstance(area, int):
            raise TypeError(
                f"a PMC area is its letter ('R'), a PmcArea or its number, got {area!r}"
            )
        try:
            return cls(area)
        except ValueError:
            raise ValueError(f"unknown PMC area number {area}") from None


def pmc_address_unfit(address: int) -> str | None:
    """Why ``address`` is no PMC address a request carries (its ``u16`` field), in the words
    every front end gives (``PMC start address 65536 is outside 0..65535``, as the client
    refuses it before sending); None when it is one (the machine says whether its area has
    it)."""
    return field_unfit("PMC start address", address, 0, _MAX_PMC_ADDRESS)


def pmc_bit_refusal(area: str, address: int, bit: int) -> str | None:
    """Why ``bit`` of PMC byte ``address`` of ``area`` (its letter) is no bit, in the words
    every front end gives (the command line's ``pmc bit R 1.8``, the dashboard's bit); None for
    a bit 0..7. An address the request's ``u16`` field cannot carry is refused first, as the
    client refuses it (``PMC start address 65536 is outside 0..65535``)."""
    beyond = pmc_address_unfit(address)
    if beyond is not None:
        return beyond
    if 0 <= bit <= 7:
        return None
    return f"{area}{address}.{bit}: bit {bit} is outside 0..7: a PMC address is 1 byte wide"


@dataclass(frozen=True, slots=True)
class PmcRange(FixedPayload):
    """IODBPMC header: ``i16 type_a, i16 type_d, u16 datano_s, u16 datano_e`` (inclusive)."""

    FORMAT: ClassVar[str] = "<hhHH"
    type_a: int
    type_d: int
    datano_s: int
    datano_e: int

    @property
    def count(self) -> int:
        return self.datano_e - self.datano_s + 1


_PMC_HEAD: Final = PmcRange.STRUCT


@dataclass(frozen=True, slots=True)
class PmcData:
    """IODBPMC with data: the 8-byte header then the bytes.

    The answer of ``pmc_rdpmcrng`` and the request of ``pmc_wrpmcrng`` and ``set_pmc``. The
    decoder does not check the data length against the header (the server answers a mismatch
    with EW_LENGTH, in the order of ``docs/protocol.md``).
    """

    type_a: int
    type_d: int
    datano_s: int
    datano_e: int
    data: bytes

    @property
    def header(self) -> PmcRange:
        return PmcRange(self.type_a, self.type_d, self.datano_s, self.datano_e)

    def encode(self) -> bytes:
        try:
            return _PMC_HEAD.pack(self.type_a, self.type_d, self.datano_s, self.datano_e) + (
                self.data
            )
        except struct.error as exc:
            fields: tuple[tuple[str, object, str], ...] = (
                ("type_a", self.type_a, "h"),
                ("type_d", self.type_d, "h"),
                ("start address", self.datano_s, "H"),
                ("end address", self.datano_e, "H"),
            )
            raise ValueError(field_error(fields, exc)) from None

    @classmethod
    def decode(cls, data: bytes) -> Self:
        if len(data) < 8:
            raise PayloadError(f"IODBPMC of {len(data)} bytes is shorter than its header")
        type_a, type_d, start, end = _PMC_HEAD.unpack_from(data, 0)
        return cls(type_a, type_d, start, end, data[8:])
