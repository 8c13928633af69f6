"""The calls both clients make of a few primitives: :class:`CompositeCalls`.

A parameter read typed as FANUC types it, a bit of a parameter or of a PMC byte changed by
read-modify-write under a per-key lock, and a PMC range read or written over calls of one
transport's size, with :class:`~focas_net.errors.ChunkedWriteError` meaning the same on both
transports. Each transport gives the primitives (reading and writing one parameter, its type,
reading a PMC range, writing PMC chunks) and everything above them is written here once.

A bit write is atomic against the bit writes **of the same client object** only: the lock is
the client's, and neither protocol has a bit operation, so two clients (or a client and
FANUC's library) writing bits of one byte at once can undo each other's change. FANUC's
library gives no more: it has no bit write and no lock, so two programs using it lose bits
the same way. Share one client among the tasks that write bits (docs/client.md, "One client
for many tasks").
"""

# Every call takes a per-call ``timeout=`` by contract, so ASYNC109 does not apply here.
# ruff: noqa: ASYNC109

from __future__ import annotations

from collections.abc import AsyncIterator, Awaitable, Callable, Sequence
from contextlib import asynccontextmanager
from decimal import Decimal

from focas_net._refusals import axis_misfit, macro_refusal, param_refusal, pmc_refusal
from focas_net.errors import EW, ChunkedWriteError, CncError

from .._typed import typed_number
from ..protocol import ParamValue, PmcArea
from ._lifecycle import Lifecycle
from ._locks import KeyedLocks
from ._values import (
    REAL_WIDTH,
    AreaLike,
    bits_shaped,
    check_bit,
    check_bit_value,
    check_item,
    check_pmc_range,
    not_finite,
    pmc_data,
)

__all__ = [
    "ChunkOutcome",
    "CompositeCalls",
    "chunked_write_error",
    "macro_named",
    "param_named",
    "pmc_named",
    "pmc_named_error",
    "write_chunked",
]

#: What became of one chunk of a chunked write: None (written, the CNC said so), or the
#: exception it ended with and whether it is *unanswered*: its request left and no answer
#: came (its deadline passed, or the connection was lost after it left).
ChunkOutcome = tuple[Exception, bool] | None


def _merge(spans: list[tuple[int, int]]) -> list[tuple[int, int]]:
    """Merge sorted inclusive ``(first, last)`` spans that touch."""
    merged: list[tuple[int, int]] = []
    for first, last in spans:
        if merged and merged[-1][1] + 1 == first:
            merged[-1] = (merged[-1][0], last)
        else:
            merged.append((first, last))
    return merged


def chunked_write_error(
    area: str, spans: Sequence[tuple[int, int]], outcomes: Sequence[ChunkOutcome]
) -> ChunkedWriteError | None:
    """The :class:`ChunkedWriteError` of a write of ``area`` whose chunk ``spans`` (inclusive
    byte ranges, in order) ended with ``outcomes``; None when every chunk was written.

    A chunk is *written* when the CNC confirmed it, *uncertain* when it is unanswered (sent,
    and no answer came: the CNC may have applied it), and *not written* otherwise (refused
    with an EW code, or never sent).
    """
    written: list[tuple[int, int]] = []
    not_written: list[tuple[int, int]] = []
    uncertain: list[tuple[int, int]] = []
    cause: Exception | None = None
    for span, outcome in zip(spans, outcomes, strict=True):
        if outcome is None:
            written.append(span)
            continue
        error, unanswered = outcome
        cause = cause or error
        if unanswered:
            uncertain.append(span)
        else:
            not_written.append(span)
    if cause is None:
        return None
    error = ChunkedWriteError(area, _merge(written), _merge(not_written), cause, _merge(uncertain))
    error.__cause__ = cause
    return error


async def write_chunked(
    area: PmcArea,
    start: int,
    data: bytes,
    step: int,
    write: Callable[[Sequence[tuple[int, bytes]]], Awaitable[list[ChunkOutcome]]],
) -> None:
    """Write ``data`` to ``area`` from ``start`` (a checked range) in chunks of at most
    ``step`` bytes with ``write`` (every chunk at once, their outcomes in order): the one
    chunk's failure as it is, or :class:`ChunkedWriteError` when a chunk of several fails."""
    chunks = [
        (s, data[s - start : s - start + step]) for s in range(start, start + len(data), step)
    ]
    outcomes = [
        None
        if outcome is None
        else (pmc_named_error(outcome[0], area, first, len(part)), outcome[1])
        for outcome, (first, part) in zip(await write(chunks), chunks, strict=True)
    ]
    if len(chunks) == 1:
        if outcomes[0] is not None:
            raise outcomes[0][0]
        return
    spans = [(first, first + len(part) - 1) for first, part in chunks]
    error = chunked_write_error(area.name, spans, outcomes)
    if error is not None:
        raise error


