"""The machine's PMC: its areas by letter, and the signals of automatic operation wired to them.

The machine reads some G signals (what the ladder asks of the CNC: cycle start, feed hold,
reset, the mode, the feed override) and sets some F signals (what the CNC tells the ladder: in
operation, cycle start lamp, feed hold lamp, resetting), at FANUC Series 0i addresses.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from typing import Final

from focas_net._refusals import pmc_protected
from focas_net._typed import pmc_count_unfit
from focas_net.errors import EW

from ._base import Counters, MachineError, need_int
from .nc import CycleState

__all__ = [
    "F_SIGNALS",
    "G_SIGNALS",
    "PATH_SIGNALS_STRIDE",
    "PMC_AREAS",
    "Area",
    "GRequest",
    "Pmc",
    "PmcAreaSpec",
    "need_pmc_count",
    "pmc_letter",
]

#: Letters of the PMC areas a machine can have.
PMC_AREAS: Final = ("X", "Y", "F", "G", "R", "T", "C", "D", "K", "A", "E")


def pmc_letter(text: str) -> str:
    """The PMC area ``text`` names, in either case and with spaces around (``" r"`` is
    ``"R"``): ValueError naming the areas for a letter that is no PMC area."""
    if not isinstance(text, str):
        raise TypeError(f"PMC area must be a letter (str), got {text!r}")
    letter = text.strip().upper()
    if letter not in PMC_AREAS:
        raise ValueError(f"unknown PMC area {text!r} (one of {', '.join(PMC_AREAS)})")
    return letter


def need_pmc_count(count: int) -> int:
    """``count`` PMC bytes to read or write, at least one: a PMC range holds one byte at least
    (FANUC's ``pmc_rdpmcrng`` and ``pmc_wrpmcrng`` give it from ``s`` to ``e``, both included),
    so a count below 1 is EW_LENGTH, as the CNC answers a range that ends before it starts,
    in the words the clients refuse it with before sending (:func:`pmc_count_unfit`). A count
    past the area is the area's to refuse (EW_NUMBER)."""
    if count < 1:
        raise MachineError(EW.LENGTH, pmc_count_unfit(count) or "")
    return count


#: The G signals the machine reads (FANUC Series 0i addresses): (byte, bit).
_ST: Final = (7, 2)  #: cycle start, G7.2 (its falling edge starts)
_SP: Final = (8, 5)  #: feed hold *SP, G8.5 (negative logic: its falling edge holds)
_ERS: Final = (8, 7)  #: external reset, G8.7
_MD: Final = 43  #: mode select MD1 MD2 MD4 (G43.0-.2), DNCI (G43.5), ZRN (G43.7)
_MD_BITS: Final = 0b1010_0111
_FV: Final = 12  #: feed override *FV0-*FV7, G12 (negative logic: 255 - G12 percent; 0 is 0 %)
_ROV: Final = 14  #: rapid traverse override ROV1 ROV2, G14.0-.1 (00 100 %, 01 50 %, 10 25 %, 11 F0)
_SOV: Final = 30  #: spindle speed override SOV0-SOV7, G30 (the percent in binary)
_MAX_FEED_OVERRIDE: Final = 254
#: ROV2 ROV1 -> the rapid override in percent (F0, the slowest, as 0 %: no F0 rate is kept).
_RAPID_OF_ROV: Final = (100, 50, 25, 0)


def _feed_of_fv(fv: int) -> int:
    """The feed override in percent of G12 (*FV0-*FV7): all 0s reads 0 %, as all 1s."""
    return 0 if fv == 0 else 0xFF - fv


def _spindle_of_sov(sov: int) -> int:
    """The spindle override in percent of G30 (SOV0-SOV7), at most 254 %."""
    return min(_MAX_FEED_OVERRIDE, sov)


#: The G and F signals of path n are 1000 * (n - 1) bytes on (FANUC's multi-path PMC).
PATH_SIGNALS_STRIDE: Final = 1000
#: G43 (MD1 MD2 MD4, DNCI, ZRN) -> the panel mode (an ``aut`` value).
_MODE_OF_G43: Final = {
    0b0000_0000: 0,  # MDI
    0b0000_0001: 1,  # MEM
    0b0010_0001: 10,  # RMT (DNC)
    0b0000_0011: 3,  # EDIT
    0b0000_0100: 4,  # HND
    0b0000_0101: 5,  # JOG
    0b1000_0101: 9,  # REF
}
#: The F signals the machine sets (F0.7 OP, F0.5 STL, F0.4 SPL, F1.1 RST): bit numbers.
_OP: Final = 7
_STL: Final = 5
_SPL: Final = 4
_RST: Final = 1
_F0_MASK: Final = 1 << _OP | 1 << _STL | 1 << _SPL
#: The PMC signals of automatic operation the machine reads, ``name: (area, byte, bit)``
#: (G43 mode select and G12 feed override are whole bytes).
G_SIGNALS: Final = {"ST": ("G", 7, 2), "*SP": ("G", 8, 5), "ERS": ("G", 8, 7)}
#: The PMC signals the machine sets, ``name: (area, byte, bit)``.
F_SIGNALS: Final = {"OP": ("F", 0, 7), "STL": ("F", 0, 5), "SPL": ("F", 0, 4), "RST": ("F", 1, 1)}

_START: Final = CycleState.START
_RESET: Final = CycleState.RESET
_HOLD: Final = CycleState.HOLD


@dataclass(frozen=True, slots=True)
class PmcAreaSpec:
    """A PMC area: its letter (one of :data:`PMC_AREAS`), its size in bytes, protection against
    writes and its initial bytes as ``{address: bytes}``."""

    letter: str
    size: int
    write_protected: bool = False
    initial: Mapping[int, bytes] = field(default_factory=dict)


@dataclass(frozen=True, slots=True)
class GRequest:
    """What a write of the G area asks of automatic operation, in the order the machine acts:
    reset (ERS rose), feed hold (*SP fell), a mode (G43's mode bits changed to a known one),
    the overrides (G12 feed, G14 rapid, G30 spindle changed), cycle start (ST fell with *SP
    on)."""

    reset: bool = False
    hold: bool = False
    mode: int | None = None
    feed_override: int | None = None
    start: bool = False
    rapid_override: int | None = None
    spindle_override: int | None = None

    @property
    def overrides(self) -> tuple[int | None, int | None, int | None]:
        """Feed, rapid and spindle override asked (None: unchanged)."""
        return (self.feed_override, self.rapid_override, self.spindle_override)


class Area:
    """One PMC area: its bytes, its size, whether it refuses writes."""

    __slots__ = ("data", "letter", "size", "write_protected")

    def __init__(self, spec: PmcAreaSpec) -> None:
        self.letter = pmc_letter(spec.letter)
        self.size = spec.size
        self.write_protected = spec.write_protected
        self.data = bytearray(spec.size)
        for address, raw in spec.initial.items():
            if address < 0 or address + len(raw) > spec.size:
                raise ValueError(f"initial bytes at {address} run past the {spec.size}-byte area")
            self.data[address : address + len(raw)] = raw

    def beyond(self, start: int, end: int) -> MachineError:
        """The refusal of addresses ``start..end - 1`` outside the area, in the words of every
        front end, the area's range after them: ``R-1 is outside PMC area R (R0..R7999)``,
        ``R8000 goes past the end of PMC area R (R0..R7999)`` and ``R7999..R8000 goes past the
        end ...``, as the command line says it from the EW code alone (without the range)."""
        letter, last = self.letter, self.size - 1
        span = f"{letter}{start}" + (f"..{letter}{end - 1}" if end - 1 != start else "")
        where = "is outside" if start < 0 else "goes past the end of"
        return MachineError(
            EW.NUMBER, f"{span} {where} PMC area {letter} ({letter}0..{letter}{last})"
        )


class Pmc:
    """The PMC areas of a machine by letter. Every change moves the PMC counter."""

    __slots__ = ("areas", "counters", "paths")

    def __init__(self, specs: Iterable[PmcAreaSpec], counters: Counters) -> None:
        self.counters = counters
        #: The machine's paths: the G signals of each are read at its own offset.
        self.paths = 1
        self.areas: dict[str, Area] = {}
        for spec in specs:
            area = Area(spec)
            if area.letter in self.areas:
                raise ValueError(f"PMC area {area.letter} given twice")
            self.areas[area.letter] = area

    def info(self, letter: str) -> tuple[int, bool] | None:
        """``(size, write_protected)``, None when the machine has no such area (ValueError for
        a letter that is no PMC area)."""
        area = self.areas.get(pmc_letter(letter))
        return None if area is None else (area.size, area.write_protected)

    def area(self, letter: str) -> Area:
        """Area ``letter``: EW_NOOPT when the machine has none, naming the areas it has (every
        front end shows these words)."""
        if not isinstance(letter, str):
            raise TypeError(f"PMC area must be a letter (str), got {letter!r}")
        area = self.areas.get(letter) or self.areas.get(letter.strip().upper())
        if area is None:
            has = ", ".join(a for a in PMC_AREAS if a in self.areas) or "none"
            shown = letter.strip().upper() or repr(letter)
            raise MachineError(EW.NOOPT, f"the CNC has no PMC area {shown} (it has {has})")
        return area

    def write(
        self, letter: str, start: int, data: bytes, force: bool
    ) -> list[tuple[int, GRequest]]:
        """Write ``data`` from ``start``: EW_NOOPT, EW_NUMBER (addresses outside the area),
        EW_PROT (write-protected, unless ``force``). A write that changed G bytes returns what
        it asks of automatic operation, ``(path, request)`` for each path whose signals
        (:data:`PATH_SIGNALS_STRIDE`) it wrote. TypeError for a start or data of another type."""
        need_int("PMC start address", start)
        if not isinstance(data, bytes | bytearray | memoryview):
            raise TypeError(f"PMC data must be bytes, got {data!r}")
        area = self.area(letter)
        need_pmc_count(len(data))
        end = start + len(data)
        if start < 0 or end > area.size:
            raise area.beyond(start, end)
        if area.write_protected and not force:
            raise MachineError(EW.PROT, pmc_protected(area.letter))
        before = bytes(area.data[start:end])
        area.data[start:end] = data
        self.counters.pmc += 1
        self.counters.version += 1
        if area.letter != "G" or before == data:
            return []
        asked = []
        for path in range(1, self.paths + 1):
            base = PATH_SIGNALS_STRIDE * (path - 1)
            if start < base + PATH_SIGNALS_STRIDE and end > base and base + _MD < area.size:
                asked.append((path, self._g_request(base, start, before)))
        return asked

    def _g_request(self, base: int, start: int, before: bytes) -> GRequest:
        """What a write of the G area from ``start``, which replaced ``before``, asks of the
        path whose signals begin at ``base`` (see :data:`G_SIGNALS`): only the signals within
        the written bytes count."""
        area = self.areas["G"].data

        def old(address: int) -> int | None:
            i = base + address - start
            return before[i] if 0 <= i < len(before) else None

        def now(address: int) -> int:
            return area[base + address] if base + address < len(area) else 0

        def fell(address: int, bit: int) -> bool:
            was = old(address)
            return was is not None and bool(was >> bit & 1) and not now(address) >> bit & 1

        def rose(address: int, bit: int) -> bool:
            was = old(address)
            return was is not None and not was >> bit & 1 and bool(now(address) >> bit & 1)

        def changed(address: int) -> bool:
            was = old(address)
            return was is not None and was != now(address)

        mode = feed = rapid = spindle = None
        if changed(_MD):
            mode = _MODE_OF_G43.get(now(_MD) & _MD_BITS)
        if changed(_FV):
            feed = _feed_of_fv(now(_FV))
        if changed(_ROV) and (old(_ROV) or 0) & 3 != now(_ROV) & 3:
            rapid = _RAPID_OF_ROV[now(_ROV) & 3]
        if changed(_SOV):
            spindle = _spindle_of_sov(now(_SOV))
        start_edge = fell(*_ST) and bool(now(_SP[0]) >> _SP[1] & 1)
        return GRequest(rose(*_ERS), fell(*_SP), mode, feed, start_edge, rapid, spindle)

    def show_overrides(self, path: int, feed: int, rapid: int, spindle: int) -> None:
        """Set G12 (*FV0-*FV7, inverted), G14 (ROV1 ROV2: the step at or under ``rapid``)
        and G30 (SOV0-SOV7) of ``path`` from the overrides the path uses, as a ladder
        passes the panel's switches on."""
        area = self.areas.get("G")
        base = PATH_SIGNALS_STRIDE * (path - 1)
        if area is None or base + _SOV >= area.size:
            return
        g = area.data
        rov = next(i for i, step in enumerate(_RAPID_OF_ROV) if rapid >= step)
        fv, sov = g[base + _FV], g[base + _SOV]  # kept while they read as the override
        values = (
            (_FV, fv if _feed_of_fv(fv) == feed else 0xFF - feed),
            (_ROV, g[base + _ROV] & ~3 | rov),
            (_SOV, sov if _spindle_of_sov(sov) == spindle else spindle),
        )
        if any(g[base + a] != v for a, v in values):
            for address, value in values:
                g[base + address] = value
            self.counters.pmc += 1
            self.counters.version += 1

    def show_cycle(self, state: CycleState, path: int = 1) -> None:
        """Set the F signals a ladder reads from the cycle's ``state`` of ``path`` (see
        :data:`F_SIGNALS`, at the path's offset; RST follows ERS)."""
        area = self.areas.get("F")
        base = PATH_SIGNALS_STRIDE * (path - 1)
        if area is None or area.size < base + 2:
            return
        g = self.areas.get("G")
        at = base + _ERS[0]
        resetting = g is not None and g.size > at and bool(g.data[at] >> _ERS[1] & 1)
        f = area.data
        f0 = f[base] & ~_F0_MASK
        if state is not _RESET:
            f0 |= 1 << _OP
        if state is _START:
            f0 |= 1 << _STL
        if state is _HOLD:
            f0 |= 1 << _SPL
        f1 = f[base + 1] & ~(1 << _RST) | (1 << _RST if resetting else 0)
        if (f0, f1) != (f[base], f[base + 1]):
            f[base], f[base + 1] = f0, f1
            self.counters.pmc += 1
            self.counters.version += 1
