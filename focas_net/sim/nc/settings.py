"""What the control's parameters say about execution, and the G codes the interpreter knows.

:class:`NcSettings` is the machine's side of the interface (rapid rates, stroke limits,
reference position, increments, function times, from the parameters); :data:`G_CODE_GROUPS`
and :data:`DEFAULT_MODAL` are FANUC's G code groups and their power-on state.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, Final

__all__ = ["DEFAULT_MODAL", "G_CODE_GROUPS", "INCH", "NcSettings"]

INCH: Final = 25.4

#: Each G code the interpreter accepts (value x 10) and its group, FANUC's numbering of the M
#: series (G40.1 group 18, G50.1 group 22); group 0 is one-shot.
G_CODE_GROUPS: Final[dict[int, int]] = {
    0: 1, 10: 1, 20: 1, 30: 1,
    40: 0, 280: 0, 530: 0,
    170: 2, 180: 2, 190: 2,
    900: 3, 910: 3,
    220: 4, 230: 4,
    940: 5,
    200: 6, 210: 6,
    400: 7,
    430: 8, 440: 8, 490: 8,
    800: 9,
    980: 10, 990: 10,
    500: 11,
    670: 12,
    960: 13, 970: 13,
    540: 14, 550: 14, 560: 14, 570: 14, 580: 14, 590: 14,
    610: 15, 620: 15, 630: 15, 640: 15,
    690: 16,
    150: 17,
    401: 18,
    501: 22,
}  # fmt: skip

#: The power-on state of each modal group (value x 10), as #4001-#4022 read it (a group not
#: modelled, 19-21, reads vacant).
DEFAULT_MODAL: Final[dict[int, int]] = {
    1: 0, 2: 170, 3: 900, 4: 220, 5: 940, 6: 210, 7: 400, 8: 490, 9: 800, 10: 980,
    11: 500, 12: 670, 13: 970, 14: 540, 15: 640, 16: 690, 17: 150, 18: 401, 22: 501,
}  # fmt: skip


@dataclass(frozen=True, slots=True)
class NcSettings:
    """What the control's parameters say about execution. Lengths in mm, feeds in mm/min,
    times in seconds; per-axis tuples follow ``axes``."""

    axes: tuple[str, ...] = ("X", "Y", "Z")
    #: A lathe's path (FANUC's T series): a dwell takes its time in U too.
    lathe: bool = False
    #: Rapid traverse rate per axis (parameter 1420).
    rapid_rates: tuple[float, ...] = (24000.0, 24000.0, 24000.0)
    #: Upper limit of cutting feed (parameter 1430/1432).
    max_cutting_feed: float = 10000.0
    #: Stored stroke limit 1 per axis, (minus, plus) in machine coordinates (parameters
    #: 1320/1321); ``None``: no limit on that axis.
    stroke_limits: tuple[tuple[float, float] | None, ...] = (None, None, None)
    #: Reference position per axis in machine coordinates (parameter 1240).
    reference: tuple[float, ...] = (0.0, 0.0, 0.0)
    #: Least input increment of axis words without a decimal point (IS-B): 0.001 mm,
    #: 0.0001 inch; the same increment in seconds for a dwell's X.
    increment_mm: float = 0.001
    increment_inch: float = 0.0001
    #: Limit of the difference between start and end radius of an arc (parameter 3410).
    arc_tolerance: float = 0.02
    #: Largest spindle speed (parameter 3772), min^-1.
    max_spindle_speed: float = 6000.0
    #: Seconds an M6 tool change and any other M function take.
    tool_change_time: float = 4.0
    m_function_time: float = 0.5
    #: Deepest subprogram nesting (M98 within M98).
    max_subprogram_nesting: int = 10
    #: Highest tool length offset number H.
    max_offset_number: int = 400
    #: Blocks executed in zero time in a row before each further one takes ``busy_block_time``
    #: (keeps an endless macro loop from hanging a read).
    zero_time_blocks: int = 10000
    busy_block_time: float = 0.001
    #: The waiting M codes, lowest and highest (parameters 8110 and 8111), on a control of
    #: ``path_count`` paths of which this is path ``path_number``; None: no waiting M codes
    #: (a one-path control has none).
    waiting_m: tuple[int, int] | None = None
    path_number: int = 1
    path_count: int = 1

    @classmethod
    def for_axes(cls, axes: Sequence[str], **values: Any) -> NcSettings:
        """Settings for ``axes`` with the per-axis defaults repeated for each axis (24 m/min
        rapids, no stroke limits, reference at 0); ``values`` override any field."""
        n = len(axes)
        defaults: dict[str, Any] = {
            "rapid_rates": (24000.0,) * n,
            "stroke_limits": (None,) * n,
            "reference": (0.0,) * n,
        }
        return cls(axes=tuple(axes), **{**defaults, **values})

    def power_on_modal(self) -> dict[int, int]:
        """The G code of each group at power-on: :data:`DEFAULT_MODAL`, on a lathe with the ZX
        plane (G18), the T series' own."""
        return {**DEFAULT_MODAL, 2: 180} if self.lathe else dict(DEFAULT_MODAL)

    def __post_init__(self) -> None:
        n = len(self.axes)
        if not 1 <= n <= 20 or len(set(self.axes)) != n:
            raise ValueError(f"1..20 distinct axis names are needed, got {self.axes!r}")
        for name, value in (
            ("rapid_rates", self.rapid_rates),
            ("stroke_limits", self.stroke_limits),
            ("reference", self.reference),
        ):
            if len(value) != n:
                raise ValueError(f"{name} has {len(value)} entries for {n} axes")
        if any(not (math.isfinite(r) and r > 0) for r in self.rapid_rates):
            raise ValueError(f"rapid rates must be positive, got {self.rapid_rates!r}")
        for limit in self.stroke_limits:
            if limit is not None and not limit[0] <= limit[1]:
                raise ValueError(f"a stroke limit is (minus, plus), got {limit!r}")
