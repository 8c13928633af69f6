"""What the CNC tells about itself beyond its identity: the figures of its data, its system
software, its setting data, its PMC's areas and title, its Ethernet board.

Protocol-free facts of the machine (:class:`InformationOperations` is a base class of
:class:`~focas_net.sim.Machine`); each front end reads them through the same methods, so the
native and the packed wire and the command line tell the same. Every figure follows what the
machine already says elsewhere: the CNC's software is its identity's series and version, the
figures of the positions are :data:`~focas_net.sim.POSITION_DECIMALS` for every axis of the
path, the setting data are parameters the machine has, the PMC's areas are its PMC areas with
their sizes. What a machine has no model of is the simulator's own value, the same on every
machine of a class (the servo, PMC and boot software, the PMC title's texts, the Ethernet
board's kind).
"""

from __future__ import annotations

from bisect import bisect_left
from dataclasses import dataclass
from typing import TYPE_CHECKING, Final, Protocol

from focas_net.errors import EW

from ._base import MachineError, need_int
from ._identity import CLASSES_16I
from ._pmc import PMC_AREAS
from ._status import POSITION_DECIMALS

if TYPE_CHECKING:
    from ._identity import Identity
    from ._items import DataItem
    from ._paths import PathInfo

__all__ = [
    "SETTING_NUMBERS",
    "VALID_FIGURES",
    "EthernetBoard",
    "InformationOperations",
    "LadderTitle",
    "PmcAreaExtent",
    "SoftwareVersion",
]

#: The parameter numbers that are setting data (FANUC's setting screen shows the parameters
#: numbered below 100: TV check, ISO code, I/O channel...).
SETTING_NUMBERS: Final = range(100)
#: Most valid figures of a position (nine digits: 999999.999 mm at three decimals).
VALID_FIGURES: Final = 9


@dataclass(frozen=True, slots=True)
class SoftwareVersion:
    """One piece of the CNC's system software: what it is (``"cnc"``, ``"boot"``,
    ``"servo"``, ``"pmc"``, ``"ladder"``), its series and its edition (4 ASCII characters
    each)."""

    name: str
    series: str
    version: str

    def __post_init__(self) -> None:
        for what, text in (("series", self.series), ("version", self.version)):
            if len(text) != 4 or not text.isascii() or not text.isprintable():
                raise ValueError(f"software {self.name} {what} must be 4 ASCII characters")


@dataclass(frozen=True, slots=True)
class LadderTitle:
    """The PMC's title data (its ladder's): machine tool builder, machine, PMC type, program
    number and edition, drawing number, date, designer, writer, remarks."""

    mtb: str
    machine: str
    pmc_type: str
    program: str
    edition: str
    drawing: str = ""
    date: str = ""
    designer: str = ""
    writer: str = ""
    remarks: str = ""


@dataclass(frozen=True, slots=True)
class PmcAreaExtent:
    """A PMC area as the PMC describes it: its letter, its first and last byte address, and
    whether it refuses writes."""

    letter: str
    first: int
    last: int
    write_protected: bool


@dataclass(frozen=True, slots=True)
class EthernetBoard:
    """The Ethernet port the CNC is reached through: its kind and its device number, as
    ``cnc_rdetherinfo`` reports them."""

    kind: int
    device: int


#: The CNC's own Ethernet port (the embedded one), the same on every machine.
EMBEDDED_ETHERNET: Final = EthernetBoard(1, 0)
#: The software beside the CNC's own, by control set: (name, series, edition).
_SOFTWARE: Final[dict[bool, tuple[tuple[str, str, str], ...]]] = {
    True: (("boot", "60W3", "0005"), ("servo", "90J0", "0014"), ("pmc", "406A", "0003")),
    False: (("boot", "60M5", "0010"), ("servo", "90D0", "0030"), ("pmc", "40A0", "0008")),
}
_TITLE_WIDTH: Final = 32


class _Facts(Protocol):
    """What :class:`InformationOperations` reads of the machine."""

    @property
    def name(self) -> str: ...

    @property
    def control_class(self) -> str: ...

    def identity(self) -> Identity: ...

    def path_info(self, path: int = 1) -> PathInfo: ...

    def param_item(self, datano: int) -> DataItem | None: ...

    def param_numbers(self) -> tuple[int, ...]: ...

    def pmc_area(self, letter: str) -> tuple[int, bool] | None: ...

    def pmc_title(self) -> LadderTitle: ...


class InformationOperations:
    """The machine's information (see the module docstring); a base class of the machine."""

    __slots__ = ()

    def figures(self: _Facts, *, path: int = 1) -> tuple[int, tuple[tuple[int, int], ...]]:
        """The most valid figures of a position and, per axis of ``path``, the decimal places
        of its input and output units (EW_PATH for a path the machine has not)."""
        axes = self.path_info(path).axes
        return VALID_FIGURES, tuple((POSITION_DECIMALS, POSITION_DECIMALS) for _ in axes)

    def system_software(self: _Facts) -> tuple[SoftwareVersion, ...]:
        """The CNC's system software: first the CNC's own (its identity's series and
        version), then the boot, servo and PMC software and the ladder (the PMC title's
        program number and edition)."""
        identity = self.identity()
        own = SoftwareVersion("cnc", identity.series, identity.version)
        others = _SOFTWARE[self.control_class in CLASSES_16I]
        title = self.pmc_title()
        ladder = SoftwareVersion("ladder", title.program.rjust(4, "0"), title.edition.rjust(4, "0"))
        return (own, *(SoftwareVersion(*o) for o in others), ladder)

    def pmc_title(self: _Facts) -> LadderTitle:
        """The PMC's title data: the machine's name, its control class's PMC, ladder program
        0001 edition 01."""
        return LadderTitle(
            mtb="FOCAS-NET",
            machine=self.name[:_TITLE_WIDTH],
            pmc_type=f"{self.control_class} PMC",
            program="0001",
            edition="01",
        )

    def ethernet_board(self: _Facts) -> EthernetBoard:
        """The Ethernet port the CNC is reached through (the embedded port)."""
        return EMBEDDED_ETHERNET

    def pmc_ranges(self: _Facts) -> tuple[PmcAreaExtent, ...]:
        """Every PMC area the machine has, in :data:`PMC_AREAS` order, with its addresses."""
        out = []
        for letter in PMC_AREAS:
            info = self.pmc_area(letter)
            if info is not None:
                size, protected = info
                out.append(PmcAreaExtent(letter, 0, size - 1, protected))
        return tuple(out)

    def setting_numbers(self: _Facts) -> tuple[int, ...]:
        """The numbers of the machine's setting data (its parameters in
        :data:`SETTING_NUMBERS`), ascending."""
        numbers = self.param_numbers()
        return numbers[: bisect_left(numbers, SETTING_NUMBERS.stop)]

    def check_setting(self: _Facts, datano: int) -> None:
        """EW_NUMBER unless ``datano`` is setting data of the machine (TypeError for a number
        of another type, naming it)."""
        need_int("setting number", datano)
        if datano not in SETTING_NUMBERS or self.param_item(datano) is None:
            raise MachineError(EW.NUMBER, f"no setting data {datano!r}")