def pmc_named_error(exc: Exception, area: PmcArea, start: int, count: int) -> Exception:
    """``exc``, the refusal of ``count`` bytes of ``area`` from ``start`` (one call's, or one
    chunk's), naming why in the words of the command line (``R7990..R8009 goes past the end of
    PMC area R``) when it is a :class:`CncError` whose code says it: the answer carries the
    code only."""
    if not isinstance(exc, CncError):
        return exc
    return with_reason(exc, pmc_refusal(exc.ew, area.name, start, start + count - 1))


@asynccontextmanager
async def pmc_named(area: PmcArea, start: int, count: int) -> AsyncIterator[None]:
    """A refusal of ``count`` bytes of ``area`` from ``start`` by one call, named as
    :func:`pmc_named_error` names it (a chunked write names each chunk's in
    :func:`write_chunked`)."""
    try:
        yield
    except CncError as exc:
        named = pmc_named_error(exc, area, start, count)
        if named is exc:
            raise
        raise named from None


def with_reason(exc: CncError, why: str | None) -> CncError:
    """``exc`` told with ``why``, the machine's reason, after its call (the answer carries
    the code only); ``exc`` itself when there is none, or when its words say why already (a
    check of the client's own, made before or after the call)."""
    if why is None or ": " in exc.detail:
        return exc
    return CncError.from_ew(exc.ew, f"{exc.detail}: {why}")


@asynccontextmanager
async def param_named(
    number: int, value: object, axis: int, protocol: str, bit: str = ""
) -> AsyncIterator[None]:
    """A refusal of a write of ``value`` to parameter ``number`` (``axis``; ``bit``: the bit
    written by read-modify-write) through ``protocol``, told with the machine's reason in the
    words of every front end (``the CNC has no parameter 1``): the answer carries the code
    only."""
    try:
        yield
    except CncError as exc:
        why = param_refusal(exc.ew, number, value, axis=axis, bit=bit, protocol=protocol)
        if exc.ew == EW.ATTRIB:  # (an axis past the path's is the client's own check)
            why = axis_misfit("parameter", number, axis)
        raise with_reason(exc, why) from None


@asynccontextmanager
async def macro_named(number: int, value: object) -> AsyncIterator[None]:
    """A refusal of a write of ``value`` to macro variable ``#number``, told with the
    machine's reason in the words of every front end: the answer carries the code only."""
    try:
        yield
    except CncError as exc:
        raise with_reason(exc, macro_refusal(exc.ew, number, value)) from None


class CompositeCalls(Lifecycle):
    """The calls written once over a transport's primitives (see the module docstring)."""

    #: The transport, as a refusal's reason names it (``packed`` or ``native``).
    _transport = "packed"

    def _init_composite(self) -> None:
        #: The width of each parameter read or written (the transport's to fill).
        self._param_widths: dict[int, int] = {}
        self._pmc_locks: KeyedLocks[tuple[int, int]] = KeyedLocks()
        self._param_locks: KeyedLocks[tuple[int, int, int]] = KeyedLocks()

    @property
    def bit_locks(self) -> int:
        """Bit-write locks alive: one per PMC byte or ``(parameter, axis)`` that a bit write
        of this client holds or waits for; 0 when no bit write is under way."""
        return len(self._pmc_locks) + len(self._param_locks)

    # -- the primitives each transport gives -----------------------------------------------
    async def _read_param_value(
        self, number: int, axis: int, deadline: float | None, path: int
    ) -> ParamValue:
        """``cnc_rdparam`` of a checked number and axis, on a checked path."""
        raise NotImplementedError

    async def _is_bit(self, number: int, value: ParamValue, deadline: float | None) -> bool:
        """Whether parameter ``number``, just read as ``value``, is a bit parameter."""
        raise NotImplementedError

    async def _write_param(
        self,
        number: int,
        value: int | Decimal | str,
        axis: int,
        width: int | None,
        deadline: float | None,
        path: int,
    ) -> None:
        """``cnc_wrparam`` of a checked number, axis and width on a checked path (a bit
        parameter's value is its 0..255)."""
        raise NotImplementedError

    async def _write_param_bits(
        self, number: int, axis: int, bits: int, width: int, deadline: float | None, path: int
    ) -> None:
        """``cnc_wrparam`` of the ``8 * width`` bits ``bits`` (unsigned) of a checked number
        and axis, whatever the parameter's integer type."""
        raise NotImplementedError

    def _pmc_area(self, area: AreaLike) -> PmcArea:
        """``area`` as a :class:`PmcArea` this transport can address (ValueError otherwise)."""
        return PmcArea.parse(area)

    async def _read_pmc(
        self, area: PmcArea, start: int, count: int, deadline: float | None
    ) -> bytes:
        """``count`` bytes of ``area`` from ``start`` (a checked range), in as many calls as
        the transport needs."""
        raise NotImplementedError

    def _pmc_write_chunk(self) -> int:
        """Most PMC bytes one write call carries."""
        raise NotImplementedError

    async def _write_pmc_chunks(
        self, area: PmcArea, chunks: Sequence[tuple[int, bytes]], deadline: float | None
    ) -> list[ChunkOutcome]:
        """Write each ``(first address, data)`` chunk; the outcome of each, in order."""
        raise NotImplementedError

    # -- parameters ------------------------------------------------------------------------
    async def read_param_value(
        self,
        number: int,
        *,
        axis: int = 0,
        path: int | None = None,
        timeout: float | None = None,
    ) -> ParamValue:
        """``cnc_rdparam`` as an IODBPSD: the value as the wire carries it and its width (1, 2,
        4 bytes, or 8 for a real parameter's REALPRM with its ``decimals``)."""
        check_item(number, axis, "parameter")
        p = self._path_of(path)
        return await self._read_param_value(number, axis, self._deadline(timeout), p)

    async def read_param(
        self,
        number: int,
        *,
        axis: int = 0,
        path: int | None = None,
        timeout: float | None = None,
    ) -> int:
        """``cnc_rdparam``: the value of parameter ``number`` (``axis`` 1..n for axis items).

        A bit parameter reads as its eight bits, 0..255 (``0b10110000`` is 176); the others as
        the signed integer they hold. A real parameter raises :class:`ValueError` (its value
        has decimals: read it with :meth:`read_param_real`).
        """
        check_item(number, axis, "parameter")
        p = self._path_of(path)
        deadline = self._deadline(timeout)
        value = await self._read_param_value(number, axis, deadline, p)
        if value.width == REAL_WIDTH:
            raise ValueError(
                f"parameter {number} is a real parameter ({value.real}): read it with "
                "read_param_real"
            )
        if await self._is_bit(number, value, deadline):
            return value.bits
        return value.value

    async def read_param_real(
        self,
        number: int,
        *,
        axis: int = 0,
        path: int | None = None,
        timeout: float | None = None,
    ) -> Decimal:
        """``cnc_rdparam``: the value of parameter ``number`` as a :class:`~decimal.Decimal`:
        a real parameter with its decimals (``12.345``), any other as its integer value (a bit
        parameter as 0..255)."""
        check_item(number, axis, "parameter")
        p = self._path_of(path)
        deadline = self._deadline(timeout)
        value = await self._read_param_value(number, axis, deadline, p)
        if value.width == REAL_WIDTH:
            return value.real
        if await self._is_bit(number, value, deadline):
            return Decimal(value.bits)
        return Decimal(value.value)

    async def write_param(
        self,
        number: int,
        value: int | Decimal | str,
        *,
        axis: int = 0,
        width: int | None = None,
        path: int | None = None,
        timeout: float | None = None,
    ) -> None:
        """``cnc_wrparam``: write ``value``.

        A bit parameter takes 0..255 or its bits as text, #7 first (``"0b10110000"``, the same
        as 176); a real parameter a number with decimals (``Decimal("12.345")``, ``"12.345"``,
        an ``int``), width 8; text is an integer (``"42"``, ``"0x2A"``) otherwise. ``width``
        (1, 2, 4 or 8) is the parameter's; left out, it is the one the CNC reports. A value
        that cannot be carried raises :class:`ValueError` (:class:`TypeError` for one that is
        not a number), naming it, before the write is sent.
        """
        check_item(number, axis, "parameter")
        if width is not None and (
            isinstance(width, bool)
            or not isinstance(width, int)
            or width not in (1, 2, 4, REAL_WIDTH)
        ):
            error = ValueError if type(width) is int else TypeError
            raise error(f"parameter width must be 1, 2, 4 or 8 (real), got {width!r}")
        if isinstance(value, bool) or not isinstance(value, int | Decimal | str):
            raise TypeError(f"parameter {number}: a value is a number or its text, got {value!r}")
        if isinstance(value, str):
            try:  # text that is no number at all, in the words of every front end
                typed_number(value)
            except ValueError as exc:
                if not bits_shaped(value):  # "1011_0000" is read once the kind is known
                    raise ValueError(f"parameter {number}: {exc}") from None
        elif isinstance(value, Decimal) and not value.is_finite():
            raise ValueError(not_finite(number, value))
        p = self._path_of(path)
        async with param_named(number, value, axis, self._transport):
            await self._write_param(number, value, axis, width, self._deadline(timeout), p)

    async def write_param_bit(
        self,
        number: int,
        bit: int,
        value: bool | int,
        *,
        axis: int = 0,
        path: int | None = None,
        timeout: float | None = None,
    ) -> None:
        """Set or clear one bit of a parameter (``1815.0``) by read-modify-write; ``value`` is
        ``True``/``False`` or ``1``/``0`` (anything else raises :class:`TypeError`).

        The bit writes of **this client** to the same ``(number, axis)`` wait for one another
        under a lock, so they never lose one another; others run in parallel. The lock is the
        client's: a write of the parameter by another client, or by a program using FANUC's
        library (which has no bit write and no lock either), between this read and write is
        undone. Share one client among the tasks that write bits.
        """
        check_item(number, axis, "parameter")
        check_bit(bit, None)  # its range once the width is read: the parameter's bits
        on = check_bit_value(value)
        p = self._path_of(path)
        deadline = self._deadline(timeout)
        held = f"parameter {number}" + (f" axis {axis}" if axis else "")
        async with self._param_locks.hold((number, axis, p), deadline, held):
            current = await self._read_param_value(number, axis, deadline, p)
            width = current.width
            if width == REAL_WIDTH:
                raise ValueError(f"parameter {number} is a real parameter: it has no bits")
            check_bit(bit, width, f"parameter {number}")
            bits = 8 * width
            raw = current.value & ((1 << bits) - 1)
            raw = raw | (1 << bit) if on else raw & ~(1 << bit)
            async with param_named(number, int(on), axis, self._transport, str(bit)):
                await self._write_param_bits(number, axis, raw, width, deadline, p)

    # -- PMC -------------------------------------------------------------------------------
    async def read_pmc(
        self, area: AreaLike, start: int, count: int, *, timeout: float | None = None
    ) -> bytes:
        """``pmc_rdpmcrng``: ``count`` bytes of ``area`` (``"R"`` or :class:`PmcArea`) from
        ``start``; a range longer than one call carries is read in several, sent together."""
        a = self._pmc_area(area)
        check_pmc_range(start, count)
        async with pmc_named(a, start, count):
            return await self._read_pmc(a, start, count, self._deadline(timeout))

    async def write_pmc(
        self, area: AreaLike, start: int, data: bytes, *, timeout: float | None = None
    ) -> None:
        """``pmc_wrpmcrng``: write ``data`` to ``area`` from ``start``.

        A range longer than one call carries is written in several calls sent together; if any
        fails, :class:`ChunkedWriteError` lists the byte ranges written, not written and
        uncertain (sent, never answered).
        """
        a = self._pmc_area(area)
        data = pmc_data(start, data)
        deadline = self._deadline(timeout)

        async def write(chunks: Sequence[tuple[int, bytes]]) -> list[ChunkOutcome]:
            return await self._write_pmc_chunks(a, chunks, deadline)

        await write_chunked(a, start, data, self._pmc_write_chunk(), write)

    async def read_pmc_bit(
        self, area: AreaLike, byte: int, bit: int, *, timeout: float | None = None
    ) -> bool:
        """One bit of a PMC byte (``R100.3`` is ``read_pmc_bit("R", 100, 3)``)."""
        check_bit(bit)
        data = await self.read_pmc(area, byte, 1, timeout=timeout)
        return bool(data[0] >> bit & 1)

    async def write_pmc_bit(
        self,
        area: AreaLike,
        byte: int,
        bit: int,
        value: bool | int,
        *,
        timeout: float | None = None,
    ) -> None:
        """Set or clear one PMC bit: read the byte, change the bit, write the byte back;
        ``value`` is ``True``/``False`` or ``1``/``0`` (anything else raises :class:`TypeError`).

        The bit writes of **this client** to the same byte wait for one another under the
        lock of ``(area, byte)``, so they never lose one another; other bytes proceed in
        parallel. The lock is the client's: a write of the byte by another client, or by a
        program using FANUC's library (whose ``pmc_wrpmcrng`` writes whole bytes too, with no
        lock), between this read and write is undone. Share one client among the tasks that
        write bits.
        """
        a = self._pmc_area(area)
        check_bit(bit)
        check_pmc_range(byte, 1)
        on = check_bit_value(value)
        deadline = self._deadline(timeout)
        async with (
            self._pmc_locks.hold((a.value, byte), deadline, f"{a.name}{byte}"),
            pmc_named(a, byte, 1),
        ):
            current = (await self._read_pmc(a, byte, 1, deadline))[0]
            new = current | (1 << bit) if on else current & ~(1 << bit)
            (outcome,) = await self._write_pmc_chunks(a, [(byte, bytes((new,)))], deadline)
            if outcome is not None:
                raise outcome[0]
